//! `m2rc ablate`: the paper's ablations as commands. Each ablation is a list of method variants
//! run over a suite with the benchmark runner (parallel, resumable, sharded: each variant has its
//! own run directory, `<out>/<ablation>/<variant>/`) and reported as one table in the `bench
//! report` layout (`<out>/<ablation>/table.{md,csv,json}`). `docs/ablations.md` says what each
//! changes and how to reproduce it.

pub mod variants;

use crate::methods::Method;
use crate::report::{LoadOptions, MethodRun, load_runs_with, table};
use crate::runner::{RunError, RunOptions, Shard, run, write_atomic};
use m2rc_planner::{CostProfile, PlannerKind};
use std::path::{Path, PathBuf};
use variants::GoldVariant;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ablation {
    /// The same grounding planned through RouteIR and through the LTL backend.
    LtlVsRouteir,
    /// Repair rounds R = 0..3 of the LLM method.
    RepairRounds,
    /// Global-T, Global-S, Global-TS and Hard-only on the frozen RouteIR.
    Scopes,
    /// Shortest feasible, sequential and global planners on the gold programs.
    OraclePlanner,
}

impl Ablation {
    pub const ALL: [Ablation; 4] = [
        Ablation::LtlVsRouteir,
        Ablation::RepairRounds,
        Ablation::Scopes,
        Ablation::OraclePlanner,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Ablation::LtlVsRouteir => "ltl-vs-routeir",
            Ablation::RepairRounds => "repair-rounds",
            Ablation::Scopes => "scopes",
            Ablation::OraclePlanner => "oracle-planner",
        }
    }

    pub fn from_name(s: &str) -> Option<Ablation> {
        Ablation::ALL.into_iter().find(|a| a.name() == s)
    }

    /// One line on what the ablation changes.
    pub fn description(self) -> &'static str {
        match self {
            Ablation::LtlVsRouteir => {
                "the gold program's grounding planned through RouteIR (sequential planner, full cost model; \
                 global planner on the hard constraints only) and through the LTL backend (RouteIR -> LTLf -> \
                 minimal DFA -> product-graph A*; soft preferences dropped)"
            }
            Ablation::RepairRounds => "the LLM method with R = 0, 1, 2, 3 repair rounds",
            Ablation::Scopes => {
                "scopes removed from the frozen RouteIR of the gold program (method notes §4.9): Global-T \
                 (every stage scope), Global-S (every spatial scope, default room scopes included), Global-TS \
                 (both), Hard-only (soft preferences, soft field and clearance dropped; path-shape waypoints \
                 merged)"
            }
            Ablation::OraclePlanner => {
                "the gold program planned by the shortest-feasible, sequential and global planners (the \
                 paper's Table IV)"
            }
        }
    }

    /// The variants compared, in table order. `repair-rounds` needs `model`.
    pub fn variants(self, model: Option<&ModelSpec>) -> Result<Vec<Box<dyn Method>>, String> {
        let gold = |name: &str, planner, profile| -> Box<dyn Method> {
            Box::new(GoldVariant::new(name, planner, profile))
        };
        let scoped =
            |name: &str, t: fn(&mut m2rc_compiler::ir::RouteIr), profile| -> Box<dyn Method> {
                let mut v = GoldVariant::new(name, PlannerKind::Sequential, profile);
                v.transform = Some(t);
                Box::new(v) as Box<dyn Method>
            };
        Ok(match self {
            Ablation::LtlVsRouteir => vec![
                gold(
                    "gold+routeir",
                    PlannerKind::Sequential,
                    CostProfile::reference(),
                ),
                gold(
                    "gold+routeir-global-hard",
                    PlannerKind::Global,
                    CostProfile::shortest(),
                ),
                {
                    let mut v =
                        GoldVariant::new("gold+ltl", PlannerKind::Ltl, CostProfile::reference());
                    v.note = Some("LTL planner: soft preferences and path shapes dropped");
                    Box::new(v) as Box<dyn Method>
                },
            ]
            .into_iter()
            .chain(match model {
                // The paper's CaG + RouteIR and CaG + LTL rows: the model's programs, with
                // R repair rounds, planned both ways.
                Some(spec) => vec![
                    Box::new(Variant {
                        name: "llm+routeir".into(),
                        inner: (spec.make)(spec.max_rounds, PlannerKind::Sequential)?,
                    }) as Box<dyn Method>,
                    Box::new(Variant {
                        name: "llm+ltl".into(),
                        inner: (spec.make)(spec.max_rounds, PlannerKind::Ltl)?,
                    }),
                ],
                None => vec![],
            })
            .collect(),
            Ablation::RepairRounds => {
                let Some(spec) = model else {
                    return Err(repair_rounds_missing());
                };
                let mut out: Vec<Box<dyn Method>> = Vec::new();
                for r in 0..=spec.max_rounds {
                    out.push(Box::new(Variant {
                        name: format!("repair-r{r}"),
                        inner: (spec.make)(r, PlannerKind::Sequential)?,
                    }));
                }
                out
            }
            Ablation::Scopes => vec![
                gold("full", PlannerKind::Sequential, CostProfile::reference()),
                scoped(
                    "global-t",
                    variants::no_stage_scope,
                    CostProfile::reference(),
                ),
                scoped(
                    "global-s",
                    variants::no_spatial_scope,
                    CostProfile::reference(),
                ),
                scoped("global-ts", variants::no_scope, CostProfile::reference()),
                scoped("hard-only", variants::no_soft, CostProfile::hard_only()),
            ],
            Ablation::OraclePlanner => vec![
                gold("shortest", PlannerKind::Shortest, CostProfile::shortest()),
                gold(
                    "sequential",
                    PlannerKind::Sequential,
                    CostProfile::reference(),
                ),
                gold("global", PlannerKind::Global, CostProfile::reference()),
            ],
        })
    }
}

