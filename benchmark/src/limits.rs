//! Size limits on what users and models hand the compiler, documented in `docs/benchmark.md`
//! ("Limits"): past them an input is refused with a message instead of being compiled in
//! unbounded time and memory. Route files are limited in [`crate::route::MAX_ROUTE_POINTS`] and
//! [`crate::route_read::MAX_ROUTE_FILE_BYTES`]; a model's reply to the same program size in
//! `m2rc_llm::wire::MAX_REPLY_BYTES`; an episode's compiling and planning in [`crate::budget`].

use m2rc_grammar::ast::{Item, RouteItem};

/// The largest `.m2r` program accepted, in bytes (the longest gold program is under 3 KB).
pub const MAX_PROGRAM_BYTES: usize = 256 * 1024;
/// The most stages (`go` items, plus `for` items) a program's routes may write out.
pub const MAX_STAGES: usize = 200;

/// `Err(message)` when `source` is past a limit.
pub fn check_program_size(source: &str) -> Result<(), String> {
    if source.len() > MAX_PROGRAM_BYTES {
        return Err(format!(
            "the program is {} bytes, more than the limit of {MAX_PROGRAM_BYTES}",
            source.len()
        ));
    }
    let parsed = m2rc_grammar::parse(source);
    let stages: usize = parsed
        .program
        .items
        .iter()
        .map(|item| match item {
            Item::Route(r) => r
                .items
                .iter()
                .filter(|i| matches!(i, RouteItem::Stage(_) | RouteItem::For(_)))
                .count(),
            _ => 0,
        })
        .sum();
    if stages > MAX_STAGES {
        return Err(format!(
            "the program has {stages} stages, more than the limit of {MAX_STAGES}"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_model_reply_is_held_to_the_program_limit() {
        assert_eq!(m2rc_llm::wire::MAX_REPLY_BYTES, MAX_PROGRAM_BYTES);
    }

    #[test]
    fn programs_past_the_limits_are_refused() {
        assert!(check_program_size("route { go rooms(kitchen).only() }").is_ok());
        let many = format!(
            "route {{\n{}}}\n",
            "  go rooms(kitchen).only()\n".repeat(MAX_STAGES + 1)
        );
        let m = check_program_size(&many).unwrap_err();
        assert!(m.contains("201 stages"), "{m}");
        let big = "// x\n".repeat(MAX_PROGRAM_BYTES);
        assert!(check_program_size(&big).unwrap_err().contains("bytes"));
    }
}
