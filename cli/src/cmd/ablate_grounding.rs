//! `m2rc ablate grounding`: the ablation table's grounding rows. The benchmark crate cannot build
//! the variants (they live in `m2rc-baselines`, above it), so the rows are built here and run
//! through `m2rc_benchmark::ablate::run_variants`: every row on the same planner, every model row
//! on one reply cache (`<out>/grounding/llm-cache`), each one-shot (`-r0`, the reference's code)
//! and with `--repair-rounds` R (`-rR`, the reference's table).

use super::ablate::AblateArgs;
use anyhow::Result;
use m2rc_baselines::calls::ModelSetup;
use m2rc_baselines::grounding::directid::{CatalogIds, DIRECT_ID, ltl};
use m2rc_baselines::grounding::{schema, toolcall, variant_setup};
use m2rc_benchmark::ablate::{AblateOptions, named, run_variants};
use m2rc_benchmark::methods::{Method, grounding2route::Grounding2Route, method_by_name};
use m2rc_llm::Backend;
use std::sync::Arc;

pub const DESCRIPTION: &str = "the same compiler, RouteIR and planner, grounded from different \
representations: CaG (the model writes `.m2r`), Schema (a JSON intent graph over operators \
generated from the built-in table, compiled to `.m2r`), Direct ID (catalog ids picked from a compact \
catalog of the map, built into RouteIR), catalog-LTL (the same ids under a restricted LTL skeleton, \
through the Direct ID path; not the `gold+ltl`/`llm+ltl` rows, which plan `.m2r` with the LTL \
backend), ToolCall (the same built-ins as \
function calls over opaque handles, one-shot; not run with the simulated model); `-r0` rows are one-shot (the reference's \
code), `-rR` rows repair up to R rounds (the reference's table). With `--llm gold` each row is its \
representation's ceiling ([GOLD replies]; CaG's is the gold program, the `oracle` method)";

/// A repairable JSON variant: its row prefix and how to build it with R repair rounds.
type Variant = (&'static str, fn(Arc<ModelSetup>, usize) -> Box<dyn Method>);

/// The JSON grounding variants after CaG, in the paper's table order.
const VARIANTS: &[Variant] = &[
    ("schema", |s, k| Box::new(schema::Schema::new(s, k))),
    ("directid", |s, k| {
        Box::new(CatalogIds::new(s, k, &DIRECT_ID))
    }),
    ("catalog-ltl", |s, k| {
        Box::new(CatalogIds::new(s, k, &ltl::FORM))
    }),
];

/// The rows, in table order.
pub fn variants(a: &AblateArgs) -> Result<Vec<Box<dyn Method>>, String> {
    let cache = a.out.join("grounding").join("llm-cache");
    let r = a.lower.repair_rounds;
    let rounds: Vec<usize> = if r == 0 { vec![0] } else { vec![0, r] };
    let gold = a.llm.backend == Backend::Gold;
    let mut out: Vec<Box<dyn Method>> = Vec::new();
    if gold {
        let oracle = method_by_name("oracle").ok_or("no oracle method")?;
        out.push(named("cag-gold", oracle));
    }
    for &k in &rounds {
        if !gold {
            let mut lower = a.lower.clone();
            lower.repair_rounds = k;
            let (m, _) = Grounding2Route::from_args(&a.llm, &lower, &cache)?;
            out.push(named(format!("cag-r{k}"), Box::new(m)));
        }
        for (prefix, make) in VARIANTS {
            let (setup, _) = variant_setup(&a.llm, &a.baseline, &cache)?;
            out.push(named(format!("{prefix}-r{k}"), make(Arc::new(setup), k)));
        }
        if gold {
            // Gold replies are the same in every round: one row says the ceiling.
            break;
        }
    }
    // ToolCall runs one-shot whatever R, as the reference's code does (no simulated form).
    if !matches!(a.llm.backend, Backend::Simulated(_)) {
        let (setup, _) = variant_setup(&a.llm, &a.baseline, &cache)?;
        out.push(named("toolcall-r0", toolcall::make(Arc::new(setup))));
    }
    Ok(out)
}

pub fn run(a: &AblateArgs, opts: &AblateOptions) -> Result<String> {
    let rows = variants(a).map_err(anyhow::Error::msg)?;
    let (_, _, markdown) = run_variants("grounding", DESCRIPTION, &rows, opts)?;
    Ok(markdown)
}
