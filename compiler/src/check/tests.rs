//! One test per diagnostic: source in, expected codes and the exact text they point at out.

use super::*;
use crate::diagnostic::{Code, Severity, apply_suggestions};
use m2rc_stdlib::vocab::{VocabSource, Vocabulary};

fn run(src: &str) -> CheckResult {
    check(src, &Vocabulary::benchmark())
}

/// `(code, text under the primary span)` for every diagnostic, in order.
fn found(src: &str) -> Vec<(&'static str, String)> {
    run(src)
        .diagnostics
        .iter()
        .map(|d| {
            (
                d.code.id(),
                src.get(d.span.start..d.span.end)
                    .unwrap_or("<bad span>")
                    .to_string(),
            )
        })
        .collect()
}

#[track_caller]
fn expect(src: &str, want: &[(&str, &str)]) {
    let got = found(src);
    let want: Vec<(&str, String)> = want.iter().map(|(c, t)| (*c, t.to_string())).collect();
    assert_eq!(
        got,
        want,
        "\nsource:\n{src}\ndiagnostics: {:#?}",
        run(src).diagnostics
    );
}

#[track_caller]
fn clean(src: &str) {
    expect(src, &[]);
}

/// Applies the first suggestion of each diagnostic and checks the result is clean.
#[track_caller]
fn fixes_to_clean(src: &str) {
    let r = run(src);
    assert!(!r.diagnostics.is_empty());
    let fixed = apply_suggestions(src, &r.diagnostics);
    let after = run(&fixed);
    assert!(
        after.diagnostics.is_empty(),
        "fixed source:\n{fixed}\nstill: {:#?}",
        after.diagnostics
    );
}

const DESIGN_EXAMPLE: &str = r#"// map: demo
let bathroom = rooms(bathroom).smallest()
let can = objects(garbage_can).in(bathroom).only()
let before = room_before_entering(bathroom)

route {
  go can {
    prefer near(objects(dresser).in(before).only()) within before
  }
}
"#;

#[test]
fn the_design_example_is_clean_and_typed() {
    let r = run(DESIGN_EXAMPLE);
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
    assert_eq!(r.stages.len(), 1);
    // `can` in `go can` resolves to the top-level binding and has type Object.
    let go = DESIGN_EXAMPLE.find("go can").unwrap() + 3;
    let span = Span::new(go, go + 3);
    assert_eq!(r.types.get(&span), Some(&Type::Object));
    let def = DESIGN_EXAMPLE.find("let can").unwrap() + 4;
    assert!(matches!(
        r.resolutions.get(&span),
        Some(Resolution::Binding { def: d, kind: BindingKind::Let }) if d.start == def
    ));
    // `bathroom` inside `rooms(...)` is the category, elsewhere the binding.
    let cat = DESIGN_EXAMPLE.find("rooms(bathroom)").unwrap() + 6;
    assert_eq!(
        r.resolutions.get(&Span::new(cat, cat + 8)),
        Some(&Resolution::Category {
            name: "bathroom".into(),
            kind: CategoryKind::Room
        })
    );
}

#[test]
fn calls_record_overload_and_argument_mapping() {
    let src = "route { go objects(chair).nearest(by: travel) }";
    let r = run(src);
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
    let (span, info) = r
        .calls
        .iter()
        .find(|(_, c)| c.builtin.name == "nearest")
        .unwrap();
    assert_eq!(
        &src[span.start..span.end],
        "objects(chair).nearest(by: travel)"
    );
    assert_eq!(info.t, Elem::Object);
    assert_eq!(info.args, vec![None, Some(0)]);
    let travel = src.find("travel").unwrap();
    assert_eq!(
        r.resolutions.get(&Span::new(travel, travel + 6)),
        Some(&Resolution::Metric(Metric::Travel))
    );
    assert_eq!(r.types.get(span), Some(&Type::Object));
}

