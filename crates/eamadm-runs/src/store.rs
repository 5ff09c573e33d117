//! The run store of an output folder, `<out>/runs/`: every finished run, checked before it is
//! trusted, never lost to another process.
//!
//! # On disk
//!
//! ```text
//! runs/<experiment>.jsonl.gz          packed bundle: the experiment's runs, one gzip member each
//! runs/loose/<key>.<keep>.run.gz      one run just finished, one gzip member (not yet packed)
//! runs/.set-aside/…                   entries that failed their checks, kept for inspection
//! runs/pretrained/<key>.subtask.gz    a pre-trained sub-task learner (crate::pretrained), not a run
//! ```
//!
//! A run is one *entry*: one gzip member (see [`crate::gzip`]) holding one line, so a bundle is a
//! valid multi-member gzip file and `zcat runs/task1.jsonl.gz` prints the lines. A line is three
//! tab-separated parts (compact JSON never holds a raw tab):
//!
//! ```text
//! {"format":3,"key":…,"experiment":…,"method":…,"seed":…,"trajectories":"figures","blake3":…}<TAB><description><TAB><record>
//! ```
//!
//! - the header says what the run is, which training trajectories the record keeps
//!   ([`KeepTrajectories`]) and `blake3`, the BLAKE3 hash of the header's other fields (as the
//!   JSON object above without `blake3`), a tab, and `<description><TAB><record>`;
//! - the description is the run's [`RunDescription`] in canonical JSON, whose BLAKE3 hash *is*
//!   the run's key, so the key is checked, not trusted;
//! - the record is the [`RunRecord`] with its per-episode curve stored as columns, training
//!   trajectories removed unless kept for all.
//!
//! # Guarantees and what they rest on
//!
//! - **Writers never share a file.** A finished run is written to a temporary file in
//!   `runs/loose/`, synced, and renamed to its content-addressed name `<key>.<keep>.run.gz`
//!   ([`RunStore::append`]); two processes storing the same run write the same bytes. Bundles are
//!   written only by [`RunStore::pack`], which needs the output folder's lock, and only by an
//!   atomic rename. This rests on `rename` being atomic within a folder (POSIX; NFS and Lustre
//!   keep it) and on the folder lock being exclusive (`flock`, which NFS emulates with
//!   byte-range locks). No append is ever shared.
//! - **Readers never change anything.** [`RunStore::open`] only reads; a damaged or torn entry is
//!   reported and skipped.
//! - **Nothing removes a run.** Packing writes the union of the bundle's verified entries and
//!   the loose runs, each run once with the richest trajectories stored, then removes only the
//!   loose files now in the bundle. A narrower plan, another shard or another
//!   `--keep-trajectories` adds runs, never drops them.
//! - **A run is trusted only when everything checks**: the entry decompresses (gzip's CRC) to at
//!   most [`MAX_ENTRY_BYTES`], the format is known, the checksum covers header and content, the
//!   description hashes to the key, the record loads, and the record's and description's
//!   experiment, method and seed agree with the header. Anything else is reported once (the
//!   next [`RunStore::pack`] sets it aside in `runs/.set-aside/`, never deleting it) and the run
//!   is recomputed.
//! - **Bytes checked or made once are not parsed again.** The index keeps, for each verified
//!   entry, the BLAKE3 hash of its compressed bytes. Bytes read back later that hash to it are
//!   the bytes checked, so they are trusted without inflating and parsing them again; bytes that
//!   differ in any way are checked in full as above. This applies four times: a loose file
//!   [`RunStore::append`] wrote from a record it serialised, when its [`AppendReceipt`] is
//!   handed to [`RunStore::open_with_receipts`] or [`RunStore::reopen`]; an entry
//!   [`RunStore::pack`] copies (a loose file replaced by another process since it was indexed
//!   is read as it now is); the bundles `pack` has just written under the lock, indexed from
//!   what it wrote; and, in [`RunStore::reopen`] by the process holding the lock since the
//!   first open, the bundles that open read (while their length is unchanged) and the loose
//!   files it verified (while their bytes hash the same). Everything else a store is opened on
//!   is checked in full, and [`RunStore::load`] checks the entry it returns in full.
//! - **No link is followed inside the store** ([`crate::no_follow`]).

use std::collections::HashMap;
use std::fs::File;
use std::io::{self, BufRead, BufReader, Read as _, Seek as _, SeekFrom, Write as _};
use std::path::{Path, PathBuf};
use std::sync::Arc;

use eamadm::{
    AgreementRecord, EpisodeRecord, RobotEpisodeMetrics, RunRecord, SubtaskRecord, TrajectoryRecord,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::key::{RunDescription, RunKey, canonical_json};

/// Which training trajectories a stored record keeps (the `--keep-trajectories` option).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum KeepTrajectories {
    /// Only what the figures draw: the evaluation episodes (in trajectories.csv, the first
    /// seed's).
    #[default]
    Figures,
    /// Also every seed's evaluation path and every training trajectory the config records
    /// (its `trajectories` section).
    All,
}

impl KeepTrajectories {
    /// Every value, in the order of the command line's help.
    pub const ALL: [Self; 2] = [Self::Figures, Self::All];

    /// The value's name on the command line and in a store header.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Figures => "figures",
            Self::All => "all",
        }
    }

    /// Whether a record stored keeping `self` holds what `wanted` asks for: all trajectories
    /// serve every request, the figures' only a request for the figures'.
    #[must_use]
    pub fn covers(self, wanted: Self) -> bool {
        self == Self::All || wanted == Self::Figures
    }
}

impl std::fmt::Display for KeepTrajectories {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for KeepTrajectories {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|keep| keep.name() == text)
            .ok_or_else(|| format!("{text:?} is not one of `figures`, `all`"))
    }
}

/// Version of the line layout above; bump it when the layout changes. Format 3 (this one)
/// checksums the header's fields too; entries of earlier formats are reported and recomputed.
pub const RUN_LINE_FORMAT: u64 = 3;

/// The most bytes one entry may decompress to: far above any run's line (the largest, a robot
/// run keeping all trajectories, is a few MB), far below what would strain memory.
pub const MAX_ENTRY_BYTES: u64 = 256 << 20;

/// The folder inside `runs/` of runs stored one file each, before they are packed.
pub const LOOSE_FOLDER: &str = crate::names::LOOSE_RUNS;

/// The ending of bundle file names: JSON lines, each line its own gzip member.
pub const BUNDLE_EXTENSION: &str = crate::names::BUNDLE_EXTENSION;

/// A failure to read or write the store.
#[derive(Debug, Error)]
pub enum StoreError {
    /// A bundle could not be read.
    #[error("could not read {}: {source}", path.display())]
    Read {
        /// The bundle or folder.
        path: PathBuf,
        /// Why.
        #[source]
        source: io::Error,
    },
    /// A bundle could not be written.
    #[error("could not write {}: {source}", path.display())]
    Write {
        /// The bundle.
        path: PathBuf,
        /// Why.
        #[source]
        source: io::Error,
    },
    /// A run could not be turned into JSON.
    #[error("could not serialise run {key}: {source}")]
    Serialize {
        /// The run.
        key: RunKey,
        /// Why.
        #[source]
        source: serde_json::Error,
    },
    /// A pre-trained artefact failed its checks ([`crate::pretrained`]): it is trained again.
    #[error("{}: {problem}", path.display())]
    Damaged {
        /// The artefact.
        path: PathBuf,
        /// What is wrong.
        problem: String,
    },
    /// A key could not be computed (its description did not serialise).
    #[error("could not compute a key: {0}")]
    Key(String),
    /// A line that was valid when the store was opened no longer is (the file changed since).
    #[error(
        "{} at byte {offset}: {problem}; the file changed while this command ran — rerun it",
        path.display()
    )]
    Changed {
        /// The bundle.
        path: PathBuf,
        /// Where the line starts.
        offset: u64,
        /// What is wrong.
        problem: String,
    },
}

/// The first part of a line.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct LineHeader {
    format: u64,
    key: String,
    experiment: String,
    method: String,
    seed: u64,
    trajectories: KeepTrajectories,
    blake3: String,
}

/// The header's fields the checksum covers (all but the checksum), in the header's order.
#[derive(Serialize)]
struct HashedHeader<'a> {
    format: u64,
    key: &'a str,
    experiment: &'a str,
    method: &'a str,
    seed: u64,
    trajectories: KeepTrajectories,
}

impl LineHeader {
    /// The checksum of this header's fields and `content` (`<description><TAB><record>`).
    fn checksum(&self, content: &[u8]) -> String {
        let fields = HashedHeader {
            format: self.format,
            key: &self.key,
            experiment: &self.experiment,
            method: &self.method,
            seed: self.seed,
            trajectories: self.trajectories,
        };
        let mut hasher = blake3::Hasher::new();
        // Serialising plain strings and numbers cannot fail; an empty hash input would only
        // make the check fail.
        hasher.update(&serde_json::to_vec(&fields).unwrap_or_default());
        hasher.update(b"\t");
        hasher.update(content);
        hasher.finalize().to_hex().to_string()
    }
}

/// Where a verified entry is.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Location {
    /// The bundle or loose run file.
    file: Arc<PathBuf>,
    /// Whether `file` is a loose run file (removed once packed) rather than a bundle.
    loose: bool,
    offset: u64,
    len: usize,
    trajectories: KeepTrajectories,
    experiment: String,
    /// The BLAKE3 hash of the entry's compressed bytes as verified (or as written by this
    /// process): bytes read back later with this hash are those very bytes, so they are copied
    /// without decompressing and parsing them again ([`RunStore::pack`]).
    digest: blake3::Hash,
}

/// What [`RunStore::append`] wrote: the run's loose file, its length and the BLAKE3 hash of its
/// bytes, and the header fields the index needs. Handed to [`RunStore::open_with_receipts`], it
/// lets the reopened store index that loose file without decompressing and parsing it, as long
/// as the file still holds exactly those bytes. It is a few dozen bytes whatever the run's size,
/// and only [`RunStore::append`] makes one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AppendReceipt {
    key: RunKey,
    keep: KeepTrajectories,
    experiment: String,
    len: u64,
    digest: blake3::Hash,
}

impl AppendReceipt {
    /// The run written.
    #[must_use]
    pub fn key(&self) -> &RunKey {
        &self.key
    }

    /// Which trajectories the written record keeps.
    #[must_use]
    pub fn keep(&self) -> KeepTrajectories {
        self.keep
    }
}

