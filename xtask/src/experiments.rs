//! The experiments a `reproduce-paper` invocation runs: the paper presets of the selected tasks
//! (or the one `--config` file), shortened for `--quick`, with `--seeds` applied, each loaded
//! into an [`eamadm::Experiment`] — all checked before anything is written.

use std::path::Path;

use eamadm::config::TaskConfig;
use eamadm::mazes::Preset;
use eamadm::{ConfigError, Experiment, ExperimentConfig, Method};
use thiserror::Error;

use crate::cli::Task;

/// Episodes of a `--quick` run (source task and each sub-task's pre-training).
pub(crate) const QUICK_EPISODES: u64 = 30;
/// Step cap of a `--quick` run's episodes on the mazes (the presets' is 2000).
pub(crate) const QUICK_MAZE_STEP_CAP: u32 = 500;

/// The four methods the paper compares, in report order; every other label of a config is an
/// ablation (or an extra method of a custom config).
pub(crate) const MAIN_METHODS: [&str; 4] =
    ["ea-madm", "epsilon-greedy", "epsilon-decreasing", "softmax"];

/// A config that cannot be used.
#[derive(Debug, Error)]
pub(crate) enum ExperimentError {
    /// The `--config` file is not a valid experiment config.
    #[error("--config {}: {source}", path.display())]
    Config {
        /// The file.
        path: std::path::PathBuf,
        /// The problem, naming the field.
        #[source]
        source: Box<ConfigError>,
    },
    /// `--config` together with `--task`.
    #[error(
        "--task cannot be combined with --config: the config file names its own task \
         (its `task` table); drop --task"
    )]
    TaskWithConfig,
}

/// One experiment of the invocation, ready to run.
#[derive(Debug, Clone)]
pub(crate) struct PlannedExperiment {
    /// Folder and file name: `task1`, `task2`, `robot`, or the `--config` file's `name`.
    pub(crate) name: String,
    /// Title for people: "Task I", "Task II", "Robot", or the config's name.
    pub(crate) title: String,
    /// The paper's maze, when the task is one (for the paper's reported numbers).
    pub(crate) paper_maze: Option<Preset>,
    /// The loaded experiment (config with `--seeds` and `--quick` applied).
    pub(crate) experiment: Experiment,
}

impl PlannedExperiment {
    /// The config actually run.
    pub(crate) fn config(&self) -> &ExperimentConfig {
        self.experiment.config()
    }
}

/// The paper preset of `task`.
pub(crate) fn preset_config(task: Task) -> ExperimentConfig {
    match task {
        Task::Task1 => ExperimentConfig::paper_task1(),
        Task::Task2 => ExperimentConfig::paper_task2(),
        Task::Robot => ExperimentConfig::paper_robot(),
    }
}

/// Reads and validates a `--config` file (its task is loaded too, so a bad map or scenario file
/// fails here).
pub(crate) fn load_config_file(path: &Path) -> Result<ExperimentConfig, ExperimentError> {
    let error = |source| ExperimentError::Config {
        path: path.to_path_buf(),
        source: Box::new(source),
    };
    let text = std::fs::read_to_string(path).map_err(|source| {
        error(ConfigError::Read {
            field: "--config".to_owned(),
            path: path.to_path_buf(),
            source,
        })
    })?;
    let config = ExperimentConfig::from_toml_str(&text).map_err(error)?;
    Experiment::new(config.clone()).map_err(error)?;
    Ok(config)
}

/// `config` shortened to a smoke run: [`QUICK_EPISODES`] episodes (and pre-training episodes),
/// maze episodes capped at [`QUICK_MAZE_STEP_CAP`] steps, trajectory episodes past the end
/// dropped.
pub(crate) fn quick(mut config: ExperimentConfig) -> ExperimentConfig {
    shorten(&mut config, QUICK_EPISODES, Some(QUICK_MAZE_STEP_CAP), None);
    config
}

/// Shortens `config` to `episodes` (source and pre-training), with the given step caps for maze
/// and robot tasks (`None` keeps the task's own).
pub(crate) fn shorten(
    config: &mut ExperimentConfig,
    episodes: u64,
    maze_step_cap: Option<u32>,
    robot_step_cap: Option<u32>,
) {
    config.episodes = config.episodes.min(episodes);
    let episodes_now = config.episodes;
    config.trajectories.episodes.retain(|&e| e < episodes_now);
    for spec in &mut config.methods {
        if let Method::EaMadm(ea) = &mut spec.method {
            ea.pretrain.episodes = ea.pretrain.episodes.min(episodes);
        }
    }
    match &mut config.task {
        TaskConfig::Maze { step_cap, .. }
        | TaskConfig::MazeFile { step_cap, .. }
        | TaskConfig::MazeText { step_cap, .. } => {
            if let Some(cap) = maze_step_cap {
                *step_cap = Some(step_cap.map_or(cap, |own| own.min(cap)));
            }
        }
        TaskConfig::Robot { step_cap, .. } => {
            if let Some(cap) = robot_step_cap {
                *step_cap = Some(step_cap.map_or(cap, |own| own.min(cap)));
            }
        }
        // A task kind added to eamadm later keeps its own cap.
        _ => {}
    }
}

