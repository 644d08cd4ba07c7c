//! Import + rasterize of the largest fixture house, the distance field over its grid, and one
//! exact distance field over a 700 x 700 grid. Targets: import under 100 ms, a 700 x 700 field
//! under 20 ms (release build).
//!
//!     cargo bench -p m2rc-stdlib --bench map_import

use criterion::{Criterion, criterion_group, criterion_main};
use m2rc_stdlib::field::distance_field;
use m2rc_stdlib::grid::Grid;
use m2rc_stdlib::import::{AssetDb, ImportOptions, import_house};
use m2rc_stdlib::load::read_document;
use m2rc_stdlib::map::{FREE, read_map_json, write_map_json};
use std::hint::black_box;
use std::path::PathBuf;

fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor")
}

fn bench(c: &mut Criterion) {
    let db = AssetDb::load(&shared().join("assets/asset-database.json")).ok();
    // The largest fixture: the one with the biggest grid.
    let mut largest = None;
    if let Ok(entries) = std::fs::read_dir(shared().join("fixtures")) {
        let mut paths: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        paths.sort();
        for p in paths {
            let label = p.display().to_string();
            let Ok((house, _, _)) = read_document(&label, None) else {
                continue;
            };
            let Ok(map) = import_house(&house, &label, db.as_ref(), &ImportOptions::default())
            else {
                continue;
            };
            if largest.as_ref().is_none_or(|(_, _, n)| map.n() > *n) {
                largest = Some((label, house, map.n()));
            }
        }
    }
    if let Some((label, house, n)) = largest {
        eprintln!("largest fixture: {label} ({n} x {n} cells at 0.05 m)");
        c.bench_function("import_largest_fixture", |b| {
            b.iter(|| {
                import_house(
                    black_box(&house),
                    &label,
                    db.as_ref(),
                    &ImportOptions::default(),
                )
                .unwrap()
            })
        });
        let map = import_house(&house, &label, db.as_ref(), &ImportOptions::default()).unwrap();
        let blocked = map.occupancy.map(|&v| v != FREE);
        c.bench_function("distance_field_largest_fixture", |b| {
            b.iter(|| distance_field(black_box(&blocked)))
        });
        let bytes = write_map_json(&map);
        c.bench_function("write_map_json_largest_fixture", |b| {
            b.iter(|| write_map_json(black_box(&map)))
        });
        c.bench_function("read_map_json_largest_fixture", |b| {
            b.iter(|| read_map_json(black_box(&bytes), "bench.json").unwrap())
        });
    }
    // 700 x 700 with a scatter of obstacles (deterministic pattern).
    let n = 700;
    let mut g = Grid::new(n, false);
    for (i, v) in g.data_mut().iter_mut().enumerate() {
        *v = (i.wrapping_mul(2_654_435_761) >> 7) % 97 == 0;
    }
    c.bench_function("distance_field_700x700", |b| {
        b.iter(|| distance_field(black_box(&g)))
    });
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20);
    targets = bench
}
criterion_main!(benches);
