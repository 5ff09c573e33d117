//! Resumable runs: each finished run is stored as `<out>/runs/<key>.json`, where the key is the
//! BLAKE3 hash of the run's description (its config and seed) in canonical JSON. A restarted
//! `reproduce-paper` computes the same keys, finds the finished runs and skips them.
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
use std::path::{Path, PathBuf};

use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::Value;
use thiserror::Error;

use crate::atomic::{AtomicWriteError, write_atomic};

/// A failure to hash, store or load a run.
#[derive(Debug, Error)]
pub(crate) enum ResumeError {
    /// The description or the record could not be turned into JSON.
    #[error("could not serialise the run {what}: {source}")]
    Serialize {
        /// `"description"` or `"record"`.
        what: &'static str,
        /// Why.
        #[source]
        source: serde_json::Error,
    },
    /// A stored run file could not be read.
    #[error("could not read {}: {source}", path.display())]
    Read {
        /// The run file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// A stored run file is not what [`RunStore::store`] writes.
    #[error("{} is not a valid run file: {problem}", path.display())]
    Corrupt {
        /// The run file.
        path: PathBuf,
        /// What is wrong with it.
        problem: String,
    },
    /// Writing a run file failed.
    #[error(transparent)]
    Write(#[from] AtomicWriteError),
}

/// The stable identity of one run: the lowercase hex BLAKE3 hash (64 characters) of its
/// description in canonical JSON (see [`canonical_json`]).
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct RunKey(String);

impl RunKey {
    /// The key of a run described by `description` (typically `(config, seed)` or a struct with
    /// both); equal descriptions give equal keys whatever the order of map entries.
    pub(crate) fn of<D: Serialize + ?Sized>(description: &D) -> Result<Self, ResumeError> {
        let canonical = canonical_json(description)?;
        Ok(Self(
            blake3::hash(canonical.as_bytes()).to_hex().to_string(),
        ))
    }

    /// The hex digest.
    pub(crate) fn as_str(&self) -> &str {
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
pub(crate) fn canonical_json<T: Serialize + ?Sized>(value: &T) -> Result<String, ResumeError> {
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

/// Version of the run-file layout below; bump it when the layout changes.
const RUN_FILE_FORMAT: u64 = 1;

/// Finished runs under `<out>/runs/`, one JSON file per [`RunKey`]:
/// `{"format": 1, "key": "<hex>", "description": …, "record": …}`. The description is kept so a
/// reader can tell what the run was; the record is whatever the runner stores (e.g. its
/// per-episode curves), read back with [`RunStore::load`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct RunStore {
    folder: PathBuf,
}

impl RunStore {
    /// The store of the output folder `out` (files in `out/runs/`; created on the first store).
    pub(crate) fn new(out: &Path) -> Self {
        Self {
            folder: out.join("runs"),
        }
    }

    /// The file of run `key`.
    pub(crate) fn path(&self, key: &RunKey) -> PathBuf {
        self.folder.join(format!("{key}.json"))
    }

    /// Whether run `key` has been stored. A file exists only once complete (writes are atomic).
    pub(crate) fn is_done(&self, key: &RunKey) -> bool {
        self.path(key).is_file()
    }

    /// Stores a finished run atomically, replacing any previous file of the same key.
    pub(crate) fn store<D, R>(
        &self,
        key: &RunKey,
        description: &D,
        record: &R,
    ) -> Result<(), ResumeError>
    where
        D: Serialize + ?Sized,
        R: Serialize + ?Sized,
    {
        let as_value = |what, value: Result<Value, serde_json::Error>| {
            value.map_err(|source| ResumeError::Serialize { what, source })
        };
        let file = serde_json::json!({
            "format": RUN_FILE_FORMAT,
            "key": key.as_str(),
            "description": as_value("description", serde_json::to_value(description))?,
            "record": as_value("record", serde_json::to_value(record))?,
        });
        let mut text =
            serde_json::to_string_pretty(&file).map_err(|source| ResumeError::Serialize {
                what: "record",
                source,
            })?;
        text.push('\n');
        write_atomic(&self.path(key), text.as_bytes())?;
        Ok(())
    }

    /// Loads the record of run `key`: `Ok(None)` if it was never stored; an error naming the
    /// file if it cannot be read or is not a run file of this key holding an `R`.
    pub(crate) fn load<R: DeserializeOwned>(&self, key: &RunKey) -> Result<Option<R>, ResumeError> {
        let path = self.path(key);
        let text = match std::fs::read_to_string(&path) {
            Ok(text) => text,
            Err(error) if error.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(source) => return Err(ResumeError::Read { path, source }),
        };
        let corrupt = |problem: String| ResumeError::Corrupt {
            path: path.clone(),
            problem,
        };
        let mut file: Value = serde_json::from_str(&text).map_err(|e| corrupt(e.to_string()))?;
        let format = file.get("format").and_then(Value::as_u64);
        if format != Some(RUN_FILE_FORMAT) {
            return Err(corrupt(format!(
                "format is {}, expected {RUN_FILE_FORMAT}",
                file.get("format")
                    .map_or("missing".to_owned(), Value::to_string)
            )));
        }
        if file.get("key").and_then(Value::as_str) != Some(key.as_str()) {
            return Err(corrupt(format!("it does not hold run {key}")));
        }
        let record = file
            .get_mut("record")
            .map(Value::take)
            .ok_or_else(|| corrupt("the field `record` is missing".to_owned()))?;
        serde_json::from_value(record)
            .map(Some)
            .map_err(|e| corrupt(format!("record: {e}")))
    }
}

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, HashMap};

    use serde::Deserialize;

    use super::*;

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

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct Record {
        steps: Vec<u32>,
        returns: Vec<f64>,
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

    #[test]
    fn store_then_load_round_trips_and_marks_done() {
        let dir = tempfile::tempdir().unwrap();
        let store = RunStore::new(dir.path());
        let key = RunKey::of(&description(3)).unwrap();
        assert!(!store.is_done(&key));
        assert_eq!(store.load::<Record>(&key).unwrap(), None);

        let record = Record {
            steps: vec![300, 120, 61],
            returns: vec![-250.5, 40.0, 155.25],
        };
        store.store(&key, &description(3), &record).unwrap();
        assert!(store.is_done(&key));
        assert_eq!(
            store.path(&key),
            dir.path().join("runs").join(format!("{key}.json"))
        );
        assert_eq!(store.load::<Record>(&key).unwrap(), Some(record));
        // Only the run file: no temporary left behind.
        let names: Vec<_> = std::fs::read_dir(dir.path().join("runs"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from(format!("{key}.json"))]);
    }

    #[test]
    fn stored_floats_come_back_bit_for_bit() {
        // A resumed run must produce the same outputs as an uninterrupted one, so every f64 must
        // survive the JSON round trip exactly (serde_json's `float_roundtrip` feature).
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
        let dir = tempfile::tempdir().unwrap();
        let store = RunStore::new(dir.path());
        let key = RunKey::of(&"floats").unwrap();
        store.store(&key, &"floats", &values).unwrap();
        let loaded: Vec<f64> = store.load(&key).unwrap().unwrap();
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

    #[test]
    fn bad_run_files_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let store = RunStore::new(dir.path());
        let key = RunKey::of(&description(1)).unwrap();
        let other = RunKey::of(&description(2)).unwrap();
        std::fs::create_dir_all(dir.path().join("runs")).unwrap();

        std::fs::write(store.path(&key), "{ not json").unwrap();
        let error = store.load::<Record>(&key).unwrap_err();
        assert!(matches!(error, ResumeError::Corrupt { .. }));
        assert!(
            error.to_string().contains(&format!("{key}.json")),
            "{error}"
        );

        // A file holding another run (e.g. copied by hand) is refused.
        store.store(&other, &description(2), &vec![1, 2]).unwrap();
        std::fs::copy(store.path(&other), store.path(&key)).unwrap();
        let error = store.load::<Vec<u32>>(&key).unwrap_err();
        assert!(error.to_string().contains("does not hold run"), "{error}");

        // A record of the wrong shape is refused.
        let error = store.load::<Record>(&other).unwrap_err();
        assert!(error.to_string().contains("record:"), "{error}");
    }
}
