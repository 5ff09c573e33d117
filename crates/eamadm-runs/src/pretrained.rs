//! Pre-trained sub-task learners as content-addressed artefacts of the run store,
//! `<out>/runs/pretrained/<key>.subtask.gz`: computed by whichever process needs one first
//! (an unsharded plan, a shard, a `run-job`) and loaded by every other, so a sweep split over
//! processes pre-trains each (task, learner, pre-training config, sub-task, seed) once, as one
//! process does (Sec. V, Fig. 5, steps 2–3; [`eamadm::Experiment::share_pretraining_with`]).
//!
//! # The key
//!
//! The BLAKE3 hash of a [`PretrainingDescription`] in canonical JSON (as a run's
//! [`RunKey`]): everything a trained sub-task depends on — the task config and the hash of any
//! file it names, the learner parameters, the pre-training config, the sub-task `k` (whose raw
//! reward it learns; pre-training standardises nothing), the seed — and the code's versions:
//! [`PRETRAINED_FORMAT`], [`crate::RESULTS_FORMAT`] and the crate version. Bumping any of them
//! changes every key, so an artefact of an older format is never even opened.
//!
//! # The file
//!
//! One gzip member (the store's deterministic encoder) holding the BLAKE3 digest of the
//! payload (32 bytes) and the payload: CBOR (`ciborium`) of the format, the description and
//! the [`PretrainedSubtask`] (its learner's Q tables, update counts and parameters, and the
//! pre-training statistics the record reports: episodes, environment steps, last episode's
//! steps). CBOR keeps every `f64` bit for bit; the learner is rebuilt through its checked form.
//!
//! An artefact is trusted only when the member decompresses (CRC and length) to at most
//! [`crate::store::MAX_ENTRY_BYTES`], the digest matches, the payload decodes, and its format
//! and description equal the ones asked for (so its content hashes to its name). Anything else
//! is [`StoreError::Damaged`]: the caller warns and trains again, and the new artefact replaces
//! the bad one. Artefacts are a cache, not results: deleting `runs/pretrained/` loses nothing
//! but time.
//!
//! Writes go through [`crate::atomic::write_atomic`] (temporary file, sync, rename). Two
//! processes that train the same sub-task at once write the same bytes, and the last rename
//! wins. The run store's listing reads only `runs/*.jsonl.gz` and `runs/loose/*.run.gz`, so
//! artefacts never appear among runs ([`crate::RunStore::keys`], `merge`, `load_runs`).
//!
//! The prior built from the learners is not stored: it also depends on the storage config,
//! and building it costs a small fraction of pre-training.

use std::io::{self, Read as _};
use std::path::{Path, PathBuf};

use eamadm::config::TaskConfig;
use eamadm::dql::DoubleQParams;
use eamadm::{ExperimentConfig, PretrainConfig, PretrainedSubtask};
use serde::{Deserialize, Serialize};

use crate::key::{RESULTS_FORMAT, RunKey, canonical_json};
use crate::store::{MAX_ENTRY_BYTES, StoreError};

/// Version of the artefact layout and of what training a sub-task computes; bump it when
/// either changes, so that old artefacts are not reused (it is part of every key).
pub const PRETRAINED_FORMAT: u32 = 2;

/// What a trained sub-task depends on; its hash (as [`RunKey::of`]) names the artefact.
#[derive(Debug, Clone, Serialize)]
pub struct PretrainingDescription {
    /// [`PRETRAINED_FORMAT`].
    pub pretrained_format: u32,
    /// [`crate::RESULTS_FORMAT`].
    pub results_format: u32,
    /// The `eamadm` (workspace) version.
    pub crate_version: &'static str,
    /// The task trained on.
    pub task: TaskConfig,
    /// BLAKE3 of the file the task reads, if it names one (as in a run's description).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub task_file_blake3: Option<String>,
    /// The sub-task learner's parameters.
    pub learner: DoubleQParams,
    /// The pre-training config.
    pub pretrain: PretrainConfig,
    /// The sub-task (its index in the task's sub-tasks).
    pub subtask: u64,
    /// The seed.
    pub seed: u64,
}

