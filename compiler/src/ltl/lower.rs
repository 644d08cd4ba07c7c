//! RouteIR → LTLf: the hard part of a grounded route as one formula over its places.
//!
//! * Destinations and must-pass places are *visits*, in route order (a stage's passes, then its
//!   destination). A visit is reached at the first position the route is in it, as in the
//!   planners and in HCS.
//! * An avoid active in every stage is a global `G !a`.
//! * An avoid active in some stages guards the visits of those stages:
//!   `(!x & !a) U (x & !a & rest)` — `a` is not entered before `x` is first reached, nor on that
//!   cell, and the rest of the route starts there. A visit with no stage-scoped avoid at or after
//!   it is written `F(x & rest)`, which is equivalent and easier to read.
//! * An avoid's spatial scope is kept (its atom is the avoided place inside the scope, the RouteIR
//!   semantics); soft preferences and path shapes have no meaning in the formula and are listed as
//!   dropped.

use super::syntax::{Formula, Kind};
use crate::ir::{ConstraintKind, Place, PlaceKind, RouteIr, Shape, StageScope};

/// What an atom stands for, so a planner can build its mask.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum AtomSource {
    /// The destination of RouteIR stage `stage` (reached as the planner's goal mask).
    Target { stage: usize },
    /// Must-pass `index` of stage `stage`.
    Pass { stage: usize, index: usize },
    /// The cells avoided by RouteIR constraint `constraint` (inside its spatial scope).
    Avoid { constraint: usize },
    /// A place named in an `ltl` route form.
    Binding { name: String },
}

#[derive(Clone, Debug, PartialEq)]
pub struct AtomDef {
    /// The name used in the formula.
    pub name: String,
    /// A human-readable description (place label, avoided area).
    pub meaning: String,
    pub source: AtomSource,
}

/// One visit of the ordered chain, with the stage-scoped avoids active while heading to it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Visit {
    pub atom: usize,
    pub avoids: Vec<usize>,
}

/// The hard structure of a route: ordered visits and avoids, atoms by index.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Skeleton {
    pub visits: Vec<Visit>,
    pub global_avoids: Vec<usize>,
}

impl Skeleton {
    /// The formula, with atom `i` written `names[i]`.
    pub fn formula(&self, names: &[String]) -> Formula {
        let atom = |i: usize| Formula::atom(&names[i]);
        let not = |i: usize| Formula::negation(atom(i));
        let and = |a: Formula, b: Formula| Formula::new(Kind::And(Box::new(a), Box::new(b)));
        let mut rest: Option<Formula> = None;
        let mut scoped_after = false;
        for v in self.visits.iter().rev() {
            scoped_after |= !v.avoids.is_empty();
            let reach = |extra: Vec<Formula>, rest: Option<Formula>| {
                let mut parts = vec![atom(v.atom)];
                parts.extend(extra);
                parts.extend(rest);
                Formula::and_all(parts)
            };
            rest = Some(if scoped_after {
                let guard: Vec<Formula> = v.avoids.iter().map(|&a| not(a)).collect();
                let mut before = vec![not(v.atom)];
                before.extend(guard.iter().cloned());
                Formula::new(Kind::Until(
                    Box::new(Formula::and_all(before)),
                    Box::new(reach(guard, rest)),
                ))
            } else {
                Formula::new(Kind::Eventually(Box::new(reach(vec![], rest))))
            });
        }
        let mut parts: Vec<Formula> = rest.into_iter().collect();
        for &a in &self.global_avoids {
            parts.push(Formula::new(Kind::Always(Box::new(not(a)))));
        }
        parts
            .into_iter()
            .reduce(and)
            .unwrap_or(Formula::new(Kind::True))
    }
}

/// A RouteIR as LTLf: the atoms, the formula, and what had to be left out.
#[derive(Clone, Debug, PartialEq)]
pub struct LtlRoute {
    pub atoms: Vec<AtomDef>,
    pub skeleton: Skeleton,
    pub formula: Formula,
    /// One line per constraint the formula cannot express (soft preferences, path shapes).
    pub dropped: Vec<String>,
}

