//! What one run produces: the per-episode curve, kept trajectories, the greedy evaluation and
//! the sub-tasks' pre-training, as serde data.

use serde::{Deserialize, Serialize};

/// Everything one run (one method, one seed) produced. A pure function of
/// `(config, method, seed)`: the same inputs give a bit-identical record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// The experiment's name (`eamadm::ExperimentConfig::name`).
    pub experiment: String,
    /// The method's label.
    pub method: String,
    /// The run's seed.
    pub seed: u64,
    /// Length of the task's optimal route in steps, when known: the BFS shortest path for a
    /// maze. Curves are compared with it.
    pub optimum_steps: Option<u64>,
    /// Sub-task pre-training (EA-MADM: every sub-task in order; a sub-task alone: its one
    /// sub-task; empty for the competitors).
    pub subtasks: Vec<SubtaskRecord>,
    /// Environment steps spent before the recorded episodes: EA-MADM's (or a sub-task
    /// alone's) sub-task pre-training, a budget-matched competitor's warm-up, 0 for the
    /// paper's competitors. The paper does not count them; every cumulative count here does
    /// (`episodes[i].env_steps`, so steps can be drawn against cumulative steps).
    pub pretrain_env_steps: u64,
    /// One record per training episode of the source task, in order.
    pub episodes: Vec<EpisodeRecord>,
    /// Environment steps of the whole run: pre-training plus training (not the evaluation).
    pub total_env_steps: u64,
    /// Trajectories of the training episodes the config keeps.
    pub trajectories: Vec<TrajectoryRecord>,
    /// The periodic greedy evaluations during training, in order: after every `k`-th training
    /// episode (`k` = the config's `evaluation.every`), one episode of the policy as it is
    /// then, without exploration and without learning, on random streams of their own (so
    /// training is the same with or without them). In each, `episode` is the number of
    /// training episodes done before it (`k`, `2k`, …), `env_steps` the run's cumulative
    /// training steps at that point (its own steps are counted nowhere), `learning_return` 0.
    /// C3's greedy fluctuation is measured on them. Empty in records made before they existed.
    #[serde(default)]
    pub greedy_evaluations: Vec<EpisodeRecord>,
    /// The greedy evaluation episode after training (no exploration, no learning).
    pub evaluation: EpisodeRecord,
    /// The evaluation episode's trajectory.
    pub evaluation_trajectory: TrajectoryRecord,
    /// Training episodes in the final window that [`final_window_actions`](Self::final_window_actions)
    /// and [`agreement`](Self::agreement) count over: the last
    /// [`DEFAULT_FINAL_WINDOW`](crate::summary::DEFAULT_FINAL_WINDOW) episodes (all of them in a shorter run).
    #[serde(default)]
    pub final_window_episodes: u64,
    /// How often each action was taken in the final window, one count per action (every
    /// method; exploring steps included). Sums to the steps of the window's episodes.
    #[serde(default)]
    pub final_window_actions: Vec<u64>,
    /// EA-MADM only: how often its exploitation choice equals each sub-task's own greedy
    /// choice, over the final window and over all source-task training; `None` otherwise.
    #[serde(default)]
    pub agreement: Option<AgreementRecord>,
}

/// How often EA-MADM's exploitation choice agrees with each sub-task's greedy argmax.
///
/// Only exploitation steps count (the ε coin said "exploit" and the MADM decision chose):
/// exploring steps choose at random and say nothing about the decision rule. A sub-task's
/// greedy choice is the argmax of its pre-trained learner's behaviour values
/// (`(Q1 + Q2) / 2`) in the state; when several actions share the maximum, the step *agrees*
/// if the chosen action is one of them.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct AgreementRecord {
    /// Over the final window's episodes.
    pub final_window: AgreementCounts,
    /// Over every training episode of the source task (the final window included).
    pub training: AgreementCounts,
}

/// Agreement counts over a set of episodes (see [`AgreementRecord`]).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct AgreementCounts {
    /// Exploitation steps (MADM decisions).
    pub decisions: u64,
    /// Per sub-task (in sub-task order): decisions equal to (one of) its argmax actions.
    /// Each is at most `decisions`.
    pub agrees: Vec<u64>,
    /// Decisions agreeing with every sub-task at once (at most the smallest of `agrees`).
    pub agrees_with_all: u64,
    /// Decisions in a state where at least one sub-task had no prior experience for at least
    /// one action (its attribute dropped out of that action's row).
    pub missing_experience: u64,
}

