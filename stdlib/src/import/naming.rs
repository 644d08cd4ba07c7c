//! Category names: ProcTHOR `objectType` / `roomType` in CamelCase to Map2Route snake_case, and the
//! object type of an asset when no asset database is at hand.

/// `ArmChair` -> `arm_chair`, `TVStand` -> `tv_stand`, `CD` -> `cd`, with the reference's one
/// rename `ShelvingUnit` -> `shelf`.
pub fn category_snake(object_type: &str) -> String {
    let chars: Vec<char> = object_type.chars().collect();
    let mut out = String::with_capacity(chars.len() + 4);
    for (i, &ch) in chars.iter().enumerate() {
        if ch.is_uppercase() && i > 0 {
            let prev = chars[i - 1];
            let next_lower = chars.get(i + 1).is_some_and(|c| c.is_lowercase());
            if prev.is_lowercase() || prev.is_ascii_digit() || (prev.is_uppercase() && next_lower) {
                out.push('_');
            }
        }
        if ch == ' ' || ch == '-' {
            out.push('_');
        } else {
            out.extend(ch.to_lowercase());
        }
    }
    let out = out.replace("__", "_");
    if out == "shelving_unit" {
        "shelf".to_string()
    } else {
        out
    }
}

/// Keywords of ProcTHOR asset ids (lower case, underscores removed) and the object type they
/// name. Asset ids start with their type, so the keyword found earliest wins, and among those the
/// longest: `desklamp` over `desk`, `toiletpaperhanger` over `toiletpaper` over `toilet`.
const ASSET_KEYWORDS: &[(&str, &str)] = &[
    ("alarmclock", "AlarmClock"),
    ("aluminumfoil", "AluminumFoil"),
    ("apple", "Apple"),
    ("armchair", "ArmChair"),
    ("baseballbat", "BaseballBat"),
    ("basketball", "BasketBall"),
    ("bathtowelholder", "TowelHolder"),
    ("bathtowel", "Towel"),
    ("faucet", "Faucet"),
    ("daybed", "Bed"),
    ("dogbed", "DogBed"),
    ("bed", "Bed"),
    ("blinds", "Blinds"),
    ("book", "Book"),
    ("boot", "Boots"),
    ("bottle", "Bottle"),
    ("bowl", "Bowl"),
    ("decorativebox", "Box"),
    ("box", "Box"),
    ("bread", "Bread"),
    ("butterknife", "ButterKnife"),
    ("cd", "CD"),
    ("candle", "Candle"),
    ("cart", "Cart"),
    ("cellphone", "CellPhone"),
    ("officechair", "Chair"),
    ("chair", "Chair"),
    ("cloth", "Cloth"),
    ("clothesdryer", "ClothesDryer"),
    ("coffeemachine", "CoffeeMachine"),
    ("coffeetable", "CoffeeTable"),
    ("countertop", "CounterTop"),
    ("creditcard", "CreditCard"),
    ("cup", "Cup"),
    ("desklamp", "DeskLamp"),
    ("desktop", "Desktop"),
    ("desk", "Desk"),
    ("diningtable", "DiningTable"),
    ("dishsponge", "DishSponge"),
    ("doorframe", "Doorframe"),
    ("doorway", "Doorway"),
    ("dresser", "Dresser"),
    ("dumbbell", "Dumbbell"),
    ("egg", "Egg"),
    ("floorlamp", "FloorLamp"),
    ("footstool", "Footstool"),
    ("fork", "Fork"),
    ("fridge", "Fridge"),
    ("garbagebag", "GarbageBag"),
    ("garbagebin", "GarbageCan"),
    ("garbagecan", "GarbageCan"),
    ("bin", "GarbageCan"),
    ("handtowelholder", "HandTowelHolder"),
    ("handtowel", "HandTowel"),
    ("houseplant", "HousePlant"),
    ("kettle", "Kettle"),
    ("keychain", "KeyChain"),
    ("knife", "Knife"),
    ("ladle", "Ladle"),
    ("laptop", "Laptop"),
    ("laundryhamper", "LaundryHamper"),
    ("lettuce", "Lettuce"),
    ("lightswitch", "LightSwitch"),
    ("microwave", "Microwave"),
    ("mug", "Mug"),
    ("newspaper", "Newspaper"),
    ("ottoman", "Ottoman"),
    ("walldecorpainting", "Painting"),
    ("walldecorphoto", "Painting"),
    ("painting", "Painting"),
    ("pan", "Pan"),
    ("papertowel", "PaperTowelRoll"),
    ("pencil", "Pencil"),
    ("pen", "Pen"),
    ("saltpeppershakerbnydpepper", "PepperShaker"),
    ("saltpeppershakerbnydsalt", "SaltShaker"),
    ("peppershaker", "PepperShaker"),
    ("saltshaker", "SaltShaker"),
    ("pillow", "Pillow"),
    ("plate", "Plate"),
    ("plunger", "Plunger"),
    ("pot", "Pot"),
    ("potato", "Potato"),
    ("remote", "RemoteControl"),
    ("roomdecor", "RoomDecor"),
    ("safe", "Safe"),
    ("scrubbrush", "ScrubBrush"),
    ("shelvingunit", "ShelvingUnit"),
    ("showercurtain", "ShowerCurtain"),
    ("showerhead", "ShowerHead"),
    ("sidetable", "SideTable"),
    ("sink", "Sink"),
    ("soapbar", "SoapBar"),
    ("soapbottle", "SoapBottle"),
    ("sofa", "Sofa"),
    ("spatula", "Spatula"),
    ("spoon", "Spoon"),
    ("spraybottle", "SprayBottle"),
    ("statue", "Statue"),
    ("stool", "Stool"),
    ("tvstand", "TVStand"),
    ("tabletopdecor", "TableTopDecor"),
    ("teddybear", "TeddyBear"),
    ("television", "Television"),
    ("tennisracquet", "TennisRacket"),
    ("tennisracket", "TennisRacket"),
    ("tissuebox", "TissueBox"),
    ("toaster", "Toaster"),
    ("toiletpaperhanger", "ToiletPaperHanger"),
    ("toiletpaper", "ToiletPaper"),
    ("toilet", "Toilet"),
    ("tomato", "Tomato"),
    ("vacuumcleaner", "VacuumCleaner"),
    ("vase", "Vase"),
    ("washingmachine", "WashingMachine"),
    ("watch", "Watch"),
    ("wateringcan", "WateringCan"),
    ("window", "Window"),
    ("winebottle", "WineBottle"),
];

