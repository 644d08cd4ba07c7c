//! Generated documentation must match its sources: `docs/language.md` is the hand-written intro
//! (`docs/src/language-intro.md`), the built-in table from `stdlib::builtins`, and the real
//! instruction programs of `tests/ui/real/`. Run with `UPDATE_DOCS=1` to rewrite it.
//!
//! Every `m2r` block of `docs/` is a program a reader may copy, so each says what it is for and is
//! held to it: `// map: <map>` first compiles and plans on that map, `// scene: ...` (written for
//! a reference scene this repository does not have) is checked only, and a block fenced
//! ` ```m2r fragment ` is a part of a program that must at least parse. `docs/diagnostics.md` is
//! left out: its examples are wrong on purpose, and the compiler's own test checks them.

use m2rc_benchmark::pipeline::{PipelineOptions, compile_and_plan};
use m2rc_compiler::diagnostic::render_text;
use m2rc_stdlib::vocab::Vocabulary;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

fn language_reference() -> String {
    let root = root();
    let mut out = std::fs::read_to_string(root.join("docs/src/language-intro.md")).unwrap();
    out.push_str("\n## Built-in functions, constants and words\n\n");
    out.push_str(
        "Generated from `stdlib/src/builtins/table.rs`. A method `Set<T>.m(...)` is called as \
         `set.m(...)`; `T` is the element type of the receiver. Parameters with `= value` may be \
         left out; any parameter may be passed by name (`by: travel`).\n\n",
    );
    out.push_str(&m2rc_stdlib::builtins::reference_markdown());
    out.push_str("\n## The real instructions, clause by clause\n\n");
    out.push_str(
        "Each instruction of the Map2Route development set (scenes 108, 111 and 114) and each short \
         clause from the reference prompts, with its program. The scenes are not in this \
         repository, so each program begins with a `// scene:` line: CI parses, resolves and \
         type-checks these files (`tests/ui/real/`) but does not ground them on a map; on the demo \
         house most would fail with E0501, which lists where the demo has each category.\n",
    );
    let dir = root.join("tests/ui/real");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "m2r"))
        .collect();
    files.sort();
    for path in files {
        let name = path.file_stem().unwrap().to_string_lossy().to_string();
        let source = std::fs::read_to_string(&path).unwrap();
        out.push_str(&format!(
            "\n### `{name}`\n\n```m2r\n{}\n{}\n```\n",
            scene_marker(&name),
            source.trim_end()
        ));
    }
    out
}

/// The `// scene:` line of a real program in the reference: the scene it was written for, from
/// its file name (`108_002`), or the reference prompts for a clause.
fn scene_marker(name: &str) -> String {
    match name.split_once('_') {
        Some((scene, _)) if scene.bytes().all(|b| b.is_ascii_digit()) => {
            format!("// scene: Map2Route {scene} (checked only)")
        }
        _ => "// scene: a clause of the reference prompts (checked only)".to_string(),
    }
}

#[test]
fn language_reference_is_up_to_date() {
    let path = root().join("docs/language.md");
    let want = language_reference();
    if std::env::var_os("UPDATE_DOCS").is_some() {
        std::fs::write(&path, &want).unwrap();
        return;
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "docs/language.md is stale: run `UPDATE_DOCS=1 cargo test -p m2rc-tests --test it docs::`"
    );
}

/// One fenced `m2r` block: where it is, its info string and its text.
struct Block {
    at: String,
    info: String,
    text: String,
}

fn m2r_blocks(path: &Path) -> Vec<Block> {
    let name = path
        .strip_prefix(root())
        .unwrap_or(path)
        .display()
        .to_string();
    let source = std::fs::read_to_string(path).unwrap();
    let mut out = Vec::new();
    let mut open: Option<(usize, String, String)> = None;
    for (i, line) in source.lines().enumerate() {
        match (&mut open, line.strip_prefix("```")) {
            (None, Some(info)) if info.trim().starts_with("m2r") => {
                open = Some((i + 1, info.trim().to_string(), String::new()));
            }
            (None, Some(_)) => open = Some((i + 1, "other".into(), String::new())),
            (Some(_), Some("")) => {
                if let Some((line, info, text)) = open.take()
                    && info != "other"
                {
                    out.push(Block {
                        at: format!("{name}:{line}"),
                        info,
                        text,
                    });
                }
            }
            (Some((_, _, text)), _) => {
                text.push_str(line);
                text.push('\n');
            }
            (None, None) => {}
        }
    }
    out
}

/// What the first line of a block says it is for.
enum Purpose {
    Map(String),
    Scene,
    Fragment,
    Unsaid,
}

