//! LIMP's deterministic referent grounding (the adaptation's stand-in for its perception): a
//! descriptor's noun is normalised and looked up by category (through an alias table, selector
//! words and plurals stripped, a substring match as the last resort) among the map's rooms and
//! objects; a spatial predicate filters the candidates with 2D comparators in the map frame (left =
//! smaller column, above = smaller row); more than one candidate left is resolved by the extended
//! variant's tie-break. In-front-of and behind need an orientation the map does not give.

use super::parse::Crd;
use crate::common::failure::Failure;
use crate::common::inventory::{Ap, ApKind, Inventory};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;

/// `isnextto`: the largest footprint-to-footprint distance, in cells (unless in the same room).
pub const NEXT_TO_CELLS: f64 = 45.0;
/// `isbetween`: the largest distance of the centroid from the anchors' segment, in cells.
pub const BETWEEN_CELLS: f64 = 30.0;

const ALIASES: &[(&str, &str)] = &[
    ("couch", "sofa"),
    ("tv", "television"),
    ("lamp", "floor_lamp"),
    ("table", "dining_table"),
    ("door", "doorway"),
    ("plant", "house_plant"),
    ("houseplant", "house_plant"),
    ("fridge", "fridge"),
    ("refrigerator", "fridge"),
    ("trash_can", "garbage_can"),
    ("bin", "garbage_can"),
    ("tv_cabinet", "tv_stand"),
    ("countertop", "counter_top"),
    ("phone", "cell_phone"),
    ("armchair", "arm_chair"),
    ("living_room", "living_room"),
    ("lounge", "living_room"),
];

const SELECTORS: &[&str] = &[
    "the", "a", "an", "nearest", "closest", "farthest", "furthest", "second", "third", "other",
    "next", "largest", "biggest", "smallest", "first", "last",
];

/// The category a noun names, if any (normalised, aliased, then a substring of a category).
pub fn category_of(noun: &str, inventory: &Inventory) -> Option<String> {
    let words: Vec<String> = noun
        .to_lowercase()
        .split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty() && !SELECTORS.contains(w))
        .map(str::to_string)
        .collect();
    if words.is_empty() {
        return None;
    }
    let joined = words.join("_");
    let singular = |s: &str| -> String {
        s.strip_suffix("ies")
            .map(|b| format!("{b}y"))
            .or_else(|| {
                s.strip_suffix('s')
                    .filter(|b| !b.ends_with('s'))
                    .map(str::to_string)
            })
            .unwrap_or_else(|| s.to_string())
    };
    let has = |c: &str| inventory.aps.iter().any(|a| a.category == c);
    for cand in [joined.clone(), singular(&joined)] {
        if has(&cand) {
            return Some(cand);
        }
        if let Some((_, to)) = ALIASES.iter().find(|(from, _)| *from == cand)
            && has(to)
        {
            return Some(to.to_string());
        }
    }
    let last = singular(words.last().expect("non-empty"));
    if has(&last) {
        return Some(last);
    }
    let mut cats: Vec<&str> = inventory.aps.iter().map(|a| a.category.as_str()).collect();
    cats.dedup();
    cats.into_iter()
        .find(|c| c.contains(&singular(&joined)) || singular(&joined).contains(c))
        .map(str::to_string)
}

