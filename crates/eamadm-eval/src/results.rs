//! Results as files: the full record as JSON, and tidy CSV tables (one row per run and
//! episode, or per trajectory step) that a pandas or R user opens directly.

use std::io::{Read, Write};

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::record::{RunRecord, TrajectoryRecord};

/// Writing or reading results failed.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ResultsError {
    /// JSON (de)serialisation or the underlying I/O failed.
    #[error("results JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// CSV writing or the underlying I/O failed.
    #[error("results CSV: {0}")]
    Csv(#[from] csv::Error),
}

/// Writes `records` as one pretty-printed JSON array (the full record: curves, trajectories,
/// evaluations, pre-training).
///
/// # Errors
/// [`ResultsError::Json`] when writing fails.
pub fn write_json<W: Write>(records: &[RunRecord], writer: W) -> Result<(), ResultsError> {
    serde_json::to_writer_pretty(writer, records)?;
    Ok(())
}

/// Reads records written by [`write_json`].
///
/// # Errors
/// [`ResultsError::Json`] for unreadable or malformed input.
pub fn read_json<R: Read>(reader: R) -> Result<Vec<RunRecord>, ResultsError> {
    Ok(serde_json::from_reader(reader)?)
}

/// One row of the curves table: one episode of one run.
///
/// The fields hold the run's values exactly; `curves.csv.gz` writes its real columns at single
/// precision (the shortest text that reads back as the same `f32`, about 7 significant
/// digits; `single`), which keeps the task returns exact (integers below 2²⁴ in
/// the paper's tasks), writes the robot's times as the short decimals they are (`1.2`, not
/// `1.2000000000000002`) and rounds the shaped learning return
/// and the derived robot times, whose last digits are noise and made about 40 % of the robot's
/// `curves.csv.gz` (docs/paper-notes.md §24.1). The run store keeps every value's bits
/// (`eamadm.load_runs`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CurveRow {
    /// The experiment's name.
    pub experiment: String,
    /// The method's label.
    pub method: String,
    /// The run's seed.
    pub seed: u64,
    /// 0-based training episode.
    pub episode: u64,
    /// Steps of the episode.
    pub steps: u64,
    /// Task return of the episode.
    #[serde(serialize_with = "single")]
    pub task_return: f64,
    /// Sum of the learning signal.
    #[serde(serialize_with = "single")]
    pub learning_return: f64,
    /// Ended inside the task.
    pub terminated: bool,
    /// Cut by the step cap.
    pub truncated: bool,
    /// Reached the target.
    pub reached: bool,
    /// Collisions in the episode.
    pub collisions: u64,
    /// Cumulative environment steps of the run, pre-training included.
    pub env_steps: u64,
    /// The optimal route length (BFS for mazes); empty when unknown.
    pub optimum_steps: Option<u64>,
    /// Robot: episode duration in seconds (empty for mazes).
    #[serde(serialize_with = "single_or_empty")]
    pub time: Option<f64>,
    /// Robot: return per second.
    #[serde(serialize_with = "single_or_empty")]
    pub average_reward: Option<f64>,
    /// Robot: time to reach the target (empty when not reached).
    #[serde(serialize_with = "single_or_empty")]
    pub time_to_reach: Option<f64>,
    /// Robot: retention time in seconds.
    #[serde(serialize_with = "single_or_empty")]
    pub retention_time: Option<f64>,
}

/// Writes `value` as the nearest `f32` (its shortest round-trip text): the curves table's
/// precision ([`CurveRow`]).
#[expect(
    clippy::trivially_copy_pass_by_ref,
    reason = "serde passes by reference"
)]
fn single<S: serde::Serializer>(value: &f64, serializer: S) -> Result<S::Ok, S::Error> {
    serializer.serialize_f32(single_precision(*value))
}

/// `value` as the nearest `f32`: the curves table's precision.
#[expect(
    clippy::cast_possible_truncation,
    reason = "single precision is the table's documented precision"
)]
fn single_precision(value: f64) -> f32 {
    value as f32
}

/// [`single`] for an optional value; `None` is an empty cell.
#[expect(clippy::ref_option, reason = "serde passes by reference")]
fn single_or_empty<S: serde::Serializer>(
    value: &Option<f64>,
    serializer: S,
) -> Result<S::Ok, S::Error> {
    match value {
        Some(value) => serializer.serialize_some(&single_precision(*value)),
        None => serializer.serialize_none(),
    }
}