#[test]
fn real_instruction_programs_check_clean() {
    clean(
        "let kitchen = rooms(kitchen).only()\nlet plant = objects(house_plant).in(kitchen).only()\n\
         let before = room_before_entering(kitchen)\nroute {\n  go plant {\n    prefer closer(objects(dining_table).in(before), objects(desk).in(before)) within before\n  }\n}",
    );
    clean(
        "let r = rooms().max_by(r => objects(tennis_racket | pillow).in(r).count())\n\
         let box = objects(box).in(r).where(b => b.next_to(objects(window))).only()\n\
         route {\n  go box as first {\n    prefer near(objects(remote_control).in(start.room())) within start.room()\n  }\n\
         \x20 go area_near(objects(counter_top).in(rooms(kitchen)).only()) as second\n  prefer far(objects(stool)) during second\n}",
    );
    clean(
        "route {\n  for r in rooms(bedroom).sorted_by(r => r.area()) {\n    go r.corners().farthest(to: doorway_entering(r), by: travel)\n  }\n}",
    );
    clean(
        "let seats = objects(chair | sofa)\nlet t = if seats.exists() { seats.nearest() } else { objects(bed).nearest() }\n\
         route { go t { avoid area_between(objects(vacuum_cleaner).only(), objects(dining_table).nearest(to: objects(vacuum_cleaner).only())) prefer clearance(0.5m) } }",
    );
    clean(
        "route { go objects(toilet).where(t => t.in(rooms(bathroom).where(b => b.only_reachable_through(rooms(living_room))))).only() { prefer far(objects(sofa)) } }",
    );
}

#[test]
fn stages_and_during_names_are_recorded_in_route_order() {
    let src = "route {\n  go objects(bed).only() as a\n  for r in rooms(bedroom) {\n    go r as b\n  }\n  prefer far(objects(sofa)) during a, b\n}";
    let r = run(src);
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
    let names: Vec<(Option<&str>, bool)> = r
        .stages
        .iter()
        .map(|s| (s.name.as_deref(), s.in_for))
        .collect();
    assert_eq!(names, [(Some("a"), false), (Some("b"), true)]);
    let b = src.rfind(", b").unwrap() + 2;
    assert_eq!(
        r.resolutions.get(&Span::new(b, b + 1)),
        Some(&Resolution::Stage(1))
    );
    // The loop variable is a Room inside the body.
    let go_r = src.find("go r").unwrap() + 3;
    assert_eq!(r.types.get(&Span::new(go_r, go_r + 1)), Some(&Type::Room));
}

#[test]
fn unused_loop_variable_is_a_warning_with_underscore_fix() {
    let src = "route { for r in rooms(bedroom) { go start } }";
    expect(src, &[("E0107", "r")]);
    fixes_to_clean(src);
}

#[test]
fn e0101_unknown_name_with_did_you_mean() {
    expect(
        "let sofa1 = objects(sofa).only()\nroute { go sofa2 }",
        &[("E0101", "sofa2")],
    );
    fixes_to_clean("let sofa1 = objects(sofa).only()\nroute { go sofa2 }");
    expect("route { go zzzqqq }", &[("E0101", "zzzqqq")]);
}

#[test]
fn e0102_category_used_as_place() {
    expect("route { go bed }", &[("E0102", "bed")]);
    fixes_to_clean("route { go bed }");
    fixes_to_clean("route { go objects(chair).nearest() { prefer far(sofa) } }");
    let r = run("route { go kitchen }");
    assert!(r.diagnostics[0].suggestions[0].replacement == "rooms(kitchen).only()");
    // A synonym gets its canonical category in the fix.
    let r = run("route { go tv }");
    assert_eq!(
        r.diagnostics[0].suggestions[0].replacement,
        "objects(television).only()"
    );
}

#[test]
fn e0103_e0104_unknown_functions_and_methods() {
    expect("route { go objcts(bed).only() }", &[("E0103", "objcts")]);
    fixes_to_clean("route { go objcts(bed).only() }");
    expect("route { go objects(bed).nearst() }", &[("E0104", "nearst")]);
    fixes_to_clean("route { go objects(bed).nearst() }");
    expect(
        "route { go objects(bed).frobnicate() }",
        &[("E0104", "frobnicate")],
    );
}