/// Why `repair-rounds` cannot run without a model.
pub fn repair_rounds_missing() -> String {
    "`ablate repair-rounds` runs the LLM method and needs a model: an OpenAI-compatible server \
     (`--llm-base-url` or M2R_LLM_BASE_URL) or the labelled offline stand-in (`--llm \
     simulated:<fault rate>:<seed>`); the other ablations run without one"
        .into()
}

/// Makes the LLM method with `R` repair rounds and the given planner; the CLI builds it from its
/// model flags (the benchmark crate does no model I/O of its own).
pub type MethodMaker = dyn Fn(usize, PlannerKind) -> Result<Box<dyn Method>, String> + Send + Sync;

/// The model side of `repair-rounds` (R runs from 0 to `max_rounds`) and of the LLM rows of
/// `ltl-vs-routeir` (R = `max_rounds`).
pub struct ModelSpec {
    pub max_rounds: usize,
    pub make: Box<MethodMaker>,
}

/// A method under its ablation name (`repair-r2`), so that each variant has its own run
/// directory and row; its configuration says which variant it is.
struct Variant {
    name: String,
    inner: Box<dyn Method>,
}

impl Method for Variant {
    fn name(&self) -> &str {
        &self.name
    }

    fn predict(
        &self,
        map: &crate::methods::PreparedMap,
        episode: &crate::episode::Episode,
    ) -> Result<crate::methods::Prediction, crate::methods::MethodError> {
        self.inner.predict(map, episode)
    }

    fn config(&self) -> serde_json::Value {
        let mut c = self.inner.config();
        if let Some(o) = c.as_object_mut() {
            o.insert("variant".into(), self.name.clone().into());
        }
        c
    }
}

pub struct AblateOptions {
    pub suite: PathBuf,
    pub out: PathBuf,
    pub shard: Option<Shard>,
    pub split: String,
    pub progress: bool,
    /// The model for `repair-rounds`; without one that ablation is not run.
    pub model: Option<ModelSpec>,
}

