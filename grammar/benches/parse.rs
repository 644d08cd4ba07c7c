//! Parse and print a long program resembling a Hard Map2Route instruction (47 lines).

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

const HARD: &str = include_str!("hard_instruction.m2r");

fn bench(c: &mut Criterion) {
    let parsed = m2rc_grammar::parse(HARD);
    assert!(parsed.errors.is_empty(), "{:?}", parsed.errors);
    c.bench_function("parse_hard_instruction", |b| {
        b.iter(|| m2rc_grammar::parse(black_box(HARD)))
    });
    c.bench_function("print_hard_instruction", |b| {
        b.iter(|| {
            m2rc_grammar::print_with_comments(black_box(&parsed.program), &parsed.comments, HARD)
        })
    });
    c.bench_function("lex_hard_instruction", |b| {
        b.iter(|| m2rc_grammar::lexer::tokenize(black_box(HARD)))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
