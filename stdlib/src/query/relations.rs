//! Relations between objects: on, inside, under, next to, near, between.

use super::{MapQuery, Target};
use crate::grid::Cell;
use crate::map::{Object, Relation};

/// The distances behind the relations, metres. One place, so docs/semantics.md and the code agree.
#[derive(Clone, Debug, PartialEq)]
pub struct Thresholds {
    /// `next_to`: largest footprint gap.
    pub next_to_m: f64,
    /// Default radius of `near` (the language's default argument says the same).
    pub near_m: f64,
    /// `between`: how far beyond the hull of the two footprints the corridor reaches.
    pub between_margin_m: f64,
    /// Vertical slack when comparing a bottom with a top (`on`, `under`).
    pub vertical_tolerance_m: f64,
    /// Share of a child's footprint that must lie over its parent's (geometric `on` / `inside`).
    pub overlap_share: f64,
    /// Radius of the region around a room corner.
    pub corner_radius_m: f64,
}

impl Default for Thresholds {
    fn default() -> Self {
        Thresholds {
            next_to_m: 0.5,
            near_m: 1.5,
            between_margin_m: 0.25,
            vertical_tolerance_m: 0.1,
            overlap_share: 0.5,
            corner_radius_m: 0.75,
        }
    }
}

impl MapQuery<'_> {
    /// Whether any object of the map carries a parent relation; when none does, `on` and `inside`
    /// fall back to geometry.
    pub fn has_parent_relations(&self) -> bool {
        self.map.objects.iter().any(|o| o.parent.is_some())
    }

    /// `child.on(parent)`.
    pub fn on(&self, child: &Object, parent: &Object) -> bool {
        self.stacked(child, parent, Relation::On)
    }

    /// `child.inside(container)`.
    pub fn inside(&self, child: &Object, container: &Object) -> bool {
        self.stacked(child, container, Relation::Inside)
    }

    fn stacked(&self, child: &Object, parent: &Object, rel: Relation) -> bool {
        if child.id == parent.id {
            return false;
        }
        if self.has_parent_relations() {
            return child
                .parent
                .is_some_and(|p| p.id == parent.id && p.relation == rel);
        }
        // Geometric fallback: most of the child's footprint over the parent's, and heights that say
        // which of the two relations it is.
        if overlap_share(&child.footprint, &parent.footprint) < self.thresholds.overlap_share
            || child.footprint.len() > parent.footprint.len()
        {
            return false;
        }
        let tol = self.thresholds.vertical_tolerance_m;
        match (child.elevation_m, parent.elevation_m, parent.height_m) {
            (Some(cb), Some(pb), Some(ph)) => {
                let ptop = pb + ph;
                match rel {
                    Relation::On => (cb - ptop).abs() <= tol,
                    Relation::Inside => {
                        let ctop = cb + child.height_m.unwrap_or(0.0);
                        cb >= pb - tol && cb < ptop - tol && ctop <= ptop + tol
                    }
                }
            }
            // Without heights, a smaller object over a larger one is taken to be on it.
            _ => rel == Relation::On,
        }
    }

    /// `lower.under(upper)`: footprints overlap, `upper` reaches higher, and neither rests on or in
    /// the other. Needs heights; without them nothing is under anything.
    pub fn under(&self, lower: &Object, upper: &Object) -> bool {
        if lower.id == upper.id || self.related(lower, upper) {
            return false;
        }
        let top = |o: &Object| Some(o.elevation_m.unwrap_or(0.0) + o.height_m?);
        let (Some(lt), Some(ut)) = (top(lower), top(upper)) else {
            return false;
        };
        ut > lt + self.thresholds.vertical_tolerance_m
            && overlap_share(&lower.footprint, &upper.footprint) > 0.0
    }

    /// One rests on or in the other (either way round).
    pub fn related(&self, a: &Object, b: &Object) -> bool {
        self.on(a, b) || self.inside(a, b) || self.on(b, a) || self.inside(b, a)
    }

    /// `a.next_to(b)`: footprint gap at most `next_to_m`, different objects, not stacked.
    pub fn next_to(&self, a: &Object, b: &Object) -> bool {
        a.id != b.id
            && self.within(
                Target::Object(a),
                Target::Object(b),
                self.thresholds.next_to_m,
            )
            && !self.related(a, b)
    }

    /// `a.next_to(b)` where `b` is any place: an object by [`Self::next_to`]; a region (a corner,
    /// a doorway, an area) when the footprint comes within `next_to_m` of its cells, so "the
    /// plunger next to the corner" reads the corner's cells as the plunger's neighbour.
    pub fn next_to_place(&self, a: &Object, b: Target) -> bool {
        match b {
            Target::Object(o) => self.next_to(a, o),
            Target::Cells(_) => self.within(Target::Object(a), b, self.thresholds.next_to_m),
            // The checker admits no room here: every object of a room would be "beside" it.
            Target::Room(_) => false,
        }
    }

    /// `x.in(region)` / `region.contains(x)`: at least half of `x`'s cells lie in the region's
    /// (sorted) cells, or the cell under `x`'s centre does. A painting hung in a corner has its
    /// footprint on the wall line, so the centre alone would miss it as often as it hits.
    pub fn lies_in(&self, x: Target, region: &[Cell]) -> bool {
        let cells = self.cells(x);
        if cells.is_empty() || region.is_empty() {
            return false;
        }
        let inside = cells
            .iter()
            .filter(|c| region.binary_search(c).is_ok())
            .count();
        if 2 * inside >= cells.len() {
            return true;
        }
        let centre = match x {
            Target::Object(o) => Some(o.center),
            _ => Self::centroid(cells),
        };
        centre.is_some_and(|[r, c]| {
            r >= 0.0
                && c >= 0.0
                && region
                    .binary_search(&Cell::new(r.round() as u32, c.round() as u32))
                    .is_ok()
        })
    }

    /// `distance(a, b) <= within_m` (with the relations' 1e-9 m tolerance), rejecting places whose
    /// bounding boxes are already farther apart before measuring cells. The box gap never exceeds
    /// the distance and both scale by the same resolution, so the answer is the same.
    fn within(&self, a: Target, b: Target, within_m: f64) -> bool {
        let limit = within_m + 1e-9;
        if self
            .box_gap_cells(a, b)
            .is_none_or(|g| g * self.res() > limit)
        {
            return false;
        }
        self.distance(a, b).is_some_and(|d| d <= limit)
    }

    /// `a.near(b, within)`: footprint gap at most `within` metres (`a` and `b` may be any places;
    /// an object is not near itself).
    pub fn near(&self, a: Target, b: Target, within_m: f64) -> bool {
        if let (Target::Object(x), Target::Object(y)) = (a, b)
            && x.id == y.id
        {
            return false;
        }
        self.within(a, b, within_m)
    }

    /// The corridor between two places (`area_between`): the convex hull of both, widened by
    /// `between_margin_m` so that even a narrow gap gives a usable area, minus the two places
    /// themselves. Sorted.
    pub fn corridor(&self, a: Target, b: Target) -> Vec<Cell> {
        self.hull_cells(&[a, b], self.thresholds.between_margin_m / self.res())
    }

    /// The convex hull of two places, without widening, minus the places (the `between` test).
    pub fn hull_between(&self, a: Target, b: Target) -> Vec<Cell> {
        self.hull_cells(&[a, b], 0.0)
    }

    /// The area enclosed by several places (`area_enclosed`): the convex hull of all their
    /// footprints minus the footprints themselves. Sorted; empty when the hull is degenerate.
    pub fn enclosed(&self, places: &[Target]) -> Vec<Cell> {
        self.hull_cells(places, 0.0)
    }

    fn hull_cells(&self, places: &[Target], margin: f64) -> Vec<Cell> {
        let own: Vec<&[Cell]> = places.iter().map(|t| self.cells(*t)).collect();
        let mut pts: Vec<[f64; 2]> = Vec::new();
        for c in places.iter().flat_map(|t| self.outline(*t)) {
            let (r, k) = (c.row as f64, c.col as f64);
            pts.extend([
                [r - 0.5, k - 0.5],
                [r - 0.5, k + 0.5],
                [r + 0.5, k - 0.5],
                [r + 0.5, k + 0.5],
            ]);
        }
        let hull = convex_hull(pts);
        if hull.len() < 3 {
            return Vec::new();
        }
        let n = self.map.n() as i64;
        let (mut r0, mut c0, mut r1, mut c1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
        for p in &hull {
            (r0, c0, r1, c1) = (r0.min(p[0]), c0.min(p[1]), r1.max(p[0]), c1.max(p[1]));
        }
        let mut out = Vec::new();
        for row in ((r0 - margin).floor() as i64).max(0)..=((r1 + margin).ceil() as i64).min(n - 1)
        {
            for col in
                ((c0 - margin).floor() as i64).max(0)..=((c1 + margin).ceil() as i64).min(n - 1)
            {
                let cell = Cell::new(row as u32, col as u32);
                if own.iter().any(|cs| cs.binary_search(&cell).is_ok()) {
                    continue;
                }
                if hull_distance(&hull, [row as f64, col as f64]) <= margin {
                    out.push(cell);
                }
            }
        }
        out
    }

    /// `o.between(a, b)`: the centre of `o` lies in the convex hull of `a` and `b` (outside both),
    /// and `o` is neither of them.
    pub fn between(&self, o: &Object, a: Target, b: Target) -> bool {
        for t in [a, b] {
            if let Target::Object(x) = t
                && x.id == o.id
            {
                return false;
            }
        }
        let center = Cell::new(
            o.center[0].round().max(0.0) as u32,
            o.center[1].round().max(0.0) as u32,
        );
        self.hull_between(a, b).binary_search(&center).is_ok()
    }
}

