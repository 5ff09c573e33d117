//! The run store of an output folder, `<out>/runs/`: every finished run, checked before it is
//! trusted, never lost to another process.
//!
//! # On disk
//!
//! ```text
//! runs/<experiment>.jsonl.zst         packed bundle: the experiment's runs, many per Zstandard frame
//! runs/loose/<key>.<keep>.run.gz      one run stored alone (RunStore::append), one gzip member of stored blocks
//! runs/loose/batch-<pid>-<time>-<n>.run.gz   the runs of one batch (LooseBatch), one such member each
//! runs/.set-aside/…                   entries that failed their checks, kept for inspection
//! runs/.writers.lock                  held shared by writers while they make a temporary file
//! ```
//!
//! A run is one line; store files are compressed frames of whole lines ([`crate::frames`]): a
//! bundle holds many lines per Zstandard frame (so `zstdcat runs/task1.jsonl.zst` prints the
//! lines), a loose file one gzip member per line (not yet packed). A bundle written before Zstandard
//! (`runs/<experiment>.jsonl.gz`, one gzip member per run) is read like a bundle and replaced by
//! the next pack. A line is three tab-separated parts (compact JSON never holds a raw tab):
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
//!   ([`RunStore::append`]); two processes storing the same run write the same bytes. A
//!   running plan appends its runs to a batch file of its own, published under a unique name
//!   while locked and locked until closed ([`LooseBatch`]); a locked loose file is read for
//!   its whole frames but never reported for a frame being written, nor removed. Bundles are
//!   written only by [`RunStore::pack`], which needs the output folder's lock, and only by an
//!   atomic rename. This rests on `rename` being atomic within a folder (POSIX; NFS and Lustre
//!   keep it) and on the folder lock being exclusive (`flock`, which NFS emulates with
//!   byte-range locks). No append is ever shared. A temporary file is removed by another
//!   process only when its writer is gone ([`crate::atomic::WritersLock`]). A running plan
//!   writes its runs through a [`LooseBatch`] (a group commit): the same files and renames,
//!   synced together once per batch instead of once per run, so a crash of the machine may
//!   lose the last batches' runs (found torn or missing, recomputed), never trust a wrong one.
//! - **Readers never change anything.** [`RunStore::open`] only reads; a damaged or torn entry is
//!   reported and skipped.
//! - **Nothing removes a run.** Packing writes the union of the bundles' verified entries and
//!   the loose runs, each run once with the richest trajectories stored, then removes only the
//!   files it read whose every run is now in the bundles it wrote (loose runs, a bundle of an
//!   earlier version, a copy of a bundle). A narrower plan, another shard or another
//!   `--keep-trajectories` adds runs, never drops them.
//! - **A run is trusted only when everything checks**: its frame decompresses (Zstandard's or
//!   gzip's checksum) within the caps of [`crate::frames`], the format is known, the checksum
//!   covers header and content, the description hashes to the key, the names in the header
//!   are safe names (as a config's: never a path), the record loads, and the record's and
//!   description's experiment, method and seed agree with the header. A frame holding a line
//!   that fails is refused whole; it is reported once (the next [`RunStore::pack`] sets it
//!   aside in `runs/.set-aside/`, never deleting it, and removes it from the live files) and
//!   its runs are recomputed.
//! - **Checksums detect faults, not forgery.** Whoever can write the folder can write a line
//!   with a recomputed checksum: `cargo xtask verify` recomputes a sample of the stored runs
//!   and compares them byte for byte ([`crate::verify`]).
//! - **Bytes checked or made once are not parsed again.** The index keeps, for each verified
//!   entry, the BLAKE3 hash of its line (and for a loose file, of the file). Bytes read back
//!   later that hash to it are the bytes checked, so they are trusted without parsing them
//!   again; bytes that differ in any way are checked in full as above. This applies four
//!   times: a loose file [`RunStore::append`] wrote from a record it serialised, when its
//!   [`AppendReceipt`] is handed to [`RunStore::open_with_receipts`] or [`RunStore::reopen`];
//!   a line [`RunStore::pack`] copies (a loose file replaced by another process since it was
//!   indexed is read as it now is); the bundles `pack` has just written under the lock,
//!   indexed from what it wrote; and, in [`RunStore::reopen`] by the process holding the lock
//!   since the first open, the bundles that open read (while their length is unchanged) and
//!   the loose files it verified (while their bytes hash the same). Everything else a store is
//!   opened on is checked in full, and [`RunStore::load`] checks the entry it returns in full.
//! - **No link is followed inside the store** ([`crate::no_follow`]); a link or special file
//!   where a store file belongs is reported once and moved (the link itself) into
//!   `runs/.set-aside/` by the next pack.

use std::collections::HashMap;
use std::io::{self, Read as _};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use eamadm::{
    AgreementRecord, EpisodeRecord, RobotEpisodeMetrics, RunRecord, SubtaskRecord, TrajectoryRecord,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::frames::{FrameLine, LineReader};
use crate::key::{RunDescription, RunKey, canonical_json};

/// Which training trajectories a stored record keeps (the `--keep-trajectories` option).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum KeepTrajectories {
    /// Only what the figures draw: the evaluation episodes (in trajectories.csv.gz, the first
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

/// The most bytes one entry (one run's line) may decompress to ([`crate::frames::MAX_LINE_BYTES`]).
pub const MAX_ENTRY_BYTES: u64 = crate::frames::MAX_LINE_BYTES;

/// The folder inside `runs/` of runs stored one file each, before they are packed.
pub const LOOSE_FOLDER: &str = crate::names::LOOSE_RUNS;

/// The ending of bundle file names: JSON lines in Zstandard frames.
pub const BUNDLE_EXTENSION: &str = crate::names::BUNDLE_EXTENSION;

/// The ending of the bundles of earlier versions (JSON lines, each its own gzip member): read,
/// and replaced by the next pack.
pub const LEGACY_BUNDLE_EXTENSION: &str = crate::names::LEGACY_BUNDLE_EXTENSION;

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

/// What a store file is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FileKind {
    /// `runs/<experiment>.jsonl.zst`, written by [`RunStore::pack`].
    Bundle,
    /// `runs/<experiment>.jsonl.gz`, a bundle of an earlier version: read, and replaced by the
    /// next pack.
    LegacyBundle,
    /// `runs/loose/<key>.<keep>.run.gz`, one run.
    Loose,
}

/// Where a verified entry is.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Location {
    /// The store file.
    file: Arc<PathBuf>,
    kind: FileKind,
    /// The byte offset of the frame holding the line.
    frame: u64,
    /// The line's offset in the frame's content, and its length with its newline.
    line: u64,
    len: u64,
    trajectories: KeepTrajectories,
    experiment: String,
    /// The BLAKE3 hash of the line (with its newline) as verified or written: a line read back
    /// later with this hash is that very line, so it is copied without being parsed again
    /// ([`RunStore::pack`]).
    digest: blake3::Hash,
    /// For a frame of a loose file read whole when indexed: the frame's length and the BLAKE3
    /// hash of its bytes, with which [`RunStore::reopen`] trusts it while it is unchanged.
    file_digest: Option<(u64, blake3::Hash)>,
}

/// What [`RunStore::append`] or [`LooseBatch::append`] wrote: the loose file and the byte at
/// which the run's frame (one gzip member) starts in it, the frame's length and the BLAKE3
/// hash of its bytes, the hash and length of its line, and the header fields the index needs.
/// Handed to [`RunStore::open_with_receipts`], the receipts of a loose file let the reopened
/// store index it without decompressing and parsing it, as long as the file holds exactly
/// the frames receipted, one after the other from its first byte to its last. It is a few
/// dozen bytes whatever the run's size, and only the store's appends make one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AppendReceipt {
    key: RunKey,
    keep: KeepTrajectories,
    experiment: String,
    file: PathBuf,
    frame: u64,
    len: u64,
    digest: blake3::Hash,
    line_len: u64,
    line_digest: blake3::Hash,
}

impl AppendReceipt {
    /// The receipt of run `key`'s `line`, written as the frame `entry` at byte `frame` of
    /// `file`.
    fn of(
        key: &RunKey,
        keep: KeepTrajectories,
        record: &RunRecord,
        file: PathBuf,
        frame: u64,
        line: &[u8],
        entry: &[u8],
    ) -> Self {
        Self {
            key: key.clone(),
            keep,
            experiment: record.experiment.clone(),
            file,
            frame,
            len: entry.len() as u64,
            digest: blake3::hash(entry),
            line_len: line.len() as u64,
            line_digest: blake3::hash(line),
        }
    }

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

    /// The loose file the run was written to.
    #[must_use]
    pub fn file(&self) -> &Path {
        &self.file
    }

    /// The byte of [`AppendReceipt::file`] at which the run's frame starts.
    #[must_use]
    pub fn frame(&self) -> u64 {
        self.frame
    }
}

