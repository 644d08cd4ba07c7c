//! A CI-sized suite from the real ProcTHOR houses: two scenes, a handful of episodes, validated by
//! the methods that must score HCS = 1 on their own annotation.

use m2rc_benchmark::episode::Episode;
use m2rc_benchmark::methods::method_by_name;
use m2rc_benchmark::suite::{ProcthorTools, SuiteConfig, SuiteManifest, build_suite};
use m2rc_stdlib::import::{AssetDb, ImportOptions};
use std::path::PathBuf;

fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor")
}

fn tools(validators: &[&str]) -> ProcthorTools {
    ProcthorTools {
        assets: Some(
            AssetDb::load(&shared().join("assets/asset-database.json")).expect("asset database"),
        ),
        import: ImportOptions::default(),
        validators: validators
            .iter()
            .map(|m| method_by_name(m).expect("method"))
            .collect(),
    }
}

fn small_config() -> SuiteConfig {
    SuiteConfig {
        name: "ci".into(),
        scenes: 2,
        dev_scenes: 0,
        episodes_per_scene: 5,
        hard_fraction: 0.4,
        seed: 7,
    }
}

#[test]
fn builds_a_small_suite_from_real_houses() {
    let dir = tempfile::tempdir().unwrap();
    let houses = shared().join("houses/procthor10k_uniform_hard_val_150.jsonl.gz");
    let m = build_suite(
        &houses,
        &small_config(),
        &tools(&["shortest"]),
        dir.path(),
        &|_, _| {},
    )
    .unwrap();
    assert_eq!(m.scenes.len(), 2);
    eprintln!("{}", serde_json::to_string_pretty(&m.scenes).unwrap());
    assert!(m.episodes.len() >= 8, "only {} episodes", m.episodes.len());
    for e in &m.episodes {
        let ep = Episode::read(&dir.path().join(&e.file)).unwrap();
        eprintln!(
            "{} {:?}: {}",
            e.instruction_id,
            e.difficulty,
            ep.instruction.as_deref().unwrap_or("")
        );
        eprintln!("{}", ep.m2rc_gold_program.as_deref().unwrap_or(""));
    }
    let reread = SuiteManifest::read(dir.path()).unwrap();
    assert_eq!(reread, m);
    // The statistics: every paper axis has a row, and nothing a person would never write.
    let stats = m2rc_benchmark::suite::stats::suite_stats(dir.path(), "eval").unwrap();
    assert_eq!(
        stats.vs_paper.len(),
        m2rc_benchmark::suite::paper::AXES.len()
    );
    assert!(stats.vs_paper.iter().all(|r| r.easy.paper > 0.0));
    for split in [&stats.easy, &stats.hard] {
        assert_eq!(split.naturalness.total(), 0, "{:?}", split.naturalness);
    }
    let md = m2rc_benchmark::suite::stats::stats_markdown(&stats);
    assert!(md.contains("| words per instruction |") && md.contains("circular references"));
    assert!(md.contains("| preference subjects named like a destination | 0 | 0 |"));
    // Every mention was read back as written (the counter of underdetermined ones is shown).
    let checked = stats.easy.underdetermined_mentions.total_checked()
        + stats.hard.underdetermined_mentions.total_checked();
    assert!(checked > 0, "no mention checked");
    // ... and none names anything but the gold's object (a circled "the dining table" in a house
    // of three, with no room said, is one).
    for split in [&stats.easy, &stats.hard] {
        let d = &split.underdetermined_mentions;
        assert_eq!(d.total_underdetermined(), 0, "{:?}", d.underdetermined);
    }
    assert!(md.contains("| path-shape subject | 0 |"), "{md}");
    assert!(md.contains("## Underdetermined mentions") && md.contains("| path-shape subject |"));
    // Every scene has walls, which outnumber every other category.
    let head = &stats.uniform_head_candidates;
    assert!(head.without_building_parts >= 1.0, "{head:?}");
    assert!(head.all_objects > head.without_building_parts, "{head:?}");
    // The paper's candidate means scaled by these scenes' object count over its 284.675.
    let [pe, ph] = stats.paper_candidates_at_this_scene_size;
    let scale = stats.objects_per_scene / 284.675;
    assert!(
        (pe - 6.3 * scale).abs() < 0.01 && (ph - 8.45 * scale).abs() < 0.01,
        "{pe} {ph}"
    );
    assert!(md.contains("Scaled to "), "{md}");
}

