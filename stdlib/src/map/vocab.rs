//! The benchmark's category vocabulary: the 97 object categories and 4 room categories that occur in
//! the Map2Route evaluation scenes. Grounding and suite generation use it to tell benchmark
//! categories from extra ones an importer may produce (`coffee_table`, `towel`, ...).

/// The 97 object categories of the Map2Route evaluation split, sorted. Includes the structural
/// categories `doorframe`, `doorway`, `wall` and `window`.
pub const OBJECT_CATEGORIES: [&str; 97] = [
    "alarm_clock",
    "apple",
    "arm_chair",
    "baseball_bat",
    "basket_ball",
    "bed",
    "book",
    "boots",
    "bottle",
    "bowl",
    "box",
    "bread",
    "butter_knife",
    "cabinet",
    "candle",
    "cart",
    "cd",
    "cell_phone",
    "chair",
    "cloth",
    "clothes_dryer",
    "coffee_machine",
    "counter_top",
    "credit_card",
    "cup",
    "desk",
    "desk_lamp",
    "dining_table",
    "dish_sponge",
    "dog_bed",
    "doorframe",
    "doorway",
    "drawer",
    "dresser",
    "dumbbell",
    "egg",
    "faucet",
    "floor_lamp",
    "fork",
    "fridge",
    "garbage_bag",
    "garbage_can",
    "house_plant",
    "kettle",
    "key_chain",
    "knife",
    "ladle",
    "laptop",
    "laundry_hamper",
    "lettuce",
    "microwave",
    "mug",
    "newspaper",
    "ottoman",
    "painting",
    "pan",
    "paper_towel_roll",
    "pen",
    "pencil",
    "pepper_shaker",
    "pillow",
    "plate",
    "plunger",
    "pot",
    "potato",
    "remote_control",
    "safe",
    "salt_shaker",
    "shelf",
    "side_table",
    "sink",
    "sink_basin",
    "soap_bar",
    "soap_bottle",
    "sofa",
    "spatula",
    "spoon",
    "spray_bottle",
    "statue",
    "stool",
    "table_top_decor",
    "teddy_bear",
    "television",
    "tennis_racket",
    "tissue_box",
    "toaster",
    "toilet",
    "toilet_paper",
    "tomato",
    "tv_stand",
    "vacuum_cleaner",
    "vase",
    "wall",
    "washing_machine",
    "watch",
    "window",
    "wine_bottle",
];

/// The 4 room categories.
pub const ROOM_CATEGORIES: [&str; 4] = ["bathroom", "bedroom", "kitchen", "living_room"];

/// Categories that are building structure rather than furniture or items.
pub const STRUCTURE_CATEGORIES: [&str; 4] = ["doorframe", "doorway", "wall", "window"];

/// Categories a robot may pass through (the reference's clearance exemption).
pub const TRAVERSABLE_CATEGORIES: [&str; 2] = ["doorframe", "doorway"];

pub fn is_benchmark_object_category(category: &str) -> bool {
    OBJECT_CATEGORIES.binary_search(&category).is_ok()
}

pub fn is_room_category(category: &str) -> bool {
    ROOM_CATEGORIES.contains(&category)
}

pub fn is_structure(category: &str) -> bool {
    STRUCTURE_CATEGORIES.contains(&category)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn object_categories_are_sorted_and_unique() {
        assert!(OBJECT_CATEGORIES.windows(2).all(|w| w[0] < w[1]));
        assert!(is_benchmark_object_category("tv_stand"));
        assert!(!is_benchmark_object_category("coffee_table"));
    }

    #[test]
    fn matches_the_reference_statistics() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../shared/reference/map2route-evaluation-statistics.json"
        );
        let Ok(text) = std::fs::read_to_string(path) else {
            return; // the shared folder is optional on a fresh machine
        };
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let objs: Vec<&str> = v["object_categories"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_str().unwrap())
            .collect();
        assert_eq!(objs, OBJECT_CATEGORIES.to_vec());
        let rooms: Vec<&str> = v["room_categories"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_str().unwrap())
            .collect();
        assert_eq!(rooms, ROOM_CATEGORIES.to_vec());
    }
}
