//! Benchmark suites generated from real ProcTHOR houses.
//!
//! A suite directory mirrors the Map2Route resource layout so that either tool can read it:
//!
//! ```text
//! <suite>/suite.json                                            manifest (scenes, episodes, config)
//! <suite>/maps/<map_id>/<map_id>.json                           Map2Route layered map
//! <suite>/instructions/<map_id>/instruction_files/instruction_<id:06>.json
//! <suite>/programs/<map_id>/instruction_<id:06>.m2r             gold program (also inside the JSON)
//! ```
//!
//! Everything is a pure function of the houses and the seed: per-episode RNG seeds are derived
//! from (seed, map key, episode id), scenes are processed in parallel but written to fixed paths,
//! and the manifest lists scenes and episodes in rank / id order.

pub mod annotate;
pub mod avoid;
pub mod dest;
pub mod determinacy;
pub mod generate;
pub mod houses;
pub mod index;
pub mod lexicon;
pub mod naturalness;
pub mod paper;
pub mod paths;
pub mod place;
pub mod plan;
pub mod realise;
pub mod refs;
pub mod render;
pub mod stats;

use crate::episode::Episode;
use crate::methods::{Method, PreparedMap};
use crate::runner::write_atomic;
use generate::{Difficulty, GeneratedEpisode, Scene, mix};
use index::MapIndex;
use m2rc_stdlib::import::{AssetDb, ImportOptions, import_house_document};
use m2rc_stdlib::map::MapDocument;
use rand::SeedableRng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::path::{Path, PathBuf};

pub const MANIFEST: &str = "suite.json";

#[derive(Debug, thiserror::Error)]
pub enum SuiteError {
    #[error("{path}: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    #[error("{0}")]
    Input(String),
}

impl SuiteError {
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        SuiteError::Io {
            path: path.display().to_string(),
            source,
        }
    }
}

/// What to build. The default mirrors the paper: 40 evaluation scenes and 4 development scenes,
/// 25 episodes per scene, 30% Hard.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SuiteConfig {
    pub name: String,
    pub scenes: usize,
    pub dev_scenes: usize,
    pub episodes_per_scene: usize,
    pub hard_fraction: f64,
    pub seed: u64,
}

