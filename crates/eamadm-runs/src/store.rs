//! The run store: every finished run as one entry of a bundle file
//! `<out>/runs/<experiment>.jsonl.gz`, so a sweep makes one file per experiment, not one per run.
//!
//! An entry is one gzip member (see [`crate::gzip`]) holding one line, so the bundle is a valid
//! multi-member gzip file and `zcat runs/task1.jsonl.gz` prints the lines. Compressed, the
//! default run's store is about 5 MB instead of 37 MB. A line is three tab-separated parts
//! (compact JSON never holds a raw tab):
//!
//! ```text
//! {"format":2,"key":…,"experiment":…,"method":…,"seed":…,"trajectories":"figures","blake3":…}<TAB><description><TAB><record>
//! ```
//!
//! - the header says what the run is, which training trajectories the record keeps
//!   ([`KeepTrajectories`]) and `blake3`, the BLAKE3 hash of the bytes `<description><TAB><record>`;
//! - the description is the run's [`RunDescription`] in canonical JSON, whose BLAKE3 hash *is* the
//!   run's key, so the key is checked, not trusted;
//! - the record is the [`RunRecord`] with its per-episode curve stored as columns, training
//!   trajectories removed unless kept for all.
//!
//! Entries are appended while a run goes (one `write` of the whole entry, then a sync), so a kill
//! loses at most the entry being written; opening the store for writing cuts such a torn tail.
//! An entry that does not decompress (gzip checks its CRC), or whose format, key or checksum is
//! wrong, is reported as a warning and ignored, and its run is recomputed; reading resumes at the
//! next entry that decompresses. At the end of an invocation the bundle is rewritten in job order
//! (see [`crate::finish`]), so its bytes do not depend on completion order or thread count.

use std::collections::HashMap;
use std::fs::{File, OpenOptions};
use std::io::{self, BufRead as _, BufReader, Read as _, Seek as _, SeekFrom, Write as _};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};

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

/// Version of the line layout above; bump it when the layout changes.
pub const RUN_LINE_FORMAT: u64 = 2;

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

/// Where a verified entry is: its offset and compressed length in the bundle.
#[derive(Debug, Clone)]
struct Location {
    file: Arc<PathBuf>,
    offset: u64,
    len: usize,
    trajectories: KeepTrajectories,
}

/// One line taken apart and checked: its header, description and record bytes.
struct Line<'a> {
    header: LineHeader,
    description: &'a [u8],
    record: &'a [u8],
}

