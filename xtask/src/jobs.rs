//! The runs of a plan as jobs: one per (experiment, method, seed), in job order (experiment,
//! then method as selected, then seed), each with its [`RunKey`]; shards of the job list by key,
//! and the job list as JSON lines for any job engine.

use std::fmt;

use eamadm::MethodSpec;
use serde::Serialize;
use thiserror::Error;

use crate::cli::ReproduceArgs;
use crate::experiments::PlannedExperiment;
use eamadm_runs::key::{ResumeError, RunDescription, RunKey};

/// One run to do.
#[derive(Debug, Clone)]
pub(crate) struct Job<'a> {
    /// Index of its experiment in the plan.
    pub(crate) experiment: usize,
    /// The method.
    pub(crate) method: &'a MethodSpec,
    /// The seed.
    pub(crate) seed: u64,
    /// The run's key.
    pub(crate) key: RunKey,
}

/// The jobs of `experiments` × `methods` × seeds, in job order.
pub(crate) fn plan_jobs<'a>(
    experiments: &'a [PlannedExperiment],
    methods: &[String],
) -> Result<Vec<Job<'a>>, ResumeError> {
    let mut jobs = Vec::new();
    for (index, planned) in experiments.iter().enumerate() {
        let config = planned.config();
        for label in methods {
            // Labels were checked against the config's; a label absent here is skipped.
            let Some(method) = config.method(label) else {
                continue;
            };
            for seed in config.seed_values() {
                let key = RunKey::of(&RunDescription::new(&planned.experiment, method, seed))?;
                jobs.push(Job {
                    experiment: index,
                    method,
                    seed,
                    key,
                });
            }
        }
    }
    Ok(jobs)
}

/// Shard `index` (1-based) of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Shard {
    /// K, from 1 to `count`.
    pub(crate) index: u64,
    /// N ≥ 1.
    pub(crate) count: u64,
}

/// A `--shard` value that is not `K/N` with 1 ≤ K ≤ N.
#[derive(Debug, Error, PartialEq, Eq)]
#[error("--shard {given:?}: {problem}; write K/N with 1 ≤ K ≤ N, e.g. --shard 2/3")]
pub(crate) struct ShardError {
    given: String,
    problem: &'static str,
}

impl Shard {
    /// Parses `K/N`.
    pub(crate) fn parse(text: &str) -> Result<Self, ShardError> {
        let error = |problem| ShardError {
            given: text.to_owned(),
            problem,
        };
        let (k, n) = text.split_once('/').ok_or_else(|| error("no `/`"))?;
        let index: u64 = k
            .trim()
            .parse()
            .map_err(|_| error("K is not a whole number"))?;
        let count: u64 = n
            .trim()
            .parse()
            .map_err(|_| error("N is not a whole number"))?;
        if count == 0 {
            return Err(error("N is 0"));
        }
        if index == 0 || index > count {
            return Err(error("K is outside 1..=N"));
        }
        Ok(Self { index, count })
    }

