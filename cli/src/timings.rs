//! Where a process spends its time, for tuning start-up (`docs/maps.md`, "Prepared-map cache"):
//! with `M2RC_TIMINGS=1` each phase's end is printed to standard error as
//! `timing: <phase> <ms since start> ms (+<ms since the previous mark>)`. Off, a mark is one
//! environment lookup, done once.

use std::sync::{Mutex, OnceLock};
use std::time::Instant;

/// The environment variable that turns the marks on.
pub const ENV: &str = "M2RC_TIMINGS";

/// The process's first mark and the latest, when timings are on.
fn clock() -> Option<&'static Mutex<(Instant, Instant)>> {
    static CLOCK: OnceLock<Option<Mutex<(Instant, Instant)>>> = OnceLock::new();
    CLOCK
        .get_or_init(|| {
            let on = std::env::var_os(ENV).is_some_and(|v| !v.is_empty() && v != "0");
            on.then(|| Mutex::new((Instant::now(), Instant::now())))
        })
        .as_ref()
}

/// Starts the clock (call first thing in `main`).
pub fn start() {
    let _ = clock();
}

/// Marks the end of `phase`.
pub fn mark(phase: &str) {
    if let Some(c) = clock() {
        let mut c = c.lock().unwrap_or_else(|p| p.into_inner());
        let now = Instant::now();
        let ms = |d: std::time::Duration| d.as_secs_f64() * 1e3;
        eprintln!(
            "timing: {phase} {:.1} ms (+{:.1})",
            ms(now - c.0),
            ms(now - c.1)
        );
        c.1 = now;
    }
}
