//! Verifies and plans a RouteIR built from catalog ids: the compile path's last two steps
//! (`m2rc_benchmark::pipeline`), on the same planner and the episode's budget. No program means
//! no route-dependent places, so there is one plan and nothing to re-bind.

use m2rc_benchmark::budget::Meter;
use m2rc_benchmark::pipeline::{CompiledRoute, PipelineOptions};
use m2rc_compiler::diagnostic::{Code, Diagnostic};
use m2rc_compiler::ir::RouteIr;
use m2rc_compiler::verify::verify;
use m2rc_planner::context::MapContext;
use m2rc_planner::lower::lower_with;
use m2rc_planner::plan;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::query::MapQuery;
use std::sync::Arc;

/// Why a RouteIR did not give a route: found wrong by the verifier (`verify`), or planning
/// failed (`plan`, which a repair round does not retry by default), or the budget ran out.
#[derive(Debug)]
pub enum PlanError {
    Verify(Vec<Diagnostic>),
    Plan(Box<Diagnostic>),
}

fn spent(meter: &Option<Arc<Meter>>) -> Result<(), PlanError> {
    match meter {
        Some(m) => m.check().map_err(PlanError::Plan),
        None => Ok(()),
    }
}

/// Verifies `ir` and plans it on `map` with `ctx`.
pub fn plan_ir(
    ir: RouteIr,
    map: &SemanticMap,
    q: &MapQuery,
    ctx: &MapContext,
    opts: &PipelineOptions,
) -> Result<CompiledRoute, PlanError> {
    let diags: Vec<Diagnostic> = verify(&ir, q)
        .into_iter()
        .map(|p| p.into_diagnostic())
        .collect();
    if diags.iter().any(Diagnostic::is_error) {
        return Err(PlanError::Verify(diags));
    }
    let mut ir = ir;
    if let Some(t) = opts.transform {
        t(&mut ir);
    }
    spent(&opts.meter)?;
    let mut profile = opts.profile.clone();
    let own = profile.max_expansions;
    if let Some(m) = &opts.meter {
        profile.max_expansions = m.plan_budget(own);
    }
    let lowered = profile.max_expansions;
    let problem = lower_with(&ir, map, ctx, profile).map_err(|m| {
        PlanError::Plan(Box::new(Diagnostic::new(
            Code::MalformedIr,
            Default::default(),
            m,
        )))
    })?;
    let planned = plan(&problem, opts.planner);
    if let Some(m) = &opts.meter {
        let cut = lowered != own
            && planned
                .failure
                .as_ref()
                .is_some_and(|f| f.code() == Code::BudgetExceeded.id());
        m.spend(if cut { u64::MAX } else { planned.expansions })
            .map_err(PlanError::Plan)?;
    }
    if let Some(f) = &planned.failure
        && !planned.is_success()
    {
        let code = Code::from_id(f.code()).unwrap_or(Code::TargetUnreachable);
        return Err(PlanError::Plan(Box::new(Diagnostic::new(
            code,
            Default::default(),
            f.to_string(),
        ))));
    }
    if !planned.is_success() {
        return Err(PlanError::Plan(Box::new(Diagnostic::new(
            Code::TargetUnreachable,
            Default::default(),
            "planning failed",
        ))));
    }
    Ok(CompiledRoute {
        ir,
        route: planned,
        warnings: diags,
        rounds: 1,
        stable: true,
        ltl: None,
    })
}
