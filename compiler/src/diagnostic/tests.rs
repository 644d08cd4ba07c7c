//! Renderer tests: snapshots of the terminal text, the JSON schema, and LSP positions.

use super::*;
use crate::check;
use m2rc_stdlib::vocab::Vocabulary;

fn diags(src: &str) -> Vec<Diagnostic> {
    check(src, &Vocabulary::benchmark()).diagnostics
}

#[test]
fn text_set_where_single() {
    let src = "// map: demo\nroute {\n  go area_near(objects(bed))\n}\n";
    insta::assert_snapshot!(render_text(&diags(src), "bed.m2r", src));
}

#[test]
fn text_unknown_category_and_wrong_receiver() {
    let src = "let r = rooms(bathroom).smallest()\nroute {\n  go objects(chiar).in(r).only().nearest()\n}\n";
    insta::assert_snapshot!(render_text(&diags(src), "two.m2r", src));
}

#[test]
fn text_ambiguous_category_and_stage_scope() {
    let src = "route {\n  go objects(table).nearest() as t\n  pass rooms(kitchen).only()\n  prefer far(objects(sofa)) during tt\n}\n";
    insta::assert_snapshot!(render_text(&diags(src), "scopes.m2r", src));
}

#[test]
fn colored_text_has_ansi_escapes_and_plain_has_none() {
    let src = "route { go area_near(objects(bed)) }";
    let d = diags(src);
    assert!(render_text_colored(&d, "x.m2r", src).contains("\u{1b}["));
    assert!(!render_text(&d, "x.m2r", src).contains("\u{1b}["));
}

#[test]
fn json_follows_the_documented_schema() {
    let src = "route {\n  go area_near(objects(bed))\n}";
    let v: serde_json::Value = serde_json::from_str(&to_json(&diags(src), src)).unwrap();
    let d = &v[0];
    assert_eq!(d["code"], "E0202");
    assert_eq!(d["severity"], "error");
    let start = src.find("objects").unwrap();
    assert_eq!(d["span"]["start"], start);
    assert_eq!(d["span"]["end"], start + "objects(bed)".len());
    assert_eq!(d["span"]["line"], 2);
    assert_eq!(d["span"]["col"], 16);
    assert_eq!(d["span"]["end_col"], 28);
    assert_eq!(d["suggestion"]["replacement"], ".only()");
    assert_eq!(d["suggestion"]["span"]["start"], start + 12);
    assert_eq!(d["suggestions"].as_array().unwrap().len(), 2);
    assert!(d["help"].is_string());
    assert!(d["labels"].is_array() && d["notes"].is_array());
    assert_eq!(to_json(&[], src), "[]");
}

#[test]
fn lsp_positions_use_utf16_after_non_ascii_text() {
    // A comment with an emoji (two UTF-16 units) and an accented letter before the error.
    let src = "// café 😀\nroute { go area_near(objects(bed)) }";
    let uri: lsp_types::Uri = "file:///x.m2r".parse().unwrap();
    let out = to_lsp(&diags(src), src, &uri);
    assert_eq!(out.len(), 1);
    let r = out[0].range;
    assert_eq!((r.start.line, r.start.character), (1, 21));
    assert_eq!((r.end.line, r.end.character), (1, 33));
    assert_eq!(
        out[0].code,
        Some(lsp_types::NumberOrString::String("E0202".into()))
    );
    let data = out[0].data.as_ref().unwrap();
    assert_eq!(data["suggestions"][0]["newText"], ".only()");
    assert_eq!(data["suggestions"][0]["range"]["start"]["character"], 33);
    // On the comment line itself, the emoji counts two units.
    let idx = LineIndex::new(src);
    assert_eq!(
        idx.utf16(src.find('😀').unwrap() + '😀'.len_utf8()),
        (0, 10)
    );
}

#[test]
fn suggestions_apply_without_overlap() {
    let src = "route { go area_near(objects(chiar)) }";
    let fixed = apply_suggestions(src, &diags(src));
    assert_eq!(fixed, "route { go area_near(objects(chair).only()) }");
}

#[test]
fn parse_errors_keep_their_code_help_and_fix() {
    let src = "let b = objects(bed).only();\nroute { go b }";
    let d = diags(src);
    assert_eq!(d[0].code, Code::Semicolon);
    assert!(!d[0].suggestions.is_empty());
    assert_eq!(
        apply_suggestions(src, &d[..1]),
        "let b = objects(bed).only()\nroute { go b }"
    );
}
