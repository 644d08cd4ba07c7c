//! The methods an ablation compares: the episode's gold program, compiled by the same pipeline,
//! with one thing changed each — the planner, the cost profile, or the frozen RouteIR's scopes.

use crate::episode::Episode;
use crate::methods::{Method, MethodError, Prediction, PreparedMap, start_cell};
use crate::pipeline::{PipelineOptions, compile_and_plan_with};
use m2rc_compiler::ir::{ConstraintKind, RouteIr, StageScope};
use m2rc_planner::{CostProfile, PlannerKind};

/// The gold program planned with `planner` and `profile`, its RouteIR changed by `transform`.
pub struct GoldVariant {
    pub name: String,
    pub planner: PlannerKind,
    pub profile: CostProfile,
    pub transform: Option<fn(&mut RouteIr)>,
    /// Warnings recorded in every prediction (e.g. what the LTL planner drops).
    pub note: Option<&'static str>,
}

impl GoldVariant {
    pub fn new(name: &str, planner: PlannerKind, profile: CostProfile) -> Self {
        GoldVariant {
            name: name.into(),
            planner,
            profile,
            transform: None,
            note: None,
        }
    }
}

impl Method for GoldVariant {
    fn name(&self) -> &str {
        &self.name
    }

    fn predict(&self, map: &PreparedMap, episode: &Episode) -> Result<Prediction, MethodError> {
        let gold = episode.m2rc_gold_program.as_deref().ok_or_else(|| {
            MethodError("the episode has no gold program (`m2rc_gold_program`)".into())
        })?;
        let opts = PipelineOptions {
            planner: self.planner,
            profile: self.profile.clone(),
            start: Some(start_cell(&map.map, episode)?),
            transform: self.transform,
            ..PipelineOptions::default()
        };
        match compile_and_plan_with(gold, &map.map, map.planning()?, &opts) {
            Ok(c) => Ok(Prediction {
                trajectory: c.route.trajectory,
                program: Some(gold.to_string()),
                notes: self.note.map(String::from).into_iter().collect(),
                ..Prediction::default()
            }),
            Err(diags) => {
                let first = diags.iter().find(|d| d.is_error()).or(diags.first());
                Err(MethodError(match first {
                    Some(d) => format!("{} {}", d.code, d.message),
                    None => "the gold program does not compile".into(),
                }))
            }
        }
    }
}

/// Global-T: every stage scope removed (each constraint active in every stage).
pub fn no_stage_scope(ir: &mut RouteIr) {
    for c in &mut ir.constraints {
        c.stage_scope = StageScope::Global;
    }
}

/// Global-S: every spatial scope removed, the default room scopes included.
pub fn no_spatial_scope(ir: &mut RouteIr) {
    for c in &mut ir.constraints {
        c.spatial_scope = None;
    }
}

/// Global-TS: both.
pub fn no_scope(ir: &mut RouteIr) {
    no_stage_scope(ir);
    no_spatial_scope(ir);
}

/// Hard-only: every soft preference dropped except path shapes, whose waypoints the
/// `hard_only` profile merges into one must-pass region per shape (as the reference does).
pub fn no_soft(ir: &mut RouteIr) {
    ir.constraints.retain(|c| {
        matches!(
            c.kind,
            ConstraintKind::Avoid { .. } | ConstraintKind::PathShape { .. }
        )
    });
    for (i, c) in ir.constraints.iter_mut().enumerate() {
        c.id = format!("c{i}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use m2rc_compiler::ir::{Constraint, Place, PlaceKind, SourceSpan};
    use m2rc_stdlib::grid::Cell;

    fn place() -> Place {
        Place {
            kind: PlaceKind::Room {
                id: 1,
                category: "kitchen".into(),
            },
            label: "kitchen 1".into(),
            cells: vec![Cell::new(1, 1)].into(),
        }
    }

    fn constraint(kind: ConstraintKind) -> Constraint {
        Constraint {
            id: "c0".into(),
            kind,
            stage_scope: StageScope::Stages(vec![1]),
            spatial_scope: Some(place()),
            span: SourceSpan::default(),
        }
    }

    fn ir() -> RouteIr {
        let json = serde_json::json!({
            "version": 1, "map_id": "m", "grid_size": 4, "resolution_m": 0.05,
            "start": [0, 0], "stages": [], "constraints": []
        });
        let mut ir: RouteIr = serde_json::from_value(json).unwrap();
        ir.constraints = vec![
            constraint(ConstraintKind::Avoid { place: place() }),
            constraint(ConstraintKind::Near { reference: place() }),
            constraint(ConstraintKind::Clearance { distance_m: 0.5 }),
        ];
        ir
    }

    #[test]
    fn scope_ablations_change_only_their_scope() {
        let mut a = ir();
        no_stage_scope(&mut a);
        assert!(
            a.constraints
                .iter()
                .all(|c| c.stage_scope == StageScope::Global)
        );
        assert!(a.constraints.iter().all(|c| c.spatial_scope.is_some()));
        let mut b = ir();
        no_spatial_scope(&mut b);
        assert!(b.constraints.iter().all(|c| c.spatial_scope.is_none()));
        assert!(
            b.constraints
                .iter()
                .all(|c| c.stage_scope != StageScope::Global)
        );
        let mut c = ir();
        no_soft(&mut c);
        assert_eq!(c.constraints.len(), 1);
        assert!(matches!(
            c.constraints[0].kind,
            ConstraintKind::Avoid { .. }
        ));
    }
}