impl PretrainingDescription {
    /// The description of training sub-task `k` of `config`'s task with `pretrain` and
    /// `seed`, on `config`'s learner parameters.
    #[must_use]
    pub fn new(config: &ExperimentConfig, pretrain: &PretrainConfig, k: usize, seed: u64) -> Self {
        Self {
            pretrained_format: PRETRAINED_FORMAT,
            results_format: RESULTS_FORMAT,
            crate_version: env!("CARGO_PKG_VERSION"),
            task: config.task.clone(),
            task_file_blake3: crate::key::task_file_digest(&config.task),
            learner: config.learner,
            pretrain: *pretrain,
            subtask: k as u64,
            seed,
        }
    }
}

/// The payload as written (borrowing the sub-task).
#[derive(Serialize)]
struct ArtefactRef<'a> {
    format: u32,
    description: &'a str,
    subtask: &'a PretrainedSubtask,
}

/// The payload as read.
#[derive(Deserialize)]
struct Artefact {
    format: u32,
    description: String,
    subtask: PretrainedSubtask,
}

/// The ending of an artefact's file name.
pub const ARTEFACT_EXTENSION: &str = crate::names::PRETRAINED_EXTENSION;

/// The pre-trained artefacts of one output folder, `<out>/runs/pretrained/`.
#[derive(Debug, Clone)]
pub struct PretrainedStore {
    /// The folder holding the run store's folder (the output folder).
    root: PathBuf,
    /// The artefacts' folder relative to `root` (`runs/pretrained`).
    relative: PathBuf,
    folder: PathBuf,
}

impl PretrainedStore {
    /// The artefacts of the output folder `out` (none yet is fine: nothing is read or made
    /// until asked).
    #[must_use]
    pub fn new(out: &Path) -> Self {
        let relative = Path::new(crate::names::RUNS_FOLDER).join(crate::names::PRETRAINED);
        Self {
            root: out.to_path_buf(),
            folder: out.join(&relative),
            relative,
        }
    }

    /// The artefacts beside the run store `store` (its folder's `pretrained/`, whatever the
    /// store's folder is named, as `merge` may be given a `runs/` folder itself).
    #[must_use]
    pub fn of(store: &crate::RunStore) -> Self {
        let runs = store.folder();
        let root = runs.parent().unwrap_or(Path::new(".")).to_path_buf();
        let relative =
            Path::new(runs.file_name().unwrap_or_default()).join(crate::names::PRETRAINED);
        Self {
            folder: runs.join(crate::names::PRETRAINED),
            root,
            relative,
        }
    }

    /// The folder of the artefacts.
    #[must_use]
    pub fn folder(&self) -> &Path {
        &self.folder
    }

    /// The key of the artefact `description` describes.
    ///
    /// # Errors
    /// [`StoreError::Key`] if the description cannot be serialised.
    pub fn key(description: &PretrainingDescription) -> Result<RunKey, StoreError> {
        RunKey::of(description).map_err(|e| StoreError::Key(e.to_string()))
    }

    /// The file of the artefact `key`.
    #[must_use]
    pub fn path(&self, key: &RunKey) -> PathBuf {
        self.folder.join(format!("{key}.{ARTEFACT_EXTENSION}"))
    }

    /// The trained sub-task `description` describes, if its artefact is stored.
    ///
    /// # Errors
    /// [`StoreError::Damaged`] for an artefact that fails a check (see the module docs),
    /// [`StoreError::Read`] if it cannot be read: the caller trains the sub-task again.
    pub fn load(
        &self,
        description: &PretrainingDescription,
    ) -> Result<Option<PretrainedSubtask>, StoreError> {
        let key = Self::key(description)?;
        let path = self.path(&key);
        let Some((artefact, _)) = self.read_checked(&path)? else {
            return Ok(None);
        };
        let expected = canonical_json(description).map_err(|e| StoreError::Key(e.to_string()))?;
        if artefact.description != expected {
            return Err(StoreError::Damaged {
                path,
                problem: "its description is not the one its name was asked for".to_owned(),
            });
        }
        Ok(Some(artefact.subtask))
    }

