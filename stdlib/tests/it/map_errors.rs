//! Malformed houses and maps are errors naming the file and the field, never panics.

use m2rc_stdlib::demo::{DEMO_HOUSE_JSON, demo_map_with};
use m2rc_stdlib::import::{AssetDb, ImportOptions, import_house};
use m2rc_stdlib::map::{read_map_json, read_map_value, write_map_json, write_map_value};
use proptest::prelude::*;
use serde_json::{Value, json};

fn demo_house() -> Value {
    serde_json::from_str(DEMO_HOUSE_JSON).unwrap()
}

fn house_err(v: &Value) -> String {
    import_house(v, "house.json", None, &ImportOptions::default())
        .unwrap_err()
        .to_string()
}

#[test]
fn house_errors_name_file_and_field() {
    let mut h = demo_house();
    h["rooms"][3]["floorPolygon"] = json!([{"x": 0, "z": 0}, {"x": 1, "z": 0}]);
    assert_eq!(
        house_err(&h),
        "house.json: rooms[3].floorPolygon: needs at least 3 points, found 2"
    );

    let mut h = demo_house();
    h["rooms"] = json!([]);
    assert_eq!(house_err(&h), "house.json: rooms: the house has no rooms");

    let mut h = demo_house();
    h.as_object_mut().unwrap().remove("rooms");
    assert_eq!(house_err(&h), "house.json: rooms: missing required key");

    let mut h = demo_house();
    h["objects"][2]["position"]["x"] = json!("left");
    assert!(
        house_err(&h).starts_with("house.json: objects[2].position.x: expected a finite number")
    );

    let mut h = demo_house();
    h["doors"][0]["wall0"] = json!("nowhere");
    assert!(house_err(&h).contains("doors[0].wall0: names no wall"));

    let mut h = demo_house();
    h["objects"][0]["children"][1]
        .as_object_mut()
        .unwrap()
        .remove("assetId");
    assert_eq!(
        house_err(&h),
        "house.json: objects[0].children[1].assetId: missing required key"
    );
}

#[test]
fn unknown_assets_are_errors() {
    let mut h = demo_house();
    let obj = h["objects"][0].as_object_mut().unwrap();
    obj.remove("objectType");
    obj.insert("assetId".into(), json!("Zzyzx_9"));
    assert!(
        house_err(&h)
            .contains("objects[0].assetId: cannot tell the object type of asset \"Zzyzx_9\"")
    );

    let db = AssetDb::from_value(
        &json!({"Sofa": [{"assetId": "Sofa_1", "boundingBox": {"x": 2, "y": 1, "z": 1}}]}),
        "db.json",
    )
    .unwrap();
    let mut h = demo_house();
    h["objects"][0]
        .as_object_mut()
        .unwrap()
        .remove("objectType");
    let e = import_house(&h, "house.json", Some(&db), &ImportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("doors[0].assetId: asset \"Doorway_Demo_1\" is not in the asset database"),
        "{e}"
    );
}

#[test]
fn nan_and_bad_options_are_errors() {
    // JSON has no NaN; Python writes one anyway, and it must be a clean parse error.
    let text = DEMO_HOUSE_JSON.replacen("\"x\":0", "\"x\":NaN", 1);
    assert!(serde_json::from_str::<Value>(&text).is_err());
    let opts = ImportOptions {
        resolution: f64::NAN,
        ..ImportOptions::default()
    };
    assert!(import_house(&demo_house(), "h.json", None, &opts).is_err());
    let opts = ImportOptions {
        robot_radius_m: -1.0,
        ..ImportOptions::default()
    };
    assert!(import_house(&demo_house(), "h.json", None, &opts).is_err());
}

fn small_map() -> Value {
    let opts = ImportOptions {
        resolution: 0.5,
        ..ImportOptions::default()
    };
    write_map_value(&demo_map_with(&opts).unwrap())
}

