//! `m2rc serve`: a small HTTP JSON planning service for a robot stack (`docs/serve.md`).
//!
//! The map is loaded once and shared read-only by every request; each request compiles and plans
//! on a blocking thread, at most as many at once as the machine has cores, under the same wall and
//! work budget (`m2rc_benchmark::budget`) as a benchmark episode, so one request cannot starve the
//! others. Off loopback every request needs a bearer token, compared in constant time.

use crate::cmd::serve_route::{Model, RouteError, Shared, plan_request};
use crate::io::{read_to_string, unusable};
use anyhow::{Context, Result, anyhow};
use axum::Router;
use axum::body::Bytes;
use axum::extract::rejection::BytesRejection;
use axum::extract::{DefaultBodyLimit, Request, State};
use axum::http::{StatusCode, header};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use clap::Args;
use serde_json::json;
use sha2::{Digest, Sha256};
use std::io::Write;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;
use std::time::Duration;
use subtle::ConstantTimeEq;

/// The environment variable holding the bearer token.
pub const TOKEN_ENV: &str = "M2R_SERVE_TOKEN";

#[derive(Args)]
pub struct ServeArgs {
    /// The map every request plans on: a Map2Route map, a ProcTHOR house or `demo`.
    #[arg(long)]
    pub map: String,
    /// Address to listen on. Any address but loopback needs a token (`M2R_SERVE_TOKEN` or
    /// `--token-file`); port 0 picks a free port (the address is printed on standard output).
    #[arg(long, default_value = "127.0.0.1:8700")]
    pub listen: SocketAddr,
    /// A file whose first line is the bearer token requests must send (`Authorization: Bearer
    /// <token>`); the environment variable `M2R_SERVE_TOKEN` is used when absent.
    #[arg(long, value_name = "FILE")]
    pub token_file: Option<PathBuf>,
    /// Largest request body, in bytes; larger bodies are refused with 413.
    #[arg(long, default_value_t = 256 * 1024)]
    pub max_body_bytes: usize,
    /// Wall-time limit of one request's compiling and planning, in seconds; over it the request
    /// is refused with 503.
    #[arg(long, default_value_t = 10.0)]
    pub max_seconds: f64,
    /// The model `{"instruction": ...}` requests are lowered through, as in `m2rc run`: with
    /// `--llm-base-url` (or `M2R_LLM_BASE_URL`, or `--llm-cache-only`) the service takes
    /// instructions; without, it plans `.m2r` programs only.
    #[command(flatten)]
    pub llm: m2rc_llm::LlmArgs,
    #[command(flatten)]
    pub lower: m2rc_llm::LowerArgs,
}

pub fn run(args: ServeArgs) -> Result<ExitCode> {
    if !(args.max_seconds.is_finite() && args.max_seconds > 0.0) {
        return Err(unusable(anyhow!(
            "--max-seconds {} must be a positive number of seconds",
            args.max_seconds
        )));
    }
    let token = read_token(&args)?;
    if token.is_none() && !args.listen.ip().is_loopback() {
        return Err(unusable(anyhow!(
            "--listen {} is not a loopback address: a token is required (set {TOKEN_ENV} or pass \
             --token-file FILE); clients then send `Authorization: Bearer <token>`",
            args.listen
        )));
    }
    let model = model_for(&args)?;
    let loaded = crate::io::load_map_prepared(&args.map)?;
    let planning = loaded.planning()?;
    let doc = loaded.doc;
    let frame = m2rc_stdlib::map::frame::MapFrame::of(&doc.map, Some(&doc.extra))
        .map_err(|e| unusable(anyhow::Error::new(e).context(format!("map `{}`", args.map))))?;
    let workers = std::thread::available_parallelism().map_or(2, |n| n.get());
    let shared = Arc::new(Shared {
        map: doc.map,
        planning,
        frame,
        max_wall: Duration::from_secs_f64(args.max_seconds),
        slots: tokio::sync::Semaphore::new(workers),
        token: token.map(|t| Sha256::digest(t.as_bytes()).into()),
        model,
    });
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(workers)
        .enable_all()
        .build()
        .context("cannot start the service's runtime")?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind(args.listen)
            .await
            .map_err(|e| unusable(anyhow!("cannot listen on {}: {e}", args.listen)))?;
        let addr = listener.local_addr()?;
        // The first line of standard output is the address, for scripts and tests using port 0.
        let mut out = std::io::stdout();
        writeln!(out, "m2rc serve: listening on http://{addr}")?;
        out.flush()?;
        axum::serve(listener, router(shared, args.max_body_bytes))
            .await
            .context("the service stopped")
    })?;
    Ok(ExitCode::SUCCESS)
}

/// The model from the `--llm-*` flags, when they name one (built before the service's runtime:
/// the HTTP client blocks, and runs on the requests' blocking threads).
fn model_for(args: &ServeArgs) -> Result<Option<Model>> {
    use m2rc_llm::Backend;
    let llm = &args.llm;
    if !matches!(llm.backend, Backend::Http) {
        return Err(unusable(anyhow!(
            "--llm simulated and --llm gold answer from an episode's gold annotations; a service \
             has no episode: give an OpenAI-compatible server with --llm-base-url"
        )));
    }
    if llm.llm_batch_out.is_some() {
        return Err(unusable(anyhow!(
            "--llm-batch-out defers every reply to a batch API, so a request would never get \
             its route; serve from a server (--llm-base-url) or from the cache (--llm-cache-only)"
        )));
    }
    if llm.llm_base_url.is_none() && !llm.llm_cache_only {
        return Ok(None);
    }
    let client = llm
        .http_client()
        .map_err(|e| unusable(anyhow!(e)))?
        .context("no HTTP client")?;
    let (store, note) = llm
        .store(&m2rc_llm::config::default_run_cache())
        .map_err(|e| unusable(anyhow!(e)))?;
    if let Some(n) = note {
        eprintln!("{n}");
    }
    let key = llm.api_key().map_err(|e| unusable(anyhow!(e)))?;
    let budget = m2rc_benchmark::budget::EpisodeBudget::from_args(&args.lower.budget)
        .map_err(|e| unusable(anyhow!(e)))?;
    Ok(Some(Model {
        client,
        store,
        key,
        prompt: args.lower.prompt_options(),
        repair: args.lower.repair_options(),
        budget,
    }))
}

