//! Rendering speed on the largest fixture house (target: well under 2 s for SVG + PNG in release).
//!
//! `cargo bench -p m2rc-stdlib --bench render`

use criterion::{Criterion, criterion_group, criterion_main};
use m2rc_stdlib::render::{RenderOptions, render_map, render_svg};
use std::hint::black_box;

fn largest_fixture() -> m2rc_stdlib::map::SemanticMap {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../shared/procthor/fixtures/procthor10k_uniform_hard_val_150_149.json"
    );
    m2rc_stdlib::load::load_map(path).expect("fixture house loads")
}

fn bench_render(c: &mut Criterion) {
    let map = largest_fixture();
    let plain = RenderOptions::default();
    let labels = RenderOptions {
        labels: true,
        ..RenderOptions::default()
    };
    let mut g = c.benchmark_group("render_149");
    g.sample_size(10);
    g.bench_function("svg", |b| {
        b.iter(|| render_svg(black_box(&map), &plain).unwrap())
    });
    g.bench_function("svg_png", |b| {
        b.iter(|| render_map(black_box(&map), &plain).unwrap())
    });
    g.bench_function("svg_png_labels", |b| {
        b.iter(|| render_map(black_box(&map), &labels).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench_render);
criterion_main!(benches);
