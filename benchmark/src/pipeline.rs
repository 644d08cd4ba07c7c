//! The whole compile path for one program on one map: check, ground, verify, plan, and re-bind the
//! route-dependent places against the planned route until the binding is stable.
//!
//! Route-dependent places (`room_before_entering(k)`, `doorway_leaving(r)`, ...) are first bound to
//! the shortest traversable path, the route is planned, the program is grounded again against that
//! route, and, when the grounding changed (a different room, hence different masks or costs), the
//! route is planned again, for at most [`PipelineOptions::max_rounds`] plans. It lives here, above
//! both the compiler and the planner, because it needs both; `m2rc compile` and the benchmark's
//! oracle method call it.

use crate::plan_failure::FailedPlan;
use m2rc_compiler::check::check;
use m2rc_compiler::diagnostic::{Code, Diagnostic, Severity};
use m2rc_compiler::eval::{Chosen, GroundOptions, ground_checked};
use m2rc_compiler::ir::{Constraint, RouteIr, Stage};
use m2rc_compiler::verify::verify;
use m2rc_grammar::ast::Span;
use m2rc_planner::choice::reached_members;
use m2rc_planner::context::MapContext;
use m2rc_planner::lower::{lower_with, span_of};
use m2rc_planner::{CostProfile, PlannedRoute, PlannerKind, plan};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::query::MapQuery;
use m2rc_stdlib::vocab::Vocabulary;

#[derive(Clone, Debug)]
pub struct PipelineOptions {
    pub planner: PlannerKind,
    pub profile: CostProfile,
    /// Start cell; the map's own start when `None`.
    pub start: Option<Cell>,
    /// Most plans made while re-binding route-dependent places.
    pub max_rounds: usize,
    /// Applied to the verified RouteIR before it is planned (the ablations' scope removal,
    /// `ablate::scopes`); `None` plans it as grounded.
    pub transform: Option<fn(&mut RouteIr)>,
    /// The episode's budget (`crate::budget`), shared by all its compiles; `None`: only the
    /// planners' own per-plan limits apply.
    pub meter: Option<std::sync::Arc<crate::budget::Meter>>,
}

impl Default for PipelineOptions {
    fn default() -> Self {
        PipelineOptions {
            planner: PlannerKind::Sequential,
            profile: CostProfile::default(),
            start: None,
            max_rounds: 4,
            transform: None,
            meter: None,
        }
    }
}

/// A compiled program: the final RouteIR, the route planned for it, and the warnings.
#[derive(Clone, Debug)]
pub struct CompiledRoute {
    pub ir: RouteIr,
    pub route: PlannedRoute,
    /// Warnings of every phase (errors abort compilation).
    pub warnings: Vec<Diagnostic>,
    /// Plans made (1 unless the program has route-dependent places).
    pub rounds: usize,
    /// Whether grounding against the final route reproduced the IR the route was planned from.
    pub stable: bool,
    /// The formula of a `route ltl "..."` program (its RouteIR then holds one stage per place the
    /// formula asks the route to enter, in the order the route first enters them).
    pub ltl: Option<m2rc_compiler::ltl::LtlRoute>,
}

/// Why a program did not compile: every diagnostic, and, when planning failed, the failed plan
/// (for its picture: `m2rc compile --png` draws it).
#[derive(Clone, Debug)]
pub struct CompileFailure {
    pub diagnostics: Vec<Diagnostic>,
    pub plan: Option<Box<FailedPlan>>,
}

impl From<Vec<Diagnostic>> for CompileFailure {
    fn from(diagnostics: Vec<Diagnostic>) -> Self {
        CompileFailure {
            diagnostics,
            plan: None,
        }
    }
}

/// Compiles `source` on `map` into a planned route, or every diagnostic that prevents it.
///
/// Builds the map's planning context when the program gets as far as planning; callers that
/// plan many programs on one map (the benchmark runner, the language server) should build a
/// [`MapContext`] once and call [`compile_and_plan_with`].
pub fn compile_and_plan(
    source: &str,
    map: &SemanticMap,
    opts: &PipelineOptions,
) -> Result<CompiledRoute, Vec<Diagnostic>> {
    compile(source, map, None, opts).map_err(|f| f.diagnostics)
}

/// [`compile_and_plan`], keeping the failed plan when planning is what failed.
pub fn compile_and_plan_explained(
    source: &str,
    map: &SemanticMap,
    opts: &PipelineOptions,
) -> Result<CompiledRoute, CompileFailure> {
    compile(source, map, None, opts)
}

