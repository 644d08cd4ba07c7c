//! The generator's vocabulary: the everyday names people use for each category ("couch",
//! "nightstand", "trash can", "TV", "the plant"), plurals and number words.
//!
//! Every name here maps back to exactly one category of the gold program, so an instruction
//! never says more (or less) than the program it was realised from. The first entry of a
//! paraphrase list is the plain name; the others are drawn by the episode's seeded RNG.

use rand::Rng;
use rand::seq::IndexedRandom;
use rand_chacha::ChaCha8Rng;

/// Everyday names of a category, plain name first. Categories not listed are named by their
/// snake_case name with spaces.
const PARAPHRASES: &[(&str, &[&str])] = &[
    ("sofa", &["sofa", "couch"]),
    ("side_table", &["side table", "nightstand", "end table"]),
    ("garbage_can", &["trash can", "garbage can", "bin"]),
    ("television", &["TV", "television"]),
    ("tv_stand", &["TV stand", "TV cabinet"]),
    ("house_plant", &["houseplant", "plant", "potted plant"]),
    ("arm_chair", &["armchair", "easy chair"]),
    ("counter_top", &["countertop", "counter"]),
    ("fridge", &["fridge", "refrigerator"]),
    ("dining_table", &["dining table"]),
    ("coffee_table", &["coffee table"]),
    ("floor_lamp", &["floor lamp", "standing lamp"]),
    ("desk_lamp", &["desk lamp"]),
    ("laundry_hamper", &["laundry hamper", "laundry basket"]),
    ("shelving_unit", &["shelving unit", "bookshelf"]),
    ("shelf", &["shelf", "shelving unit"]),
    ("dresser", &["dresser", "chest of drawers"]),
    ("cd", &["CD"]),
    ("remote_control", &["remote control", "remote"]),
    ("cell_phone", &["cell phone", "phone"]),
    ("living_room", &["living room", "lounge"]),
    ("bathroom", &["bathroom", "washroom"]),
    ("bedroom", &["bedroom"]),
    ("kitchen", &["kitchen"]),
    ("window", &["window"]),
];

fn names(cat: &str) -> Option<&'static [&'static str]> {
    PARAPHRASES.iter().find(|(c, _)| *c == cat).map(|(_, n)| *n)
}

/// The plain name of a category.
pub fn plain(cat: &str) -> String {
    match names(cat) {
        Some(n) => n[0].to_string(),
        None => cat.replace('_', " "),
    }
}

/// A name for a category: the plain one most of the time, a paraphrase otherwise.
pub fn noun(cat: &str, rng: &mut ChaCha8Rng) -> String {
    match names(cat) {
        Some(n) if n.len() > 1 && rng.random_bool(0.45) => {
            n[1..].choose(rng).copied().unwrap_or(n[0]).to_string()
        }
        Some(n) => n[0].to_string(),
        None => cat.replace('_', " "),
    }
}

/// The plural of a (plain) name.
pub fn plural(name: &str) -> String {
    let (head, tail) = match name.split_once(' ') {
        // "chest of drawers" -> "chests of drawers"
        Some((h, t)) if t.starts_with("of ") => (h.to_string(), format!(" {t}")),
        _ => (name.to_string(), String::new()),
    };
    let p = if head.ends_with("ch")
        || head.ends_with("sh")
        || head.ends_with('s')
        || head.ends_with('x')
    {
        format!("{head}es")
    } else if head.ends_with('y') && !head.ends_with("ey") && !head.ends_with("ay") {
        format!("{}ies", &head[..head.len() - 1])
    } else {
        format!("{head}s")
    };
    format!("{p}{tail}")
}

/// "two", "three", ... for small counts.
pub fn number_word(n: usize) -> String {
    match n {
        1 => "one".into(),
        2 => "two".into(),
        3 => "three".into(),
        4 => "four".into(),
        5 => "five".into(),
        6 => "six".into(),
        other => other.to_string(),
    }
}

/// "a" or "an".
pub fn article(word: &str) -> &'static str {
    match word.chars().next() {
        Some(c) if "aeiouAEIOU".contains(c) => "an",
        _ => "a",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn plurals_and_paraphrases() {
        assert_eq!(plural("window"), "windows");
        assert_eq!(plural("box"), "boxes");
        assert_eq!(plural("chest of drawers"), "chests of drawers");
        assert_eq!(plural("TV"), "TVs");
        assert_eq!(plain("garbage_can"), "trash can");
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let seen: std::collections::BTreeSet<String> =
            (0..50).map(|_| noun("sofa", &mut rng)).collect();
        assert!(seen.contains("couch") && seen.contains("sofa"), "{seen:?}");
    }
}
