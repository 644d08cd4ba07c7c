//! Spatial predicate grounding (SPG) with the relation geometry of Lang2LTL-2's upstream module,
//! in grid cells as the adaptation's bridge runs it: left / right / in front of / behind are read
//! relative to the anchor-to-robot direction (a 180° half-plane each), near / next to / at / by
//! as a 360° sweep, `between` as the segment between two anchors, and the four cardinal
//! directions (north = up the map). Every relation holds only within [`MAX_RANGE`] of its anchor:
//! the upstream 25, which in grid cells is 1.25 m.

/// The range of every relation, in cells (upstream `MAX_RANGE = 25`, applied to grid units).
pub const MAX_RANGE: f64 = 25.0;

/// The relations the geometry knows; an unseen one is matched to the most similar by embeddings.
pub const KNOWN_RELATIONS: &[&str] = &[
    "left of",
    "right of",
    "in front of",
    "behind",
    "near",
    "next to",
    "at",
    "by",
    "between",
    "north of",
    "south of",
    "east of",
    "west of",
];

/// The canonical relation a name is, if the geometry knows it.
pub fn canonical(relation: &str) -> Option<&'static str> {
    let r = relation.to_lowercase().replace('_', " ");
    let r = r.trim();
    KNOWN_RELATIONS
        .iter()
        .copied()
        .find(|k| *k == r)
        .or(match r {
            "left" | "to the left of" => Some("left of"),
            "right" | "to the right of" => Some("right of"),
            "front" | "in front" => Some("in front of"),
            "behind of" | "back of" => Some("behind"),
            "close to" | "near to" | "nearby" | "beside" => Some("near"),
            _ => None,
        })
}

/// Whether `relation` holds for a target at `t` given anchors at `anchors` and the robot at
/// `robot` (all `[row, col]` in cells).
pub fn holds(relation: &str, t: [f64; 2], anchors: &[[f64; 2]], robot: [f64; 2]) -> bool {
    let Some(a) = anchors.first().copied() else {
        return false;
    };
    // Math frame: x = col, y = -row (up).
    let v = |p: [f64; 2], q: [f64; 2]| (q[1] - p[1], -(q[0] - p[0]));
    let (dx, dy) = v(a, t);
    let dist = dx.hypot(dy);
    match relation {
        "between" => {
            let Some(b) = anchors.get(1).copied() else {
                return false;
            };
            let (sx, sy) = v(a, b);
            let len2 = sx * sx + sy * sy;
            if len2 == 0.0 {
                return false;
            }
            let s = (dx * sx + dy * sy) / len2;
            let (px, py) = (dx - s * sx, dy - s * sy);
            (0.0..=1.0).contains(&s) && px.hypot(py) <= MAX_RANGE
        }
        _ if dist > MAX_RANGE => false,
        "near" | "next to" | "at" | "by" => true,
        "north of" => dy > 0.0 && dy.abs() >= dx.abs(),
        "south of" => dy < 0.0 && dy.abs() >= dx.abs(),
        "east of" => dx > 0.0 && dx.abs() >= dy.abs(),
        "west of" => dx < 0.0 && dx.abs() >= dy.abs(),
        rel @ ("left of" | "right of" | "in front of" | "behind") => {
            // The anchor faces the robot: front is towards the robot, left is the robot's left
            // when it looks at the anchor.
            let (fx, fy) = v(a, robot);
            let norm = fx.hypot(fy);
            if norm == 0.0 {
                return false;
            }
            let (fx, fy) = (fx / norm, fy / norm);
            let along = dx * fx + dy * fy;
            // The robot looks along -f; its left is -f rotated by +90°: (fy, -fx).
            let side = dx * fy - dy * fx;
            match rel {
                "in front of" => along > 0.0,
                "behind" => along < 0.0,
                "left of" => side > 0.0,
                _ => side < 0.0,
            }
        }
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relation_geometry() {
        // Robot below the anchor (larger row), looking up the map at it.
        let (a, robot) = ([50.0, 50.0], [90.0, 50.0]);
        assert!(holds("in front of", [60.0, 50.0], &[a], robot));
        assert!(holds("behind", [40.0, 50.0], &[a], robot));
        assert!(holds("left of", [50.0, 40.0], &[a], robot));
        assert!(holds("right of", [50.0, 60.0], &[a], robot));
        assert!(!holds("left of", [50.0, 60.0], &[a], robot));
        // 1.25 m: 25 cells.
        assert!(holds("near", [50.0, 74.0], &[a], robot));
        assert!(!holds("near", [50.0, 76.0], &[a], robot));
        assert!(holds("north of", [30.0, 52.0], &[a], robot));
        assert!(holds("between", [50.0, 100.0], &[a, [50.0, 150.0]], robot));
        assert!(!holds("between", [50.0, 200.0], &[a, [50.0, 150.0]], robot));
        assert_eq!(canonical("to the left of"), Some("left of"));
        assert_eq!(canonical("inside"), None);
    }
}
