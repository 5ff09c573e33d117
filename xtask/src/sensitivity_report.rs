//! The readings of the paper in a run's outputs: the plan printout's line and
//! `sensitivity.csv` (issue 20 item 4). The rows are computed by `eamadm::sensitivity` and the
//! report's section on them is written by `eamadm_present::report`; this module only writes files.

use std::path::Path;

use eamadm::sensitivity::{self, SensitivityRow};

use crate::atomic::write_atomic;
use crate::claims_report::ClaimsReportError;
use crate::experiments::PlannedExperiment;
use crate::jobs::Job;

/// The plan printout's line on the readings' runs (empty when the plan has none).
pub(crate) fn describe_readings(experiments: &[PlannedExperiment], jobs: &[Job<'_>]) -> String {
    let mut names: Vec<&str> = Vec::new();
    let mut runs = 0;
    for job in jobs {
        if let Some((reading, _)) = experiments[job.experiment].reading {
            runs += 1;
            if !names.contains(&reading.name()) {
                names.push(reading.name());
            }
        }
    }
    if runs == 0 {
        return String::new();
    }
    format!(
        "  readings: {} ({runs} runs of only the methods each changes; the others' runs are \
         reused; sensitivity.csv)\n",
        names.join(", ")
    )
}

/// Writes `sensitivity.csv` into `out` (only its header when no reading ran).
pub(crate) fn write_sensitivity_csv(
    out: &Path,
    rows: &[SensitivityRow],
) -> Result<(), ClaimsReportError> {
    let mut csv = Vec::new();
    sensitivity::write_csv(rows, &mut csv)?;
    write_atomic(&out.join(eamadm::output_names::SENSITIVITY), &csv)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use eamadm::claims::ClaimOptions;
    use eamadm::paper::Reading;
    use eamadm::sensitivity::{Change, ReadingRuns};

    use crate::cli::{KeepTrajectories, ReproduceArgs, ReproduceCommand, RunModeArgs, Task};
    use crate::experiments::{base_count, plan_experiments};
    use crate::jobs::plan_jobs;
    use crate::plan::{Workspace, default_methods};

    #[test]
    fn each_reading_plans_only_the_runs_of_the_methods_it_changes() {
        let planned = plan_experiments(
            &[Task::Task1, Task::Task2],
            false,
            None,
            2,
            true,
            crate::cli::Readings::All,
        )
        .unwrap();
        let jobs = plan_jobs(&planned, &default_methods()).unwrap();
        let bases = base_count(&planned);
        assert_eq!(bases, 2);
        for job in &jobs {
            let planned = &planned[job.experiment];
            match planned.reading {
                None => assert!(job.experiment < bases),
                Some((reading, _)) => assert!(
                    reading.methods().contains(&job.method.label.as_str()),
                    "{} reruns {}",
                    planned.name,
                    job.method.label
                ),
            }
        }
        // Task I: every reading but the Task II reward one; the counts of runs per reading.
        let reading_runs = |name: &str| {
            jobs.iter()
                .filter(|job| planned[job.experiment].name == name)
                .count()
        };
        assert_eq!(reading_runs("task1-reading-gamma-0.99"), 4 * 2);
        assert_eq!(reading_runs("task2-reading-task2-reward-as-task1"), 4 * 2);
        assert_eq!(reading_runs("task1-reading-epsilon-greedy-0.95"), 2);
        assert_eq!(reading_runs("task1-reading-task2-reward-as-task1"), 0);
        // --method narrows the readings' runs as it narrows the base's.
        let narrow = plan_jobs(&planned, &["softmax".to_owned()]).unwrap();
        assert!(narrow.iter().all(|job| job.method.label == "softmax"));
        let describe = super::describe_readings(&planned, &jobs);
        assert!(describe.contains("gamma-0.99"), "{describe}");
        assert!(describe.contains(&format!("{} runs", jobs.len() - 20 * 2 * 2)));
    }

    #[test]
    fn a_reading_that_changes_nothing_reruns_the_base_runs_bit_for_bit_and_holds() {
        let mut planned = plan_experiments(
            &[Task::Task1],
            false,
            None,
            2,
            true,
            crate::cli::Readings::All,
        )
        .unwrap();
        let config = planned[0].config().shortened(&eamadm::Shortening {
            maze_step_cap: Some(80),
            ..eamadm::Shortening::episodes(6)
        });
        planned[0].experiment = eamadm::Experiment::new(config.clone()).unwrap();
        let base = &planned[0].experiment;
        // A reading whose change is nothing, rerunning two of the paper's methods.
        let mut no_op = config.clone();
        no_op.name = "task1-reading-no-op".to_owned();
        no_op
            .methods
            .retain(|m| m.label == "softmax" || m.label == "epsilon-greedy");
        let rerun = eamadm::Experiment::new(no_op.clone()).unwrap();
        let paper: Vec<_> = config
            .methods
            .iter()
            .filter(|m| m.role == eamadm::Role::Paper)
            .collect();
        let mut base_scores = Vec::new();
        let mut reading = ReadingRuns {
            reading: "no-op".to_owned(),
            task: "task1".to_owned(),
            methods: no_op.methods.iter().map(|m| m.label.clone()).collect(),
            scores: Vec::new(),
        };
        for method in &paper {
            for seed in config.seed_values() {
                let record = base.run(method, seed).unwrap();
                base_scores.push(eamadm::scores::final_score_of(&record, base).unwrap());
                if let Some(spec) = no_op.method(&method.label) {
                    let again = rerun.run(spec, seed).unwrap();
                    assert_eq!(again.experiment, "task1-reading-no-op");
                    let renamed = eamadm::RunRecord {
                        experiment: record.experiment.clone(),
                        ..again
                    };
                    assert_eq!(renamed, record, "{} seed {seed}", method.label);
                    reading
                        .scores
                        .push(eamadm::scores::final_score_of(&renamed, &rerun).unwrap());
                }
            }
        }
        let rows =
            eamadm::sensitivity::sensitivity(&base_scores, &[reading], &ClaimOptions::default())
                .unwrap();
        assert_eq!(rows.len(), 3, "C1–C3 on Task I");
        assert!(
            rows.iter().all(|row| row.change == Change::Holds),
            "{rows:?}"
        );
        // A real reading on the same base does change its reruns.
        let gamma = Reading::Gamma099.apply(&config).unwrap();
        assert_eq!(gamma.learner.gamma, 0.99);
    }

    #[test]
    fn the_quick_plan_writes_the_same_sensitivity_at_one_and_two_threads() {
        let run = |threads: usize| {
            let dir = tempfile::tempdir().unwrap();
            std::fs::create_dir(dir.path().join("fixtures")).unwrap();
            let root = dir.path().canonicalize().unwrap();
            let workspace = Workspace {
                current_dir: root.clone(),
                root: root.clone(),
            };
            let command = ReproduceCommand {
                plan: ReproduceArgs {
                    seeds: Some(2),
                    tasks: vec![Task::Task1],
                    methods: vec![
                        "ea-madm".to_owned(),
                        "epsilon-greedy".to_owned(),
                        "softmax".to_owned(),
                    ],
                    config: None,
                    out: Some("out".into()),
                    quick: true,
                    wait: false,
                    keep_trajectories: KeepTrajectories::Figures,
                    readings: crate::cli::Readings::All,
                    pretrained_cache: None,
                    suites: vec![],
                    family_size: None,
                },
                mode: RunModeArgs::default(),
            };
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(|| crate::reproduce::reproduce_paper(&command, &workspace))
                .unwrap();
            let read = |file: &str| std::fs::read_to_string(root.join("out").join(file)).unwrap();
            (read(eamadm::output_names::SENSITIVITY), read("REPORT.md"))
        };
        let (csv, report) = run(1);
        // Task I: C1–C3 under each of the six readings that change Task I.
        assert_eq!(csv.lines().count(), 1 + 3 * 6, "{csv}");
        assert!(csv.starts_with("claim,task,reading,method,base_verdict,verdict,change"));
        assert!(report.contains("### Sensitivity to the readings of the paper"));
        assert!(report.contains("`pretrain-double`"));
        assert_eq!((csv, report), run(2));
    }
}