fn purpose(b: &Block) -> Purpose {
    if b.info.split_whitespace().nth(1) == Some("fragment") {
        return Purpose::Fragment;
    }
    let first = b.text.lines().next().unwrap_or("").trim();
    let comment = first.strip_prefix("//").map(str::trim).unwrap_or("");
    if let Some(m) = comment.strip_prefix("map:") {
        Purpose::Map(m.trim().to_string())
    } else if comment.starts_with("scene:") {
        Purpose::Scene
    } else {
        Purpose::Unsaid
    }
}

#[test]
fn every_program_in_the_docs_compiles_on_its_map_or_checks_for_its_scene() {
    let vocab = Vocabulary::benchmark();
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .filter(|p| p.file_name().is_some_and(|f| f != "diagnostics.md"))
        .collect();
    docs.push(root().join("README.md"));
    docs.sort();
    let mut failures = Vec::new();
    let mut compiled = 0;
    for path in &docs {
        for b in m2r_blocks(path) {
            match purpose(&b) {
                Purpose::Map(m) => {
                    let arg = if m == "demo" {
                        m.clone()
                    } else {
                        root().join(&m).to_string_lossy().into_owned()
                    };
                    let map = m2rc_stdlib::load::load_map(&arg)
                        .unwrap_or_else(|e| panic!("{}: map {m}: {e}", b.at));
                    match compile_and_plan(&b.text, &map, &PipelineOptions::default()) {
                        Ok(_) => compiled += 1,
                        Err(d) => failures.push(format!(
                            "{} does not compile on {m}:\n{}",
                            b.at,
                            render_text(&d, &b.at, &b.text)
                        )),
                    }
                }
                Purpose::Scene => {
                    let r = m2rc_compiler::check::check(&b.text, &vocab);
                    if r.has_errors() {
                        failures.push(format!(
                            "{} (checked only) has errors:\n{}",
                            b.at,
                            render_text(&r.diagnostics, &b.at, &b.text)
                        ));
                    }
                }
                Purpose::Fragment => {
                    if !m2rc_grammar::parse::parse(&b.text).is_ok() {
                        failures.push(format!("{}: the fragment does not parse", b.at));
                    }
                }
                Purpose::Unsaid => failures.push(format!(
                    "{}: an `m2r` block must begin with `// map: <map>` (it is then compiled on \
                     that map), `// scene: ...` (written for a reference scene: checked only), or \
                     be fenced ```m2r fragment",
                    b.at
                )),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(
        compiled >= 2,
        "the reference's demo programs are compiled ({compiled})"
    );
}

/// The reference's programs for scene 108 do not ground on the demo house; E0501 then says where
/// the demo does have the category, so the reader sees the program was written for another scene.
#[test]
fn a_scene_program_on_the_demo_says_where_the_demo_has_its_categories() {
    let source = std::fs::read_to_string(root().join("tests/ui/real/108_006.m2r")).unwrap();
    let map = m2rc_stdlib::load::load_map("demo").unwrap();
    let diags = compile_and_plan(&source, &map, &PipelineOptions::default())
        .expect_err("the demo's smallest bathroom has no garbage can");
    let notes: Vec<&String> = diags
        .iter()
        .filter(|d| d.code.id() == "E0501")
        .flat_map(|d| &d.notes)
        .collect();
    assert!(
        notes
            .iter()
            .any(|n| *n == "the map `demo` has 2 `garbage_can`, in kitchen_1 and bathroom_1"),
        "{notes:?}"
    );
    assert!(
        notes
            .iter()
            .any(|n| *n == "the map `demo` has 1 `dresser`, in bedroom_1"),
        "{notes:?}"
    );
}

/// `docs/diagnostics.md` is generated from the code registry with every example's real output;
/// the examples of map codes (E05xx, E07xx) are compiled and planned on the demo house here,
/// where the planner is at hand.
#[test]
fn diagnostics_reference_is_up_to_date() {
    let map = m2rc_stdlib::load::load_map("demo").unwrap();
    let on_demo = |source: &str| {
        compile_and_plan(source, &map, &PipelineOptions::default())
            .err()
            .unwrap_or_default()
    };
    let want = m2rc_compiler::diagnostic::doc::diagnostics_markdown(&on_demo);
    let path = root().join("docs/diagnostics.md");
    if std::env::var_os("UPDATE_DOCS").is_some() {
        std::fs::write(&path, &want).unwrap();
        return;
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "docs/diagnostics.md is stale: run `UPDATE_DOCS=1 cargo test -p m2rc-tests --test it docs::`"
    );
    for code in ["E0501", "E0706"] {
        let section = want.split(&format!("### {code}:")).nth(1).unwrap();
        let section = section.split("\n### ").next().unwrap();
        assert!(section.contains(&format!("error[{code}]")), "{section}");
    }
}