/// The files a store being opened may index without checking them in full, because this
/// process checked or made their bytes.
#[derive(Default)]
struct Trusted {
    /// Loose run files by path, with a receipt per frame: those this process appended and
    /// those the store being reopened had verified (used only while the file holds exactly
    /// the frames receipted, each hashing to its receipt's digest).
    received: HashMap<PathBuf, Vec<AppendReceipt>>,
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

/// What failed its checks, to be set aside by the next [`RunStore::pack`]: a frame (its
/// compressed bytes), a whole loose file, or a link or special file where a store file belongs
/// (moved aside itself, never followed).
#[derive(Debug, Clone, PartialEq, Eq)]
struct Rejected {
    file: PathBuf,
    /// The whole file is moved aside (a loose file, a link, a special file).
    whole: bool,
    offset: u64,
    len: u64,
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
    // Names read back from stored bytes become file names (the bundle of an experiment):
    // checked by the rule a config's names follow before anything else, so a forged entry can
    // never name a path.
    for (what, name) in [
        ("experiment", &header.experiment),
        ("method", &header.method),
    ] {
        if !eamadm::is_safe_slug(name) {
            return Err(format!(
                "the header's {what} name {name:?} is not a safe name (letters, digits, '-', '_' \
                 and '.', as a config's names): a forged or damaged entry"
            ));
        }
    }
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

/// The line (without its newline) the store keeps for `record` of run `key` described by
/// `description` (canonical JSON), compacted under `keep` (for `verify`).
///
/// # Errors
/// [`StoreError::Serialize`] if the record does not serialise.
pub fn line_for(
    key: &RunKey,
    description: &[u8],
    record: &RunRecord,
    keep: KeepTrajectories,
) -> Result<Vec<u8>, StoreError> {
    let mut line = line_bytes(key, description, &compact(record.clone(), keep), keep)?;
    line.pop();
    Ok(line)
}

/// `line` (one store line, without its newline) with its header's checksum recomputed over
/// whatever it now holds: what anyone who can write the folder can do, which is why the
/// checksums detect faults and not forgery. For tests of `verify`.
///
/// # Errors
/// If the line has no header to recompute.
pub fn with_checksum_recomputed(line: &[u8]) -> Result<Vec<u8>, String> {
    let mut parts = line.splitn(2, |&b| b == b'\t');
    let (Some(header), Some(content)) = (parts.next(), parts.next()) else {
        return Err("not a store line".to_owned());
    };
    let mut header: LineHeader =
        serde_json::from_slice(header).map_err(|e| format!("header: {e}"))?;
    header.blake3 = header.checksum(content);
    let mut forged = serde_json::to_vec(&header).map_err(|e| e.to_string())?;
    forged.push(b'\t');
    forged.extend_from_slice(content);
    Ok(forged)
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
    /// The line of this run in a store file (with its newline), compacted under `keep`.
    pub fn line(&self, key: &RunKey, keep: KeepTrajectories) -> Result<Vec<u8>, StoreError> {
        line_bytes(key, &self.description, &self.record, keep)
    }
}

/// A line checked: its bytes (with the newline) and what they hold.
struct CheckedEntry {
    line: Vec<u8>,
    header: LineHeader,
    description: Vec<u8>,
    record: RunRecord,
}

/// A line of a frame being indexed, checked, waiting for the rest of its frame.
struct Candidate {
    key: RunKey,
    line: u64,
    len: u64,
    digest: blake3::Hash,
    trajectories: KeepTrajectories,
    experiment: String,
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
    /// Every store file listed when this store was opened (bundles, loose files, and links or
    /// special files in their places): those [`RunStore::pack`] may remove once their runs are
    /// in the bundles it wrote.
    files: Vec<PathBuf>,
    /// The loose files among them that a writer still held locked when they were read (a
    /// [`LooseBatch`] being written): never removed by a pack, which may not have seen all
    /// their runs.
    live: Vec<PathBuf>,
    /// The frame [`RunStore::load`] read last, kept open for the next line.
    reader: Mutex<LineReader>,
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
        let trusted = Trusted {
            received: by_file(receipts.iter().cloned()),
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
    /// (Bytes damaged in place are still found: [`RunStore::pack`] hashes every line it copies
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
        // The loose files this store verified, as receipts of their frames; the receipts of
        // runs appended since take their place where both name a file.
        let mut received = by_file(self.index.iter().filter_map(|(key, at)| {
            let (len, digest) = at.file_digest?;
            Some(AppendReceipt {
                key: key.clone(),
                keep: at.trajectories,
                experiment: at.experiment.clone(),
                file: at.file.to_path_buf(),
                frame: at.frame,
                len,
                digest,
                line_len: at.len,
                line_digest: at.digest,
            })
        }));
        received.extend(by_file(receipts.iter().cloned()));
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
            files: Vec::new(),
            live: Vec::new(),
            reader: Mutex::new(LineReader::default()),
        };
        let read = |path: &Path| {
            let path = path.to_path_buf();
            move |source| StoreError::Read { path, source }
        };
        let mut bundles = Vec::new();
        for (path, name) in list(folder).map_err(read(folder))? {
            if name.ends_with(&format!(".{BUNDLE_EXTENSION}")) {
                bundles.push((path, FileKind::Bundle));
            } else if name.ends_with(&format!(".{LEGACY_BUNDLE_EXTENSION}")) {
                bundles.push((path, FileKind::LegacyBundle));
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
        bundles.sort_by(|a, b| a.0.cmp(&b.0));
        for (path, kind) in bundles {
            store.files.push(path.clone());
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
                _ => store.index_file(&path, kind, warn)?,
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
        // One buffer for every batch file: a fresh one per file was grown by doubling and
        // its pages faulted in again for each (a third of a 1000-seed command's page faults).
        let mut file_bytes = Vec::new();
        for path in loose {
            store.files.push(path.clone());
            let received = trusted.received.get(&path);
            if !received
                .is_some_and(|receipts| store.index_received(&path, receipts, &mut file_bytes))
            {
                store.index_file(&path, FileKind::Loose, warn)?;
            }
        }
        Ok(store)
    }

    /// Indexes the loose file `path` from `receipts` (sorted by frame) if the file holds
    /// exactly the frames receipted, one after the other from its first byte to its last, each
    /// with the BLAKE3 hash its receipt gives (the bytes the store's appends wrote); returns
    /// whether it did. A file that cannot be read or holds other bytes (more, fewer, changed)
    /// is left to the full check, which reports it as [`RunStore::open`] does.
    fn index_received(
        &mut self,
        path: &Path,
        receipts: &[AppendReceipt],
        bytes: &mut Vec<u8>,
    ) -> bool {
        let Ok(file) = crate::no_follow::open_regular(path) else {
            return false;
        };
        let total: u64 = receipts.iter().map(|receipt| receipt.len).sum();
        bytes.clear();
        // Room for the whole file at once (a failed reservation only leaves the read to grow
        // the buffer as it goes).
        if let Ok(room) = usize::try_from(total.saturating_add(1)) {
            let _ = bytes.try_reserve(room);
        }
        // One byte more than the receipts' length reveals a longer file without reading it all.
        let read = file.take(total.saturating_add(1)).read_to_end(bytes);
        if read.is_err() || bytes.len() as u64 != total {
            return false;
        }
        let mut at = 0_u64;
        for receipt in receipts {
            let frame = usize::try_from(at).ok().and_then(|start| {
                let end = start.checked_add(usize::try_from(receipt.len).ok()?)?;
                bytes.get(start..end)
            });
            if receipt.frame != at
                || frame.is_none_or(|frame| blake3::hash(frame) != receipt.digest)
            {
                return false;
            }
            at += receipt.len;
        }
        let shared = Arc::new(path.to_path_buf());
        for receipt in receipts {
            let location = Location {
                file: Arc::clone(&shared),
                kind: FileKind::Loose,
                frame: receipt.frame,
                line: 0,
                len: receipt.line_len,
                trajectories: receipt.keep,
                experiment: receipt.experiment.clone(),
                digest: receipt.line_digest,
                file_digest: Some((receipt.len, receipt.digest)),
            };
            self.insert(receipt.key.clone(), location);
        }
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

    /// Reads and checks every frame of the store file `path` into the index, streaming (see
    /// [`crate::frames`] for what one frame may cost). A frame whose lines all check is
    /// indexed; one that does not decompress, or holds a line that fails, is refused whole,
    /// reported (unless it was already set aside: a pack killed before it removed the file)
    /// and remembered for [`RunStore::pack`] to set aside. A loose file still locked by its
    /// writer ([`LooseBatch`]) is live: its whole frames are indexed, a frame it is still
    /// writing is passed over quietly, and no pack removes it.
    fn index_file(
        &mut self,
        path: &Path,
        kind: FileKind,
        warn: &mut dyn FnMut(&str),
    ) -> Result<(), StoreError> {
        let read_error = |source| StoreError::Read {
            path: path.to_path_buf(),
            source,
        };
        let mut file = match crate::no_follow::open_regular(path) {
            Ok(file) => file,
            Err(error) if error.kind() == io::ErrorKind::InvalidInput => {
                // A link or special file where a store file belongs: named, never followed,
                // and moved aside (the link itself) by the next pack.
                warn(&format!("{error}"));
                self.rejected.push(Rejected {
                    file: path.to_path_buf(),
                    whole: true,
                    offset: 0,
                    len: 0,
                });
                return Ok(());
            }
            // Packed and removed by another process since it was listed.
            Err(error) if kind == FileKind::Loose && error.kind() == io::ErrorKind::NotFound => {
                return Ok(());
            }
            Err(source) => return Err(read_error(source)),
        };
        // A writer holds its batch file locked from before it is visible until it is closed,
        // so a locked loose file may still grow (see `LooseBatch`).
        let live = kind == FileKind::Loose && held_by_writer(&file);
        if live {
            self.live.push(path.to_path_buf());
        }
        let end = file.metadata().map_err(read_error)?.len();
        // A loose file small enough is read whole, so the bytes hashed for a later reopen are
        // the bytes checked.
        let whole = if kind == FileKind::Loose && end <= LOOSE_HELD_BYTES {
            let mut bytes = Vec::new();
            (&mut file)
                .take(LOOSE_HELD_BYTES + 1)
                .read_to_end(&mut bytes)
                .map_err(read_error)?;
            Some(bytes)
        } else {
            None
        };
        let end = whole.as_ref().map_or(end, |bytes| bytes.len() as u64);
        let shared = Arc::new(path.to_path_buf());
        let mut offset = 0_u64;
        let mut number = 0_usize;
        // A bundle's verified entries and rejected ones, recorded for `reopen`.
        let rejected_before = self.rejected.len();
        let mut entries = Vec::new();
        while offset < end {
            number += 1;
            let mut candidates = Vec::new();
            let mut problem: Option<String> = None;
            let mut check = |line: FrameLine| match check_frame_line(path, offset, line) {
                Ok(candidate) => {
                    candidates.push(candidate);
                    ControlFlow::Continue(())
                }
                Err(found) => {
                    problem = Some(found);
                    ControlFlow::Break(())
                }
            };
            let read = match &whole {
                Some(bytes) => {
                    let mut rest = &bytes[usize::try_from(offset).unwrap_or(usize::MAX)..];
                    crate::frames::read_frame(&mut rest, &mut check)
                }
                None => crate::frames::reader_at(path, offset)
                    .map_err(|e| e.to_string())
                    .and_then(|mut reader| crate::frames::read_frame(&mut reader, &mut check)),
            };
            let (next, problem) = match (read, problem) {
                (Ok(len), None) if len > 0 => {
                    // A loose frame's own bytes, hashed for a later reopen.
                    let frame_digest =
                        whole
                            .as_ref()
                            .filter(|_| kind == FileKind::Loose)
                            .and_then(|bytes| {
                                let start = usize::try_from(offset).ok()?;
                                let frame = bytes.get(start..start + usize::try_from(len).ok()?)?;
                                Some((len, blake3::hash(frame)))
                            });
                    for candidate in candidates {
                        let key = candidate.key;
                        let location = Location {
                            file: Arc::clone(&shared),
                            kind,
                            frame: offset,
                            line: candidate.line,
                            len: candidate.len,
                            trajectories: candidate.trajectories,
                            experiment: candidate.experiment,
                            digest: candidate.digest,
                            // Only a frame of one line is receipted, as appends write them.
                            file_digest: frame_digest.filter(|_| candidate.line == 0),
                        };
                        if kind != FileKind::Loose {
                            entries.push((key.clone(), location.clone()));
                        }
                        self.insert(key, location);
                    }
                    offset += len;
                    continue;
                }
                // A frame its live writer has not finished: passed over, not reported.
                _ if live => break,
                (Ok(len), Some(problem)) => (offset + len.max(1), problem),
                (Ok(_), None) => (end, "an empty frame".to_owned()),
                (Err(problem), _) => {
                    // Damaged or incomplete: go on at the next frame that reads whole.
                    let next = next_frame(path, whole.as_deref(), offset + 1, end);
                    let what = if next < end {
                        "damaged"
                    } else {
                        "incomplete or damaged"
                    };
                    (next, format!("{what} ({problem})"))
                }
            };
            let rejected = Rejected {
                file: path.to_path_buf(),
                whole: false,
                offset,
                len: next - offset,
            };
            if !already_set_aside(&self.folder, &rejected) {
                warn(&format!(
                    "{} frame {number} (byte {offset}): {problem}; ignored, its runs will be \
                     recomputed",
                    path.display()
                ));
            }
            self.rejected.push(rejected);
            offset = next;
        }
        if kind != FileKind::Loose {
            let contents = BundleContents {
                len: end,
                entries,
                rejected: self.rejected[rejected_before..].to_vec(),
            };
            self.bundles.insert(path.to_path_buf(), contents);
        }
        Ok(())
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

    /// Whether run `key` is stored (verified when the store was opened), with any
    /// trajectories.
    #[must_use]
    pub fn line_exists(&self, key: &RunKey) -> bool {
        self.index.contains_key(key)
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
        keys.sort_by(|(_, a), (_, b)| (&a.file, a.frame, a.line).cmp(&(&b.file, b.frame, b.line)));
        keys.into_iter().map(|(key, _)| key).collect()
    }

    /// Whether the store holds no verified run.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.index.is_empty()
    }

    /// The experiment of every verified run, by key (for `verify` and `gc`).
    pub fn experiments(&self) -> impl Iterator<Item = (&RunKey, &str)> {
        self.index
            .iter()
            .map(|(key, at)| (key, at.experiment.as_str()))
    }

    /// The line at `location`, read again with `reader` and checked in full (a loose file may
    /// have been replaced by another process's identical copy since it was indexed).
    fn entry_at(reader: &mut LineReader, location: &Location) -> Result<CheckedEntry, StoreError> {
        let changed = |problem: String| StoreError::Changed {
            path: location.file.to_path_buf(),
            offset: location.frame,
            problem,
        };
        let mut line = reader
            .read(
                &location.file,
                location.frame,
                location.line,
                location.len,
                location.kind == FileKind::Loose,
            )
            .map_err(|e| changed(format!("the entry can no longer be read: {e}")))?;
        if line.last() != Some(&b'\n') {
            return Err(changed("the entry is not one whole line".to_owned()));
        }
        let checked = parse_line(&line[..line.len() - 1]).map_err(&changed)?;
        let (header, description, record) =
            (checked.header, checked.description.to_vec(), checked.record);
        line.shrink_to_fit();
        Ok(CheckedEntry {
            line,
            header,
            description,
            record,
        })
    }

    /// Reads run `key`, compacted under `keep`: `Ok(None)` if the store does not hold it with
    /// the trajectories `keep` asks for. Runs read in storage order ([`RunStore::keys`]: job
    /// order in a packed bundle) decompress each frame once.
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
        let checked = {
            let mut reader = self
                .reader
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            Self::entry_at(&mut reader, location)?
        };
        if checked.header.key != key.as_str() {
            return Err(StoreError::Changed {
                path: location.file.to_path_buf(),
                offset: location.frame,
                problem: format!("it holds run {}, not {key}", checked.header.key),
            });
        }
        Ok(Some(StoredRun {
            description: checked.description,
            record: compact(checked.record, keep),
        }))
    }

    /// The stored line of run `key` (without its newline) and the trajectories it keeps,
    /// checked in full; `Ok(None)` if the store does not hold it. For `verify`, which compares
    /// it with the line the run's recomputation makes.
    ///
    /// # Errors
    /// [`StoreError::Changed`] if it no longer checks.
    pub fn line(&self, key: &RunKey) -> Result<Option<(Vec<u8>, KeepTrajectories)>, StoreError> {
        let Some(location) = self.index.get(key) else {
            return Ok(None);
        };
        let mut reader = self
            .reader
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let mut checked = Self::entry_at(&mut reader, location)?;
        checked.line.pop();
        Ok(Some((checked.line, checked.header.trajectories)))
    }

    /// Stores a finished run in a file of its own, `runs/loose/<key>.<keep>.run.gz`: written
    /// aside, synced, then renamed into place, so no other process ever sees it half written and
    /// no two processes write the same file. (Two storing the same run write the same bytes.)
    /// Needs no lock; [`RunStore::pack`] moves it into its bundle later. Returns the receipt
    /// of the bytes written, with which [`RunStore::open_with_receipts`] indexes the file
    /// without reading it back in full. Many runs in a row are cheaper through a
    /// [`LooseBatch`], which writes them into one file and syncs once per batch.
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
        let (line, entry) = Self::entry(&path, key, description, record, keep)?;
        self.make_loose_folder().map_err(write)?;
        crate::atomic::write_atomic_among_writers(&path, &entry, &self.writers())
            .map_err(|e| write(e.source))?;
        Ok(AppendReceipt::of(
            key,
            keep,
            record,
            path.clone(),
            0,
            &line,
            &entry,
        ))
    }

    /// A run's line and its frame in a loose file (one gzip member of stored blocks), for
    /// the file `path`.
    fn entry(
        path: &Path,
        key: &RunKey,
        description: &RunDescription,
        record: &RunRecord,
        keep: KeepTrajectories,
    ) -> Result<(Vec<u8>, Vec<u8>), StoreError> {
        let write = |source| StoreError::Write {
            path: path.to_path_buf(),
            source,
        };
        let description =
            canonical_json(description).map_err(|e| write(io::Error::other(e.to_string())))?;
        let line = line_bytes(key, description.as_bytes(), record, keep)?;
        let entry = crate::gzip::compress_stored(&line).map_err(write)?;
        Ok((line, entry))
    }

    /// Makes `runs/loose/` (and `runs/`), refusing a link on the way.
    fn make_loose_folder(&self) -> io::Result<()> {
        let out = self.folder.parent().unwrap_or(Path::new("."));
        crate::no_follow::ensure_folders(
            out,
            &Path::new(crate::names::RUNS_FOLDER).join(LOOSE_FOLDER),
        )
    }

    /// A batch of loose runs written with one sync for many (group commit): see [`LooseBatch`].
    ///
    /// # Errors
    /// [`StoreError::Write`] if `runs/loose/` cannot be made.
    pub fn batch(&self, limit: BatchLimit) -> Result<LooseBatch<'_>, StoreError> {
        let loose = self.folder.join(LOOSE_FOLDER);
        self.make_loose_folder()
            .map_err(|source| StoreError::Write {
                path: loose.clone(),
                source,
            })?;
        Ok(LooseBatch {
            store: self,
            limit,
            loose,
            state: Mutex::new(BatchState {
                open: None,
                written: Vec::new(),
                made: 0,
                syncing: None,
                failure: None,
            }),
        })
    }