    /// The artefact at `path` (in this store's folder) and its file's bytes, checked (see
    /// the module docs) but for the description, which the caller compares; `None` if absent.
    fn read_checked(&self, path: &Path) -> Result<Option<(Artefact, Vec<u8>)>, StoreError> {
        let read = |source| StoreError::Read {
            path: path.to_path_buf(),
            source,
        };
        let relative = self.relative.join(path.file_name().unwrap_or_default());
        crate::no_follow::check_under(&self.root, &relative, true).map_err(read)?;
        let mut file = match crate::no_follow::open_regular(path) {
            Ok(file) => file,
            Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(None),
            Err(source) => return Err(read(source)),
        };
        let damaged = |problem: String| StoreError::Damaged {
            path: path.to_path_buf(),
            problem,
        };
        // Compressed, an artefact is far smaller than the cap on what it decompresses to.
        let mut bytes = Vec::new();
        (&mut file)
            .take(MAX_ENTRY_BYTES + 1)
            .read_to_end(&mut bytes)
            .map_err(read)?;
        let mut content = Vec::new();
        flate2::read::GzDecoder::new(bytes.as_slice())
            .take(MAX_ENTRY_BYTES + 1)
            .read_to_end(&mut content)
            .map_err(|e| damaged(format!("does not decompress ({e})")))?;
        if content.len() as u64 > MAX_ENTRY_BYTES || bytes.len() as u64 > MAX_ENTRY_BYTES {
            return Err(damaged(format!(
                "larger than the cap of {MAX_ENTRY_BYTES} bytes"
            )));
        }
        let Some((digest, payload)) = content.split_first_chunk::<32>() else {
            return Err(damaged("shorter than its checksum".to_owned()));
        };
        if blake3::hash(payload) != blake3::Hash::from_bytes(*digest) {
            return Err(damaged(
                "checksum mismatch: the payload was edited or damaged".to_owned(),
            ));
        }
        let artefact: Artefact = ciborium::from_reader(payload)
            .map_err(|e| damaged(format!("payload does not decode ({e})")))?;
        if artefact.format != PRETRAINED_FORMAT {
            return Err(damaged(format!(
                "format is {}, expected {PRETRAINED_FORMAT}",
                artefact.format
            )));
        }
        Ok(Some((artefact, bytes)))
    }

    /// Copies into this store every artefact of `other` it lacks (as `merge` gathers the
    /// shards' runs), each checked first: its description must hash to its file name. A bad
    /// one is passed to `warn` and left out. Returns how many were copied.
    ///
    /// # Errors
    /// [`StoreError::Read`] if `other`'s folder cannot be listed, [`StoreError::Write`] if
    /// an artefact cannot be written here.
    pub fn adopt(
        &self,
        other: &PretrainedStore,
        warn: &mut dyn FnMut(&str),
    ) -> Result<usize, StoreError> {
        let listing = match std::fs::read_dir(&other.folder) {
            Ok(listing) => listing,
            Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(0),
            Err(source) => {
                return Err(StoreError::Read {
                    path: other.folder.clone(),
                    source,
                });
            }
        };
        let mut names: Vec<String> = listing
            .flatten()
            .map(|entry| entry.file_name().to_string_lossy().into_owned())
            .filter(|name| {
                name.strip_suffix(&format!(".{ARTEFACT_EXTENSION}"))
                    .is_some_and(|key| {
                        key.len() == 64 && key.bytes().all(|b| b.is_ascii_hexdigit())
                    })
            })
            .collect();
        names.sort();
        let mut copied = 0;
        for name in names {
            let target = self.folder.join(&name);
            if target.exists() {
                continue;
            }
            let source = other.folder.join(&name);
            let checked = other.read_checked(&source).and_then(|found| {
                let key = name.trim_end_matches(&format!(".{ARTEFACT_EXTENSION}"));
                match found {
                    Some((artefact, bytes))
                        if blake3::hash(artefact.description.as_bytes())
                            .to_hex()
                            .as_str()
                            == key =>
                    {
                        Ok(Some(bytes))
                    }
                    Some(_) => Err(StoreError::Damaged {
                        path: source.clone(),
                        problem: "its description does not hash to its name".to_owned(),
                    }),
                    None => Ok(None),
                }
            });
            match checked {
                Ok(Some(bytes)) => {
                    let write = |source| StoreError::Write {
                        path: target.clone(),
                        source,
                    };
                    crate::no_follow::ensure_folders(&self.root, &self.relative).map_err(write)?;
                    crate::atomic::write_atomic(&target, &bytes).map_err(|e| write(e.source))?;
                    copied += 1;
                }
                Ok(None) => {}
                Err(error) => warn(&format!("{error}; not copied")),
            }
        }
        Ok(copied)
    }