/// The files a store being opened may index without checking them in full, because this
/// process checked or made their bytes.
#[derive(Default)]
struct Trusted {
    /// Loose run files by path: those [`RunStore::append`] wrote (their receipts) and those
    /// the store being reopened had verified (used only while the file's bytes hash to the
    /// receipt's digest).
    received: HashMap<PathBuf, AppendReceipt>,
    /// Bundles by path, while their length is the one recorded: those [`RunStore::pack`] just
    /// wrote and those the store being reopened had read, both under the folder's lock (which
    /// no other writer of bundles can hold meanwhile).
    bundles: HashMap<PathBuf, BundleContents>,
}

/// What a bundle held when it was read in full or written: its length, every verified entry in
/// file order (those a richer or earlier duplicate outranks included, so a reopen indexes
/// exactly what a full read would) and the entries that failed their checks.
#[derive(Debug, Clone, Default)]
struct BundleContents {
    len: u64,
    entries: Vec<(RunKey, Location)>,
    rejected: Vec<Rejected>,
}

/// An entry that failed its checks, to be set aside by the next [`RunStore::pack`].
#[derive(Debug, Clone, PartialEq, Eq)]
struct Rejected {
    file: PathBuf,
    loose: bool,
    offset: u64,
    len: usize,
}

/// One line taken apart and checked: its header, description and record.
struct Line<'a> {
    header: LineHeader,
    description: &'a [u8],
    record: RunRecord,
}

/// Splits and checks one line (without its newline): format, checksum, key, and that the record
/// loads and agrees with the header and description.
fn parse_line(bytes: &[u8]) -> Result<Line<'_>, String> {
    let mut parts = bytes.splitn(3, |&b| b == b'\t');
    let (Some(header), Some(description), Some(record)) =
        (parts.next(), parts.next(), parts.next())
    else {
        return Err("not three tab-separated parts (a torn or edited line)".to_owned());
    };
    let header: LineHeader = serde_json::from_slice(header).map_err(|e| format!("header: {e}"))?;
    if header.format != RUN_LINE_FORMAT {
        return Err(format!(
            "format is {}, expected {RUN_LINE_FORMAT}",
            header.format
        ));
    }
    let content = &bytes[bytes.len() - description.len() - 1 - record.len()..];
    let digest = header.checksum(content);
    if digest != header.blake3 {
        return Err(format!(
            "checksum mismatch for run {} (stored {}, header and content hash to {digest}): the \
             line was edited or damaged",
            header.key, header.blake3
        ));
    }
    let key = blake3::hash(description).to_hex();
    if key.as_str() != header.key {
        return Err(format!(
            "the description hashes to {key}, not to the key {}",
            header.key
        ));
    }
    let record = serde_json::from_slice::<StoredRecord>(record)
        .map_err(|e| format!("record: {e}"))?
        .into_record()?;
    let about: DescriptionFields =
        serde_json::from_slice(description).map_err(|e| format!("description: {e}"))?;
    let described_method = about.config.methods.first().map(|m| m.label.as_str());
    let agree = record.experiment == header.experiment
        && record.method == header.method
        && record.seed == header.seed
        && about.seed == header.seed
        && about.config.name == header.experiment
        && described_method == Some(header.method.as_str());
    if !agree {
        return Err(format!(
            "the header says {} {} seed {}, but the record is {} {} seed {} and the description \
             {} {} seed {}",
            header.experiment,
            header.method,
            header.seed,
            record.experiment,
            record.method,
            record.seed,
            about.config.name,
            described_method.unwrap_or("(no method)"),
            about.seed
        ));
    }
    Ok(Line {
        header,
        description,
        record,
    })
}

/// What a line's description says of the run, to check it against the header.
#[derive(Deserialize)]
struct DescriptionFields {
    seed: u64,
    config: DescribedConfig,
}

#[derive(Deserialize)]
struct DescribedConfig {
    name: String,
    methods: Vec<DescribedMethod>,
}

#[derive(Deserialize)]
struct DescribedMethod {
    label: String,
}

/// `record` as the store keeps it under `keep`: without training trajectories unless all are
/// kept (the figures draw only the greedy evaluation, which is always kept).
pub fn compact(mut record: RunRecord, keep: KeepTrajectories) -> RunRecord {
    if keep == KeepTrajectories::Figures {
        record.trajectories = Vec::new();
    }
    record
}

/// A [`RunRecord`] as a store line holds it: the per-episode curve as columns (one array per
/// field) instead of one object per episode, which would repeat every field name per episode —
/// a third of the size. Converting there and back is exact.
#[derive(Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct StoredRecord {
    experiment: String,
    method: String,
    seed: u64,
    optimum_steps: Option<u64>,
    subtasks: Vec<SubtaskRecord>,
    pretrain_env_steps: u64,
    episodes: EpisodeColumns,
    total_env_steps: u64,
    trajectories: Vec<TrajectoryRecord>,
    /// A few per run (one per `evaluation.every` episodes): kept as records.
    #[serde(default)]
    greedy_evaluations: Vec<EpisodeRecord>,
    evaluation: EpisodeRecord,
    evaluation_trajectory: TrajectoryRecord,
    final_window_episodes: u64,
    final_window_actions: Vec<u64>,
    agreement: Option<AgreementRecord>,
}

/// [`EpisodeRecord`]s field by field; every column has one entry per episode.
#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct EpisodeColumns {
    episode: Vec<u64>,
    steps: Vec<u64>,
    task_return: Vec<f64>,
    learning_return: Vec<f64>,
    terminated: Vec<bool>,
    truncated: Vec<bool>,
    reached: Vec<bool>,
    collisions: Vec<u64>,
    env_steps: Vec<u64>,
    robot: Vec<Option<RobotEpisodeMetrics>>,
}

impl StoredRecord {
    fn from_record(record: &RunRecord, keep: KeepTrajectories) -> Self {
        let mut columns = EpisodeColumns::default();
        for e in &record.episodes {
            columns.episode.push(e.episode);
            columns.steps.push(e.steps);
            columns.task_return.push(e.task_return);
            columns.learning_return.push(e.learning_return);
            columns.terminated.push(e.terminated);
            columns.truncated.push(e.truncated);
            columns.reached.push(e.reached);
            columns.collisions.push(e.collisions);
            columns.env_steps.push(e.env_steps);
            columns.robot.push(e.robot);
        }
        Self {
            experiment: record.experiment.clone(),
            method: record.method.clone(),
            seed: record.seed,
            optimum_steps: record.optimum_steps,
            subtasks: record.subtasks.clone(),
            pretrain_env_steps: record.pretrain_env_steps,
            episodes: columns,
            total_env_steps: record.total_env_steps,
            trajectories: match keep {
                KeepTrajectories::All => record.trajectories.clone(),
                KeepTrajectories::Figures => Vec::new(),
            },
            greedy_evaluations: record.greedy_evaluations.clone(),
            evaluation: record.evaluation.clone(),
            evaluation_trajectory: record.evaluation_trajectory.clone(),
            final_window_episodes: record.final_window_episodes,
            final_window_actions: record.final_window_actions.clone(),
            agreement: record.agreement.clone(),
        }
    }

    fn into_record(self) -> Result<RunRecord, String> {
        let c = self.episodes;
        let n = c.episode.len();
        let lengths = [
            c.steps.len(),
            c.task_return.len(),
            c.learning_return.len(),
            c.terminated.len(),
            c.truncated.len(),
            c.reached.len(),
            c.collisions.len(),
            c.env_steps.len(),
            c.robot.len(),
        ];
        if lengths.iter().any(|&len| len != n) {
            return Err(format!(
                "record: the episode columns differ in length ({n} episodes, columns {lengths:?})"
            ));
        }
        let episodes = (0..n)
            .map(|i| EpisodeRecord {
                episode: c.episode[i],
                steps: c.steps[i],
                task_return: c.task_return[i],
                learning_return: c.learning_return[i],
                terminated: c.terminated[i],
                truncated: c.truncated[i],
                reached: c.reached[i],
                collisions: c.collisions[i],
                env_steps: c.env_steps[i],
                robot: c.robot[i],
            })
            .collect();
        Ok(RunRecord {
            experiment: self.experiment,
            method: self.method,
            seed: self.seed,
            optimum_steps: self.optimum_steps,
            subtasks: self.subtasks,
            pretrain_env_steps: self.pretrain_env_steps,
            episodes,
            total_env_steps: self.total_env_steps,
            trajectories: self.trajectories,
            greedy_evaluations: self.greedy_evaluations,
            evaluation: self.evaluation,
            evaluation_trajectory: self.evaluation_trajectory,
            final_window_episodes: self.final_window_episodes,
            final_window_actions: self.final_window_actions,
            agreement: self.agreement,
        })
    }
}

/// The line (with its newline) for `record`, compacted under `keep`.
fn line_bytes(
    key: &RunKey,
    description: &[u8],
    record: &RunRecord,
    keep: KeepTrajectories,
) -> Result<Vec<u8>, StoreError> {
    let serialize = |source| StoreError::Serialize {
        key: key.clone(),
        source,
    };
    let mut content = description.to_vec();
    content.push(b'\t');
    serde_json::to_writer(&mut content, &StoredRecord::from_record(record, keep))
        .map_err(serialize)?;
    let mut header = LineHeader {
        format: RUN_LINE_FORMAT,
        key: key.as_str().to_owned(),
        experiment: record.experiment.clone(),
        method: record.method.clone(),
        seed: record.seed,
        trajectories: keep,
        blake3: String::new(),
    };
    header.blake3 = header.checksum(&content);
    let mut line = serde_json::to_vec(&header).map_err(serialize)?;
    line.push(b'\t');
    line.extend_from_slice(&content);
    line.push(b'\n');
    Ok(line)
}

/// The bundle entry for `record`, compacted under `keep`: its line as one gzip member.
fn entry_bytes(
    key: &RunKey,
    description: &[u8],
    record: &RunRecord,
    keep: KeepTrajectories,
) -> Result<Vec<u8>, StoreError> {
    let line = line_bytes(key, description, record, keep)?;
    crate::gzip::compress(&line).map_err(|e| StoreError::Serialize {
        key: key.clone(),
        source: serde_json::Error::io(e),
    })
}

/// A run read back from a store: its description (canonical JSON) and record.
#[derive(Debug, Clone, PartialEq)]
pub struct StoredRun {
    /// The run's description, as stored (its hash is the key).
    pub description: Vec<u8>,
    /// The record, compacted as asked.
    pub record: RunRecord,
}

impl StoredRun {
    /// The entry of this run in a bundle (one gzip member), compacted under `keep`.
    pub fn entry(&self, key: &RunKey, keep: KeepTrajectories) -> Result<Vec<u8>, StoreError> {
        entry_bytes(key, &self.description, &self.record, keep)
    }
}