    /// The lock that writers of this store's temporary files hold while they make one.
    fn writers(&self) -> crate::atomic::WritersLock {
        crate::atomic::WritersLock::in_folder(&self.folder)
    }

    /// Packs the store into its bundles, one per experiment: the union of every verified entry
    /// of this store and of the runs `wanted` that `sources` hold (as `merge` takes them from
    /// other stores), each run once with the richest trajectories stored. A bundle lists first
    /// the runs of `wanted` in that order (the plan's job order), then any other runs by key, so
    /// its bytes are a function of the set of runs; a bundle that would be written with the
    /// lines it holds, in its order, is left as it is. The entries that failed their checks
    /// are first set aside in `runs/.set-aside/`. Lines are copied byte for byte, each read
    /// again on the way: lines that still hash to the digest taken when they were verified (or
    /// written) are copied as they are, any others are checked in full again (a loose file
    /// replaced by another process since it was indexed is packed as what it now holds, and
    /// one that no longer checks is [`StoreError::Changed`], with nothing removed). Then every
    /// store file this store read and did not just write (loose runs, a bundle of an earlier
    /// version, a stray copy of a bundle: all their runs are now in the bundles, their failed
    /// entries set aside) is removed, and temporary files of writers that are gone are removed.
    /// Needs the output folder's lock (`_lock`), so no two packs overlap; writers of loose runs
    /// may go on meanwhile (their new files stay loose). Returns the store reopened: what
    /// [`RunStore::open`] would read, with the bundles just written indexed from what was
    /// written rather than read back, and every other file checked in full.
    pub fn pack(
        self,
        lock: &crate::output_folder::OutputFolder,
        sources: &[RunStore],
        wanted: &[RunKey],
        warn: &mut dyn FnMut(&str),
    ) -> Result<Self, StoreError> {
        self.pack_dropping(lock, sources, wanted, &[], warn)
    }

