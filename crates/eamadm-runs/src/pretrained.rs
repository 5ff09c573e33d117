//! Pre-trained sub-task learners as content-addressed artefacts in a cache folder,
//! `<cache>/<key>.subtask.gz` (`--pretrained-cache`, by default `target/pretrained-cache` of the
//! workspace: outside every output folder, which it would otherwise double in size;
//! docs/paper-notes.md §14): computed by whichever process needs one first (an unsharded plan,
//! a shard, a `run-job`, of any output folder) and loaded by every other, so a sweep split over
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
//! [`crate::store::MAX_ENTRY_BYTES`] (counted streaming, before anything is held), the digest
//! matches, the payload decodes, and its format and description equal the ones asked for (so
//! its content hashes to its name). Anything else is [`StoreError::Damaged`]: the caller warns
//! and trains again, and the new artefact replaces the bad one. Artefacts are a cache, not
//! results: deleting the cache loses nothing but time. Like the run store's checksums, the
//! digest detects faults, not forgery: `cargo xtask verify` trains a sample again and
//! compares.
//!
//! Writes go through [`crate::atomic::write_atomic_among_writers`] (temporary file, sync,
//! rename; coordinated with sweeps by the cache's `.writers.lock`). Two processes that train
//! the same sub-task at once write the same bytes, and the last rename wins.
//!
//! The prior built from the learners is not stored: it also depends on the storage config,
//! and building it costs a small fraction of pre-training.

use std::io::{self, Read as _};
use std::path::{Path, PathBuf};