/// One episode of the source task.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EpisodeRecord {
    /// 0-based episode index (for the evaluation: the number of training episodes).
    pub episode: u64,
    /// Environment steps of this episode.
    pub steps: u64,
    /// Sum of the task's own rewards (what the paper's reward curves plot).
    pub task_return: f64,
    /// Sum of the rewards the learner learned from (the standardised signal for EA-MADM,
    /// equal to `task_return` for the competitors; 0 without learning).
    pub learning_return: f64,
    /// The episode ended inside the task (target reached, obstacle hit, target lost).
    pub terminated: bool,
    /// The episode was cut by the step cap.
    pub truncated: bool,
    /// The target was reached.
    pub reached: bool,
    /// Collisions in the episode: bumps for a maze (the agent stays), hits for the robot.
    pub collisions: u64,
    /// Environment steps consumed so far in this run, this episode included, *including
    /// sub-task pre-training*. For the evaluation: the run's total (training) steps.
    pub env_steps: u64,
    /// The robot task's per-episode metrics (Sec. VI.B); `None` for mazes.
    pub robot: Option<RobotEpisodeMetrics>,
}

/// The robot task's metrics of one episode (Sec. VI.B, Fig. 13–15).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RobotEpisodeMetrics {
    /// Duration of the episode in seconds.
    pub time: f64,
    /// Return divided by the episode's duration (reward per second).
    pub average_reward: f64,
    /// Time to reach the target in seconds; `None` when it was not reached.
    pub time_to_reach: Option<f64>,
    /// Time spent stalled in front of an obstacle, in seconds.
    pub retention_time: f64,
}

/// The states, actions and positions of one episode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrajectoryRecord {
    /// The episode (for the evaluation: the number of training episodes).
    pub episode: u64,
    /// `true` for the greedy evaluation episode.
    pub greedy: bool,
    /// Visited states, starting with the initial one (`actions.len() + 1` entries).
    pub states: Vec<usize>,
    /// Chosen actions.
    pub actions: Vec<usize>,
    /// Positions along the episode, one per state: tile `[x, y]` for a maze (column, row from
    /// the top), `[x, y]` in metres for the robot.
    pub positions: Vec<[f64; 2]>,
}

/// The pre-training of one sub-task of an EA-MADM run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SubtaskRecord {
    /// The sub-task's name (e.g. `reach the target faster`).
    pub name: String,
    /// Pre-training episodes.
    pub episodes: u64,
    /// Environment steps they consumed.
    pub env_steps: u64,
    /// Steps of the last pre-training episode.
    pub last_episode_steps: u64,
    /// State–action pairs the sub-task's learner updated at least once (its experience).
    pub visited_pairs: u64,
    /// Clusters of its EA tree (`None` with table storage).
    pub clusters: Option<u64>,
    /// State–action pairs of the task for which the source task finds prior experience.
    pub answered_pairs: u64,
    /// Experience samples inserted into its EA tree (`None` with table storage): the
    /// visited pairs.
    #[serde(default)]
    pub tree_samples: Option<u64>,
    /// Estimated heap bytes of its EA tree, clusters and lookup index
    /// (`ea_tree::TreeStats::bytes`); `None` with table storage.
    #[serde(default)]
    pub tree_bytes: Option<u64>,
    /// Bytes of the dense double-Q tables the tree stands in for: two `f64` per
    /// state–action pair of the task.
    #[serde(default)]
    pub table_bytes: u64,
    /// The sub-task's pre-trained greedy policy by itself on the task: one greedy episode
    /// without learning, on the same start as the run's evaluation episode (its
    /// `task_return` is the task's reward; `env_steps` is this episode's steps alone).
    #[serde(default)]
    pub greedy_alone: Option<EpisodeRecord>,
    /// The pre-trained learner's behaviour values `(Q1 + Q2) / 2` of each action in the
    /// task's start state: what the sub-task learned to expect from the start (e.g. close to
    /// `r / (1 − γ)` for a learner paid `r` per step that learned to idle).
    #[serde(default)]
    pub start_values: Vec<f64>,
    /// Pre-training episodes (not the stopping rule's checks) that reached the target.
    #[serde(default)]
    pub reached_episodes: u64,
    /// With the stopping rule of pre-training "to convergence": whether it found the sub-task
    /// converged (`false`: it stopped at its cap of episodes); `None` for a fixed number of
    /// episodes.
    #[serde(default)]
    pub converged: Option<bool>,
    /// The stopping rule's greedy check episodes (0 without a rule).
    #[serde(default)]
    pub checks: u64,
    /// Environment steps of those checks (included in `env_steps`).
    #[serde(default)]
    pub check_env_steps: u64,
    /// Whether the last check's greedy episode reached the target (`None` without checks).
    #[serde(default)]
    pub last_check_reached: Option<bool>,
}
