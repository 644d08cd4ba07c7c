//! Must-avoids: rooms (never a destination's or the start's), the area around an object, or the
//! area between two objects, never touching the start region or a destination's must-pass
//! region, so that each forbids a way of getting somewhere, never the getting there.

use super::generate::{START_RADIUS, Scene, disc};
use super::place::dilate;
use super::plan::{Avoid, AvoidPlace, Stage};
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::query::Target;
use rand::Rng;
use rand::seq::{IndexedRandom, SliceRandom};
use rand_chacha::ChaCha8Rng;

/// Share of must-avoids placed on object areas rather than rooms.
const OBJECT_AVOID_SHARE: f64 = 0.5;
/// Width of the "area around an object" that a must-avoid keeps out of, metres.
pub const AROUND_M: f64 = 0.5;

impl<'a> Scene<'a> {
    /// One must-avoid for an episode with these stages; `rooms` are the rooms still free to avoid.
    pub(crate) fn avoid(
        &self,
        rng: &mut ChaCha8Rng,
        start: Cell,
        stages: &[Stage],
        rooms: &mut Vec<u32>,
    ) -> Option<Avoid> {
        if rng.random_bool(OBJECT_AVOID_SHARE)
            && let Some(a) = self.object_avoid(rng, start, stages)
        {
            return Some(a);
        }
        self.room_avoid(rng, rooms)
    }

    /// The rooms an episode may avoid: not the start's, not a destination's.
    pub(crate) fn avoidable_rooms(
        &self,
        rng: &mut ChaCha8Rng,
        start: Cell,
        stages: &[Stage],
    ) -> Vec<u32> {
        let start_room = self.ix.room_at(start);
        let mut rooms: Vec<u32> = self
            .ix
            .map
            .rooms
            .iter()
            .map(|r| r.id)
            .filter(|&r| r != start_room && stages.iter().all(|s| s.room != r))
            .collect();
        rooms.shuffle(rng);
        rooms
    }

    fn room_avoid(&self, rng: &mut ChaCha8Rng, rooms: &mut Vec<u32>) -> Option<Avoid> {
        let room = rooms.pop()?;
        let desc = super::refs::room_descriptions(&self.ix, room, 2)
            .choose(rng)
            .cloned()?;
        Some(Avoid {
            place: AvoidPlace::Room(desc),
            room: Some(room),
            cells: self.ix.room_free_cells(room),
        })
    }

    /// "Keep out of the area around the dining table" (the compiler's `area_near(x, 0.5 m)`) or
    /// "don't walk between the sofa and the TV" (`area_between`, two objects of one room 0.5-3 m
    /// apart).
    fn object_avoid(&self, rng: &mut ChaCha8Rng, start: Cell, stages: &[Stage]) -> Option<Avoid> {
        let ix = &self.ix;
        let res = ix.resolution();
        let n = ix.map.n();
        let mut blocked = vec![false; n * n];
        for c in disc(start, START_RADIUS + 2.0) {
            if (c.row as usize) < n && (c.col as usize) < n {
                blocked[ix.free.index(c)] = true;
            }
        }
        for s in stages {
            for (i, b) in dilate(n, &s.goal, 2).into_iter().enumerate() {
                blocked[i] |= b;
            }
        }
        // Never an object of a category the destinations name: "keep out of the area around
        // the armchair" after "go to the armchair" reads as avoiding the destination.
        let named = super::place::named_categories(ix, stages);
        let mut pool: Vec<u32> = self
            .descriptions
            .keys()
            .copied()
            .filter(|o| {
                stages.iter().all(|s| !s.anchor_objects.contains(o))
                    && ix.object(*o).parent.is_none()
                    && !named.contains(&ix.object(*o).category)
            })
            .collect();
        pool.shuffle(rng);
        let describe = |o: u32, rng: &mut ChaCha8Rng| {
            let d = self.describable(o, 2);
            d.choose(rng).map(|r| (*r).clone())
        };
        let region = |cells: Vec<Cell>| -> Option<Vec<usize>> {
            let free: Vec<usize> = cells
                .into_iter()
                .filter(|&c| ix.free.passable(c))
                .map(|c| ix.free.index(c))
                .collect();
            (!free.is_empty() && free.iter().all(|&i| !blocked[i])).then_some(free)
        };
        let between = rng.random_bool(0.5);
        for (i, &a) in pool.iter().enumerate().take(40) {
            let oa = ix.object(a);
            if between {
                let partner = pool[i + 1..].iter().copied().find(|&b| {
                    let ob = ix.object(b);
                    let gap = ix.footprint_distance(a, b) * res;
                    ob.room == oa.room && ob.category != oa.category && (0.5..=3.0).contains(&gap)
                });
                let Some(b) = partner else { continue };
                let cells = self
                    .q
                    .corridor(Target::Object(oa), Target::Object(ix.object(b)));
                if let Some(cells) = region(cells)
                    && let Some((da, db)) = self.pair_descriptions(rng, a, b, 2)
                {
                    return Some(Avoid {
                        place: AvoidPlace::Between(da, db),
                        room: oa.room,
                        cells,
                    });
                }
            } else {
                let cells = self.q.area_near(Target::Object(oa), AROUND_M);
                if let Some(cells) = region(cells)
                    && let Some(d) = describe(a, rng)
                {
                    return Some(Avoid {
                        place: AvoidPlace::Around(d),
                        room: oa.room,
                        cells,
                    });
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::super::index::MapIndex;
    use super::super::plan::{Dest, Stage};
    use super::super::refs::ObjRef;
    use super::*;
    use rand::SeedableRng;

    /// The demo house has three beds. With one of them the destination, an object must-avoid is
    /// never about another bed ("keep out of the area around the bed" would read as avoiding the
    /// destination), nor about anything else the destination's words name.
    #[test]
    fn object_avoids_never_name_a_destination_category() {
        let map = m2rc_stdlib::demo::demo_map().unwrap();
        let scene = Scene::new(MapIndex::new(&map), "procthor/demo".into());
        let ix = &scene.ix;
        let bed = ix.of_cat("bed")[0];
        assert_eq!(ix.of_cat("bed").len(), 3);
        let start = map.start.unwrap();
        let room = ix.object_room(bed).unwrap();
        let goal: Vec<usize> = ix.room_free_cells(room).into_iter().take(1).collect();
        let stage = Stage {
            dest: Dest::Object {
                id: bed,
                desc: ObjRef::Unique { cat: "bed".into() },
            },
            anchor_objects: vec![bed],
            room,
            goal,
            center: [0.0, 0.0],
            radius: 1.0,
            avoids: vec![],
            softs: vec![],
        };
        let stages = [stage];
        let mut categories = std::collections::BTreeSet::new();
        for seed in 0..300 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let Some(a) = scene.object_avoid(&mut rng, start, &stages) else {
                continue;
            };
            match &a.place {
                AvoidPlace::Around(d) => {
                    categories.insert(d.category().to_string());
                }
                AvoidPlace::Between(x, y) => {
                    categories.insert(x.category().to_string());
                    categories.insert(y.category().to_string());
                }
                AvoidPlace::Room(_) => {}
            }
        }
        assert!(categories.len() > 3, "too few avoids drawn: {categories:?}");
        assert!(!categories.contains("bed"), "{categories:?}");
    }
}