/// The annotation of what the generator now places: a path-shape preference is measured in an
/// area R that holds its whole closed reference loop (so a route that follows the loop is scored
/// on the loop, not on the walk through the room), and an object-area must-avoid never overlaps a
/// destination's must-pass region or the start region (it forbids a way, never the goal).
#[test]
fn loops_lie_in_their_region_and_object_avoids_spare_the_goals() {
    let dir = tempfile::tempdir().unwrap();
    let houses = shared().join("houses/procthor10k_uniform_hard_val_150.jsonl.gz");
    let config = SuiteConfig {
        episodes_per_scene: 8,
        ..small_config()
    };
    let m = build_suite(
        &houses,
        &config,
        &tools(&["shortest"]),
        dir.path(),
        &|_, _| {},
    )
    .unwrap();
    let cells = |v: &serde_json::Value| -> std::collections::BTreeSet<(i64, i64)> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|c| (c[0].as_i64().unwrap(), c[1].as_i64().unwrap()))
            .collect()
    };
    let (mut loops, mut object_avoids) = (0, 0);
    for e in &m.episodes {
        let text = std::fs::read_to_string(dir.path().join(&e.file)).unwrap();
        let ep: serde_json::Value = serde_json::from_str(&text).unwrap();
        for s in ep["soft_constraints"].as_array().unwrap() {
            if s["preference_type"] != "path_shape_preference" {
                continue;
            }
            loops += 1;
            let ring = s["reference_trajectory"].as_array().unwrap();
            assert!(ring.len() >= 9, "{}: loop of {} cells", e.file, ring.len());
            // A circle is closed; a patrol ends at the doorway it leaves by.
            if s["path_shape_annotation"]["shape_spec"]["type"] == "circle" {
                assert_eq!(ring.first(), ring.last(), "{}: loop not closed", e.file);
            }
            let region = cells(&s["cells"]);
            for c in ring {
                let c = (c[0].as_i64().unwrap(), c[1].as_i64().unwrap());
                assert!(region.contains(&c), "{}: loop cell {c:?} outside R", e.file);
            }
        }
        let program = ep["m2rc_gold_program"].as_str().unwrap();
        let hard = ep["hard_constraints"].as_array().unwrap();
        let passes: Vec<_> = hard
            .iter()
            .filter(|h| h["kind"] == "must_pass")
            .map(|h| cells(&h["cells"]))
            .collect();
        for h in hard.iter().filter(|h| h["kind"] == "must_avoid") {
            let area = cells(&h["cells"]);
            if passes.iter().any(|p| !p.is_disjoint(&area)) {
                // Only a room avoid may meet a must-pass region (never: the generator keeps
                // destinations and the start out of avoided rooms), so this is a failure.
                panic!(
                    "{}: must-avoid {} overlaps a must-pass region",
                    e.file, h["label"]
                );
            }
        }
        object_avoids += program.matches("avoid area_").count();
    }
    eprintln!("{loops} loops, {object_avoids} object-area avoids");
    assert!(
        loops > 0 && object_avoids > 0,
        "{loops} loops, {object_avoids} object-area avoids"
    );
}