/// The runs of one store folder (`<out>/runs/`), indexed when opened: the index holds where each
/// verified entry is, never the records, so memory does not grow with the runs' size.
#[derive(Debug)]
pub struct RunStore {
    folder: PathBuf,
    index: HashMap<RunKey, Location>,
    rejected: Vec<Rejected>,
    /// What each bundle held when this store read it in full or wrote it, for
    /// [`RunStore::reopen`] (a few dozen bytes a run, never a record).
    bundles: HashMap<PathBuf, BundleContents>,
}

impl RunStore {
    /// The store of the output folder `out` (its `runs/`; none yet is an empty store). Every
    /// bundle and loose run is read and checked; each bad entry is passed to `warn` and ignored
    /// (its run will be recomputed). Nothing is changed on disk.
    pub fn open(out: &Path, warn: &mut dyn FnMut(&str)) -> Result<Self, StoreError> {
        Self::open_with_receipts(out, &[], warn)
    }

    /// Like [`RunStore::open`], but a loose run file this process wrote is indexed from its
    /// `receipts` ([`RunStore::append`]'s) without being decompressed and parsed again, when
    /// the file's length and the BLAKE3 hash of its bytes equal the receipt's: those are the
    /// bytes `append` made from the record it serialised. Any other file, and a receipted file
    /// whose bytes differ (replaced by another process, damaged, cut short), is checked in full
    /// as [`RunStore::open`] does; a receipt whose file is gone is ignored.
    pub fn open_with_receipts(
        out: &Path,
        receipts: &[AppendReceipt],
        warn: &mut dyn FnMut(&str),
    ) -> Result<Self, StoreError> {
        let folder = out.join(crate::names::RUNS_FOLDER);
        crate::no_follow::check_under(out, Path::new(crate::names::RUNS_FOLDER), false).map_err(
            |source| StoreError::Read {
                path: folder.clone(),
                source,
            },
        )?;
        let received = receipts
            .iter()
            .map(|receipt| {
                let path = loose_path_in(&folder, &receipt.key, receipt.keep);
                (path, receipt.clone())
            })
            .collect();
        let trusted = Trusted {
            received,
            bundles: HashMap::new(),
        };
        Self::open_folder(&folder, trusted, warn)
    }

    /// This store opened again, as [`RunStore::open_with_receipts`] would open its output
    /// folder with `receipts`, without reading again what this store has already checked: a
    /// bundle whose length is the one this store read (or wrote) is indexed from what it held,
    /// and a loose file it indexed is trusted while its bytes hash to the digest checked. This
    /// is for a process holding the folder's lock ([`crate::output_folder::OutputFolder`]) since
    /// this store was opened, so that no bundle can have been rewritten meanwhile; any other
    /// file, a bundle of another length and a loose file with other bytes are checked in full.
    /// (Bytes damaged in place are still found: [`RunStore::pack`] hashes every entry it copies
    /// and [`RunStore::load`] checks in full.)
    pub fn reopen(
        self,
        receipts: &[AppendReceipt],
        warn: &mut dyn FnMut(&str),
    ) -> Result<Self, StoreError> {
        let out = self.folder.parent().unwrap_or(Path::new("."));
        crate::no_follow::check_under(out, Path::new(crate::names::RUNS_FOLDER), false).map_err(
            |source| StoreError::Read {
                path: self.folder.clone(),
                source,
            },
        )?;
        // The loose files this store verified, as receipts of their bytes; the receipts of runs
        // appended since take their place where both name a file.
        let mut received: HashMap<PathBuf, AppendReceipt> = self
            .index
            .iter()
            .filter(|(_, at)| at.loose)
            .map(|(key, at)| {
                let receipt = AppendReceipt {
                    key: key.clone(),
                    keep: at.trajectories,
                    experiment: at.experiment.clone(),
                    len: at.len as u64,
                    digest: at.digest,
                };
                (at.file.to_path_buf(), receipt)
            })
            .collect();
        for receipt in receipts {
            let path = loose_path_in(&self.folder, &receipt.key, receipt.keep);
            received.insert(path, receipt.clone());
        }
        let trusted = Trusted {
            received,
            bundles: self.bundles,
        };
        Self::open_folder(&self.folder, trusted, warn)
    }

    /// A store opened only to read (as `merge` does): `path` is an output folder (its `runs/` is
    /// read) or a `runs/` folder itself. Nothing is changed on disk.
    pub fn open_read_only(path: &Path, warn: &mut dyn FnMut(&str)) -> Result<Self, StoreError> {
        let runs = path.join(crate::names::RUNS_FOLDER);
        let folder = if runs.is_dir() {
            runs
        } else {
            path.to_path_buf()
        };
        if !folder.is_dir() {
            return Err(StoreError::Read {
                path: path.to_path_buf(),
                source: io::Error::new(
                    io::ErrorKind::NotFound,
                    "not a run store (neither a folder with runs/ nor a runs/ folder)",
                ),
            });
        }
        Self::open_folder(&folder, Trusted::default(), warn)
    }

    /// Indexes every bundle (sorted by path) and then every loose run file (sorted by path) of
    /// `folder`, each checked in full unless `trusted` vouches for its bytes.
    fn open_folder(
        folder: &Path,
        mut trusted: Trusted,
        warn: &mut dyn FnMut(&str),
    ) -> Result<Self, StoreError> {
        let mut store = Self {
            folder: folder.to_path_buf(),
            index: HashMap::new(),
            rejected: Vec::new(),
            bundles: HashMap::new(),
        };
        let read = |path: &Path| {
            let path = path.to_path_buf();
            move |source| StoreError::Read { path, source }
        };
        let mut bundles = Vec::new();
        for (path, name) in list(folder).map_err(read(folder))? {
            if name.ends_with(&format!(".{BUNDLE_EXTENSION}")) {
                bundles.push(path);
            } else if name.ends_with(".jsonl") {
                // The uncompressed bundle of an earlier version: say why its runs do not count,
                // instead of silently recomputing or listing them missing.
                warn(&format!(
                    "{}: an uncompressed bundle written by an earlier version; its runs are not \
                     read (they are recomputed, and the file is removed when its experiment's \
                     outputs are next written)",
                    path.display()
                ));
            }
        }
        // Sorted, so which of two equal entries is indexed does not depend on directory order.
        bundles.sort();
        for path in bundles {
            match trusted.bundles.remove(&path) {
                // A symbolic link or special file has no length here and is checked (and
                // named) in full below.
                Some(contents)
                    if std::fs::symlink_metadata(&path)
                        .is_ok_and(|meta| meta.is_file() && meta.len() == contents.len) =>
                {
                    for (key, location) in &contents.entries {
                        store.insert(key.clone(), location.clone());
                    }
                    store.rejected.extend(contents.rejected.iter().cloned());
                    store.bundles.insert(path, contents);
                }
                _ => store.index_file(&path, false, warn)?,
            }
        }
        let loose_folder = folder.join(LOOSE_FOLDER);
        crate::no_follow::check_under(folder, Path::new(LOOSE_FOLDER), false)
            .map_err(read(&loose_folder))?;
        let mut loose: Vec<PathBuf> = list(&loose_folder)
            .map_err(read(&loose_folder))?
            .into_iter()
            .filter(|(_, name)| name.ends_with(&format!(".{}", crate::names::RUN_FILE_EXTENSION)))
            .map(|(path, _)| path)
            .collect();
        loose.sort();
        for path in loose {
            let received = trusted.received.get(&path);
            if !received.is_some_and(|receipt| store.index_received(&path, receipt)) {
                store.index_file(&path, true, warn)?;
            }
        }
        Ok(store)
    }

    /// Indexes the loose file `path` from `receipt` if the file holds exactly the bytes
    /// [`RunStore::append`] wrote (same length, same BLAKE3 hash); returns whether it did. A
    /// file that cannot be read or holds other bytes is left to the full check, which reports
    /// it as [`RunStore::open`] does.
    fn index_received(&mut self, path: &Path, receipt: &AppendReceipt) -> bool {
        let Ok(file) = crate::no_follow::open_regular(path) else {
            return false;
        };
        let mut bytes = Vec::new();
        // One byte more than the receipt's length reveals a longer file without reading it all.
        let read = file
            .take(receipt.len.saturating_add(1))
            .read_to_end(&mut bytes);
        if read.is_err()
            || bytes.len() as u64 != receipt.len
            || blake3::hash(&bytes) != receipt.digest
        {
            return false;
        }
        let location = Location {
            file: Arc::new(path.to_path_buf()),
            loose: true,
            offset: 0,
            len: bytes.len(),
            trajectories: receipt.keep,
            experiment: receipt.experiment.clone(),
            digest: receipt.digest,
        };
        self.insert(receipt.key.clone(), location);
        true
    }

    /// Adds a verified entry to the index: the richest stored version serves; of equals, the
    /// first indexed stays.
    fn insert(&mut self, key: RunKey, location: Location) {
        match self.index.entry(key) {
            std::collections::hash_map::Entry::Vacant(entry) => {
                entry.insert(location);
            }
            std::collections::hash_map::Entry::Occupied(mut entry) => {
                if !entry.get().trajectories.covers(location.trajectories) {
                    entry.insert(location);
                }
            }
        }
    }

    /// Reads and checks every entry of the bundle or loose file `path` into the index, one
    /// entry in memory at a time.
    fn index_file(
        &mut self,
        path: &Path,
        loose: bool,
        warn: &mut dyn FnMut(&str),
    ) -> Result<(), StoreError> {
        let file = match crate::no_follow::open_regular(path) {
            Ok(file) => file,
            Err(error) if error.kind() == io::ErrorKind::InvalidInput => {
                // A link or special file where a store file belongs: named, never followed.
                warn(&format!("{error}"));
                return Ok(());
            }
            // Packed and removed by another process since it was listed.
            Err(error) if loose && error.kind() == io::ErrorKind::NotFound => return Ok(()),
            Err(source) => {
                return Err(StoreError::Read {
                    path: path.to_path_buf(),
                    source,
                });
            }
        };
        let shared = Arc::new(path.to_path_buf());
        let end = file
            .metadata()
            .map_err(|source| StoreError::Read {
                path: path.to_path_buf(),
                source,
            })?
            .len();
        let mut reader = BufReader::new(file);
        let mut offset = 0_u64;
        let mut line = Vec::new();
        let mut number = 0_usize;
        // A bundle's verified entries and rejected ones, recorded for `reopen`.
        let rejected_before = self.rejected.len();
        let mut entries = Vec::new();
        while offset < end {
            number += 1;
            let (next, digest) = match read_entry(&mut reader, offset, &mut line) {
                Ok(read) => read,
                Err(problem) => {
                    // Damaged or incomplete: go on at the next entry that decompresses whole.
                    let next = next_entry(&mut reader, offset + 1, &mut line)
                        .map_err(|source| StoreError::Read {
                            path: path.to_path_buf(),
                            source,
                        })?
                        .unwrap_or(end);
                    warn(&format!(
                        "{} entry {number} (byte {offset}): {} ({problem}); ignored, the run \
                         will be recomputed",
                        path.display(),
                        if next < end {
                            "damaged"
                        } else {
                            "incomplete or damaged"
                        }
                    ));
                    self.reject(path, loose, offset, next);
                    offset = next;
                    continue;
                }
            };
            let checked = match line.strip_suffix(b"\n") {
                Some(text) => parse_line(text),
                None => Err("not one whole line (no newline at its end)".to_owned()),
            };
            match checked {
                Ok(parsed) => {
                    let key = RunKey::from_verified_hex(parsed.header.key);
                    let location = Location {
                        file: Arc::clone(&shared),
                        loose,
                        offset,
                        len: usize::try_from(next - offset).unwrap_or(usize::MAX),
                        trajectories: parsed.header.trajectories,
                        experiment: parsed.header.experiment,
                        digest,
                    };
                    if !loose {
                        entries.push((key.clone(), location.clone()));
                    }
                    self.insert(key, location);
                }
                Err(problem) => {
                    warn(&format!(
                        "{} entry {number} (byte {offset}): {problem}; ignored, the run will be \
                         recomputed",
                        path.display()
                    ));
                    self.reject(path, loose, offset, next);
                }
            }
            offset = next;
        }
        if !loose {
            let contents = BundleContents {
                len: end,
                entries,
                rejected: self.rejected[rejected_before..].to_vec(),
            };
            self.bundles.insert(path.to_path_buf(), contents);
        }
        Ok(())
    }

