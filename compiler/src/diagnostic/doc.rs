//! Generates `docs/diagnostics.md` from the code registry, with each example's real output, so
//! the reference cannot drift from the checker. Codes from `E0500` on need a map (and `E07xx` the
//! planner, which this crate does not depend on), so their examples are compiled on the demo house
//! by the caller: the test that keeps the file current lives in the end-to-end tests
//! (`tests/tests/it/docs.rs`); regenerate with `UPDATE_DOCS=1 cargo test -p m2rc-tests --test it docs::`.

use super::{Code, Severity, render_text};
use m2rc_stdlib::vocab::Vocabulary;

const HEADER: &str = r#"# Diagnostics

<!-- Generated from `compiler/src/diagnostic/codes.rs` by `UPDATE_DOCS=1 cargo test -p m2rc-tests --test it docs::`; do not edit by hand. -->

Every problem m2rc reports has a stable code. Codes are never renumbered or reused.

| Range | Phase |
|---|---|
| `E00xx` | parsing |
| `E01xx` | names: bindings, built-ins, arguments |
| `E02xx` | types |
| `E03xx` | route structure and scopes |
| `E04xx` | categories and vocabulary |
| `E05xx` | grounding against a map |
| `E06xx` | verification |
| `E07xx` | planning |

Each diagnostic has a code, a severity (`error` or `warning`; a program with only warnings is
accepted), a message, a primary span, secondary labels, notes, an optional `help`, and zero or more
machine-applicable suggestions (the first is the preferred fix; several are alternatives, such as
each candidate of an ambiguous category).

## Success and `--fix`

On success `m2rc check` prints `ok: N bindings, M stages` on standard error (with the warnings, if
any); with errors it prints the diagnostics and `file: N error(s), M warning(s)`.

`m2rc check prog.m2r --fix` applies what the repair loop applies before it asks a model (the
same code): every error with exactly one suggestion whose edit overlaps no other, re-checking after
each pass (at most four). It rewrites the file atomically (`-o fixed.m2r` writes elsewhere, `-o -`
standard output; a program read from `-` goes to standard output), prints one line per fix
(`fixed [E0401]: `bedd` -> `bed` (unknown category `bedd`)`), then checks the result as above. A
diagnostic with several suggestions (each candidate of an ambiguous category) is left to the
writer: choosing one would invent meaning. Nothing to fix leaves the file untouched.

## JSON form

`m2rc check --format json` prints an array of objects:

```json
{
  "code": "E0202",
  "severity": "error",
  "title": "a set where a single value is expected",
  "message": "expected `Place`, found the set `Set<Object>`",
  "span": { "start": 11, "end": 23, "line": 1, "col": 12, "end_line": 1, "end_col": 24 },
  "labels": [ { "span": { "...": "as above" }, "message": "..." } ],
  "notes": [ "a set never stands for one of its elements: choose one explicitly" ],
  "help": "take the only element with `.only()` ...",
  "suggestion": { "span": { "start": 23, "end": 23, "...": "..." }, "replacement": ".only()" },
  "suggestions": [ { "span": { "...": "..." }, "replacement": ".only()" },
                   { "span": { "...": "..." }, "replacement": ".nearest()" } ]
}
```

* `start` / `end`: byte offsets into the file, half-open.
* `line` / `col` (and `end_line` / `end_col`): 1-based; columns count Unicode characters.
* `help`: text or `null`. `suggestion`: the preferred fix or `null`; apply it by replacing the
  bytes `span.start..span.end` with `replacement` (an empty span inserts, an empty replacement
  deletes). `suggestions`: all fixes, preferred first.

In the language server, positions are 0-based lines and UTF-16 columns (the LSP default); notes
and help are appended to the message, labels become related information, and the suggestions
travel in `data.suggestions` as `{range, newText}` for code actions.

## Codes
"#;

/// The whole Markdown file. `on_demo` compiles and plans a program on the built-in demo house
/// and returns its diagnostics (for the examples of codes that need a map).
pub fn diagnostics_markdown(on_demo: &dyn Fn(&str) -> Vec<super::Diagnostic>) -> String {
    let mut out = String::from(HEADER);
    let vocab = Vocabulary::benchmark();
    for info in Code::registry() {
        let sev = match info.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        out.push_str(&format!("\n### {}: {} ({sev})\n", info.id, info.title));
        if info.example.is_empty() {
            out.push_str("\nNo standalone example: this code needs ");
            out.push_str(match info.id {
                "E0404" => "a map (`m2rc check --map`): a category the benchmark knows but the map lacks.\n",
                "E0000" => "a parser error of a kind newer than this registry.\n",
                "E0804" => "a formula checked outside a program (`docs/ltl.md`); in a `.m2r` \
                            program an unbound name in a formula is E0101.\n",
                "E0810" => "a formula whose automaton outgrows its budget: a long conjunction of \
                            unordered `F` atoms (each doubles it), too large to print here.\n",
                "E0901" | "E0902" | "E0903" => "a JSON reply of the Schema grounding variant \
                            (`docs/ablations.md`, \"grounding\"), not a `.m2r` program.\n",
                "E0904" | "E0905" => "a JSON reply of the Direct ID or catalog-LTL grounding \
                            variants (`docs/ablations.md`, \"grounding\"), checked against \
                            the scene catalog.\n",
                _ => "input that is impractical to show here.\n",
            });
            continue;
        }
        out.push_str("\n```m2r\n");
        out.push_str(info.example);
        out.push_str("\n```\n");
        let diagnostics = if info.id < "E0500" {
            crate::check(info.example, &vocab).diagnostics
        } else {
            out.push_str("\nOn the demo house (`m2rc compile example.m2r --map demo`):\n");
            on_demo(info.example)
        };
        let shown: Vec<_> = diagnostics
            .into_iter()
            .filter(|d| d.code.id() == info.id)
            .collect();
        out.push_str("\n```text\n");
        out.push_str(&render_text(&shown, "example.m2r", info.example));
        out.push_str("```\n");
    }
    out
}