#[test]
fn map_errors_name_file_and_field() {
    let err = |v: &Value| read_map_value(v, "map.json").unwrap_err().to_string();
    let mut m = small_map();
    m.as_object_mut().unwrap().remove("grid_size");
    assert_eq!(err(&m), "map.json: grid_size: missing required key");

    let mut m = small_map();
    m["layers"]["room"][3] = json!([1, 2]);
    assert!(err(&m).starts_with("map.json: layers.room[3]: has 2 columns"));

    let mut m = small_map();
    m["object_instances"][4]["category"] = json!(7);
    assert_eq!(
        err(&m),
        "map.json: object_instances[4].category: expected a string, found 7"
    );

    let mut m = small_map();
    m["layers"]["occupancy"][0][0] = json!(-1);
    assert!(
        err(&m).starts_with("map.json: layers.occupancy[0][0]: expected a non-negative integer")
    );

    let mut m = small_map();
    m.as_object_mut().unwrap().remove("room_instances");
    assert_eq!(err(&m), "map.json: room_instances: missing required key");

    assert!(
        read_map_json(b"{not json", "bad.json")
            .unwrap_err()
            .to_string()
            .starts_with("bad.json: not valid JSON")
    );
}

#[test]
fn unknown_keys_are_kept() {
    let mut m = small_map();
    m["my_tool"] = json!({"version": 3});
    m["object_instances"][0]["confidence"] = json!(0.5);
    let doc = m2rc_stdlib::map::read_map_document(&m, "map.json").unwrap();
    let out: Value =
        serde_json::from_slice(&m2rc_stdlib::map::write_map_document_json(&doc)).unwrap();
    assert_eq!(out["my_tool"], json!({"version": 3}));
    assert_eq!(out["object_instances"][0]["confidence"], json!(0.5));
    // Without the document wrapper the model still reads.
    let map = read_map_value(&m, "map.json").unwrap();
    assert!(!write_map_json(&map).is_empty());
}

/// A random edit of a JSON document: drop a key, change a value's type, or cut an array.
#[derive(Clone, Debug)]
enum Edit {
    Remove,
    Replace(Value),
    Truncate(usize),
}

fn edit_strategy() -> impl Strategy<Value = Edit> {
    prop_oneof![
        Just(Edit::Remove),
        prop_oneof![
            Just(json!(null)),
            Just(json!("x")),
            Just(json!(-1)),
            Just(json!(1e300)),
            Just(json!(0)),
            Just(json!([])),
            Just(json!({})),
            Just(json!([[0, 0]])),
            Just(json!(4_294_967_296u64)),
        ]
        .prop_map(Edit::Replace),
        (0usize..3).prop_map(Edit::Truncate),
    ]
}

/// Applies `edit` at the node reached by following `path` (indices into whatever containers are
/// met, wrapped around their length).
fn apply(v: &mut Value, path: &[usize], edit: &Edit) {
    let (Some(&step), rest) = (path.first(), &path[1.min(path.len())..]) else {
        if let (Edit::Truncate(k), Value::Array(a)) = (edit, &mut *v) {
            a.truncate(*k);
        } else if let Edit::Replace(r) = edit {
            *v = r.clone();
        }
        return;
    };
    match v {
        Value::Object(o) if !o.is_empty() => {
            let key = o.keys().nth(step % o.len()).unwrap().clone();
            if rest.is_empty() && matches!(edit, Edit::Remove) {
                o.shift_remove(&key);
            } else {
                apply(o.get_mut(&key).unwrap(), rest, edit);
            }
        }
        Value::Array(a) if !a.is_empty() => {
            let i = step % a.len();
            if rest.is_empty() && matches!(edit, Edit::Remove) {
                a.remove(i);
            } else {
                apply(&mut a[i], rest, edit);
            }
        }
        _ => apply(v, &[], edit),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn mutated_houses_never_panic(path in prop::collection::vec(0usize..64, 1..6), edit in edit_strategy()) {
        let mut h = demo_house();
        apply(&mut h, &path, &edit);
        let opts = ImportOptions { resolution: 0.25, ..ImportOptions::default() };
        if let Err(e) = import_house(&h, "house.json", None, &opts) {
            prop_assert!(e.to_string().starts_with("house.json"));
        }
    }

    #[test]
    fn mutated_maps_never_panic(path in prop::collection::vec(0usize..64, 1..6), edit in edit_strategy()) {
        static MAP: std::sync::OnceLock<Value> = std::sync::OnceLock::new();
        let mut m = MAP.get_or_init(small_map).clone();
        apply(&mut m, &path, &edit);
        match read_map_value(&m, "map.json") {
            Ok(map) => {
                // Whatever reads must write and read back.
                let bytes = write_map_json(&map);
                prop_assert!(read_map_json(&bytes, "again.json").is_ok());
            }
            Err(e) => prop_assert!(e.to_string().starts_with("map.json")),
        }
    }
}
