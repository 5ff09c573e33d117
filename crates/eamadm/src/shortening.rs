//! Shorter versions of an experiment: the one rule by which `cargo xtask reproduce-paper --quick`,
//! the reference fixtures and the Python package's `eamadm.run(..., episodes=, quick=)` cut a
//! config down, so that "as `--quick` does" means the same thing everywhere.
//!
//! [`ExperimentConfig::shortened`] applies a [`Shortening`]:
//!
//! - **episodes**: the source task trains `min(episodes, config.episodes)` episodes; every
//!   pre-training (EA-MADM's sub-tasks, a sub-task alone) at most `episodes`, and a
//!   pre-training stopping rule's cap (`Convergence::max_episodes`) in the same proportion
//!   as its fewest episodes, `⌊cap · fewest_after / fewest_before⌋`, never below the new
//!   fewest; the trajectory episodes past the new end are dropped;
//! - **warm-up budgets** of ε-greedy and softmax competitors shrink in proportion to the
//!   episodes, `⌊budget · episodes_after / episodes_before⌋` (a budget written for the full run,
//!   as pre-training shrinks with it), then are capped at `max_warmup_env_steps`;
//! - **step caps**: a maze task's at most `maze_step_cap`, the robot's at most
//!   `robot_step_cap` (the task's own when it is lower).
//!
//! Seeds are not part of it: `--quick` runs [`QUICK_SEEDS`] seeds unless `--seeds` says
//! otherwise, and so does Python's `quick=True` unless `seeds=` does.
//!
//! ```
//! use eamadm::{Shortening, paper};
//!
//! let quick = paper::task1().shortened(&Shortening::QUICK);
//! assert_eq!(quick.episodes, 30);
//! assert_eq!(quick.task.step_cap(), Some(500));
//! // Only the episodes: the step cap stays the preset's (none set, so the maze's 2000).
//! let shorter = paper::task1().shortened(&Shortening::episodes(30));
//! assert_eq!((shorter.episodes, shorter.task.step_cap()), (30, None));
//! ```

use crate::config::{ExperimentConfig, Method, PretrainConfig, TaskConfig};

/// Seeds per method of a `--quick` run (and of Python's `run(..., quick=True)`).
pub const QUICK_SEEDS: u32 = 3;

/// How to shorten an experiment ([`ExperimentConfig::shortened`]); `None` leaves that part
/// as the config has it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Shortening {
    /// At most this many source-task episodes, and pre-training episodes.
    pub episodes: Option<u64>,
    /// Maze episodes capped at this many steps (a lower cap of the task's own is kept).
    pub maze_step_cap: Option<u32>,
    /// Robot episodes capped at this many steps (a lower cap of the task's own is kept).
    pub robot_step_cap: Option<u32>,
    /// Competitors' warm-up budgets capped at this many environment steps, after they shrank
    /// with the episodes.
    pub max_warmup_env_steps: Option<u64>,
}

impl Shortening {
    /// `cargo xtask reproduce-paper --quick`: 30 episodes (and pre-training episodes), maze
    /// episodes capped at 500 steps, the robot's cap kept, warm-ups at most 1 000 000 steps (far
    /// above the presets' shortened budgets, so a config's own budget cannot make a smoke run
    /// take minutes per run).
    pub const QUICK: Self = Self {
        episodes: Some(30),
        maze_step_cap: Some(500),
        robot_step_cap: None,
        max_warmup_env_steps: Some(1_000_000),
    };

    /// Only the episodes: at most `episodes` source and pre-training episodes, warm-ups in
    /// proportion, step caps kept.
    #[must_use]
    pub const fn episodes(episodes: u64) -> Self {
        Self {
            episodes: Some(episodes),
            maze_step_cap: None,
            robot_step_cap: None,
            max_warmup_env_steps: None,
        }
    }
}

impl ExperimentConfig {
    /// This config shortened by `shortening` (see the [module docs](crate::shortening) for
    /// exactly what changes). Shortening never lengthens: each part becomes the smaller of
    /// the config's and the shortening's. A config that validated still validates.
    #[must_use]
    pub fn shortened(&self, shortening: &Shortening) -> Self {
        let mut config = self.clone();
        if let Some(episodes) = shortening.episodes {
            shorten_episodes(&mut config, episodes);
        }
        if let Some(cap) = shortening.max_warmup_env_steps {
            for spec in &mut config.methods {
                if let Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } =
                    &mut spec.method
                {
                    training.warmup_env_steps = training.warmup_env_steps.min(cap);
                }
            }
        }
        let lower = |own: &mut Option<u32>, cap: Option<u32>| {
            if let Some(cap) = cap {
                *own = Some(own.map_or(cap, |own| own.min(cap)));
            }
        };
        match &mut config.task {
            TaskConfig::Maze { step_cap, .. }
            | TaskConfig::MazeFile { step_cap, .. }
            | TaskConfig::MazeText { step_cap, .. } => lower(step_cap, shortening.maze_step_cap),
            TaskConfig::Robot { step_cap, .. } => lower(step_cap, shortening.robot_step_cap),
        }
        config
    }
}