impl LtlRoute {
    pub fn atom_names(&self) -> Vec<String> {
        self.atoms.iter().map(|a| a.name.clone()).collect()
    }

    /// The `--emit ltl` text: `//` lines for the atoms and the dropped constraints, then the
    /// formula on the last line.
    pub fn text(&self) -> String {
        let mut out = String::new();
        for a in &self.atoms {
            out.push_str(&format!("// {}: {}\n", a.name, a.meaning));
        }
        for d in &self.dropped {
            out.push_str(&format!("// dropped: {d}\n"));
        }
        out.push_str(&self.formula.to_string());
        out.push('\n');
        out
    }
}

/// An identifier for a place: `category_id` for objects and rooms, the construction for regions.
pub fn base_name(p: &Place) -> String {
    let raw = match &p.kind {
        PlaceKind::Object { id, category, .. } => format!("{category}_{id}"),
        PlaceKind::Room { id, category } => format!("{category}_{id}"),
        PlaceKind::Region { construction } => construction.kind.clone(),
        PlaceKind::AnyOf { members } => match members.first() {
            Some(m) => format!("any_{}", base_name(m)),
            None => "any".into(),
        },
    };
    sanitize(&raw)
}

/// Lower-case letters, digits and `_`, starting with a letter, never a keyword of the syntax.
pub fn sanitize(raw: &str) -> String {
    let mut s: String = raw
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    while s.contains("__") {
        s = s.replace("__", "_");
    }
    let mut s = s.trim_matches('_').to_string();
    if s.is_empty() || !s.starts_with(|c: char| c.is_ascii_alphabetic()) {
        s = format!("p_{s}");
    }
    if ["true", "false", "tt", "ff"].contains(&s.as_str()) {
        s.push('_');
    }
    s
}

struct Namer {
    atoms: Vec<AtomDef>,
    /// Place (or place-in-scope) of each atom, to reuse an atom for the same area.
    keys: Vec<(bool, Place, Option<Place>)>,
}

impl Namer {
    fn fresh(&self, base: &str) -> String {
        if !self.atoms.iter().any(|a| a.name == base) {
            return base.to_string();
        }
        (2..)
            .map(|k| format!("{base}_{k}"))
            .find(|n| !self.atoms.iter().any(|a| a.name == *n))
            .unwrap_or_else(|| base.to_string())
    }

    /// The atom for `place` (visited, or avoided within `scope`), reused when the area is the same.
    fn atom(
        &mut self,
        place: &Place,
        avoid: bool,
        scope: Option<&Place>,
        source: AtomSource,
    ) -> usize {
        // Visiting and avoiding a room or region mean the same cells; an object's avoided cells
        // (its footprint) differ from where it is reached (the band around it).
        let object = matches!(place.kind, PlaceKind::Object { .. });
        let key_avoid = avoid && (object || scope.is_some());
        if let Some(i) = self
            .keys
            .iter()
            .position(|(a, p, s)| *a == key_avoid && p == place && s.as_ref() == scope)
        {
            return i;
        }
        let mut base = base_name(place);
        let mut meaning = place.label.clone();
        if let Some(s) = scope {
            base = format!("{base}_in_{}", base_name(s));
            meaning = format!("{meaning}, inside {}", s.label);
        } else if key_avoid {
            base.push_str("_area");
            meaning = format!("the footprint of {meaning}");
        }
        let name = self.fresh(&base);
        self.atoms.push(AtomDef {
            name,
            meaning,
            source,
        });
        self.keys.push((key_avoid, place.clone(), scope.cloned()));
        self.atoms.len() - 1
    }
}

