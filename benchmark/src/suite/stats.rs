//! Suite statistics in the shape of the paper's Fig. 2 and the reference
//! `valunseen_dataset_statistics.json`: instruction length, rooms traversed, candidates before
//! disambiguation, reference depth, hard and soft constraint counts, Easy vs Hard; each axis
//! beside the paper's value and the ratio ([`super::paper`]), and the naturalness counters
//! ([`super::naturalness`]).

use super::determinacy::{Counts, Determinacy, KINDS, count_by_kind};
use super::naturalness::Naturalness;
use super::paper::{AXES, TOLERANCE};
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
    /// Length of the reference (shortest legal) route, metres.
    pub reference_route_length_m: Summary,
    pub naturalness: Naturalness,
    /// Mentions whose words, read in their sentence's context, do not pick out the gold's
    /// object, by kind (target 0), beside the mentions checked.
    pub underdetermined_mentions: Counts,
}

impl SplitStats {
    fn per_episode(&self, n: usize) -> f64 {
        if self.episodes == 0 {
            0.0
        } else {
            round3(n as f64 / self.episodes as f64)
        }
    }

    fn hist_mean(h: &BTreeMap<usize, usize>) -> f64 {
        let n: usize = h.values().sum();
        if n == 0 {
            return 0.0;
        }
        round3(h.iter().map(|(k, v)| k * v).sum::<usize>() as f64 / n as f64)
    }

    /// The value of a paper axis ([`super::paper::AXES`]) on this split.
    pub fn axis(&self, axis: &str) -> Option<f64> {
        let soft = |k: &str| self.per_episode(self.soft_by_type.get(k).copied().unwrap_or(0));
        Some(match axis {
            "words per instruction" => self.words_per_instruction.mean,
            "rooms visited" => self.rooms_visited.mean,
            "room transitions" => self.room_transitions.mean,
            "candidates per reference (mean)" => self.candidates_per_reference.mean,
            "candidates per reference (median)" => self.candidates_per_reference.median,
            "candidates per reference (p90)" => self.candidates_per_reference.p90,
            "ambiguity rate" => self.ambiguity_rate,
            "depth per reference" => self.depth_per_reference.mean,
            "episode max depth" => self.episode_max_depth.mean,
            "must-pass per episode (incl. start)" => self.per_episode(self.must_pass),
            "must-avoid per episode" => self.per_episode(self.must_avoid),
            "additional hard constraints per episode" => {
                Self::hist_mean(&self.additional_hard_hist)
            }
            "soft constraints per episode (incl. clearance)" => {
                Self::hist_mean(&self.soft_including_clearance_hist)
            }
            "near preferences per episode" => soft("near"),
            "far preferences per episode" => soft("far"),
            "relative preferences per episode" => soft("relative"),
            "path-shape preferences per episode" => soft("path_shape"),
            "reference route length (m)" => self.reference_route_length_m.mean,
            _ => return None,
        })
    }
}

/// One axis of one split beside the paper.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct VsPaper {
    pub suite: f64,
    pub paper: f64,
    /// suite / paper.
    pub ratio: f64,
    /// Whether the ratio lies within 1 ± [`TOLERANCE`].
    pub within_tolerance: bool,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct AxisRow {
    pub axis: String,
    pub source: String,
    pub easy: VsPaper,
    pub hard: VsPaper,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct UniformHead {
    /// Every object instance, walls, doorways and windows included.
    pub all_objects: f64,
    /// Without walls, doorways, doorframes and windows.
    pub without_building_parts: f64,
}

/// Σ n_c² / Σ n_c of category counts: the expected count of the category of a uniformly drawn
/// instance.
fn size_biased_mean<'c>(counts: impl Iterator<Item = &'c usize>) -> f64 {
    let (mut sum, mut sq) = (0usize, 0usize);
    for &n in counts {
        sum += n;
        sq += n * n;
    }
    if sum == 0 {
        0.0
    } else {
        sq as f64 / sum as f64
    }
}

