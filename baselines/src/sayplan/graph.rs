//! SayPlan's map abstraction: a 2D scene graph (scene → rooms → objects, rooms adjacent through
//! doorways, the agent at its start) and the views of it the model sees. The collapsed view shows
//! the scene, the agent and every room; expanding a room shows its objects, contracting hides them.
//!
//! Adaptation: `adjacent_to` joins rooms that share a passage (m2rc's one definition of
//! adjacency), not rooms whose labels merely touch through a wall, since m2rc's room layer leaves
//! walls and door cuts unlabelled.

use crate::iln::graph::nearest;
use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::query::MapQuery;
use serde_json::{Value, json};
use std::collections::BTreeSet;

/// Attributes shown per node, and their length, in the prompt.
const MAX_ATTRIBUTES: usize = 8;
const MAX_ATTRIBUTE_CHARS: usize = 120;

#[derive(Clone, Debug, PartialEq)]
pub enum NodeKind {
    Scene,
    Agent,
    Room {
        navigation_target: Option<Cell>,
    },
    Object {
        room: Option<u32>,
        /// Free 8-neighbours of the footprint, nearest the centre (L1) first.
        approach_cells: Vec<Cell>,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub id: String,
    pub kind: NodeKind,
    pub name: String,
    pub category: String,
    pub position: [f64; 2],
    pub attributes: Vec<String>,
    /// Indices of the nodes this one `contains`.
    pub children: Vec<usize>,
}

impl Node {
    pub fn type_name(&self) -> &'static str {
        match self.kind {
            NodeKind::Scene => "scene",
            NodeKind::Agent => "agent",
            NodeKind::Room { .. } => "room",
            NodeKind::Object { .. } => "object",
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct SceneGraph {
    /// `scene_0`, `agent_0`, then rooms by id, then objects by id.
    pub nodes: Vec<Node>,
    /// `adjacent_to` pairs of room node indices.
    pub adjacent: Vec<(usize, usize)>,
    /// The room node the agent starts in, when any.
    pub agent_room: Option<usize>,
    pub start: Cell,
}

impl SceneGraph {
    pub fn build(map: &SemanticMap, start: Cell) -> Self {
        let q = MapQuery::new(map);
        let mut nodes = vec![
            Node {
                id: "scene_0".into(),
                kind: NodeKind::Scene,
                name: "scene".into(),
                category: "scene".into(),
                position: [0.0, 0.0],
                attributes: vec![],
                children: vec![],
            },
            Node {
                id: "agent_0".into(),
                kind: NodeKind::Agent,
                name: "agent".into(),
                category: "agent".into(),
                position: [start.row as f64, start.col as f64],
                attributes: vec![],
                children: vec![],
            },
        ];
        let mut room_centroids = Vec::new();
        for room in &map.rooms {
            let cells = q.room_cells(room.id);
            let centroid = MapQuery::centroid(cells).unwrap_or([0.0, 0.0]);
            let free: Vec<Cell> = cells
                .iter()
                .copied()
                .filter(|&c| q.is_traversable(c))
                .collect();
            room_centroids.push((room.id, centroid, !cells.is_empty()));
            nodes.push(Node {
                id: format!("room_{}", room.id),
                kind: NodeKind::Room {
                    navigation_target: nearest(&free, centroid),
                },
                name: room.name.clone(),
                category: room.category.clone(),
                position: centroid,
                attributes: room.attributes.clone(),
                children: vec![],
            });
        }
        // Rooms are nodes 2.. in map order; an id that names no room has no node.
        let room_node = |id: u32| map.rooms.iter().position(|r| r.id == id).map(|i| 2 + i);
        for o in &map.objects {
            let at_centre = {
                let (r, c) = (o.center[0].round(), o.center[1].round());
                let n = map.n() as f64;
                (r >= 0.0 && c >= 0.0 && r < n && c < n)
                    .then(|| map.room_at(Cell::new(r as u32, c as u32)))
                    .filter(|&x| x != 0)
            };
            let nearest_room = || {
                room_centroids
                    .iter()
                    .filter(|(_, _, has)| *has)
                    .min_by(|a, b| {
                        let d = |p: [f64; 2]| (p[0] - o.center[0]).hypot(p[1] - o.center[1]);
                        d(a.1).total_cmp(&d(b.1))
                    })
                    .map(|(id, _, _)| *id)
            };
            let known = |r: &u32| map.room(*r).is_some();
            let room = o
                .room
                .filter(known)
                .or(at_centre.filter(known))
                .or_else(nearest_room);
            let idx = nodes.len();
            nodes.push(Node {
                id: format!("object_{}", o.id),
                kind: NodeKind::Object {
                    room,
                    approach_cells: approach_cells(map, &o.footprint, o.center),
                },
                name: o.name.clone(),
                category: o.category.clone(),
                position: o.center,
                attributes: o.attributes.clone(),
                children: vec![],
            });
            if let Some(r) = room.and_then(room_node) {
                nodes[r].children.push(idx);
            }
        }
        nodes[0].children = (2..2 + map.rooms.len()).collect();
        let adjacent = map
            .room_adjacency()
            .into_iter()
            .filter_map(|(a, b)| Some((room_node(a)?, room_node(b)?)))
            .collect();
        let agent_room = room_node(map.room_at(start));
        SceneGraph {
            nodes,
            adjacent,
            agent_room,
            start,
        }
    }

    pub fn index(&self, id: &str) -> Option<usize> {
        self.nodes.iter().position(|n| n.id == id)
    }

    /// The nodes shown before any expansion: the scene, the agent and the rooms.
    pub fn collapsed(&self) -> BTreeSet<usize> {
        self.nodes
            .iter()
            .enumerate()
            .filter(|(_, n)| !matches!(n.kind, NodeKind::Object { .. }))
            .map(|(i, _)| i)
            .collect()
    }

    /// The visible part of the graph as the prompt shows it: nodes and `[src, tgt, rel]` edges.
    pub fn view_json(&self, visible: &BTreeSet<usize>) -> Value {
        let nodes: Vec<Value> = visible
            .iter()
            .map(|&i| self.node_json(i, visible))
            .collect();
        let mut edges = Vec::new();
        for &i in visible {
            for &c in &self.nodes[i].children {
                if visible.contains(&c) {
                    edges.push(json!([self.nodes[i].id, self.nodes[c].id, "contains"]));
                }
            }
        }
        for &(a, b) in &self.adjacent {
            if visible.contains(&a) && visible.contains(&b) {
                edges.push(json!([self.nodes[a].id, self.nodes[b].id, "adjacent_to"]));
            }
        }
        if let Some(r) = self.agent_room
            && visible.contains(&r)
        {
            edges.push(json!(["agent_0", self.nodes[r].id, "located_at"]));
        }
        json!({"nodes": nodes, "edges": edges})
    }

    fn node_json(&self, i: usize, visible: &BTreeSet<usize>) -> Value {
        let n = &self.nodes[i];
        let room_id = match &n.kind {
            NodeKind::Object { room: Some(r), .. } => json!(format!("room_{r}")),
            _ => Value::Null,
        };
        let attributes: Vec<String> = n
            .attributes
            .iter()
            .take(MAX_ATTRIBUTES)
            .map(|a| a.chars().take(MAX_ATTRIBUTE_CHARS).collect())
            .collect();
        json!({
            "id": n.id,
            "type": n.type_name(),
            "name": n.name,
            "category": n.category,
            "position": [round1(n.position[0]), round1(n.position[1])],
            "room_id": room_id,
            "child_count": n.children.len(),
            "visible_children": n.children.iter().filter(|c| visible.contains(c)).count(),
            "attributes": attributes,
        })
    }
}

fn round1(x: f64) -> f64 {
    (x * 10.0).round() / 10.0
}

/// How far (Chebyshev rings, cells) approach cells are looked for around a footprint: 1 m.
pub const APPROACH_RINGS: usize = 20;

/// The free cells nearest a footprint: its free 8-neighbours, as in the reference; when it has
/// none, the free cells of the first ring around it that has any, up to [`APPROACH_RINGS`].
/// Adaptation: m2rc's occupancy keeps a margin around furniture and walls, so the cells touching
/// an object are almost never free (the reference's rule would leave nearly every object of the
/// default suite unreachable). Sorted nearest the centre (L1) first, then row-major.
pub fn approach_cells(map: &SemanticMap, footprint: &[Cell], center: [f64; 2]) -> Vec<Cell> {
    let mut seen: BTreeSet<Cell> = footprint.iter().copied().collect();
    let n = map.n() as i64;
    let mut ring: Vec<Cell> = footprint.to_vec();
    let mut out = BTreeSet::new();
    for _ in 0..APPROACH_RINGS {
        let mut next = Vec::new();
        for c in &ring {
            for dr in -1i64..=1 {
                for dc in -1i64..=1 {
                    let (y, x) = (c.row as i64 + dr, c.col as i64 + dc);
                    if y < 0 || x < 0 || y >= n || x >= n {
                        continue;
                    }
                    let q = Cell::new(y as u32, x as u32);
                    if seen.insert(q) {
                        next.push(q);
                        if map.is_free(q) {
                            out.insert(q);
                        }
                    }
                }
            }
        }
        if !out.is_empty() || next.is_empty() {
            break;
        }
        ring = next;
    }
    let mut v: Vec<Cell> = out.into_iter().collect();
    let l1 = |c: &Cell| (c.row as f64 - center[0]).abs() + (c.col as f64 - center[1]).abs();
    v.sort_by(|a, b| l1(a).total_cmp(&l1(b)).then(a.cmp(b)));
    v
}
