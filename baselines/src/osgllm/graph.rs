//! OSG-LLM's map abstraction: a floor / room / object scene graph whose nodes are the atomic
//! propositions the model may name (`enter(floor_0)`, `enter(room_<id>)`, `reach(object_<id>)`),
//! each true on a region of traversable cells.
//!
//! The regions follow the adaptation (reference §4): the floor is every traversable cell, a room
//! its traversable room-layer cells, an object the traversable cells within 20 cells (1 m) of its
//! footprint's bounding box, or the nearest traversable cell within 80 cells when the band holds
//! none. Room adjacency is the map's passage adjacency (`SemanticMap::room_adjacency`): it holds
//! every pair of rooms whose free cells touch, which is the adaptation's pixel rule, and also the
//! pairs joined through a small unlabelled door patch, which m2rc's imported maps may have and the
//! pixel rule would miss.

use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use serde_json::{Value, json};
use std::collections::BTreeMap;

/// Cells around an object's bounding box that count as reaching it (1 m at 0.05 m per cell).
pub const OBJECT_REACH_CELLS: u32 = 20;
/// How far the nearest traversable cell may be when an object's band holds none.
pub const NEAREST_FREE_CELLS: u32 = 80;
/// Objects listed per room in the model's view of the graph.
pub const MAX_PROMPT_OBJECTS_PER_ROOM: usize = 80;

/// One node of the graph the model can name.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// `floor_0`, `room_<id>` or `object_<id>`.
    pub id: String,
    /// `enter(floor_0)`, `enter(room_<id>)`, `reach(object_<id>)`.
    pub ap: String,
    pub category: String,
    pub name: String,
    /// The room of an object, or the room itself (none for the floor).
    pub room: Option<u32>,
    /// Row-major indices of the traversable cells where the proposition is true, ascending.
    pub cells: Vec<u32>,
}

/// The scene graph of one map.
#[derive(Clone, Debug)]
pub struct SceneGraph {
    pub n: usize,
    /// Row-major traversability.
    pub traversable: Vec<bool>,
    /// The floor, then rooms by id, then objects by id.
    pub nodes: Vec<Node>,
    /// Room id -> adjacent room ids, ascending.
    pub adjacency: BTreeMap<u32, Vec<u32>>,
    by_id: BTreeMap<String, usize>,
    by_ap: BTreeMap<String, usize>,
}

impl SceneGraph {
    pub fn build(map: &SemanticMap) -> SceneGraph {
        let n = map.n();
        let traversable: Vec<bool> = (0..n * n)
            .map(|i| map.is_free(Cell::new((i / n) as u32, (i % n) as u32)))
            .collect();
        let mut nodes = vec![Node {
            id: "floor_0".into(),
            ap: "enter(floor_0)".into(),
            category: "floor".into(),
            name: "floor".into(),
            room: None,
            cells: (0..n * n)
                .filter(|&i| traversable[i])
                .map(|i| i as u32)
                .collect(),
        }];
        let mut room_cells: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
        for (i, &free) in traversable.iter().enumerate() {
            let id = map.room_layer.data().get(i).copied().unwrap_or(0);
            if free && id != 0 {
                room_cells.entry(id).or_default().push(i as u32);
            }
        }
        for r in &map.rooms {
            nodes.push(Node {
                id: format!("room_{}", r.id),
                ap: format!("enter(room_{})", r.id),
                category: r.category.clone(),
                name: r.name.clone(),
                room: Some(r.id),
                cells: room_cells.remove(&r.id).unwrap_or_default(),
            });
        }
        for o in &map.objects {
            let cells = approach_cells(map, &traversable, &o.footprint, o.center);
            let room = o
                .room
                .or_else(|| vote(map, o.footprint.iter().map(|c| map.room_at(*c))))
                .or_else(|| {
                    vote(
                        map,
                        cells
                            .iter()
                            .map(|&i| map.room_layer.data().get(i as usize).copied().unwrap_or(0)),
                    )
                });
            nodes.push(Node {
                id: format!("object_{}", o.id),
                ap: format!("reach(object_{})", o.id),
                category: o.category.clone(),
                name: o.name.clone(),
                room,
                cells,
            });
        }
        let mut adjacency: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
        for (a, b) in map.room_adjacency() {
            adjacency.entry(a).or_default().push(b);
            adjacency.entry(b).or_default().push(a);
        }
        for v in adjacency.values_mut() {
            v.sort_unstable();
            v.dedup();
        }
        SceneGraph::from_parts(n, traversable, nodes, adjacency)
    }

