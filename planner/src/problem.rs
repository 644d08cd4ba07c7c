//! The planner's own input: masks, cells and weights, with nothing left to look up in a map or a
//! program. Keeping it independent of the RouteIR lets tests and benchmarks build problems directly,
//! and lets the RouteIR change without touching the search code (`lower.rs` is the only bridge).

use m2rc_stdlib::grid::{Cell, Grid};
use serde::{Deserialize, Serialize};

/// A set of cells, either as a full mask or as a list (object footprints and small regions are
/// lists; rooms and scopes are often masks already). A mask is shared, not copied: the same room
/// scopes many constraints of a program, and a copy of a suite map's mask is half a megabyte.
#[derive(Clone, Debug, PartialEq)]
pub enum Area {
    Mask(std::sync::Arc<Grid<bool>>),
    Cells(Vec<Cell>),
}

impl Area {
    /// The area of the cells a mask sets.
    pub fn mask(grid: Grid<bool>) -> Area {
        Area::Mask(std::sync::Arc::new(grid))
    }

    /// The area as a row-major mask of side `n`; cells outside the grid are dropped.
    pub fn to_mask(&self, n: usize) -> Vec<bool> {
        match self {
            Area::Mask(g) if g.n() == n => g.data().to_vec(),
            _ => {
                let mut out = vec![false; n * n];
                self.or_into(&mut out, n);
                out
            }
        }
    }

    /// Sets the area's cells in `out`, a row-major mask of side `n` (cells outside it dropped):
    /// the union of several areas without a mask of each.
    pub fn or_into(&self, out: &mut [bool], n: usize) {
        let mut set = |c: Cell| {
            if (c.row as usize) < n && (c.col as usize) < n {
                out[c.row as usize * n + c.col as usize] = true;
            }
        };
        match self {
            Area::Mask(g) if g.n() == n => {
                out.iter_mut().zip(g.data()).for_each(|(o, &v)| *o |= v);
            }
            Area::Mask(g) => g
                .iter_cells()
                .filter(|(_, v)| **v)
                .for_each(|(c, _)| set(c)),
            Area::Cells(cells) => cells.iter().for_each(|&c| set(c)),
        }
    }

    /// The cells in row-major order.
    pub fn cells(&self) -> Vec<Cell> {
        match self {
            Area::Mask(g) => g
                .iter_cells()
                .filter(|(_, v)| **v)
                .map(|(c, _)| c)
                .collect(),
            Area::Cells(c) => {
                let mut v = c.clone();
                v.sort_unstable();
                v.dedup();
                v
            }
        }
    }

    pub fn is_empty(&self) -> bool {
        match self {
            Area::Mask(g) => !g.data().iter().any(|v| *v),
            Area::Cells(c) => c.is_empty(),
        }
    }
}

/// Where a stage, an avoid region or a soft term came from, so a failure can be mapped back to the
/// `.m2r` span that caused it. Indices refer to the RouteIR the problem was lowered from.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize,
)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Origin {
    /// Built by hand (tests, benchmarks).
    #[default]
    Unknown,
    /// The destination of RouteIR stage `stage` (`go <place>`).
    Target { stage: usize },
    /// Must-pass `index` of RouteIR stage `stage` (`pass <place>`).
    Pass { stage: usize, index: usize },
    /// RouteIR constraint `index` (`avoid`, `prefer`); `part` numbers the waypoints of a shape.
    Constraint { index: usize, part: usize },
}

/// What a stage must reach. The goal-mask rules of the reference planner (§4.2 of the method
/// notes) live in `goal.rs`; a target only says which rule applies.
#[derive(Clone, Debug, PartialEq)]
pub enum Target {
    /// One cell (a position).
    Position(Cell),
    /// Room cells; the stage ends at the first traversable room cell entered.
    Room(Area),
    /// Region cells. `fallback`, for "near" regions, is the room and centre whose nearest traversable
    /// cell replaces a region that has no traversable cell.
    Region {
        cells: Area,
        fallback: Option<Fallback>,
    },
    /// An object: the goal is the band `0 < d ≤ goal radius` around its footprint, inside its room,
    /// falling back to the room's traversable cell nearest the object's centre.
    Object {
        footprint: Vec<Cell>,
        room: Option<Area>,
        center: [f64; 2],
    },
    /// Any one of these targets (`go S` on a set): the goal is the union of the members' goals,
    /// each under its own rule and fallback, so one search reaches whichever member is cheapest
    /// by route, with the segment's constraints applied to every member alike.
    AnyOf(Vec<Target>),
}