/// [`compile_and_plan_explained`] with a planning context built beforehand (one seeded with the
/// prepared-map cache's distance field, or shared by a service's requests).
pub fn compile_and_plan_explained_with(
    source: &str,
    map: &SemanticMap,
    ctx: &MapContext,
    opts: &PipelineOptions,
) -> Result<CompiledRoute, CompileFailure> {
    compile(source, map, Some(ctx), opts)
}

/// [`compile_and_plan`] with a planning context built once for `map` and shared across calls
/// (and threads): the distance fields a plan needs are computed once per map, not per program.
pub fn compile_and_plan_with(
    source: &str,
    map: &SemanticMap,
    ctx: &MapContext,
    opts: &PipelineOptions,
) -> Result<CompiledRoute, Vec<Diagnostic>> {
    compile(source, map, Some(ctx), opts).map_err(|f| f.diagnostics)
}

fn compile(
    source: &str,
    map: &SemanticMap,
    shared: Option<&MapContext>,
    opts: &PipelineOptions,
) -> Result<CompiledRoute, CompileFailure> {
    if let Some(m) = &opts.meter {
        m.check().map_err(|d| vec![*d])?;
        // A model's program is held to the limits a user's is (`m2rc check`, `compile`).
        crate::limits::check_program_size(source).map_err(|why| vec![*m.refuse(why)])?;
    }
    let vocab = Vocabulary::from_map(map);
    let checked = check(source, &vocab);
    let mut warnings: Vec<Diagnostic> = checked
        .diagnostics
        .iter()
        .filter(|d| !d.is_error())
        .cloned()
        .collect();
    if checked.has_errors() {
        return Err(checked.diagnostics.into());
    }
    if let Some(d) = m2rc_compiler::ltl::program::desugar(&checked.program, source) {
        let owned;
        let ctx = match shared {
            Some(c) => c,
            None => {
                owned = MapContext::new(map).map_err(|m| {
                    with_warnings(
                        vec![Diagnostic::new(Code::MalformedIr, Span::default(), m)],
                        &warnings,
                    )
                })?;
                &owned
            }
        };
        return crate::pipeline_ltl::compile_ltl(&checked, d, source, map, ctx, opts, warnings)
            .map_err(CompileFailure::from);
    }
    let q = MapQuery::new(map);
    let mut route: Option<Vec<Cell>> = None;
    let mut chosen: Vec<Chosen> = Vec::new();
    let mut last: Option<(RouteIr, PlannedRoute)> = None;
    let mut rounds = 0;
    let mut owned: Option<Result<MapContext, String>> = None;
    loop {
        let g = ground_checked(
            &checked,
            source,
            &q,
            &GroundOptions {
                start: opts.start,
                route: route.take(),
                chosen: std::mem::take(&mut chosen),
            },
        );
        let mut diags: Vec<Diagnostic> = g
            .problems
            .into_iter()
            .map(|p| p.into_diagnostic())
            .collect();
        let mut ir = match g.ir {
            Some(ir) if !diags.iter().any(Diagnostic::is_error) => ir,
            _ => return Err(with_warnings(diags, &warnings).into()),
        };
        diags.extend(verify(&ir, &q).into_iter().map(|p| p.into_diagnostic()));
        if diags.iter().any(Diagnostic::is_error) {
            return Err(with_warnings(diags, &warnings).into());
        }
        merge(&mut warnings, diags);
        if let Some(t) = opts.transform {
            t(&mut ir);
        }
        if matches!(opts.planner, PlannerKind::Ltl) {
            merge(&mut warnings, crate::pipeline_ltl::ignored_by_ltl(&ir));
        }
        if let Some((prev_ir, prev_route)) = last.take() {
            if same_grounding(&prev_ir, &ir) {
                return Ok(CompiledRoute {
                    ir,
                    route: prev_route,
                    warnings,
                    rounds,
                    stable: true,
                    ltl: None,
                });
            }
            if rounds >= opts.max_rounds.max(1) {
                return Ok(CompiledRoute {
                    ir: prev_ir,
                    route: prev_route,
                    warnings,
                    rounds,
                    stable: false,
                    ltl: None,
                });
            }
        }
        // The episode's budget: checked before every plan, which gets what is left of it.
        let mut profile = opts.profile.clone();
        let own_budget = profile.max_expansions;
        if let Some(m) = &opts.meter {
            m.check().map_err(|d| with_warnings(vec![*d], &warnings))?;
            profile.max_expansions = m.plan_budget(profile.max_expansions);
        }
        // One planning context per map: the re-plan rounds share its distance fields.
        let problem = match shared {
            Some(c) => lower_with(&ir, map, c, profile),
            None => match owned.get_or_insert_with(|| MapContext::new(map)) {
                Ok(c) => lower_with(&ir, map, c, profile),
                Err(m) => Err(m.clone()),
            },
        };
        let problem = problem.map_err(|m| {
            with_warnings(
                vec![Diagnostic::new(Code::MalformedIr, Span::default(), m)],
                &warnings,
            )
        })?;
        let planned = plan(&problem, opts.planner);
        rounds += 1;
        // A search stopped at a budget the meter lowered has spent the episode's budget.
        let cut_short = problem.profile.max_expansions != own_budget
            && planned
                .failure
                .as_ref()
                .is_some_and(|f| f.code() == Code::BudgetExceeded.id());
        let spent = opts.meter.as_ref().map(|m| {
            m.spend(if cut_short {
                u64::MAX
            } else {
                planned.expansions
            })
        });
        if !planned.is_success() {
            // A search cut short by the episode's budget is reported as that, with no picture
            // of a failed plan (nothing in the map cut the way).
            if let Some(Err(d)) = spent {
                return Err(with_warnings(vec![*d], &warnings).into());
            }
            let failed = planned.failure.as_ref().map(|f| {
                Box::new(FailedPlan::new(
                    &ir,
                    f,
                    planned.trajectory.clone(),
                    &q,
                    opts.profile.goal_radius_m,
                ))
            });
            let diag = plan_failure(&ir, &planned, failed.as_deref());
            return Err(CompileFailure {
                diagnostics: with_warnings(vec![diag], &warnings),
                plan: failed,
            });
        }
        if ir.route_bindings.is_empty() {
            return Ok(CompiledRoute {
                ir,
                route: planned,
                warnings,
                rounds,
                stable: true,
                ltl: None,
            });
        }
        route = Some(planned.trajectory.clone());
        chosen = reached_members(&problem, &planned);
        last = Some((ir, planned));
    }
}

