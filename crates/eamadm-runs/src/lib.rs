//! The run store and output folder of the eamadm reproduction: where every finished run of an
//! experiment (Sec. VI: Task I, Task II and the robot, each method over many seeds) is kept, so
//! that an interrupted, sharded or cluster-run sweep resumes and merges without recomputing a
//! run, and where the outputs made from them are written.
//!
//! - [`key`]: a run's [`RunDescription`] (its config, method, seed and code version) and its
//!   [`RunKey`], the BLAKE3 hash of the description in canonical JSON;
//! - [`store`]: the [`RunStore`] of `<out>/runs/`, every run checked (key, checksum, record)
//!   before it is trusted, and bytes checked or written once recognised by their BLAKE3 hash
//!   rather than parsed again ([`AppendReceipt`]);
//! - [`pretrained`]: the pre-trained sub-task learners as content-addressed artefacts in a
//!   cache folder outside the output folder, shared by every process of a sweep;
//! - [`gzip`]: compression whose bytes depend only on the content;
//! - [`atomic`]: files written aside and renamed into place;
//! - [`no_follow`]: paths opened without following links, never hanging on a FIFO;
//! - [`output_folder`]: the folder's lock, its staged set of outputs and their manifest;
//! - [`frames`]: the compressed frames of the store's files, read streaming against caps;
//! - [`gc`]: what no plan needs any more (old formats, old set-aside entries, artefacts of
//!   other plans);
//! - [`jobs`]: a plan's runs as [`jobs::Job`]s with their keys, in job order, and the loop that
//!   runs the missing ones into the store in parallel, sharing pre-training per seed;
//! - [`shard`]: which runs shard `K/N` of a plan holds, by key;
//! - [`verify`]: stored runs and artefacts recomputed and compared byte for byte, since the
//!   checksums catch faults, not forgery;
//! - [`names`]: the name of every file and folder in an output folder (the facade's
//!   [`eamadm::output_names`], which the reserved experiment names derive from).
//!
//! The store holds [`eamadm::RunRecord`]s, the results of [`eamadm::Experiment::run`] (the
//! paper's Algorithm 2 and its competitors); it adds no numbers of its own.
//!
//! ```
//! use eamadm_runs::{KeepTrajectories, RunDescription, RunKey, RunStore};
//!
//! let mut config = eamadm::paper::task1();
//! config.episodes = 2;
//! config.trajectories.episodes.clear();
//! config.methods.retain(|m| m.label == "epsilon-greedy");
//! let experiment = eamadm::Experiment::new(config.clone())?;
//! let method = &config.methods[0];
//! let description = RunDescription::new(&experiment, method, 0);
//! let key = RunKey::of(&description)?;
//!
//! let out = tempfile::tempdir()?;
//! let store = RunStore::open(out.path(), &mut |warning| panic!("{warning}"))?;
//! let record = experiment.run(method, 0)?;
//! store.append(&key, &description, &record, KeepTrajectories::Figures)?;
//!
//! let store = RunStore::open(out.path(), &mut |warning| panic!("{warning}"))?;
//! let loaded = store.load(&key, KeepTrajectories::Figures)?.expect("stored");
//! assert_eq!(loaded.record.episodes, record.episodes);
//! assert_eq!(store.keys(), [&key]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod atomic;
pub mod frames;
pub mod gc;
pub mod gzip;
pub mod jobs;
pub mod key;
pub mod no_follow;
pub mod output_folder;
pub mod pretrained;
pub mod shard;
pub mod store;
pub mod verify;

pub use eamadm::output_names as names;
pub use key::{RESULTS_FORMAT, RunDescription, RunKey, canonical_json};
pub use pretrained::{PRETRAINED_FORMAT, PretrainedStore, PretrainingDescription};
pub use store::{
    AppendReceipt, BatchLimit, KeepTrajectories, LooseBatch, RunStore, StoreError, StoredRun,
    compact,
};