/// The replacement goal of a target whose own cells are unusable.
#[derive(Clone, Debug, PartialEq)]
pub struct Fallback {
    /// `None` = the whole grid.
    pub room: Option<Area>,
    /// `[row, col]` in cells.
    pub center: [f64; 2],
}

/// Why a stage exists. Shape waypoints are stages only because the reference plans loops that way;
/// the hard-only baselines drop or merge them (see [`WaypointMode`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StageRole {
    /// A hard must-pass place.
    Pass,
    /// A waypoint of a path-shape preference (circle, follow_wall, patrol).
    Waypoint,
    /// The segment's destination (always the last stage of a segment).
    Destination,
}

#[derive(Clone, Debug, PartialEq)]
pub struct StageSpec {
    pub target: Target,
    pub role: StageRole,
    /// Turns are charged while inside this mask (the waypoint's room for loop waypoints).
    pub smoothness: Option<Area>,
    pub origin: Origin,
}

/// A hard must-avoid region active during one segment.
#[derive(Clone, Debug, PartialEq)]
pub struct Forbid {
    pub cells: Area,
    pub origin: Origin,
}

/// How "be closer to A than to B" becomes a per-cell cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RelativeMode {
    /// `d_close / (d_close + d_far)`, the reference default.
    #[default]
    Ratio,
    /// `clip(max(0, d_close - d_far) / R_rel, 0, 1)`.
    Difference,
}

/// One soft term. Reference areas with no cells contribute nothing (the lowering substitutes the
/// rounded centre cell, as the reference does, before it gets here).
#[derive(Clone, Debug, PartialEq)]
pub enum SoftKind {
    Near {
        reference: Area,
    },
    Far {
        reference: Area,
    },
    Relative {
        closer: Area,
        farther: Area,
        mode: RelativeMode,
    },
    /// Stay near the union of the waypoint cells (the reference `prefer_path_shape` field).
    PathShape {
        waypoints: Area,
    },
    /// An extra clearance term with its own radius, in metres (the `clearance(d)` preference).
    Clearance {
        radius_m: f64,
    },
}

#[derive(Clone, Debug, PartialEq)]
pub struct SoftTerm {
    pub kind: SoftKind,
    /// Replaces the profile's λ for this term.
    pub weight: Option<f64>,
    /// Spatial scope; `None` = the whole map.
    pub scope: Option<Area>,
    pub origin: Origin,
}

/// Everything active while heading to one destination.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentSpec {
    /// In visiting order; the last one is normally the destination.
    pub stages: Vec<StageSpec>,
    pub forbidden: Vec<Forbid>,
    pub soft: Vec<SoftTerm>,
}

/// What the hard-only baselines do with shape waypoint stages.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WaypointMode {
    /// Plan them as ordered stages (the reference planner).
    #[default]
    Stages,
    /// Merge each run of consecutive waypoint stages into one stage over the union of their cells
    /// (the reference "hard only" ablation).
    Collapse,
    /// Ignore them (hard constraints only).
    Drop,
}

/// Weights and radii of the cost model. Radii are metres and are turned into cells with the map's
/// resolution as `max(1, r / resolution)`, as the reference does.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct CostProfile {
    pub name: String,
    pub near_weight: f64,
    pub near_radius_m: f64,
    pub far_weight: f64,
    pub far_sigma_m: f64,
    pub relative_weight: f64,
    /// Only used by [`RelativeMode::Difference`].
    pub relative_radius_m: f64,
    pub path_shape_weight: f64,
    pub path_shape_radius_m: f64,
    pub clearance_weight: f64,
    pub clearance_radius_m: f64,
    /// Whether the always-on clearance term is charged.
    pub clearance: bool,
    /// Multiplies near, far, relative and path-shape terms (not clearance); 0 turns them off.
    pub soft_scale: f64,
    /// λ_s of the turn penalty inside loop-waypoint stages; 0 turns smoothness off.
    pub smoothness_weight: f64,
    /// Band around an object footprint that counts as "at the object".
    pub goal_radius_m: f64,
    /// A* expansions allowed per segment, shared by its stages; 0 = unlimited.
    pub max_expansions: u64,
    pub waypoints: WaypointMode,
    /// Use the exact distance-to-target heuristic (reference). When false, the heuristic is the
    /// straight-line distance to the target's bounding box: cheaper to build, same optimal cost,
    /// possibly different ties.
    pub edt_heuristic: bool,
    /// Whether a diagonal step may not pass the corner of an avoided cell either (only of a
    /// wall, in the reference). The evaluator's segment test counts a touched corner as
    /// entering the region; the full cost model's clearance term keeps its routes off such
    /// corners, a hard-constraint-only profile has nothing that does, so those set it.
    pub avoid_corners: bool,
}