/// Equal stages and constraints (the binding records differ only in what they were read from).
fn same_grounding(a: &RouteIr, b: &RouteIr) -> bool {
    let key = |s: &[Stage], c: &[Constraint]| (s.to_vec(), c.to_vec());
    key(&a.stages, &a.constraints) == key(&b.stages, &b.constraints)
}

fn merge(into: &mut Vec<Diagnostic>, more: Vec<Diagnostic>) {
    for d in more {
        if !into.contains(&d) {
            into.push(d);
        }
    }
}

fn with_warnings(mut diags: Vec<Diagnostic>, warnings: &[Diagnostic]) -> Vec<Diagnostic> {
    merge(&mut diags, warnings.to_vec());
    m2rc_compiler::diagnostic::sort(&mut diags);
    diags
}

/// A planning failure as a diagnostic pointing at the stage (and the avoid regions) responsible,
/// with why the target is cut off when the map says.
fn plan_failure(ir: &RouteIr, planned: &PlannedRoute, failed: Option<&FailedPlan>) -> Diagnostic {
    let Some(f) = &planned.failure else {
        return Diagnostic::new(Code::TargetUnreachable, Span::default(), "planning failed");
    };
    let code = Code::from_id(f.code()).unwrap_or(Code::TargetUnreachable);
    let span = f
        .target()
        .and_then(|o| span_of(ir, o))
        .map_or(Span::default(), |s| s.span());
    let mut d = Diagnostic::new(code, span, f.to_string());
    d.severity = Severity::Error;
    if let Some(why) = failed.and_then(|p| p.why.as_ref()) {
        d = d.note(why.clone());
    }
    for o in f.forbids() {
        if let Some(s) = span_of(ir, *o) {
            d = d.label(s.span(), "this avoid region blocks the way");
        }
    }
    d.note(format!(
        "planner `{}`; reference failure code {}",
        planned.planner,
        f.reference_code()
    ))
}

/// Index into the trajectory where each stage (segment) ends.
pub fn stage_ends(route: &PlannedRoute) -> Vec<usize> {
    let mut out = Vec::new();
    let mut at = 0usize;
    for s in &route.segments {
        at += s.path.len().saturating_sub(1);
        out.push(at);
    }
    out
}

impl CompiledRoute {
    /// The route's hard constraints as LTLf (`m2rc compile --emit ltl|dfa|hoa|dot`).
    pub fn ltl_route(&self) -> m2rc_compiler::ltl::LtlRoute {
        match &self.ltl {
            Some(l) => l.clone(),
            None => m2rc_compiler::ltl::lower(&self.ir),
        }
    }
}
