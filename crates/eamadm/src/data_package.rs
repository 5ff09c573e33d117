//! `datapackage.json`: the [Frictionless Data Package](https://specs.frictionlessdata.io/data-package/)
//! that the main job writes beside `final-scores.csv` and `claims.csv`, so that every column
//! carries its type, unit, meaning and when it is blank ([`columns`](mod@crate::columns)), and
//! `frictionless`, pandas or R can load the tables typed. The columns are documented once, in
//! `eamadm-eval` next to the code that writes them ([`scores::COLUMNS`], [`claims::CLAIM_COLUMNS`]);
//! this module names the files ([`output_names`](crate::output_names)) and composes the package.
//!
//! ```
//! let package = eamadm::data_package::data_package();
//! assert_eq!(package["resources"][0]["path"], eamadm::output_names::FINAL_SCORES);
//! assert_eq!(package["resources"][1]["path"], eamadm::output_names::CLAIMS);
//! assert!(eamadm::data_package::markdown().contains("| `step_cap` | integer | steps |"));
//! ```

use serde_json::Value;

use crate::columns::{self, Resource};
use crate::output_names::{CLAIMS, FINAL_SCORES, LAYOUTS, ORACLE, PRETRAINING, TUNING};
use crate::{claims, oracle, scores};

/// The package's name.
pub const NAME: &str = "eamadm-results";

/// The package's tables: `final-scores.csv`, `claims.csv`, then `oracle.csv`,
/// `pretraining.csv` and `layouts.csv`.
pub const RESOURCES: [Resource; 5] = [
    Resource {
        name: "final-scores",
        path: FINAL_SCORES,
        title: "Per-run final scores",
        description: "One row per run (task, method, seed): the scores the claims are tested \
                      on, computed from the run's record by `eamadm::scores::final_scores`.",
        columns: scores::COLUMNS,
    },
    Resource {
        name: "claims",
        path: CLAIMS,
        title: "The paper's claims tested",
        description: "Per claim and task: one row per method and metric (its IQM over seeds, \
                      the verdict on a method under test), then each comparison of a method \
                      under test with a competitor, then the per-seed outcome rows; computed \
                      from `final-scores.csv` by `eamadm::claims`.",
        columns: claims::CLAIM_COLUMNS,
    },
    Resource {
        name: "oracle",
        path: ORACLE,
        title: "The decision step on the best sub-task values available",
        description: "Per task, decision rule, own column and seed: the greedy episode of \
                      EA-MADM's decision, of the plain aggregators and of each sub-task alone \
                      on exact sub-task values (value iteration; the mazes) or on sub-tasks \
                      pre-trained to convergence (the robot: the best estimate available), with \
                      the share of states whose decision is a shortest-path action; computed \
                      by `eamadm::oracle::oracle_rows` (docs/paper-notes.md §21).",
        columns: oracle::ORACLE_COLUMNS,
    },
    Resource {
        name: "pretraining",
        path: PRETRAINING,
        title: "Sub-task pre-training per run",
        description: "One row per sub-task of every run that pre-trains sub-tasks: episodes, \
                      steps, reaching episodes and whether the stopping rule found it \
                      converged; from the run records by `eamadm::oracle::pretraining_rows`.",
        columns: oracle::PRETRAINING_COLUMNS,
    },
    Resource {
        name: "layouts",
        path: LAYOUTS,
        title: "The maze layouts the runs play",
        description: "One row per maze layout of the run: the paper's two always, the \
                      positive control's hand-designed map when it ran, the family's layouts \
                      with `--suite family`; how each was made (kind, generator parameters and \
                      seed), its start, target, obstacles, Manhattan distance, BFS optimum, \
                      detour ratio and map. The `layout` of `final-scores.csv` names its row \
                      (the robot's scenario has none); written by `eamadm::family`.",
        columns: crate::family::LAYOUT_COLUMNS,
    },
];

/// `tuning.csv`, written beside the others by `--suite tuning` (and then in its package).
pub const TUNING_RESOURCE: Resource = Resource {
    name: "tuning",
    path: TUNING,
    title: "Tuning trials (--suite tuning)",
    description: "One row per hyperparameter trial of every method the claims compare, on the \
                  tuning seeds: its values, its score by the task's objective and whether it \
                  is its method's chosen trial, the one run on the held-out seeds for the \
                  \"each at its best\" verdicts; written by `eamadm::tuning`.",
    columns: crate::tuning::TUNING_COLUMNS,
};

/// The data package of [`RESOURCES`].
#[must_use]
pub fn data_package() -> Value {
    columns::data_package(NAME, &RESOURCES)
}

/// The text of `datapackage.json`.
#[must_use]
pub fn data_package_text() -> String {
    columns::to_json_text(&data_package())
}

/// The text of `datapackage.json` of a run that wrote `tuning.csv` too: [`RESOURCES`] and
/// [`TUNING_RESOURCE`].
#[must_use]
pub fn data_package_text_with_tuning() -> String {
    let [scores, claims, oracle, pretraining, layouts] = RESOURCES;
    columns::to_json_text(&columns::data_package(
        NAME,
        &[
            scores,
            claims,
            oracle,
            pretraining,
            layouts,
            TUNING_RESOURCE,
        ],
    ))
}

/// [`RESOURCES`] and [`TUNING_RESOURCE`] as Markdown: a section with a table of columns per
/// file (spliced into `docs/outputs.md`).
#[must_use]
pub fn markdown() -> String {
    let [scores, claims, oracle, pretraining, layouts] = RESOURCES;
    columns::markdown(&[
        scores,
        claims,
        oracle,
        pretraining,
        layouts,
        TUNING_RESOURCE,
    ])
}