#[test]
fn e0105_method_on_the_wrong_receiver() {
    let src = "route { go objects(bed).only().nearest() }";
    expect(src, &[("E0105", "nearest")]);
    let d = &run(src).diagnostics[0];
    assert!(
        d.message.contains("Set<T>") && d.message.contains("found `Object`"),
        "{}",
        d.message
    );
    // A method of single rooms called on a set suggests choosing one first.
    let src = "route { go rooms(kitchen).area() }";
    expect(src, &[("E0105", "area")]);
    // Lambda parameter of the wrong element type: the label points at the parameter.
    let src = "route { go rooms().where(r => r.on(objects(bed))).only() }";
    expect(src, &[("E0105", "on")]);
    assert_eq!(run(src).diagnostics[0].labels.len(), 2);
}

#[test]
fn e0106_duplicate_binding_and_shadowing() {
    expect(
        "let b = objects(bed).only()\nlet b = objects(sofa).only()\nroute { go b }",
        &[("E0106", "b")],
    );
    // Shadowing in a nested scope is allowed.
    clean(
        "let b = objects(bed).only()\nroute { go b { let b = objects(sofa).only() prefer far(b) } }",
    );
    // Lambda parameters may reuse an outer name.
    clean(
        "let r = rooms(kitchen).only()\nroute { go rooms().where(r => r.contains(objects(bed))).only() { avoid r } }",
    );
}

#[test]
fn e0107_unused_binding_is_a_warning_with_a_removal() {
    let src = "let b = objects(bed).only()\nroute { go start }";
    expect(src, &[("E0107", "b")]);
    let r = run(src);
    assert_eq!(r.diagnostics[0].severity, Severity::Warning);
    assert!(!r.has_errors());
    fixes_to_clean(src);
    clean("let _b = objects(bed).only()\nroute { go start }");
}

#[test]
fn e0108_stage_local_binding_used_outside() {
    let src = "route {\n  go objects(bed).only() {\n    let s = objects(sofa).only()\n    prefer far(s)\n  }\n  go s\n}";
    expect(src, &[("E0108", "s")]);
    let d = &run(src).diagnostics[0];
    assert_eq!(d.labels.len(), 1);
}

#[test]
fn e0109_e0110_named_arguments() {
    expect(
        "route { go objects(chair).nearest(too: start) }",
        &[("E0109", "too")],
    );
    fixes_to_clean("route { go objects(chair).nearest(too: start) }");
    expect(
        "route { go objects(chair).nearest(to: start, to: start) }",
        &[("E0110", "to: start")],
    );
    expect(
        "route { go objects(chair).kth_nearest(2, k: 3) }",
        &[("E0110", "k: 3")],
    );
}

#[test]
fn e0111_e0112_e0113_e0114_builtin_misuse() {
    expect("route { go objects }", &[("E0111", "objects")]);
    expect(
        "let start = objects(bed).only()\nroute { go start }",
        &[("E0112", "start")],
    );
    expect("let travel = 2\nroute { go start }", &[("E0112", "travel")]);
    expect(
        "route { go nearest(objects(chair)) }",
        &[("E0113", "nearest")],
    );
    fixes_to_clean("route { go nearest(objects(chair)) }");
    expect(
        "route { go start { prefer start.room().patrol(clockwise) } }",
        &[("E0114", "patrol")],
    );
    fixes_to_clean("route { go start { prefer start.room().patrol(clockwise) } }");
}

#[test]
fn e0201_type_mismatch() {
    expect(
        "route { go objects(bed).only() { prefer near(2) } }",
        &[("E0201", "2")],
    );
    expect(
        "route { go start { prefer follow_wall(start.room(), travel) } }",
        &[("E0201", "travel")],
    );
}

