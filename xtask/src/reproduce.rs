//! `cargo xtask reproduce-paper`: check everything (arguments, config, tasks) before touching
//! the output folder, run (resuming), then write the results, figures and `REPORT.md`.

use std::time::Instant;

use crate::Failure;
use crate::claims_report::{Verdicts, write_claim_outputs};
use crate::cli::ReproduceArgs;
use crate::execute::run_experiments;
use crate::experiments::{load_config_file, plan_experiments};
use crate::output_folder::OutputFolder;
use crate::outputs::{write_experiment, write_results_json};
use crate::plan::{QUICK_SEEDS, ReproducePlan, Workspace, default_methods};
use crate::progress::Progress;
use crate::resume::RunStore;
use eamadm::claims::ClaimOptions;

/// Runs the command.
pub(crate) fn reproduce_paper(args: &ReproduceArgs, workspace: &Workspace) -> Result<(), Failure> {
    // Everything is checked before the output folder is created: a bad config writes nothing.
    let custom = match &args.config {
        Some(path) => {
            Some(load_config_file(&workspace.current_dir.join(path)).map_err(Failure::invalid)?)
        }
        None => None,
    };
    let known: Vec<String> = match &custom {
        Some(config) => config.methods.iter().map(|m| m.label.clone()).collect(),
        None => default_methods(),
    };
    let mut plan = ReproducePlan::from_args(args, &known, workspace).map_err(Failure::invalid)?;
    if let (Some(config), None) = (&custom, args.seeds) {
        plan.seeds = if plan.quick {
            QUICK_SEEDS.min(config.seeds)
        } else {
            config.seeds
        };
    }
    let config_file = plan.config.as_deref().zip(custom.as_ref());
    let experiments = plan_experiments(
        &plan.tasks,
        !args.tasks.is_empty(),
        config_file,
        plan.seeds,
        plan.quick,
    )
    .map_err(Failure::invalid)?;
    print!("{}", plan.describe());

    // One process per output folder; what a killed earlier invocation left is repaired here.
    let folder = OutputFolder::open(&plan.out, args.wait).map_err(Failure::failed)?;
    let started = Instant::now();
    let store = RunStore::new(folder.root());
    let progress = Progress::for_stdout();
    let grouped =
        run_experiments(&experiments, &plan.methods, &store, &progress).map_err(Failure::failed)?;

    // The set of outputs is written aside and swapped in whole (see `output_folder`).
    let staging = folder.staging().map_err(Failure::failed)?;
    let all: Vec<_> = grouped.iter().flat_map(|g| g.records.iter()).collect();
    write_results_json(&staging, &all).map_err(Failure::failed)?;
    let mut scores = Vec::new();
    let mut figures = Vec::new();
    let mut behaviour = Vec::new();
    for (planned, group) in experiments.iter().zip(&grouped) {
        figures.push(write_experiment(&staging, planned, &group.records).map_err(Failure::failed)?);
        let mut section = String::new();
        if matches!(planned.config().task, eamadm::TaskConfig::Robot { .. }) {
            crate::robot_report::write_robot_behaviour(
                &mut section,
                &group.records,
                planned.config().learner.gamma,
            );
        }
        behaviour.push(section);
        scores.extend(
            eamadm::scores::final_scores(&group.records, planned.config())
                .map_err(Failure::failed)?,
        );
    }
    let verdicts = Verdicts::compute(scores, &ClaimOptions::default()).map_err(Failure::failed)?;
    write_claim_outputs(
        &staging,
        &experiments,
        &figures,
        &behaviour,
        &verdicts,
        plan.quick,
    )
    .map_err(Failure::failed)?;
    folder.commit().map_err(Failure::failed)?;
    let resumed: usize = grouped.iter().map(|g| g.resumed).sum();
    println!(
        "done in {:.1} s: {} runs ({resumed} resumed from an earlier invocation)\nreport: {}",
        started.elapsed().as_secs_f64(),
        all.len(),
        plan.out.join("REPORT.md").display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(config: Option<&str>, out: &str) -> ReproduceArgs {
        ReproduceArgs {
            seeds: Some(1),
            tasks: vec![],
            methods: vec!["epsilon-greedy".to_owned()],
            config: config.map(Into::into),
            out: Some(out.into()),
            quick: true,
            wait: false,
        }
    }

    fn workspace() -> (tempfile::TempDir, Workspace) {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir(dir.path().join("fixtures")).unwrap();
        let root = dir.path().canonicalize().unwrap();
        (
            dir,
            Workspace {
                current_dir: root.clone(),
                root,
            },
        )
    }

    #[test]
    fn an_invalid_config_names_the_field_and_writes_nothing() {
        let (_dir, ws) = workspace();
        let text = eamadm::PAPER_TASK2_TOML.replace("gamma = 0.95", "gamma = 1.5");
        std::fs::write(ws.root.join("bad.toml"), text).unwrap();
        let failure = reproduce_paper(&args(Some("bad.toml"), "out"), &ws).unwrap_err();
        assert_eq!(failure.exit_code, 2);
        assert!(
            failure.message.contains("`learner.gamma` = 1.5"),
            "{}",
            failure.message
        );
        assert!(!ws.root.join("out").exists());
    }

    #[test]
    fn a_valid_config_runs_and_writes_every_output() {
        let (_dir, ws) = workspace();
        let mut config = eamadm::paper::task1();
        config.name = "mine".to_owned();
        config.episodes = 3;
        std::fs::write(ws.root.join("mine.toml"), config.to_toml_string().unwrap()).unwrap();
        reproduce_paper(&args(Some("mine.toml"), "out"), &ws).unwrap();
        for file in [
            "REPORT.md",
            "results.json",
            "mine/curves.csv",
            "mine/trajectories.csv",
            "mine/steps.svg",
            "mine/return.svg",
            "mine/trajectories.svg",
        ] {
            assert!(ws.root.join("out").join(file).is_file(), "{file}");
        }
        let report = std::fs::read_to_string(ws.root.join("out/REPORT.md")).unwrap();
        assert!(report.contains("## mine (`mine`)"), "{report}");
        // Every visible top-level entry but the experiment's folder is a name configs may not
        // take, so no experiment can overwrite it.
        for entry in std::fs::read_dir(ws.root.join("out")).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            if name.starts_with('.') || name == "mine" {
                continue;
            }
            assert!(
                eamadm::RESERVED_NAMES
                    .iter()
                    .any(|reserved| reserved.eq_ignore_ascii_case(&name)),
                "{name} is not reserved"
            );
        }
    }

    fn write_config(ws: &Workspace, file: &str, name: &str) {
        let mut config = eamadm::paper::task1();
        config.name = name.to_owned();
        config.episodes = 3;
        std::fs::write(ws.root.join(file), config.to_toml_string().unwrap()).unwrap();
    }

    #[test]
    fn a_run_of_other_arguments_leaves_no_stale_outputs() {
        let (_dir, ws) = workspace();
        write_config(&ws, "first.toml", "first");
        write_config(&ws, "second.toml", "second");
        reproduce_paper(&args(Some("first.toml"), "out"), &ws).unwrap();
        assert!(ws.root.join("out/first/curves.csv").is_file());
        reproduce_paper(&args(Some("second.toml"), "out"), &ws).unwrap();
        let out = ws.root.join("out");
        assert!(
            !out.join("first").exists(),
            "the first run's outputs are gone"
        );
        assert!(out.join("second/curves.csv").is_file());
        let manifest = std::fs::read_to_string(out.join(".outputs")).unwrap();
        assert!(
            manifest.lines().all(|line| !line.starts_with("first/")),
            "{manifest}"
        );
        assert!(manifest.contains("REPORT.md\n"), "{manifest}");
        assert!(!out.join(".staging").exists() && !out.join(".committed").exists());
        // The run store is not part of the set: both runs' records stay for resuming.
        assert_eq!(std::fs::read_dir(out.join("runs")).unwrap().count(), 2);
    }

    #[test]
    fn names_that_would_escape_the_output_folder_are_refused_before_writing() {
        let (_dir, ws) = workspace();
        for name in ["..", "runs", "REPORT.md"] {
            let text = eamadm::PAPER_TASK1_TOML.replacen(
                "name = \"task1\"",
                &format!("name = {name:?}"),
                1,
            );
            std::fs::write(ws.root.join("bad.toml"), text).unwrap();
            let failure = reproduce_paper(&args(Some("bad.toml"), "out/sub"), &ws).unwrap_err();
            assert_eq!(failure.exit_code, 2, "{name}: {}", failure.message);
            assert!(failure.message.contains("`name`"), "{}", failure.message);
            assert!(!ws.root.join("out").exists(), "{name}");
        }
    }

    #[test]
    fn a_busy_output_folder_is_refused_with_a_clear_message() {
        let (_dir, ws) = workspace();
        write_config(&ws, "mine.toml", "mine");
        let held = OutputFolder::open(&ws.root.join("out"), false).unwrap();
        let failure = reproduce_paper(&args(Some("mine.toml"), "out"), &ws).unwrap_err();
        assert_eq!(failure.exit_code, 1);
        assert!(
            failure
                .message
                .contains("another reproduce-paper is using this output folder"),
            "{}",
            failure.message
        );
        assert!(!ws.root.join("out/REPORT.md").exists());
        drop(held);
        reproduce_paper(&args(Some("mine.toml"), "out"), &ws).unwrap();
    }

    /// Splits a line of a CSV without quoted fields (the claim and score tables have none).
    fn cells(line: &str) -> Vec<&str> {
        line.split(',').collect()
    }

    #[test]
    fn claims_csv_can_be_recomputed_from_final_scores_csv() {
        use eamadm::stats::{self, Bootstrap, PermutationTest, Statistic};
        let (_dir, ws) = workspace();
        let args = ReproduceArgs {
            seeds: Some(3),
            tasks: vec![crate::cli::Task::Task1],
            methods: vec![
                "ea-madm".to_owned(),
                "softmax".to_owned(),
                "epsilon-greedy".to_owned(),
            ],
            config: None,
            out: Some("out".into()),
            quick: true,
            wait: false,
        };
        reproduce_paper(&args, &ws).unwrap();
        let out = ws.root.join("out");
        let scores =
            eamadm::scores::read_csv(std::fs::File::open(out.join("final-scores.csv")).unwrap())
                .unwrap();
        assert_eq!(scores.len(), 9);
        let claims = std::fs::read_to_string(out.join("claims.csv")).unwrap();
        let mut lines = claims.lines();
        let header = cells(lines.next().unwrap());
        let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
        let of = |method: &str, metric: &str| -> Vec<f64> {
            scores
                .iter()
                .filter(|s| s.method == method)
                .filter_map(|s| s.value(metric))
                .collect()
        };
        let number = |cell: &str| cell.parse::<f64>().unwrap();
        let (mut singles, mut comparisons) = (0, 0);
        let mut raw_p: std::collections::BTreeMap<(String, String), Vec<(f64, f64)>> =
            std::collections::BTreeMap::new();
        for line in lines {
            let row = cells(line);
            let (method, metric, versus) = (
                row[column("method")],
                row[column("metric")],
                row[column("versus")],
            );
            let x = of(method, metric);
            if versus.is_empty() {
                // A single-method row: the IQM over seeds and its bootstrap interval.
                let interval = Bootstrap::default().interval(&x, Statistic::Iqm).unwrap();
                assert_eq!(
                    number(row[column("estimate")]),
                    stats::iqm(&x).unwrap(),
                    "{line}"
                );
                assert_eq!(number(row[column("ci_low")]), interval.low, "{line}");
                assert_eq!(number(row[column("ci_high")]), interval.high, "{line}");
                singles += 1;
            } else {
                let y = of(versus, metric);
                let difference = Bootstrap::default()
                    .difference(&x, &y, Statistic::Iqm)
                    .unwrap();
                let p = PermutationTest::default()
                    .p_value(&x, &y, Statistic::Iqm)
                    .unwrap();
                assert_eq!(
                    number(row[column("estimate")]),
                    stats::iqm(&x).unwrap() - stats::iqm(&y).unwrap(),
                    "{line}"
                );
                assert_eq!(number(row[column("ci_low")]), difference.low, "{line}");
                assert_eq!(number(row[column("ci_high")]), difference.high, "{line}");
                assert_eq!(number(row[column("p_value")]), p, "{line}");
                raw_p
                    .entry((row[column("claim")].to_owned(), method.to_owned()))
                    .or_default()
                    .push((p, number(row[column("p_holm")])));
                comparisons += 1;
            }
        }
        // C1, C2: one metric; C3: two. Three methods, one under test, two competitors.
        assert_eq!(singles, 3 * (1 + 1 + 2));
        assert_eq!(comparisons, 2 * (1 + 1 + 2));
        for ((claim, method), pairs) in raw_p {
            let raw: Vec<f64> = pairs.iter().map(|(p, _)| *p).collect();
            let holm: Vec<f64> = pairs.iter().map(|(_, h)| *h).collect();
            assert_eq!(stats::holm(&raw).unwrap(), holm, "{claim} {method}");
        }
        let report = std::fs::read_to_string(out.join("REPORT.md")).unwrap();
        assert!(
            report.contains("## Verdicts on the paper's claims"),
            "{report}"
        );
    }
}