/// The object type an asset id names, by keyword (`Dining_Table_230_1` -> `DiningTable`,
/// `RoboTHOR_office_chair_jules` -> `Chair`); `None` when no keyword matches.
///
pub fn object_type_from_asset_id(asset_id: &str) -> Option<&'static str> {
    let key: String = asset_id
        .chars()
        .filter(|c| c.is_alphanumeric())
        .flat_map(char::to_lowercase)
        .collect();
    let key = key.strip_prefix("robothor").unwrap_or(&key);
    let mut best: Option<((isize, usize), &'static str)> = None;
    for &(kw, ty) in ASSET_KEYWORDS {
        let Some(pos) = key.find(kw) else { continue };
        let rank = (-(pos as isize), kw.len());
        if best.is_none_or(|(r, _)| rank > r) {
            best = Some((rank, ty));
        }
    }
    best.map(|b| b.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snake_case_matches_map2route_names() {
        for (t, want) in [
            ("ArmChair", "arm_chair"),
            ("TVStand", "tv_stand"),
            ("CD", "cd"),
            ("CounterTop", "counter_top"),
            ("HousePlant", "house_plant"),
            ("ShelvingUnit", "shelf"),
            ("LivingRoom", "living_room"),
            ("Television", "television"),
            ("BasketBall", "basket_ball"),
            ("PaperTowelRoll", "paper_towel_roll"),
        ] {
            assert_eq!(category_snake(t), want);
        }
    }

    #[test]
    fn asset_ids_name_their_types() {
        for (a, want) in [
            ("Dining_Table_230_1", "DiningTable"),
            ("Houseplant_9", "HousePlant"),
            ("RoboTHOR_office_chair_jules", "Chair"),
            ("Dog_Statue_1", "Statue"),
            ("Dog_Bed_3", "DogBed"),
            ("Desk_Lamp_2", "DeskLamp"),
            ("Toilet_Paper_Used_Up_1", "ToiletPaper"),
            ("RoboTHOR_salt_pepper_shaker_bnyd_salt_v", "SaltShaker"),
            ("Wall_Decor_Photo_3V", "Painting"),
            ("bin_12", "GarbageCan"),
            ("Doorway_Double_10", "Doorway"),
            ("Window_Slider_48x24", "Window"),
            ("Countertop_L_8x", "CounterTop"),
        ] {
            assert_eq!(object_type_from_asset_id(a), Some(want), "{a}");
        }
        assert_eq!(object_type_from_asset_id("Zzz_1"), None);
    }

    /// Every asset of the real ProcTHOR database is named correctly without the database.
    #[test]
    fn keywords_cover_the_asset_database() {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../shared/procthor/assets/asset-database.json"
        );
        let Ok(text) = std::fs::read_to_string(path) else {
            return;
        };
        let db: serde_json::Value = serde_json::from_str(&text).unwrap();
        let mut checked = 0;
        for (ty, assets) in db.as_object().unwrap() {
            for a in assets.as_array().unwrap() {
                let id = a["assetId"].as_str().unwrap();
                assert_eq!(object_type_from_asset_id(id), Some(ty.as_str()), "{id}");
                checked += 1;
            }
        }
        assert!(checked > 1000);
    }
}