    fn reject(&mut self, path: &Path, loose: bool, offset: u64, next: u64) {
        self.rejected.push(Rejected {
            file: path.to_path_buf(),
            loose,
            offset,
            len: usize::try_from(next.saturating_sub(offset)).unwrap_or(usize::MAX),
        });
    }

    /// The folder of the bundles.
    #[must_use]
    pub fn folder(&self) -> &Path {
        &self.folder
    }

    /// The bundle file of experiment `experiment`.
    #[must_use]
    pub fn bundle_path(&self, experiment: &str) -> PathBuf {
        self.folder.join(format!("{experiment}.{BUNDLE_EXTENSION}"))
    }

    /// The loose run file of run `key` keeping `keep`.
    #[must_use]
    pub fn loose_path(&self, key: &RunKey, keep: KeepTrajectories) -> PathBuf {
        loose_path_in(&self.folder, key, keep)
    }

    /// Whether run `key` was stored (and verified when the store was opened, or written by this
    /// process with those very bytes) keeping at least the trajectories `keep` asks for.
    #[must_use]
    pub fn has(&self, key: &RunKey, keep: KeepTrajectories) -> bool {
        self.index
            .get(key)
            .is_some_and(|location| location.trajectories.covers(keep))
    }

    /// How many verified runs the store holds.
    #[must_use]
    pub fn len(&self) -> usize {
        self.index.len()
    }

    /// The keys of every verified run, in storage order: file by file (bundles and loose run
    /// files by path, so experiment by experiment), and in a file by place; a packed bundle
    /// holds its runs in the plan's job order (method by method, seed by seed).
    #[must_use]
    pub fn keys(&self) -> Vec<&RunKey> {
        let mut keys: Vec<(&RunKey, &Location)> = self.index.iter().collect();
        keys.sort_by(|(_, a), (_, b)| (&a.file, a.offset).cmp(&(&b.file, b.offset)));
        keys.into_iter().map(|(key, _)| key).collect()
    }

    /// Whether the store holds no verified run.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.index.is_empty()
    }

    /// The entry at `location`, read and checked again (a loose file may have been replaced
    /// by another process's identical copy since it was indexed).
    fn entry_at(location: &Location) -> Result<CheckedEntry, StoreError> {
        let path: &Path = &location.file;
        let read = |source| StoreError::Read {
            path: path.to_path_buf(),
            source,
        };
        let mut file = crate::no_follow::open_regular(path).map_err(read)?;
        file.seek(SeekFrom::Start(location.offset)).map_err(read)?;
        let mut entry = vec![0; location.len];
        file.read_exact(&mut entry).map_err(read)?;
        let changed = |problem: String| StoreError::Changed {
            path: path.to_path_buf(),
            offset: location.offset,
            problem,
        };
        let mut rest = entry.as_slice();
        let mut bytes = Vec::new();
        capped_decompress(&mut rest, &mut bytes)
            .map_err(|e| changed(format!("the entry no longer decompresses: {e}")))?;
        if !rest.is_empty() || bytes.last() != Some(&b'\n') {
            return Err(changed("the entry is not one whole line".to_owned()));
        }
        bytes.pop();
        let line = parse_line(&bytes).map_err(&changed)?;
        let (header, description, record) = (line.header, line.description.to_vec(), line.record);
        Ok(CheckedEntry {
            entry,
            header,
            description,
            record,
        })
    }

    /// Reads run `key`, compacted under `keep`: `Ok(None)` if the store does not hold it with
    /// the trajectories `keep` asks for.
    pub fn load(
        &self,
        key: &RunKey,
        keep: KeepTrajectories,
    ) -> Result<Option<StoredRun>, StoreError> {
        let Some(location) = self.index.get(key) else {
            return Ok(None);
        };
        if !location.trajectories.covers(keep) {
            return Ok(None);
        }
        let checked = Self::entry_at(location)?;
        if checked.header.key != key.as_str() {
            return Err(StoreError::Changed {
                path: location.file.to_path_buf(),
                offset: location.offset,
                problem: format!("it holds run {}, not {key}", checked.header.key),
            });
        }
        Ok(Some(StoredRun {
            description: checked.description,
            record: compact(checked.record, keep),
        }))
    }

    /// Stores a finished run in a file of its own, `runs/loose/<key>.<keep>.run.gz`: written
    /// aside, synced, then renamed into place, so no other process ever sees it half written and
    /// no two processes write the same file. (Two storing the same run write the same bytes.)
    /// Needs no lock; [`RunStore::pack`] moves it into its bundle later. Returns the receipt
    /// of the bytes written, with which [`RunStore::open_with_receipts`] indexes the file
    /// without reading it back in full.
    pub fn append(
        &self,
        key: &RunKey,
        description: &RunDescription,
        record: &RunRecord,
        keep: KeepTrajectories,
    ) -> Result<AppendReceipt, StoreError> {
        let path = self.loose_path(key, keep);
        let write = |source| StoreError::Write {
            path: path.clone(),
            source,
        };
        let description =
            canonical_json(description).map_err(|e| write(io::Error::other(e.to_string())))?;
        let entry = entry_bytes(key, description.as_bytes(), record, keep)?;
        let out = self.folder.parent().unwrap_or(Path::new("."));
        crate::no_follow::ensure_folders(
            out,
            &Path::new(crate::names::RUNS_FOLDER).join(LOOSE_FOLDER),
        )
        .map_err(write)?;
        crate::atomic::write_atomic(&path, &entry).map_err(|e| write(e.source))?;
        Ok(AppendReceipt {
            key: key.clone(),
            keep,
            experiment: record.experiment.clone(),
            len: entry.len() as u64,
            digest: blake3::hash(&entry),
        })
    }

    /// Packs the store into its bundles, one per experiment: the union of every verified entry
    /// of this store and of the runs `wanted` that `sources` hold (as `merge` takes them from
    /// other stores), each run once with the richest trajectories stored. A bundle lists first
    /// the runs of `wanted` in that order (the plan's job order), then any other runs by key, so
    /// its bytes are a function of the set of runs. The entries that failed their checks are
    /// first set aside in `runs/.set-aside/`. Entries are copied byte for byte, each read again
    /// on the way: bytes that still hash to the digest taken when they were verified (or
    /// written) are copied as they are, any others are checked in full again (a loose file
    /// replaced by another process since it was indexed is packed as what it now holds, and one
    /// that no longer checks is [`StoreError::Changed`], with nothing removed). Then the loose
    /// files now in a bundle are removed, and temporary files of killed writers are removed.
    /// Needs the output folder's lock (`_lock`), so no two packs overlap; writers of loose runs
    /// may go on meanwhile (their new files stay loose). Returns the store reopened: what
    /// [`RunStore::open`] would read, with the bundles just written indexed from what was
    /// written rather than read back, and every other file checked in full.
    pub fn pack(
        self,
        _lock: &crate::output_folder::OutputFolder,
        sources: &[RunStore],
        wanted: &[RunKey],
        warn: &mut dyn FnMut(&str),
    ) -> Result<Self, StoreError> {
        let folder = self.folder.clone();
        let write = |path: &Path| {
            let path = path.to_path_buf();
            move |source| StoreError::Write { path, source }
        };
        let out = folder.parent().unwrap_or(Path::new(".")).to_path_buf();
        crate::no_follow::ensure_folders(&out, Path::new(crate::names::RUNS_FOLDER))
            .map_err(write(&folder))?;
        // Every run to pack and where its entry is, per experiment.
        let mut chosen: HashMap<RunKey, &Location> = self
            .index
            .iter()
            .map(|(key, at)| (key.clone(), at))
            .collect();
        for key in wanted {
            let better = sources
                .iter()
                .filter_map(|store| store.index.get(key))
                .find(|at| {
                    chosen
                        .get(key)
                        .is_none_or(|own| !own.trajectories.covers(at.trajectories))
                });
            if let Some(at) = better {
                chosen.insert(key.clone(), at);
            }
        }
        let position: HashMap<&RunKey, usize> =
            wanted.iter().enumerate().map(|(i, key)| (key, i)).collect();
        let mut experiments: Vec<&str> = chosen.values().map(|at| at.experiment.as_str()).collect();
        experiments.sort_unstable();
        experiments.dedup();
        // Rejected entries are copied aside before their bundles are replaced below: afterwards
        // their offsets would point into the new bundles.
        self.set_aside(warn)?;
        // What each bundle written holds, to index it without reading it back.
        let mut written = HashMap::new();
        for experiment in experiments {
            let mut keys: Vec<&RunKey> = chosen
                .iter()
                .filter(|(_, at)| at.experiment == experiment)
                .map(|(key, _)| key)
                .collect();
            keys.sort_by_key(|key| {
                (
                    position.get(key).copied().unwrap_or(usize::MAX),
                    (*key).clone(),
                )
            });
            let path = self.bundle_path(experiment);
            let mut bundle =
                crate::atomic::AtomicFile::create(&path).map_err(|e| write(&path)(e.source))?;
            let shared = Arc::new(path.clone());
            let mut entries = Vec::with_capacity(keys.len());
            let mut offset = 0_u64;
            let mut source = OpenSource::default();
            for key in &keys {
                let at = chosen[*key];
                let (bytes, key, location) = match source.read_verified(at) {
                    // The very bytes verified (or written) earlier: copied as they are.
                    Some(bytes) => {
                        let location = Location {
                            file: Arc::clone(&shared),
                            loose: false,
                            offset,
                            len: bytes.len(),
                            trajectories: at.trajectories,
                            experiment: at.experiment.clone(),
                            digest: at.digest,
                        };
                        (bytes, (*key).clone(), location)
                    }
                    // Changed since (another process's copy of a loose file, or damage):
                    // checked in full again, and indexed as what it now holds.
                    None => {
                        let checked = Self::entry_at(at)?;
                        let location = Location {
                            file: Arc::clone(&shared),
                            loose: false,
                            offset,
                            len: checked.entry.len(),
                            trajectories: checked.header.trajectories,
                            experiment: checked.header.experiment,
                            digest: blake3::hash(&checked.entry),
                        };
                        let key = RunKey::from_verified_hex(checked.header.key);
                        (checked.entry, key, location)
                    }
                };
                bundle.write_all(&bytes).map_err(write(&path))?;
                offset += bytes.len() as u64;
                entries.push((key, location));
            }
            bundle.commit().map_err(|e| write(&path)(e.source))?;
            let contents = BundleContents {
                len: offset,
                entries,
                rejected: Vec::new(),
            };
            written.insert(path, contents);
        }
        // The loose runs now packed, and the rejected entries, leave the loose folder.
        let mut packed: Vec<&Path> = self
            .index
            .values()
            .filter(|at| at.loose)
            .map(|at| at.file.as_path())
            .collect();
        packed.sort_unstable();
        packed.dedup();
        for path in packed {
            match std::fs::remove_file(path) {
                Ok(()) => {}
                Err(error) if error.kind() == io::ErrorKind::NotFound => {}
                Err(source) => return Err(write(path)(source)),
            }
        }
        for dir in [
            folder.clone(),
            folder.join(LOOSE_FOLDER),
            folder.join(crate::names::PRETRAINED),
        ] {
            crate::atomic::remove_stale_temporary_files(&dir).map_err(write(&dir))?;
        }
        drop(chosen);
        // Reopened as `open` would (every other file checked in full: other bundles, loose runs
        // that appeared meanwhile, loose runs not packed), its own bundles from what it wrote.
        let trusted = Trusted {
            received: HashMap::new(),
            bundles: written,
        };
        Self::open_folder(&folder, trusted, &mut |_| {})
    }

    /// Copies each rejected entry into `runs/.set-aside/` (a loose file is moved there whole),
    /// so it is reported once and kept for inspection, never deleted.
    fn set_aside(&self, warn: &mut dyn FnMut(&str)) -> Result<(), StoreError> {
        if self.rejected.is_empty() {
            return Ok(());
        }
        let aside = self.folder.join(crate::names::SET_ASIDE);
        let write = |path: &Path| {
            let path = path.to_path_buf();
            move |source| StoreError::Write { path, source }
        };
        crate::no_follow::ensure_folder(&aside).map_err(write(&aside))?;
        for rejected in &self.rejected {
            let name = rejected
                .file
                .file_name()
                .map_or_else(|| "entry".into(), |n| n.to_string_lossy().into_owned());
            let target = aside.join(format!("{name}.at-{}", rejected.offset));
            if rejected.loose {
                std::fs::rename(&rejected.file, &target).map_err(write(&target))?;
            } else {
                let read = |source| StoreError::Read {
                    path: rejected.file.clone(),
                    source,
                };
                let mut file = crate::no_follow::open_regular(&rejected.file).map_err(read)?;
                file.seek(SeekFrom::Start(rejected.offset)).map_err(read)?;
                let mut bytes = Vec::new();
                file.take(rejected.len as u64)
                    .read_to_end(&mut bytes)
                    .map_err(read)?;
                crate::atomic::write_atomic(&target, &bytes)
                    .map_err(|e| write(&target)(e.source))?;
            }
            warn(&format!(
                "{} (byte {}): set aside as {}",
                rejected.file.display(),
                rejected.offset,
                target.display()
            ));
        }
        Ok(())
    }
}

