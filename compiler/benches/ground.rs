//! Grounding speed on the largest fixture house: a Hard-sized program (several stages, filters,
//! lambdas, rankings, relations, scopes) grounded from the checked AST.
//! Target: under 5 ms per grounding (the map index is built once per map and measured apart).

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
}

criterion_group!(benches, bench);
criterion_main!(benches);
