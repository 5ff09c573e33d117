//! The identity of a run for resuming: the key is the BLAKE3 hash of the run's description (its
//! config and seed) in canonical JSON. A restarted `reproduce-paper` computes the same keys,
//! finds the finished runs in the run store ([`crate::store`]) and skips them.
//!
//! The description must contain everything the run's result depends on: the full config of the
//! method and task, the seed, and a version of the code that computes it (e.g. the `eamadm`
//! crate version or a "results format" number bumped on numeric changes) — otherwise a stale
//! result would be reused after the code changes.
//!
//! Records come back bit for bit (xtask turns on `serde_json`'s `float_roundtrip`; without it
//! about a third of arbitrary `f64`s change in the last bit), so a resumed run's outputs equal an
//! uninterrupted run's.

use std::fmt;

use eamadm::{Experiment, ExperimentConfig, MethodSpec};
use serde::Serialize;
use serde_json::Value;
use thiserror::Error;

/// Version of the numbers a run produces, in the resume key: bump it when a change of code
/// changes results without changing the config or the crate version, so that stored runs are
/// not reused.
pub const RESULTS_FORMAT: u32 = 3;

/// What identifies a run for resuming: everything its record depends on.
#[derive(Debug, Serialize)]
pub struct RunDescription {
    /// [`RESULTS_FORMAT`].
    pub results_format: u32,
    /// The `eamadm` (workspace) version.
    pub crate_version: &'static str,
    /// The experiment's config with this method only, and the seed fields neutral (the seed is
    /// below), so the same run is recognised whatever `--seeds` or `--method` selected.
    pub config: ExperimentConfig,
    /// The run's seed.
    pub seed: u64,
    /// BLAKE3 of the file the task reads (a maze map or robot scenario named by path), whose
    /// content the config does not hold; absent for the embedded presets.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub task_file_blake3: Option<String>,
}

impl RunDescription {
    /// The description of running `method` with `seed` in `experiment`. The hash of a file
    /// the task names is taken of the bytes the experiment's task was built from
    /// ([`eamadm::Task::input_text`], read once when the experiment was loaded), never of the
    /// file as it is now: a file replaced during a run changes neither what the run computes
    /// nor the key it is stored under (the next invocation, loading the new file, sees new
    /// keys and computes new runs).
    pub fn new(experiment: &Experiment, method: &MethodSpec, seed: u64) -> Self {
        let config = ExperimentConfig {
            methods: vec![method.clone()],
            seeds: 1,
            base_seed: 0,
            ..experiment.config().clone()
        };
        Self {
            results_format: RESULTS_FORMAT,
            crate_version: env!("CARGO_PKG_VERSION"),
            task_file_blake3: task_input_digest(experiment),
            config,
            seed,
        }
    }
}

/// The BLAKE3 hash (hex) of the text of the file `experiment`'s task names, as read when its
/// task was loaded; `None` for a task the config holds whole.
pub(crate) fn task_input_digest(experiment: &Experiment) -> Option<String> {
    experiment
        .task()
        .input_text()
        .map(|text| blake3::hash(text.as_bytes()).to_hex().to_string())
}

/// A run description that cannot be hashed.
#[derive(Debug, Error)]
pub enum ResumeError {
    /// The description could not be turned into JSON.
    #[error("could not serialise the run {what}: {source}")]
    Serialize {
        /// `"description"`.
        what: &'static str,
        /// Why.
        #[source]
        source: serde_json::Error,
    },
}

/// The stable identity of one run: the lowercase hex BLAKE3 hash (64 characters) of its
/// description in canonical JSON (see [`canonical_json`]).
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RunKey(String);

impl RunKey {
    /// The key of a run described by `description` (typically `(config, seed)` or a struct with
    /// both); equal descriptions give equal keys whatever the order of map entries.
    pub fn of<D: Serialize + ?Sized>(description: &D) -> Result<Self, ResumeError> {
        let canonical = canonical_json(description)?;
        Ok(Self(
            blake3::hash(canonical.as_bytes()).to_hex().to_string(),
        ))
    }

