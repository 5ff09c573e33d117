//! `REPORT.md` from Python, made by the text the main job writes (`eamadm_present::report`), never
//! re-derived here: for an output folder, from its `final-scores.csv` and `report-context.toml`
//! (the report's context, figures and robot behaviour included, as the main job wrote it); for
//! runs of [`run_config`](crate::experiment::run_config), from the scores and facts computed
//! beside them ([`report_input`]), with the figures drawn of the same runs.
//!
//! A report of runs does not open with the main job's "Made by `cargo xtask reproduce-paper`
//! … rerun the command" (no such command made it): its opening paragraph is the caller's
//! ([`PYTHON_OPENING`] by default). A folder's report keeps its own opening.

use std::path::{Path, PathBuf};

use eamadm::eamadm_eval::family::{FamilyFindings, FamilyVerdicts};
use eamadm::facts::{ExperimentFacts, ReportContext};
use eamadm::output_names::{FAMILY, FINAL_SCORES, LAYOUTS, REPORT, REPORT_CONTEXT, SENSITIVITY};
use eamadm::scores::FinalScore;
use eamadm::verdicts::Verdicts;
use eamadm::{Experiment, RunRecord};
use pyo3::prelude::*;

use crate::error::{guard, not_found, value_error};

/// The opening paragraph of a report of runs made in Python: what made it and where its
/// tables are.
const PYTHON_OPENING: &str = "Made by `eamadm.report` from runs of `eamadm.run` in Python{quick}. The per-seed \
     scores are its `scores_csv` (the columns of `final-scores.csv`), every estimate and \
     comparison its `claims_csv` (those of `claims.csv`).";

/// The opening paragraph of `python -m eamadm reproduce`'s report.
const CLI_OPENING: &str = "Made by `python -m eamadm reproduce`{quick}. Do not edit: rerun the command. The \
     per-seed scores are in [final-scores.csv](final-scores.csv), every estimate and comparison \
     in [claims.csv](claims.csv).";

/// What the main job's report says of a `--quick` run, after the command.
const QUICK_NOTE: &str =
    " --quick (a smoke run: few seeds and episodes; these numbers mean little)";

/// An experiment's facts (TOML) and its runs' `final-scores.csv` rows.
pub(crate) type ReportInput = (String, String);

/// What a report needs of one experiment's runs, as text Python carries opaquely: the
/// experiment's facts (TOML) and its runs' `final-scores.csv` rows, both made by
/// [`Experiment::report_facts`], the main job's own builder (the robot's reward diagnosis
/// included); and the figures of the runs, drawn by the main job's code, as `[(path, SVG
/// text)]` (paths `<experiment>/<file>.svg`, which the facts' figures and the report name).
pub(crate) fn report_input(
    experiment: &Experiment,
    records: &[RunRecord],
) -> PyResult<(ReportInput, Vec<(String, String)>)> {
    let (mut facts, scores) = experiment
        .report_facts(records)
        .map_err(|error| value_error("config", error))?;
    let drawing = crate::figures::draw(&facts, experiment.task(), records, "config")?;
    facts.figures = drawing.figures;
    let files = drawing
        .files
        .into_iter()
        .map(|(file, svg)| (format!("{}/{file}", facts.name), svg))
        .collect();
    let mut scores_csv = Vec::new();
    eamadm::scores::write_csv(&scores, &mut scores_csv)
        .map_err(|error| value_error("config", error))?;
    let facts = toml::to_string(&facts).map_err(|error| value_error("config", error))?;
    let scores_csv = String::from_utf8(scores_csv).map_err(|error| value_error("config", error))?;
    Ok(((facts, scores_csv), files))
}

/// The text of `folder/name`; a `ValueError` naming `dir` and the file when it cannot be read.
fn read(folder: &Path, name: &str, hint: &str) -> PyResult<String> {
    let path = folder.join(name);
    std::fs::read_to_string(&path).map_err(|error| {
        value_error(
            "dir",
            format!("cannot read {}: {error}{hint}", path.display()),
        )
    })
}

