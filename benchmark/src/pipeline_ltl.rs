//! The compile path of `route ltl "..."` programs: ground the desugared program (one stage per
//! atom, `compiler::ltl::program`), build each atom's mask as the planner's goal mask of that
//! place and each `avoid` as its cells, conjoin `G !a` for the avoids, and plan the cheapest
//! accepting route on the product of the grid and the formula's automaton. Every `--planner`
//! plans an LTL program this way (a warning says so when another planner was asked for).

use crate::pipeline::{CompiledRoute, PipelineOptions};
use m2rc_compiler::check::CheckResult;
use m2rc_compiler::diagnostic::{Code, Diagnostic};
use m2rc_compiler::eval::{GroundOptions, ground_checked};
use m2rc_compiler::ir::ConstraintKind;
use m2rc_compiler::ltl::lower::{base_name, sanitize};
use m2rc_compiler::ltl::program::{Desugared, with_avoids};
use m2rc_compiler::ltl::{AtomDef, AtomSource, Dfa, LtlRoute, Skeleton};
use m2rc_planner::context::MapContext;
use m2rc_planner::lower::lower_with;
use m2rc_planner::product::ProductFailure;
use m2rc_planner::product_lower::plan_places;
use m2rc_planner::route::path_length_m;
use m2rc_planner::{CostProfile, PlanStatus, PlannedRoute, PlannedSegment, PlannerKind, goal};
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::query::MapQuery;