/// The file [`RunStore::pack`] last read an entry from, kept open for the next entry of the same
/// bundle.
#[derive(Default)]
struct OpenSource {
    open: Option<(Arc<PathBuf>, File)>,
}

impl OpenSource {
    /// The compressed bytes at `location` if they hash to its digest, i.e. are the bytes
    /// verified when it was indexed; `None` if they differ or cannot be read (the caller then
    /// checks the entry in full, which reports why).
    fn read_verified(&mut self, location: &Location) -> Option<Vec<u8>> {
        // A loose file is reopened for its one entry, so one replaced since it was indexed is
        // read as it now is; a bundle, which only a pack under the lock rewrites, stays open.
        let reuse = !location.loose
            && self
                .open
                .as_ref()
                .is_some_and(|(path, _)| path == &location.file);
        if !reuse {
            let file = crate::no_follow::open_regular(&location.file).ok()?;
            self.open = Some((Arc::clone(&location.file), file));
        }
        let (_, file) = self.open.as_mut()?;
        file.seek(SeekFrom::Start(location.offset)).ok()?;
        let mut bytes = vec![0; location.len];
        file.read_exact(&mut bytes).ok()?;
        (blake3::hash(&bytes) == location.digest).then_some(bytes)
    }
}

/// An entry read and checked: its compressed bytes and what they hold.
struct CheckedEntry {
    entry: Vec<u8>,
    header: LineHeader,
    description: Vec<u8>,
    record: RunRecord,
}

/// Checks the bytes of a bundle or loose run file as [`RunStore::open`] does, in memory:
/// how many entries verify, and one problem per entry that does not. Never panics and never
/// holds more than [`MAX_ENTRY_BYTES`] of one entry (the fuzz target `store_bytes` calls it).
#[must_use]
pub fn check_bytes(bytes: &[u8]) -> (usize, Vec<String>) {
    let mut rest = bytes;
    let mut verified = 0;
    let mut problems = Vec::new();
    let mut line = Vec::new();
    while !rest.is_empty() {
        let start = bytes.len() - rest.len();
        match capped_decompress(&mut rest, &mut line) {
            Ok(()) => match line.strip_suffix(b"\n").map(parse_line) {
                Some(Ok(_)) => verified += 1,
                Some(Err(problem)) => problems.push(problem),
                None => problems.push("not one whole line".to_owned()),
            },
            Err(error) => {
                problems.push(error.to_string());
                // Resume at the next byte that may start a member, as the store's reader does.
                let next = bytes[start + 1..]
                    .iter()
                    .position(|&b| b == 0x1f)
                    .map_or(bytes.len(), |skip| start + 1 + skip);
                rest = &bytes[next..];
            }
        }
    }
    (verified, problems)
}

/// The loose run file of run `key` keeping `keep` in the store folder `folder`.
fn loose_path_in(folder: &Path, key: &RunKey, keep: KeepTrajectories) -> PathBuf {
    folder
        .join(LOOSE_FOLDER)
        .join(format!("{key}.{keep}.{}", crate::names::RUN_FILE_EXTENSION))
}

/// The regular files and other entries of `folder` (none when it does not exist), as path and
/// name.
fn list(folder: &Path) -> io::Result<Vec<(PathBuf, String)>> {
    let entries = match std::fs::read_dir(folder) {
        Ok(entries) => entries,
        Err(error) if error.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(error) => return Err(error),
    };
    let mut found = Vec::new();
    for entry in entries {
        let entry = entry?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if entry.file_type()?.is_dir() {
            continue;
        }
        found.push((entry.path(), name));
    }
    Ok(found)
}

/// Decompresses one gzip member from the start of `reader` into `line`, refusing more than
/// [`MAX_ENTRY_BYTES`] (checked while reading, so a small file that inflates enormously never
/// fills memory).
fn capped_decompress<R: BufRead>(reader: &mut R, line: &mut Vec<u8>) -> io::Result<()> {
    line.clear();
    // The bufread decoder takes exactly one member's bytes from the reader, so the reader's
    // position afterwards is where the next member starts.
    let mut decoder = flate2::bufread::GzDecoder::new(reader);
    let read = (&mut decoder).take(MAX_ENTRY_BYTES + 1).read_to_end(line)?;
    if read as u64 > MAX_ENTRY_BYTES {
        return Err(io::Error::other(format!(
            "it decompresses to more than {MAX_ENTRY_BYTES} bytes, the cap of one entry"
        )));
    }
    Ok(())
}

/// Decompresses the entry at byte `at` of the file into `line`; returns where the next entry
/// starts and the BLAKE3 hash of the entry's compressed bytes, or why the entry is damaged or
/// incomplete.
fn read_entry(
    reader: &mut BufReader<File>,
    at: u64,
    line: &mut Vec<u8>,
) -> Result<(u64, blake3::Hash), String> {
    let io = |e: io::Error| e.to_string();
    if reader.stream_position().map_err(io)? != at {
        reader.seek(SeekFrom::Start(at)).map_err(io)?;
    }
    let mut hashing = Hashing::new(reader);
    capped_decompress(&mut hashing, line).map_err(io)?;
    let (digest, hashed) = hashing.finish();
    let next = reader.stream_position().map_err(io)?;
    // The decoder takes its member's bytes, and only those, through the hashing reader.
    if next.checked_sub(at) != Some(hashed) {
        return Err(format!(
            "read {hashed} bytes of a {}-byte entry (a file changing while read)",
            next - at
        ));
    }
    Ok((next, digest))
}

/// A reader that hashes every byte taken from the reader it wraps, whether read or consumed
/// from its buffer: the compressed bytes of one entry as the gzip decoder takes them.
struct Hashing<'a, R> {
    inner: &'a mut R,
    hasher: blake3::Hasher,
    taken: u64,
}

impl<'a, R: BufRead> Hashing<'a, R> {
    fn new(inner: &'a mut R) -> Self {
        Self {
            inner,
            hasher: blake3::Hasher::new(),
            taken: 0,
        }
    }

    /// The hash of the bytes taken, and how many.
    fn finish(self) -> (blake3::Hash, u64) {
        (self.hasher.finalize(), self.taken)
    }
}

impl<R: BufRead> io::Read for Hashing<'_, R> {
    fn read(&mut self, into: &mut [u8]) -> io::Result<usize> {
        let read = self.inner.read(into)?;
        self.hasher.update(&into[..read]);
        self.taken += read as u64;
        Ok(read)
    }
}