impl Default for CostProfile {
    fn default() -> Self {
        CostProfile::reference()
    }
}

impl CostProfile {
    /// The Grounding2Route planner's constants (method notes §4.4–4.5).
    pub fn reference() -> Self {
        CostProfile {
            name: "reference".into(),
            near_weight: 8.0,
            near_radius_m: 1.5,
            far_weight: 96.0,
            far_sigma_m: 1.5,
            relative_weight: 64.0,
            relative_radius_m: 1.5,
            path_shape_weight: 18.0,
            path_shape_radius_m: 0.9,
            clearance_weight: 36.0,
            clearance_radius_m: 0.75,
            clearance: true,
            soft_scale: 1.0,
            smoothness_weight: 0.02,
            goal_radius_m: 0.30,
            max_expansions: 1_000_000,
            waypoints: WaypointMode::Stages,
            edt_heuristic: true,
            avoid_corners: false,
        }
    }

    /// The shortest-feasible baseline: hard constraints only, no soft field, no clearance, no
    /// turn penalty, waypoint stages dropped, unlimited expansions.
    pub fn shortest() -> Self {
        CostProfile {
            name: "shortest".into(),
            clearance: false,
            soft_scale: 0.0,
            smoothness_weight: 0.0,
            max_expansions: 0,
            waypoints: WaypointMode::Drop,
            avoid_corners: true,
            ..CostProfile::reference()
        }
    }

    /// The reference "hard only" ablation: no soft terms, no clearance, waypoint runs merged.
    pub fn hard_only() -> Self {
        CostProfile {
            name: "hard_only".into(),
            clearance: false,
            soft_scale: 0.0,
            smoothness_weight: 0.0,
            waypoints: WaypointMode::Collapse,
            avoid_corners: true,
            ..CostProfile::reference()
        }
    }

    /// A radius in metres as cells, `max(1, r / resolution)`.
    pub fn cells(&self, metres: f64, resolution: f64) -> f64 {
        (metres / resolution).max(1.0)
    }

    /// A reason the profile cannot be used, if any (negative or non-finite numbers).
    pub fn validate(&self) -> Result<(), String> {
        let fields = [
            ("near_weight", self.near_weight),
            ("near_radius_m", self.near_radius_m),
            ("far_weight", self.far_weight),
            ("far_sigma_m", self.far_sigma_m),
            ("relative_weight", self.relative_weight),
            ("relative_radius_m", self.relative_radius_m),
            ("path_shape_weight", self.path_shape_weight),
            ("path_shape_radius_m", self.path_shape_radius_m),
            ("clearance_weight", self.clearance_weight),
            ("clearance_radius_m", self.clearance_radius_m),
            ("soft_scale", self.soft_scale),
            ("smoothness_weight", self.smoothness_weight),
            ("goal_radius_m", self.goal_radius_m),
        ];
        for (name, v) in fields {
            if !v.is_finite() || v < 0.0 {
                return Err(format!(
                    "cost profile field `{name}` must be a finite number >= 0, got {v}"
                ));
            }
        }
        Ok(())
    }
}

/// A complete planning problem.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanProblem {
    /// Cells the robot may occupy.
    pub traversable: Grid<bool>,
    /// Cells the clearance term keeps away from; `None` = the non-traversable cells.
    pub obstacles: Option<Grid<bool>>,
    /// Metres per cell.
    pub resolution: f64,
    pub start: Cell,
    pub segments: Vec<SegmentSpec>,
    pub profile: CostProfile,
    /// Distance fields shared by every problem on the same map (see [`crate::context`]); `None`
    /// computes them for this problem alone. When set, they must come from a
    /// [`crate::context::MapContext`] built with this problem's `traversable` and `obstacles`
    /// (`lower_with` guarantees it).
    pub map_fields: Option<std::sync::Arc<crate::context::MapFields>>,
}