/// The curve rows of one run, episode by episode.
pub fn curve_rows(record: &RunRecord) -> impl Iterator<Item = CurveRow> + '_ {
    record.episodes.iter().map(move |episode| CurveRow {
        experiment: record.experiment.clone(),
        method: record.method.clone(),
        seed: record.seed,
        episode: episode.episode,
        steps: episode.steps,
        task_return: episode.task_return,
        learning_return: episode.learning_return,
        terminated: episode.terminated,
        truncated: episode.truncated,
        reached: episode.reached,
        collisions: episode.collisions,
        env_steps: episode.env_steps,
        optimum_steps: record.optimum_steps,
        time: episode.robot.map(|r| r.time),
        average_reward: episode.robot.map(|r| r.average_reward),
        time_to_reach: episode.robot.and_then(|r| r.time_to_reach),
        retention_time: episode.robot.map(|r| r.retention_time),
    })
}

/// Writes the curves of `records` as CSV with a header: one row per (run, episode), columns
/// as in [`CurveRow`] (empty cells for missing values).
///
/// # Errors
/// [`ResultsError::Csv`] when writing fails.
pub fn write_curves_csv<W: Write>(records: &[RunRecord], writer: W) -> Result<(), ResultsError> {
    let mut csv = CurvesCsv::new(writer);
    for record in records {
        csv.push(record)?;
    }
    csv.finish()
}

/// The curves table written run by run, so that a caller streaming records (one at a time from
/// a run store) never holds them all; the bytes equal [`write_curves_csv`]'s over the same runs.
///
/// The bytes are those of `csv`'s serde writer over each run's [`curve_rows`] (a header, then
/// `itoa` integers, `ryu` singles, `true`/`false`, empty cells for `None`, labels quoted
/// where `csv` quotes them; the law `the_curves_table_is_the_curve_rows_serialised`), written
/// without the serde calls and `csv`'s quoting check per cell: a run's labels and seed are
/// quoted once, as its rows' common start, and the numbers need no quotes. A thousand-seed
/// table is 200,000 rows (docs/paper-notes.md §24.3).
pub struct CurvesCsv<W: Write> {
    writer: W,
    /// Rows not yet handed to `writer` (handed on in pieces of about [`Self::PIECE`] bytes).
    pending: Vec<u8>,
    wrote_header: bool,
}

impl<W: Write> CurvesCsv<W> {
    /// About how many bytes are handed to the writer at a time.
    const PIECE: usize = 1 << 16;

    /// A table writing to `writer`; nothing is written before the first run or [`Self::finish`].
    pub fn new(writer: W) -> Self {
        Self {
            writer,
            pending: Vec::with_capacity(Self::PIECE + 4096),
            wrote_header: false,
        }
    }

    fn header(&mut self) {
        if !self.wrote_header {
            self.pending
                .extend_from_slice(CURVE_COLUMNS.join(",").as_bytes());
            self.pending.push(b'\n');
            self.wrote_header = true;
        }
    }

    /// Appends the rows of one run, episode by episode.
    ///
    /// # Errors
    /// [`ResultsError::Csv`] when writing fails.
    pub fn push(&mut self, record: &RunRecord) -> Result<(), ResultsError> {
        if record.episodes.is_empty() {
            return Ok(());
        }
        self.header();
        let start = row_start(record)?;
        let (mut integer, mut real) = (itoa::Buffer::new(), ryu::Buffer::new());
        for episode in &record.episodes {
            let row = &mut self.pending;
            row.extend_from_slice(&start);
            for value in [episode.episode, episode.steps] {
                row.extend_from_slice(integer.format(value).as_bytes());
                row.push(b',');
            }
            for value in [episode.task_return, episode.learning_return] {
                row.extend_from_slice(real.format(single_precision(value)).as_bytes());
                row.push(b',');
            }
            for flag in [episode.terminated, episode.truncated, episode.reached] {
                row.extend_from_slice(if flag { b"true," } else { b"false," });
            }
            for value in [episode.collisions, episode.env_steps] {
                row.extend_from_slice(integer.format(value).as_bytes());
                row.push(b',');
            }
            if let Some(optimum) = record.optimum_steps {
                row.extend_from_slice(integer.format(optimum).as_bytes());
            }
            let robot = episode.robot;
            for value in [
                robot.map(|r| r.time),
                robot.map(|r| r.average_reward),
                robot.and_then(|r| r.time_to_reach),
                robot.map(|r| r.retention_time),
            ] {
                row.push(b',');
                if let Some(value) = value {
                    row.extend_from_slice(real.format(single_precision(value)).as_bytes());
                }
            }
            row.push(b'\n');
            if self.pending.len() >= Self::PIECE {
                self.writer
                    .write_all(&self.pending)
                    .map_err(csv::Error::from)?;
                self.pending.clear();
            }
        }
        Ok(())
    }