/// The candidates of a descriptor: by category, filtered by its spatial predicate.
pub fn candidates<'i>(
    crd: &Crd,
    inventory: &'i Inventory,
    map: &SemanticMap,
) -> Result<Vec<&'i Ap>, Failure> {
    let cat = category_of(&crd.noun, inventory).ok_or_else(|| {
        Failure::new(
            "grounding_failed",
            format!("no room or object category for `{}`", crd.noun),
        )
    })?;
    let base: Vec<&Ap> = inventory.aps.iter().filter(|a| a.category == cat).collect();
    let Some((pred, args)) = &crd.relation else {
        return Ok(base);
    };
    let anchors: Vec<Vec<&Ap>> = args
        .iter()
        .map(|a| candidates(a, inventory, map))
        .collect::<Result<_, _>>()?;
    let any = |list: &[&Ap], f: &dyn Fn(&Ap) -> bool| list.iter().any(|a| f(a));
    let keep: Vec<&Ap> = match pred.as_str() {
        "isinfrontof" | "isbehind" => {
            return Err(Failure::new(
                "unsupported_comparator",
                format!("`{pred}` needs the anchor's orientation, which the map does not give"),
            ));
        }
        "isleftof" | "isrightof" | "isabove" | "isbelow" => {
            let first = anchors.first().ok_or_else(|| missing(pred))?;
            base.into_iter()
                .filter(|x| {
                    any(first, &|y| match pred.as_str() {
                        "isleftof" => x.center[1] < y.center[1],
                        "isrightof" => x.center[1] > y.center[1],
                        "isabove" => x.center[0] < y.center[0],
                        _ => x.center[0] > y.center[0],
                    })
                })
                .collect()
        }
        "isnextto" => {
            let first = anchors.first().ok_or_else(|| missing(pred))?;
            let dist = |x: &Ap| {
                first
                    .iter()
                    .filter(|y| y.name != x.name)
                    .map(|y| footprint_distance(map, x, y))
                    .fold(f64::INFINITY, f64::min)
            };
            let near: Vec<(&Ap, f64)> = base
                .into_iter()
                .map(|x| (x, dist(x)))
                .filter(|(x, d)| {
                    *d <= NEXT_TO_CELLS
                        || any(first, &|y| {
                            y.room.is_some() && y.room == x.room && y.name != x.name
                        })
                })
                .collect();
            // The extended variant keeps those within a cell of the closest.
            let best = near.iter().map(|(_, d)| *d).fold(f64::INFINITY, f64::min);
            near.into_iter()
                .filter(|(_, d)| *d <= best + 1.0)
                .map(|(x, _)| x)
                .collect()
        }
        "isbetween" => {
            let (Some(a), Some(b)) = (anchors.first(), anchors.get(1)) else {
                return Err(missing(pred));
            };
            base.into_iter()
                .filter(|x| {
                    a.iter().any(|p| {
                        b.iter()
                            .any(|q| p.name != q.name && between(x.center, p.center, q.center))
                    })
                })
                .collect()
        }
        "isinside" => {
            let first = anchors.first().ok_or_else(|| missing(pred))?;
            base.into_iter()
                .filter(|x| any(first, &|y| matches!(y.kind, ApKind::Room(r) if x.room == Some(r) && x.name != y.name)))
                .collect()
        }
        "contains" => {
            let first = anchors.first().ok_or_else(|| missing(pred))?;
            base.into_iter()
                .filter(|x| matches!(x.kind, ApKind::Room(r) if any(first, &|y| y.room == Some(r) && !y.is_room())))
                .collect()
        }
        other => {
            return Err(Failure::new(
                "unsupported_predicate",
                format!("`{other}` is not one of LIMP's spatial predicates"),
            ));
        }
    };
    Ok(keep)
}

fn missing(pred: &str) -> Failure {
    Failure::new(
        "grounding_failed",
        format!("`{pred}` has too few arguments"),
    )
}

fn between(x: [f64; 2], a: [f64; 2], b: [f64; 2]) -> bool {
    let (dr, dc) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dr * dr + dc * dc;
    let t = if len2 == 0.0 {
        0.0
    } else {
        (((x[0] - a[0]) * dr + (x[1] - a[1]) * dc) / len2).clamp(0.0, 1.0)
    };
    let (pr, pc) = (a[0] + t * dr, a[1] + t * dc);
    let inside = x[0] >= a[0].min(b[0]) - BETWEEN_CELLS
        && x[0] <= a[0].max(b[0]) + BETWEEN_CELLS
        && x[1] >= a[1].min(b[1]) - BETWEEN_CELLS
        && x[1] <= a[1].max(b[1]) + BETWEEN_CELLS;
    inside && (x[0] - pr).hypot(x[1] - pc) <= BETWEEN_CELLS
}

/// The cells of an AP's instance: an object's footprint (or its centre), a room's cells.
pub fn instance_cells(map: &SemanticMap, ap: &Ap) -> Vec<Cell> {
    match ap.kind {
        ApKind::Object(id) => {
            let fp = map
                .object(id)
                .map(|o| o.footprint.clone())
                .unwrap_or_default();
            if fp.is_empty() {
                vec![Cell::new(
                    ap.center[0].max(0.0).round() as u32,
                    ap.center[1].max(0.0).round() as u32,
                )]
            } else {
                fp
            }
        }
        ApKind::Room(id) => map.room_cells(id),
    }
}

/// The smallest distance between two instances' cells, in cells (bounded work: large
/// footprints are sampled on their bounding-box border).
fn footprint_distance(map: &SemanticMap, a: &Ap, b: &Ap) -> f64 {
    let sample = |cells: Vec<Cell>| -> Vec<Cell> {
        if cells.len() <= 400 {
            return cells;
        }
        let step = cells.len() / 400 + 1;
        cells.into_iter().step_by(step).collect()
    };
    let (x, y) = (
        sample(instance_cells(map, a)),
        sample(instance_cells(map, b)),
    );
    x.iter()
        .map(|c| c.nearest_dist(&y))
        .fold(f64::INFINITY, f64::min)
}

/// The selector word of a noun that changes the tie-break, if any.
pub fn selector(noun: &str) -> Option<&'static str> {
    let lower = noun.to_lowercase();
    let words: Vec<&str> = lower.split(|c: char| !c.is_alphanumeric()).collect();
    for (w, s) in [
        ("farthest", "farthest"),
        ("furthest", "farthest"),
        ("largest", "largest"),
        ("biggest", "largest"),
        ("smallest", "smallest"),
        ("second", "second"),
        ("third", "third"),
        ("other", "second"),
        ("next", "second"),
    ] {
        if words.contains(&w) {
            return Some(s);
        }
    }
    None
}