    /// The runs of this store that no plan of this code can ask for: stored by another
    /// `RESULTS_FORMAT` or crate version (their keys hash those, so no key computed now
    /// matches them). Reads every stored line's description (for `gc`).
    ///
    /// # Errors
    /// [`StoreError`] if a stored line can no longer be read.
    pub fn stale_runs(&self) -> Result<Vec<RunKey>, StoreError> {
        #[derive(Deserialize)]
        struct Versions {
            results_format: u32,
            crate_version: String,
        }
        let mut stale = Vec::new();
        for key in self.keys() {
            let Some((line, _)) = self.line(key)? else {
                continue;
            };
            let description = line.split(|&b| b == b'\t').nth(1).unwrap_or_default();
            let current = serde_json::from_slice::<Versions>(description).is_ok_and(|v| {
                v.results_format == crate::RESULTS_FORMAT
                    && v.crate_version == env!("CARGO_PKG_VERSION")
            });
            if !current {
                stale.push(key.clone());
            }
        }
        Ok(stale)
    }

    /// [`RunStore::pack`] leaving out the runs `dropped` (for `gc`): their lines are written into
    /// no bundle, and the files that held them are removed with the others read.
    ///
    /// # Errors
    /// As [`RunStore::pack`].
    pub fn pack_dropping(
        mut self,
        _lock: &crate::output_folder::OutputFolder,
        sources: &[RunStore],
        wanted: &[RunKey],
        dropped: &[RunKey],
        warn: &mut dyn FnMut(&str),
    ) -> Result<Self, StoreError> {
        for key in dropped {
            self.index.remove(key);
        }
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
        // Rejected entries are copied aside before their files are replaced or removed below.
        self.set_aside(warn)?;
        // What each bundle written holds, to index it without reading it back.
        let mut written = HashMap::new();
        let mut reader = LineReader::default();
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
            if let Some(contents) = self.unchanged_bundle(&path, &keys, &chosen, &mut reader) {
                written.insert(path, contents);
                continue;
            }
            let bundle = crate::atomic::AtomicFile::create_among_writers(&path, &self.writers())
                .map_err(|e| write(&path)(e.source))?;
            let mut frames = crate::frames::FrameWriter::new(bundle).map_err(write(&path))?;
            let shared = Arc::new(path.clone());
            let mut entries = Vec::with_capacity(keys.len());
            for key in &keys {
                let at = chosen[*key];
                let (line, digest, key, trajectories, experiment) =
                    match read_verified(&mut reader, at) {
                        // The very line verified (or written) earlier: copied as it is, its
                        // digest the one it was just checked against.
                        Some(line) => (
                            line,
                            at.digest,
                            (*key).clone(),
                            at.trajectories,
                            at.experiment.clone(),
                        ),
                        // Changed since (another process's copy of a loose file, or damage):
                        // checked in full again, and indexed as what it now holds.
                        None => {
                            let checked = Self::entry_at(&mut reader, at)?;
                            let key = RunKey::from_verified_hex(checked.header.key);
                            let digest = blake3::hash(&checked.line);
                            (
                                checked.line,
                                digest,
                                key,
                                checked.header.trajectories,
                                checked.header.experiment,
                            )
                        }
                    };
                let (frame, offset) = frames.push(&line).map_err(write(&path))?;
                let location = Location {
                    file: Arc::clone(&shared),
                    kind: FileKind::Bundle,
                    frame,
                    line: offset,
                    len: line.len() as u64,
                    trajectories,
                    experiment,
                    digest,
                    file_digest: None,
                };
                entries.push((key, location));
            }
            let (bundle, len) = frames.finish().map_err(write(&path))?;
            bundle.commit().map_err(|e| write(&path)(e.source))?;
            let contents = BundleContents {
                len,
                entries,
                rejected: Vec::new(),
            };
            written.insert(path, contents);
        }
        drop(reader);
        // The files read whose runs are now all in the bundles written (loose runs, duplicates
        // of packed runs, a bundle of an earlier version or a stray copy) leave the store.
        for path in &self.files {
            if written.contains_key(path) || self.live.contains(path) {
                continue;
            }
            match std::fs::symlink_metadata(path) {
                Ok(meta) if meta.is_file() => match std::fs::remove_file(path) {
                    Ok(()) => {}
                    Err(error) if error.kind() == io::ErrorKind::NotFound => {}
                    Err(source) => return Err(write(path)(source)),
                },
                // Set aside above (moved), or not a file: nothing to remove.
                _ => {}
            }
        }
        let writers = self.writers();
        for dir in [
            folder.clone(),
            folder.join(LOOSE_FOLDER),
            folder.join(crate::names::PRETRAINED),
        ] {
            crate::atomic::remove_stale_temporary_files(&dir, Some(&writers))
                .map_err(write(&dir))?;
        }
        drop(chosen);
        // Reopened as `open` would (every other file checked in full: other bundles, loose runs
        // that appeared meanwhile), its own bundles from what it wrote.
        let trusted = Trusted {
            received: HashMap::new(),
            bundles: written,
        };
        Self::open_folder(&folder, trusted, &mut |_| {})
    }

    /// What the bundle `path` holds if it already holds exactly `keys` in this order, each
    /// the line chosen for it, and nothing that failed: then it need not be written again.
    /// Its lines are read and hashed all the same (damage in place is found as when copying).
    fn unchanged_bundle(
        &self,
        path: &Path,
        keys: &[&RunKey],
        chosen: &HashMap<RunKey, &Location>,
        reader: &mut LineReader,
    ) -> Option<BundleContents> {
        let contents = self.bundles.get(path)?;
        let same = contents.rejected.is_empty()
            && contents.entries.len() == keys.len()
            && contents
                .entries
                .iter()
                .zip(keys)
                .all(|((key, at), wanted)| {
                    key == *wanted && chosen.get(key).is_some_and(|chosen| *chosen == at)
                })
            && std::fs::symlink_metadata(path)
                .is_ok_and(|meta| meta.is_file() && meta.len() == contents.len)
            && contents
                .entries
                .iter()
                .all(|(_, at)| read_verified(reader, at).is_some());
        same.then(|| contents.clone())
    }

