//! The compile path of `route ltl "..."` programs: ground the desugared program (one stage per
//! atom, `compiler::ltl::program`), build each atom's mask as the planner's goal mask of that
//! place and each `avoid` as its cells, conjoin `G !a` for the avoids, and plan the cheapest
//! accepting route on the product of the grid and the formula's automaton. Every `--planner`
//! plans an LTL program this way. The route's stages are the places the formula asks it to enter
//! (its positive atoms), in the order the route first enters them, each cut there.

use crate::pipeline::{CompiledRoute, PipelineOptions};
use m2rc_compiler::check::CheckResult;
use m2rc_compiler::diagnostic::{Code, Diagnostic};
use m2rc_compiler::eval::{GroundOptions, ground_checked};
use m2rc_compiler::ir::{ConstraintKind, RouteIr};
use m2rc_compiler::ltl::lower::{base_name, sanitize};
use m2rc_compiler::ltl::program::{Desugared, visit_atoms, with_avoids};
use m2rc_compiler::ltl::{AtomDef, AtomSource, Dfa, LtlRoute, Skeleton};
use m2rc_planner::context::MapContext;
use m2rc_planner::lower::lower_with;
use m2rc_planner::product::ProductFailure;
use m2rc_planner::product_lower::plan_places;
use m2rc_planner::route::path_length_m;
use m2rc_planner::{CostProfile, PlanStatus, PlannedRoute, PlannedSegment, goal};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::query::MapQuery;

/// E0809 for each constraint of `ir` the LTL planner leaves out of the formula (preferences,
/// path shapes, clearance: everything but avoids), when a program is planned with
/// `--planner ltl`: the route it gets does not try to satisfy them.
pub(crate) fn ignored_by_ltl(ir: &RouteIr) -> Vec<Diagnostic> {
    ir.constraints
        .iter()
        .filter(|c| !matches!(c.kind, ConstraintKind::Avoid { .. }))
        .map(|c| {
            Diagnostic::new(
                Code::LtlDropped,
                c.span.span(),
                "the LTL planner ignores this preference: it is not part of the route's formula",
            )
            .help("plan with another `--planner` to use it")
        })
        .collect()
}

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
            ..Default::default()
        },
    );
    let diags: Vec<Diagnostic> = g
        .problems
        .into_iter()
        .map(|p| p.into_diagnostic())
        .collect();
    let Some(mut ir) = g.ir.filter(|_| !diags.iter().any(Diagnostic::is_error)) else {
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
    // Per atom of the formula with a mask: its stage of the desugared IR and its mask.
    let mut grounded: Vec<(usize, usize)> = Vec::new();
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
        grounded.push((k, masks.len()));
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
                    "start elsewhere (`--start-cell row,col` or `--start x,y` in metres), or loosen the formula",
                ),
                ProductFailure::Budget { expansions } => (
                    format!("the search stopped after {expansions} expansions without an accepting route"),
                    "simplify the formula, or raise the expansion budget",
                ),
                ProductFailure::StartBlocked => (
                    "the start cell is not traversable".to_string(),
                    "start on a free cell (`--start-cell row,col` or `--start x,y` in metres)",
                ),
                e @ ProductFailure::TooLarge { .. } => (
                    e.to_string(),
                    "use fewer places in the formula, or plan on a smaller map",
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
    let visits = visit_atoms(&d.formula);
    let mut entries: Vec<(usize, usize)> = grounded
        .iter()
        .filter(|(k, _)| visits.contains(&d.atoms[*k]))
        .filter_map(|&(k, m)| {
            let mask = &masks[m];
            let first = route.trajectory.iter().position(|c| {
                (c.row as usize) < n && mask.get(c.row as usize * n + c.col as usize) == Some(&true)
            })?;
            Some((first, k))
        })
        .collect();
    entries.sort();
    let segments = stage_segments(&route.trajectory, &entries, problem.resolution);
    ir.stages = entries
        .iter()
        .filter_map(|&(_, k)| {
            let mut st = ir.stages.get(k)?.clone();
            st.name = d.atoms[k].clone();
            Some(st)
        })
        .collect();
    let planned = PlannedRoute {
        planner: m2rc_planner::product_lower::NAME.into(),
        profile: "shortest".into(),
        status: PlanStatus::Success,
        length_m,
        cost: route.cost,
        expansions: route.expansions,
        segments,
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

/// The route cut at each entry (trajectory index of a place's first cell, ascending): one segment
/// per entry, from the previous cut to it; what follows the last entry (the formula may need the
/// route to go on) stays in the last segment. A route without entries is one segment.
fn stage_segments(
    traj: &[Cell],
    entries: &[(usize, usize)],
    resolution: f64,
) -> Vec<PlannedSegment> {
    if traj.is_empty() {
        return Vec::new();
    }
    let mut cuts: Vec<usize> = entries.iter().map(|&(i, _)| i).collect();
    match cuts.last_mut() {
        Some(last) => *last = traj.len() - 1,
        None => cuts.push(traj.len() - 1),
    }
    let mut from = 0usize;
    cuts.iter()
        .enumerate()
        .map(|(index, &to)| {
            let path = traj[from..=to].to_vec();
            from = to;
            let length_m = path_length_m(&path, resolution);
            PlannedSegment {
                index,
                status: PlanStatus::Success,
                cost: length_m / resolution,
                length_m,
                path,
                expansions: 0,
                stages: Vec::new(),
            }
        })
        .collect()
}
