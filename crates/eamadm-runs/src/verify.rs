//! Recomputing stored results to see that they are what their configs compute: the answer to
//! forgery, which checksums cannot give.
//!
//! # What the checksums guard, and what they do not
//!
//! Every run line and pre-trained artefact carries a BLAKE3 checksum of its content, and its
//! name or key is the hash of its description: they catch faults (a flipped bit, a torn write,
//! a file cut short or renamed). They do not catch forgery: anyone who can write the output
//! folder or the artefact cache can change a result and recompute the checksums, and the
//! store will trust it. [`verify_run`] and [`verify_artefact`] recompute a stored result from
//! its config (the artefact from scratch, never from the cache) and compare it byte for byte
//! with what is stored; `cargo xtask verify` runs them on a seeded sample ([`sample`]) of a
//! folder, and `cargo xtask merge --verify F` on the shards before merging them.

use std::sync::Mutex;

use eamadm::{Experiment, MethodSpec, PretrainConfig, PretrainedSubtask, PretrainingCache};

use crate::key::{RunDescription, RunKey, canonical_json};
use crate::pretrained::{PretrainedStore, PretrainingDescription};
use crate::store::{RunStore, StoreError};

/// A stored result that is not what its config computes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mismatch {
    /// What it is, for people (`run task1 ea-madm seed 3`, `artefact …`).
    pub what: String,
    /// Its key.
    pub key: RunKey,
    /// How it differs.
    pub problem: String,
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} ({}): {}", self.what, self.key, self.problem)
    }
}

/// The items of `items` to check: all of them (`fraction` = `None`), or the `fraction` (in
/// (0, 1]) of them, at least one, picked by `seed`: each item's rank is the BLAKE3 hash of the
/// seed and its key, so the sample is a function of the seed and the keys alone. Returned in
/// their given order.
#[must_use]
pub fn sample<T>(
    items: Vec<T>,
    key_of: impl Fn(&T) -> &RunKey,
    fraction: Option<f64>,
    seed: u64,
) -> Vec<T> {
    let Some(fraction) = fraction else {
        return items;
    };
    if items.is_empty() {
        return items;
    }
    let wanted = ((items.len() as f64) * fraction.clamp(0.0, 1.0))
        .ceil()
        .max(1.0) as usize;
    let rank = |item: &T| {
        let mut hasher = blake3::Hasher::new();
        hasher.update(&seed.to_le_bytes());
        hasher.update(key_of(item).as_str().as_bytes());
        *hasher.finalize().as_bytes()
    };
    let mut ranked: Vec<(usize, [u8; 32])> = items
        .iter()
        .enumerate()
        .map(|(index, item)| (index, rank(item)))
        .collect();
    ranked.sort_by_key(|a| a.1);
    let mut chosen: Vec<usize> = ranked.into_iter().take(wanted).map(|(i, _)| i).collect();
    chosen.sort_unstable();
    let mut items: Vec<Option<T>> = items.into_iter().map(Some).collect();
    chosen
        .into_iter()
        .filter_map(|index| items[index].take())
        .collect()
}

/// Recomputes run `key` (`method` with `seed` in `experiment`) and compares the line it makes
/// with the stored line byte for byte, under the trajectories the stored line keeps.
/// `Ok(None)` when they are equal.
///
/// # Errors
/// [`StoreError`] if the stored run cannot be read (or the run cannot be computed, as
/// [`StoreError::Key`]).
pub fn verify_run(
    store: &RunStore,
    experiment: &Experiment,
    method: &MethodSpec,
    seed: u64,
    key: &RunKey,
) -> Result<Option<Mismatch>, StoreError> {
    let what = format!(
        "run {} {} seed {seed}",
        experiment.config().name,
        method.label
    );
    let Some((stored, keep)) = store.line(key)? else {
        return Ok(Some(Mismatch {
            what,
            key: key.clone(),
            problem: "not stored".to_owned(),
        }));
    };
    let record = experiment
        .run(method, seed)
        .map_err(|e| StoreError::Key(format!("{what} cannot be recomputed: {e}")))?;
    let description = canonical_json(&RunDescription::new(experiment, method, seed))
        .map_err(|e| StoreError::Key(e.to_string()))?;
    let computed = crate::store::line_for(key, description.as_bytes(), &record, keep)?;
    Ok((computed != stored).then(|| Mismatch {
        what,
        key: key.clone(),
        problem: first_difference(&stored, &computed),
    }))
}