/// Share of `a`'s cells that are also in `b` (both sorted).
fn overlap_share(a: &[Cell], b: &[Cell]) -> f64 {
    if a.is_empty() {
        return 0.0;
    }
    a.iter().filter(|c| b.binary_search(c).is_ok()).count() as f64 / a.len() as f64
}

/// Andrew's monotone chain; returns the hull counter-clockwise in (row, col) space.
fn convex_hull(mut pts: Vec<[f64; 2]>) -> Vec<[f64; 2]> {
    pts.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut lower: Vec<[f64; 2]> = Vec::new();
    for &p in &pts {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], p) <= 0.0 {
            lower.pop();
        }
        lower.push(p);
    }
    let mut upper: Vec<[f64; 2]> = Vec::new();
    for &p in pts.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], p) <= 0.0 {
            upper.pop();
        }
        upper.push(p);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

/// 0 inside the (counter-clockwise) hull, else the distance to its boundary.
fn hull_distance(hull: &[[f64; 2]], p: [f64; 2]) -> f64 {
    let mut inside = true;
    let mut best = f64::INFINITY;
    for i in 0..hull.len() {
        let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
        let cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        if cross < 0.0 {
            inside = false;
        }
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        best = best.min((p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy));
    }
    if inside { 0.0 } else { best }
}