use eamadm::config::TaskConfig;
use eamadm::dql::DoubleQParams;
use eamadm::{Experiment, PretrainConfig, PretrainedSubtask};
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
    /// The description of training sub-task `k` of `experiment`'s task with `pretrain` and
    /// `seed`, on its learner parameters; a file the task names is hashed as the experiment
    /// read it (see [`crate::RunDescription::new`]).
    #[must_use]
    pub fn new(experiment: &Experiment, pretrain: &PretrainConfig, k: usize, seed: u64) -> Self {
        let config = experiment.config();
        Self {
            pretrained_format: PRETRAINED_FORMAT,
            results_format: RESULTS_FORMAT,
            crate_version: env!("CARGO_PKG_VERSION"),
            task: config.task.clone(),
            task_file_blake3: crate::key::task_input_digest(experiment),
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

/// The pre-trained artefacts of one cache folder (`--pretrained-cache`; outside the output
/// folder, shared by every output folder and process that names it).
#[derive(Debug, Clone)]
pub struct PretrainedStore {
    folder: PathBuf,
}

impl PretrainedStore {
    /// The artefacts in the folder `folder` (none yet is fine: nothing is read or made until
    /// asked). The folder itself may be a link (the user chose it); nothing inside it is
    /// followed.
    #[must_use]
    pub fn new(folder: &Path) -> Self {
        Self {
            folder: folder.to_path_buf(),
        }
    }

    /// Where versions before the cache kept the artefacts of an output folder `out`
    /// (`<out>/runs/pretrained/`): read by `merge` and `gc`, which move them into the cache.
    #[must_use]
    pub fn legacy(out: &Path) -> Self {
        Self::new(
            &out.join(crate::names::RUNS_FOLDER)
                .join(crate::names::PRETRAINED),
        )
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

    /// The keys of the artefacts in the folder (files named `<64 hex digits>.subtask.gz`),
    /// sorted; none when the folder does not exist.
    ///
    /// # Errors
    /// [`StoreError::Read`] if the folder cannot be listed.
    pub fn keys(&self) -> Result<Vec<RunKey>, StoreError> {
        let listing = match std::fs::read_dir(&self.folder) {
            Ok(listing) => listing,
            Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
            Err(source) => {
                return Err(StoreError::Read {
                    path: self.folder.clone(),
                    source,
                });
            }
        };
        let mut keys: Vec<RunKey> = listing
            .flatten()
            .filter_map(|entry| {
                let name = entry.file_name().to_string_lossy().into_owned();
                let key = name.strip_suffix(&format!(".{ARTEFACT_EXTENSION}"))?;
                (key.len() == 64 && key.bytes().all(|b| b.is_ascii_hexdigit()))
                    .then(|| RunKey::from_verified_hex(key.to_owned()))
            })
            .collect();
        keys.sort();
        Ok(keys)
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
        let Some(artefact) = self.read_checked(&path)? else {
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

    /// The artefact `key` checked (see the module docs) and its description, which hashes to
    /// its key; `None` if absent. For `verify`, which recomputes what the description says.
    ///
    /// # Errors
    /// [`StoreError::Damaged`] or [`StoreError::Read`].
    pub fn load_any(
        &self,
        key: &RunKey,
    ) -> Result<Option<(String, PretrainedSubtask)>, StoreError> {
        let path = self.path(key);
        let Some(artefact) = self.read_checked(&path)? else {
            return Ok(None);
        };
        if blake3::hash(artefact.description.as_bytes())
            .to_hex()
            .as_str()
            != key.as_str()
        {
            return Err(StoreError::Damaged {
                path,
                problem: "its description does not hash to its name".to_owned(),
            });
        }
        Ok(Some((artefact.description, artefact.subtask)))
    }

    /// The artefact at `path` (in this store's folder), checked (see the module docs) but for
    /// the description, which the caller compares; `None` if absent. Read streaming, twice:
    /// first to count and hash what the member decompresses to (refusing it past the cap, so a
    /// bomb costs a few KiB of memory), then to decode the payload while hashing it again.
    fn read_checked(&self, path: &Path) -> Result<Option<Artefact>, StoreError> {
        let read = |source| StoreError::Read {
            path: path.to_path_buf(),
            source,
        };
        let damaged = |problem: String| StoreError::Damaged {
            path: path.to_path_buf(),
            problem,
        };
        let name = path.file_name().unwrap_or_default();
        crate::no_follow::check_under(&self.folder, Path::new(name), true).map_err(read)?;
        let mut file = match crate::no_follow::open_regular(path) {
            Ok(file) => file,
            Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(None),
            Err(source) => return Err(read(source)),
        };
        // First pass: the digest, then the payload counted and hashed, never held.
        let digest = {
            let mut buffered = io::BufReader::new(&mut file);
            let mut decoder = flate2::bufread::GzDecoder::new(&mut buffered);
            let mut digest = [0_u8; 32];
            decoder
                .read_exact(&mut digest)
                .map_err(|e| damaged(format!("does not decompress to its checksum ({e})")))?;
            let mut hasher = blake3::Hasher::new();
            let len = io::copy(&mut (&mut decoder).take(MAX_ENTRY_BYTES + 1), &mut hasher)
                .map_err(|e| damaged(format!("does not decompress ({e})")))?;
            if len > MAX_ENTRY_BYTES {
                return Err(damaged(format!(
                    "larger than the cap of {MAX_ENTRY_BYTES} bytes"
                )));
            }
            drop(decoder);
            if !io::BufRead::fill_buf(&mut buffered)
                .map_err(read)?
                .is_empty()
            {
                return Err(damaged(
                    "bytes follow the artefact's gzip member".to_owned(),
                ));
            }
            if hasher.finalize() != blake3::Hash::from_bytes(digest) {
                return Err(damaged(
                    "checksum mismatch: the payload was edited or damaged".to_owned(),
                ));
            }
            digest
        };
        // Second pass: decoded as it streams, hashed again (the file may have been changed in
        // place meanwhile).
        io::Seek::seek(&mut file, io::SeekFrom::Start(0)).map_err(read)?;
        let mut decoder = flate2::bufread::GzDecoder::new(io::BufReader::new(file));
        let mut skipped = [0_u8; 32];
        decoder.read_exact(&mut skipped).map_err(read)?;
        let mut hashing = HashingReader {
            inner: decoder.take(MAX_ENTRY_BYTES),
            hasher: blake3::Hasher::new(),
        };
        let artefact: Result<Artefact, _> = ciborium::from_reader(&mut hashing);
        io::copy(&mut hashing, &mut io::sink()).map_err(read)?;
        if hashing.hasher.finalize() != blake3::Hash::from_bytes(digest) {
            return Err(damaged("the file changed while it was read".to_owned()));
        }
        let artefact = artefact.map_err(|e| damaged(format!("payload does not decode ({e})")))?;
        if artefact.format != PRETRAINED_FORMAT {
            return Err(damaged(format!(
                "format is {}, expected {PRETRAINED_FORMAT}",
                artefact.format
            )));
        }
        Ok(Some(artefact))
    }

    /// Copies into this store every artefact of `other` it lacks (as `merge` and `gc` gather
    /// the artefacts older versions kept in output folders), each checked first: its
    /// description must hash to its file name. A bad one is passed to `warn` and left out.
    /// Returns how many were copied.
    ///
    /// # Errors
    /// [`StoreError::Read`] if `other`'s folder cannot be listed, [`StoreError::Write`] if
    /// an artefact cannot be written here.
    pub fn adopt(
        &self,
        other: &PretrainedStore,
        warn: &mut dyn FnMut(&str),
    ) -> Result<usize, StoreError> {
        let mut copied = 0;
        for key in other.keys()? {
            let target = self.path(&key);
            if target.exists() {
                continue;
            }
            match other.load_any(&key) {
                Ok(Some((description, subtask))) => {
                    let write = |source| StoreError::Write {
                        path: target.clone(),
                        source,
                    };
                    let bytes = artefact_bytes_of(&description, &subtask).map_err(write)?;
                    crate::atomic::write_atomic_among_writers(&target, &bytes, &self.writers())
                        .map_err(|e| write(e.source))?;
                    copied += 1;
                }
                Ok(None) => {}
                Err(error) => warn(&format!("{error}; not copied")),
            }
        }
        Ok(copied)
    }

    /// Removes the artefact `key` (for `gc`); absent is fine.
    ///
    /// # Errors
    /// [`StoreError::Write`] if it cannot be removed.
    pub fn remove(&self, key: &RunKey) -> Result<(), StoreError> {
        let path = self.path(key);
        match std::fs::remove_file(&path) {
            Ok(()) => Ok(()),
            Err(error) if error.kind() == io::ErrorKind::NotFound => Ok(()),
            Err(source) => Err(StoreError::Write { path, source }),
        }
    }

    /// Removes the temporary files of writers that are gone ([`crate::atomic::WritersLock`]);
    /// returns how many.
    ///
    /// # Errors
    /// [`StoreError::Write`] if the folder cannot be swept.
    pub fn remove_stale_temporary_files(&self) -> Result<usize, StoreError> {
        crate::atomic::remove_stale_temporary_files(&self.folder, Some(&self.writers())).map_err(
            |source| StoreError::Write {
                path: self.folder.clone(),
                source,
            },
        )
    }

    fn writers(&self) -> crate::atomic::WritersLock {
        crate::atomic::WritersLock::in_folder(&self.folder)
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
        std::fs::create_dir_all(&self.folder).map_err(write)?;
        crate::atomic::write_atomic_among_writers(&path, &bytes, &self.writers())
            .map_err(|e| write(e.source))
    }
}

/// A reader hashing every byte read through it.
struct HashingReader<R> {
    inner: R,
    hasher: blake3::Hasher,
}

impl<R: io::Read> io::Read for HashingReader<R> {
    fn read(&mut self, into: &mut [u8]) -> io::Result<usize> {
        let read = self.inner.read(into)?;
        self.hasher.update(&into[..read]);
        Ok(read)
    }
}

/// The file of the artefact of `subtask` trained as `description` describes: the bytes
/// [`PretrainedStore::save`] writes (for `verify`, which compares them with the cache's).
///
/// # Errors
/// If the description or sub-task does not serialise.
pub fn artefact_file(
    description: &PretrainingDescription,
    subtask: &PretrainedSubtask,
) -> io::Result<Vec<u8>> {
    artefact_bytes(description, subtask)
}

/// The compressed file of the artefact.
fn artefact_bytes(
    description: &PretrainingDescription,
    subtask: &PretrainedSubtask,
) -> io::Result<Vec<u8>> {
    let description = canonical_json(description).map_err(io::Error::other)?;
    artefact_bytes_of(&description, subtask)
}

/// The compressed file of the artefact of `description` (canonical JSON).
fn artefact_bytes_of(description: &str, subtask: &PretrainedSubtask) -> io::Result<Vec<u8>> {
    let mut content = vec![0; 32];
    ciborium::into_writer(
        &ArtefactRef {
            format: PRETRAINED_FORMAT,
            description,
            subtask,
        },
        &mut content,
    )
    .map_err(io::Error::other)?;
    let digest = blake3::hash(&content[32..]);
    content[..32].copy_from_slice(digest.as_bytes());
    crate::gzip::compress(&content)
}

/// The cache read only, as a [`PretrainingCache`](eamadm::PretrainingCache): runs repeated
/// after a plan (the oracle's, `eamadm::oracle`) take the sub-tasks it already trained and
/// stored; a missing or damaged artefact is trained again in memory (the same learner: a pure
/// function of its description) and not stored.
#[derive(Debug, Clone)]
pub struct ReadOnlyCache(pub PretrainedStore);

impl eamadm::PretrainingCache for ReadOnlyCache {
    fn load(
        &self,
        experiment: &Experiment,
        pretrain: &PretrainConfig,
        k: usize,
        seed: u64,
    ) -> Option<PretrainedSubtask> {
        let description = PretrainingDescription::new(experiment, pretrain, k, seed);
        self.0.load(&description).ok().flatten()
    }

    fn save(&self, _: &Experiment, _: &PretrainConfig, _: usize, _: u64, _: &PretrainedSubtask) {}
}

#[cfg(test)]
mod tests {
    use super::*;

    use std::sync::Mutex;

    use eamadm::{ExperimentConfig, Method, PretrainingCache};

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
        let experiment = Experiment::new(config.clone()).unwrap();
        PretrainingDescription::new(&experiment, &pretrain(config), k, seed)
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
        let files: Vec<_> = std::fs::read_dir(store.folder())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|name| name != crate::atomic::WRITERS_LOCK_FILE)
            .collect();
        assert_eq!(
            files.len(),
            1,
            "one file, no temporary file left: {files:?}"
        );
        assert_eq!(store.load(&description).unwrap(), Some(subtask));
    }

    #[test]
    fn the_read_only_cache_loads_what_is_stored_and_stores_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let store = PretrainedStore::new(dir.path());
        let config = config();
        let experiment = Experiment::new(config.clone()).unwrap();
        let cache = ReadOnlyCache(store.clone());
        assert_eq!(cache.load(&experiment, &pretrain(&config), 1, 5), None);
        let subtask = trained(&config, 1, 5);
        cache.save(&experiment, &pretrain(&config), 1, 5, &subtask);
        assert!(store.keys().unwrap().is_empty(), "nothing stored");
        store.save(&described(&config, 1, 5), &subtask).unwrap();
        assert_eq!(
            cache.load(&experiment, &pretrain(&config), 1, 5),
            Some(subtask)
        );
    }
}