#[test]
fn e0202_set_where_single_needs_an_explicit_choice() {
    expect(
        "route { go area_near(objects(bed)) }",
        &[("E0202", "objects(bed)")],
    );
    fixes_to_clean("route { go area_near(objects(bed)) }");
    expect(
        "let d = room_before_entering(rooms(bathroom))\nroute { go d }",
        &[("E0202", "rooms(bathroom)")],
    );
    // Sets are fine where sets are accepted: `go` and `pass` on a set are any one member.
    clean("route { go start { avoid objects(sofa) prefer near(objects(bed)) } }");
    clean("route { go objects(bed) { pass rooms(kitchen) } }");
}

#[test]
fn e0203_number_needs_a_unit() {
    expect(
        "route { go objects(bed).only() { prefer clearance(0.5) } }",
        &[("E0203", "0.5")],
    );
    fixes_to_clean("route { go objects(bed).only() { prefer clearance(0.5) } }");
    expect(
        "route { go objects(chair).near(objects(cup), within: 1).nearest() }",
        &[("E0203", "1")],
    );
}

#[test]
fn e0204_strings() {
    expect(
        "route { go objects(\"bed\").only() }",
        &[("E0204", "\"bed\"")],
    );
    fixes_to_clean("route { go objects(\"bed\").only() }");
    fixes_to_clean("route { go objects(\"dining table\").only() }");
}

#[test]
fn e0205_e0206_e0207_arity() {
    expect(
        "route { go objects(bed, sofa).nearest() }",
        &[("E0205", "sofa")],
    );
    fixes_to_clean("route { go objects(bed, sofa).nearest() }");
    expect(
        "route { go area_between(start, start, start) }",
        &[("E0205", "start")],
    );
    fixes_to_clean("route { go area_between(start, start, start) }");
    // A direction may be left out (the shorter way is taken); a missing place is still E0206.
    let src = "route { go start { prefer closer(objects(bed)) } }";
    expect(src, &[("E0206", "closer(objects(bed))")]);
    assert!(
        run(src).diagnostics[0]
            .help
            .as_deref()
            .unwrap()
            .contains("closer(a: Place | Set<Place>, b: Place | Set<Place>)")
    );
    expect(
        "route { go area_between(start) }",
        &[("E0206", "area_between(start)")],
    );
    expect(
        "route { go objects(chair).kth_nearest(to: start, 2) }",
        &[
            ("E0206", "objects(chair).kth_nearest(to: start, 2)"),
            ("E0207", "2"),
        ],
    );
}

#[test]
fn e0208_e0209_lambdas() {
    expect("let f = x => x\nroute { go start }", &[("E0208", "x => x")]);
    expect(
        "route { go rooms().where(r => r.area()).only() }",
        &[("E0209", "r.area()")],
    );
    expect(
        "route { go rooms().max_by(r => r.contains(objects(bed))) }",
        &[("E0209", "r.contains(objects(bed))")],
    );
    clean("route { go rooms().max_by(r => r.area()) }");
}

#[test]
fn e0210_comparisons() {
    expect(
        "route { go rooms().where(r => r.area() < 2m).only() }",
        &[("E0210", "r.area() < 2m")],
    );
    let src = "route { go objects(chair).where(c => c.distance(start) < 2).nearest() }";
    expect(src, &[("E0210", "c.distance(start) < 2")]);
    fixes_to_clean(src);
    expect(
        "route { go rooms().where(r => r == objects(bed).only()).only() }",
        &[("E0210", "r == objects(bed).only()")],
    );
    clean("route { go rooms().where(r => objects(stool).in(r).count() == 2).only() }");
}

#[test]
fn e0211_e0212_if() {
    expect(
        "route { go if objects(tv_stand).exists() { objects(tv_stand).only() } else { rooms(kitchen) } }",
        &[(
            "E0211",
            "if objects(tv_stand).exists() { objects(tv_stand).only() } else { rooms(kitchen) }",
        )],
    );
    expect(
        "route { go if objects(bed).count() { start } else { start } }",
        &[("E0212", "objects(bed).count()")],
    );
    // Two different places join to Place.
    clean(
        "route { go if objects(bed).exists() { objects(bed).nearest() } else { rooms(kitchen).only() } }",
    );
}