pub(crate) fn compile_ltl(
    checked: &CheckResult,
    d: Desugared,
    source: &str,
    map: &SemanticMap,
    ctx: &MapContext,
    opts: &PipelineOptions,
    mut warnings: Vec<Diagnostic>,
) -> Result<CompiledRoute, Vec<Diagnostic>> {
    let span = d.span;
    let fail = |mut diags: Vec<Diagnostic>, warnings: &[Diagnostic]| {
        diags.extend(warnings.iter().cloned());
        m2rc_compiler::diagnostic::sort(&mut diags);
        diags
    };
    if !matches!(opts.planner, PlannerKind::Ltl) {
        warnings.push(
            Diagnostic::new(
                Code::LtlDropped,
                span,
                "an LTL route is always planned by the LTL planner",
            )
            .help("pass `--planner ltl` to say so"),
        );
    }
    let program = CheckResult {
        program: d.program.clone(),
        ..checked.clone()
    };
    let q = MapQuery::new(map);
    let g = ground_checked(
        &program,
        source,
        &q,
        &GroundOptions {
            start: opts.start,
            route: None,
        },
    );
    let diags: Vec<Diagnostic> = g
        .problems
        .into_iter()
        .map(|p| p.into_diagnostic())
        .collect();
    let Some(ir) = g.ir.filter(|_| !diags.iter().any(Diagnostic::is_error)) else {
        return Err(fail(diags, &warnings));
    };
    warnings.extend(diags);
    let problem = lower_with(&ir, map, ctx, CostProfile::shortest())
        .map_err(|m| fail(vec![Diagnostic::new(Code::MalformedIr, span, m)], &warnings))?;
    let n = map.n();
    let trav = problem.traversable.data();
    let radius = goal::goal_radius_cells(problem.profile.goal_radius_m, problem.resolution);
    let mut atoms: Vec<AtomDef> = Vec::new();
    let mut masks: Vec<Vec<bool>> = Vec::new();
    for (k, name) in d.atoms.iter().enumerate() {
        let (Some(stage), Some(seg)) = (ir.stages.get(k), problem.segments.get(k)) else {
            return Err(fail(
                vec![Diagnostic::new(
                    Code::MalformedIr,
                    span,
                    "an atom was not grounded",
                )],
                &warnings,
            ));
        };
        let Some(target) = seg.stages.last() else {
            continue;
        };
        masks.push(goal::goal_mask(&target.target, trav, n, radius));
        atoms.push(AtomDef {
            name: name.clone(),
            meaning: stage.target.label.clone(),
            source: AtomSource::Binding { name: name.clone() },
        });
    }
    let mut avoid_names = Vec::new();
    for (ci, c) in ir.constraints.iter().enumerate() {
        if let ConstraintKind::Avoid { place } = &c.kind {
            let mut name = sanitize(&format!("avoid_{}", base_name(place)));
            while atoms.iter().any(|a| a.name == name) {
                name.push('_');
            }
            let mut cells = vec![false; n * n];
            for cell in place.cells.cells() {
                if c.spatial_scope
                    .as_ref()
                    .is_none_or(|s| s.cells.contains(*cell))
                    && (cell.row as usize) < n
                    && (cell.col as usize) < n
                {
                    cells[cell.row as usize * n + cell.col as usize] = true;
                }
            }
            masks.push(cells);
            atoms.push(AtomDef {
                name: name.clone(),
                meaning: format!("avoided: {}", place.label),
                source: AtomSource::Avoid { constraint: ci },
            });
            avoid_names.push(name);
        }
    }
    if let Some(m) = &opts.meter {
        m.check().map_err(|d| fail(vec![*d], &warnings))?;
    }
    let formula = with_avoids(&d.formula, &avoid_names);
    let names: Vec<String> = atoms.iter().map(|a| a.name.clone()).collect();
    let dfa = Dfa::build(&formula, &names, true).map_err(|e| {
        fail(
            vec![Diagnostic::new(Code::LtlTooLarge, span, e.to_string())],
            &warnings,
        )
    })?;
    let mut budget = opts
        .profile
        .max_expansions
        .saturating_mul(names.len().max(1) as u64);
    if let Some(m) = &opts.meter {
        m.check_product((n * n) as u64, dfa.states() as u64)
            .map_err(|d| {
                let mut d = *d;
                d.span = span;
                fail(vec![d], &warnings)
            })?;
        budget = m.plan_budget(budget);
    }
    let planned = plan_places(&problem.traversable, &masks, &dfa, problem.start, budget);
    let spent = match &planned {
        Ok(r) => r.expansions,
        Err(
            ProductFailure::Budget { expansions } | ProductFailure::NoAcceptingRoute { expansions },
        ) => *expansions,
        Err(_) => 0,
    };
    if let Some(m) = &opts.meter
        && let (Err(d), Err(_)) = (m.spend(spent), &planned)
    {
        let mut d = *d;
        d.span = span;
        return Err(fail(vec![d], &warnings));
    }
    let route = match planned {
        Ok(r) => r,
        Err(e) => {
            let (message, help) = match e {
                ProductFailure::StartRejected => (
                    "the start cell already violates the formula (e.g. it lies in an avoided place)"
                        .to_string(),
                    "start elsewhere (`--start row,col`), or loosen the formula",
                ),
                ProductFailure::Budget { expansions } => (
                    format!("the search stopped after {expansions} expansions without an accepting route"),
                    "simplify the formula, or raise the expansion budget",
                ),
                ProductFailure::StartBlocked => (
                    "the start cell is not traversable".to_string(),
                    "start on a free cell (`--start row,col`)",
                ),
                ProductFailure::NoAcceptingRoute { .. } | ProductFailure::Invalid(_) => (
                    "no route on this map satisfies the formula".to_string(),
                    "a required place may be unreachable, or walled off by the avoided ones",
                ),
            };
            return Err(fail(
                vec![Diagnostic::new(Code::LtlNoRoute, span, message).help(help)],
                &warnings,
            ));
        }
    };
    let length_m = path_length_m(&route.trajectory, problem.resolution);
    let planned = PlannedRoute {
        planner: m2rc_planner::product_lower::NAME.into(),
        profile: "shortest".into(),
        status: PlanStatus::Success,
        length_m,
        cost: route.cost,
        expansions: route.expansions,
        segments: vec![PlannedSegment {
            index: 0,
            status: PlanStatus::Success,
            path: route.trajectory.clone(),
            length_m,
            cost: route.cost,
            expansions: route.expansions,
            stages: Vec::new(),
        }],
        trajectory: route.trajectory,
        failure: None,
    };
    let ltl = LtlRoute {
        atoms,
        skeleton: Skeleton::default(),
        formula,
        dropped: d.dropped,
    };
    Ok(CompiledRoute {
        ir,
        route: planned,
        warnings,
        rounds: 1,
        stable: true,
        ltl: Some(ltl),
    })
}