#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct SuiteStats {
    pub scenes: usize,
    pub objects_per_scene: f64,
    pub rooms_per_scene: f64,
    /// The scale of the candidate axes in these houses: the mean number of candidates of a
    /// reference whose head is an object drawn uniformly from its scene (Σ n_c² / Σ n_c over the
    /// scene's categories, averaged over scenes), with and without the parts of the building. A
    /// suite above it leans on high-count categories; the paper's houses carry more of them.
    pub uniform_head_candidates: UniformHead,
    /// The paper's mean candidates per reference scaled by objects per scene (these scenes' over
    /// the paper's): what the paper's references would count in houses of this size, if each
    /// category's count grows with the house. Easy and Hard.
    pub paper_candidates_at_this_scene_size: [f64; 2],
    pub overall: SplitStats,
    pub easy: SplitStats,
    pub hard: SplitStats,
    /// Every paper axis, Easy and Hard, with the ratio.
    pub vs_paper: Vec<AxisRow>,
}

fn vs(suite: f64, paper: f64) -> VsPaper {
    let ratio = if paper.abs() > 1e-12 {
        round3(suite / paper)
    } else {
        0.0
    };
    VsPaper {
        suite: round3(suite),
        paper: round3(paper),
        ratio,
        within_tolerance: (ratio - 1.0).abs() <= TOLERANCE,
    }
}

