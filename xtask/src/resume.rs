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

use serde::Serialize;
use serde_json::Value;
use thiserror::Error;

/// A run description that cannot be hashed.
#[derive(Debug, Error)]
pub(crate) enum ResumeError {
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

    /// A key read from a run store line whose description was checked to hash to `hex`.
    pub(crate) fn from_verified_hex(hex: String) -> Self {
        Self(hex)
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

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, HashMap};

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
