//! ProcTHOR import over the real houses in `../shared/procthor/`: room counts, every object and
//! child present with its parent, and byte-identical write -> read -> write.

use m2rc_stdlib::import::check::check_house as validate;
use m2rc_stdlib::import::{AssetDb, ImportOptions, import_house_document, import_warnings};
use m2rc_stdlib::load::{count_documents, read_document};
use m2rc_stdlib::map::{MapDocument, Relation, read_map_document_json, write_map_document_json};
use serde_json::Value;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::OnceLock;

fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/procthor")
}

fn assets() -> Option<&'static AssetDb> {
    static DB: OnceLock<Option<AssetDb>> = OnceLock::new();
    DB.get_or_init(|| AssetDb::load(&shared().join("assets/asset-database.json")).ok())
        .as_ref()
}

const SETS: [&str; 3] = [
    "procthor10k_uniform_hard_val_150.jsonl.gz",
    "attr_onav_one_room_train_500.jsonl.gz",
    "attr_onav_one_room_val_100.jsonl.gz",
];

/// Every object id of the house (children included) with its parent's id.
fn house_objects(house: &Value) -> Vec<(String, Option<String>)> {
    fn walk(list: &Value, parent: Option<&str>, out: &mut Vec<(String, Option<String>)>) {
        for o in list.as_array().into_iter().flatten() {
            let id = o["id"].as_str().unwrap().to_string();
            out.push((id.clone(), parent.map(str::to_string)));
            walk(&o["children"], Some(&id), out);
        }
    }
    let mut out = Vec::new();
    walk(&house["objects"], None, &mut out);
    out
}

fn attr<'a>(attrs: &'a [String], key: &str) -> Option<&'a str> {
    attrs
        .iter()
        .find_map(|a| a.strip_prefix(key).and_then(|r| r.strip_prefix('=')))
}

/// Imports one house and checks it against its source.
fn check_house(house: &Value, label: &str) -> MapDocument {
    let doc = import_house_document(house, label, assets(), &ImportOptions::default())
        .unwrap_or_else(|e| panic!("{label}: {e}"));
    let map = &doc.map;
    assert_eq!(
        map.rooms.len(),
        house["rooms"].as_array().unwrap().len(),
        "{label}: room count"
    );
    let by_source: HashMap<&str, &m2rc_stdlib::map::Object> = map
        .objects
        .iter()
        .filter_map(|o| attr(&o.attributes, "procthor_object_id").map(|id| (id, o)))
        .collect();
    for (id, parent) in house_objects(house) {
        let o = by_source
            .get(id.as_str())
            .unwrap_or_else(|| panic!("{label}: object {id} missing"));
        assert!(!o.footprint.is_empty(), "{label}: {id} has no cells");
        match parent {
            None => assert!(o.parent.is_none(), "{label}: {id} should have no parent"),
            Some(p) => {
                let pid = by_source[p.as_str()].id;
                assert_eq!(o.parent.map(|x| x.id), Some(pid), "{label}: parent of {id}");
            }
        }
    }
    let doors = house["doors"].as_array().map_or(0, Vec::len);
    let windows = house["windows"].as_array().map_or(0, Vec::len);
    let count = |c: &str| map.objects.iter().filter(|o| o.category == c).count();
    assert_eq!(
        count("doorway") + count("doorframe"),
        doors,
        "{label}: doors"
    );
    assert_eq!(count("window"), windows, "{label}: windows");
    assert!(count("wall") >= 4, "{label}: walls");
    // Every room has some free space, and the occupancy is binary.
    assert!(map.occupancy.data().iter().all(|&v| v <= 1));
    for r in &map.rooms {
        assert!(
            map.room_cells(r.id).iter().any(|&c| map.is_free(c)) || r.area_m2 < 2.0,
            "{label}: room {} has no free cell",
            r.id
        );
    }
    // The map matches the house: holes where ProcTHOR cuts them and clear of walls, every
    // connected room reachable from the start, no leak between rooms the house keeps apart.
    let report = validate(house, label, map).unwrap();
    assert_eq!(
        report.holes,
        doors + windows,
        "{label}: every hole is checked"
    );
    assert!(report.is_clean(), "{label}: {:#?}", report.warnings(map));
    assert!(
        import_warnings(&doc).is_empty(),
        "{label}: {:?}",
        import_warnings(&doc)
    );
    // Open walls are open boundaries, each joining two rooms that a passage connects.
    let empty_walls = house["walls"]
        .as_array()
        .map_or(0, |w| w.iter().filter(|w| w["empty"] == true).count());
    assert_eq!(
        empty_walls > 0,
        !map.open_boundaries.is_empty(),
        "{label}: open boundaries"
    );
    doc
}

fn round_trip(doc: &MapDocument, label: &str) {
    let first = write_map_document_json(doc);
    let back = read_map_document_json(&first, label).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back.map, doc.map, "{label}: read back differs");
    let second = write_map_document_json(&back);
    assert!(
        first == second,
        "{label}: write -> read -> write is not byte-identical"
    );
}

#[test]
fn fixture_houses_import_and_round_trip() {
    let dir = shared().join("fixtures");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).collect();
    paths.sort();
    let mut n = 0;
    for path in paths {
        let label = path.display().to_string();
        let (house, _, _) = read_document(&label, None).unwrap();
        let doc = check_house(&house, &label);
        // Relations: receptacle contents are inside, the rest on.
        assert!(
            doc.map
                .objects
                .iter()
                .any(|o| o.parent.is_some_and(|p| p.relation == Relation::On))
        );
        // Writing a 600 x 600 map is a few MB of JSON; one large round trip is enough here.
        if n == 0 {
            round_trip(&doc, &label);
        }
        n += 1;
    }
    assert_eq!(n, 5);
}

/// A spread of houses from all three sets (every 37th house); the full set is `all_houses_import`.
#[test]
fn sample_of_houses_imports() {
    for set in SETS {
        let path = shared().join("houses").join(set).display().to_string();
        let Ok(total) = count_documents(&path) else {
            return;
        };
        for i in (0..total).step_by(37) {
            let (house, label, _) = read_document(&path, Some(i)).unwrap();
            let doc = check_house(&house, &label);
            if i == 0 {
                round_trip(&doc, &label);
            }
        }
    }
}

#[test]
#[ignore = "imports all 750 houses (about a minute in debug builds); run with --ignored"]
fn all_houses_import() {
    let mut n = 0;
    for set in SETS {
        let path = shared().join("houses").join(set).display().to_string();
        let total = count_documents(&path).unwrap();
        for i in 0..total {
            let (house, label, _) = read_document(&path, Some(i)).unwrap();
            check_house(&house, &label);
            n += 1;
        }
    }
    assert_eq!(n, 750);
}

#[test]
fn builtin_sizes_import_without_the_database() {
    let path = shared().join("houses").join(SETS[0]).display().to_string();
    let Ok((house, label, _)) = read_document(&path, Some(3)) else {
        return;
    };
    let with_db =
        import_house_document(&house, &label, assets(), &ImportOptions::default()).unwrap();
    let without = import_house_document(&house, &label, None, &ImportOptions::default()).unwrap();
    assert_eq!(with_db.map.rooms, without.map.rooms);
    let cats = |d: &MapDocument| {
        d.map
            .objects
            .iter()
            .map(|o| o.category.clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(cats(&with_db), cats(&without));
}
