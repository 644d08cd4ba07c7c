//! Aggregation across episodes, as the reference's summary does: plain means of HCS, PL and
//! H-SPL, and for each soft category a macro average (each episode's mean of its finite raw
//! values, averaged over the episodes that have one), separately for overall, easy and hard.

use super::evaluate::EpisodeMetrics;
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;

/// Display name and the `preference_type` values it collects.
pub const SCS_FIELDS: [(&str, &[&str]); 5] = [
    ("near preference", &["near_preference"]),
    ("far preference", &["far_preference"]),
    ("relative preference", &["relative_preference"]),
    (
        "path-shape preference",
        &["geometric_path_preference", "path_shape_preference"],
    ),
    ("clearance", &["clearance"]),
];

/// One evaluated episode, as the aggregation sees it.
#[derive(Clone, Copy, Debug)]
pub struct EpisodeRecord<'a> {
    pub map_id: &'a str,
    pub instruction_id: &'a str,
    /// `difficulty_level`; anything but easy/hard counts only towards overall.
    pub difficulty: Option<&'a str>,
    pub metrics: &'a EpisodeMetrics,
}

/// Soft averages, keyed by the reference's display names.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ScsBlock {
    #[serde(rename = "near preference")]
    pub near: Option<f64>,
    #[serde(rename = "far preference")]
    pub far: Option<f64>,
    #[serde(rename = "relative preference")]
    pub relative: Option<f64>,
    #[serde(rename = "path-shape preference")]
    pub path_shape: Option<f64>,
    #[serde(rename = "clearance")]
    pub clearance: Option<f64>,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PathEfficiency {
    #[serde(rename = "PL")]
    pub pl: Option<f64>,
    #[serde(rename = "H-SPL")]
    pub h_spl: Option<f64>,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MetricBlock {
    #[serde(rename = "HCS")]
    pub hcs: Option<f64>,
    #[serde(rename = "SCS")]
    pub scs: ScsBlock,
    #[serde(rename = "path efficiency")]
    pub path_efficiency: PathEfficiency,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ScoreBlock {
    pub record_count: usize,
    pub finished_instruction_count: usize,
    pub metric: MetricBlock,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Aggregate {
    pub overall: ScoreBlock,
    pub easy: ScoreBlock,
    pub hard: ScoreBlock,
}

fn mean(values: impl IntoIterator<Item = f64>) -> Option<f64> {
    let v: Vec<f64> = values.into_iter().collect();
    (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64)
}

/// Finite raw values of one episode whose type or source type is in `types`.
pub fn raw_values(metrics: &EpisodeMetrics, types: &[&str]) -> Vec<f64> {
    metrics
        .details
        .soft_constraints
        .iter()
        .filter(|d| {
            d.preference_type
                .as_deref()
                .is_some_and(|t| types.contains(&t))
                || d.source_preference_type
                    .as_deref()
                    .is_some_and(|t| types.contains(&t))
        })
        .filter_map(|d| d.raw_value.filter(|x| x.is_finite()))
        .collect()
}

/// One episode's value per soft category: the mean of its finite raw values (`None` when it has
/// none), the quantity C.7 averages over episodes.
pub fn episode_soft_values(metrics: &EpisodeMetrics) -> ScsBlock {
    let v = |k: usize| mean(raw_values(metrics, SCS_FIELDS[k].1));
    ScsBlock {
        near: v(0),
        far: v(1),
        relative: v(2),
        path_shape: v(3),
        clearance: v(4),
    }
}

fn soft_average(records: &[&EpisodeRecord<'_>], types: &[&str]) -> Option<f64> {
    mean(
        records
            .iter()
            .filter_map(|r| mean(raw_values(r.metrics, types))),
    )
}

/// The metric block of a set of records.
pub fn metric_block(records: &[&EpisodeRecord<'_>]) -> MetricBlock {
    let finite = |x: f64| x.is_finite().then_some(x);
    MetricBlock {
        hcs: mean(records.iter().filter_map(|r| finite(r.metrics.hcs))),
        scs: ScsBlock {
            near: soft_average(records, SCS_FIELDS[0].1),
            far: soft_average(records, SCS_FIELDS[1].1),
            relative: soft_average(records, SCS_FIELDS[2].1),
            path_shape: soft_average(records, SCS_FIELDS[3].1),
            clearance: soft_average(records, SCS_FIELDS[4].1),
        },
        path_efficiency: PathEfficiency {
            pl: mean(records.iter().filter_map(|r| finite(r.metrics.pl))),
            h_spl: mean(
                records
                    .iter()
                    .filter_map(|r| finite(r.metrics.segment_wise_spl)),
            ),
        },
    }
}

fn score_block(records: &[&EpisodeRecord<'_>]) -> ScoreBlock {
    let unique: BTreeSet<(&str, &str)> = records
        .iter()
        .map(|r| (r.map_id, r.instruction_id))
        .collect();
    ScoreBlock {
        record_count: records.len(),
        finished_instruction_count: unique.len(),
        metric: metric_block(records),
    }
}

/// Overall, easy and hard blocks (difficulty compared case-insensitively).
pub fn aggregate(records: &[EpisodeRecord<'_>]) -> Aggregate {
    let level = |r: &EpisodeRecord<'_>| r.difficulty.map(str::to_lowercase);
    let all: Vec<&EpisodeRecord<'_>> = records.iter().collect();
    let easy: Vec<&EpisodeRecord<'_>> = records
        .iter()
        .filter(|r| level(r).as_deref() == Some("easy"))
        .collect();
    let hard: Vec<&EpisodeRecord<'_>> = records
        .iter()
        .filter(|r| level(r).as_deref() == Some("hard"))
        .collect();
    Aggregate {
        overall: score_block(&all),
        easy: score_block(&easy),
        hard: score_block(&hard),
    }
}