#[test]
fn e0213_e0214_e0215_loops_and_operators() {
    expect(
        "route { for r in rooms(bedroom).only() { go r } }",
        &[("E0213", "rooms(bedroom).only()")],
    );
    expect(
        "let n = objects(bed) + 1\nroute { go start }",
        &[("E0214", "objects(bed) + 1")],
    );
    expect(
        "route { go objects(bed).where(b => not b.area()).only() }",
        &[("E0105", "area")],
    );
    expect(
        "route { go objects(bed).where(b => b.near(start) and 3).only() }",
        &[("E0214", "3")],
    );
    expect(
        "route { go (objects(bed) | sofa).nearest() }",
        &[("E0215", "objects(bed) | sofa")],
    );
    clean("let s = objects(bed) | objects(sofa)\nroute { go s.nearest() }");
    clean("let c = bed | sofa\nroute { go objects(c).nearest() }");
}

#[test]
fn e0301_e0302_e0303_route_structure() {
    expect(
        "let b = objects(bed).only()",
        &[("E0107", "b"), ("E0301", "")],
    );
    expect(
        "route { go start }\nroute { go start }",
        &[("E0302", "route")],
    );
    expect("route { }", &[("E0303", "route")]);
    expect("route { prefer clearance() }", &[("E0303", "route")]);
}

#[test]
fn e0304_e0305_e0306_e0307_stage_scopes() {
    expect(
        "route {\n  go objects(bed).only()\n  pass rooms(kitchen).only()\n}",
        &[("E0304", "pass")],
    );
    let src = "route {\n  go objects(bed).only() as first {\n    prefer far(objects(sofa)) during first\n  }\n}";
    expect(src, &[("E0305", "during first")]);
    fixes_to_clean(src);
    let src = "route {\n  go objects(bed).only() as bed_stage\n  prefer far(objects(sofa)) during bedstage\n}";
    expect(src, &[("E0306", "bedstage")]);
    fixes_to_clean(src);
    expect(
        "route {\n  go objects(bed).only() as a\n  go objects(sofa).only() as a\n}",
        &[("E0307", "a")],
    );
    // `during` may name a stage declared later.
    clean("route {\n  prefer far(objects(sofa)) during b\n  go objects(bed).only() as b\n}");
}

#[test]
fn e0308_to_e0315_constraint_values_and_scopes() {
    expect(
        "route { go start { prefer far(objects(sofa)) within 2m } }",
        &[("E0308", "2m")],
    );
    let src = "route { go start { prefer objects(sofa).only() } }";
    expect(src, &[("E0309", "objects(sofa).only()")]);
    fixes_to_clean(src);
    let src = "route { go start { prefer kitchen } }";
    expect(src, &[("E0309", "kitchen")]);
    assert_eq!(
        run(src).diagnostics[0].suggestions[0].replacement,
        "near(rooms(kitchen))"
    );
    fixes_to_clean(src);
    let src = "route { go start { avoid near(objects(sofa)) } }";
    expect(src, &[("E0310", "near(objects(sofa))")]);
    fixes_to_clean(src);
    expect("route { go 3 }", &[("E0311", "3")]);
    let src =
        "route { go start { prefer far(objects(sofa)) within start.room() within start.room() } }";
    expect(src, &[("E0312", "within start.room()")]);
    let src = "route {\n  go objects(bed).only() as a\n  go objects(sofa).only() as b\n  prefer far(objects(desk)) during b, a\n}";
    expect(src, &[("E0313", "b, a")]);
    fixes_to_clean(src);
    let src = "route {\n  go objects(bed).only()\n  avoid here.room()\n}";
    expect(src, &[("E0314", "here")]);
    fixes_to_clean(src);
    clean("route { go objects(bed).only() { avoid here.room() } }");
    expect("route { go start { avoid 2m } }", &[("E0315", "2m")]);
    // Spatial scopes accept sets of rooms.
    clean("route { go start { prefer far(objects(sofa)) within rooms(kitchen) } }");
}