    /// Copies each rejected frame into `runs/.set-aside/` (a loose file, link or special file
    /// is moved there whole), so it is reported once and kept for inspection, never deleted.
    /// One already set aside with the same bytes (by a pack killed before it removed the file)
    /// is not copied or reported again.
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
            let target = set_aside_path(&self.folder, rejected);
            if already_set_aside(&self.folder, rejected) {
                if rejected.whole {
                    // Copied there by a pack killed before it removed this one.
                    let _ = std::fs::remove_file(&rejected.file);
                }
                continue;
            }
            if rejected.whole {
                match std::fs::rename(&rejected.file, &target) {
                    Ok(()) => {}
                    // Packed or moved by another process since.
                    Err(error) if error.kind() == io::ErrorKind::NotFound => continue,
                    Err(source) => return Err(write(&target)(source)),
                }
            } else {
                let read = |source| StoreError::Read {
                    path: rejected.file.clone(),
                    source,
                };
                let mut reader =
                    crate::frames::reader_at(&rejected.file, rejected.offset).map_err(read)?;
                let mut bytes = Vec::new();
                (&mut reader)
                    .take(rejected.len)
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

/// The most bytes of a loose file read whole when indexed (so that its hash, for a later
/// reopen, is of the bytes checked); a larger one is read streaming and checked in full again
/// by a reopen. A batch file stops taking runs at [`BATCH_FILE_BYTES`].
const LOOSE_HELD_BYTES: u64 = 16 << 20;

/// A [`LooseBatch`] starts a new file once its file holds this many bytes, so a batch file is
/// read whole when indexed ([`LOOSE_HELD_BYTES`]) unless one run alone is larger.
const BATCH_FILE_BYTES: u64 = 8 << 20;

/// When a [`LooseBatch`] closes its file and syncs what it has written: after `runs` runs or
/// `interval`, whichever comes first (and when it is finished).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BatchLimit {
    /// Runs per batch (at least 1).
    pub runs: usize,
    /// The longest a written run waits for its batch's sync to start.
    pub interval: std::time::Duration,
}

impl Default for BatchLimit {
    /// 256 runs or 2 seconds: a crash of the machine loses at most the runs of the last
    /// seconds (recomputed on the next invocation), and a sweep of thousands of short runs
    /// makes and syncs a handful of files instead of one file and two syncs per run.
    fn default() -> Self {
        Self {
            runs: 256,
            interval: std::time::Duration::from_secs(2),
        }
    }
}

/// Loose runs written many to a file, with one sync per batch: a **group commit**.
/// [`LooseBatch::append`] adds a run's frame (one gzip member, as in a single run's loose
/// file) to the batch's own file in `runs/loose/`, `batch-<pid>-<time>-<n>.run.gz`, with one
/// `write`, and does not force it to disk. The file is made as a locked temporary file and
/// renamed into place still locked ([`crate::atomic::AtomicFile::publish_locked`]), and it
/// stays locked until the batch closes it: so another process never mistakes it for a
/// finished file. A reader indexes its whole frames and passes over a frame being written;
/// a pack copies its runs but never removes it while it is locked (see
/// [`RunStore::pack`]). When the batch reaches its [`BatchLimit`] (or 8 MiB, `BATCH_FILE_BYTES`),
/// its file is closed and synced on a thread of its own while the next file is written: on
/// Linux by one `syncfs` of the store's file system, elsewhere by syncing each file and then
/// the folder once. [`LooseBatch::finish`] closes and syncs the rest and waits for every
/// sync. One file per batch instead of one per run saves creating, renaming and later
/// removing a file per run (docs/paper-notes.md §24.2).
///
/// **A killed process** loses nothing it wrote: the kernel holds it, and the file's lock goes
/// with the process, so the next open reads the file as finished (a frame cut short by the
/// kill, if any, is reported, set aside and recomputed).
///
/// **The durability trade** (docs/paper-notes.md §24): a crash of the *machine* (power
/// loss, kernel panic) may lose the runs written since the last completed sync, at most two
/// batches (the one being synced and the one being written). A lost run's frame is missing,
/// empty or torn; the next open finds its gzip CRC or its checksum wrong, reports it, the
/// next pack sets it aside, and the run is recomputed (same bits: every run is a function of
/// its description). Nothing wrong is ever trusted, and the runs of earlier batches are safe.
pub struct LooseBatch<'a> {
    store: &'a RunStore,
    limit: BatchLimit,
    loose: PathBuf,
    state: Mutex<BatchState>,
}

struct BatchState {
    /// The file being written, if any.
    open: Option<BatchFile>,
    /// Batch files closed since the last sync started.
    written: Vec<PathBuf>,
    /// Files this batch has made, for their names.
    made: u64,
    /// The sync in flight.
    syncing: Option<std::thread::JoinHandle<io::Result<()>>>,
    /// The first failed sync, reported by the next append or by `finish`.
    failure: Option<io::Error>,
}

/// A batch file being written: open, locked, `len` bytes long, holding `runs` runs since
/// `started`.
struct BatchFile {
    path: PathBuf,
    file: std::fs::File,
    len: u64,
    runs: usize,
    started: std::time::Instant,
}

impl LooseBatch<'_> {
    /// Stores a finished run in the batch's file, synced with its batch, and returns the
    /// receipt of its frame.
    ///
    /// # Errors
    /// [`StoreError`] if the run cannot be written, or an earlier sync of this batch failed.
    pub fn append(
        &self,
        key: &RunKey,
        description: &RunDescription,
        record: &RunRecord,
        keep: KeepTrajectories,
    ) -> Result<AppendReceipt, StoreError> {
        let (line, entry) = RunStore::entry(&self.loose, key, description, record, keep)?;
        let mut state = self
            .state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let open = match &mut state.open {
            Some(open) => open,
            None => {
                let made = self.create_file(&mut state.made)?;
                state.open.insert(made)
            }
        };
        let frame = open.len;
        if let Err(source) = io::Write::write_all(&mut open.file, &entry) {
            // Closed, so that the frame it may have cut short is found once its writer is
            // gone, and the next run goes to a new file.
            let path = open.path.clone();
            state.open = None;
            return Err(StoreError::Write { path, source });
        }
        open.len += entry.len() as u64;
        open.runs += 1;
        let receipt = AppendReceipt::of(key, keep, record, open.path.clone(), frame, &line, &entry);
        if open.runs >= self.limit.runs.max(1)
            || open.len >= BATCH_FILE_BYTES
            || open.started.elapsed() >= self.limit.interval
        {
            Self::close(&mut state);
            self.start_sync(&mut state);
        }
        match state.failure.take() {
            Some(source) => Err(StoreError::Write {
                path: self.loose.clone(),
                source,
            }),
            None => Ok(receipt),
        }
    }

    /// A new batch file, locked and in place (`runs/loose/` made again if it was removed).
    fn create_file(&self, made: &mut u64) -> Result<BatchFile, StoreError> {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |since| since.as_nanos());
        let mut last = None;
        for attempt in 0..4 {
            *made += 1;
            let name = format!(
                "batch-{}-{nanos}-{made}.{}",
                std::process::id(),
                crate::names::RUN_FILE_EXTENSION
            );
            let path = self.loose.join(name);
            if attempt > 0 {
                // The folder was removed under us, or the name taken: made again.
                self.store
                    .make_loose_folder()
                    .map_err(|source| StoreError::Write {
                        path: self.loose.clone(),
                        source,
                    })?;
            }
            let published =
                crate::atomic::AtomicFile::create_among_writers(&path, &self.store.writers())
                    .and_then(crate::atomic::AtomicFile::publish_locked);
            match published {
                Ok(file) => {
                    return Ok(BatchFile {
                        path,
                        file,
                        len: 0,
                        runs: 0,
                        started: std::time::Instant::now(),
                    });
                }
                Err(error) => last = Some(error),
            }
        }
        let error = last.expect("at least one attempt");
        Err(StoreError::Write {
            path: error.path,
            source: error.source,
        })
    }

    /// Closes the file being written (which unlocks it) and queues it for the next sync.
    fn close(state: &mut BatchState) {
        if let Some(open) = state.open.take() {
            drop(open.file);
            state.written.push(open.path);
        }
    }

    /// Waits for the sync in flight (keeping its failure), then starts syncing what was
    /// written since on a thread of its own.
    fn start_sync(&self, state: &mut BatchState) {
        Self::wait(state);
        let files = Arc::new(std::mem::take(&mut state.written));
        if files.is_empty() {
            return;
        }
        let (loose, to_sync) = (self.loose.clone(), Arc::clone(&files));
        let spawned = std::thread::Builder::new()
            .name("eamadm-store-sync".to_owned())
            .spawn(move || sync_written(&loose, &to_sync));
        match spawned {
            Ok(handle) => state.syncing = Some(handle),
            // No thread to spare: sync here and now.
            Err(_) => {
                if let Err(error) = sync_written(&self.loose, &files) {
                    state.failure.get_or_insert(error);
                }
            }
        }
    }

    /// Waits for the sync in flight, keeping its failure.
    fn wait(state: &mut BatchState) {
        if let Some(handle) = state.syncing.take() {
            let result = handle
                .join()
                .unwrap_or_else(|_| Err(io::Error::other("the sync thread panicked")));
            if let Err(error) = result {
                state.failure.get_or_insert(error);
            }
        }
    }

    /// Closes the file being written, syncs every run written and waits until they are on
    /// disk.
    ///
    /// # Errors
    /// [`StoreError::Write`] if a sync failed.
    pub fn finish(self) -> Result<(), StoreError> {
        let mut state = self
            .state
            .into_inner()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        Self::close(&mut state);
        Self::wait(&mut state);
        let files = std::mem::take(&mut state.written);
        if let Err(error) = sync_written(&self.loose, &files) {
            state.failure.get_or_insert(error);
        }
        match state.failure {
            Some(source) => Err(StoreError::Write {
                path: self.loose,
                source,
            }),
            None => Ok(()),
        }
    }

    /// The batch files written and not yet handed to a sync, the one being written last (for
    /// tests of a crash).
    #[doc(hidden)]
    #[must_use]
    pub fn unsynced(&self) -> Vec<PathBuf> {
        let state = self
            .state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let mut files = state.written.clone();
        files.extend(state.open.as_ref().map(|open| open.path.clone()));
        files
    }
}

/// Forces the loose files `files` of the folder `loose` and their names to disk: one `syncfs`
/// on Linux (the file system's dirty data, ours among it), elsewhere each file and then the
/// folder. Nothing to do for no file.
fn sync_written(loose: &Path, files: &[PathBuf]) -> io::Result<()> {
    if files.is_empty() {
        return Ok(());
    }
    #[cfg(target_os = "linux")]
    {
        let _ = files;
        let folder = std::fs::File::open(loose)?;
        rustix::fs::syncfs(&folder).map_err(io::Error::from)
    }
    #[cfg(not(target_os = "linux"))]
    {
        for file in files {
            match std::fs::File::open(file) {
                Ok(file) => file.sync_all()?,
                // Packed and removed by another process meanwhile: its bundle was synced.
                Err(error) if error.kind() == io::ErrorKind::NotFound => {}
                Err(error) => return Err(error),
            }
        }
        crate::atomic::sync_folder(loose)
    }
}

/// Checks one line of the frame at byte `frame` of `path`: a line too long to be held is read
/// again whole (under the cap, so legitimately long) to be parsed.
fn check_frame_line(path: &Path, frame: u64, line: FrameLine) -> Result<Candidate, String> {
    let bytes = match line.bytes {
        Some(bytes) => bytes,
        None => crate::frames::reader_at(path, frame)
            .and_then(|reader| crate::frames::read_line_at(reader, line.offset, line.len))
            .map_err(|e| format!("a long line cannot be read again ({e})"))?,
    };
    if blake3::hash(&bytes) != line.digest {
        return Err("the file changed while it was read".to_owned());
    }
    let text = bytes.strip_suffix(b"\n").unwrap_or(&bytes);
    let parsed = parse_line(text)?;
    Ok(Candidate {
        key: RunKey::from_verified_hex(parsed.header.key),
        line: line.offset,
        len: line.len,
        digest: line.digest,
        trajectories: parsed.header.trajectories,
        experiment: parsed.header.experiment,
    })
}

/// The line at `location` if it hashes to the digest verified; `None` if it differs or cannot
/// be read (the caller then checks it in full, which reports why).
fn read_verified(reader: &mut LineReader, location: &Location) -> Option<Vec<u8>> {
    let line = reader
        .read(
            &location.file,
            location.frame,
            location.line,
            location.len,
            location.kind == FileKind::Loose,
        )
        .ok()?;
    (blake3::hash(&line) == location.digest).then_some(line)
}

