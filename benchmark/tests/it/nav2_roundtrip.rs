//! A Nav2 map of a real building: fixture houses written as a `map_server` PGM + YAML and their
//! rooms and objects as GeoJSON (`export::nav2`), imported back with `import::nav2`, give the
//! same traversability, the same rooms and footprints, and the same routes for the suite's gold
//! programs from the same starts.

use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{PreparedMap, method_by_name, start_cell};
use m2rc_benchmark::pipeline::{PipelineOptions, compile_and_plan_with};
use m2rc_benchmark::suite::{ProcthorTools, SuiteConfig, SuiteManifest, build_suite};
use m2rc_stdlib::export::nav2::to_nav2;
use m2rc_stdlib::import::nav2::{Nav2Options, import_nav2};
use m2rc_stdlib::import::{AssetDb, ImportOptions};
use m2rc_stdlib::map::frame::MapFrame;
use std::path::PathBuf;

fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor")
}

#[test]
fn a_house_written_as_a_nav2_map_imports_back_to_the_same_routes() {
    if !shared().join("fixtures").exists() {
        eprintln!("fixture houses not found beside the repository; skipping");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let tools = ProcthorTools {
        assets: Some(AssetDb::load(&shared().join("assets/asset-database.json")).unwrap()),
        import: ImportOptions::default(),
        validators: vec![method_by_name("shortest").unwrap()],
    };
    let config = SuiteConfig {
        name: "nav2-roundtrip".into(),
        scenes: 2,
        dev_scenes: 0,
        episodes_per_scene: 5,
        hard_fraction: 0.5,
        seed: 5,
    };
    let suite = dir.path().join("suite");
    let manifest: SuiteManifest = build_suite(
        &shared().join("fixtures"),
        &config,
        &tools,
        &suite,
        &|_, _| {},
    )
    .unwrap();
    let mut compared = 0;
    for scene in &manifest.scenes {
        let path = manifest.map_path(&suite, &scene.map_id).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let house = m2rc_stdlib::map::read_map_json(&bytes, "map").unwrap();
        let frame = MapFrame::from_grid(&house);
        let files = to_nav2(&house, &frame, "map.pgm");
        let out = dir.path().join(&scene.map_id);
        std::fs::create_dir_all(&out).unwrap();
        std::fs::write(out.join("map.pgm"), &files.pgm).unwrap();
        std::fs::write(out.join("map.yaml"), &files.yaml).unwrap();
        let sem = out.join("semantics.geojson");
        std::fs::write(&sem, serde_json::to_vec(&files.geojson).unwrap()).unwrap();
        // The grid is already eroded: import it as it is.
        let opts = Nav2Options {
            robot_radius_m: 0.0,
            ..Nav2Options::default()
        };
        let (doc, _) = import_nav2(&out.join("map.yaml"), Some(&sem), &opts).unwrap();
        let nav = doc.map;
        // Compared cell by cell, counting, so a failure does not print whole grids.
        let differ = |a: &[u32], b: &[u32]| a.iter().zip(b).filter(|(x, y)| x != y).count();
        let occ = |m: &m2rc_stdlib::map::SemanticMap| -> Vec<u32> {
            m.occupancy.data().iter().map(|&v| v as u32).collect()
        };
        assert_eq!(nav.n(), house.n());
        let id = &scene.map_id;
        assert_eq!(differ(&occ(&nav), &occ(&house)), 0, "{id}: traversability");
        let rooms = differ(nav.room_layer.data(), house.room_layer.data());
        assert_eq!(rooms, 0, "{id}: rooms");
        let objects = differ(nav.object_layer.data(), house.object_layer.data());
        assert_eq!(objects, 0, "{id}: object layer");
        assert_eq!(nav.rooms.len(), house.rooms.len());
        for (a, b) in nav.rooms.iter().zip(&house.rooms) {
            assert_eq!((&a.name, &a.category), (&b.name, &b.category));
        }
        assert_eq!(nav.objects.len(), house.objects.len());
        let nav_frame = MapFrame::of(&nav, Some(&doc.extra)).unwrap();
        for c in [house.start.unwrap(), m2rc_stdlib::grid::Cell::new(3, 7)] {
            assert_eq!(nav_frame.cell_to_map(c), frame.cell_to_map(c));
        }
        let by_name = |m: &m2rc_stdlib::map::SemanticMap, name: &str| {
            m.objects
                .iter()
                .find(|o| o.name == name)
                .map(|o| o.footprint.clone())
        };
        for o in &house.objects {
            assert_eq!(
                by_name(&nav, &o.name),
                Some(o.footprint.clone()),
                "{}",
                o.name
            );
        }
        let a = PreparedMap::new(house);
        let b = PreparedMap::new(nav);
        for entry in manifest
            .episodes
            .iter()
            .filter(|e| e.map_id == scene.map_id)
        {
            let episode = Episode::read(&suite.join(&entry.file)).unwrap();
            let Some(gold) = episode.m2rc_gold_program.as_deref() else {
                continue;
            };
            let start = start_cell(&a.map, &episode).unwrap();
            let opts = PipelineOptions {
                start: Some(start),
                ..PipelineOptions::default()
            };
            let ra = compile_and_plan_with(gold, &a.map, a.planning().unwrap(), &opts);
            let rb = compile_and_plan_with(gold, &b.map, b.planning().unwrap(), &opts);
            match (ra, rb) {
                (Ok(ra), Ok(rb)) => {
                    assert_eq!(
                        ra.route.trajectory, rb.route.trajectory,
                        "{}: the route differs on the Nav2 map",
                        entry.file
                    );
                    compared += 1;
                }
                (Err(_), Err(_)) => {}
                (ra, rb) => panic!(
                    "{}: plans on one map only (house ok: {}, nav2 ok: {})",
                    entry.file,
                    ra.is_ok(),
                    rb.is_ok()
                ),
            }
        }
    }
    eprintln!("same routes for {compared} gold programs");
    assert!(compared >= 5, "only {compared} gold programs planned");
}
