//! ILN's map abstraction: the area–passage graph (an osmAG stand-in built from the room layer).
//!
//! Areas are the rooms a robot can stand in, each with its centroid and medoid (the free room
//! cell nearest the centroid, where a route into the area ends). Passages are the connected
//! boundary components between two rooms; each has an anchor (the free passage cell nearest the
//! component's mean, which a route goes through) and a width (its cell count).
//!
//! Adaptation: the reference finds passages as raw 4-neighbour label changes; m2rc's maps cut
//! doorways as small unlabelled patches, so the passages come from the one definition the rest of
//! m2rc uses (`MapQuery::passages`: label changes and door patches, grouped 8-connected).

use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::SemanticMap;
use m2rc_stdlib::query::MapQuery;
use serde::Serialize;

/// How far the start's area is looked for around an unlabelled start cell (cells).
pub const START_AREA_RADIUS: i64 = 120;

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Area {
    /// `room_<id>`.
    pub id: String,
    pub room: u32,
    pub category: String,
    pub name: String,
    /// Mean `[row, col]` of the room's cells.
    pub centroid: [f64; 2],
    pub medoid: Cell,
    /// Indices into [`AreaGraph::passages`].
    pub passages: Vec<usize>,
    /// Sorted distinct object categories in the room (landmarks; no instance ids).
    pub landmarks: Vec<String>,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PassageEdge {
    /// `passage_<k>`.
    pub id: String,
    /// Indices into [`AreaGraph::areas`], smaller room id first.
    pub areas: (usize, usize),
    pub anchor: Cell,
    pub width: usize,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct AreaGraph {
    /// By room id.
    pub areas: Vec<Area>,
    pub passages: Vec<PassageEdge>,
}

impl AreaGraph {
    pub fn build(map: &SemanticMap) -> Self {
        let q = MapQuery::new(map);
        let mut areas = Vec::new();
        for room in &map.rooms {
            let cells = q.room_cells(room.id);
            let free: Vec<Cell> = cells
                .iter()
                .copied()
                .filter(|&c| q.is_traversable(c))
                .collect();
            let Some(centroid) = MapQuery::centroid(cells) else {
                continue;
            };
            let Some(medoid) = nearest(&free, centroid) else {
                continue;
            };
            let mut landmarks: Vec<String> = map
                .objects_in_room(room.id)
                .map(|o| o.category.clone())
                .collect();
            landmarks.sort();
            landmarks.dedup();
            areas.push(Area {
                id: format!("room_{}", room.id),
                room: room.id,
                category: room.category.clone(),
                name: room.name.clone(),
                centroid,
                medoid,
                passages: Vec::new(),
                landmarks,
            });
        }
        let index = |room: u32| areas.iter().position(|a| a.room == room);
        let mut passages = Vec::new();
        for p in q.passages() {
            let (Some(a), Some(b)) = (index(p.rooms.0), index(p.rooms.1)) else {
                continue;
            };
            let free: Vec<Cell> = p
                .cells
                .iter()
                .copied()
                .filter(|&c| q.is_traversable(c))
                .collect();
            let Some(mean) = MapQuery::centroid(&p.cells) else {
                continue;
            };
            let Some(anchor) = nearest(&free, mean) else {
                continue;
            };
            passages.push(PassageEdge {
                id: format!("passage_{}", passages.len()),
                areas: (a, b),
                anchor,
                width: p.cells.len(),
            });
        }
        for (k, p) in passages.iter().enumerate() {
            areas[p.areas.0].passages.push(k);
            areas[p.areas.1].passages.push(k);
        }
        AreaGraph { areas, passages }
    }

    pub fn area(&self, id: &str) -> Option<usize> {
        self.areas.iter().position(|a| a.id == id)
    }

    pub fn passage(&self, id: &str) -> Option<usize> {
        self.passages.iter().position(|p| p.id == id)
    }

    /// The area a route from `start` begins in: the room labelled at the start cell, else the
    /// nearest free labelled cell's room within [`START_AREA_RADIUS`] (Euclidean, row-major ties).
    pub fn start_area(&self, map: &SemanticMap, start: Cell) -> Option<usize> {
        let area_of = |c: Cell| {
            let room = map.room_at(c);
            (room != 0).then(|| self.areas.iter().position(|a| a.room == room))?
        };
        if let Some(a) = area_of(start) {
            return Some(a);
        }
        let n = map.n() as i64;
        let (sr, sc) = (start.row as i64, start.col as i64);
        for r in 1..=START_AREA_RADIUS {
            let mut best: Option<(i64, Cell, usize)> = None;
            for dr in -r..=r {
                for dc in -r..=r {
                    if dr.abs() != r && dc.abs() != r {
                        continue;
                    }
                    let (y, x) = (sr + dr, sc + dc);
                    if y < 0 || x < 0 || y >= n || x >= n {
                        continue;
                    }
                    let c = Cell::new(y as u32, x as u32);
                    let d = dr * dr + dc * dc;
                    if !map.is_free(c) {
                        continue;
                    }
                    if let Some(a) = area_of(c)
                        && best.is_none_or(|(bd, bc, _)| d < bd || (d == bd && c < bc))
                    {
                        best = Some((d, c, a));
                    }
                }
            }
            if let Some((_, _, a)) = best {
                return Some(a);
            }
        }
        None
    }

    /// The text the model reads: areas with their passages, passages with rooms, anchor and
    /// width, and the landmark categories of each area.
    pub fn serialise(&self) -> String {
        let mut s = String::from("areas:\n");
        for a in &self.areas {
            let ps: Vec<&str> = a
                .passages
                .iter()
                .map(|&k| self.passages[k].id.as_str())
                .collect();
            s.push_str(&format!(
                "{}: category={}, name={}, passages=[{}]\n",
                a.id,
                a.category,
                a.name,
                ps.join(", ")
            ));
        }
        s.push_str("passages:\n");
        for p in &self.passages {
            s.push_str(&format!(
                "{}: rooms={}<->{}, anchor=[{},{}], width={}\n",
                p.id,
                self.areas[p.areas.0].id,
                self.areas[p.areas.1].id,
                p.anchor.row,
                p.anchor.col,
                p.width
            ));
        }
        s.push_str("semantic_landmarks_by_area:\n");
        for a in &self.areas {
            s.push_str(&format!("{}: [{}]\n", a.id, a.landmarks.join(", ")));
        }
        s
    }
}

/// The cell of `cells` nearest `point` (Euclidean), the first in order on ties.
pub fn nearest(cells: &[Cell], point: [f64; 2]) -> Option<Cell> {
    let d = |c: &Cell| {
        let (dr, dc) = (c.row as f64 - point[0], c.col as f64 - point[1]);
        dr * dr + dc * dc
    };
    let mut best: Option<(f64, Cell)> = None;
    for c in cells {
        let dc = d(c);
        if best.is_none_or(|(bd, _)| dc < bd) {
            best = Some((dc, *c));
        }
    }
    best.map(|(_, c)| c)
}