/// Where `rejected` is (or would be) set aside.
fn set_aside_path(folder: &Path, rejected: &Rejected) -> PathBuf {
    let name = rejected
        .file
        .file_name()
        .map_or_else(|| "entry".into(), |n| n.to_string_lossy().into_owned());
    folder
        .join(crate::names::SET_ASIDE)
        .join(format!("{name}.at-{}", rejected.offset))
}

/// Whether `rejected` was set aside already: its place in `.set-aside/` holds its very bytes
/// (for a file moved whole, a file of the same length and hash). A pack killed after setting
/// it aside and before removing it from the store leaves it so; it was reported then.
fn already_set_aside(folder: &Path, rejected: &Rejected) -> bool {
    let target = set_aside_path(folder, rejected);
    let Ok(meta) = std::fs::symlink_metadata(&target) else {
        return false;
    };
    if !meta.is_file() {
        return false;
    }
    let (source, len) = if rejected.whole {
        match std::fs::symlink_metadata(&rejected.file) {
            Ok(own) if own.is_file() => (&rejected.file, own.len()),
            _ => return false,
        }
    } else {
        (&rejected.file, rejected.len)
    };
    if meta.len() != len || len > LOOSE_HELD_BYTES * 4 {
        return false;
    }
    let hash_of = |path: &Path, offset: u64| -> Option<blake3::Hash> {
        let reader = crate::frames::reader_at(path, offset).ok()?;
        let mut hasher = blake3::Hasher::new();
        let copied = io::copy(&mut reader.take(len), &mut hasher).ok()?;
        (copied == len).then(|| hasher.finalize())
    };
    let at = if rejected.whole { 0 } else { rejected.offset };
    hash_of(&target, 0).is_some() && hash_of(&target, 0) == hash_of(source, at)
}

/// Checks the bytes of a store file as [`RunStore::open`] does, in memory: how many lines
/// verify, and one problem per frame that does not. Never panics and never holds more than
/// [`crate::frames`] allows for one frame (the fuzz target `store_bytes` calls it).
#[must_use]
pub fn check_bytes(bytes: &[u8]) -> (usize, Vec<String>) {
    let mut offset = 0_usize;
    let mut verified = 0;
    let mut problems = Vec::new();
    while offset < bytes.len() {
        let mut good = 0;
        let mut problem = None;
        let mut rest = &bytes[offset..];
        let read = crate::frames::read_frame(&mut rest, &mut |line| {
            let checked = match &line.bytes {
                Some(text) => parse_line(text.strip_suffix(b"\n").unwrap_or(text)).map(|_| ()),
                None => Err("a line longer than is held".to_owned()),
            };
            match checked {
                Ok(()) => {
                    good += 1;
                    ControlFlow::Continue(())
                }
                Err(found) => {
                    problem = Some(found);
                    ControlFlow::Break(())
                }
            }
        });
        match (read, problem) {
            (Ok(len), None) if len > 0 => {
                verified += good;
                offset += usize::try_from(len).unwrap_or(bytes.len());
            }
            (Ok(len), Some(found)) => {
                problems.push(found);
                offset += usize::try_from(len.max(1)).unwrap_or(bytes.len());
            }
            (Ok(_), None) => break,
            (Err(found), _) => {
                problems.push(found);
                // Resume at the next byte that may start a frame, as the store's reader does.
                offset = bytes[offset + 1..]
                    .iter()
                    .position(|&b| b == 0x1f || b == 0x28)
                    .map_or(bytes.len(), |skip| offset + 1 + skip);
            }
        }
    }
    (verified, problems)
}

/// Whether another open file description holds a lock on `file`: a loose file a
/// [`LooseBatch`] is still writing (it locks the file before the file is visible and keeps it
/// locked until it closes it, or its process dies).
fn held_by_writer(file: &std::fs::File) -> bool {
    match file.try_lock_shared() {
        Ok(()) => {
            let _ = file.unlock();
            false
        }
        Err(std::fs::TryLockError::WouldBlock) => true,
        // No locks on this file system: nothing can be told, so nothing is taken for live.
        Err(std::fs::TryLockError::Error(_)) => false,
    }
}

