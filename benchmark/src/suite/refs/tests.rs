use super::*;
use crate::suite::realise::Speaker;

#[test]
fn circular_and_stacked_chains_are_unnatural() {
    let bedroom = |adj: &str| match adj {
        "l" => RoomRef::Largest {
            cat: "living_room".into(),
        },
        _ => RoomRef::Smallest {
            cat: "living_room".into(),
        },
    };
    let stacked = ObjRef::Nearest {
        cat: "chair".into(),
        room: Some(bedroom("s")),
        anchor: Box::new(ObjRef::InRoom {
            cat: "sofa".into(),
            room: bedroom("l"),
        }),
    };
    assert!(!stacked.is_natural());
    let circular = ObjRef::Nearest {
        cat: "sink".into(),
        room: None,
        anchor: Box::new(ObjRef::Nearest {
            cat: "toilet".into(),
            room: None,
            anchor: Box::new(ObjRef::Unique { cat: "sink".into() }),
        }),
    };
    assert!(!circular.is_natural());
    let fine = ObjRef::Nearest {
        cat: "chair".into(),
        room: Some(bedroom("l")),
        anchor: Box::new(ObjRef::Unique { cat: "sofa".into() }),
    };
    assert!(fine.is_natural());
    assert_eq!(
        fine.m2r(),
        "objects(chair).in(rooms(living_room).largest()).nearest(to: objects(sofa).only())"
    );
}

/// Inside a clause already scoped to a room, a description leaves that room out (the program
/// keeps it); any other room is still named, and "closest to you" keeps its room.
#[test]
fn a_scoped_clause_does_not_name_its_room_twice() {
    use rand::SeedableRng;
    let map = m2rc_stdlib::demo::demo_map().unwrap();
    let ix = MapIndex::new(&map);
    let kitchen = ix.rooms_of_cat("kitchen")[0];
    let in_kitchen = ObjRef::InRoom {
        cat: "fridge".into(),
        room: RoomRef::Unique {
            cat: "kitchen".into(),
        },
    };
    let from_you = ObjRef::FromYou {
        cat: "fridge".into(),
        room: Some(RoomRef::Unique {
            cat: "kitchen".into(),
        }),
        farthest: false,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let mut sp = Speaker::new(&mut rng);
    assert!(in_kitchen.text(&ix, &mut sp).contains("kitchen"));
    sp.implied_room = Some(kitchen);
    let t = in_kitchen.text(&ix, &mut sp);
    assert!(!t.contains("kitchen") && t.starts_with("the "), "{t}");
    assert!(from_you.text(&ix, &mut sp).contains("kitchen"));
    sp.implied_room = Some(ix.rooms_of_cat("bathroom")[0]);
    assert!(in_kitchen.text(&ix, &mut sp).contains("kitchen"));
    assert_eq!(
        in_kitchen.m2r(),
        "objects(fridge).in(rooms(kitchen).only()).only()"
    );
}

/// Two objects of one room ("between the fridge in the kitchen and the sink") name the room
/// once; two of different rooms name both, and the scope the clause had is restored.
#[test]
fn a_pair_in_one_room_names_the_room_once() {
    use rand::SeedableRng;
    let map = m2rc_stdlib::demo::demo_map().unwrap();
    let ix = MapIndex::new(&map);
    let in_room = |cat: &str, room: &str| ObjRef::InRoom {
        cat: cat.into(),
        room: RoomRef::Unique { cat: room.into() },
    };
    let (fridge, sink) = (in_room("fridge", "kitchen"), in_room("sink", "kitchen"));
    let toilet = in_room("toilet", "bathroom");
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut sp = Speaker::new(&mut rng);
    let (ta, tb) = ObjRef::pair_text(&fridge, &sink, &ix, &mut sp);
    assert!(ta.contains("kitchen"), "{ta}");
    // Not "the sink in that room" either: no room at all.
    assert!(
        tb.starts_with("the ") && !tb.contains(" in ") && !tb.contains("room"),
        "{tb}"
    );
    assert_eq!(sp.implied_room, None);
    let mut sp = Speaker::new(&mut rng);
    let (_, tb) = ObjRef::pair_text(&fridge, &toilet, &ix, &mut sp);
    assert!(tb.contains("bathroom"), "{tb}");
    let bath = ix.rooms_of_cat("bathroom")[0];
    let mut sp = Speaker::new(&mut rng);
    sp.implied_room = Some(bath);
    let (ta, _) = ObjRef::pair_text(&fridge, &sink, &ix, &mut sp);
    assert!(ta.contains("kitchen"), "{ta}");
    assert_eq!(sp.implied_room, Some(bath));
}