    /// A key read from a run store line whose description was checked to hash to `hex`.
    pub fn from_verified_hex(hex: String) -> Self {
        Self(hex)
    }

    /// The hex digest.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for RunKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// Serialises `value` to compact JSON with every object's keys in sorted (byte) order, so that
/// the text does not depend on field or map insertion order — nor on whether some crate in the
/// build turned on the `preserve_order` feature of `serde_json`. Non-finite floats become `null`,
/// as `serde_json` writes them.
pub fn canonical_json<T: Serialize + ?Sized>(value: &T) -> Result<String, ResumeError> {
    let value = serde_json::to_value(value).map_err(|source| ResumeError::Serialize {
        what: "description",
        source,
    })?;
    let mut text = String::new();
    write_canonical(&value, &mut text);
    Ok(text)
}

fn write_canonical(value: &Value, out: &mut String) {
    match value {
        Value::Object(map) => {
            let mut entries: Vec<(&String, &Value)> = map.iter().collect();
            entries.sort_by(|a, b| a.0.cmp(b.0));
            out.push('{');
            for (index, (key, item)) in entries.into_iter().enumerate() {
                if index > 0 {
                    out.push(',');
                }
                // A JSON string's Display is its quoted, escaped form.
                out.push_str(&Value::String(key.clone()).to_string());
                out.push(':');
                write_canonical(item, out);
            }
            out.push('}');
        }
        Value::Array(items) => {
            out.push('[');
            for (index, item) in items.iter().enumerate() {
                if index > 0 {
                    out.push(',');
                }
                write_canonical(item, out);
            }
            out.push(']');
        }
        scalar => out.push_str(&scalar.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, HashMap};

    use super::*;
    use eamadm::ExperimentConfig;

    #[test]
    fn the_key_ignores_other_methods_and_the_seed_count() {
        let config = eamadm::paper::task1();
        let method = config.method("softmax").unwrap().clone();
        let key = |config: &ExperimentConfig, seed| {
            let experiment = Experiment::new(config.clone()).unwrap();
            RunKey::of(&RunDescription::new(&experiment, &method, seed)).unwrap()
        };
        let mut fewer = config.clone();
        fewer.seeds = 3;
        fewer.methods.truncate(4);
        assert_eq!(key(&config, 2), key(&fewer, 2));
        assert_ne!(key(&config, 2), key(&config, 3));
        let mut other = config.clone();
        other.episodes = 199;
        assert_ne!(key(&config, 2), key(&other, 2));
    }

    #[test]
    fn the_key_follows_the_bytes_the_task_was_built_from() {
        let dir = tempfile::tempdir().unwrap();
        let map = dir.path().join("maze.map");
        std::fs::write(&map, "S..\n.#.\n..T\n").unwrap();
        let mut config = eamadm::paper::task1();
        config.task = eamadm::TaskConfig::MazeFile {
            path: map.clone(),
            rewards: eamadm::mazes::Preset::Task1,
            step_cap: None,
        };
        let method = config.methods[1].clone();
        let key = |experiment: &Experiment| {
            RunKey::of(&RunDescription::new(experiment, &method, 0)).unwrap()
        };
        let loaded = Experiment::new(config.clone()).unwrap();
        let before = key(&loaded);
        // The file replaced after loading (an editor saving, a sync tool): the loaded
        // experiment's key is still that of the bytes it was built from (9dc06af read the file
        // again for every key, so a key named the new map while the task ran on the old).
        std::fs::write(&map, "S.#\n...\n..T\n").unwrap();
        assert_eq!(key(&loaded), before);
        assert_eq!(
            RunDescription::new(&loaded, &method, 0).task_file_blake3,
            Some(blake3::hash(b"S..\n.#.\n..T\n").to_hex().to_string())
        );
        // Loading it again reads the new file: another key.
        assert_ne!(key(&Experiment::new(config).unwrap()), before);
        // The presets carry no file, so their keys do not change with this field.
        let preset = Experiment::new(eamadm::paper::task1()).unwrap();
        let preset = RunDescription::new(&preset, &method, 0);
        assert_eq!(preset.task_file_blake3, None);
        assert!(!canonical_json(&preset).unwrap().contains("task_file"));
    }

    #[derive(Serialize)]
    struct Description<'a> {
        task: &'a str,
        method: &'a str,
        alpha: f64,
        episodes: u32,
        seed: u64,
    }

    fn description(seed: u64) -> Description<'static> {
        Description {
            task: "task1",
            method: "ea-madm",
            alpha: 0.1,
            episodes: 200,
            seed,
        }
    }