#[test]
fn e0401_to_e0406_categories() {
    expect(
        "route { go objects(chiar).nearest() }",
        &[("E0401", "chiar")],
    );
    fixes_to_clean("route { go objects(chiar).nearest() }");
    expect(
        "route { go objects(kitchen).nearest() }",
        &[("E0402", "kitchen")],
    );
    fixes_to_clean("route { go objects(kitchen).nearest() }");
    expect("route { go rooms(bed).nearest() }", &[("E0403", "bed")]);
    fixes_to_clean("route { go rooms(bed).nearest() }");
    let src = "route { go objects(table).nearest() }";
    expect(src, &[("E0405", "table")]);
    let reps: Vec<String> = run(src).diagnostics[0]
        .suggestions
        .iter()
        .map(|s| s.replacement.clone())
        .collect();
    assert_eq!(
        reps,
        [
            "dining_table",
            "side_table",
            "desk",
            "dining_table | side_table | desk"
        ]
    );
    fixes_to_clean(src);
    let src = "route { go objects(tv).nearest() }";
    expect(src, &[("E0406", "tv")]);
    let r = run(src);
    assert!(!r.has_errors());
    let tv = src.find("tv").unwrap();
    assert_eq!(
        r.resolutions.get(&Span::new(tv, tv + 2)),
        Some(&Resolution::Category {
            name: "television".into(),
            kind: CategoryKind::Object
        })
    );
    expect(
        "route { go objects(plant | counter).nearest() }",
        &[("E0406", "plant"), ("E0406", "counter")],
    );
}

#[test]
fn e0404_category_not_in_the_map() {
    let vocab = Vocabulary {
        objects: ["bed", "sofa", "side_table"]
            .iter()
            .map(|s| s.to_string())
            .collect(),
        rooms: ["bedroom"].iter().map(|s| s.to_string()).collect(),
        source: VocabSource::Map("test".into()),
    };
    let r = check("route { go objects(dining_table).nearest() }", &vocab);
    let codes: Vec<&str> = r.diagnostics.iter().map(|d| d.code.id()).collect();
    assert_eq!(codes, ["E0404"]);
    assert!(r.diagnostics[0].notes[0].contains("side_table"));
    let r = check("route { go objects(table).nearest() }", &vocab);
    assert!(
        r.diagnostics
            .iter()
            .all(|d| d.code == Code::SynonymResolved),
        "{:#?}",
        r.diagnostics
    );
    let r = check("route { go rooms(kitchen).only() }", &vocab);
    assert_eq!(r.diagnostics[0].code, Code::CategoryNotInMap);
}

#[test]
fn parse_errors_are_converted_and_do_not_cascade() {
    let r = run("route { go objects(bed).only(");
    assert!(
        r.diagnostics.iter().all(|d| d.code.id().starts_with("E00")),
        "{:#?}",
        r.diagnostics
    );
    assert!(r.has_errors());
}

#[test]
fn registry_examples_produce_their_codes() {
    let mut failures = Vec::new();
    for info in Code::registry() {
        if info.example.is_empty() || info.id >= "E0500" {
            continue;
        }
        let r = run(info.example);
        if !r.diagnostics.iter().any(|d| d.code.id() == info.id) {
            let got: Vec<&str> = r.diagnostics.iter().map(|d| d.code.id()).collect();
            failures.push(format!("{}: {:?} gave {got:?}", info.id, info.example));
        }
    }
    assert!(
        failures.is_empty(),
        "examples not producing their code:\n{}",
        failures.join("\n")
    );
}

#[test]
fn diagnostics_are_sorted_and_deterministic() {
    let src = "let a = objects(chiar)\nlet b = rooms(bed)\nroute { go zz { prefer kitchen } }";
    let one = run(src).diagnostics;
    let two = run(src).diagnostics;
    assert_eq!(one, two);
    assert!(
        one.windows(2)
            .all(|w| (w[0].span.start, w[0].code.id()) <= (w[1].span.start, w[1].code.id()))
    );
}

mod robustness {
    use super::*;
    use proptest::prelude::*;