impl<R: BufRead> BufRead for Hashing<'_, R> {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        self.inner.fill_buf()
    }

    fn consume(&mut self, amount: usize) {
        if amount > 0 {
            // The buffer `fill_buf` returned is still there (consuming is what changes it), so
            // asking again reads nothing; a failure here cannot happen and would show as a
            // count that disagrees with the reader's position (checked by `read_entry`).
            if let Ok(buffer) = self.inner.fill_buf() {
                let taken = &buffer[..amount.min(buffer.len())];
                self.hasher.update(taken);
                self.taken += taken.len() as u64;
            }
        }
        self.inner.consume(amount);
    }
}

/// The first byte at or after `from` where a whole entry decompresses, if any.
fn next_entry(
    reader: &mut BufReader<File>,
    from: u64,
    line: &mut Vec<u8>,
) -> io::Result<Option<u64>> {
    /// The first byte of a gzip member.
    const MAGIC: u8 = 0x1f;
    let mut at = from;
    loop {
        reader.seek(SeekFrom::Start(at))?;
        let buffer = reader.fill_buf()?;
        if buffer.is_empty() {
            return Ok(None);
        }
        match buffer.iter().position(|&b| b == MAGIC) {
            Some(skip) => {
                let candidate = at + skip as u64;
                if read_entry(reader, candidate, line).is_ok() {
                    return Ok(Some(candidate));
                }
                at = candidate + 1;
            }
            None => at += buffer.len() as u64,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gzip;

    /// Two tiny runs of Task I and their descriptions.
    pub(crate) fn runs() -> Vec<(RunKey, RunDescription, RunRecord)> {
        runs_of(2)
    }

    /// `seeds` tiny runs of Task I and their descriptions.
    fn runs_of(seeds: u32) -> Vec<(RunKey, RunDescription, RunRecord)> {
        let mut config = eamadm::paper::task1();
        config.episodes = 3;
        config.seeds = seeds;
        config.trajectories.episodes.retain(|&e| e < 3);
        if let eamadm::TaskConfig::Maze { step_cap, .. } = &mut config.task {
            *step_cap = Some(40);
        }
        config.methods.retain(|m| m.label == "epsilon-greedy");
        let experiment = eamadm::Experiment::new(config.clone()).unwrap();
        let method = &config.methods[0];
        config
            .seed_values()
            .map(|seed| {
                let description = RunDescription::new(&experiment, method, seed);
                let key = RunKey::of(&description).unwrap();
                let record = experiment.run(method, seed).unwrap();
                (key, description, record)
            })
            .collect()
    }

    /// A store in `dir` holding `runs`, packed, and the path of their bundle.
    fn stored(dir: &Path, runs: &[(RunKey, RunDescription, RunRecord)]) -> PathBuf {
        let (store, _) = open(dir);
        for (key, description, record) in runs {
            store
                .append(key, description, record, KeepTrajectories::Figures)
                .unwrap();
        }
        pack(dir, &keys(runs));
        store.bundle_path(&runs[0].2.experiment)
    }

    fn keys(runs: &[(RunKey, RunDescription, RunRecord)]) -> Vec<RunKey> {
        runs.iter().map(|(key, _, _)| key.clone()).collect()
    }

    /// Packs the store of `dir` under its lock; returns the warnings.
    fn pack(dir: &Path, wanted: &[RunKey]) -> Vec<String> {
        let folder = crate::output_folder::OutputFolder::open(dir, false).unwrap();
        let (store, mut warnings) = open(dir);
        store
            .pack(&folder, &[], wanted, &mut |w| warnings.push(w.to_owned()))
            .unwrap();
        warnings
    }

    fn open(dir: &Path) -> (RunStore, Vec<String>) {
        let mut warnings = Vec::new();
        let store = RunStore::open(dir, &mut |w| warnings.push(w.to_owned())).unwrap();
        (store, warnings)
    }

    #[test]
    fn append_then_reopen_loads_the_compacted_record() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        assert!(!runs[0].2.trajectories.is_empty(), "the config keeps some");
        let (store, _) = open(dir.path());
        for (key, description, record) in &runs {
            store
                .append(key, description, record, KeepTrajectories::Figures)
                .unwrap();
        }
        let (store, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.len(), 2);
        let (key, _, record) = &runs[0];
        let loaded = store.load(key, KeepTrajectories::Figures).unwrap().unwrap();
        assert_eq!(
            loaded.record,
            compact(record.clone(), KeepTrajectories::Figures)
        );
        assert!(loaded.record.trajectories.is_empty());
        // A record stored without its training trajectories cannot serve a request for all.
        assert!(!store.has(key, KeepTrajectories::All));
        assert_eq!(store.load(key, KeepTrajectories::All).unwrap(), None);
        // One file per run until packed, then one bundle for the experiment.
        let names = |folder: &str| -> Vec<String> {
            let mut names: Vec<_> = std::fs::read_dir(dir.path().join(folder))
                .unwrap()
                .map(|e| e.unwrap().file_name().into_string().unwrap())
                .collect();
            names.sort();
            names
        };
        assert_eq!(names("runs/loose").len(), 2);
        assert_eq!(names("runs"), vec!["loose"]);
        assert!(pack(dir.path(), &keys(&runs)).is_empty());
        assert_eq!(
            names("runs"),
            vec![
                "loose".to_owned(),
                format!("{}.jsonl.gz", record.experiment)
            ]
        );
        assert!(names("runs/loose").is_empty());
        let (store, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.len(), 2);
        // Packed, the keys come in the order the runs were packed (job order), whatever the
        // order of their hashes.
        let wanted = keys(&runs);
        assert_eq!(store.keys(), wanted.iter().collect::<Vec<_>>());
        let reversed: Vec<RunKey> = wanted.iter().rev().cloned().collect();
        let other = tempfile::tempdir().unwrap();
        let (store, _) = open(other.path());
        for (key, description, record) in runs.iter().rev() {
            store
                .append(key, description, record, KeepTrajectories::Figures)
                .unwrap();
        }
        assert!(pack(other.path(), &reversed).is_empty());
        let (store, _) = open(other.path());
        assert_eq!(store.keys(), reversed.iter().collect::<Vec<_>>());
    }

    #[test]
    fn all_trajectories_are_kept_when_asked_and_serve_both_requests() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        let (store, _) = open(dir.path());
        let (key, description, record) = &runs[1];
        store
            .append(key, description, record, KeepTrajectories::All)
            .unwrap();
        let (store, _) = open(dir.path());
        let all = store.load(key, KeepTrajectories::All).unwrap().unwrap();
        assert_eq!(&all.record, record);
        let figures = store.load(key, KeepTrajectories::Figures).unwrap().unwrap();
        assert!(figures.record.trajectories.is_empty());
    }

    #[test]
    fn an_edited_line_is_ignored_with_a_warning_naming_the_checksum() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        let bundle = stored(dir.path(), &runs);
        let bytes = std::fs::read(&bundle).unwrap();
        let entries = gzip::split_members(&bytes).unwrap();
        assert_eq!(entries.len(), 2);
        // Change one number of the first record's first episode (its steps, a digit longer) and
        // compress the line again, so the entry decompresses but its checksum fails.
        let first_line = String::from_utf8(entries[0].1.clone()).unwrap();
        let steps = format!("\"steps\":[{},", runs[0].2.episodes[0].steps);
        assert!(first_line.contains(&steps), "{first_line}");
        let edited = first_line.replacen(
            &steps,
            &format!("\"steps\":[{}0,", runs[0].2.episodes[0].steps),
            1,
        );
        let edited = gzip::compress(edited.as_bytes()).unwrap();
        std::fs::write(&bundle, [edited.as_slice(), entries[1].0].concat()).unwrap();
        let (store, warnings) = open(dir.path());
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("checksum mismatch"), "{}", warnings[0]);
        assert!(warnings[0].contains("entry 1 (byte 0)"), "{}", warnings[0]);
        assert!(!store.has(&runs[0].0, KeepTrajectories::Figures));
        assert!(store.has(&runs[1].0, KeepTrajectories::Figures));
    }

    #[test]
    fn check_bytes_counts_what_verifies_and_names_the_rest() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        let bundle = std::fs::read(stored(dir.path(), &runs)).unwrap();
        assert_eq!(check_bytes(&bundle), (2, vec![]));
        let (verified, problems) = check_bytes(&bundle[..bundle.len() - 5]);
        assert_eq!(verified, 1);
        assert!(!problems.is_empty());
        // A small member that inflates past the cap is refused while reading.
        let mut zeros = crate::gzip::encoder(Vec::new());
        let block = vec![0_u8; 1 << 20];
        for _ in 0..=(MAX_ENTRY_BYTES >> 20) {
            zeros.write_all(&block).unwrap();
        }
        let zeros = zeros.finish().unwrap();
        // Level 1 packs zeros about 250:1, so the member is a small fraction of the cap.
        assert!(
            zeros.len() < (MAX_ENTRY_BYTES >> 6) as usize,
            "{}",
            zeros.len()
        );
        let (verified, problems) = check_bytes(&zeros);
        assert_eq!(verified, 0);
        assert!(problems[0].contains("the cap of one entry"), "{problems:?}");
    }

    #[test]
    fn a_damaged_entry_is_skipped_and_reading_resumes_at_the_next() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        let bundle = stored(dir.path(), &runs);
        let whole = std::fs::read(&bundle).unwrap();
        let first_len = gzip::split_members(&whole).unwrap()[0].0.len();
        // A disk error in the middle of the first entry's compressed data.
        let mut damaged = whole.clone();
        damaged[first_len / 2] ^= 0x55;
        std::fs::write(&bundle, &damaged).unwrap();
        let (store, warnings) = open(dir.path());
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(
            warnings[0].contains("entry 1 (byte 0): damaged"),
            "{}",
            warnings[0]
        );
        assert!(!store.has(&runs[0].0, KeepTrajectories::Figures));
        let second = store
            .load(&runs[1].0, KeepTrajectories::Figures)
            .unwrap()
            .unwrap();
        assert_eq!(
            second.record,
            compact(runs[1].2.clone(), KeepTrajectories::Figures)
        );
        // Not the tail: nothing was cut.
        assert_eq!(std::fs::read(&bundle).unwrap(), damaged);
    }

    #[test]
    fn a_bundle_reads_as_plain_gzip_whose_lines_are_the_runs() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        // What `zcat` does: every member in turn, concatenated.
        let bundle = std::fs::read(stored(dir.path(), &runs)).unwrap();
        let mut text = String::new();
        flate2::read::MultiGzDecoder::new(bundle.as_slice())
            .read_to_string(&mut text)
            .unwrap();
        let keys: Vec<String> = text
            .lines()
            .map(|line| {
                let header = line.split('\t').next().unwrap();
                let header: LineHeader = serde_json::from_str(header).unwrap();
                header.key
            })
            .collect();
        let expected: Vec<String> = runs.iter().map(|(key, _, _)| key.to_string()).collect();
        assert_eq!(keys, expected);
    }

    #[test]
    fn an_uncompressed_bundle_of_an_earlier_version_is_named_not_read() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        let bundle = stored(dir.path(), &runs);
        let line = gzip::split_members(&std::fs::read(&bundle).unwrap()).unwrap()[0]
            .1
            .clone();
        std::fs::remove_file(&bundle).unwrap();
        let old = dir.path().join("runs/task1.jsonl");
        std::fs::write(&old, line).unwrap();
        let (store, warnings) = open(dir.path());
        assert_eq!(store.len(), 0);
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(
            warnings[0].contains("task1.jsonl: an uncompressed bundle"),
            "{}",
            warnings[0]
        );
    }

    #[test]
    fn a_torn_tail_is_never_cut_by_a_reader_and_is_set_aside_by_the_packer() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        let bundle = stored(dir.path(), &runs[..1]);
        let whole = std::fs::read(&bundle).unwrap();
        let mut torn = whole.clone();
        torn.extend_from_slice(&whole[..whole.len() / 2]);
        std::fs::write(&bundle, &torn).unwrap();

        let (store, warnings) = open(dir.path());
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("incomplete"), "{}", warnings[0]);
        // A reader changes nothing: the tail may be another process's entry being written.
        assert_eq!(std::fs::read(&bundle).unwrap(), torn);
        let (key, description, record) = &runs[1];
        store
            .append(key, description, record, KeepTrajectories::Figures)
            .unwrap();
        let warnings = pack(dir.path(), &keys(&runs));
        assert!(
            warnings.iter().any(|w| w.contains("set aside")),
            "{warnings:?}"
        );
        let (store, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "reported once: {warnings:?}");
        assert_eq!(store.len(), 2);
        let aside: Vec<_> = std::fs::read_dir(dir.path().join("runs/.set-aside"))
            .unwrap()
            .map(|entry| entry.unwrap().path())
            .collect();
        assert_eq!(aside.len(), 1);
        // What is kept is the torn tail itself, not the bytes the new bundle has there.
        assert_eq!(std::fs::read(&aside[0]).unwrap(), &whole[..whole.len() / 2]);
    }

    #[test]
    fn the_episode_columns_convert_back_exactly_and_must_agree_in_length() {
        for (_, _, record) in runs() {
            let stored = StoredRecord::from_record(&record, KeepTrajectories::All);
            let text = serde_json::to_vec(&stored).unwrap();
            let back: StoredRecord = serde_json::from_slice(&text).unwrap();
            assert_eq!(back.into_record().unwrap(), record);
        }
        let (_, _, record) = runs().remove(0);
        let mut stored = StoredRecord::from_record(&record, KeepTrajectories::Figures);
        stored.episodes.steps.pop();
        let problem = stored.into_record().unwrap_err();
        assert!(problem.contains("differ in length"), "{problem}");
    }

    /// `text` (a line without newline) with its header edited by `edit` and, when `rehash`,
    /// its checksum recomputed (what a careful forger does).
    fn edited(text: &str, rehash: bool, edit: impl Fn(&mut LineHeader)) -> String {
        let (header, content) = text.split_once('\t').unwrap();
        let mut header: LineHeader = serde_json::from_str(header).unwrap();
        edit(&mut header);
        if rehash {
            header.blake3 = header.checksum(content.as_bytes());
        }
        format!("{}\t{content}", serde_json::to_string(&header).unwrap())
    }

    fn line_of(run: &(RunKey, RunDescription, RunRecord), record: &RunRecord) -> String {
        let description = canonical_json(&run.1).unwrap();
        let line = line_bytes(
            &run.0,
            description.as_bytes(),
            record,
            KeepTrajectories::Figures,
        )
        .unwrap();
        String::from_utf8(line).unwrap().trim_end().to_owned()
    }

    #[test]
    fn a_line_under_another_key_or_format_or_with_an_edited_header_is_refused() {
        let runs = runs();
        let text = line_of(&runs[0], &runs[0].2);
        assert!(parse_line(text.as_bytes()).is_ok());
        let problem = |line: &str| parse_line(line.as_bytes()).err().unwrap();
        // The header is checksummed: its `trajectories` or key cannot be edited alone.
        let all = edited(&text, false, |h| h.trajectories = KeepTrajectories::All);
        assert!(
            problem(&all).contains("checksum mismatch"),
            "{}",
            problem(&all)
        );
        let other_key = edited(&text, false, |h| h.key = runs[1].0.to_string());
        assert!(problem(&other_key).contains("checksum mismatch"));
        let other_key = edited(&text, true, |h| h.key = runs[1].0.to_string());
        assert!(
            problem(&other_key).contains("not to the key"),
            "{}",
            problem(&other_key)
        );
        let old_format = edited(&text, true, |h| h.format = 2);
        assert!(problem(&old_format).contains("format is 2"));
        assert!(problem("{}").contains("three"));
        // A valid record under another run's key and description, checksum recomputed.
        let swapped = line_of(&runs[1], &runs[0].2);
        let swapped = edited(&swapped, true, |h| h.seed = runs[1].2.seed);
        assert!(
            problem(&swapped).contains("but the record is"),
            "{}",
            problem(&swapped)
        );
        // A record that does not load (columns of different lengths), checksum recomputed.
        let short = text.replacen("\"steps\":[", "\"steps\":[7,", 1);
        let short = edited(&short, true, |_| {});
        assert!(
            problem(&short).contains("differ in length"),
            "{}",
            problem(&short)
        );
    }

    /// What a store knows: every run's location (file, offset, length, trajectories,
    /// experiment, digest), the entries it rejected, and the order of its keys.
    type Contents = (HashMap<RunKey, Location>, Vec<Rejected>, Vec<RunKey>);

    fn contents(store: &RunStore) -> Contents {
        (
            store.index.clone(),
            store.rejected.clone(),
            store.keys().into_iter().cloned().collect(),
        )
    }

    fn append_all(
        dir: &Path,
        runs: &[(RunKey, RunDescription, RunRecord)],
        keep: KeepTrajectories,
    ) -> Vec<AppendReceipt> {
        let (store, _) = open(dir);
        runs.iter()
            .map(|(key, description, record)| store.append(key, description, record, keep).unwrap())
            .collect()
    }

    /// Opens the store of `dir`, lets `meanwhile` change the folder (as another process
    /// would between indexing and packing), packs it wanting `wanted`, and checks that the
    /// store `pack` returns is the store `open` then reads; returns the pack's warnings.
    fn pack_equals_open(
        dir: &Path,
        wanted: &[RunKey],
        meanwhile: impl FnOnce(&RunStore),
    ) -> Vec<String> {
        let lock = crate::output_folder::OutputFolder::open(dir, false).unwrap();
        let (store, mut warnings) = open(dir);
        meanwhile(&store);
        let packed = store
            .pack(&lock, &[], wanted, &mut |w| warnings.push(w.to_owned()))
            .unwrap();
        let (opened, _) = open(dir);
        assert_eq!(contents(&packed), contents(&opened));
        // And every location's digest is the hash of the bytes there.
        for location in opened.index.values() {
            let bytes = std::fs::read(&*location.file).unwrap();
            let start = usize::try_from(location.offset).unwrap();
            let entry = &bytes[start..start + location.len];
            assert_eq!(blake3::hash(entry), location.digest);
        }
        warnings
    }

    #[test]
    fn the_store_pack_returns_is_the_store_open_reads() {
        let runs = runs_of(4);
        let all = keys(&runs);
        let figures = KeepTrajectories::Figures;

        // Fresh appends.
        let dir = tempfile::tempdir().unwrap();
        append_all(dir.path(), &runs[..2], figures);
        assert!(pack_equals_open(dir.path(), &all, |_| {}).is_empty());

        // Resumed: a bundle and new loose runs; then one more not in `wanted`.
        append_all(dir.path(), &runs[2..3], figures);
        assert!(pack_equals_open(dir.path(), &all[..2], |_| {}).is_empty());
        append_all(dir.path(), &runs[3..], figures);
        assert!(pack_equals_open(dir.path(), &all, |_| {}).is_empty());

        // A concurrent writer's loose file appearing after indexing stays loose and is read.
        let dir = tempfile::tempdir().unwrap();
        append_all(dir.path(), &runs[..2], figures);
        pack_equals_open(dir.path(), &all, |_| {
            append_all(dir.path(), &runs[2..3], figures);
        });
        let (store, _) = open(dir.path());
        assert_eq!(store.len(), 3);
        assert!(store.index[&runs[2].0].loose);

        // A damaged entry in a bundle (set aside, left out), and a damaged bundle of its own
        // (nothing verified in it, so not rewritten: rejected again).
        let dir = tempfile::tempdir().unwrap();
        let bundle = stored(dir.path(), &runs[..2]);
        let mut damaged = std::fs::read(&bundle).unwrap();
        damaged[20] ^= 0x55;
        std::fs::write(&bundle, &damaged).unwrap();
        std::fs::write(dir.path().join("runs/other.jsonl.gz"), &damaged[..30]).unwrap();
        let warnings = pack_equals_open(dir.path(), &all, |_| {});
        assert_eq!(
            warnings.iter().filter(|w| w.contains("set aside")).count(),
            2,
            "{warnings:?}"
        );
        let (store, _) = open(dir.path());
        assert_eq!(store.len(), 1);
        assert_eq!(store.rejected.len(), 1);

        // A torn tail.
        let dir = tempfile::tempdir().unwrap();
        let bundle = stored(dir.path(), &runs[..1]);
        let whole = std::fs::read(&bundle).unwrap();
        std::fs::write(&bundle, [&whole[..], &whole[..whole.len() / 2]].concat()).unwrap();
        append_all(dir.path(), &runs[1..2], figures);
        pack_equals_open(dir.path(), &all, |_| {});

        // Duplicates: a run stored keeping the figures' trajectories and keeping all, loose and
        // packed; the richer serves, the poorer loose file stays loose.
        let dir = tempfile::tempdir().unwrap();
        stored(dir.path(), &runs[..2]);
        append_all(dir.path(), &runs[..1], KeepTrajectories::All);
        append_all(dir.path(), &runs[1..2], figures);
        assert!(pack_equals_open(dir.path(), &all, |_| {}).is_empty());
        let (store, _) = open(dir.path());
        assert!(store.has(&runs[0].0, KeepTrajectories::All));
        assert!(!store.index[&runs[0].0].loose);

        // A loose file replaced after indexing by other bytes of the same length that still
        // hold the run (another process's copy whose gzip header says another time): checked
        // in full on the way, and the bytes now there are packed, as `open` reads them.
        let dir = tempfile::tempdir().unwrap();
        append_all(dir.path(), &runs[..2], figures);
        let mut replaced = Vec::new();
        pack_equals_open(dir.path(), &all, |store| {
            let path = store.loose_path(&runs[0].0, figures);
            replaced = std::fs::read(&path).unwrap();
            replaced[4] = 1; // the gzip header's modification time
            crate::atomic::write_atomic(&path, &replaced).unwrap();
        });
        let bundle = std::fs::read(dir.path().join("runs/task1.jsonl.gz")).unwrap();
        assert_eq!(&bundle[..replaced.len()], replaced.as_slice());
    }

    #[test]
    fn pack_finds_a_loose_file_damaged_after_indexing_and_keeps_it() {
        let runs = runs();
        let dir = tempfile::tempdir().unwrap();
        append_all(dir.path(), &runs, KeepTrajectories::Figures);
        let lock = crate::output_folder::OutputFolder::open(dir.path(), false).unwrap();
        let (store, _) = open(dir.path());
        let path = store.loose_path(&runs[0].0, KeepTrajectories::Figures);
        let mut bytes = std::fs::read(&path).unwrap();
        let middle = bytes.len() / 2;
        bytes[middle] ^= 0x55;
        std::fs::write(&path, &bytes).unwrap();
        let error = store
            .pack(&lock, &[], &keys(&runs), &mut |w| panic!("{w}"))
            .unwrap_err();
        assert!(matches!(error, StoreError::Changed { .. }), "{error}");
        assert!(
            error.to_string().contains("no longer decompresses"),
            "{error}"
        );
        // Nothing was lost: both loose files are still there, no bundle was committed.
        assert_eq!(std::fs::read(&path).unwrap(), bytes);
        assert!(
            dir.path()
                .join("runs/loose")
                .join(format!("{}.figures.run.gz", runs[1].0))
                .exists()
        );
        assert!(!dir.path().join("runs/task1.jsonl.gz").exists());
    }

    #[test]
    fn receipts_index_exactly_the_bytes_appended_and_the_rest_is_checked_in_full() {
        let runs = runs_of(3);
        let figures = KeepTrajectories::Figures;
        let dir = tempfile::tempdir().unwrap();
        let receipts = append_all(dir.path(), &runs, figures);
        assert_eq!(receipts[0].key(), &runs[0].0);
        assert_eq!(receipts[0].keep(), figures);
        let reopen = |receipts: &[AppendReceipt]| {
            let mut warnings = Vec::new();
            let store = RunStore::open_with_receipts(dir.path(), receipts, &mut |w| {
                warnings.push(w.to_owned());
            })
            .unwrap();
            (store, warnings)
        };
        // Untouched: the same store as a full check gives.
        let (trusting, warnings) = reopen(&receipts);
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(contents(&trusting), contents(&open(dir.path()).0));

        // The trust is in the bytes alone: a receipt made here for bytes that are no entry at
        // all is believed (which is why only `append` makes receipts), while `open` rejects
        // them. So the receipted path really skips the decompression and parse.
        let path = trusting.loose_path(&runs[0].0, figures);
        let whole = std::fs::read(&path).unwrap();
        let garbage = b"not a gzip member".to_vec();
        std::fs::write(&path, &garbage).unwrap();
        let forged = AppendReceipt {
            len: garbage.len() as u64,
            digest: blake3::hash(&garbage),
            ..receipts[0].clone()
        };
        let (trusting, warnings) = reopen(std::slice::from_ref(&forged));
        assert!(warnings.is_empty(), "{warnings:?}");
        assert!(trusting.has(&runs[0].0, figures));
        let (checking, warnings) = open(dir.path());
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(!checking.has(&runs[0].0, figures));

        // A receipted file replaced by other bytes (here the same garbage, against the true
        // receipt) is checked in full: rejected with a warning, and set aside by the next pack.
        let (store, warnings) = reopen(&receipts);
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("damaged"), "{}", warnings[0]);
        assert!(!store.has(&runs[0].0, figures));
        assert_eq!(contents(&store), contents(&open(dir.path()).0));
        // Replaced by a longer file that starts with the appended bytes: checked in full too
        // (it then holds two entries, the second a torn copy).
        std::fs::write(&path, [&whole[..], &whole[..10]].concat()).unwrap();
        let (store, warnings) = reopen(&receipts);
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("incomplete"), "{}", warnings[0]);
        assert!(store.has(&runs[0].0, figures));
        assert_eq!(contents(&store), contents(&open(dir.path()).0));
        std::fs::write(&path, &garbage).unwrap();
        let lock = crate::output_folder::OutputFolder::open(dir.path(), false).unwrap();
        let (store, _) = reopen(&receipts);
        let mut warnings = Vec::new();
        let store = store
            .pack(&lock, &[], &keys(&runs), &mut |w| {
                warnings.push(w.to_owned());
            })
            .unwrap();
        assert!(
            warnings.len() == 1 && warnings[0].contains("set aside"),
            "{warnings:?}"
        );
        assert_eq!(store.len(), 2);
        let aside = dir
            .path()
            .join("runs/.set-aside")
            .join(format!("{}.figures.run.gz.at-0", runs[0].0));
        assert_eq!(std::fs::read(aside).unwrap(), garbage);

        // A receipt whose file is gone (packed meanwhile) is ignored, silently.
        assert!(!path.exists());
        let (store, warnings) = reopen(&receipts);
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.len(), 2);
        assert_eq!(contents(&store), contents(&open(dir.path()).0));
    }

    /// Opens the store of `dir`, lets `meanwhile` change the folder (as this process's jobs
    /// and other processes would between the first open and the reopen; it returns the
    /// receipts of what it appended), reopens, and checks that the reopened store is the store
    /// `open` then reads.
    fn reopen_equals_open(dir: &Path, meanwhile: impl FnOnce(&RunStore) -> Vec<AppendReceipt>) {
        let (store, _) = open(dir);
        let receipts = meanwhile(&store);
        let reopened = store.reopen(&receipts, &mut |_| {}).unwrap();
        let (opened, _) = open(dir);
        assert_eq!(contents(&reopened), contents(&opened));
    }

    #[test]
    fn a_reopened_store_is_the_store_open_reads() {
        let runs = runs_of(4);
        let figures = KeepTrajectories::Figures;

        // Resumed: a bundle and a loose run of an earlier invocation; a run appended now.
        let dir = tempfile::tempdir().unwrap();
        stored(dir.path(), &runs[..2]);
        append_all(dir.path(), &runs[2..3], figures);
        reopen_equals_open(dir.path(), |_| append_all(dir.path(), &runs[3..], figures));

        // Another process's loose run appearing meanwhile (no receipt: checked in full).
        let dir = tempfile::tempdir().unwrap();
        stored(dir.path(), &runs[..2]);
        reopen_equals_open(dir.path(), |_| {
            append_all(dir.path(), &runs[2..3], figures);
            Vec::new()
        });

        // A damaged entry and a torn tail in a bundle, and a bundle of nothing good: their
        // rejected entries carry over.
        let dir = tempfile::tempdir().unwrap();
        let bundle = stored(dir.path(), &runs[..2]);
        let mut damaged = std::fs::read(&bundle).unwrap();
        damaged[20] ^= 0x55;
        let torn = [&damaged[..], &damaged[..damaged.len() / 2]].concat();
        std::fs::write(&bundle, &torn).unwrap();
        std::fs::write(dir.path().join("runs/other.jsonl.gz"), &damaged[..30]).unwrap();
        reopen_equals_open(dir.path(), |store| {
            assert_eq!(store.rejected.len(), 3);
            Vec::new()
        });

        // Duplicates: the richer loose copy of a packed run removed meanwhile; the bundle's
        // poorer entry, outranked at the first open, serves again.
        let dir = tempfile::tempdir().unwrap();
        stored(dir.path(), &runs[..2]);
        append_all(dir.path(), &runs[..1], KeepTrajectories::All);
        reopen_equals_open(dir.path(), |store| {
            let richer = store.loose_path(&runs[0].0, KeepTrajectories::All);
            assert!(store.index[&runs[0].0].loose);
            std::fs::remove_file(richer).unwrap();
            Vec::new()
        });

        // Two bundles holding the same runs: the second's entries, outranked at the first open
        // by the first's (first of equals), serve once the first is found damaged.
        let dir = tempfile::tempdir().unwrap();
        let bundle = stored(dir.path(), &runs[..2]);
        let copy = dir.path().join("runs/a-copy.jsonl.gz");
        std::fs::copy(&bundle, &copy).unwrap();
        reopen_equals_open(dir.path(), |store| {
            assert_eq!(*store.index[&runs[0].0].file, copy);
            std::fs::write(&copy, b"damaged").unwrap();
            Vec::new()
        });
        assert_eq!(*open(dir.path()).0.index[&runs[0].0].file, bundle);

        // A bundle of another length (here grown by a torn copy of its first entry): read in
        // full again. A loose file replaced by other bytes: checked in full, and rejected.
        let dir = tempfile::tempdir().unwrap();
        let bundle = stored(dir.path(), &runs[..2]);
        append_all(dir.path(), &runs[2..3], figures);
        reopen_equals_open(dir.path(), |store| {
            let whole = std::fs::read(&bundle).unwrap();
            std::fs::write(&bundle, [&whole[..], &whole[..40]].concat()).unwrap();
            let loose = store.loose_path(&runs[2].0, figures);
            std::fs::write(loose, b"not a gzip member").unwrap();
            Vec::new()
        });
        let (store, warnings) = open(dir.path());
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        assert_eq!(store.len(), 2);
    }

    /// The reopen trusts a bundle of the length it read without reading it again (the lock
    /// keeps packers out meanwhile); bytes damaged in place are then found by `pack`, which
    /// hashes what it copies, and nothing is removed.
    #[test]
    fn a_reopen_trusts_a_bundle_of_the_same_length_and_pack_still_finds_damage() {
        let runs = runs_of(2);
        let dir = tempfile::tempdir().unwrap();
        let bundle = stored(dir.path(), &runs);
        let lock = crate::output_folder::OutputFolder::open(dir.path(), false).unwrap();
        let (store, _) = open(dir.path());
        let mut damaged = std::fs::read(&bundle).unwrap();
        damaged[20] ^= 0x55;
        std::fs::write(&bundle, &damaged).unwrap();
        let reopened = store.reopen(&[], &mut |_| {}).unwrap();
        assert_eq!(reopened.len(), 2, "trusted, not read again");
        assert_eq!(
            open(dir.path()).0.len(),
            1,
            "a full read rejects the damaged entry"
        );
        let packed = reopened.pack(&lock, &[], &keys(&runs), &mut |_| {});
        assert!(
            matches!(packed, Err(StoreError::Changed { .. })),
            "{packed:?}"
        );
        assert_eq!(
            std::fs::read(&bundle).unwrap(),
            damaged,
            "nothing rewritten"
        );
    }
}
