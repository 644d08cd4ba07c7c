//! Parse + check of a long real program (scene 108, hard instruction 018). Target: under 1 ms.
//! Also a generated 100 000-line program (each `let` uses the one before): under 1 s, which needs
//! name resolution in O(n log n) rather than a scan of every earlier binding per use.

use criterion::{Criterion, criterion_group, criterion_main};
use m2rc_stdlib::vocab::Vocabulary;
use std::hint::black_box;

const PROGRAM: &str = include_str!("scene108_018.m2r");

/// `lines` lines: a chain of bindings, each ranked relative to the previous, and a route.
pub fn long_program(lines: usize) -> String {
    let mut s = String::from("let p0 = objects(chair).nearest()\n");
    for i in 1..lines - 3 {
        s.push_str(&format!(
            "let p{i} = objects(chair).nearest(to: p{})\n",
            i - 1
        ));
    }
    s.push_str(&format!("route {{\n  go p{}\n}}\n", lines - 4));
    s
}

fn bench(c: &mut Criterion) {
    let vocab = Vocabulary::benchmark();
    let r = m2rc_compiler::check(PROGRAM, &vocab);
    assert!(r.diagnostics.is_empty(), "{:#?}", r.diagnostics);
    c.bench_function("parse_and_check_scene108_018", |b| {
        b.iter(|| m2rc_compiler::check(black_box(PROGRAM), &vocab))
    });
    let long = long_program(100_000);
    let r = m2rc_compiler::check(&long, &vocab);
    assert!(
        !r.has_errors(),
        "{:#?}",
        &r.diagnostics[..r.diagnostics.len().min(3)]
    );
    let mut group = c.benchmark_group("long");
    group.sample_size(10);
    group.bench_function("parse_and_check_100k_lines", |b| {
        b.iter(|| m2rc_compiler::check(black_box(&long), &vocab))
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