/// Destinations that are not objects: "the other one" of a pair, a doorway between two rooms and
/// the way back to the start. Each is validated like any episode (the oracle compiles and plans
/// the gold program and must score HCS = 1), and its must-pass region is what the program says:
/// the way back ends in the start region, a doorway is the passage's cells.
#[test]
fn other_ones_doorways_and_returns_are_annotated_as_their_programs_say() {
    let dir = tempfile::tempdir().unwrap();
    let houses = shared().join("houses/procthor10k_uniform_hard_val_150.jsonl.gz");
    let config = SuiteConfig {
        scenes: 3,
        episodes_per_scene: 12,
        hard_fraction: 0.6,
        ..small_config()
    };
    let m = build_suite(
        &houses,
        &config,
        &tools(&["oracle", "shortest"]),
        dir.path(),
        &|_, _| {},
    )
    .unwrap();
    let (mut others, mut doorways, mut returns, mut windows) = (0, 0, 0, 0);
    for e in &m.episodes {
        let text = std::fs::read_to_string(dir.path().join(&e.file)).unwrap();
        let ep: serde_json::Value = serde_json::from_str(&text).unwrap();
        let program = ep["m2rc_gold_program"].as_str().unwrap();
        let hard = ep["hard_constraints"].as_array().unwrap();
        let passes: Vec<&serde_json::Value> =
            hard.iter().filter(|h| h["kind"] == "must_pass").collect();
        others += program.matches(".except(t").count();
        // "The other one" is said right after the sentence that sends the robot to its pair's
        // first member, never after a preference that would become its antecedent.
        let clauses = ep["m2rc_generation"]["clauses"].as_array().unwrap();
        for w in clauses.windows(2) {
            if w[1]["text"].as_str().unwrap().contains("the other one") {
                let before = w[0]["program"].as_str().unwrap();
                assert!(before.starts_with("go t"), "{}: after {before:?}", e.file);
            }
        }
        doorways += program.matches("doorways_between(").count();
        // A window destination is a must-pass region like any object's, and it was validated.
        windows += program.matches("= objects(window)").count();
        if program.contains("\n  go start") {
            returns += 1;
            let last = passes.last().unwrap();
            assert_eq!(last["cells"], passes[0]["cells"], "{}", e.file);
            let said = ep["instruction"].as_str().unwrap();
            assert!(
                said.contains("start") || said.contains("began"),
                "{}: {said}",
                e.file
            );
        }
    }
    eprintln!("{others} other-ones, {doorways} doorways, {returns} returns, {windows} windows");
    assert!(
        windows > 0,
        "no window destination in {} episodes",
        m.episodes.len()
    );
    assert!(
        others + doorways + returns > 0,
        "{others} other-ones, {doorways} doorways, {returns} returns"
    );
}

/// Same houses, same config, same bytes: every file of two builds into different directories is
/// identical (no clock, no hash-map order, no output path leaks into a suite).
#[test]
fn a_suite_built_twice_is_the_same_bytes() {
    let houses = shared().join("houses/procthor10k_uniform_hard_val_150.jsonl.gz");
    let config = SuiteConfig {
        scenes: 1,
        episodes_per_scene: 4,
        ..small_config()
    };
    let dirs = [tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap()];
    for d in &dirs {
        build_suite(&houses, &config, &tools(&[]), d.path(), &|_, _| {}).unwrap();
    }
    let files = |root: &std::path::Path| {
        let mut out = std::collections::BTreeMap::new();
        let mut stack = vec![root.to_path_buf()];
        while let Some(dir) = stack.pop() {
            for entry in std::fs::read_dir(&dir).unwrap() {
                let path = entry.unwrap().path();
                if path.is_dir() {
                    stack.push(path);
                } else {
                    let rel = path.strip_prefix(root).unwrap().to_path_buf();
                    out.insert(rel, std::fs::read(&path).unwrap());
                }
            }
        }
        out
    };
    let (a, b) = (files(dirs[0].path()), files(dirs[1].path()));
    assert!(a.len() > 4, "only {} files", a.len());
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    for (path, bytes) in &a {
        assert!(
            bytes == &b[path],
            "{} differs between two builds",
            path.display()
        );
    }
}