/// One finished ablation: its table and where it was written.
#[derive(Clone, Debug)]
pub struct AblationResult {
    pub ablation: Ablation,
    pub table: table::Table,
    pub dir: PathBuf,
    pub markdown: String,
}

/// Runs every variant of `ab` (resuming finished records) and writes its table.
pub fn run_ablation(ab: Ablation, opts: &AblateOptions) -> Result<AblationResult, RunError> {
    let variants = ab
        .variants(opts.model.as_ref())
        .map_err(RunError::Invalid)?;
    let (table, dir, markdown) = run_variants(ab.name(), ab.description(), &variants, opts)?;
    Ok(AblationResult {
        ablation: ab,
        table,
        dir,
        markdown,
    })
}

/// A method under another name (an ablation row), so that it has its own run directory and
/// row; its configuration says which variant it is.
pub fn named(name: impl Into<String>, inner: Box<dyn Method>) -> Box<dyn Method> {
    Box::new(Variant {
        name: name.into(),
        inner,
    })
}

/// Runs `variants` as the ablation `name` (`<out>/<name>/<variant>/`, resuming finished records)
/// and writes its table; an ablation whose methods the benchmark crate cannot build (the
/// grounding variants live above it) is run this way by the CLI.
pub fn run_variants(
    name: &str,
    description: &str,
    variants: &[Box<dyn Method>],
    opts: &AblateOptions,
) -> Result<(table::Table, PathBuf, String), RunError> {
    let dir = opts.out.join(name);
    let mut runs: Vec<MethodRun> = Vec::new();
    for v in variants {
        let vdir = dir.join(v.name());
        run(
            v.as_ref(),
            &RunOptions {
                suite: opts.suite.clone(),
                out: vdir.clone(),
                shard: opts.shard,
                split: opts.split.clone(),
                progress: opts.progress,
            },
        )?;
        // A shard of an ablation holds only its share of the episodes.
        runs.extend(load_runs_with(
            std::slice::from_ref(&vdir),
            LoadOptions {
                allow_incomplete: opts.shard.is_some(),
                allow_invalid_routes: false,
            },
        )?);
    }
    let t = table::table(&runs);
    let markdown = section(name, description, &t, opts);
    write(&dir.join("table.md"), &markdown)?;
    write(&dir.join("table.csv"), &table::csv(&t))?;
    write(&dir.join("table.json"), &(table::json(&t) + "\n"))?;
    Ok((t, dir, markdown))
}

fn write(path: &Path, text: &str) -> Result<(), RunError> {
    write_atomic(path, text.as_bytes()).map_err(|e| RunError::Io {
        path: path.display().to_string(),
        source: e,
    })
}

fn section(name: &str, description: &str, t: &table::Table, opts: &AblateOptions) -> String {
    let mut out = format!("## Ablation `{name}`\n\n{description}.\n\n");
    out.push_str(&format!(
        "Suite `{}`, split `{}`{}.\n\n",
        opts.suite.display(),
        opts.split,
        opts.shard
            .map(|s| format!(", shard {s} only"))
            .unwrap_or_default()
    ));
    out.push_str(&table::markdown(t));
    out
}

/// Runs every ablation that this build can run; writes `<out>/ablations.md` with all tables and,
/// for an ablation that cannot run, the reason.
pub fn run_all(opts: &AblateOptions) -> Result<Vec<AblationResult>, RunError> {
    let mut results = Vec::new();
    let mut report = String::from("# Ablations\n\n");
    for ab in Ablation::ALL {
        match ab.variants(opts.model.as_ref()) {
            Err(why) => {
                report.push_str(&format!(
                    "## Ablation `{}`\n\nNot run: {why}.\n\n",
                    ab.name()
                ));
            }
            Ok(_) => {
                let r = run_ablation(ab, opts)?;
                report.push_str(&r.markdown);
                report.push('\n');
                results.push(r);
            }
        }
    }
    write(&opts.out.join("ablations.md"), &report)?;
    Ok(results)
}
