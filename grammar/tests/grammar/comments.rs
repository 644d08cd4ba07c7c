//! Where the formatter puts comments: nothing is lost, end-of-line comments stay on their line,
//! other comments move before the next statement, and the result is a fixed point.

use m2rc_grammar::{parse, print_with_comments};

fn fmt(src: &str) -> String {
    let parsed = parse(src);
    assert!(parsed.errors.is_empty(), "{:?}", parsed.errors);
    let out = print_with_comments(&parsed.program, &parsed.comments, src);
    let again = parse(&out);
    assert_eq!(
        print_with_comments(&again.program, &again.comments, &out),
        out,
        "not idempotent"
    );
    assert_eq!(
        again.comments.len(),
        parsed.comments.len(),
        "a comment was lost"
    );
    out
}

#[test]
fn header_leading_trailing_and_final_comments() {
    let src = "// map: demo\n// the instruction\n\nlet a = 1 // one\n// before b\nlet b = 2\n// the end\n";
    assert_eq!(fmt(src), src);
}

#[test]
fn comments_inside_blocks_keep_their_block() {
    let src = "route {\n  // first stage\n  go a { // to a\n    pass b // via b\n    // still in the stage\n  }\n  // last\n}\n";
    let want = "route {\n  // first stage\n  go a {\n    // to a\n    pass b // via b\n    // still in the stage\n  }\n  // last\n}\n";
    assert_eq!(fmt(src), want);
}

#[test]
fn comments_inside_an_expression_move_before_the_next_statement() {
    let src = "let a = f(\n  // why x\n  x,\n)\nlet b = 2\n";
    assert_eq!(fmt(src), "let a = f(x)\n// why x\nlet b = 2\n");
}

#[test]
fn comments_keep_an_otherwise_empty_block_open() {
    let src = "route {\n  go a {\n    // nothing yet\n  }\n}\n";
    assert_eq!(fmt(src), src);
    assert_eq!(fmt("route { // todo\n}"), "route {\n  // todo\n}\n");
}

#[test]
fn blank_lines_collapse_to_one() {
    let src = "let a = 1\n\n\n\nlet b = 2\nroute {\n\n  go a\n\n\n  go b\n}\n";
    assert_eq!(
        fmt(src),
        "let a = 1\n\nlet b = 2\nroute {\n  go a\n\n  go b\n}\n"
    );
}

#[test]
fn a_comment_without_a_final_newline() {
    assert_eq!(fmt("let a = 1 // no newline"), "let a = 1 // no newline\n");
    assert_eq!(fmt("// only a comment"), "// only a comment\n");
}