/// Splits and checks one line (without its newline): format, checksum, key.
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
    let digest = blake3::hash(content).to_hex();
    if digest.as_str() != header.blake3 {
        return Err(format!(
            "checksum mismatch for run {} (stored {}, content hashes to {digest}): the line was \
             edited or damaged",
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
    Ok(Line {
        header,
        description,
        record,
    })
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
    let header = LineHeader {
        format: RUN_LINE_FORMAT,
        key: key.as_str().to_owned(),
        experiment: record.experiment.clone(),
        method: record.method.clone(),
        seed: record.seed,
        trajectories: keep,
        blake3: blake3::hash(&content).to_hex().to_string(),
    };
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
/// verified line is, never the records, so memory does not grow with the runs' size.
#[derive(Debug)]
pub struct RunStore {
    folder: PathBuf,
    index: HashMap<RunKey, Location>,
    appenders: Mutex<HashMap<String, File>>,
}

impl RunStore {
    /// The store of the output folder `out`, opened for resuming and appending: every bundle is
    /// read and checked; a torn last entry (a kill mid-append) is cut off; each bad entry is
    /// passed to `warn` and ignored (its run will be recomputed).
    pub fn open(out: &Path, warn: &mut dyn FnMut(&str)) -> Result<Self, StoreError> {
        Self::open_folder(&out.join("runs"), true, warn)
    }

    /// A store folder opened only to read (as `merge` does): `path` is an output folder (its
    /// `runs/` is read) or a `runs/` folder itself. Nothing is changed on disk.
    pub fn open_read_only(path: &Path, warn: &mut dyn FnMut(&str)) -> Result<Self, StoreError> {
        let runs = path.join("runs");
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
        Self::open_folder(&folder, false, warn)
    }

    fn open_folder(
        folder: &Path,
        repair: bool,
        warn: &mut dyn FnMut(&str),
    ) -> Result<Self, StoreError> {
        let mut index = HashMap::new();
        let mut bundles = Vec::new();
        match std::fs::read_dir(folder) {
            Ok(entries) => {
                for entry in entries {
                    let entry = entry.map_err(|source| StoreError::Read {
                        path: folder.to_path_buf(),
                        source,
                    })?;
                    let path = entry.path();
                    let name = entry.file_name();
                    let name = name.to_string_lossy();
                    if !path.is_file() {
                        continue;
                    }
                    if name.ends_with(&format!(".{BUNDLE_EXTENSION}")) {
                        bundles.push(path);
                    } else if name.ends_with(".jsonl") {
                        // The uncompressed bundle of an earlier version: say why its runs do
                        // not count, instead of silently recomputing or listing them missing.
                        warn(&format!(
                            "{}: an uncompressed bundle written by an earlier version; its runs \
                             are not read (they are recomputed, and the file is removed when \
                             its experiment's outputs are next written)",
                            path.display()
                        ));
                    }
                }
            }
            Err(error) if error.kind() == io::ErrorKind::NotFound => {}
            Err(source) => {
                return Err(StoreError::Read {
                    path: folder.to_path_buf(),
                    source,
                });
            }
        }
        // Sorted, so which of two equal lines is indexed does not depend on directory order.
        bundles.sort();
        for path in bundles {
            index_bundle(&path, repair, &mut index, warn)?;
        }
        Ok(Self {
            folder: folder.to_path_buf(),
            index,
            appenders: Mutex::new(HashMap::new()),
        })
    }

    /// The folder of the bundles.
    pub fn folder(&self) -> &Path {
        &self.folder
    }

    /// The bundle file of experiment `experiment`.
    pub fn bundle_path(&self, experiment: &str) -> PathBuf {
        self.folder.join(format!("{experiment}.{BUNDLE_EXTENSION}"))
    }

    /// Whether run `key` was stored (and verified when the store was opened) keeping at least
    /// the trajectories `keep` asks for.
    pub fn has(&self, key: &RunKey, keep: KeepTrajectories) -> bool {
        self.index
            .get(key)
            .is_some_and(|location| covers(location.trajectories, keep))
    }

    /// How many verified runs the store holds.
    pub fn len(&self) -> usize {
        self.index.len()
    }

    /// Whether the store holds no verified run.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.index.is_empty()
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
        if !covers(location.trajectories, keep) {
            return Ok(None);
        }
        let path: &Path = &location.file;
        let read = |source| StoreError::Read {
            path: path.to_path_buf(),
            source,
        };
        let mut file = File::open(path).map_err(read)?;
        file.seek(SeekFrom::Start(location.offset)).map_err(read)?;
        let mut entry = vec![0; location.len];
        file.read_exact(&mut entry).map_err(read)?;
        let changed = |problem: String| StoreError::Changed {
            path: path.to_path_buf(),
            offset: location.offset,
            problem,
        };
        let (bytes, used) = crate::gzip::decompress_member(&entry)
            .map_err(|e| changed(format!("the entry no longer decompresses: {e}")))?;
        let Some(bytes) = bytes.strip_suffix(b"\n").filter(|_| used == entry.len()) else {
            return Err(changed("the entry is not one whole line".to_owned()));
        };
        let line = parse_line(bytes).map_err(&changed)?;
        if line.header.key != key.as_str() {
            return Err(changed(format!(
                "it holds run {}, not {key}",
                line.header.key
            )));
        }
        let record = serde_json::from_slice::<StoredRecord>(line.record)
            .map_err(|e| changed(format!("record: {e}")))?
            .into_record()
            .map_err(&changed)?;
        Ok(Some(StoredRun {
            description: line.description.to_vec(),
            record: compact(record, keep),
        }))
    }

    /// Appends a finished run to its experiment's bundle (one write, then a sync, so a kill
    /// leaves at most a torn last entry, which the next [`RunStore::open`] cuts off).
    pub fn append(
        &self,
        key: &RunKey,
        description: &RunDescription,
        record: &RunRecord,
        keep: KeepTrajectories,
    ) -> Result<(), StoreError> {
        let description = canonical_json(description).map_err(|e| StoreError::Write {
            path: self.folder.clone(),
            source: io::Error::other(e.to_string()),
        })?;
        let entry = entry_bytes(key, description.as_bytes(), record, keep)?;
        let path = self.bundle_path(&record.experiment);
        let write = |source| StoreError::Write {
            path: path.clone(),
            source,
        };
        let mut appenders = self
            .appenders
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        let file = match appenders.entry(record.experiment.clone()) {
            std::collections::hash_map::Entry::Occupied(entry) => entry.into_mut(),
            std::collections::hash_map::Entry::Vacant(entry) => {
                std::fs::create_dir_all(&self.folder).map_err(write)?;
                let file = OpenOptions::new()
                    .create(true)
                    .append(true)
                    .open(&path)
                    .map_err(write)?;
                entry.insert(file)
            }
        };
        file.write_all(&entry).map_err(write)?;
        // Synced outside the lock, so that runs finishing together do not wait on each other's
        // disk flush.
        let handle = file.try_clone().map_err(write)?;
        drop(appenders);
        handle.sync_data().map_err(write)?;
        Ok(())
    }
}

/// Whether a record stored keeping `stored` holds what `wanted` asks for.
fn covers(stored: KeepTrajectories, wanted: KeepTrajectories) -> bool {
    stored.covers(wanted)
}

/// Reads and checks every entry of the bundle `path` into `index`, one entry in memory at a time.
fn index_bundle(
    path: &Path,
    repair: bool,
    index: &mut HashMap<RunKey, Location>,
    warn: &mut dyn FnMut(&str),
) -> Result<(), StoreError> {
    let read = |source| StoreError::Read {
        path: path.to_path_buf(),
        source,
    };
    let file = Arc::new(path.to_path_buf());
    let mut reader = BufReader::new(File::open(path).map_err(read)?);
    let end = reader.get_ref().metadata().map_err(read)?.len();
    let mut offset = 0_u64;
    let mut line = Vec::new();
    let mut number = 0_usize;
    while offset < end {
        number += 1;
        let next = match read_entry(&mut reader, offset, &mut line) {
            Ok(next) => next,
            Err(problem) => {
                // Damaged or incomplete: go on at the next entry that decompresses whole; none
                // means this is the torn tail of a kill mid-append.
                if let Some(next) = next_entry(&mut reader, offset + 1, &mut line).map_err(read)? {
                    warn(&format!(
                        "{} entry {number} (byte {offset}): damaged ({problem}); ignored, the \
                         run will be recomputed",
                        path.display()
                    ));
                    offset = next;
                    continue;
                }
                if repair {
                    warn(&format!(
                        "{} entry {number} (byte {offset}): incomplete (an interrupted write); \
                         cut off, the run will be recomputed",
                        path.display()
                    ));
                    let file = OpenOptions::new().write(true).open(path).map_err(read)?;
                    file.set_len(offset).map_err(read)?;
                    file.sync_all().map_err(read)?;
                } else {
                    warn(&format!(
                        "{} entry {number} (byte {offset}): incomplete (an interrupted write); \
                         ignored",
                        path.display()
                    ));
                }
                break;
            }
        };
        let checked = match line.strip_suffix(b"\n") {
            Some(text) => parse_line(text),
            None => Err("not one whole line (no newline at its end)".to_owned()),
        };
        match checked {
            Ok(parsed) => {
                let key = RunKey::from_verified_hex(parsed.header.key);
                index.entry(key).or_insert_with(|| Location {
                    file: Arc::clone(&file),
                    offset,
                    len: usize::try_from(next - offset).unwrap_or(usize::MAX),
                    trajectories: parsed.header.trajectories,
                });
            }
            Err(problem) => warn(&format!(
                "{} entry {number} (byte {offset}): {problem}; ignored, the run will be recomputed",
                path.display()
            )),
        }
        offset = next;
    }
    Ok(())
}

/// Decompresses the entry at byte `at` of the bundle into `line`; returns where the next entry
/// starts, or why the entry is damaged or incomplete.
fn read_entry(reader: &mut BufReader<File>, at: u64, line: &mut Vec<u8>) -> Result<u64, String> {
    let io = |e: io::Error| e.to_string();
    if reader.stream_position().map_err(io)? != at {
        reader.seek(SeekFrom::Start(at)).map_err(io)?;
    }
    line.clear();
    // The bufread decoder takes exactly one member's bytes from the reader, so the reader's
    // position afterwards is where the next member starts.
    flate2::bufread::GzDecoder::new(&mut *reader)
        .read_to_end(line)
        .map_err(io)?;
    reader.stream_position().map_err(io)
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
        let mut config = eamadm::paper::task1();
        config.episodes = 3;
        config.seeds = 2;
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
                let description = RunDescription::new(&config, method, seed);
                let key = RunKey::of(&description).unwrap();
                let record = experiment.run(method, seed).unwrap();
                (key, description, record)
            })
            .collect()
    }

    /// A store in `dir` holding `runs`, closed, and the path of their bundle.
    fn stored(dir: &Path, runs: &[(RunKey, RunDescription, RunRecord)]) -> PathBuf {
        let (store, _) = open(dir);
        for (key, description, record) in runs {
            store
                .append(key, description, record, KeepTrajectories::Figures)
                .unwrap();
        }
        store.bundle_path(&runs[0].2.experiment)
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
        // One bundle for the experiment, not one file per run.
        let names: Vec<_> = std::fs::read_dir(dir.path().join("runs"))
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        assert_eq!(names, vec![format!("{}.jsonl.gz", record.experiment)]);
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
    fn a_torn_tail_is_cut_off_and_appending_continues() {
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
        assert_eq!(std::fs::read(&bundle).unwrap(), whole);
        let (key, description, record) = &runs[1];
        store
            .append(key, description, record, KeepTrajectories::Figures)
            .unwrap();
        let (store, warnings) = open(dir.path());
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(store.len(), 2);
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

    #[test]
    fn a_line_under_another_key_or_format_is_refused() {
        let runs = runs();
        let (key, description, record) = &runs[0];
        let description = canonical_json(description).unwrap();
        let line = line_bytes(
            key,
            description.as_bytes(),
            record,
            KeepTrajectories::Figures,
        )
        .unwrap();
        let text = String::from_utf8(line).unwrap();
        let text = text.trim_end();
        assert!(parse_line(text.as_bytes()).is_ok());
        let other_key = text.replacen(key.as_str(), runs[1].0.as_str(), 1);
        let problem = parse_line(other_key.as_bytes()).err().unwrap();
        assert!(problem.contains("not to the key"), "{problem}");
        let old_format = text.replacen("\"format\":2", "\"format\":1", 1);
        let problem = parse_line(old_format.as_bytes()).err().unwrap();
        assert!(problem.contains("format is 1"), "{problem}");
        let problem = parse_line(b"{}").err().unwrap();
        assert!(problem.contains("three"), "{problem}");
    }
}
