//! Suite statistics in the shape of the paper's Fig. 2 and the reference
//! `valunseen_dataset_statistics.json`: instruction length, rooms traversed, candidates before
//! disambiguation, reference depth, hard and soft constraint counts, Easy vs Hard.

use super::{SuiteError, SuiteManifest};
use crate::episode::GENERATION_KEY;
use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;

/// Summary of a numeric sample.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Summary {
    pub count: usize,
    pub mean: f64,
    pub median: f64,
    pub p90: f64,
    pub max: f64,
}

impl Summary {
    pub fn of(values: &[f64]) -> Summary {
        if values.is_empty() {
            return Summary::default();
        }
        let mut v = values.to_vec();
        v.sort_by(f64::total_cmp);
        let q = |p: f64| v[((p * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
        Summary {
            count: v.len(),
            mean: round3(v.iter().sum::<f64>() / v.len() as f64),
            median: q(0.5),
            p90: q(0.9),
            max: v[v.len() - 1],
        }
    }
}

/// Statistics of one split (overall, easy or hard).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SplitStats {
    pub episodes: usize,
    pub words_per_instruction: Summary,
    pub chars_per_instruction: Summary,
    pub rooms_visited: Summary,
    pub room_transitions: Summary,
    pub candidates_per_reference: Summary,
    pub ambiguity_rate: f64,
    pub depth_per_reference: Summary,
    pub episode_max_depth: Summary,
    pub must_pass: usize,
    pub must_avoid: usize,
    /// Hard constraints beyond the start anchor, per episode: histogram.
    pub additional_hard_hist: BTreeMap<usize, usize>,
    /// Soft constraints including the clearance entry, per episode: histogram.
    pub soft_including_clearance_hist: BTreeMap<usize, usize>,
    /// Non-clearance soft constraints by type.
    pub soft_by_type: BTreeMap<String, usize>,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SuiteStats {
    pub scenes: usize,
    pub objects_per_scene: f64,
    pub rooms_per_scene: f64,
    pub overall: SplitStats,
    pub easy: SplitStats,
    pub hard: SplitStats,
}

#[derive(Default)]
struct Acc {
    episodes: usize,
    words: Vec<f64>,
    chars: Vec<f64>,
    rooms: Vec<f64>,
    transitions: Vec<f64>,
    candidates: Vec<f64>,
    depth: Vec<f64>,
    max_depth: Vec<f64>,
    must_pass: usize,
    must_avoid: usize,
    additional: BTreeMap<usize, usize>,
    soft_hist: BTreeMap<usize, usize>,
    soft_by_type: BTreeMap<String, usize>,
}

impl Acc {
    fn add(&mut self, ep: &Value) {
        self.episodes += 1;
        let text = ep.get("instruction").and_then(Value::as_str).unwrap_or("");
        self.words.push(text.split_whitespace().count() as f64);
        self.chars
            .push(text.chars().filter(|c| !c.is_whitespace()).count() as f64);
        let generation = ep.get(GENERATION_KEY);
        let num = |k: &str| generation.and_then(|g| g.get(k)).and_then(Value::as_f64);
        if let Some(r) = num("rooms_visited") {
            self.rooms.push(r);
        }
        if let Some(t) = num("room_transitions") {
            self.transitions.push(t);
        }
        let refs = generation
            .and_then(|g| g.get("references"))
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        let mut ep_max = 0.0f64;
        for r in &refs {
            if let Some(c) = r.get("candidates").and_then(Value::as_f64) {
                self.candidates.push(c);
            }
            if let Some(d) = r.get("depth").and_then(Value::as_f64) {
                self.depth.push(d);
                ep_max = ep_max.max(d);
            }
        }
        if !refs.is_empty() {
            self.max_depth.push(ep_max);
        }
        let hard = ep
            .get("hard_constraints")
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        let kind = |c: &Value| {
            c.get("kind")
                .and_then(Value::as_str)
                .unwrap_or("")
                .to_string()
        };
        self.must_pass += hard.iter().filter(|c| kind(c) == "must_pass").count();
        self.must_avoid += hard.iter().filter(|c| kind(c) == "must_avoid").count();
        *self
            .additional
            .entry(hard.len().saturating_sub(1))
            .or_default() += 1;
        let soft = ep
            .get("soft_constraints")
            .and_then(Value::as_array)
            .cloned()
            .unwrap_or_default();
        *self.soft_hist.entry(soft.len()).or_default() += 1;
        for s in &soft {
            let t = s
                .get("preference_type")
                .and_then(Value::as_str)
                .unwrap_or("unknown");
            let t = match t {
                "near_preference" => "near",
                "far_preference" => "far",
                "relative_preference" => "relative",
                "path_shape_preference" | "geometric_path_preference" => "path_shape",
                "clearance" => continue,
                other => other,
            };
            *self.soft_by_type.entry(t.to_string()).or_default() += 1;
        }
    }

    fn finish(&self) -> SplitStats {
        let ambiguous = self.candidates.iter().filter(|&&c| c > 1.0).count();
        SplitStats {
            episodes: self.episodes,
            words_per_instruction: Summary::of(&self.words),
            chars_per_instruction: Summary::of(&self.chars),
            rooms_visited: Summary::of(&self.rooms),
            room_transitions: Summary::of(&self.transitions),
            candidates_per_reference: Summary::of(&self.candidates),
            ambiguity_rate: if self.candidates.is_empty() {
                0.0
            } else {
                round3(ambiguous as f64 / self.candidates.len() as f64)
            },
            depth_per_reference: Summary::of(&self.depth),
            episode_max_depth: Summary::of(&self.max_depth),
            must_pass: self.must_pass,
            must_avoid: self.must_avoid,
            additional_hard_hist: self.additional.clone(),
            soft_including_clearance_hist: self.soft_hist.clone(),
            soft_by_type: self.soft_by_type.clone(),
        }
    }
}

fn round3(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// Computes the statistics of the evaluation split of a suite directory (`split` = `eval`, `dev`,
/// or `all`).
pub fn suite_stats(dir: &Path, split: &str) -> Result<SuiteStats, SuiteError> {
    let manifest = SuiteManifest::read(dir)?;
    let (mut all, mut easy, mut hard) = (Acc::default(), Acc::default(), Acc::default());
    let scenes: Vec<_> = manifest
        .scenes
        .iter()
        .filter(|s| split == "all" || s.split == split)
        .collect();
    let (mut objects, mut rooms) = (0usize, 0usize);
    for scene in &scenes {
        let path = dir.join(&scene.file);
        let bytes = std::fs::read(&path).map_err(|e| SuiteError::io(&path, e))?;
        let v: Value = serde_json::from_slice(&bytes)
            .map_err(|e| SuiteError::Input(format!("{}: {e}", path.display())))?;
        objects += v
            .get("object_instances")
            .and_then(Value::as_array)
            .map_or(0, Vec::len);
        rooms += v
            .get("room_instances")
            .and_then(Value::as_array)
            .map_or(0, Vec::len);
    }
    for e in manifest
        .episodes
        .iter()
        .filter(|e| split == "all" || e.split == split)
    {
        let path = dir.join(&e.file);
        let bytes = std::fs::read(&path).map_err(|err| SuiteError::io(&path, err))?;
        let v: Value = serde_json::from_slice(&bytes)
            .map_err(|err| SuiteError::Input(format!("{}: {err}", path.display())))?;
        all.add(&v);
        match v.get("difficulty_level").and_then(Value::as_str) {
            Some("hard") => hard.add(&v),
            _ => easy.add(&v),
        }
    }
    let n = scenes.len().max(1) as f64;
    Ok(SuiteStats {
        scenes: scenes.len(),
        objects_per_scene: round3(objects as f64 / n),
        rooms_per_scene: round3(rooms as f64 / n),
        overall: all.finish(),
        easy: easy.finish(),
        hard: hard.finish(),
    })
}

/// The statistics as a Markdown report, with the paper's evaluation-split values alongside.
pub fn stats_markdown(s: &SuiteStats) -> String {
    let mut out = String::new();
    out.push_str(&format!(
        "# Suite statistics\n\n{} scenes, {:.1} objects and {:.2} rooms per scene (paper: 40 scenes, 284.7 objects, 8.55 rooms).\n\n",
        s.scenes, s.objects_per_scene, s.rooms_per_scene
    ));
    out.push_str("| statistic | overall | easy | hard | paper (overall / easy / hard) |\n|---|---:|---:|---:|---|\n");
    let row = |name: &str, f: &dyn Fn(&SplitStats) -> String, paper: &str| {
        format!(
            "| {name} | {} | {} | {} | {paper} |\n",
            f(&s.overall),
            f(&s.easy),
            f(&s.hard)
        )
    };
    out.push_str(&row(
        "episodes",
        &|x| x.episodes.to_string(),
        "1000 / 700 / 300",
    ));
    out.push_str(&row(
        "words per instruction",
        &|x| format!("{:.1}", x.words_per_instruction.mean),
        "55.8 / 35.9 / 102.2",
    ));
    out.push_str(&row(
        "rooms visited",
        &|x| format!("{:.2}", x.rooms_visited.mean),
        "6.59 / 4.98 / 10.34",
    ));
    out.push_str(&row(
        "room transitions",
        &|x| format!("{:.2}", x.room_transitions.mean),
        "5.59 / 3.98 / 9.34",
    ));
    out.push_str(&row(
        "candidates per reference (mean / median / p90)",
        &|x| {
            let c = &x.candidates_per_reference;
            format!("{:.2} / {} / {}", c.mean, c.median, c.p90)
        },
        "- / 6.30, 3, 8 / 8.45, 3, 10",
    ));
    out.push_str(&row(
        "ambiguity rate",
        &|x| format!("{:.3}", x.ambiguity_rate),
        "- / 0.819 / 0.826",
    ));
    out.push_str(&row(
        "depth per reference",
        &|x| format!("{:.2}", x.depth_per_reference.mean),
        "- / 2.21 / 2.39",
    ));
    out.push_str(&row(
        "episode max depth",
        &|x| format!("{:.2}", x.episode_max_depth.mean),
        "- / 2.98 / 3.82",
    ));
    out.push_str(&row(
        "must-pass (incl. start)",
        &|x| x.must_pass.to_string(),
        "2820 / 1612 / 1208",
    ));
    out.push_str(&row(
        "must-avoid",
        &|x| x.must_avoid.to_string(),
        "305 / 130 / 175",
    ));
    for kind in ["near", "far", "relative", "path_shape"] {
        out.push_str(&row(
            &format!("soft: {kind}"),
            &|x| x.soft_by_type.get(kind).copied().unwrap_or(0).to_string(),
            match kind {
                "near" => "558 / 284 / 274",
                "far" => "591 / 288 / 303",
                "relative" => "224 / 126 / 98",
                _ => "222 / 89 / 133",
            },
        ));
    }
    let hist = |h: &BTreeMap<usize, usize>| {
        h.iter()
            .map(|(k, v)| format!("{k}:{v}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    out.push_str(&format!(
        "\nAdditional hard constraints per episode (count:episodes): easy {}; hard {}.\n",
        hist(&s.easy.additional_hard_hist),
        hist(&s.hard.additional_hard_hist)
    ));
    out.push_str(&format!(
        "Soft constraints incl. clearance per episode: easy {}; hard {}.\n",
        hist(&s.easy.soft_including_clearance_hist),
        hist(&s.hard.soft_including_clearance_hist)
    ));
    out
}