    /// Ends the table (a header alone when no run had an episode, so the file opens as an empty
    /// table) and flushes it.
    ///
    /// # Errors
    /// [`ResultsError::Csv`] when writing fails.
    pub fn finish(mut self) -> Result<(), ResultsError> {
        self.header();
        self.writer
            .write_all(&self.pending)
            .and_then(|()| self.writer.flush())
            .map_err(csv::Error::from)?;
        Ok(())
    }
}

/// The start every row of `record` shares: its experiment and method as `csv` writes them
/// (quoted when they hold a comma, a quote or a line break) and its seed, each with its comma.
fn row_start(record: &RunRecord) -> Result<Vec<u8>, ResultsError> {
    let mut start = csv::Writer::from_writer(Vec::new());
    start.write_field(&record.experiment)?;
    start.write_field(&record.method)?;
    start.write_field(itoa::Buffer::new().format(record.seed))?;
    // An empty last field: the record's bytes end with the comma before it.
    start.write_field("")?;
    // Not ended: the bytes stop at the comma before that field.
    start
        .into_inner()
        .map_err(|error| csv::Error::from(error.into_error()).into())
}

/// The column names of the curves table, in order.
pub const CURVE_COLUMNS: [&str; 17] = [
    "experiment",
    "method",
    "seed",
    "episode",
    "steps",
    "task_return",
    "learning_return",
    "terminated",
    "truncated",
    "reached",
    "collisions",
    "env_steps",
    "optimum_steps",
    "time",
    "average_reward",
    "time_to_reach",
    "retention_time",
];

/// One row of the trajectories table: one step (state) of a kept trajectory.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrajectoryRow {
    /// The experiment's name.
    pub experiment: String,
    /// The method's label.
    pub method: String,
    /// The run's seed.
    pub seed: u64,
    /// The episode (for the evaluation: the number of training episodes).
    pub episode: u64,
    /// `true` for the greedy evaluation episode.
    pub greedy: bool,
    /// Time step within the episode (0 = the initial state).
    pub t: u64,
    /// The state at time `t`.
    pub state: usize,
    /// The action taken at time `t` (empty for the last state).
    pub action: Option<usize>,
    /// Position: tile column (maze) or metres (robot).
    pub x: f64,
    /// Position: tile row from the top (maze) or metres (robot).
    pub y: f64,
}

/// Writes every kept trajectory of `records` (training episodes, then the evaluation, run by
/// run) as CSV with a header, one row per visited state.
///
/// # Errors
/// [`ResultsError::Csv`] when writing fails.
pub fn write_trajectories_csv<W: Write>(
    records: &[RunRecord],
    writer: W,
) -> Result<(), ResultsError> {
    let mut csv = TrajectoriesCsv::new(writer);
    for record in records {
        csv.push(record)?;
    }
    csv.finish()
}

/// The column names of the trajectories table, in order.
pub const TRAJECTORY_COLUMNS: [&str; 10] = [
    "experiment",
    "method",
    "seed",
    "episode",
    "greedy",
    "t",
    "state",
    "action",
    "x",
    "y",
];

/// The trajectories table written run by run (see [`CurvesCsv`]); the bytes equal
/// [`write_trajectories_csv`]'s over the same runs.
pub struct TrajectoriesCsv<W: Write> {
    csv: csv::Writer<W>,
    wrote_rows: bool,
}

impl<W: Write> TrajectoriesCsv<W> {
    /// A table writing to `writer`; nothing is written before the first run or [`Self::finish`].
    pub fn new(writer: W) -> Self {
        Self {
            csv: csv::Writer::from_writer(writer),
            wrote_rows: false,
        }
    }

    /// Appends the rows of one run: its kept training trajectories, then its evaluation.
    ///
    /// # Errors
    /// [`ResultsError::Csv`] when writing fails.
    pub fn push(&mut self, record: &RunRecord) -> Result<(), ResultsError> {
        let all = record
            .trajectories
            .iter()
            .chain(std::iter::once(&record.evaluation_trajectory));
        for trajectory in all {
            for row in trajectory_rows(record, trajectory) {
                self.csv.serialize(row)?;
                self.wrote_rows = true;
            }
        }
        Ok(())
    }

