//! `m2rc map import --from nav2`: the hand-drawn house of docs/maps.md on a synthetic
//! `map_server` map, its padding note, the categories outside the vocabulary, and each error of
//! the semantic layer naming its feature.

use crate::common::m2rc;
use serde_json::{Value, json};
use std::path::Path;

/// A 10 x 8 m map at 5 cm (200 x 160 pixels), origin (-1, -2): free inside, a black border,
/// unknown grey in the last 10 columns.
fn write_map(dir: &Path) {
    let (w, h) = (200usize, 160usize);
    let mut pgm = format!("P5\n{w} {h}\n255\n").into_bytes();
    for y in 0..h {
        for x in 0..w {
            let v = if x >= 190 {
                205
            } else if x < 2 || y < 2 || x >= 188 || y >= h - 2 {
                0
            } else {
                254
            };
            pgm.push(v);
        }
    }
    std::fs::write(dir.join("map.pgm"), pgm).unwrap();
    std::fs::write(
        dir.join("map.yaml"),
        "image: map.pgm\nresolution: 0.05\norigin: [-1.0, -2.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
    )
    .unwrap();
}

/// The example of docs/maps.md, "Nav2 import".
fn example() -> Value {
    let doc =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/maps.md"))
            .unwrap();
    let at = doc.find("A small house drawn by hand").unwrap();
    let start = at + doc[at..].find("```json\n").unwrap() + 8;
    let end = start + doc[start..].find("```").unwrap();
    serde_json::from_str(&doc[start..end]).unwrap()
}

fn import(dir: &Path, sem: &Value) -> crate::common::Run {
    std::fs::write(dir.join("sem.geojson"), serde_json::to_vec(sem).unwrap()).unwrap();
    m2rc(
        &[
            "map",
            "import",
            "--from",
            "nav2",
            "map.yaml",
            "--semantics",
            "sem.geojson",
            "-o",
            "map.json",
        ],
        dir,
    )
}

#[test]
fn the_documented_house_imports_and_lists_its_own_categories() {
    let dir = tempfile::tempdir().unwrap();
    write_map(dir.path());
    let r = import(dir.path(), &example()).expect(0);
    assert!(
        r.stderr.contains("padded to a square 200x200 grid"),
        "{}",
        r.stderr
    );
    assert!(r.stderr.contains("kept: lab"), "{}", r.stderr);
    let map: Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("map.json")).unwrap()).unwrap();
    assert_eq!(map["grid_size"], json!(200));
    assert_eq!(
        map["metadata"]["map_frame"]["origin"],
        json!([-1.0, -2.0, 0.0])
    );
    // Image row 0 (the top) is grid row 159; rows 160..199 are padding.
    let occ = &map["layers"]["occupancy"];
    assert_eq!(occ[100][100], json!(0), "free in the middle");
    assert_eq!(occ[199][100], json!(2), "padding is unknown");
    assert_eq!(occ[100][195], json!(2), "grey is unknown");
    assert_eq!(
        occ[100][3],
        json!(1),
        "eroded by the robot radius next to the wall"
    );
    let info = m2rc(&["map", "info", "map.json"], dir.path()).expect(0);
    assert!(
        info.stdout
            .contains("outside the benchmark vocabulary: lab\n"),
        "{}",
        info.stdout
    );
    assert!(info.stdout.contains("kitchen_1"), "{}", info.stdout);
    // A program on it, from a start in metres.
    std::fs::write(
        dir.path().join("p.m2r"),
        "route {\n  go objects(sofa).only()\n}\n",
    )
    .unwrap();
    let r = m2rc(
        &[
            "compile", "p.m2r", "--map", "map.json", "--start", "1.0,1.0", "--emit", "nav-path",
        ],
        dir.path(),
    )
    .expect(0);
    assert!(r.stdout.contains("position: {x: 1.0"), "{}", r.stdout);
}

fn with_feature(f: Value) -> Value {
    let mut sem = example();
    sem["features"].as_array_mut().unwrap().push(f);
    sem
}

#[test]
fn semantic_errors_name_the_feature() {
    let dir = tempfile::tempdir().unwrap();
    write_map(dir.path());
    let outside = with_feature(json!({"type": "Feature",
        "properties": {"kind": "room", "category": "bedroom", "name": "far"},
        "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [20, 0], [20, 1], [0, 0]]]}}));
    let r = import(dir.path(), &outside).expect(2);
    assert!(
        r.stderr.contains("features[6] (`far`)") && r.stderr.contains("outside the image"),
        "{}",
        r.stderr
    );
    let category = with_feature(json!({"type": "Feature",
        "properties": {"kind": "room", "category": "Living Room"},
        "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1], [0, 0]]]}}));
    let r = import(dir.path(), &category).expect(2);
    assert!(
        r.stderr.contains("features[6]")
            && r.stderr.contains("unknown category `Living Room`")
            && r.stderr.contains("`living_room`"),
        "{}",
        r.stderr
    );
    let bowtie = with_feature(json!({"type": "Feature",
        "properties": {"kind": "object", "category": "rug", "name": "bowtie"},
        "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [1, 1], [1, 0], [0, 1], [0, 0]]]}}));
    let r = import(dir.path(), &bowtie).expect(2);
    assert!(
        r.stderr.contains("(`bowtie`)") && r.stderr.contains("self-intersecting"),
        "{}",
        r.stderr
    );
    assert!(
        !dir.path().join("map.json").exists(),
        "a failed import writes nothing"
    );
}

#[test]
fn an_output_over_an_input_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    write_map(dir.path());
    for out in ["map.pgm", "map.yaml"] {
        let r = m2rc(
            &["map", "import", "--from", "nav2", "map.yaml", "-o", out],
            dir.path(),
        )
        .expect(2);
        assert!(r.stderr.contains("is an input"), "{}", r.stderr);
    }
    assert!(
        std::fs::read(dir.path().join("map.pgm"))
            .unwrap()
            .starts_with(b"P5")
    );
}