#[cfg(test)]
mod tests {
    use super::super::fixture::two_rooms;
    use super::*;
    use crate::map::Parent;

    #[test]
    fn parent_relations_win_over_geometry() {
        let mut map = two_rooms();
        let q = MapQuery::new(&map);
        let (bed, lamp, book) = (
            map.object(1).unwrap(),
            map.object(2).unwrap(),
            map.object(3).unwrap(),
        );
        // No parents in the map: the book (elevated, over the bed) is on the bed by geometry.
        assert!(q.on(book, bed));
        assert!(!q.inside(book, bed));
        assert!(!q.on(lamp, bed));
        assert!(
            q.under(bed, map.object(4).unwrap()),
            "the shelf hangs above the bed"
        );
        map.objects[2].parent = Some(Parent {
            id: 2,
            relation: Relation::Inside,
        });
        let q = MapQuery::new(&map);
        let (bed, lamp, book) = (
            map.object(1).unwrap(),
            map.object(2).unwrap(),
            map.object(3).unwrap(),
        );
        assert!(!q.on(book, bed));
        assert!(q.inside(book, lamp));
    }

    #[test]
    fn next_to_near_and_between_use_footprint_gaps() {
        let map = two_rooms();
        let q = MapQuery::new(&map);
        let (bed, lamp) = (map.object(1).unwrap(), map.object(2).unwrap());
        let chair = map.object(5).unwrap();
        // Gap bed-lamp: 2 cells = 0.2 m at 0.1 m/cell.
        assert!(q.next_to(bed, lamp));
        assert!(!q.next_to(bed, bed));
        assert!(q.near(Target::Object(bed), Target::Object(chair), 1.5));
        assert!(!q.near(Target::Object(bed), Target::Object(chair), 0.1));
        let corridor = q.corridor(Target::Object(bed), Target::Object(chair));
        assert!(!corridor.is_empty());
        assert!(corridor.iter().all(|c| !bed.footprint.contains(c)));
        let (rug, plant) = (map.object(6).unwrap(), map.object(7).unwrap());
        assert!(q.between(rug, Target::Object(bed), Target::Object(chair)));
        assert!(!q.between(plant, Target::Object(bed), Target::Object(chair)));
        assert!(
            !q.between(lamp, Target::Object(bed), Target::Object(chair)),
            "beside the hull, not in it"
        );
        assert!(
            corridor.contains(&Cell::new(3, 7)),
            "the widened corridor reaches the lamp's column"
        );
        assert!(!q.between(bed, Target::Object(bed), Target::Object(chair)));
    }

    #[test]
    fn hull_contains_its_interior() {
        let hull = convex_hull(vec![
            [0.0, 0.0],
            [0.0, 4.0],
            [4.0, 4.0],
            [4.0, 0.0],
            [2.0, 2.0],
        ]);
        assert_eq!(hull.len(), 4);
        assert_eq!(hull_distance(&hull, [2.0, 2.0]), 0.0);
        assert!((hull_distance(&hull, [2.0, 6.0]) - 2.0).abs() < 1e-9);
    }
}