/// Lowers a grounded route to LTLf.
pub fn lower(ir: &RouteIr) -> LtlRoute {
    let mut namer = Namer {
        atoms: Vec::new(),
        keys: Vec::new(),
    };
    let all: Vec<usize> = (0..ir.stages.len()).collect();
    let mut sk = Skeleton::default();
    let mut dropped = Vec::new();
    // Visits first, so destination atoms get the plain names.
    let mut stage_visits: Vec<Vec<usize>> = Vec::new();
    for (si, st) in ir.stages.iter().enumerate() {
        let mut v = Vec::new();
        for (pi, p) in st.passes.iter().enumerate() {
            v.push(namer.atom(
                &p.place,
                false,
                None,
                AtomSource::Pass {
                    stage: si,
                    index: pi,
                },
            ));
        }
        v.push(namer.atom(&st.target, false, None, AtomSource::Target { stage: si }));
        stage_visits.push(v);
    }
    let mut scoped: Vec<Vec<usize>> = vec![Vec::new(); ir.stages.len()];
    for (ci, c) in ir.constraints.iter().enumerate() {
        match &c.kind {
            ConstraintKind::Avoid { place } => {
                let a = namer.atom(
                    place,
                    true,
                    c.spatial_scope.as_ref(),
                    AtomSource::Avoid { constraint: ci },
                );
                let stages = match &c.stage_scope {
                    StageScope::Global => all.clone(),
                    StageScope::Stages(s) => s.clone(),
                };
                if all.iter().all(|i| stages.contains(i)) {
                    if !sk.global_avoids.contains(&a) {
                        sk.global_avoids.push(a);
                    }
                } else {
                    for s in stages {
                        if let Some(list) = scoped.get_mut(s)
                            && !list.contains(&a)
                        {
                            list.push(a);
                        }
                    }
                }
            }
            other => dropped.push(format!("{} {} (soft: not part of the formula)", c.id, {
                match other {
                    ConstraintKind::Near { reference } => {
                        format!("prefer near {}", reference.label)
                    }
                    ConstraintKind::Far { reference } => {
                        format!("prefer far from {}", reference.label)
                    }
                    ConstraintKind::Relative { closer, farther } => format!(
                        "prefer closer to {} than to {}",
                        closer.label, farther.label
                    ),
                    ConstraintKind::PathShape {
                        shape,
                        around,
                        waypoints,
                        ..
                    } => format!(
                        "prefer {} {} {} ({} waypoints)",
                        format!("{shape:?}").to_lowercase(),
                        if *shape == Shape::Through {
                            "by"
                        } else {
                            "around"
                        },
                        around.label,
                        waypoints.len()
                    ),
                    ConstraintKind::Clearance { distance_m } => {
                        format!("prefer clearance {distance_m} m")
                    }
                    ConstraintKind::Avoid { .. } => String::new(),
                }
            })),
        }
    }
    for (si, v) in stage_visits.iter().enumerate() {
        for &atom in v {
            sk.visits.push(Visit {
                atom,
                avoids: scoped[si].clone(),
            });
        }
    }
    let names: Vec<String> = namer.atoms.iter().map(|a| a.name.clone()).collect();
    let formula = sk.formula(&names);
    LtlRoute {
        atoms: namer.atoms,
        skeleton: sk,
        formula,
        dropped,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(n: &[&str]) -> Vec<String> {
        n.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn chains_and_scoped_avoids() {
        let sk = Skeleton {
            visits: vec![
                Visit {
                    atom: 0,
                    avoids: vec![],
                },
                Visit {
                    atom: 1,
                    avoids: vec![],
                },
            ],
            global_avoids: vec![2],
        };
        assert_eq!(
            sk.formula(&names(&["a", "b", "c"])).to_string(),
            "F(a & F b) & G !c"
        );
        let sk = Skeleton {
            visits: vec![
                Visit {
                    atom: 0,
                    avoids: vec![],
                },
                Visit {
                    atom: 1,
                    avoids: vec![2],
                },
            ],
            global_avoids: vec![],
        };
        assert_eq!(
            sk.formula(&names(&["a", "b", "c"])).to_string(),
            "!a U (a & (!b & !c) U (b & !c))"
        );
        assert_eq!(Skeleton::default().formula(&[]).to_string(), "true");
    }

    #[test]
    fn names_are_identifiers() {
        assert_eq!(sanitize("Living Room #3"), "living_room_3");
        assert_eq!(sanitize("3d"), "p_3d");
        assert_eq!(sanitize("true"), "true_");
    }
}