/// The comparison rows of a suite's statistics.
pub fn vs_paper(easy: &SplitStats, hard: &SplitStats) -> Vec<AxisRow> {
    AXES.iter()
        .map(|a| AxisRow {
            axis: a.axis.to_string(),
            source: a.source.to_string(),
            easy: vs(easy.axis(a.axis).unwrap_or(0.0), a.easy),
            hard: vs(hard.axis(a.axis).unwrap_or(0.0), a.hard),
        })
        .collect()
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
    length: Vec<f64>,
    naturalness: Naturalness,
    determinacy: Vec<Determinacy>,
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
        if let Some(l) = num("reference_route_length_m") {
            self.length.push(l);
        }
        self.naturalness.add(generation);
        self.naturalness.add_soft(ep.get("soft_constraints"));
        if let Some(d) = generation
            .and_then(|g| g.get("determinacy"))
            .and_then(|d| serde_json::from_value::<Determinacy>(d.clone()).ok())
        {
            self.determinacy.push(d);
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
            reference_route_length_m: Summary::of(&self.length),
            naturalness: self.naturalness.clone(),
            underdetermined_mentions: count_by_kind(self.determinacy.iter()),
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
    let (mut head_all, mut head_things) = (0.0, 0.0);
    for scene in &scenes {
        let path = dir.join(&scene.file);
        let bytes = std::fs::read(&path).map_err(|e| SuiteError::io(&path, e))?;
        let v: Value = serde_json::from_slice(&bytes)
            .map_err(|e| SuiteError::Input(format!("{}: {e}", path.display())))?;
        let instances = v
            .get("object_instances")
            .and_then(Value::as_array)
            .map(Vec::as_slice)
            .unwrap_or(&[]);
        objects += instances.len();
        let mut by_cat: BTreeMap<&str, usize> = BTreeMap::new();
        for o in instances {
            *by_cat
                .entry(o.get("category").and_then(Value::as_str).unwrap_or(""))
                .or_default() += 1;
        }
        head_all += size_biased_mean(by_cat.values());
        head_things += size_biased_mean(
            by_cat
                .iter()
                .filter(|(c, _)| !m2rc_stdlib::map::vocab::is_structure(c))
                .map(|(_, n)| n),
        );
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
    let (easy, hard) = (easy.finish(), hard.finish());
    Ok(SuiteStats {
        scenes: scenes.len(),
        objects_per_scene: round3(objects as f64 / n),
        rooms_per_scene: round3(rooms as f64 / n),
        uniform_head_candidates: UniformHead {
            all_objects: round3(head_all / n),
            without_building_parts: round3(head_things / n),
        },
        paper_candidates_at_this_scene_size: scaled_paper_candidates(objects as f64 / n),
        overall: all.finish(),
        vs_paper: vs_paper(&easy, &hard),
        easy,
        hard,
    })
}

fn scaled_paper_candidates(objects_per_scene: f64) -> [f64; 2] {
    let scale = objects_per_scene / super::paper::OBJECTS_PER_SCENE;
    super::paper::CANDIDATES_MEAN.map(|paper| round3(paper * scale))
}

/// The statistics as a Markdown report: every axis beside the paper's value and the ratio, the
/// naturalness counters, and the histograms.
pub fn stats_markdown(s: &SuiteStats) -> String {
    let mut out = String::new();
    out.push_str(&format!(
        "# Suite statistics\n\n{} scenes, {:.1} objects and {:.2} rooms per scene (paper: 40 scenes, {:.1} objects, {:.2} rooms); {} episodes ({} Easy, {} Hard; paper 700 / 300).\n\n",
        s.scenes,
        s.objects_per_scene,
        s.rooms_per_scene,
        super::paper::OBJECTS_PER_SCENE,
        super::paper::ROOMS_PER_SCENE,
        s.overall.episodes,
        s.easy.episodes,
        s.hard.episodes
    ));
    out.push_str("| axis | Easy | paper | ratio | Hard | paper | ratio |\n|---|---:|---:|---:|---:|---:|---:|\n");
    let mark = |v: &VsPaper| {
        if v.within_tolerance {
            format!("{:.2}", v.ratio)
        } else {
            format!("**{:.2}**", v.ratio)
        }
    };
    for r in &s.vs_paper {
        out.push_str(&format!(
            "| {} | {:.3} | {:.3} | {} | {:.3} | {:.3} | {} |\n",
            r.axis,
            r.easy.suite,
            r.easy.paper,
            mark(&r.easy),
            r.hard.suite,
            r.hard.paper,
            mark(&r.hard)
        ));
    }
    out.push_str(&format!(
        "\nFor scale, in these scenes: a reference to an object drawn uniformly from its scene would have {:.2} candidates on average ({:.2} counting walls, doorways and windows).\n",
        s.uniform_head_candidates.without_building_parts, s.uniform_head_candidates.all_objects
    ));
    let [pe, ph] = s.paper_candidates_at_this_scene_size;
    out.push_str(&format!(
        "Scaled to {:.1} objects per scene, the paper's mean candidates per reference would be {pe:.2} Easy and {ph:.2} Hard.\n",
        s.objects_per_scene
    ));
    out.push_str(&format!(
        "\nRatios in bold lie outside 1 ± {TOLERANCE}.\n\n## Naturalness counters (should all be 0)\n\n| counter | Easy | Hard |\n|---|---:|---:|\n"
    ));
    let (e, h) = (&s.easy.naturalness, &s.hard.naturalness);
    for (name, a, b) in [
        (
            "stacked same-category rooms",
            e.stacked_same_category_rooms,
            h.stacked_same_category_rooms,
        ),
        (
            "singleton superlatives",
            e.singleton_superlatives,
            h.singleton_superlatives,
        ),
        (
            "circular references",
            e.circular_references,
            h.circular_references,
        ),
        (
            "rooms described more than once per episode",
            e.rooms_described_more_than_once,
            h.rooms_described_more_than_once,
        ),
        (
            "preference subjects named like a destination",
            e.preference_subjects_named_like_a_destination,
            h.preference_subjects_named_like_a_destination,
        ),
        (
            "must-avoids named like a destination",
            e.must_avoids_named_like_a_destination,
            h.must_avoids_named_like_a_destination,
        ),
        (
            "objects in two preferences",
            e.objects_in_two_preferences,
            h.objects_in_two_preferences,
        ),
    ] {
        out.push_str(&format!("| {name} | {a} | {b} |\n"));
    }
    out.push_str(&determinacy_markdown(
        &s.easy.underdetermined_mentions,
        &s.hard.underdetermined_mentions,
    ));
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

/// The underdetermined-mention counter: by kind, Easy and Hard, with the mentions checked.
fn determinacy_markdown(e: &Counts, h: &Counts) -> String {
    let mut out = String::from(
        "\n## Underdetermined mentions (should all be 0)\n\nA mention is underdetermined when its words, read in the context its sentence gives, do not pick out the gold's object.\n\n",
    );
    if e.total_checked() + h.total_checked() == 0 {
        out.push_str("This suite records no mention checks (built before the check existed).\n");
        return out;
    }
    out.push_str("| kind | Easy | checked | Hard | checked |\n|---|---:|---:|---:|---:|\n");
    let n = |m: &BTreeMap<String, usize>, k: &str| m.get(k).copied().unwrap_or(0);
    for k in KINDS {
        out.push_str(&format!(
            "| {k} | {} | {} | {} | {} |\n",
            n(&e.underdetermined, k),
            n(&e.checked, k),
            n(&h.underdetermined, k),
            n(&h.checked, k)
        ));
    }
    out.push_str(&format!(
        "| all | {} | {} | {} | {} |\n",
        e.total_underdetermined(),
        e.total_checked(),
        h.total_underdetermined(),
        h.total_checked()
    ));
    out
}
