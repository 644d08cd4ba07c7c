//! Objects and the agent start placed outside the house: still imported (an object keeps its
//! footprint, clipped to the grid), but the user hears about it, because such a house is usually
//! a broken export or a hand edit gone wrong.

use super::house::{House, HouseObject};
use super::raster::inside_or_on;

/// How far outside every floor polygon a centre may lie and still count as in the house, metres:
/// wall-mounted things (paintings, light switches) sit on the wall line, a few cm out.
const OUTSIDE_TOLERANCE_M: f64 = 0.3;

fn distance_to_polygon(p: [f64; 2], poly: &[[f64; 2]]) -> f64 {
    let mut best = f64::INFINITY;
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        let d = [b[0] - a[0], b[1] - a[1]];
        let len2 = d[0] * d[0] + d[1] * d[1];
        let t = if len2 > 0.0 {
            (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let q = [a[0] + t * d[0], a[1] + t * d[1]];
        best = best.min((p[0] - q[0]).hypot(p[1] - q[1]));
    }
    best
}

/// Whether world `(x, z)` lies on the floor of some room, or within the tolerance of one.
pub(super) fn in_house(house: &House, p: [f64; 2]) -> bool {
    house.rooms.iter().any(|r| {
        inside_or_on(p, &r.polygon) || distance_to_polygon(p, &r.polygon) <= OUTSIDE_TOLERANCE_M
    })
}

/// Warnings for objects (children included) and the start outside the house.
pub(super) fn placement_warnings(house: &House, warn: &mut Vec<(String, String)>) {
    fn walk(house: &House, o: &HouseObject, warn: &mut Vec<(String, String)>) {
        let p = [o.position[0], o.position[2]];
        if !in_house(house, p) {
            warn.push((
                format!("{}.position", o.path),
                format!(
                    "{} at ({:.2}, {:.2}) is outside every room's floor; it is kept where it is",
                    o.id, p[0], p[1]
                ),
            ));
        }
        for c in &o.children {
            walk(house, c, warn);
        }
    }
    for o in &house.objects {
        walk(house, o, warn);
    }
}