    /// A graph from its parts (small hand-made graphs in tests, and [`SceneGraph::build`]).
    pub fn from_parts(
        n: usize,
        traversable: Vec<bool>,
        nodes: Vec<Node>,
        adjacency: BTreeMap<u32, Vec<u32>>,
    ) -> SceneGraph {
        let by_id = nodes
            .iter()
            .enumerate()
            .map(|(i, x)| (x.id.clone(), i))
            .collect();
        let by_ap = nodes
            .iter()
            .enumerate()
            .map(|(i, x)| (x.ap.clone(), i))
            .collect();
        SceneGraph {
            n,
            traversable,
            nodes,
            adjacency,
            by_id,
            by_ap,
        }
    }

    pub fn node(&self, id: &str) -> Option<&Node> {
        self.by_id.get(id).map(|&i| &self.nodes[i])
    }

    pub fn node_by_ap(&self, ap: &str) -> Option<&Node> {
        self.by_ap.get(ap).map(|&i| &self.nodes[i])
    }

    /// The room-layer room a cell lies in, when it is one of the graph's rooms.
    pub fn room_of_cell(&self, map: &SemanticMap, cell: Cell) -> Option<u32> {
        let id = map.room_at(cell);
        self.node(&format!("room_{id}")).map(|_| id)
    }

    fn rooms(&self) -> impl Iterator<Item = &Node> {
        self.nodes.iter().filter(|x| x.id.starts_with("room_"))
    }

    fn objects_of(&self, room: u32) -> impl Iterator<Item = &Node> {
        self.nodes
            .iter()
            .filter(move |x| x.id.starts_with("object_") && x.room == Some(room))
    }

    fn room_ids(&self, room: u32) -> Vec<String> {
        self.adjacency
            .get(&room)
            .map(|v| v.iter().map(|r| format!("room_{r}")).collect())
            .unwrap_or_default()
    }

    /// The compact graph of the grounding call: ids, categories, names, APs and connections,
    /// never coordinates, sizes or attributes (the adaptation shows the model no geometry).
    pub fn prompt_json(&self) -> Value {
        let rooms: Vec<Value> = self
            .rooms()
            .map(|r| {
                let id = r.room.unwrap_or(0);
                let objects: Vec<Value> = self
                    .objects_of(id)
                    .take(MAX_PROMPT_OBJECTS_PER_ROOM)
                    .map(
                        |o| json!({"id": o.id, "category": o.category, "name": o.name, "ap": o.ap}),
                    )
                    .collect();
                json!({
                    "id": r.id, "category": r.category, "name": r.name, "ap": r.ap,
                    "connected_rooms": self.room_ids(id), "objects": objects,
                })
            })
            .collect();
        let object_count = self
            .nodes
            .iter()
            .filter(|x| x.id.starts_with("object_"))
            .count();
        json!({
            "floor": {"id": "floor_0", "ap": "enter(floor_0)"},
            "rooms": rooms,
            "object_count": object_count,
        })
    }

    /// The smaller graph of the heuristic call: rooms with their connections, objects with their
    /// parent room.
    pub fn heuristic_json(&self) -> Value {
        let rooms: Vec<Value> = self
            .rooms()
            .map(|r| json!({"id": r.id, "category": r.category, "connected_rooms": self.room_ids(r.room.unwrap_or(0))}))
            .collect();
        let objects: Vec<Value> = self
            .nodes
            .iter()
            .filter(|x| x.id.starts_with("object_"))
            .map(|o| {
                json!({"id": o.id, "category": o.category,
                       "parent_id": o.room.map(|r| format!("room_{r}"))})
            })
            .collect();
        json!({"rooms": rooms, "objects": objects})
    }