/// The pre-trainings `methods` do with `seed` in `experiment` that the cache holds artefacts
/// of ([`Experiment::shared_pretrainings`]), each once: description, key and a method that
/// trains it.
///
/// # Errors
/// [`StoreError::Key`] if a description cannot be hashed.
pub fn artefacts_of<'a>(
    experiment: &Experiment,
    methods: &[&'a MethodSpec],
    seed: u64,
) -> Result<Vec<(PretrainingDescription, RunKey, &'a MethodSpec)>, StoreError> {
    let mut found: Vec<(PretrainingDescription, RunKey, &'a MethodSpec)> = Vec::new();
    for method in methods {
        for (pretrain, k) in experiment.shared_pretrainings(std::slice::from_ref(method)) {
            let description = PretrainingDescription::new(experiment, &pretrain, k, seed);
            let key = PretrainedStore::key(&description)?;
            if found.iter().all(|(_, seen, _)| *seen != key) {
                found.push((description, key, *method));
            }
        }
    }
    Ok(found)
}

/// Trains the pre-training `description` describes from scratch (with `method`, which trains
/// it) and compares the artefact it makes with the cache's byte for byte. `Ok(None)` when
/// equal; an artefact the cache does not hold is no mismatch (nothing is stored to trust).
///
/// # Errors
/// [`StoreError`] if the stored artefact cannot be read.
pub fn verify_artefact(
    cache: &PretrainedStore,
    experiment: &Experiment,
    method: &MethodSpec,
    description: &PretrainingDescription,
) -> Result<Option<Mismatch>, StoreError> {
    let key = PretrainedStore::key(description)?;
    let path = cache.path(&key);
    let what = format!(
        "artefact {} sub-task {} seed {}",
        experiment.config().name,
        description.subtask,
        description.seed
    );
    let stored = match std::fs::read(&path) {
        Ok(bytes) => bytes,
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => return Err(StoreError::Read { path, source }),
    };
    let recorder = Recorder::default();
    let _ = experiment.share_pretraining_with(&[method], description.seed, &recorder);
    let trained = lock(&recorder.trained)
        .iter()
        .find(|(pretrain, k, _)| {
            *pretrain == description.pretrain && *k as u64 == description.subtask
        })
        .map(|(_, _, subtask)| subtask.clone());
    let Some(trained) = trained else {
        return Ok(Some(Mismatch {
            what,
            key,
            problem: format!("{} does not train this sub-task", method.label),
        }));
    };
    let computed = crate::pretrained::artefact_file(description, &trained)
        .map_err(|source| StoreError::Write { path, source })?;
    Ok((computed != stored).then(|| Mismatch {
        what,
        key,
        problem: format!(
            "the stored artefact ({} bytes) differs from the one training makes ({} bytes){}",
            stored.len(),
            computed.len(),
            match cache.load(description) {
                Ok(Some(loaded)) if loaded != trained => {
                    "; its learner is not the one trained (its checksum was recomputed)"
                }
                Ok(_) => "",
                Err(_) => "; it also fails its own checks",
            }
        ),
    }))
}

/// Where two lines first differ, for people.
fn first_difference(stored: &[u8], computed: &[u8]) -> String {
    let at = stored
        .iter()
        .zip(computed)
        .position(|(a, b)| a != b)
        .unwrap_or(stored.len().min(computed.len()));
    let around = |bytes: &[u8]| {
        let start = at.saturating_sub(40);
        let end = (at + 40).min(bytes.len());
        String::from_utf8_lossy(&bytes[start..end]).into_owned()
    };
    format!(
        "the stored line differs from the recomputed one at byte {at}: stored …{}…, computed …{}…",
        around(stored),
        around(computed)
    )
}

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// A cache that keeps what is trained and never answers with a stored learner, so everything
/// is trained from scratch.
#[derive(Default)]
struct Recorder {
    trained: Mutex<Vec<(PretrainConfig, usize, PretrainedSubtask)>>,
}

impl PretrainingCache for Recorder {
    fn load(
        &self,
        _: &Experiment,
        _: &PretrainConfig,
        _: usize,
        _: u64,
    ) -> Option<PretrainedSubtask> {
        None
    }

    fn save(
        &self,
        _: &Experiment,
        pretrain: &PretrainConfig,
        k: usize,
        _: u64,
        subtask: &PretrainedSubtask,
    ) {
        lock(&self.trained).push((*pretrain, k, subtask.clone()));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sample_is_a_seeded_fraction_of_at_least_one() {
        let keys: Vec<RunKey> = (0..100_u64)
            .map(|i| RunKey::of(&i).expect("an integer hashes"))
            .collect();
        let pick = |fraction, seed| sample(keys.clone(), |key| key, fraction, seed);
        assert_eq!(pick(Some(0.05), 0).len(), 5);
        assert_eq!(pick(Some(0.05), 0), pick(Some(0.05), 0));
        assert_ne!(pick(Some(0.05), 0), pick(Some(0.05), 1));
        assert_eq!(pick(Some(0.001), 3).len(), 1);
        assert_eq!(pick(None, 0), keys);
        // In the given order.
        let five = pick(Some(0.05), 7);
        let mut sorted = five.clone();
        sorted.sort_by_key(|key| keys.iter().position(|k| k == key));
        assert_eq!(five, sorted);
    }
}