/// `(REPORT.md, claims.csv, final-scores.csv)` of the output folder `folder`: the verdicts
/// judged again from its `final-scores.csv` and rendered with its `report-context.toml`, so
/// the text is the folder's own `REPORT.md` byte for byte when both were written by the same
/// version.
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "pyo3 hands extracted arguments over by value"
)]
pub(crate) fn report_of_folder(folder: PathBuf) -> PyResult<(String, String, String)> {
    guard("dir", || folder_report(&folder))
}

fn folder_report(folder: &Path) -> PyResult<(String, String, String)> {
    if !folder.exists() {
        return Err(not_found(
            "dir",
            format!("{} does not exist", folder.display()),
        ));
    }
    if !folder.is_dir() {
        return Err(value_error(
            "dir",
            format!("{} is not a folder", folder.display()),
        ));
    }
    if !folder.join(REPORT).is_file() && !folder.join(FINAL_SCORES).is_file() {
        return Err(value_error(
            "dir",
            format!(
                "{} holds no {REPORT} or {FINAL_SCORES}: give the output folder of \
                 `cargo xtask reproduce-paper` (its --out)",
                folder.display()
            ),
        ));
    }
    let scores_csv = read(folder, FINAL_SCORES, "")?;
    let context_text = read(
        folder,
        REPORT_CONTEXT,
        "; an older version wrote this folder: rerun `cargo xtask reproduce-paper` \
         (finished runs are reused)",
    )?;
    let context = eamadm::paper::report_context_from_toml(&context_text).map_err(|error| {
        value_error(
            "dir",
            format!("{REPORT_CONTEXT} of {}: {error}", folder.display()),
        )
    })?;
    let scores = eamadm::scores::read_csv(scores_csv.as_bytes()).map_err(|error| {
        value_error(
            "dir",
            format!("{FINAL_SCORES} of {}: {error}", folder.display()),
        )
    })?;
    // The readings' rows are not in final-scores.csv: read them back from their own table
    // (a folder of a plan without readings has only its header, or none before it existed).
    let sensitivity = match std::fs::read_to_string(folder.join(SENSITIVITY)) {
        Ok(text) => eamadm::sensitivity::read_csv(text.as_bytes()).map_err(|error| {
            value_error(
                "dir",
                format!("{SENSITIVITY} of {}: {error}", folder.display()),
            )
        })?,
        Err(error) if error.kind() == std::io::ErrorKind::NotFound => Vec::new(),
        Err(error) => {
            return Err(value_error(
                "dir",
                format!(
                    "cannot read {}: {error}",
                    folder.join(SENSITIVITY).display()
                ),
            ));
        }
    };
    let family = family_of_folder(folder)?.and_then(|(_, findings)| findings);
    let (report, claims, scores) = render(
        &context,
        scores,
        sensitivity,
        family,
        &format!("dir {}", folder.display()),
    )?;
    // A folder `python -m eamadm reproduce` made says so, as its own REPORT.md does.
    let own = std::fs::read_to_string(folder.join(REPORT)).unwrap_or_default();
    let report = match opening_of(&own) {
        Some(opening) if opening.starts_with("Made by `python -m eamadm reproduce`") => {
            with_opening(&report, opening)?
        }
        _ => report,
    };
    Ok((report, claims, scores))
}

/// `(REPORT.md, claims.csv, final-scores.csv, report-context.toml)` of runs: `inputs` holds
/// one [`report_input`] per experiment (in report order); `quick` marks the report as a smoke
/// run; `cli` opens it as `python -m eamadm reproduce`'s (else as `eamadm.report`'s).
#[pyfunction]
#[expect(
    clippy::needless_pass_by_value,
    reason = "pyo3 hands extracted arguments over by value"
)]
#[pyo3(signature = (inputs, quick, cli=false))]
pub(crate) fn report_of_runs(
    inputs: Vec<(String, String)>,
    quick: bool,
    cli: bool,
) -> PyResult<(String, String, String, String)> {
    guard("results", || runs_report(&inputs, quick, cli))
}

