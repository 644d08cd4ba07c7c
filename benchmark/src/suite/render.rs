//! Rendering an episode plan into its three views: the Map2Route annotation, the gold `.m2r`
//! program, and the instruction text. Each clause is realised from the same plan item as the
//! program statement beside it, and the pair is recorded in `m2rc_generation.clauses`.

use super::annotate::{
    TIMESTAMP, avoid_json, cells_json, default_clearance, footprints_json, global_scope, round3,
    soft_base, stage_scope, wrap,
};
use super::avoid::AROUND_M;
use super::generate::{
    Clause, Difficulty, EpisodeMeta, GeneratedEpisode, RefStat, START_RADIUS, Scene, disc,
    room_traversal,
};
use super::index::MapIndex;
use super::plan::{AvoidPlace, Dest, Pref, RoomScope, ShapeKind, SoftPlan, Stage, Subject};
use super::realise::{self, Position, Speaker, sentence};
use super::refs::{ObjRef, RoomRef};
use crate::episode::{GENERATION_KEY, GOLD_PROGRAM_KEY};
use m2rc_stdlib::grid::Cell;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};
use std::collections::BTreeMap;

mod dest;
mod scope;
mod shape;

use super::determinacy::Reader;
use scope::{LegPhrase, StageDest};

/// How the canonical trajectory of a `through` was made, in its annotation.
const THROUGH_NOTES: &str = "generated: the language's `through` (free floor within 0.5 m of each object, in order), entered and left where the reference route enters and leaves the room, each region reached by the shortest path over the room's legal floor, the objects in the order of the shortest such trajectory";

/// What rendering accumulates.
struct Out {
    sentences: Vec<String>,
    clauses: Vec<Clause>,
    refs: Vec<RefStat>,
    hard: Vec<Value>,
    soft: Vec<Value>,
    lets: Vec<String>,
    route: Vec<String>,
    soft_counts: BTreeMap<String, usize>,
}

impl Out {
    /// Adds a sentence realising `program`, with the templates used since the last clause.
    fn say(&mut self, sp: &mut Speaker<'_>, text: String, program: String) {
        let templates = std::mem::take(&mut sp.templates);
        self.clauses.push(Clause {
            templates,
            text: text.clone(),
            program,
        });
        self.sentences.push(text);
    }

    fn stat(&mut self, ix: &MapIndex<'_>, role: &str, r: &ObjRef, text: &str) {
        self.refs.push(RefStat {
            role: role.to_string(),
            expression: text.to_string(),
            category: r.category().to_string(),
            depth: r.depth(),
            candidates: r.candidates(ix),
            object_categories: r.object_cats().iter().map(|c| c.to_string()).collect(),
            room_categories: r.rooms().iter().map(|x| x.category().to_string()).collect(),
            superlative_over: r
                .rooms()
                .iter()
                .filter_map(|x| x.superlative_over(ix))
                .collect(),
        });
    }

    fn stat_room(&mut self, ix: &MapIndex<'_>, role: &str, r: &RoomRef, text: &str) {
        self.refs.push(RefStat {
            role: role.to_string(),
            expression: text.to_string(),
            category: r.category().to_string(),
            depth: r.depth(),
            candidates: ix.rooms_of_cat(r.category()).len(),
            object_categories: vec![],
            room_categories: vec![r.category().to_string()],
            superlative_over: r.superlative_over(ix).into_iter().collect(),
        });
    }

    /// A reference to a part of the building (corners, walls, doorways): `candidates` is how many
    /// the house has, what a reader chooses among before the rest of the phrase narrows it.
    fn stat_structure(&mut self, role: &str, what: &str, candidates: usize, text: &str) {
        self.refs.push(RefStat {
            role: role.to_string(),
            expression: text.to_string(),
            category: what.to_string(),
            depth: 2,
            candidates,
            object_categories: vec![],
            room_categories: vec![],
            superlative_over: vec![],
        });
    }

    /// A reference made by a category inside a scope room ("the fridge" while in the kitchen).
    fn stat_implied(&mut self, ix: &MapIndex<'_>, role: &str, cat: &str, text: &str) {
        self.refs.push(RefStat {
            role: role.to_string(),
            expression: text.to_string(),
            category: cat.to_string(),
            depth: 2,
            candidates: ix.all_of_cat(cat).len(),
            object_categories: vec![cat.to_string()],
            room_categories: vec![],
            superlative_over: vec![],
        });
    }
}