/// The paper's maze behind a config's task, if any.
pub(crate) fn paper_maze(config: &ExperimentConfig) -> Option<Preset> {
    match &config.task {
        TaskConfig::Maze { preset, .. } => Some(*preset),
        _ => None,
    }
}

/// Title for people of a task.
pub(crate) fn task_title(task: Task) -> &'static str {
    match task {
        Task::Task1 => "Task I",
        Task::Task2 => "Task II",
        Task::Robot => "Robot",
    }
}

/// The experiments to run: one per selected task (its preset), or the `--config` file's one;
/// `seeds` per method, shortened when `quick`.
pub(crate) fn plan_experiments(
    tasks: &[Task],
    tasks_given: bool,
    config_file: Option<&Path>,
    seeds: u32,
    quick_run: bool,
) -> Result<Vec<PlannedExperiment>, ExperimentError> {
    let mut configs: Vec<(String, ExperimentConfig)> = Vec::new();
    match config_file {
        Some(path) => {
            if tasks_given {
                return Err(ExperimentError::TaskWithConfig);
            }
            let config = load_config_file(path)?;
            configs.push((config.name.clone(), config));
        }
        None => {
            for &task in tasks {
                configs.push((task_title(task).to_owned(), preset_config(task)));
            }
        }
    }
    configs
        .into_iter()
        .map(|(title, mut config)| {
            config.seeds = seeds;
            if quick_run {
                config = quick(config);
            }
            let name = config.name.clone();
            let paper_maze = paper_maze(&config);
            let experiment = Experiment::new(config).map_err(|source| ExperimentError::Config {
                path: config_file.map_or_else(|| name.clone().into(), Path::to_path_buf),
                source: Box::new(source),
            })?;
            Ok(PlannedExperiment {
                name,
                title,
                paper_maze,
                experiment,
            })
        })
        .collect()
}

/// Method labels for people.
pub(crate) fn method_title(label: &str) -> String {
    match label {
        "ea-madm" => "EA-MADM".to_owned(),
        "epsilon-greedy" => "ε-greedy".to_owned(),
        "epsilon-decreasing" => "ε-decreasing".to_owned(),
        "softmax" => "softmax".to_owned(),
        other => other.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quick_shortens_every_part() {
        let config = quick(ExperimentConfig::paper_task1());
        assert_eq!(config.episodes, QUICK_EPISODES);
        assert_eq!(config.task.step_cap(), Some(QUICK_MAZE_STEP_CAP));
        for spec in &config.methods {
            if let Method::EaMadm(ea) = &spec.method {
                assert_eq!(ea.pretrain.episodes, QUICK_EPISODES);
            }
        }
        assert!(config.validate().is_ok());
        let robot = quick(ExperimentConfig::paper_robot());
        assert_eq!(robot.task.step_cap(), None);
    }

    #[test]
    fn presets_are_planned_with_the_given_seeds() {
        let planned = plan_experiments(&Task::ALL, false, None, 2, true).unwrap();
        let names: Vec<&str> = planned.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(names, ["task1", "task2", "robot"]);
        assert!(planned.iter().all(|p| p.config().seeds == 2));
        assert_eq!(planned[0].paper_maze, Some(Preset::Task1));
        assert_eq!(planned[2].paper_maze, None);
    }

    #[test]
    fn a_bad_config_file_names_the_field() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.toml");
        let text = eamadm::PAPER_TASK1_TOML.replace("episodes = 200", "episodes = 0");
        std::fs::write(&path, text).unwrap();
        let error = plan_experiments(&[], false, Some(&path), 3, false).unwrap_err();
        assert!(error.to_string().contains("`episodes` = 0"), "{error}");
        std::fs::write(&path, eamadm::PAPER_TASK1_TOML).unwrap();
        let error = plan_experiments(&[Task::Task1], true, Some(&path), 3, false).unwrap_err();
        assert!(matches!(error, ExperimentError::TaskWithConfig));
    }
}