    #[test]
    fn same_description_same_key_and_different_seed_different_key() {
        let a = RunKey::of(&description(7)).unwrap();
        let b = RunKey::of(&description(7)).unwrap();
        let c = RunKey::of(&description(8)).unwrap();
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_eq!(a.as_str().len(), 64);
        assert!(a.as_str().chars().all(|ch| ch.is_ascii_hexdigit()));
    }

    #[test]
    fn key_is_pinned() {
        // Changing the hashing scheme silently invalidates every stored run: this test makes it
        // a deliberate act.
        assert_eq!(
            canonical_json(&description(7)).unwrap(),
            r#"{"alpha":0.1,"episodes":200,"method":"ea-madm","seed":7,"task":"task1"}"#
        );
        assert_eq!(
            RunKey::of(&description(7)).unwrap().as_str(),
            blake3::hash(
                br#"{"alpha":0.1,"episodes":200,"method":"ea-madm","seed":7,"task":"task1"}"#
            )
            .to_hex()
            .as_str()
        );
    }

    #[test]
    fn map_order_does_not_matter() {
        let mut forward = HashMap::new();
        let mut backward = HashMap::new();
        for i in 0..50 {
            forward.insert(format!("k{i}"), i);
        }
        for i in (0..50).rev() {
            backward.insert(format!("k{i}"), i);
        }
        let sorted: BTreeMap<_, _> = forward.clone().into_iter().collect();
        let key = RunKey::of(&sorted).unwrap();
        assert_eq!(RunKey::of(&forward).unwrap(), key);
        assert_eq!(RunKey::of(&backward).unwrap(), key);
        // Nested objects too, whatever serde_json's map type.
        let x = serde_json::json!({"b": {"y": 1, "x": [2, {"q": 3, "p": 4}]}, "a": "s\"t"});
        assert_eq!(
            canonical_json(&x).unwrap(),
            r#"{"a":"s\"t","b":{"x":[2,{"p":4,"q":3}],"y":1}}"#
        );
    }
}

#[cfg(test)]
mod float_tests {
    #[test]
    fn stored_floats_come_back_bit_for_bit() {
        // A resumed run must produce the same outputs as an uninterrupted one, so every f64 must
        // survive the JSON round trip of the run store exactly (serde_json's `float_roundtrip`).
        let mut state = 0x9E37_79B9_7F4A_7C15_u64;
        let values: Vec<f64> = (0..20_000)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                f64::from_bits(state)
            })
            .filter(|v| v.is_finite())
            .chain([0.1, 1.0 / 3.0, -155.25, 5e-324, f64::MAX, f64::MIN_POSITIVE])
            .collect();
        let text = serde_json::to_vec(&values).unwrap();
        let loaded: Vec<f64> = serde_json::from_slice(&text).unwrap();
        let differing = values
            .iter()
            .zip(&loaded)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(loaded.len(), values.len());
        assert_eq!(
            differing,
            0,
            "{differing} of {} values changed",
            values.len()
        );
    }
}