impl Default for SuiteConfig {
    fn default() -> Self {
        SuiteConfig {
            name: "map2route-procthor".into(),
            scenes: 40,
            dev_scenes: 4,
            episodes_per_scene: 25,
            hard_fraction: 0.3,
            seed: 0,
        }
    }
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SceneEntry {
    pub map_id: String,
    /// The key written into instructions: `procthor/<map_id>`.
    pub map_key: String,
    /// `eval` or `dev`.
    pub split: String,
    /// Where the house came from (`file:line`).
    pub house: String,
    pub rank: usize,
    pub rooms: usize,
    pub area_m2: f64,
    pub file: String,
    /// Episodes the generator could not produce for this scene (fewer than requested).
    pub shortfall: usize,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EpisodeEntry {
    pub map_id: String,
    pub id: u32,
    pub instruction_id: String,
    pub split: String,
    pub difficulty: Difficulty,
    pub file: String,
    pub program: String,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SuiteManifest {
    pub format: String,
    pub config: SuiteConfig,
    pub houses: String,
    pub scenes: Vec<SceneEntry>,
    pub episodes: Vec<EpisodeEntry>,
}

impl SuiteManifest {
    pub fn read(dir: &Path) -> Result<SuiteManifest, SuiteError> {
        let path = dir.join(MANIFEST);
        let text = std::fs::read_to_string(&path).map_err(|e| SuiteError::io(&path, e))?;
        serde_json::from_str(&text)
            .map_err(|e| SuiteError::Input(format!("{}: {e}", path.display())))
    }

    /// The map file of a scene, under the suite directory.
    pub fn map_path(&self, dir: &Path, map_id: &str) -> Option<PathBuf> {
        self.scenes
            .iter()
            .find(|s| s.map_id == map_id)
            .map(|s| dir.join(&s.file))
    }
}

/// Turns a house JSON into a semantic map (the ProcTHOR importer), and keeps or rejects a
/// generated episode (the compiler-backed validity check). Supplied by the caller so that the
/// suite can be built with whatever importer and validator the build has.
pub trait SceneTools: Sync {
    fn import(&self, house: &Value, map_id: &str) -> Result<MapDocument, String>;
    /// `Ok(())` keeps the episode; `Err(reason)` drops it.
    fn validate(&self, map: &PreparedMap, episode: &GeneratedEpisode) -> Result<(), String>;
}

/// Progress callback: called once per finished scene with (scene map_id, episodes kept).
pub type Progress<'a> = &'a (dyn Fn(&str, usize) + Sync);

/// Builds a suite from `houses` into `out`. Scenes that cannot be imported are reported as errors;
/// scenes where fewer episodes validate than requested are recorded with a shortfall.
pub fn build_suite(
    houses_path: &Path,
    config: &SuiteConfig,
    tools: &dyn SceneTools,
    out: &Path,
    progress: Progress<'_>,
) -> Result<SuiteManifest, SuiteError> {
    let houses = houses::read_houses(houses_path)?;
    let ranked = houses::rank_houses(&houses);
    let wanted = config.scenes + config.dev_scenes;
    if ranked.len() < wanted {
        return Err(SuiteError::Input(format!(
            "{}: {} multi-room houses, but {} scenes were requested",
            houses_path.display(),
            ranked.len(),
            wanted
        )));
    }
    if !(0.0..=1.0).contains(&config.hard_fraction) {
        return Err(SuiteError::Input(format!(
            "hard fraction {} is not within 0..1",
            config.hard_fraction
        )));
    }
    let jobs: Vec<(usize, &houses::House)> = ranked.into_iter().take(wanted).enumerate().collect();
    let results: Vec<Result<(SceneEntry, Vec<EpisodeEntry>), SuiteError>> = jobs
        .par_iter()
        .map(|&(rank, house)| {
            let split = if rank < config.scenes { "eval" } else { "dev" };
            let map_id = format!(
                "{:03}_{}",
                rank + 1,
                if split == "eval" { "valunseen" } else { "dev" }
            );
            let r = build_scene(house, rank, split, &map_id, config, tools, out);
            if let Ok((_, eps)) = &r {
                progress(&map_id, eps.len());
            }
            r
        })
        .collect();
    let mut scenes = Vec::new();
    let mut episodes = Vec::new();
    for r in results {
        let (scene, eps) = r?;
        scenes.push(scene);
        episodes.extend(eps);
    }
    let manifest = SuiteManifest {
        format: "m2rc-suite/1".into(),
        config: config.clone(),
        houses: if houses_path == Path::new("-") {
            houses::STDIN_NAME.to_string()
        } else {
            houses_path.display().to_string()
        },
        scenes,
        episodes,
    };
    let bytes = serde_json::to_vec_pretty(&manifest).expect("manifest serializes");
    write_atomic(&out.join(MANIFEST), &bytes)
        .map_err(|e| SuiteError::io(&out.join(MANIFEST), e))?;
    Ok(manifest)
}

fn build_scene(
    house: &houses::House,
    rank: usize,
    split: &str,
    map_id: &str,
    config: &SuiteConfig,
    tools: &dyn SceneTools,
    out: &Path,
) -> Result<(SceneEntry, Vec<EpisodeEntry>), SuiteError> {
    let map_key = format!("procthor/{map_id}");
    let doc = tools
        .import(&house.json, map_id)
        .map_err(|e| SuiteError::Input(format!("{}: cannot import: {e}", house.source)))?;
    let map_file = format!("maps/{map_id}/{map_id}.json");
    let bytes = m2rc_stdlib::map::write_map_document_json(&doc);
    write_atomic(&out.join(&map_file), &bytes)
        .map_err(|e| SuiteError::io(&out.join(&map_file), e))?;

    let prepared = PreparedMap::new(doc.map);
    let scene = Scene::new(MapIndex::new(&prepared.map), map_key.clone());
    let k = config.episodes_per_scene;
    let hard = (k as f64 * config.hard_fraction).round() as usize;
    let mut plan: Vec<Difficulty> = (0..k)
        .map(|i| {
            if i < hard {
                Difficulty::Hard
            } else {
                Difficulty::Easy
            }
        })
        .collect();
    plan.shuffle(&mut ChaCha8Rng::seed_from_u64(mix(
        config.seed,
        &map_key,
        0,
    )));

    // Candidate episode numbers are tried in order; ids of kept episodes are renumbered 1..=k so
    // that a suite has no gaps. Each slot gets a bounded number of tries.
    let mut entries = Vec::new();
    let mut candidate = 0u32;
    for difficulty in plan {
        for _ in 0..4 {
            candidate += 1;
            let id = entries.len() as u32 + 1;
            let Some(mut ep) = scene.episode(config.seed, candidate, difficulty) else {
                continue;
            };
            ep.set_id(id);
            if tools.validate(&prepared, &ep).is_err() {
                continue;
            }
            entries.push(write_episode(
                out,
                map_id,
                split,
                &ep,
                config.seed,
                &house.source,
            )?);
            break;
        }
    }
    let shortfall = k - entries.len();
    let entry = SceneEntry {
        map_id: map_id.to_string(),
        map_key,
        split: split.to_string(),
        house: house.source.clone(),
        rank: rank + 1,
        rooms: house.rooms,
        area_m2: (house.area_m2 * 1000.0).round() / 1000.0,
        file: map_file,
        shortfall,
    };
    Ok((entry, entries))
}

fn write_episode(
    out: &Path,
    map_id: &str,
    split: &str,
    ep: &GeneratedEpisode,
    seed: u64,
    house: &str,
) -> Result<EpisodeEntry, SuiteError> {
    let instruction_id = format!("instruction_{:06}", ep.id);
    let file = format!("instructions/{map_id}/instruction_files/{instruction_id}.json");
    let program = format!("programs/{map_id}/{instruction_id}.m2r");
    let mut value = ep.instruction.clone();
    generate::attach_generation(&mut value, seed, house);
    let bytes = serde_json::to_vec(&value).expect("instruction serializes");
    write_atomic(&out.join(&file), &bytes).map_err(|e| SuiteError::io(&out.join(&file), e))?;
    write_atomic(&out.join(&program), ep.program.as_bytes())
        .map_err(|e| SuiteError::io(&out.join(&program), e))?;
    Ok(EpisodeEntry {
        map_id: map_id.to_string(),
        id: ep.id,
        instruction_id,
        split: split.to_string(),
        difficulty: ep.difficulty,
        file,
        program,
    })
}

/// The standard tools: the ProcTHOR importer (with the asset database when given) and validation
/// by running methods on each generated episode and requiring HCS = 1 from every one of them.
/// `suite build` validates with `oracle` (gold program -> compiler -> planner), which checks that
/// every reference of the gold program resolves uniquely and that its route satisfies the
/// annotation, and with `shortest`, which checks the annotation itself is feasible.
pub struct ProcthorTools {
    pub assets: Option<AssetDb>,
    pub import: ImportOptions,
    pub validators: Vec<Box<dyn Method>>,
}

impl SceneTools for ProcthorTools {
    fn import(&self, house: &Value, map_id: &str) -> Result<MapDocument, String> {
        let mut opts = self.import.clone();
        opts.map_id = Some(map_id.to_string());
        import_house_document(house, map_id, self.assets.as_ref(), &opts).map_err(|e| e.to_string())
    }

    fn validate(&self, map: &PreparedMap, ep: &GeneratedEpisode) -> Result<(), String> {
        let parsed = m2rc_grammar::parse(&ep.program);
        if let Some(e) = parsed.errors.first() {
            return Err(format!("gold program does not parse: {e:?}"));
        }
        let episode = Episode::from_value(ep.instruction.clone(), "generated episode")
            .map_err(|e| e.to_string())?;
        // The strict check `eval` relaxes for the reference's files: a suite holds none of it.
        episode
            .check(Some(map.map.n()))
            .map_err(|e| e.to_string())?;
        for method in &self.validators {
            let record = crate::runner::predict_and_score(method.as_ref(), map, &episode, "");
            let hcs = record
                .get("metrics_summary")
                .and_then(|s| s.get("HCS"))
                .and_then(Value::as_f64);
            if hcs != Some(1.0) {
                let why = record.get("error").and_then(Value::as_str).unwrap_or("");
                return Err(format!(
                    "{} scores HCS {hcs:?} on its own annotation {why}",
                    method.name()
                ));
            }
        }
        Ok(())
    }
}
