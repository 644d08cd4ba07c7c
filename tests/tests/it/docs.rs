//! Generated documentation must match its sources: `docs/language.md` is the hand-written intro
//! (`docs/src/language-intro.md`), the built-in table from `stdlib::builtins`, and the real
//! instruction programs of `tests/ui/real/`. Run with `UPDATE_DOCS=1` to rewrite it.

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
         clause from the reference prompts, with its program. These files are checked in CI \
         (`tests/ui/real/`).\n",
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
            "\n### `{name}`\n\n```m2r\n{}\n```\n",
            source.trim_end()
        ));
    }
    out
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
