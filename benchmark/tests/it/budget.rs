//! The per-episode budget (issue 28, item 3): whatever program a model writes, its compiling and
//! planning stop at the episode's work and memory budget with a reason, and every later compile
//! of the same episode is refused at once.

use m2rc_benchmark::budget::{EpisodeBudget, Meter};
use m2rc_benchmark::pipeline::{PipelineOptions, compile_and_plan};
use m2rc_compiler::diagnostic::Code;
use m2rc_planner::PlannerKind;
use std::sync::Arc;

const LTL: &str = "let bed = objects(bed).nearest(start)\nlet kitchen = rooms(kitchen).only()\nroute ltl \"F(kitchen & F bed)\"\n";
const PLAIN: &str = "route {\n  go objects(bed).nearest(start)\n}\n";

fn opts(meter: &Arc<Meter>) -> PipelineOptions {
    PipelineOptions {
        planner: PlannerKind::Ltl,
        meter: Some(meter.clone()),
        ..PipelineOptions::default()
    }
}

#[test]
fn a_product_graph_past_the_memory_estimate_is_refused_before_it_is_searched() {
    let map = m2rc_stdlib::demo::demo_map().unwrap();
    let roomy = Arc::new(Meter::new(EpisodeBudget::default()));
    assert!(compile_and_plan(LTL, &map, &opts(&roomy)).is_ok());
    let tight = Arc::new(Meter::new(EpisodeBudget {
        max_product_mb: 1,
        ..EpisodeBudget::default()
    }));
    let diags = compile_and_plan(LTL, &map, &opts(&tight)).unwrap_err();
    let d = diags.iter().find(|d| d.is_error()).unwrap();
    assert_eq!(d.code, Code::BudgetExceeded);
    assert!(d.message.contains("78961 cells"), "{}", d.message);
    assert!(
        d.message.contains("memory budget of 1 MiB"),
        "{}",
        d.message
    );
    // The episode is over: its next program is refused before it is even checked.
    let again = compile_and_plan(PLAIN, &map, &opts(&tight)).unwrap_err();
    assert_eq!(again[0].code, Code::BudgetExceeded);
    assert_eq!(tight.exceeded().as_deref(), Some(d.message.as_str()));
}

#[test]
fn plans_share_the_episode_work_budget() {
    let map = m2rc_stdlib::demo::demo_map().unwrap();
    let seq = |meter: &Arc<Meter>| PipelineOptions {
        meter: Some(meter.clone()),
        ..PipelineOptions::default()
    };
    let roomy = Arc::new(Meter::new(EpisodeBudget::default()));
    let ok = compile_and_plan(PLAIN, &map, &seq(&roomy)).unwrap();
    assert_eq!(roomy.expansions(), ok.route.expansions);
    assert!(ok.route.expansions > 10);
    let tight = Arc::new(Meter::new(EpisodeBudget {
        max_expansions: 10,
        ..EpisodeBudget::default()
    }));
    let diags = compile_and_plan(PLAIN, &map, &seq(&tight)).unwrap_err();
    assert_eq!(diags[0].code, Code::BudgetExceeded);
    assert!(
        diags[0]
            .message
            .contains("work budget of 10 planner expansions"),
        "{}",
        diags[0].message
    );
}

#[test]
fn a_program_past_the_size_limits_ends_the_episode() {
    let map = m2rc_stdlib::demo::demo_map().unwrap();
    let many = format!(
        "route {{\n{}}}\n",
        "  go objects(bed).nearest(start)\n".repeat(201)
    );
    let meter = Arc::new(Meter::new(EpisodeBudget::default()));
    let opts = PipelineOptions {
        meter: Some(meter.clone()),
        ..PipelineOptions::default()
    };
    let diags = compile_and_plan(&many, &map, &opts).unwrap_err();
    assert_eq!(diags[0].code, Code::BudgetExceeded);
    assert!(
        diags[0].message.contains("201 stages"),
        "{}",
        diags[0].message
    );
    assert_eq!(meter.expansions(), 0, "nothing was planned");
    assert!(
        meter
            .exceeded()
            .unwrap()
            .contains("more than the limit of 200")
    );
}
