//! Rendering a loop-shaped preference (circle, patrol, follow_wall) and the canonical-path
//! annotation every path-shape preference carries.

use super::super::annotate::{TIMESTAMP, footprints_json, soft_base, stage_scope};
use super::super::generate::Scene;
use super::super::plan::{ShapeKind, ShapePlan, SoftPlan};
use super::super::realise::{self, Speaker, sentence};
use super::Out;
use serde_json::{Value, json};

/// How the canonical trajectory of a loop was made, in its annotation.
const LOOP_NOTES: &str = "generated: the language's shape (circle: radius half the larger extent + 0.45 m about the centroid; patrol / follow_wall: the stdlib's wall loop waypoints joined by shortest paths, a patrol ending at the doorway the reference route leaves by), from the stage start";

impl Scene<'_> {
    /// A circle, patrol or wall loop: (annotation, program line); its sentence goes to `out`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn loop_soft(
        &self,
        sp: &mut Speaker<'_>,
        out: &mut Out,
        soft: &SoftPlan,
        shape: &ShapePlan,
        var: &str,
        dest: super::StageDest<'_>,
        leg: &super::LegPhrase,
        (no, order): (usize, u32),
        label: &str,
        role: &str,
    ) -> (Value, String) {
        let ix = &self.ix;
        let mut c = soft_base(
            no,
            "path_shape_preference",
            stage_scope(order),
            label,
            ix,
            &shape.area,
        );
        let dir = if shape.clockwise {
            "clockwise"
        } else {
            "counterclockwise"
        };
        let (text, line, kind) = match shape.kind {
            ShapeKind::Circle => {
                let (o, desc) = shape.object.clone().expect("a circle has an object");
                // Named by its category alone, the object is the one of the room the sentence
                // is scoped to, which it then says ("in the living room, circle the dining
                // table"): without it "the dining table" is any of the house's.
                let mut scope_text = None;
                let (t, m2r) = match &desc {
                    Some(d) => {
                        let (t, read) = d.said(ix, sp);
                        out.stat(ix, role, d, &t);
                        sp.reader.note("path-shape subject", &t, vec![o], read);
                        (t, d.m2r())
                    }
                    None => {
                        let (room, said) = self.scope(sp, out, soft, var, dest);
                        scope_text = Some(said);
                        let cat = &ix.object(o).category;
                        let t = format!("the {}", sp.noun(cat));
                        out.stat_implied(ix, role, cat, &t);
                        let read = sp.reader.bare(ix, cat);
                        sp.reader
                            .note("path-shape subject", &t, vec![o], read.clone());
                        sp.reader.named_object(&read);
                        sp.reader.scope = None;
                        (t, format!("objects({cat}).in({room}).only()"))
                    }
                };
                c["object_ids"] = json!([o]);
                c["reference_region"] =
                    json!({"mode": "object", "object_id": o, "cells": footprints_json(ix, &[o])});
                let s = realise::circle(sp, &t, shape.clockwise);
                let s = if let Some(scope) = scope_text {
                    format!("{scope}, {s}")
                } else if sp.chance(0.5) {
                    self.check_leg(sp, leg);
                    format!("{}, {s}", leg.text)
                } else {
                    s
                };
                (
                    sentence(&s),
                    format!(
                        "prefer circle({m2r}, {dir}) within area_near({m2r}, within: {:.2}m)",
                        shape.within_m
                    ),
                    "circle",
                )
            }
            ShapeKind::Patrol => (
                sentence(&realise::patrol(sp, shape.clockwise)),
                format!("prefer patrol(start.room(), {dir}) within start.room()"),
                "patrol",
            ),
            ShapeKind::FollowWall => (
                sentence(&realise::follow_wall(sp, shape.clockwise)),
                format!("prefer follow_wall(start.room(), {dir}) within start.room()"),
                "follow_wall",
            ),
            ShapeKind::Through => unreachable!("a `through` is rendered as an object preference"),
        };
        // A patrol or wall loop names the room's walls, and a patrol the doorway it ends at.
        for (word, what, count) in [
            ("wall", "wall", ix.count_any(&["wall"])),
            ("door", "doorway", ix.count_any(&["doorway", "doorframe"])),
        ] {
            if kind != "circle" && text.contains(word) && count > 0 {
                out.stat_structure(role, what, count, &text);
            }
        }
        annotate(&mut c, shape, kind, dir, LOOP_NOTES);
        out.say(sp, text, line.clone());
        (c, line)
    }
}

/// The canonical reference trajectory of a path-shape preference, as the annotation tool stores
/// it: the evaluator scores against `shape_reference_trajectory`.
pub(super) fn annotate(c: &mut Value, shape: &ShapePlan, kind: &str, dir: &str, notes: &str) {
    let ring: Vec<Value> = shape
        .reference
        .iter()
        .map(|c| json!([c.row, c.col]))
        .collect();
    c["reference_waypoint_count"] = json!(ring.len());
    c["reference_trajectory"] = json!(ring.clone());
    c["path_shape_annotation"] = json!({
        "version": 1, "annotation_type": "canonical_path_shape_reference",
        "shape_spec": {"type": kind, "direction": dir, "ordered_control_points": ring.clone()},
        "shape_reference_trajectory": ring, "shape_reference_source": format!("m2rc_canonical_{kind}_v3"),
        "annotator_id": "m2rc-suite",
        "notes": notes,
        "created_at": TIMESTAMP, "updated_at": TIMESTAMP, "history": [],
    });
}