impl<'a> Scene<'a> {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn render(
        &self,
        rng: &mut ChaCha8Rng,
        id: u32,
        difficulty: Difficulty,
        start: Cell,
        stages: Vec<Stage>,
        global_avoids: Vec<super::plan::Avoid>,
        route: Vec<Cell>,
    ) -> GeneratedEpisode {
        let ix = &self.ix;
        let mut sp = Speaker::new(rng);
        sp.reader.start = Some(start);
        let mut out = Out {
            sentences: vec![],
            clauses: vec![],
            refs: vec![],
            hard: vec![],
            soft: vec![],
            lets: vec![],
            route: vec![],
            soft_counts: BTreeMap::new(),
        };
        let start_cells: Vec<Value> = disc(start, START_RADIUS)
            .into_iter()
            .filter(|&c| ix.free.passable(c))
            .map(|c| json!([c.row, c.col]))
            .collect();
        out.hard.push(json!({
            "constraint_id": "start", "kind": "must_pass", "shape": "freeform",
            "center": [start.row as f64, start.col as f64], "radius": START_RADIUS,
            "width": 2.0 * START_RADIUS, "height": 2.0 * START_RADIUS, "order": 1, "source": "custom",
            "object_id": null, "scope": global_scope(), "label": "start", "cells": start_cells,
        }));
        let n = stages.len();
        let mut objects_json: Vec<Value> = Vec::new();
        let (mut avoid_no, mut soft_no) = (0usize, 0usize);
        // Texts and program expressions of the destinations, rendered first so a pair can be
        // stated out of order.
        // Destinations are described in the order the instruction mentions them, so a room is
        // described where it first appears and referred back to afterwards.
        let mut dests: Vec<Option<(String, String, String)>> = vec![None; n];
        let mut skip_dest_sentence = vec![false; n];
        for (k, stage) in stages.iter().enumerate() {
            let order = k as u32 + 2;
            let back = matches!(stage.dest, Dest::Return);
            let var = if back {
                "start".to_string()
            } else {
                format!("t{}", k + 1)
            };
            let pos = match (n, k) {
                (1, _) => Position::Only,
                (_, 0) => Position::First,
                (n, k) if k + 1 == n => Position::Last,
                _ => Position::Middle,
            };
            let pair = !skip_dest_sentence[k]
                && k + 1 < n
                && matches!(stage.dest, Dest::Object { .. })
                && matches!(stages[k + 1].dest, Dest::Object { .. })
                && stage.softs.is_empty()
                && stage.avoids.is_empty()
                && matches!(pos, Position::First | Position::Only)
                && sp.chance(0.3);
            if pair {
                // "Before you go to B, stop at A": B is said (and read) first.
                skip_dest_sentence[k + 1] = true;
                dests[k + 1] = Some(self.dest_text(&mut sp, &mut out, k + 1, &stages));
            }
            if dests[k].is_none() {
                dests[k] = Some(self.dest_text(&mut sp, &mut out, k, &stages));
            }
            let (text, m2r, short) = dests[k].clone().unwrap_or_default();
            let (text, m2r, short) = (&text, &m2r, &short);
            if !back {
                out.lets.push(format!("let {var} = {m2r}"));
            }
            if !skip_dest_sentence[k] {
                let s = if pair {
                    let next = dests[k + 1].clone().unwrap_or_default();
                    realise::before_pair(&mut sp, text, &next.0)
                } else if matches!(stage.dest, Dest::Conditional { .. }) {
                    text.clone()
                } else if back {
                    realise::return_to_start(&mut sp)
                } else {
                    realise::destination(&mut sp, pos, text)
                };
                let prog = if pair {
                    format!("go {var}\ngo t{}", k + 2)
                } else {
                    format!("go {var}")
                };
                out.say(&mut sp, s, prog);
            }
            let (center, radius) = (stage.center, stage.radius);
            let target_id = match &stage.dest {
                Dest::Object { id, .. } | Dest::Conditional { id, .. } | Dest::Other { id, .. } => {
                    json!(id)
                }
                _ => Value::Null,
            };
            out.hard.push(json!({
                "constraint_id": format!("target_{}", k + 1), "kind": "must_pass", "shape": "freeform",
                "center": center, "radius": radius, "width": 2.0 * radius, "height": 2.0 * radius,
                "order": order, "source": if target_id.is_null() { "custom" } else { "template_object" },
                "object_id": target_id, "scope": global_scope(), "label": text,
                "cells": cells_json(ix, &stage.goal),
            }));
            if let Some(&first) = stage.anchor_objects.first() {
                let o = ix.object(first);
                objects_json.push(json!({
                    "order": k + 1, "object_id": first, "name": o.name, "category": o.category,
                    "center": [round3(center[0]), round3(center[1])],
                }));
            }
            // The destination object a short name ("the desk") names by its category.
            let named = match &stage.dest {
                Dest::Object { id, .. } | Dest::Conditional { id, .. } => Some(*id),
                _ => None,
            };
            // `before`: the reader where the phrase stands (it opens its sentence).
            let leg_phrase = |sp: &mut Speaker<'_>, before: &Reader| {
                let by_name = self.leg_read(before, named);
                let (text, names) = if back {
                    (realise::leg_back(sp), None)
                } else if matches!(stage.dest, Dest::Conditional { .. }) {
                    // Naming the target would give away which branch of the condition holds.
                    (realise::leg_there(sp), None)
                } else if n > 1
                    && (named.is_none() || by_name == named.into_iter().collect::<Vec<_>>())
                {
                    (realise::leg(sp, short), named)
                } else if n > 1 && before.last_destination == named {
                    // "The desk" would be another desk the instruction named: "there" is the
                    // destination named last.
                    let t = realise::leg_there(sp);
                    let read = named.into_iter().collect();
                    return LegPhrase {
                        text: t,
                        names: named,
                        read,
                    };
                } else if n > 1 {
                    // Neither names it: the check flags the mention and the plan is redrawn.
                    (realise::leg(sp, short), named)
                } else {
                    let t = sp.pick(
                        "leg.only",
                        &["on the way there", "along the way", "on your way"],
                    );
                    (t.to_string(), None)
                };
                let read = self.leg_read(before, names);
                LegPhrase { text, names, read }
            };
            let mut body: Vec<String> = Vec::new();
            for avoid in &stage.avoids {
                avoid_no += 1;
                let before = sp.reader.clone();
                let (t, m2r, kind) = self.avoid_text(&mut sp, &mut out, &avoid.place);
                // The sentence may open with the leg phrase: read it before the avoided place.
                let l = leg_phrase(&mut sp, &before);
                self.check_leg(&mut sp, &l);
                let s = realise::avoid(&mut sp, kind, &t, Some(&l.text));
                out.say(&mut sp, s, format!("avoid {m2r}"));
                out.hard.push(avoid_json(
                    ix,
                    avoid_no,
                    &avoid.cells,
                    &t,
                    stage_scope(order),
                ));
                body.push(format!("avoid {m2r}"));
            }
            for soft in &stage.softs {
                soft_no += 1;
                *out.soft_counts.entry(soft.kind().to_string()).or_default() += 1;
                let before = sp.reader.clone();
                let l = leg_phrase(&mut sp, &before);
                let (json, line) = self.soft(
                    &mut sp,
                    &mut out,
                    soft,
                    &var,
                    StageDest {
                        short,
                        room: stage.room,
                        named,
                    },
                    order,
                    soft_no,
                    &l,
                    n,
                );
                out.soft.push(json);
                body.push(line);
            }
            if body.is_empty() {
                out.route.push(format!("  go {var}"));
            } else {
                out.route.push(format!("  go {var} {{"));
                out.route.extend(body.iter().map(|b| format!("    {b}")));
                out.route.push("  }".to_string());
            }
        }
        for avoid in &global_avoids {
            avoid_no += 1;
            let (t, m2r, kind) = self.avoid_text(&mut sp, &mut out, &avoid.place);
            let s = realise::avoid(&mut sp, kind, &t, None);
            out.say(&mut sp, s, format!("avoid {m2r}"));
            out.hard
                .push(avoid_json(ix, avoid_no, &avoid.cells, &t, global_scope()));
            out.route.push(format!("  avoid {m2r}"));
        }
        out.soft.push(default_clearance());
        self.finish(
            sp,
            out,
            id,
            difficulty,
            start,
            n,
            avoid_no,
            objects_json,
            route,
        )
    }

    /// (text, program, kind) of a must-avoid's place.
    fn avoid_text(
        &self,
        sp: &mut Speaker<'_>,
        out: &mut Out,
        place: &AvoidPlace,
    ) -> (String, String, &'static str) {
        let ix = &self.ix;
        match place {
            AvoidPlace::Room(r) => {
                let (t, _) = sp.room_said(ix, r, "must-avoid");
                out.stat_room(ix, "must-avoid", r, &t);
                (t, r.m2r(), "room")
            }
            AvoidPlace::Around(x) => {
                let (t, read) = x.said(ix, sp);
                out.stat(ix, "must-avoid", x, &t);
                let gold = x.resolve(ix, sp.reader.start);
                sp.reader.note("must-avoid", &t, gold, read);
                (
                    t,
                    format!("area_near({}, within: {AROUND_M:.1}m)", x.m2r()),
                    "around",
                )
            }
            AvoidPlace::Between(a, b) => {
                let (ta, tb) = self.partners(sp, a, b);
                out.stat(ix, "must-avoid", a, &ta);
                out.stat(ix, "must-avoid", b, &tb);
                (
                    format!("{ta} and {tb}"),
                    format!("area_between({}, {})", a.m2r(), b.m2r()),
                    "between",
                )
            }
        }
    }

    /// One stage-scoped preference: its annotation, its program line, and its sentence.
    #[allow(clippy::too_many_arguments)]
    fn soft(
        &self,
        sp: &mut Speaker<'_>,
        out: &mut Out,
        soft: &SoftPlan,
        var: &str,
        dest: StageDest<'_>,
        order: u32,
        no: usize,
        leg: &LegPhrase,
        stages: usize,
    ) -> (Value, String) {
        let ix = &self.ix;
        let role = format!("{} preference", soft.kind());
        // The map's own room name, as the pictures and `m2rc compile` name rooms.
        let room = ix.map.room(soft.room).map_or_else(
            || format!("room {}", soft.room),
            m2rc_compiler::eval::room_name,
        );
        let label = format!("{} in {room}", soft.kind());
        if let Pref::Shape(shape) = &soft.pref
            && shape.kind != ShapeKind::Through
        {
            return self.loop_soft(
                sp,
                out,
                soft,
                shape,
                var,
                dest,
                leg,
                (no, order),
                &label,
                &role,
            );
        }
        let (s_m2r, s_text) = self.scope(sp, out, soft, var, dest);
        sp.implied_room = Some(soft.room);
        let (kind, pref_text, pref_m2r, ids): (&str, String, String, Vec<Vec<u32>>) =
            match &soft.pref {
                Pref::Near(x) => {
                    let (t, m) = self.subject_text(sp, out, x, &s_m2r, &role);
                    let said = if soft.passing {
                        realise::near_passing(sp, &t)
                    } else {
                        realise::near(sp, &t)
                    };
                    ("near_preference", said, format!("near({m})"), vec![x.ids()])
                }
                Pref::Far(x) => {
                    let (t, m) = self.subject_text(sp, out, x, &s_m2r, &role);
                    (
                        "far_preference",
                        realise::far(sp, &t),
                        format!("far({m})"),
                        vec![x.ids()],
                    )
                }
                Pref::Relative(a, b) => {
                    let (ta, ma) = self.subject_text(sp, out, a, &s_m2r, &role);
                    let (tb, mb) = self.subject_text(sp, out, b, &s_m2r, &role);
                    (
                        "relative_preference",
                        realise::relative(sp, &ta, &tb),
                        format!("closer({ma}, {mb})"),
                        vec![a.ids(), b.ids()],
                    )
                }
                Pref::Shape(shape) => {
                    let said: Vec<(String, String)> = shape
                        .via
                        .iter()
                        .map(|x| self.subject_text(sp, out, x, &s_m2r, &role))
                        .collect();
                    let texts: Vec<&str> = said.iter().map(|(t, _)| t.as_str()).collect();
                    let m2r: Vec<&str> = said.iter().map(|(_, m)| m.as_str()).collect();
                    (
                        "path_shape_preference",
                        realise::through(sp, &texts),
                        format!("through({})", m2r.join(", ")),
                        shape.via.iter().map(Subject::ids).collect(),
                    )
                }
            };
        sp.implied_room = None;
        sp.reader.scope = None;
        let mut c = soft_base(no, kind, stage_scope(order), &label, ix, &soft.region);
        if let [one] = ids.as_slice() {
            c["object_ids"] = json!(one);
            c["reference_region"] =
                json!({"mode": "object", "object_id": one[0], "cells": footprints_json(ix, one)});
        } else {
            let firsts: Vec<u32> = ids.iter().map(|x| x[0]).collect();
            c["object_ids"] = json!(firsts);
            let regions: Vec<Value> = ids
                .iter()
                .map(|x| json!({"object_id": x[0], "cells": footprints_json(ix, x)}))
                .collect();
            c["reference_regions"] = json!(regions);
        }
        if let Pref::Shape(shape) = &soft.pref {
            shape::annotate(&mut c, shape, "through", "unspecified", THROUGH_NOTES);
        }
        let with_leg = stages > 1 && soft.scope != RoomScope::Start && sp.chance(0.5);
        // After a leg phrase the room clause goes last: "As you go to the watch, stay close to
        // the dog bed as you pass through the lounge", not two "as you" clauses in a row.
        let shape = if with_leg {
            sp.pick("soft.shape.after_leg", &["{p} {s}"])
        } else {
            sp.pick("soft.shape", &["{s}, {p}", "{p} {s}", "{s}, {p}"])
        };
        let mut s = realise::fill(shape, &[("s", &s_text), ("p", &pref_text)]);
        if with_leg {
            self.check_leg(sp, leg);
            s = format!("{}, {s}", leg.text);
        }
        let line = format!("prefer {pref_m2r} within {s_m2r}");
        out.say(sp, sentence(&s), line.clone());
        (c, line)
    }

    #[allow(clippy::too_many_arguments)]
    fn finish(
        &self,
        sp: Speaker<'_>,
        out: Out,
        id: u32,
        difficulty: Difficulty,
        start: Cell,
        n_stages: usize,
        avoid_no: usize,
        objects_json: Vec<Value>,
        route: Vec<Cell>,
    ) -> GeneratedEpisode {
        let ix = &self.ix;
        let instruction = out.sentences.join(" ");
        let mut program = format!("// map: {}\n", self.map_key);
        for line in wrap(&format!("\"{instruction}\""), 96) {
            program.push_str(&format!("// {line}\n"));
        }
        for l in &out.lets {
            program.push_str(l);
            program.push('\n');
        }
        program.push_str("\nroute {\n");
        for l in &out.route {
            program.push_str(l);
            program.push('\n');
        }
        program.push_str("}\n");
        let (rooms_visited, room_transitions) = room_traversal(ix, &route);
        let length_cells: f64 = route.windows(2).map(|w| w[0].dist(w[1])).sum();
        let meta = EpisodeMeta {
            max_depth: out.refs.iter().map(|r| r.depth).max().unwrap_or(0),
            max_candidates: out.refs.iter().map(|r| r.candidates).max().unwrap_or(0),
            references: out.refs,
            destinations: n_stages,
            must_avoid: avoid_no,
            soft: out.soft_counts,
            rooms_visited,
            room_transitions,
            reference_route_length_m: round3(length_cells * ix.resolution()),
            room_descriptions: sp.room_full.clone(),
            determinacy: sp.reader.record.clone(),
            clauses: out.clauses,
        };
        let ordering = (1..=n_stages)
            .map(|k| format!("obj{k}"))
            .collect::<Vec<_>>()
            .join(" -> ");
        let mut instruction_json = json!({
            "id": id,
            "map_id": self.map_key,
            "template_instruction_id": format!("m2rc_{:06}", id),
            "object_count": n_stages,
            "objects": objects_json,
            "human_expert_trajectory": [],
            "start_pose": {"row": start.row, "col": start.col},
            "feasible": true,
            "name": format!("instruction_{id:06}"),
            "notes": "generated by m2rc suite build; no human demonstration",
            "created_by": "m2rc-suite",
            "hard_constraints": out.hard,
            "soft_constraints": out.soft,
            "ordering": ordering,
            "difficulty_level": difficulty.as_str(),
            "created_at": TIMESTAMP,
            "updated_at": TIMESTAMP,
            "instruction": instruction,
        });
        let mut generation = json!({
            "generator": "m2rc-suite",
            "version": env!("CARGO_PKG_VERSION"),
            "template": format!("m2rc-suite/{}", difficulty.as_str()),
        });
        if let (Some(g), Value::Object(m)) = (
            generation.as_object_mut(),
            serde_json::to_value(&meta).expect("meta serializes"),
        ) {
            g.extend(m);
        }
        instruction_json[GOLD_PROGRAM_KEY] = json!(program);
        instruction_json[GENERATION_KEY] = generation;
        GeneratedEpisode {
            id,
            difficulty,
            instruction: instruction_json,
            meta,
            program,
            reference_route: route,
        }
    }
}