/// `receipts` by the loose file they name, each file's sorted by frame.
fn by_file(receipts: impl Iterator<Item = AppendReceipt>) -> HashMap<PathBuf, Vec<AppendReceipt>> {
    let mut files: HashMap<PathBuf, Vec<AppendReceipt>> = HashMap::new();
    for receipt in receipts {
        files.entry(receipt.file.clone()).or_default().push(receipt);
    }
    for receipts in files.values_mut() {
        receipts.sort_by_key(|receipt| receipt.frame);
    }
    files
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

/// The first byte at or after `from` (before `end`) of `path` (or of its bytes `whole`, when
/// read whole) where a whole frame reads, or `end`.
fn next_frame(path: &Path, whole: Option<&[u8]>, from: u64, end: u64) -> u64 {
    let Some(bytes) = whole else {
        return next_frame_on_disk(path, from, end);
    };
    let mut at = usize::try_from(from).unwrap_or(bytes.len());
    while at < bytes.len() {
        match bytes[at..].iter().position(|&b| b == 0x1f || b == 0x28) {
            Some(skip) => {
                let candidate = at + skip;
                let mut rest = &bytes[candidate..];
                if crate::frames::read_frame(&mut rest, &mut |_| ControlFlow::Continue(()))
                    .is_ok_and(|len| len > 0)
                {
                    return candidate as u64;
                }
                at = candidate + 1;
            }
            None => break,
        }
    }
    end
}

/// [`next_frame`] in a file read in pieces, looking for a frame's magic.
fn next_frame_on_disk(path: &Path, from: u64, end: u64) -> u64 {
    let mut at = from;
    while at < end {
        let Ok(mut reader) = crate::frames::reader_at(path, at) else {
            return end;
        };
        let Ok(buffer) = io::BufRead::fill_buf(&mut reader) else {
            return end;
        };
        if buffer.is_empty() {
            return end;
        }
        match buffer.iter().position(|&b| b == 0x1f || b == 0x28) {
            Some(skip) => {
                let candidate = at + skip as u64;
                if frame_reads(path, candidate) {
                    return candidate;
                }
                at = candidate + 1;
            }
            None => at += buffer.len() as u64,
        }
    }
    end
}

/// Whether a whole frame reads at byte `at` of `path`.
fn frame_reads(path: &Path, at: u64) -> bool {
    crate::frames::reader_at(path, at).is_ok_and(|mut reader| {
        crate::frames::read_frame(&mut reader, &mut |_| ControlFlow::Continue(()))
            .is_ok_and(|len| len > 0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gzip;
    use std::io::Write as _;

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

    /// The lines of a store file (any framing), each with its newline.
    fn lines_of(bytes: &[u8]) -> Vec<Vec<u8>> {
        crate::frames::decompress(bytes)
            .unwrap()
            .split_inclusive(|&b| b == b'\n')
            .map(<[u8]>::to_vec)
            .collect()
    }

    /// The line (with its newline) of each run, as a store file holds it.
    fn run_lines(runs: &[(RunKey, RunDescription, RunRecord)]) -> Vec<Vec<u8>> {
        runs.iter()
            .map(|run| {
                let description = canonical_json(&run.1).unwrap();
                line_bytes(
                    &run.0,
                    description.as_bytes(),
                    &run.2,
                    KeepTrajectories::Figures,
                )
                .unwrap()
            })
            .collect()
    }

    /// `lines` as a bundle of an earlier version, one gzip member each.
    fn legacy_bytes(lines: &[Vec<u8>]) -> Vec<u8> {
        lines
            .iter()
            .flat_map(|line| gzip::compress(line).unwrap())
            .collect()
    }

    /// `runs` as a bundle of an earlier version in `dir` (`runs/<experiment>.jsonl.gz`, one gzip
    /// member per run); its path.
    fn legacy_bundle(dir: &Path, runs: &[(RunKey, RunDescription, RunRecord)]) -> PathBuf {
        let path = dir.join("runs").join(format!(
            "{}.{LEGACY_BUNDLE_EXTENSION}",
            runs[0].2.experiment
        ));
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, legacy_bytes(&run_lines(runs))).unwrap();
        path
    }

    /// The visible entries of `folder`, sorted.
    fn visible(folder: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(folder)
            .map(|entries| {
                entries
                    .map(|e| e.unwrap().file_name().into_string().unwrap())
                    .filter(|name| !name.starts_with('.'))
                    .collect()
            })
            .unwrap_or_default();
        names.sort();
        names
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
        let names = |folder: &str| visible(&dir.path().join(folder));
        assert_eq!(names("runs/loose").len(), 2);
        assert_eq!(names("runs"), vec!["loose"]);
        assert!(pack(dir.path(), &keys(&runs)).is_empty());
        assert_eq!(
            names("runs"),
            vec![
                "loose".to_owned(),
                format!("{}.jsonl.zst", record.experiment)
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
        let runs = runs();
        // Change one number of the first record's first episode (its steps, a digit longer):
        // the line decompresses but its checksum fails.
        let mut lines = run_lines(&runs);
        let first = String::from_utf8(lines[0].clone()).unwrap();
        let steps = format!("\"steps\":[{},", runs[0].2.episodes[0].steps);
        assert!(first.contains(&steps), "{first}");
        let edited = first.replacen(
            &steps,
            &format!("\"steps\":[{}0,", runs[0].2.episodes[0].steps),
            1,
        );
        lines[0] = edited.into_bytes();
        // In a bundle of an earlier version (one gzip member a run) only that run is lost.
        let dir = tempfile::tempdir().unwrap();
        let bundle = legacy_bundle(dir.path(), &runs);
        std::fs::write(&bundle, legacy_bytes(&lines)).unwrap();
        let (store, warnings) = open(dir.path());
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("checksum mismatch"), "{}", warnings[0]);
        assert!(warnings[0].contains("frame 1 (byte 0)"), "{}", warnings[0]);
        assert!(!store.has(&runs[0].0, KeepTrajectories::Figures));
        assert!(store.has(&runs[1].0, KeepTrajectories::Figures));
        // In a bundle's Zstandard frame the frame is refused whole: its runs are recomputed.
        let dir = tempfile::tempdir().unwrap();
        let bundle = stored(dir.path(), &runs);
        std::fs::write(&bundle, crate::frames::compress(&lines.concat()).unwrap()).unwrap();
        let (store, warnings) = open(dir.path());
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("checksum mismatch"), "{}", warnings[0]);
        assert!(store.is_empty());
    }

    #[test]
    fn check_bytes_counts_what_verifies_and_names_the_rest() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        let bundle = std::fs::read(stored(dir.path(), &runs)).unwrap();
        assert_eq!(check_bytes(&bundle), (2, vec![]));
        let (verified, problems) = check_bytes(&bundle[..bundle.len() - 5]);
        assert_eq!(verified, 0);
        assert!(!problems.is_empty());
        let legacy = legacy_bytes(&run_lines(&runs));
        let (verified, problems) = check_bytes(&legacy[..legacy.len() - 5]);
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
    fn a_damaged_frame_is_skipped_and_reading_resumes_at_the_next() {
        let runs = runs();
        let lines = run_lines(&runs);
        // A bundle of two frames (one run each), and a bundle of an earlier version.
        for bytes in [
            [
                crate::frames::compress(&lines[0]).unwrap(),
                crate::frames::compress(&lines[1]).unwrap(),
            ]
            .concat(),
            legacy_bytes(&lines),
        ] {
            let dir = tempfile::tempdir().unwrap();
            let bundle = stored(dir.path(), &runs);
            let first_len = {
                let mut rest = bytes.as_slice();
                crate::frames::read_frame(&mut rest, &mut |_| ControlFlow::Continue(())).unwrap()
            };
            // A disk error in the middle of the first frame's compressed data.
            let mut damaged = bytes.clone();
            damaged[usize::try_from(first_len).unwrap() / 2] ^= 0x55;
            std::fs::write(&bundle, &damaged).unwrap();
            let (store, warnings) = open(dir.path());
            assert_eq!(warnings.len(), 1, "{warnings:?}");
            assert!(
                warnings[0].contains("frame 1 (byte 0): damaged"),
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
    }

    #[test]
    fn a_bundle_reads_as_plain_zstd_whose_lines_are_the_runs() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        // What `zstdcat` does: every frame in turn, concatenated.
        let bundle = std::fs::read(stored(dir.path(), &runs)).unwrap();
        let text = String::from_utf8(zstd::stream::decode_all(bundle.as_slice()).unwrap()).unwrap();
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

    /// A store of an earlier version (gzip bundles) is read as it is, and its next pack
    /// rewrites it as Zstandard bundles and removes the old files: nothing is recomputed.
    #[test]
    fn a_bundle_of_an_earlier_version_is_read_and_replaced_by_the_next_pack() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        let legacy = legacy_bundle(dir.path(), &runs);
        let (store, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.len(), 2);
        assert!(pack(dir.path(), &keys(&runs)).is_empty());
        assert!(!legacy.exists());
        let (store, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.keys(), keys(&runs).iter().collect::<Vec<_>>());
        assert_eq!(
            visible(&dir.path().join("runs")),
            vec!["task1.jsonl.zst".to_owned()]
        );
    }

    #[test]
    fn an_uncompressed_bundle_of_an_earlier_version_is_named_not_read() {
        let dir = tempfile::tempdir().unwrap();
        let runs = runs();
        let bundle = stored(dir.path(), &runs);
        let line = lines_of(&std::fs::read(&bundle).unwrap())[0].clone();
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
        // And every location's digest is the hash of the line there.
        let mut reader = LineReader::default();
        for location in opened.index.values() {
            let line = reader
                .read(
                    &location.file,
                    location.frame,
                    location.line,
                    location.len,
                    true,
                )
                .unwrap();
            assert_eq!(blake3::hash(&line), location.digest);
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
        assert_eq!(store.index[&runs[2].0].kind, FileKind::Loose);

        // A damaged entry in a bundle of an earlier version (set aside, left out, the other
        // run kept), and a damaged bundle of its own (nothing verified in it): both set aside
        // and removed, so never reported again (9dc06af set the second aside on every run).
        let dir = tempfile::tempdir().unwrap();
        let legacy = legacy_bundle(dir.path(), &runs[..2]);
        let mut damaged = std::fs::read(&legacy).unwrap();
        damaged[20] ^= 0x55;
        std::fs::write(&legacy, &damaged).unwrap();
        std::fs::write(dir.path().join("runs/other.jsonl.zst"), &damaged[..30]).unwrap();
        let warnings = pack_equals_open(dir.path(), &all, |_| {});
        assert_eq!(
            warnings.iter().filter(|w| w.contains("set aside")).count(),
            2,
            "{warnings:?}"
        );
        let (store, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.len(), 1);
        assert!(store.rejected.is_empty());
        assert_eq!(
            visible(&dir.path().join("runs")),
            vec!["task1.jsonl.zst".to_owned()]
        );

        // A torn tail.
        let dir = tempfile::tempdir().unwrap();
        let bundle = stored(dir.path(), &runs[..1]);
        let whole = std::fs::read(&bundle).unwrap();
        std::fs::write(&bundle, [&whole[..], &whole[..whole.len() / 2]].concat()).unwrap();
        append_all(dir.path(), &runs[1..2], figures);
        pack_equals_open(dir.path(), &all, |_| {});

        // Duplicates: a run stored keeping the figures' trajectories and keeping all, loose and
        // packed; the richer serves and is packed, the poorer loose copy is removed.
        let dir = tempfile::tempdir().unwrap();
        stored(dir.path(), &runs[..2]);
        append_all(dir.path(), &runs[..1], KeepTrajectories::All);
        append_all(dir.path(), &runs[1..2], figures);
        assert!(pack_equals_open(dir.path(), &all, |_| {}).is_empty());
        let (store, _) = open(dir.path());
        assert!(store.has(&runs[0].0, KeepTrajectories::All));
        assert_eq!(store.index[&runs[0].0].kind, FileKind::Bundle);
        assert!(visible(&dir.path().join("runs/loose")).is_empty());

        // A loose file replaced after indexing by other bytes of the same length that still
        // hold the run (another process's copy whose gzip header says another time): checked
        // in full on the way, and the line now there is packed, as `open` reads it.
        let dir = tempfile::tempdir().unwrap();
        append_all(dir.path(), &runs[..2], figures);
        pack_equals_open(dir.path(), &all, |store| {
            let path = store.loose_path(&runs[0].0, figures);
            let mut replaced = std::fs::read(&path).unwrap();
            replaced[4] = 1; // the gzip header's modification time
            crate::atomic::write_atomic(&path, &replaced).unwrap();
        });
        let (store, _) = open(dir.path());
        assert_eq!(store.len(), 2);
    }

    /// The group commit's durability trade (docs/paper-notes.md §24): a crash of the machine
    /// between batches loses at most the runs not yet handed to a sync. Here the process dies
    /// after six runs with a batch of four (the first file of four synced), and the power loss
    /// tears the second batch file in its first frame, as an unsynced file may be after a
    /// reboot. The next open trusts the four synced runs, reports the torn frame, never
    /// indexes either lost run; the resumed invocation recomputes exactly those two, and after
    /// its pack the store holds the very bytes of a store that never crashed.
    #[test]
    fn a_crash_between_batches_loses_at_most_the_unsynced_runs_and_resumes() {
        let runs = runs_of(6);
        let figures = KeepTrajectories::Figures;
        let limit = BatchLimit {
            runs: 4,
            interval: std::time::Duration::from_secs(3600),
        };
        let dir = tempfile::tempdir().unwrap();
        let (store, _) = open(dir.path());
        let batch = store.batch(limit).unwrap();
        let receipts: Vec<AppendReceipt> = runs
            .iter()
            .map(|(key, description, record)| {
                batch.append(key, description, record, figures).unwrap()
            })
            .collect();
        // One file per batch: the first four runs in one, the last two in the next.
        assert!(receipts[..4].iter().all(|r| r.file() == receipts[0].file()));
        assert!(receipts[4..].iter().all(|r| r.file() == receipts[4].file()));
        assert_ne!(receipts[0].file(), receipts[4].file());
        assert_eq!(
            batch.unsynced(),
            [receipts[4].file().to_path_buf()],
            "the runs after the last full batch wait for their sync"
        );
        // The process dies here (no `finish`), then the machine: the unsynced file is torn.
        drop(batch);
        drop(store);
        let lost = receipts[4].file();
        let torn = std::fs::read(lost).unwrap();
        std::fs::write(lost, &torn[..usize::try_from(receipts[4].len / 2).unwrap()]).unwrap();

        let (store, warnings) = open(dir.path());
        assert_eq!(store.len(), 4);
        for (key, _, _) in &runs[..4] {
            assert!(store.has(key, figures));
        }
        for (key, _, _) in &runs[4..] {
            assert!(!store.has(key, figures));
        }
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("recomputed"), "{warnings:?}");
        // The resumed invocation recomputes what the store lacks (the same bits) and packs.
        let batch = store.batch(limit).unwrap();
        for (key, description, record) in &runs {
            if !store.has(key, figures) {
                batch.append(key, description, record, figures).unwrap();
            }
        }
        batch.finish().unwrap();
        drop(store);
        pack(dir.path(), &keys(&runs));
        let (store, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.keys(), keys(&runs).iter().collect::<Vec<_>>());
        assert!(visible(&dir.path().join("runs/loose")).is_empty());

        let clean = tempfile::tempdir().unwrap();
        let bundle = stored(clean.path(), &runs);
        assert_eq!(
            std::fs::read(store.bundle_path(&runs[0].2.experiment)).unwrap(),
            std::fs::read(bundle).unwrap()
        );
    }

    /// A batch written in full and finished is one file holding, one after the other, the
    /// very frames that appending one run at a time writes to a file each; its receipts index
    /// it as a full check does.
    #[test]
    fn a_finished_batch_is_one_file_of_the_frames_single_appends_store() {
        let runs = runs_of(3);
        let figures = KeepTrajectories::Figures;
        let (one, batched) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        append_all(one.path(), &runs, figures);
        let (store, _) = open(batched.path());
        let batch = store.batch(BatchLimit::default()).unwrap();
        let receipts: Vec<AppendReceipt> = runs
            .iter()
            .map(|(key, description, record)| {
                batch.append(key, description, record, figures).unwrap()
            })
            .collect();
        batch.finish().unwrap();
        let files = visible(&batched.path().join("runs/loose"));
        assert_eq!(files.len(), 1, "{files:?}");
        let singles: Vec<u8> = runs
            .iter()
            .flat_map(|(key, _, _)| {
                std::fs::read(loose_path_in(&one.path().join("runs"), key, figures)).unwrap()
            })
            .collect();
        assert_eq!(std::fs::read(receipts[0].file()).unwrap(), singles);
        let (store, warnings) = open(batched.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.len(), 3);
        let trusting =
            RunStore::open_with_receipts(batched.path(), &receipts, &mut |w| panic!("{w}"))
                .unwrap();
        assert_eq!(contents(&trusting), contents(&store));
    }

    /// A batch file its writer still holds (another process's `run-job` or sweep, here a
    /// batch not yet finished) is read for its whole frames, a frame being written is passed
    /// over without a word, and a pack copies its runs but leaves the file; once the writer
    /// has closed it, the next pack reads it whole and removes it. A writer killed with a
    /// frame cut short leaves a file that is reported once and set aside.
    #[test]
    fn a_batch_file_being_written_is_read_but_never_removed_or_reported() {
        let runs = runs_of(3);
        let figures = KeepTrajectories::Figures;
        let dir = tempfile::tempdir().unwrap();
        let (store, _) = open(dir.path());
        let batch = store.batch(BatchLimit::default()).unwrap();
        let receipts: Vec<AppendReceipt> = runs[..2]
            .iter()
            .map(|(key, description, record)| {
                batch.append(key, description, record, figures).unwrap()
            })
            .collect();
        // Half of a third frame, as a reader may see a `write` in progress.
        let (line, entry) =
            RunStore::entry(dir.path(), &runs[2].0, &runs[2].1, &runs[2].2, figures).unwrap();
        assert!(!line.is_empty());
        let path = receipts[0].file().to_path_buf();
        let mut file = std::fs::OpenOptions::new()
            .append(true)
            .open(&path)
            .unwrap();
        std::io::Write::write_all(&mut file, &entry[..entry.len() / 2]).unwrap();
        drop(file);
        let (other, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(other.len(), 2);
        assert!(pack(dir.path(), &keys(&runs)).is_empty());
        assert!(path.exists(), "a live batch file is never removed");
        let (other, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(other.len(), 2);
        // The writer dies with its third frame cut short: reported once, set aside, removed.
        drop(batch);
        let (_, warnings) = open(dir.path());
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(warnings[0].contains("incomplete"), "{warnings:?}");
        // (The pack's own open reports it as above; the pack then sets it aside.)
        let warnings = pack(dir.path(), &keys(&runs));
        assert!(
            warnings.len() == 2 && warnings[1].contains("set aside"),
            "{warnings:?}"
        );
        assert!(!path.exists());
        let (store, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.len(), 2);
        drop(store);
    }

    /// What a kill between a bundle's rename and the removal of the loose files it packed
    /// leaves: loose copies of packed runs. They are recognised, removed by the next pack and
    /// never reported (9dc06af kept them for ever).
    #[test]
    fn loose_copies_of_packed_runs_left_by_a_kill_are_removed_quietly() {
        let runs = runs();
        let dir = tempfile::tempdir().unwrap();
        stored(dir.path(), &runs);
        append_all(dir.path(), &runs, KeepTrajectories::Figures);
        assert_eq!(visible(&dir.path().join("runs/loose")).len(), 2);
        let (store, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.len(), 2);
        assert!(pack(dir.path(), &keys(&runs)).is_empty());
        assert!(visible(&dir.path().join("runs/loose")).is_empty());
        let (store, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.keys(), keys(&runs).iter().collect::<Vec<_>>());
    }

    /// A garbage bundle and a link among the loose files are reported once: the next pack sets
    /// them aside (the link itself, never followed) and they leave the store (9dc06af warned
    /// and copied them aside again on every run). A pack killed after setting a file aside
    /// and before removing it is recognised too.
    #[cfg(unix)]
    #[test]
    fn garbage_and_links_in_the_store_are_reported_once() {
        let runs = runs();
        let dir = tempfile::tempdir().unwrap();
        stored(dir.path(), &runs);
        let elsewhere = tempfile::tempdir().unwrap();
        let target = elsewhere.path().join("keep.txt");
        std::fs::write(&target, b"not ours").unwrap();
        let garbage = dir.path().join("runs/junk.jsonl.gz");
        std::fs::write(&garbage, b"\x1f\x8b garbage, not a member").unwrap();
        let link = dir
            .path()
            .join(format!("runs/loose/{}.figures.run.gz", "ab".repeat(32)));
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let (_, warnings) = open(dir.path());
        assert_eq!(warnings.len(), 2, "{warnings:?}");
        let warnings = pack(dir.path(), &keys(&runs));
        assert_eq!(
            warnings.iter().filter(|w| w.contains("set aside")).count(),
            2,
            "{warnings:?}"
        );
        for _ in 0..2 {
            let (store, warnings) = open(dir.path());
            assert!(warnings.is_empty(), "reported once: {warnings:?}");
            assert_eq!(store.len(), 2);
            assert!(pack(dir.path(), &keys(&runs)).is_empty());
        }
        assert_eq!(std::fs::read(&target).unwrap(), b"not ours");
        let aside = dir.path().join("runs/.set-aside");
        assert_eq!(visible(&aside).len(), 2, "{:?}", visible(&aside));
        // Set aside by a pack that was killed before it removed the file: not reported again.
        std::fs::write(&garbage, b"\x1f\x8b other garbage").unwrap();
        std::fs::copy(&garbage, aside.join("junk.jsonl.gz.at-0")).unwrap();
        let (_, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert!(pack(dir.path(), &keys(&runs)).is_empty());
        assert!(!garbage.exists());
    }

    /// A forged entry whose experiment (or method) name is a path, its checksum recomputed:
    /// refused by the rule a config's names follow, set aside, and nothing is made outside the
    /// output folder (9dc06af's pack made folders outside `--out` and wrote the bundle there).
    #[test]
    fn names_read_from_stored_bytes_never_become_paths() {
        let runs = runs();
        let base = tempfile::tempdir().unwrap();
        let dir = base.path().join("deep/out");
        std::fs::create_dir_all(&dir).unwrap();
        for name in [
            "../../escaped",
            "/tmp/eamadm-escaped-35",
            "runs",
            ".hidden",
            "a/b",
        ] {
            let mut record = runs[0].2.clone();
            record.experiment = name.to_owned();
            let mut description = RunDescription::new(
                &eamadm::Experiment::new(eamadm::paper::task1()).unwrap(),
                &eamadm::paper::task1().methods[1],
                record.seed,
            );
            description.config.name = name.to_owned();
            description.config.methods[0].label = record.method.clone();
            let key = RunKey::of(&description).unwrap();
            let (store, _) = open(&dir);
            store
                .append(&key, &description, &record, KeepTrajectories::Figures)
                .unwrap();
            let (store, warnings) = open(&dir);
            assert!(!store.has(&key, KeepTrajectories::Figures), "{name}");
            assert_eq!(warnings.len(), 1, "{name}: {warnings:?}");
            assert!(warnings[0].contains("not a safe name"), "{}", warnings[0]);
            pack(&dir, &[]);
        }
        assert_eq!(visible(base.path()), vec!["deep".to_owned()]);
        assert_eq!(visible(&base.path().join("deep")), vec!["out".to_owned()]);
        assert!(!Path::new("/tmp/eamadm-escaped-35").exists());
        assert_eq!(visible(&dir.join("runs")), vec!["loose".to_owned()]);
        assert_eq!(visible(&dir.join("runs/.set-aside")).len(), 5);
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
            error
                .to_string()
                .contains("the file changed while this command ran"),
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
        assert!(!dir.path().join("runs/task1.jsonl.zst").exists());
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
        // (it then holds a torn frame after its entry, as a batch file cut short by a kill
        // does: the whole frame is indexed, the torn one refused).
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
        let bundle = legacy_bundle(dir.path(), &runs[..2]);
        let mut damaged = std::fs::read(&bundle).unwrap();
        damaged[20] ^= 0x55;
        let torn = [&damaged[..], &damaged[..damaged.len() / 2]].concat();
        std::fs::write(&bundle, &torn).unwrap();
        std::fs::write(dir.path().join("runs/other.jsonl.zst"), &damaged[..30]).unwrap();
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
            assert_eq!(store.index[&runs[0].0].kind, FileKind::Loose);
            std::fs::remove_file(richer).unwrap();
            Vec::new()
        });

        // Two bundles holding the same runs: the second's entries, outranked at the first open
        // by the first's (first of equals), serve once the first is found damaged.
        let dir = tempfile::tempdir().unwrap();
        let bundle = stored(dir.path(), &runs[..2]);
        let copy = dir.path().join("runs/a-copy.jsonl.zst");
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
            0,
            "a full read rejects the damaged frame"
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
