//! The paper's figures for `suite stats` to compare against: the Map2Route evaluation split
//! (`scripts/statics/valunseen_dataset_statistics.json`: 40 scenes, 700 Easy and 300 Hard
//! episodes; see `../shared/reference/map2route-evaluation-statistics.json`), normalised per
//! episode where the paper gives totals, and the reference-route lengths of issue 14's table.

/// One axis: its name, the paper's Easy and Hard values, and where the number comes from.
pub struct PaperAxis {
    pub axis: &'static str,
    pub easy: f64,
    pub hard: f64,
    pub source: &'static str,
}

/// Object instances per evaluation scene (`per_scene.objects_mean`), walls, doorways and windows
/// included.
pub const OBJECTS_PER_SCENE: f64 = 284.675;
/// Rooms per evaluation scene (`per_scene.rooms_mean`).
pub const ROOMS_PER_SCENE: f64 = 8.55;

/// Mean candidates per reference before disambiguation, Easy and Hard
/// (`candidates_before_disambiguation.mean`).
pub const CANDIDATES_MEAN: [f64; 2] = [6.3, 8.45];

const EASY: f64 = 700.0;
const HARD: f64 = 300.0;

/// The Fig. 2 axes and the per-type soft-constraint rates.
pub const AXES: &[PaperAxis] = &[
    PaperAxis {
        axis: "words per instruction",
        easy: 35.906,
        hard: 102.157,
        source: "instruction_words_mean",
    },
    PaperAxis {
        axis: "rooms visited",
        easy: 4.981,
        hard: 10.34,
        source: "room traversal (E.1)",
    },
    PaperAxis {
        axis: "room transitions",
        easy: 3.981,
        hard: 9.34,
        source: "room_transitions_mean",
    },
    PaperAxis {
        axis: "candidates per reference (mean)",
        easy: CANDIDATES_MEAN[0],
        hard: CANDIDATES_MEAN[1],
        source: "candidates_before_disambiguation.mean",
    },
    PaperAxis {
        axis: "candidates per reference (median)",
        easy: 3.0,
        hard: 3.0,
        source: "candidates_before_disambiguation.median",
    },
    PaperAxis {
        axis: "candidates per reference (p90)",
        easy: 8.0,
        hard: 10.0,
        source: "candidates_before_disambiguation.p90",
    },
    PaperAxis {
        axis: "ambiguity rate",
        easy: 0.819,
        hard: 0.826,
        source: "ambiguity_rate",
    },
    PaperAxis {
        axis: "depth per reference",
        easy: 2.213,
        hard: 2.39,
        source: "reference_depth.per_reference_mean",
    },
    PaperAxis {
        axis: "episode max depth",
        easy: 2.98,
        hard: 3.817,
        source: "reference_depth.episode_max_mean",
    },
    PaperAxis {
        axis: "must-pass per episode (incl. start)",
        easy: 1612.0 / EASY,
        hard: 1208.0 / HARD,
        source: "hard_constraints.must_pass / episodes",
    },
    PaperAxis {
        axis: "must-avoid per episode",
        easy: 130.0 / EASY,
        hard: 175.0 / HARD,
        source: "hard_constraints.must_avoid / episodes",
    },
    PaperAxis {
        axis: "additional hard constraints per episode",
        easy: (426.0 + 2.0 * 218.0 + 3.0 * 45.0 + 4.0 * 10.0 + 5.0) / EASY,
        hard: (4.0 + 2.0 * 26.0 + 3.0 * 118.0 + 4.0 * 101.0 + 5.0 * 37.0 + 6.0 * 14.0) / HARD,
        source: "additional_hard_constraints_per_episode_hist",
    },
    PaperAxis {
        axis: "soft constraints per episode (incl. clearance)",
        easy: (74.0 + 2.0 * 476.0 + 3.0 * 139.0 + 4.0 * 11.0) / EASY,
        hard: (2.0 + 2.0 * 19.0 + 3.0 * 110.0 + 4.0 * 119.0 + 5.0 * 39.0 + 6.0 * 10.0 + 7.0) / HARD,
        source: "soft_constraints_including_clearance_per_episode_hist",
    },
    PaperAxis {
        axis: "near preferences per episode",
        easy: 284.0 / EASY,
        hard: 274.0 / HARD,
        source: "soft_constraints_excluding_clearance.near",
    },
    PaperAxis {
        axis: "far preferences per episode",
        easy: 288.0 / EASY,
        hard: 303.0 / HARD,
        source: "soft_constraints_excluding_clearance.far",
    },
    PaperAxis {
        axis: "relative preferences per episode",
        easy: 126.0 / EASY,
        hard: 98.0 / HARD,
        source: "soft_constraints_excluding_clearance.relative",
    },
    PaperAxis {
        axis: "path-shape preferences per episode",
        easy: 89.0 / EASY,
        hard: 133.0 / HARD,
        source: "soft_constraints_excluding_clearance.path_shape",
    },
    PaperAxis {
        axis: "reference route length (m)",
        easy: 28.0,
        hard: 66.2,
        source: "issue 14 (shortest route over the paper's episodes)",
    },
];

/// An axis is "close" when the suite's value is within this ratio band of the paper's.
pub const TOLERANCE: f64 = 0.25;
