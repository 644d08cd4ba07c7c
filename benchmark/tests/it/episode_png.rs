//! Episode pictures explain their scores: the instruction, every score the report counts, the
//! path-shape reference route nDTW is measured against, and regions named with the map's room
//! names, on a small suite from real houses.

use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::{PreparedMap, method_by_name};
use m2rc_benchmark::report::episode_png::{episode_png, episode_render_options};
use m2rc_benchmark::suite::{ProcthorTools, SuiteConfig, SuiteManifest, build_suite};
use m2rc_stdlib::import::{AssetDb, ImportOptions};
use m2rc_stdlib::render::Overlay;
use std::path::PathBuf;

fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor")
}

/// "room 7" and the like: a room by its number instead of the map's name for it.
fn names_a_room_by_number(text: &str) -> bool {
    text.match_indices("room ").any(|(i, _)| {
        text[i + 5..]
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_digit())
    })
}

#[test]
fn episode_pictures_show_instruction_scores_reference_route_and_room_names() {
    let dir = tempfile::tempdir().unwrap();
    let tools = ProcthorTools {
        assets: Some(AssetDb::load(&shared().join("assets/asset-database.json")).unwrap()),
        import: ImportOptions::default(),
        validators: vec![method_by_name("shortest").unwrap()],
    };
    let config = SuiteConfig {
        name: "pictures".into(),
        scenes: 1,
        dev_scenes: 0,
        episodes_per_scene: 8,
        hard_fraction: 0.5,
        seed: 7,
    };
    let houses = shared().join("houses/procthor10k_uniform_hard_val_150.jsonl.gz");
    build_suite(&houses, &config, &tools, dir.path(), &|_, _| {}).unwrap();
    let manifest = SuiteManifest::read(dir.path()).unwrap();
    let shortest = method_by_name("shortest").unwrap();
    let mut references = 0;
    for entry in &manifest.episodes {
        let episode = Episode::read(&dir.path().join(&entry.file)).unwrap();
        let map_path = manifest.map_path(dir.path(), &entry.map_id).unwrap();
        let map =
            m2rc_stdlib::map::read_map_json(&std::fs::read(&map_path).unwrap(), "map").unwrap();
        let room_names: Vec<String> = map
            .rooms
            .iter()
            .map(m2rc_compiler::eval::room_name)
            .collect();
        let prepared = PreparedMap::new(map.clone());
        let route: Vec<[i64; 2]> = shortest
            .predict(&prepared, &episode)
            .unwrap()
            .trajectory
            .iter()
            .map(|c| [c.row as i64, c.col as i64])
            .collect();
        let opts = episode_render_options(&map, &episode, &route, "shortest");
        let caption = opts.caption.join("\n");
        let instruction = episode.instruction.clone().unwrap();
        assert!(caption.contains(instruction.trim()), "{caption}");
        assert!(
            caption.contains("HCS ")
                && caption.contains("segment-wise SPL ")
                && caption.contains("PL "),
            "{caption}"
        );
        // One caption line per preference, with its score.
        assert_eq!(
            opts.caption.len(),
            2 + episode.soft_constraints.len(),
            "{caption}"
        );
        let mut labels: Vec<String> = Vec::new();
        for o in &opts.overlays {
            match o {
                Overlay::Region { label: Some(l), .. }
                | Overlay::Reference { label: Some(l), .. } => labels.push(l.clone()),
                _ => {}
            }
        }
        for text in labels.iter().chain(&opts.caption) {
            assert!(!names_a_room_by_number(text), "{text}");
        }
        // Every soft region is named after the map's room it lies in.
        for l in labels
            .iter()
            .filter(|l| l.contains(". ") && l.contains(" in "))
        {
            assert!(
                room_names.iter().any(|r| l.ends_with(r.as_str())),
                "{l} names no room of {room_names:?}"
            );
        }
        let shapes = episode
            .soft_constraints
            .iter()
            .filter(|s| s.preference_type.as_deref() == Some("path_shape_preference"))
            .count();
        let drawn = opts
            .overlays
            .iter()
            .filter(|o| matches!(o, Overlay::Reference { cells, .. } if cells.len() > 2))
            .count();
        assert_eq!(drawn, shapes, "one reference route per path shape");
        if shapes > 0 {
            assert!(caption.contains("nDTW "), "{caption}");
            references += 1;
        }
        // And the suite itself names rooms as the map does.
        for s in &episode.soft_constraints {
            let l = s.label.clone().unwrap_or_default();
            assert!(!names_a_room_by_number(&l), "suite label {l}");
        }
        let png = episode_png(&map, &episode, &route, "shortest").unwrap();
        assert!(png.starts_with(b"\x89PNG"));
    }
    assert!(references > 0, "the suite has a path-shape episode to draw");
}