fn runs_report(
    inputs: &[(String, String)],
    quick: bool,
    cli: bool,
) -> PyResult<(String, String, String, String)> {
    if inputs.is_empty() {
        return Err(value_error(
            "results",
            "expected the results of at least one run",
        ));
    }
    let mut context = eamadm::paper::report_context(quick);
    let mut scores = Vec::new();
    for (facts, scores_csv) in inputs {
        let facts: ExperimentFacts =
            toml::from_str(facts).map_err(|error| value_error("results", error))?;
        if context.experiments.iter().any(|e| e.name == facts.name) {
            return Err(value_error(
                "results",
                format!(
                    "two results of the experiment {:?}: run its methods and seeds in one \
                     `eamadm.run` call",
                    facts.name
                ),
            ));
        }
        context.experiments.push(facts);
        scores.extend(
            eamadm::scores::read_csv(scores_csv.as_bytes())
                .map_err(|error| value_error("results", error))?,
        );
    }
    let (report, claims, scores) = render(&context, scores, Vec::new(), None, "results")?;
    let opening = if cli { CLI_OPENING } else { PYTHON_OPENING }
        .replace("{quick}", if quick { QUICK_NOTE } else { "" });
    let context = eamadm::paper::report_context_toml(&context)
        .map_err(|error| value_error("results", error))?;
    Ok((with_opening(&report, &opening)?, claims, scores, context))
}

/// The opening paragraph of a report: the one after its title.
fn opening_of(report: &str) -> Option<&str> {
    let (_, rest) = report.split_once("\n\n")?;
    let (opening, _) = rest.split_once("\n\n")?;
    opening.starts_with("Made by ").then_some(opening)
}

/// `report` with its opening paragraph replaced by `opening`.
fn with_opening(report: &str, opening: &str) -> PyResult<String> {
    let old = opening_of(report).ok_or_else(|| {
        crate::error::internal_error(
            "report",
            &"the rendered report has no opening paragraph after its title",
        )
    })?;
    Ok(report.replacen(old, opening, 1))
}

/// The maze family of the output folder `folder` (`--suite family`), judged again from its
/// `family/final-scores.csv` and `layouts.csv` as the main job judges it
/// (`eamadm::family::judge_family`); `None` when the folder has no family.
pub(crate) fn family_of_folder(
    folder: &Path,
) -> PyResult<Option<(FamilyVerdicts, Option<FamilyFindings>)>> {
    let scores_path = folder.join(FAMILY).join(FINAL_SCORES);
    if !scores_path.is_file() {
        return Ok(None);
    }
    let error = |file: &Path, error: &dyn std::fmt::Display| {
        value_error("dir", format!("{}: {error}", file.display()))
    };
    let scores = std::fs::read(&scores_path).map_err(|e| error(&scores_path, &e))?;
    let scores =
        eamadm::scores::read_csv(scores.as_slice()).map_err(|e| error(&scores_path, &e))?;
    let layouts_path = folder.join(LAYOUTS);
    let layouts = std::fs::read(&layouts_path).map_err(|e| error(&layouts_path, &e))?;
    let layouts = eamadm::family::read_layouts_csv(layouts.as_slice())
        .map_err(|e| error(&layouts_path, &e))?;
    eamadm::family::judge_family(&scores, &layouts)
        .map(Some)
        .map_err(|e| error(&scores_path, &e))
}

/// The report, `claims.csv` and `final-scores.csv` of `scores` in `context`, as the main job
/// writes them (the verdicts judged with the context's margins, as the main job's), with the
/// maze family's findings when it ran.
fn render(
    context: &ReportContext,
    scores: Vec<FinalScore>,
    sensitivity: Vec<eamadm::sensitivity::SensitivityRow>,
    family: Option<FamilyFindings>,
    argument: &str,
) -> PyResult<(String, String, String)> {
    let error = |error: &dyn std::fmt::Display| value_error(argument, error);
    let options = context.claim_options().map_err(|e| error(&e))?;
    let verdicts = Verdicts::compute(scores, &options, context)
        .map_err(|e| error(&e))?
        .with_sensitivity(sensitivity);
    let findings = eamadm::findings::Findings::of(context, &verdicts).with_family(family);
    let report = eamadm_present::report::render(context, &verdicts, &findings);
    let claims = verdicts.claims_csv().map_err(|e| error(&e))?;
    let scores = verdicts.scores_csv().map_err(|e| error(&e))?;
    Ok((report, claims, scores))
}