    /// Ends the table (a header alone when no run had a trajectory) and flushes it.
    ///
    /// # Errors
    /// [`ResultsError::Csv`] when writing fails.
    pub fn finish(mut self) -> Result<(), ResultsError> {
        if !self.wrote_rows {
            self.csv.write_record(TRAJECTORY_COLUMNS)?;
        }
        self.csv.flush().map_err(csv::Error::from)?;
        Ok(())
    }
}

fn trajectory_rows<'a>(
    record: &'a RunRecord,
    trajectory: &'a TrajectoryRecord,
) -> impl Iterator<Item = TrajectoryRow> + 'a {
    trajectory
        .states
        .iter()
        .enumerate()
        .map(move |(t, &state)| {
            let [x, y] = trajectory
                .positions
                .get(t)
                .copied()
                .unwrap_or([f64::NAN; 2]);
            TrajectoryRow {
                experiment: record.experiment.clone(),
                method: record.method.clone(),
                seed: record.seed,
                episode: trajectory.episode,
                greedy: trajectory.greedy,
                t: t as u64,
                state,
                action: trajectory.actions.get(t).copied(),
                x,
                y,
            }
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::{EpisodeRecord, RobotEpisodeMetrics};

    fn episode(episode: u64, robot: Option<RobotEpisodeMetrics>) -> EpisodeRecord {
        EpisodeRecord {
            episode,
            steps: 10 + episode,
            task_return: -1.5,
            learning_return: 0.25,
            terminated: true,
            truncated: false,
            reached: true,
            collisions: 1,
            env_steps: 100 + episode,
            robot,
        }
    }

    fn record() -> RunRecord {
        let trajectory = TrajectoryRecord {
            episode: 2,
            greedy: true,
            states: vec![0, 1],
            actions: vec![3],
            positions: vec![[0.0, 0.0], [1.0, 0.0]],
        };
        RunRecord {
            experiment: "small".to_owned(),
            method: "ea-madm".to_owned(),
            seed: 7,
            optimum_steps: Some(9),
            subtasks: Vec::new(),
            pretrain_env_steps: 80,
            episodes: vec![
                episode(0, None),
                episode(
                    1,
                    Some(RobotEpisodeMetrics {
                        time: 2.0,
                        average_reward: 0.5,
                        time_to_reach: None,
                        retention_time: 0.4,
                    }),
                ),
            ],
            total_env_steps: 101,
            trajectories: Vec::new(),
            greedy_evaluations: Vec::new(),
            evaluation: episode(2, None),
            evaluation_trajectory: trajectory,
            final_window_episodes: 2,
            final_window_actions: vec![3, 0, 1, 7],
            agreement: Some(crate::record::AgreementRecord {
                final_window: crate::record::AgreementCounts {
                    decisions: 9,
                    agrees: vec![8, 2],
                    agrees_with_all: 2,
                    missing_experience: 1,
                },
                training: crate::record::AgreementCounts {
                    decisions: 20,
                    agrees: vec![15, 4],
                    agrees_with_all: 3,
                    missing_experience: 5,
                },
            }),
        }
    }

    #[test]
    fn curves_csv_has_a_header_and_one_row_per_episode() {
        let mut out = Vec::new();
        write_curves_csv(&[record()], &mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], CURVE_COLUMNS.join(","));
        assert_eq!(
            lines[1],
            "small,ea-madm,7,0,10,-1.5,0.25,true,false,true,1,100,9,,,,"
        );
        assert_eq!(
            lines[2],
            "small,ea-madm,7,1,11,-1.5,0.25,true,false,true,1,101,9,2.0,0.5,,0.4"
        );
        assert_eq!(lines.len(), 3);

        let mut empty = Vec::new();
        write_curves_csv(&[], &mut empty).unwrap();
        assert_eq!(
            String::from_utf8(empty).unwrap().trim_end(),
            CURVE_COLUMNS.join(",")
        );
    }

    #[test]
    fn curve_reals_are_written_at_single_precision_and_read_back_as_the_same_f32() {
        let mut record = record();
        record.episodes.truncate(1);
        let episode = &mut record.episodes[0];
        episode.task_return = -26_461.0;
        episode.learning_return = 2.388_184_499_385_979_5;
        episode.robot = Some(RobotEpisodeMetrics {
            time: 3.0 * 0.4,
            average_reward: -8.333_333_333_333_332,
            time_to_reach: Some(0.1 + 0.2),
            retention_time: 0.8,
        });
        let mut out = Vec::new();
        write_curves_csv(&[record.clone()], &mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        let row = text.lines().nth(1).unwrap();
        assert_eq!(
            row,
            "small,ea-madm,7,0,10,-26461.0,2.3881845,true,false,true,1,100,9,1.2,-8.333333,0.3,0.8"
        );
        let cells: Vec<&str> = row.split(',').collect();
        let episode = &record.episodes[0];
        let robot = episode.robot.unwrap();
        for (cell, value) in [
            (cells[5], episode.task_return),
            (cells[6], episode.learning_return),
            (cells[13], robot.time),
            (cells[14], robot.average_reward),
            (cells[15], robot.time_to_reach.unwrap()),
            (cells[16], robot.retention_time),
        ] {
            let read: f32 = cell.parse().unwrap();
            assert_eq!(
                read.to_bits(),
                (value as f32).to_bits(),
                "{cell} against {value}"
            );
        }
    }

    #[test]
    fn trajectories_csv_lists_every_state() {
        let mut out = Vec::new();
        write_trajectories_csv(&[record()], &mut out).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "experiment,method,seed,episode,greedy,t,state,action,x,y\n\
             small,ea-madm,7,2,true,0,0,3,0.0,0.0\n\
             small,ea-madm,7,2,true,1,1,,1.0,0.0\n"
        );
    }

    proptest::proptest! {
        /// The law of `CurvesCsv::push`: the bytes of `csv`'s serde writer over
        /// `curve_rows`, whatever the values (non-finite, huge, tiny) and labels (commas,
        /// quotes, line breaks).
        #[test]
        fn the_curves_table_is_the_curve_rows_serialised(
            label in "[a-z,\"\n ]{0,6}",
            optimum in proptest::option::of(proptest::num::u64::ANY),
            bits in proptest::collection::vec(proptest::num::u64::ANY, 6),
            counts in proptest::collection::vec(proptest::num::u64::ANY, 4),
            flags in proptest::collection::vec(proptest::bool::ANY, 4),
        ) {
            let mut record = record();
            record.method = label;
            record.optimum_steps = optimum;
            let real = |i: usize| f64::from_bits(bits[i]);
            let episode = &mut record.episodes[1];
            (episode.task_return, episode.learning_return) = (real(0), real(1));
            (episode.steps, episode.collisions, episode.env_steps, episode.episode) =
                (counts[0], counts[1], counts[2], counts[3]);
            (episode.terminated, episode.truncated, episode.reached) = (flags[0], flags[1], flags[2]);
            episode.robot = Some(RobotEpisodeMetrics {
                time: real(2),
                average_reward: real(3),
                time_to_reach: flags[3].then(|| real(4)),
                retention_time: real(5),
            });
            let mut pushed = Vec::new();
            write_curves_csv(std::slice::from_ref(&record), &mut pushed).unwrap();
            let mut serialised = csv::Writer::from_writer(Vec::new());
            for row in curve_rows(&record) {
                serialised.serialize(row).unwrap();
            }
            proptest::prop_assert_eq!(pushed, serialised.into_inner().unwrap());
        }
    }

    #[test]
    fn streaming_tables_equal_the_whole_table_writers() {
        let mut second = record();
        second.seed = 8;
        second.evaluation_trajectory.states.clear();
        let records = vec![record(), second];
        let mut whole = Vec::new();
        write_curves_csv(&records, &mut whole).unwrap();
        let mut streamed = Vec::new();
        let mut csv = CurvesCsv::new(&mut streamed);
        for record in &records {
            csv.push(record).unwrap();
        }
        csv.finish().unwrap();
        assert_eq!(streamed, whole);

        let mut whole = Vec::new();
        write_trajectories_csv(&records, &mut whole).unwrap();
        let mut streamed = Vec::new();
        let mut csv = TrajectoriesCsv::new(&mut streamed);
        for record in &records {
            csv.push(record).unwrap();
        }
        csv.finish().unwrap();
        assert_eq!(streamed, whole);

        let mut empty = Vec::new();
        TrajectoriesCsv::new(&mut empty).finish().unwrap();
        assert_eq!(
            String::from_utf8(empty).unwrap().trim_end(),
            TRAJECTORY_COLUMNS.join(",")
        );
    }

    #[test]
    fn json_round_trips() {
        let records = vec![record()];
        let mut out = Vec::new();
        write_json(&records, &mut out).unwrap();
        assert_eq!(read_json(out.as_slice()).unwrap(), records);
        assert!(read_json(&b"[{\"experiment\": 1}]"[..]).is_err());
    }
}