/// The token from `--token-file` or `M2R_SERVE_TOKEN`; an empty one is refused, never treated as
/// "no token".
fn read_token(args: &ServeArgs) -> Result<Option<String>> {
    let (token, from) = match &args.token_file {
        Some(p) => (
            read_to_string(p)?
                .lines()
                .next()
                .unwrap_or("")
                .trim()
                .to_string(),
            format!("--token-file {}", p.display()),
        ),
        None => match std::env::var(TOKEN_ENV) {
            Ok(t) => (t.trim().to_string(), TOKEN_ENV.to_string()),
            Err(_) => return Ok(None),
        },
    };
    if token.is_empty() {
        return Err(unusable(anyhow!("{from}: the token is empty")));
    }
    Ok(Some(token))
}

fn router(shared: Arc<Shared>, max_body: usize) -> Router {
    Router::new()
        .route("/route", post(route))
        .route("/map", get(map_summary))
        .fallback(not_found)
        .layer(middleware::from_fn_with_state(shared.clone(), authorise))
        .layer(DefaultBodyLimit::max(max_body))
        .with_state(shared)
}

/// A JSON error body: what is wrong and, when there is one, how to fix it.
pub fn error(status: StatusCode, message: &str, help: Option<&str>) -> Response {
    (
        status,
        axum::Json(json!({"status": "error", "message": message, "help": help})),
    )
        .into_response()
}

async fn authorise(State(s): State<Arc<Shared>>, req: Request, next: Next) -> Response {
    let Some(want) = &s.token else {
        return next.run(req).await;
    };
    let given = req
        .headers()
        .get(header::AUTHORIZATION)
        .and_then(|v| v.to_str().ok())
        .and_then(|v| v.strip_prefix("Bearer "))
        .unwrap_or("");
    // Digests of equal length, compared in constant time: neither the token nor its length leaks.
    let given: [u8; 32] = Sha256::digest(given.trim().as_bytes()).into();
    if bool::from(given.ct_eq(want)) {
        next.run(req).await
    } else {
        let mut r = error(
            StatusCode::UNAUTHORIZED,
            "missing or wrong bearer token",
            Some("send `Authorization: Bearer <token>` with the service's token"),
        );
        r.headers_mut().insert(
            header::WWW_AUTHENTICATE,
            header::HeaderValue::from_static("Bearer"),
        );
        r
    }
}

async fn not_found() -> Response {
    error(
        StatusCode::NOT_FOUND,
        "no such endpoint",
        Some("the endpoints are `POST /route` and `GET /map`"),
    )
}

async fn map_summary(State(s): State<Arc<Shared>>) -> Response {
    let mut info = crate::cmd::map::info_json(&s.map);
    info["frame"] = s.frame.to_json();
    axum::Json(info).into_response()
}

/// Gives a worker slot back when dropped (the planning thread ended, or its task never ran).
struct Release(Arc<Shared>);

impl Drop for Release {
    fn drop(&mut self) {
        self.0.slots.add_permits(1);
    }
}

async fn route(State(s): State<Arc<Shared>>, body: Result<Bytes, BytesRejection>) -> Response {
    let body = match body {
        Ok(b) => b,
        Err(rej) => {
            let status = rej.status();
            let help = (status == StatusCode::PAYLOAD_TOO_LARGE)
                .then_some("the request body is over the service's --max-body-bytes");
            return error(status, &rej.body_text(), help);
        }
    };
    let Ok(slot) = s.slots.acquire().await else {
        return error(
            StatusCode::SERVICE_UNAVAILABLE,
            "the service is stopping",
            None,
        );
    };
    // The slot goes back when the planning thread ends, not when the answer leaves: a request
    // answered "too slow" keeps its thread until its own budget stops it, and slow requests
    // must not add threads beyond one per core meanwhile.
    slot.forget();
    let release = Release(s.clone());
    let shared = s.clone();
    let limit = s.max_wall + Duration::from_secs(1);
    let work = tokio::task::spawn_blocking(move || {
        let _release = release;
        plan_request(&shared, &body)
    });
    match tokio::time::timeout(limit, work).await {
        Ok(Ok(Ok(body))) => (StatusCode::OK, axum::Json(body)).into_response(),
        Ok(Ok(Err(RouteError { status, body }))) => (status, axum::Json(body)).into_response(),
        Ok(Err(_)) => error(
            StatusCode::INTERNAL_SERVER_ERROR,
            "the request failed inside the planner",
            None,
        ),
        Err(_) => error(
            StatusCode::SERVICE_UNAVAILABLE,
            &format!(
                "the request took longer than the time limit of {:.1} s",
                s.max_wall.as_secs_f64()
            ),
            Some("simplify the program, or restart the service with a larger --max-seconds"),
        ),
    }
}
