//! The experiments a `reproduce-paper` invocation runs: the paper presets of the selected tasks
//! (or the one `--config` file), shortened for `--quick`, with `--seeds` applied, each loaded
//! into an [`eamadm::Experiment`] — all checked before anything is written.

use std::path::Path;

use eamadm::paper::Reading;
use eamadm::{ConfigError, Experiment, ExperimentConfig, Shortening};
use thiserror::Error;

use crate::cli::Readings;
use eamadm::paper::PaperTask;

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
    /// The loaded experiment (config with `--seeds` and `--quick` applied).
    pub(crate) experiment: Experiment,
    /// For a reading's experiment (the methods a reading of the paper reruns on a paper task,
    /// [`eamadm::paper::Reading`]): the reading and the index of its base experiment in the
    /// plan. Such experiments come after every base experiment, write no tables or figures of
    /// their own and feed `sensitivity.csv`; `None` for the base experiments.
    pub(crate) reading: Option<(Reading, usize)>,
    /// For an experiment of `--suite tuning` (a trial on the tuning seeds, or a method's
    /// chosen trial on the held-out seeds): which, and the index of its base experiment. Such
    /// experiments come after the others, write no tables or figures of their own and feed
    /// `tuning.csv` and the "each at its best" verdicts; `None` otherwise.
    pub(crate) tuning: Option<crate::tuning_suite::TuningRun>,
    /// For a layout of `--suite family`: the layout's row of `layouts.csv`. Such experiments
    /// write no tables or figures of their own (their final scores join `final-scores.csv`
    /// and the pooled verdicts); `None` otherwise.
    pub(crate) family: Option<eamadm::family::LayoutRow>,
}

impl PlannedExperiment {
    /// The config actually run.
    pub(crate) fn config(&self) -> &ExperimentConfig {
        self.experiment.config()
    }
}

/// Reads and parses a `--config` file, once (its task is loaded, and so checked, when the
/// experiment is planned).
pub(crate) fn load_config_file(path: &Path) -> Result<ExperimentConfig, ExperimentError> {
    let error = |source| ExperimentError::Config {
        path: path.to_path_buf(),
        source: Box::new(source),
    };
    let text = eamadm::read_input_file(path, "--config").map_err(error)?;
    ExperimentConfig::from_toml_str(&text).map_err(error)
}

/// `config` shortened to a smoke run: [`Shortening::QUICK`], the facade's one definition of
/// `--quick` (which Python's `eamadm.run(..., quick=True)` applies too).
pub(crate) fn quick(config: &ExperimentConfig) -> ExperimentConfig {
    config.shortened(&Shortening::QUICK)
}

/// The experiments to run: one per selected task (its preset), or the `--config` file's one
/// (read once by [`load_config_file`]: its path and config); `seeds` per method, shortened when
/// `quick`. Each experiment (and so its task: a maze's BFS, the robot's planner) is built once.
/// After the presets come their readings' experiments ([`reading_experiments`]) when `readings`
/// is [`Readings::All`]; a config file has none (the readings are readings of the paper's
/// presets).
pub(crate) fn plan_experiments(
    tasks: &[PaperTask],
    tasks_given: bool,
    config_file: Option<(&Path, &ExperimentConfig)>,
    seeds: u32,
    quick_run: bool,
    readings: Readings,
) -> Result<Vec<PlannedExperiment>, ExperimentError> {
    let mut configs: Vec<(String, ExperimentConfig)> = Vec::new();
    match config_file {
        Some((_, config)) => {
            if tasks_given {
                return Err(ExperimentError::TaskWithConfig);
            }
            configs.push((config.name.clone(), config.clone()));
        }
        None => {
            for &task in tasks {
                configs.push((task.title().to_owned(), task.config()));
            }
        }
    }
    let planned: Vec<PlannedExperiment> = configs
        .into_iter()
        .map(|(title, mut config)| {
            config.seeds = seeds;
            if quick_run {
                config = quick(&config);
            }
            let name = config.name.clone();
            let experiment = Experiment::new(config).map_err(|source| ExperimentError::Config {
                path: config_file
                    .map_or_else(|| name.clone().into(), |(path, _)| path.to_path_buf()),
                source: Box::new(source),
            })?;
            Ok(PlannedExperiment {
                name,
                title,
                experiment,
                reading: None,
                tuning: None,
                family: None,
            })
        })
        .collect::<Result<_, ExperimentError>>()?;
    if config_file.is_some() || readings == Readings::None {
        return Ok(planned);
    }
    let readings = reading_experiments(&planned)?;
    Ok([planned, readings].concat())
}

/// The experiments of every reading of the paper ([`eamadm::paper::readings`]) on each of
/// `bases` it changes, reading-major: each base's config (seeds and `--quick` applied) with the
/// reading's change and only the methods it reruns.
pub(crate) fn reading_experiments(
    bases: &[PlannedExperiment],
) -> Result<Vec<PlannedExperiment>, ExperimentError> {
    let mut planned = Vec::new();
    for &reading in eamadm::paper::readings() {
        for (index, base) in bases.iter().enumerate() {
            let Some(config) = reading.apply(base.config()) else {
                continue;
            };
            let name = config.name.clone();
            let experiment = Experiment::new(config).map_err(|source| ExperimentError::Config {
                path: name.clone().into(),
                source: Box::new(source),
            })?;
            planned.push(PlannedExperiment {
                title: format!("{} under the reading {}", base.title, reading.name()),
                name,
                experiment,
                reading: Some((reading, index)),
                tuning: None,
                family: None,
            });
        }
    }
    Ok(planned)
}

/// The experiments of `--suite family`: one per layout of the first `size` of the family
/// ([`eamadm::family::maze_family`]), as [`eamadm::family::FamilyLayout::experiment`] defines
/// it; shortened when `quick_run`; on `seeds` seeds when given (`--seeds`), else on the
/// family's own ([`eamadm::family::FAMILY_SEEDS`], [`crate::plan::QUICK_SEEDS`] when quick).
pub(crate) fn family_experiments(
    size: usize,
    seeds: Option<u32>,
    quick_run: bool,
) -> Result<Vec<PlannedExperiment>, crate::Failure> {
    let family = eamadm::family::maze_family(size)
        .map_err(|error| crate::Failure::invalid(format!("--family-size {size}: {error}")))?;
    family
        .iter()
        .map(|layout| {
            let mut config = layout.experiment();
            if quick_run {
                config = quick(&config);
                config.seeds = crate::plan::QUICK_SEEDS;
            }
            if let Some(seeds) = seeds {
                config.seeds = seeds;
            }
            let name = config.name.clone();
            let experiment = Experiment::new(config)
                .map_err(|error| crate::Failure::invalid(format!("{name}: {error}")))?;
            Ok(PlannedExperiment {
                title: format!("Family layout {}", layout.name),
                name,
                experiment,
                reading: None,
                tuning: None,
                family: Some(layout.row()),
            })
        })
        .collect()
}