    const TOKENS: &[&str] = &[
        "let",
        "x",
        "y",
        "=",
        "route",
        "{",
        "}",
        "go",
        "as",
        "pass",
        "avoid",
        "prefer",
        "within",
        "during",
        "for",
        "in",
        "if",
        "else",
        "and",
        "or",
        "not",
        "(",
        ")",
        ".",
        ",",
        ":",
        "=>",
        "|",
        "==",
        "<",
        "+",
        "*",
        "-",
        "2",
        "1.5m",
        "\"s\"",
        "objects",
        "rooms",
        "bed",
        "kitchen",
        "table",
        "tv",
        "nearest",
        "only",
        "where",
        "near",
        "start",
        "here",
        "clockwise",
        "travel",
        "\n",
        "é",
        "😀",
    ];

    fn assert_sane(src: &str) {
        let r = run(src);
        for d in &r.diagnostics {
            assert!(
                d.span.start <= d.span.end && d.span.end <= src.len(),
                "{d:?}"
            );
            for s in &d.suggestions {
                assert!(s.span.end <= src.len());
            }
        }
        let _ = crate::diagnostic::render_text(&r.diagnostics, "p.m2r", src);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        #[test]
        fn token_soup_never_panics(toks in proptest::collection::vec(proptest::sample::select(TOKENS), 0..50)) {
            assert_sane(&toks.join(" "));
        }

        #[test]
        fn every_prefix_of_a_real_program_is_checked_without_panic(cut in 0usize..400) {
            let cut = cut.min(DESIGN_EXAMPLE.len());
            if DESIGN_EXAMPLE.is_char_boundary(cut) {
                assert_sane(&DESIGN_EXAMPLE[..cut]);
            }
        }
    }
}

#[test]
fn physical_relations_refuse_rooms_and_regions_next_to_refuses_rooms() {
    // Grounding keeps only objects for these: a room or region argument would never hold.
    for rel in ["on", "inside", "under", "holding"] {
        expect(
            &format!(
                "let k = rooms(kitchen).only()\nroute {{ go objects(cup).{rel}(k).nearest() }}"
            ),
            &[("E0201", "k")],
        );
        expect(
            &format!(
                "route {{ go objects(cup).{rel}(rooms(kitchen).only().corners()).nearest() }}"
            ),
            &[("E0201", "rooms(kitchen).only().corners()")],
        );
    }
    expect(
        "let k = rooms(kitchen).only()\nroute { go objects(cup).next_to(k).nearest() }",
        &[("E0201", "k")],
    );
    clean("route { go objects(cup).next_to(rooms(kitchen).only().corners()).nearest() }");
    clean(
        "route { go objects(cup).where(c => c.next_to(rooms(kitchen).only().doorways().only())).nearest() }",
    );
}

#[test]
fn regions_as_containers_and_sets_as_ranking_targets_check() {
    clean("route { go objects(painting).in(rooms(bedroom).only().corners().farthest()).only() }");
    clean(
        "route { go objects(painting).where(p => p.in(area_near(objects(bed).nearest()))).nearest() }",
    );
    clean(
        "route { go rooms(bedroom).only().corners().where(c => c.contains(objects(painting))).only() }",
    );
    clean("route { go objects(chair).nearest(to: objects(dresser)) }");
    clean("route { go objects(chair).nearest_first(to: objects(dresser)).kth(2) }");
    clean("route { go objects(bed).nearest() { prefer near_each(objects(dresser)) } }");
}

#[test]
fn a_one_place_through_offers_near_and_no_second_place() {
    let src = "route { go objects(bed).nearest() { prefer through(objects(box).nearest()) } }";
    expect(src, &[("E0206", "through(objects(box).nearest())")]);
    let d = &run(src).diagnostics[0];
    let help = d.help.clone().unwrap_or_default();
    assert!(help.contains("near(objects(box).nearest())"), "{help}");
    fixes_to_clean(src);
    let fixed = apply_suggestions(src, &run(src).diagnostics);
    assert!(
        fixed.contains("prefer near(objects(box).nearest())"),
        "{fixed}"
    );
}
