//! Checker tests for the language v2 constructs and the diagnostics fixes that are not errors
//! (so have no file in `tests/ui/errors`): what now checks clean, and how odd text is read.

use crate::check::check;
use crate::diagnostic::{Code, LineIndex};
use m2rc_stdlib::vocab::Vocabulary;

fn errors(src: &str) -> Vec<(Code, String)> {
    check(src, &Vocabulary::benchmark())
        .errors()
        .map(|d| (d.code, d.message.clone()))
        .collect()
}

fn clean(src: &str) {
    let e = errors(src);
    assert!(e.is_empty(), "{src}\n{e:#?}");
}

#[test]
fn center_takes_a_single_place_or_a_set() {
    clean("route { go center(start.room()) }");
    clean("route { go center(objects(potato)) }");
    clean("let k = rooms(kitchen).only()\nroute { go center([k, start.room()]) }");
}

#[test]
fn unions_and_set_literals_of_places_are_sets() {
    clean(
        "let k = rooms(kitchen).only()\nlet l = rooms(living_room).nearest()\n\
         route { go objects(sofa).nearest() { avoid k | l\n prefer far(objects(window)) within [k, l] } }",
    );
    clean("let s = [objects(sofa).nearest(), objects(bed).nearest()]\nroute { go s.nearest() }");
    clean("route { go [objects(sofa).nearest(), objects(bed).nearest(),].farthest() }");
    // A one-element literal is the element itself.
    clean("route { go [objects(sofa).nearest()] }");
    let r = check("route { go start { avoid [] } }", &Vocabulary::benchmark());
    let d = r.errors().next().expect("an empty literal is an error");
    assert_eq!(d.code, Code::UnexpectedToken);
    assert!(
        d.help.as_deref().unwrap_or("").contains("at least one"),
        "{d:?}"
    );
}

#[test]
fn new_builtins_check_with_their_documented_types() {
    clean("route { go objects(sofa).max_by(s => s.length()) }");
    clean("route { go objects(dining_table).max_by(t => t.squareness()) }");
    clean("route { go objects(dining_table).smallest() }");
    clean("route { go objects(painting).largest() }");
    clean(
        "route { go objects(chair).where(c => c.width() < 50cm and c.footprint_area() > 0.1).nearest() }",
    );
    clean("route { for c in objects(chair).farthest_first() { go c } }");
    clean("route { go objects(chair).sorted_by_descending(c => c.footprint_area()).kth(2) }");
    clean("route { go rooms(bedroom).sorted_by(r => r.area()).reversed().kth(1) }");
    clean("route { go house_corners().nearest() }");
    clean("route { go house_center() }");
    clean("route { go rooms().farthest(to: rooms(kitchen).only(), by: travel) }");
    clean("route { go kth_entered(rooms(bedroom), 2) }");
    clean("route { go rooms(bathroom).except(visited()).nearest() }");
    clean(
        "let a = objects(sofa).nearest()\nlet b = objects(television).nearest()\n\
         let c = objects(coffee_table).nearest()\nroute { go area_enclosed([a, b, c]) }",
    );
    // Path shapes: the direction may be left out; `until` and `passing` are places.
    clean("route { go start { prefer follow_wall(start.room()) } }");
    clean("route { go start { prefer patrol(start.room()) } }");
    clean("route { go start { prefer circle(objects(bed).nearest()) } }");
    clean(
        "route { go start { prefer follow_wall(start.room(), until: doorway_leaving(start.room()), passing: objects(sofa).nearest()) } }",
    );
}

#[test]
fn byte_order_mark_and_any_line_ending_are_accepted() {
    let body = ["let b = objects(bed).nearest()", "route {", "  go b", "}"];
    clean(&format!("\u{feff}{}", body.join("\n")));
    clean(&body.join("\r\n"));
    clean(&body.join("\r"));
    clean(&format!("// a comment\r{}", body.join("\r")));
    // Positions count a lone CR as a line end.
    let src = [
        "let b = objects(bed).nearest()",
        "route {",
        "  go objects(chiar).nearest()",
        "}",
    ]
    .join("\r");
    let r = check(&src, &Vocabulary::benchmark());
    let d = r.errors().next().expect("the misspelt category");
    assert_eq!(LineIndex::new(&src).line_col(d.span.start).0, 3);
    let crlf = src.replace('\r', "\r\n");
    let r = check(&crlf, &Vocabulary::benchmark());
    let d = r.errors().next().unwrap();
    assert_eq!(LineIndex::new(&crlf).line_col(d.span.start), (3, 14));
}

#[test]
fn out_of_range_literals_are_check_errors_but_expressions_are_not_guessed() {
    let e = errors("route { go objects(chair).kth_nearest(0) { prefer clearance(-5m) } }");
    assert_eq!(
        e.iter()
            .filter(|(c, _)| *c == Code::ArgumentOutOfRange)
            .count(),
        2,
        "{e:#?}"
    );
    clean("route { go objects(chair).kth_nearest(1) { prefer clearance(0m) } }");
    // A computed ordinal is the map's business (E0504 at grounding), not the checker's.
    clean("route { go objects(chair).kth_nearest(objects(bed).count()) }");
}

#[test]
fn missing_direction_suggestions_never_pick_one() {
    // No built-in requires a direction any more; a hypothetical one would get both words.
    for b in m2rc_stdlib::builtins::BUILTINS {
        for p in b.params {
            if p.ty.contains(&m2rc_stdlib::builtins::Ty::Is(
                m2rc_stdlib::builtins::Type::Direction,
            )) {
                assert_ne!(
                    p.req,
                    m2rc_stdlib::builtins::Requirement::Default(
                        m2rc_stdlib::builtins::DefaultValue::Direction(
                            m2rc_stdlib::builtins::Direction::Counterclockwise
                        )
                    ),
                    "{} defaults a direction the instruction did not give",
                    b.name
                );
            }
        }
    }
}