/// At most `episodes` source and pre-training episodes; warm-up budgets in proportion.
fn shorten_episodes(config: &mut ExperimentConfig, episodes: u64) {
    let episodes_before = config.episodes;
    config.episodes = config.episodes.min(episodes);
    let episodes_now = config.episodes;
    config.trajectories.episodes.retain(|&e| e < episodes_now);
    for spec in &mut config.methods {
        match &mut spec.method {
            Method::EaMadm(ea) => shorten_pretraining(&mut ea.pretrain, episodes),
            Method::SubtaskGreedy(alone) => shorten_pretraining(&mut alone.pretrain, episodes),
            // A budget written for the full run shrinks with the episodes, as pre-training
            // does (only roughly matched in a shortened run, whose step caps differ too).
            Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } => {
                training.warmup_env_steps = u64::try_from(
                    u128::from(training.warmup_env_steps) * u128::from(episodes_now)
                        / u128::from(episodes_before.max(1)),
                )
                .unwrap_or(u64::MAX);
            }
        }
    }
}

/// At most `episodes` pre-training episodes; a stopping rule's cap shrinks in the same
/// proportion, `⌊cap · fewest_after / fewest_before⌋`, never below the new fewest (so the
/// rule still validates).
fn shorten_pretraining(pretrain: &mut PretrainConfig, episodes: u64) {
    let before = pretrain.episodes;
    pretrain.episodes = before.min(episodes);
    if let Some(until) = pretrain.until.as_mut() {
        let scaled = u128::from(until.max_episodes) * u128::from(pretrain.episodes)
            / u128::from(before.max(1));
        until.max_episodes = u64::try_from(scaled)
            .unwrap_or(u64::MAX)
            .max(pretrain.episodes);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::paper;

    #[test]
    fn quick_shortens_every_part() {
        let config = paper::task1().shortened(&Shortening::QUICK);
        assert_eq!(config.episodes, 30);
        assert_eq!(config.task.step_cap(), Some(500));
        for spec in &config.methods {
            match &spec.method {
                Method::EaMadm(ea) => {
                    assert_eq!(ea.pretrain.episodes, 30);
                    // the stopping rule's cap shrinks with it: 1000 × 30 / 200
                    assert_eq!(ea.pretrain.until.map(|u| u.max_episodes), Some(150));
                }
                Method::SubtaskGreedy(alone) => {
                    assert_eq!(alone.pretrain.episodes, 30);
                    assert_eq!(alone.pretrain.until.map(|u| u.max_episodes), Some(150));
                }
                Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } => {
                    assert!(
                        training.warmup_env_steps
                            <= paper::PaperTask::Task1.pretrain_budget().unwrap() * 30 / 200
                    );
                }
            }
        }
        assert!(config.validate().is_ok());
        let robot = paper::robot().shortened(&Shortening::QUICK);
        assert_eq!(robot.task.step_cap(), paper::robot().task.step_cap());
        assert_eq!(robot.episodes, 30);
    }

    #[test]
    fn the_warm_up_cap_binds_only_above_it() {
        let mut huge = paper::task1();
        huge.episodes = 30;
        for spec in &mut huge.methods {
            if let Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } =
                &mut spec.method
            {
                training.warmup_env_steps = 1_000_000_000;
            }
        }
        let capped = huge.shortened(&Shortening::QUICK);
        let mut any = false;
        for spec in &capped.methods {
            if let Method::EpsilonGreedy { training, .. } | Method::Softmax { training, .. } =
                &spec.method
            {
                assert_eq!(training.warmup_env_steps, 1_000_000);
                any = true;
            }
        }
        assert!(any, "the preset has competitors with a warm-up");
        // On the presets the cap never binds: QUICK is the episodes and the step cap alone.
        for preset in [paper::task1(), paper::task2(), paper::robot()] {
            let without_cap = Shortening {
                max_warmup_env_steps: None,
                ..Shortening::QUICK
            };
            assert_eq!(
                preset.shortened(&Shortening::QUICK),
                preset.shortened(&without_cap)
            );
        }
    }

    #[test]
    fn shortening_never_lengthens_and_default_changes_nothing() {
        let preset = paper::task1();
        assert_eq!(preset.shortened(&Shortening::default()), preset);
        let longer = preset.shortened(&Shortening {
            episodes: Some(10_000),
            maze_step_cap: Some(u32::MAX),
            robot_step_cap: Some(1),
            max_warmup_env_steps: Some(u64::MAX),
        });
        assert_eq!(longer.episodes, preset.episodes);
        assert_eq!(longer.task.step_cap(), Some(u32::MAX));
        let mut capped = preset.clone();
        if let TaskConfig::Maze { step_cap, .. } = &mut capped.task {
            *step_cap = Some(100);
        }
        let kept = capped.shortened(&Shortening::QUICK);
        assert_eq!(
            kept.task.step_cap(),
            Some(100),
            "a lower cap of the task's own stays"
        );
    }

    #[test]
    fn episodes_alone_keep_the_step_cap_and_scale_the_warm_up() {
        let preset = paper::task2();
        let shorter = preset.shortened(&Shortening::episodes(20));
        assert_eq!(shorter.episodes, 20);
        assert_eq!(shorter.task.step_cap(), preset.task.step_cap());
        for (before, after) in preset.methods.iter().zip(&shorter.methods) {
            if let (
                Method::EpsilonGreedy { training: b, .. },
                Method::EpsilonGreedy { training: a, .. },
            ) = (&before.method, &after.method)
            {
                assert_eq!(
                    a.warmup_env_steps,
                    b.warmup_env_steps * 20 / preset.episodes
                );
            }
        }
        assert!(shorter.trajectories.episodes.iter().all(|&e| e < 20));
    }
}
