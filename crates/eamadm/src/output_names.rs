//! The names of every file and folder the reproduction tooling writes into an output folder,
//! in one place: the run store crate `eamadm-runs` re-exports this module as its `names`, and
//! [`crate::RESERVED_NAMES`] is derived from [`TOP_LEVEL`], so an experiment can never be named
//! like one of them.
//!
//! They live here, in the facade, because the run store depends on `eamadm` (for the records it
//! stores), so `eamadm` cannot depend on it: the names go where both can see them.

/// The run store folder, `<out>/runs/`.
pub const RUNS_FOLDER: &str = "runs";
/// The ending of a run store bundle, `runs/<experiment>.jsonl.zst` (JSON lines in Zstandard
/// frames).
pub const BUNDLE_EXTENSION: &str = "jsonl.zst";
/// The ending of the bundles of earlier versions, `runs/<experiment>.jsonl.gz` (one gzip member
/// per line): still read, and replaced by the next pack.
pub const LEGACY_BUNDLE_EXTENSION: &str = "jsonl.gz";
/// Inside [`RUNS_FOLDER`], the folder of runs stored one file each before they are packed into
/// their bundles.
pub const LOOSE_RUNS: &str = "loose";
/// The ending of a single run file, `runs/loose/<key>.<trajectories>.run.gz`.
pub const RUN_FILE_EXTENSION: &str = "run.gz";
/// Inside [`RUNS_FOLDER`], where earlier versions kept the pre-trained sub-task learners (now in
/// a cache outside the output folder, `--pretrained-cache`): read by `merge` and moved into the
/// cache by `gc`.
pub const PRETRAINED: &str = "pretrained";
/// The ending of a pre-trained artefact, `<cache>/<key>.subtask.gz`.
pub const PRETRAINED_EXTENSION: &str = "subtask.gz";
/// The report.
pub const REPORT: &str = "REPORT.md";
/// One row per task, method and seed.
pub const FINAL_SCORES: &str = "final-scores.csv";
/// The verdicts on the paper's claims.
pub const CLAIMS: &str = "claims.csv";
/// The Frictionless Data Package beside [`FINAL_SCORES`] and [`CLAIMS`]: every column's type,
/// unit and meaning ([`crate::data_package`]).
pub const DATA_PACKAGE: &str = "datapackage.json";
/// The verdicts judged again under other readings of the paper (`eamadm::paper::readings`):
/// one row per claim × task × reading, holds or flips.
pub const SENSITIVITY: &str = "sensitivity.csv";
/// What `REPORT.md` was rendered from beyond `final-scores.csv` (the run's
/// `eamadm_eval::facts::ReportContext` as TOML, whose floats read back exactly: tasks, experiments, figures with their
/// captions, the robot's behaviour), so the report can be rendered again from the folder
/// alone, byte for byte (the Python package's `eamadm.report(dir)` does).
pub const REPORT_CONTEXT: &str = "report-context.toml";
/// What `REPORT.md` states, as data (`eamadm_eval::findings::Findings` as JSON): per task the
/// verdicts with their deciding comparisons, the strongest controls, collapses,
/// re-judgements, equalities and the diagnosis; the README's generated blocks are rendered
/// from it.
pub const FINDINGS: &str = "findings.json";
/// Every trial of `--suite tuning` with its values, score and whether it was chosen
/// (`crate::tuning::TuningRow`).
pub const TUNING: &str = "tuning.csv";
/// Every record in one JSON file, written by earlier versions (removed when found).
pub const LEGACY_RESULTS: &str = "results.json";
/// Each experiment's per-episode table, `<out>/<experiment>/curves.csv.gz`.
pub const CURVES: &str = "curves.csv.gz";
/// Each experiment's evaluation paths, `<out>/<experiment>/trajectories.csv.gz` (gzip, as the
/// curves: the paths of a policy looping to the step cap compress about twentyfold).
pub const TRAJECTORIES: &str = "trajectories.csv.gz";
/// The output folder's lock file.
pub const LOCK_FILE: &str = ".reproduce-paper.lock";
/// Where a set of outputs is written before it is committed.
pub const STAGING: &str = ".staging";
/// A complete set of outputs whose swap into the folder has begun.
pub const COMMITTED: &str = ".committed";
/// The manifest of the current set of outputs.
pub const MANIFEST: &str = ".outputs";
/// Where run files that failed their checks are set aside (inside [`RUNS_FOLDER`]), never
/// deleted.
pub const SET_ASIDE: &str = ".set-aside";

/// `oracle.csv`: the decision step on exact (maze) or converged (robot) sub-task values
/// ([`crate::oracle`]).
pub const ORACLE: &str = "oracle.csv";
/// `pretraining.csv`: each sub-task's pre-training per run ([`crate::oracle::PretrainingRow`]).
pub const PRETRAINING: &str = "pretraining.csv";
/// The maze layouts the run's rows play (`eamadm::family::LAYOUT_COLUMNS`): the paper's two,
/// the positive control's, the family's.
pub const LAYOUTS: &str = "layouts.csv";
/// The folder of the maze family's outputs (`--suite family`): its runs' final scores, pooled
/// verdicts, per-layout effects, figures and report. Not in [`TOP_LEVEL`]: the output folder
/// keeps it as an experiment's folder (a safe slug), which a reserved name could not be.
pub const FAMILY: &str = "family";

/// The visible entries the tooling keeps at the top of an output folder, beside the
/// experiments' folders. (Its bookkeeping entries are hidden names, which no experiment name
/// can take.)
pub const TOP_LEVEL: [&str; 13] = [
    RUNS_FOLDER,
    LEGACY_RESULTS,
    REPORT,
    FINAL_SCORES,
    CLAIMS,
    DATA_PACKAGE,
    SENSITIVITY,
    REPORT_CONTEXT,
    FINDINGS,
    ORACLE,
    PRETRAINING,
    LAYOUTS,
    TUNING,
];

/// The device names Windows reserves: a file or folder of that name cannot be made there.
pub const WINDOWS_DEVICES: [&str; 22] = [
    "con", "prn", "aux", "nul", "com1", "com2", "com3", "com4", "com5", "com6", "com7", "com8",
    "com9", "lpt1", "lpt2", "lpt3", "lpt4", "lpt5", "lpt6", "lpt7", "lpt8", "lpt9",
];

/// [`TOP_LEVEL`] followed by [`WINDOWS_DEVICES`].
pub(crate) const RESERVED: [&str; TOP_LEVEL.len() + WINDOWS_DEVICES.len()] = {
    let mut all = [""; TOP_LEVEL.len() + WINDOWS_DEVICES.len()];
    let mut i = 0;
    while i < TOP_LEVEL.len() {
        all[i] = TOP_LEVEL[i];
        i += 1;
    }
    let mut j = 0;
    while j < WINDOWS_DEVICES.len() {
        all[TOP_LEVEL.len() + j] = WINDOWS_DEVICES[j];
        j += 1;
    }
    all
};
