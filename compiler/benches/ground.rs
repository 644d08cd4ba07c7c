//! Grounding speed on the largest fixture house: a Hard-sized program (several stages, filters,
//! lambdas, rankings, relations, scopes) grounded from the checked AST.
//! Target: under 5 ms per grounding (the map index is built once per map and measured apart).
//! Also: nested filters, ten rooms-in-rooms deep (each level relating its candidate to its
//! parent's), under 50 ms; without memoisation this was exponential in the depth.

use criterion::{Criterion, criterion_group, criterion_main};
use m2rc_compiler::check::check;
use m2rc_compiler::eval::{GroundOptions, ground_checked};
use m2rc_stdlib::query::MapQuery;
use m2rc_stdlib::vocab::Vocabulary;
use std::hint::black_box;

/// The largest of the five fixture houses (by grid cells).
const HOUSE: &str = "procthor10k_uniform_hard_val_150_149.json";

const PROGRAM: &str = r#"
let kitchen = rooms(kitchen).only()
let bedroom = rooms(bedroom).where(r => objects(bed).in(r).exists()).largest()
let bath = rooms(bathroom).except(start.room()).smallest()
let fridge = objects(fridge).only()
let sofa = objects(sofa).nearest()

route {
  go fridge as fetch {
    prefer near(objects().on(objects(counter_top)).near(fridge, within: 2m)) within kitchen
    avoid area_near(sofa, within: 30cm)
  }
  go objects(bed).in(bedroom).nearest() as rest {
    prefer far(objects().where(o => o.next_to(objects(bed)) and not o.on(objects(bed))))
    prefer closer(objects(bed).in(bedroom).nearest(), bedroom.doorways().nearest()) within bedroom
  }
  go bath as wash {
    prefer near(objects(sink).nearest()) within kitchen
    pass bath.doorways().nearest()
  }
  prefer far(objects(sofa)) during fetch, rest
  prefer clearance(40cm)
}
"#;

/// `rooms().where(a1 => rooms().where(a2 => a2.adjacent_to(a1) and rooms().where(a3 => ...``
/// `depth` levels deep, each level relating its candidate to its parent's.
pub fn nested_rooms(depth: usize) -> String {
    let mut body = format!("a{depth}.adjacent_to(a{})", depth - 1);
    for i in (2..depth).rev() {
        body = format!(
            "a{i}.adjacent_to(a{}) and rooms().where(a{} => {body}).exists()",
            i - 1,
            i + 1
        );
    }
    format!(
        "let deep = rooms().where(a1 => rooms().where(a2 => {body}).exists())\nroute {{\n  go deep.nearest()\n}}\n"
    )
}

/// Four nested object filters, each relating its candidate to its parent's.
const NESTED_OBJECTS: &str = "let o = objects().where(o1 => objects(chair).where(o2 => o2.near(o1) and objects(dining_table).where(o3 => o3.near(o2) and objects().where(o4 => o4.next_to(o3)).exists()).exists()).exists())\nroute {\n  go o.nearest()\n}\n";

fn bench(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../shared/procthor/fixtures/"
    );
    let Ok(map) = m2rc_stdlib::load::load_map(&format!("{path}{HOUSE}")) else {
        eprintln!("fixture house {HOUSE} not found beside the repository; skipping");
        return;
    };
    let checked = check(PROGRAM, &Vocabulary::from_map(&map));
    assert!(!checked.has_errors(), "{:#?}", checked.diagnostics);
    let q = MapQuery::new(&map);
    let opts = GroundOptions::default();
    let g = ground_checked(&checked, PROGRAM, &q, &opts);
    assert!(g.ir.is_some(), "{:#?}", g.problems);
    c.bench_function("ground hard program (largest fixture house)", |b| {
        b.iter(|| ground_checked(black_box(&checked), PROGRAM, &q, &opts))
    });
    c.bench_function("index largest fixture house (MapQuery::new)", |b| {
        b.iter(|| MapQuery::new(black_box(&map)))
    });
    let vocab = Vocabulary::from_map(&map);
    for (name, program) in [
        ("ground 10-deep nested rooms().where", nested_rooms(10)),
        (
            "ground 4-deep nested objects().where",
            NESTED_OBJECTS.to_string(),
        ),
    ] {
        let checked = check(&program, &vocab);
        assert!(!checked.has_errors(), "{:#?}", checked.diagnostics);
        let g = ground_checked(&checked, &program, &q, &opts);
        assert!(
            g.problems
                .iter()
                .all(|p| !p.is_error() || p.code == "E0503"),
            "{:#?}",
            g.problems
        );
        c.bench_function(name, |b| {
            b.iter(|| ground_checked(black_box(&checked), &program, &q, &opts))
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
