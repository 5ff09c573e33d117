//! Experience-aggregative RL with multi-attribute decision-making (EA-MADM): the method, its
//! competitors and the experiment runner.
//!
//! (Guide to come.)

pub use dql;
pub use ea_tree;
pub use madm_owa;
pub use mazes;
pub use reward_std;
pub use wmr_model;

pub mod agent;
pub mod config;
pub mod error;
pub mod pretrain;
pub mod prior;
pub mod record;
pub mod results;
mod rng;
pub mod runner;
pub mod signal;
mod strict;
pub mod summary;
pub mod task;

pub use agent::{EaMadmPolicy, PolicyError};
pub use config::{
    ConfigError, EaMadmConfig, ExperimentConfig, Method, MethodSpec, PAPER_ROBOT_TOML,
    PAPER_TASK1_TOML, PAPER_TASK2_TOML, PretrainConfig, Storage, TaskConfig, TrajectoryConfig,
    paper_methods,
};
pub use error::{RunError, RunFailure};
pub use pretrain::{PretrainedSubtask, pretrain_subtasks};
pub use prior::{PriorTable, build_prior};
pub use record::{EpisodeRecord, RobotEpisodeMetrics, RunRecord, SubtaskRecord, TrajectoryRecord};
pub use runner::{Experiment, run, run_all};
pub use signal::StandardisedReward;
pub use summary::{DEFAULT_FINAL_WINDOW, MethodSummary, RobotSummary, SeedSummary, summarise};
pub use task::Task;
