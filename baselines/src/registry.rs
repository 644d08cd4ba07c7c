//! The baselines the CLI can build: `m2rc bench run --method <name>` looks the name up here and
//! builds the method from the model flags (`--llm*`, `--embed-model`, `--embeddings`). Adding a
//! baseline is one line in [`BASELINES`].

use crate::calls::ModelSetup;
use crate::calls::embed::EmbedMode;
use clap::{Args, ValueEnum};
use m2rc_benchmark::methods::Method;
use m2rc_llm::{Backend, LlmArgs};
use std::path::Path;
use std::sync::Arc;

/// A baseline: its command-line name and how to build it over a model setup.
pub struct Baseline {
    pub name: &'static str,
    pub make: fn(Arc<ModelSetup>) -> Box<dyn Method>,
}

impl Baseline {
    pub const fn new(name: &'static str, make: fn(Arc<ModelSetup>) -> Box<dyn Method>) -> Self {
        Baseline { name, make }
    }
}

/// Every baseline, in Table I's order.
pub const BASELINES: &[Baseline] = &[
    Baseline::new(crate::lang2ltl::NAME, crate::lang2ltl::make),
    Baseline::new(crate::sayplan::method::NAME, crate::sayplan::method::make),
    Baseline::new(crate::osgllm::NAME, crate::osgllm::method::make),
    Baseline::new(crate::lang2ltl2::NAME, crate::lang2ltl2::make),
    Baseline::new(crate::limp::NAME, crate::limp::make),
    Baseline::new(crate::ltlcodegen::NAME, crate::ltlcodegen::method::make),
    Baseline::new(crate::iln::method::NAME, crate::iln::method::make),
];

/// The ablation table's grounding variants (issue 31): built like baselines, but not rows of
/// Table I, so `bench table1` does not run them.
pub const GROUNDING_VARIANTS: &[Baseline] = &[
    Baseline::new(
        crate::grounding::schema::NAME,
        crate::grounding::schema::make,
    ),
    Baseline::new(
        crate::grounding::directid::NAME,
        crate::grounding::directid::make,
    ),
    Baseline::new(
        crate::grounding::directid::ltl::NAME,
        crate::grounding::directid::ltl::make,
    ),
    Baseline::new(
        crate::grounding::toolcall::NAME,
        crate::grounding::toolcall::make,
    ),
];

/// The methods that ground by text similarity, so their runs say where embeddings came from.
const EMBEDDING_USERS: &[&str] = &[crate::lang2ltl::NAME, crate::lang2ltl2::NAME];

/// Whether `name` asks for embeddings (the others' labels leave them out: saying "lexical
/// embeddings" on a method that never embeds would suggest a handicap it does not have).
pub fn uses_embeddings(name: &str) -> bool {
    EMBEDDING_USERS.contains(&name)
}

fn every_method() -> impl Iterator<Item = &'static Baseline> {
    BASELINES.iter().chain(GROUNDING_VARIANTS)
}

/// The names of [`BASELINES`].
pub fn baseline_names() -> Vec<&'static str> {
    BASELINES.iter().map(|b| b.name).collect()
}

pub fn is_baseline(name: &str) -> bool {
    every_method().any(|b| b.name == name)
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EmbeddingsFlag {
    /// `POST {base}/embeddings` on the --llm-base-url server, with --embed-model.
    Server,
    /// A deterministic hashed character-trigram encoder (offline; not a neural model; labelled).
    Lexical,
}

/// The flags only baselines read.
#[derive(Args, Clone, Debug)]
pub struct BaselineArgs {
    /// Embedding model for the baselines that ground by text similarity (Lang2LTL, Lang2LTL-2).
    #[arg(long, env = "M2R_EMBED_MODEL", default_value = "default")]
    pub embed_model: String,
    /// Where those embeddings come from (default: `server`, or `lexical` with `--llm gold`).
    #[arg(long, value_enum)]
    pub embeddings: Option<EmbeddingsFlag>,
}

/// A built baseline and the setup it shares with the command (which prints the store's counts
/// and finishes the batch file after the run).
pub struct Built {
    pub method: Box<dyn Method>,
    pub setup: Arc<ModelSetup>,
    /// A line about imported batch replies, for the user.
    pub note: Option<String>,
}

/// The model setup from the flags; the cache defaults to `default_cache`.
pub fn model_setup(
    llm: &LlmArgs,
    args: &BaselineArgs,
    default_cache: &Path,
) -> Result<(ModelSetup, Option<String>), String> {
    if let Backend::Simulated(_) = llm.backend {
        return Err(
            "--llm simulated injects faults into a .m2r program and has no meaning for a \
             baseline; use --llm gold (each call answered from the episode's annotations) or a \
             server"
                .into(),
        );
    }
    let (store, note) = llm.store(default_cache)?;
    let gold = llm.backend == Backend::Gold;
    let embeddings = match args.embeddings {
        Some(EmbeddingsFlag::Lexical) => EmbedMode::Lexical,
        None if gold => EmbedMode::Lexical,
        Some(EmbeddingsFlag::Server) | None => EmbedMode::Server {
            model: args.embed_model.clone(),
        },
    };
    let offline = llm.llm_cache_only || llm.llm_batch_out.is_some();
    let client = |model: &str| -> Result<Option<m2rc_llm::HttpClient>, String> {
        let mut cfg = llm.config()?;
        cfg.model = model.to_string();
        if cfg.base_url.is_empty() && offline {
            cfg.base_url = "http://offline.invalid/v1".into();
        }
        m2rc_llm::HttpClient::new(cfg).map(Some)
    };
    let http = if gold { None } else { client(&llm.llm_model)? };
    let embed_http = match &embeddings {
        EmbedMode::Server { model } if gold && llm.llm_base_url.is_none() && !offline => {
            return Err(format!(
                "--llm gold with server embeddings ({model}) needs --llm-base-url; pass \
                 --embeddings lexical to run offline"
            ));
        }
        EmbedMode::Server { model } => client(model)?,
        EmbedMode::Lexical => None,
    };
    Ok((
        ModelSetup {
            backend: llm.backend.clone(),
            store,
            http,
            embed_http,
            model: llm.llm_model.clone(),
            base_url: llm.llm_base_url.clone(),
            temperature: llm.llm_temperature,
            max_tokens: (!gold).then_some(llm.llm_max_tokens),
            embeddings,
        },
        note,
    ))
}

/// Builds baseline `name`, or `Ok(None)` when no baseline has that name.
pub fn build(
    name: &str,
    llm: &LlmArgs,
    args: &BaselineArgs,
    default_cache: &Path,
) -> Result<Option<Built>, String> {
    let Some(b) = every_method().find(|b| b.name == name) else {
        return Ok(None);
    };
    let (setup, note) = if crate::grounding::is_variant(name) {
        crate::grounding::variant_setup(llm, args, default_cache)?
    } else {
        model_setup(llm, args, default_cache)?
    };
    let setup = Arc::new(setup);
    Ok(Some(Built {
        method: (b.make)(setup.clone()),
        setup,
        note,
    }))
}