    /// Stores `subtask`, trained as `description` describes, atomically (see the module
    /// docs); the same bytes whichever process writes them.
    ///
    /// # Errors
    /// [`StoreError::Write`] if it cannot be written.
    pub fn save(
        &self,
        description: &PretrainingDescription,
        subtask: &PretrainedSubtask,
    ) -> Result<(), StoreError> {
        let key = Self::key(description)?;
        let path = self.path(&key);
        let write = |source| StoreError::Write {
            path: path.clone(),
            source,
        };
        let bytes = artefact_bytes(description, subtask).map_err(write)?;
        crate::no_follow::ensure_folders(&self.root, &self.relative).map_err(write)?;
        crate::atomic::write_atomic(&path, &bytes).map_err(|e| write(e.source))
    }
}

/// The compressed file of the artefact.
fn artefact_bytes(
    description: &PretrainingDescription,
    subtask: &PretrainedSubtask,
) -> io::Result<Vec<u8>> {
    let description = canonical_json(description).map_err(io::Error::other)?;
    let mut content = vec![0; 32];
    ciborium::into_writer(
        &ArtefactRef {
            format: PRETRAINED_FORMAT,
            description: &description,
            subtask,
        },
        &mut content,
    )
    .map_err(io::Error::other)?;
    let digest = blake3::hash(&content[32..]);
    content[..32].copy_from_slice(digest.as_bytes());
    crate::gzip::compress(&content)
}

#[cfg(test)]
mod tests {
    use super::*;

    use std::sync::Mutex;

    use eamadm::{Method, PretrainingCache};

    /// Task I with its EA-MADM pre-training cut to 3 episodes per sub-task.
    fn config() -> ExperimentConfig {
        let mut config = eamadm::paper::task1();
        config.episodes = 2;
        config.methods.retain(|m| m.label == "ea-madm");
        for method in &mut config.methods {
            if let Method::EaMadm(ea) = &mut method.method {
                ea.pretrain.episodes = 3;
            }
        }
        config
    }

    fn pretrain(config: &ExperimentConfig) -> PretrainConfig {
        match &config.methods[0].method {
            Method::EaMadm(ea) => ea.pretrain,
            _ => panic!("ea-madm"),
        }
    }

    /// Keeps what the experiment trains.
    #[derive(Default)]
    struct Capture(Mutex<Vec<(usize, PretrainedSubtask)>>);

    impl PretrainingCache for Capture {
        fn load(
            &self,
            _: &ExperimentConfig,
            _: &PretrainConfig,
            _: usize,
            _: u64,
        ) -> Option<PretrainedSubtask> {
            None
        }

        fn save(
            &self,
            _: &ExperimentConfig,
            _: &PretrainConfig,
            k: usize,
            _: u64,
            subtask: &PretrainedSubtask,
        ) {
            self.0.lock().unwrap().push((k, subtask.clone()));
        }
    }