    /// Whether run `key` belongs to this shard: the key's first 64 bits (it is a BLAKE3 hash,
    /// so they are uniform) modulo N, plus one, is K. It depends on the key only, so every
    /// machine and thread count agrees.
    pub(crate) fn holds(self, key: &RunKey) -> bool {
        let bucket = u64::from_str_radix(&key.as_str()[..16], 16).unwrap_or(0) % self.count;
        bucket + 1 == self.index
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// One line of `--list-jobs`.
#[derive(Debug, Serialize)]
pub(crate) struct JobLine<'a> {
    /// The run's key.
    pub(crate) key: &'a str,
    /// The experiment (also the bundle and output folder name).
    pub(crate) experiment: &'a str,
    /// The task the experiment runs (`task1`, `task2`, `robot`, or `config` for a config file).
    pub(crate) task: &'a str,
    /// The method's label.
    pub(crate) method: &'a str,
    /// The seed.
    pub(crate) seed: u64,
    /// The `cargo xtask` arguments that run exactly this job into the plan's run store.
    pub(crate) run: Vec<String>,
}

/// The plan options of `args` as command-line arguments (the same plan when given again), with
/// relative paths made absolute against `current_dir` so a job runs from any folder.
pub(crate) fn plan_arguments(
    args: &ReproduceArgs,
    out: &std::path::Path,
    current_dir: &std::path::Path,
) -> Vec<String> {
    let mut arguments = Vec::new();
    if let Some(seeds) = args.seeds {
        arguments.extend(["--seeds".to_owned(), seeds.to_string()]);
    }
    for task in &args.tasks {
        arguments.extend(["--task".to_owned(), task.name().to_owned()]);
    }
    for method in &args.methods {
        arguments.extend(["--method".to_owned(), method.clone()]);
    }
    if let Some(config) = &args.config {
        arguments.extend([
            "--config".to_owned(),
            current_dir.join(config).display().to_string(),
        ]);
    }
    arguments.extend(["--out".to_owned(), out.display().to_string()]);
    if args.quick {
        arguments.push("--quick".to_owned());
    }
    if args.keep_trajectories == crate::cli::KeepTrajectories::All {
        arguments.extend(["--keep-trajectories".to_owned(), "all".to_owned()]);
    }
    if args.readings != crate::cli::Readings::All {
        arguments.extend(["--readings".to_owned(), args.readings.name().to_owned()]);
    }
    for suite in &args.suites {
        arguments.extend(["--suite".to_owned(), suite.name().to_owned()]);
    }
    if let Some(size) = args.family_size {
        arguments.extend(["--family-size".to_owned(), size.to_string()]);
    }
    if let Some(cache) = &args.pretrained_cache {
        arguments.extend([
            "--pretrained-cache".to_owned(),
            current_dir.join(cache).display().to_string(),
        ]);
    }
    arguments
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::Task;
    use crate::experiments::plan_experiments;

    #[test]
    fn shards_parse_and_refuse_nonsense() {
        assert_eq!(Shard::parse("2/3"), Ok(Shard { index: 2, count: 3 }));
        assert_eq!(Shard::parse("1/1").unwrap().to_string(), "1/1");
        for bad in ["0/3", "4/3", "1/0", "3", "a/3", "1/b", "-1/3"] {
            let error = Shard::parse(bad).unwrap_err();
            assert!(error.to_string().contains("K/N"), "{error}");
        }
    }

    #[test]
    fn the_shards_split_the_jobs_exactly_and_stably() {
        let planned =
            plan_experiments(&Task::ALL, false, None, 3, true, crate::cli::Readings::All).unwrap();
        let methods = crate::plan::default_methods();
        let jobs = plan_jobs(&planned, &methods).unwrap();
        // Each task runs the default methods its config defines (the robots have no controls).
        let expected: usize = planned
            .iter()
            .map(|p| {
                methods
                    .iter()
                    .filter(|label| p.config().method(label).is_some())
                    .count()
                    * 3
            })
            .sum();
        assert_eq!(jobs.len(), expected);
        let count = 3;
        let mut sizes = Vec::new();
        for job in &jobs {
            let holders: Vec<u64> = (1..=count)
                .filter(|&index| Shard { index, count }.holds(&job.key))
                .collect();
            assert_eq!(holders.len(), 1, "each run is in exactly one shard");
        }
        for index in 1..=count {
            sizes.push(
                jobs.iter()
                    .filter(|job| Shard { index, count }.holds(&job.key))
                    .count(),
            );
        }
        // Hash buckets: every shard gets work (72 runs over 3 shards).
        assert!(sizes.iter().all(|&size| size > 10), "{sizes:?}");
        // The bucket of a pinned key, so a change of the rule is deliberate.
        let key = RunKey::from_verified_hex(format!("{:016x}{}", 7_u64, "0".repeat(48)));
        assert!(Shard { index: 2, count: 3 }.holds(&key));
    }
}
