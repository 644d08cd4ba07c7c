//! Parse + check of a long real program (scene 108, hard instruction 018). Target: under 1 ms.

use criterion::{Criterion, criterion_group, criterion_main};
use m2rc_stdlib::vocab::Vocabulary;
use std::hint::black_box;

const PROGRAM: &str = include_str!("scene108_018.m2r");

fn bench(c: &mut Criterion) {
    let vocab = Vocabulary::benchmark();
    let r = m2rc_compiler::check(PROGRAM, &vocab);
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
    c.bench_function("parse_and_check_scene108_018", |b| {
        b.iter(|| m2rc_compiler::check(black_box(PROGRAM), &vocab))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