    fn trained(config: &ExperimentConfig, k: usize, seed: u64) -> PretrainedSubtask {
        let experiment = eamadm::Experiment::new(config.clone()).unwrap();
        let capture = Capture::default();
        let methods: Vec<_> = config.methods.iter().collect();
        let _ = experiment.share_pretraining_with(&methods, seed, &capture);
        let mut kept = capture.0.into_inner().unwrap();
        kept.retain(|(j, _)| *j == k);
        kept.pop().unwrap().1
    }

    fn described(config: &ExperimentConfig, k: usize, seed: u64) -> PretrainingDescription {
        PretrainingDescription::new(config, &pretrain(config), k, seed)
    }

    #[test]
    fn a_stored_subtask_loads_bit_for_bit_and_only_under_its_own_description() {
        let dir = tempfile::tempdir().unwrap();
        let store = PretrainedStore::new(dir.path());
        let config = config();
        let description = described(&config, 1, 5);
        assert_eq!(store.load(&description).unwrap(), None);
        let subtask = trained(&config, 1, 5);
        store.save(&description, &subtask).unwrap();
        let loaded = store.load(&description).unwrap().unwrap();
        // PartialEq on the learner compares every f64 (and its update counts).
        assert_eq!(loaded, subtask);
        // The same bytes whoever writes them.
        let path = store.path(&PretrainedStore::key(&description).unwrap());
        let first = std::fs::read(&path).unwrap();
        store.save(&description, &subtask).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), first);
        // Another sub-task, seed or pre-training is another artefact.
        assert_eq!(store.load(&described(&config, 0, 5)).unwrap(), None);
        assert_eq!(store.load(&described(&config, 1, 6)).unwrap(), None);
        let mut longer = described(&config, 1, 5);
        longer.pretrain.episodes = 4;
        assert_eq!(store.load(&longer).unwrap(), None);
    }

    #[test]
    fn a_damaged_or_truncated_or_misfiled_artefact_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let store = PretrainedStore::new(dir.path());
        let config = config();
        let description = described(&config, 0, 2);
        store.save(&description, &trained(&config, 0, 2)).unwrap();
        let path = store.path(&PretrainedStore::key(&description).unwrap());
        let whole = std::fs::read(&path).unwrap();
        let damaged = |bytes: &[u8]| {
            std::fs::write(&path, bytes).unwrap();
            match store.load(&description) {
                Err(StoreError::Damaged { problem, .. }) => problem,
                other => panic!("{other:?}"),
            }
        };
        assert!(damaged(&whole[..whole.len() / 2]).contains("decompress"));
        let mut flipped = whole.clone();
        flipped[whole.len() / 2] ^= 0x20;
        assert!(!damaged(&flipped).is_empty());
        // A payload edited and compressed again: the checksum catches it.
        let mut content = Vec::new();
        flate2::read::GzDecoder::new(whole.as_slice())
            .read_to_end(&mut content)
            .unwrap();
        let last = content.len() - 1;
        content[last] ^= 1;
        let recompressed = crate::gzip::compress(&content).unwrap();
        assert!(damaged(&recompressed).contains("checksum mismatch"));
        // Another sub-task's artefact under this name (checksum intact).
        let other = described(&config, 1, 2);
        let misfiled = artefact_bytes(&other, &trained(&config, 1, 2)).unwrap();
        assert!(damaged(&misfiled).contains("not the one"));
        // Saving again repairs it.
        store.save(&description, &trained(&config, 0, 2)).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), whole);
    }

    #[test]
    fn a_format_bump_changes_the_key_and_an_old_payload_is_refused() {
        let config = config();
        let description = described(&config, 0, 1);
        let mut bumped = description.clone();
        bumped.pretrained_format += 1;
        assert_ne!(
            PretrainedStore::key(&description).unwrap(),
            PretrainedStore::key(&bumped).unwrap()
        );
        // A payload of another format under the current name is refused, not misread.
        let dir = tempfile::tempdir().unwrap();
        let store = PretrainedStore::new(dir.path());
        let subtask = trained(&config, 0, 1);
        let text = canonical_json(&description).unwrap();
        let mut content = vec![0; 32];
        ciborium::into_writer(
            &ArtefactRef {
                format: PRETRAINED_FORMAT + 1,
                description: &text,
                subtask: &subtask,
            },
            &mut content,
        )
        .unwrap();
        let digest = blake3::hash(&content[32..]);
        content[..32].copy_from_slice(digest.as_bytes());
        let path = store.path(&PretrainedStore::key(&description).unwrap());
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, crate::gzip::compress(&content).unwrap()).unwrap();
        match store.load(&description) {
            Err(StoreError::Damaged { problem, .. }) => {
                let expected = format!("format is {}", PRETRAINED_FORMAT + 1);
                assert!(problem.contains(&expected), "{problem}");
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn artefacts_are_not_runs() {
        let dir = tempfile::tempdir().unwrap();
        let config = config();
        let description = described(&config, 0, 1);
        PretrainedStore::new(dir.path())
            .save(&description, &trained(&config, 0, 1))
            .unwrap();
        let mut warnings = Vec::new();
        let store =
            crate::RunStore::open(dir.path(), &mut |w| warnings.push(w.to_owned())).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        assert!(store.is_empty());
        let read_only =
            crate::RunStore::open_read_only(dir.path(), &mut |w| panic!("{w}")).unwrap();
        assert!(read_only.keys().is_empty());
    }

    #[test]
    fn adopting_copies_the_checked_artefacts_another_store_lacks() {
        let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        let (from, into) = (
            PretrainedStore::new(a.path()),
            PretrainedStore::new(b.path()),
        );
        let config = config();
        for k in 0..2 {
            from.save(&described(&config, k, 3), &trained(&config, k, 3))
                .unwrap();
        }
        // One of them damaged, and one stray file that is no artefact.
        let damaged = from.path(&PretrainedStore::key(&described(&config, 1, 3)).unwrap());
        let whole = std::fs::read(&damaged).unwrap();
        std::fs::write(&damaged, &whole[..whole.len() / 2]).unwrap();
        std::fs::write(from.folder().join("notes.txt"), "x").unwrap();
        let mut warnings = Vec::new();
        let copied = into
            .adopt(&from, &mut |w| warnings.push(w.to_owned()))
            .unwrap();
        assert_eq!(copied, 1);
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert_eq!(
            into.load(&described(&config, 0, 3)).unwrap(),
            Some(trained(&config, 0, 3))
        );
        assert_eq!(into.load(&described(&config, 1, 3)).unwrap(), None);
        // Nothing to do the second time; an absent folder is no error.
        assert_eq!(
            into.adopt(&from, &mut |w| warnings.push(w.to_owned()))
                .unwrap(),
            0
        );
        let empty = PretrainedStore::new(&a.path().join("nowhere"));
        assert_eq!(into.adopt(&empty, &mut |w| panic!("{w}")).unwrap(), 0);
    }

    #[test]
    fn writers_of_one_artefact_at_once_all_succeed_and_leave_one_valid_file() {
        let dir = tempfile::tempdir().unwrap();
        let store = PretrainedStore::new(dir.path());
        let config = config();
        let description = described(&config, 0, 4);
        let subtask = trained(&config, 0, 4);
        std::thread::scope(|scope| {
            for _ in 0..4 {
                scope.spawn(|| {
                    for _ in 0..5 {
                        store.save(&description, &subtask).unwrap();
                    }
                });
            }
        });
        let files: Vec<_> = std::fs::read_dir(store.folder()).unwrap().collect();
        assert_eq!(files.len(), 1, "one file, no temporary file left");
        assert_eq!(store.load(&description).unwrap(), Some(subtask));
    }
}