    /// A short summary for the record.
    pub fn summary(&self) -> Value {
        let rooms = self.rooms().count();
        json!({
            "rooms": rooms,
            "objects": self.nodes.len() - 1 - rooms,
            "room_links": self.adjacency.values().map(Vec::len).sum::<usize>() / 2,
        })
    }
}

/// The most frequent non-zero room id of `ids` that is one of the map's rooms (smallest id on a tie).
fn vote(map: &SemanticMap, ids: impl Iterator<Item = u32>) -> Option<u32> {
    let mut counts: BTreeMap<u32, usize> = BTreeMap::new();
    for id in ids.filter(|&id| id != 0 && map.room(id).is_some()) {
        *counts.entry(id).or_insert(0) += 1;
    }
    let best = counts.values().copied().max()?;
    counts
        .into_iter()
        .find(|&(_, c)| c == best)
        .map(|(id, _)| id)
}

/// Traversable cells within [`OBJECT_REACH_CELLS`] of the footprint's bounding box; else the
/// nearest traversable cell to the centre within [`NEAREST_FREE_CELLS`]; else none.
fn approach_cells(
    map: &SemanticMap,
    traversable: &[bool],
    footprint: &[Cell],
    center: [f64; 2],
) -> Vec<u32> {
    let n = map.n();
    if n == 0 {
        return Vec::new();
    }
    let (r0, r1, c0, c1) = if footprint.is_empty() {
        let r = center[0].round().clamp(0.0, (n - 1) as f64) as u32;
        let c = center[1].round().clamp(0.0, (n - 1) as f64) as u32;
        (r, r, c, c)
    } else {
        footprint.iter().fold((u32::MAX, 0, u32::MAX, 0), |b, x| {
            (
                b.0.min(x.row),
                b.1.max(x.row),
                b.2.min(x.col),
                b.3.max(x.col),
            )
        })
    };
    let k = OBJECT_REACH_CELLS;
    let lim = (n - 1) as u32;
    let mut out = Vec::new();
    for r in r0.saturating_sub(k)..=(r1.saturating_add(k)).min(lim) {
        for c in c0.saturating_sub(k)..=(c1.saturating_add(k)).min(lim) {
            let dr = r0.saturating_sub(r).max(r.saturating_sub(r1)) as u64;
            let dc = c0.saturating_sub(c).max(c.saturating_sub(c1)) as u64;
            let i = r as usize * n + c as usize;
            if dr * dr + dc * dc <= (k as u64) * (k as u64) && traversable[i] {
                out.push(i as u32);
            }
        }
    }
    if out.is_empty() {
        let seed = Cell::new(
            center[0].round().clamp(0.0, lim as f64) as u32,
            center[1].round().clamp(0.0, lim as f64) as u32,
        );
        if let Some(c) = nearest_traversable(traversable, n, seed, NEAREST_FREE_CELLS) {
            out.push((c.row as usize * n + c.col as usize) as u32);
        }
    }
    out
}

/// The traversable cell nearest `seed` (Euclidean, then row, then column) within `radius` cells.
pub fn nearest_traversable(
    traversable: &[bool],
    n: usize,
    seed: Cell,
    radius: u32,
) -> Option<Cell> {
    let lim = n.checked_sub(1)? as u32;
    let mut best: Option<(u64, Cell)> = None;
    for r in seed.row.saturating_sub(radius)..=seed.row.saturating_add(radius).min(lim) {
        for c in seed.col.saturating_sub(radius)..=seed.col.saturating_add(radius).min(lim) {
            let cell = Cell::new(r, c);
            let d = cell.dist_sq(seed);
            if d <= (radius as u64).pow(2)
                && traversable[r as usize * n + c as usize]
                && best.is_none_or(|(bd, _)| d < bd)
            {
                best = Some((d, cell));
            }
        }
    }
    best.map(|(_, c)| c)
}
