//! Does the decision step ever help? (issue 32; docs/paper-notes.md §21): EA-MADM's decision
//! and the plain aggregators fed the best sub-task values available, exactly as a run feeds
//! its learned ones.
//!
//! On a maze the model is known, small and deterministic, so every sub-task's exact `Q*` is
//! computed by value iteration ([`dql::value_iteration`] on [`mazes::MazeEnv::subtask_model`],
//! γ of the experiment's learner). On the robot no model is known: the sub-tasks pre-trained
//! by the method's own pre-training (the presets' stopping rule, "to convergence") are the best
//! estimate available, and the rows say so ([`OracleValues::PretrainedToConvergence`]).
//!
//! Those values go into a [`PriorTable`] (every pair answered) and through the method's own
//! [`EaMadmPolicy`]: the same decision matrix (Eq. 13), column scaling, OWA weighting and
//! tie-breaks as in its runs, with the source task's own column twice: at the source learner's
//! initial values (the decision as it first guides learning) and at the values the method's
//! run learned (the run is repeated, a pure function of config and seed, to recover its
//! learner). Each row plays the decision's greedy episode from the run's evaluation start and,
//! on a maze, measures the share of states whose decision is a shortest-path action. Each
//! sub-task acting alone on the same values gives the rows to compare with.
//!
//! ```no_run
//! use eamadm::{Experiment, NoPretrainingCache, paper};
//!
//! let experiment = Experiment::new(paper::task1())?;
//! let rows = eamadm::oracle::oracle_rows(&experiment, &NoPretrainingCache)?;
//! for row in rows.iter().filter(|row| row.seed == 0) {
//!     println!("{} ({:?}): reached {} in {} steps", row.decision, row.own_values, row.reached, row.greedy_steps);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use dql::{DoubleQ, Environment, Greedy, Learner, QTable, value_iteration};
use rayon::prelude::*;

use crate::agent::EaMadmPolicy;
use crate::config::{EaMadmConfig, Method, MethodSpec};
use crate::error::{RunError, RunFailure};
use crate::prior::{PriorTable, build_prior};
use crate::rng::{Stream, stream_rng};
use crate::runner::{Experiment, PretrainingCache, greedy_episode};
use crate::task::{Counting, TaskEnv, TaskKind};
use wmr_model::SubtaskRepairs;

pub use eamadm_eval::oracle::{
    FailingPart, ORACLE_COLUMNS, OracleError, OracleFinding, OracleRow, OracleValues, OwnValues,
    PRETRAINING_COLUMNS, PretrainingRow, PretrainingSummary, oracle_findings, pretraining_rows,
    pretraining_summary, reach_pretraining, read_csv, read_pretraining_csv, write_csv,
    write_pretraining_csv,
};

/// The decision rules the oracle feeds, by label, when the experiment has them: EA-MADM and
/// the two plain aggregators.
pub const DECISIONS: [&str; 3] = ["ea-madm", "subtasks-mean", "subtasks-max"];

/// Value iteration stops within this distance of `Q*` in every cell.
const TOLERANCE: f64 = 1e-9;

/// The oracle rows of `experiment` (see the module docs): for each decision of [`DECISIONS`]
/// the experiment has (an EA-MADM method on the paper's sub-task rewards), its initial-values
/// row then its learned-values row for every seed; then each sub-task alone for every seed.
/// Sub-tasks are taken from `cache` where it holds them (a run store's pre-trained artefacts)
/// and trained otherwise. Empty when the experiment has none of the decisions.
///
/// # Errors
/// [`RunError`] naming the method and seed whose run (repeated for its learned values) or
/// pre-training failed.
pub fn oracle_rows(
    experiment: &Experiment,
    cache: &dyn PretrainingCache,
) -> Result<Vec<OracleRow>, RunError> {
    oracle_rows_of(experiment, cache, |_| true)
}

/// [`oracle_rows`] for the decisions whose label `planned` accepts only: a plan that runs some
/// of the experiment's methods (`reproduce-paper --method`) has no oracle rows for the others.
/// Each decision's rows repeat that method's run once per seed, so an oracle of a method the
/// plan does not run would cost as much as running it (docs/paper-notes.md §24.2).
///
/// # Errors
/// As [`oracle_rows`].
pub fn oracle_rows_of(
    experiment: &Experiment,
    cache: &dyn PretrainingCache,
    planned: impl Fn(&str) -> bool,
) -> Result<Vec<OracleRow>, RunError> {
    let decisions: Vec<(&MethodSpec, &EaMadmConfig)> = DECISIONS
        .iter()
        .filter(|label| planned(label))
        .filter_map(|label| experiment.config().method(label))
        .filter_map(|spec| match &spec.method {
            Method::EaMadm(ea) if ea.subtask_rewards == SubtaskRepairs::PAPER => Some((spec, ea)),
            _ => None,
        })
        .collect();
    if decisions.is_empty() {
        return Ok(Vec::new());
    }
    let seeds: Vec<u64> = experiment.config().seed_values().collect();
    let per_seed: Vec<SeedRows> = match experiment.task().kind() {
        TaskKind::Maze(env) => {
            let exact = exact_values(env.as_ref(), experiment.config().learner.gamma)?;
            let facts = MazeFacts::of(env.as_ref());
            seeds
                .par_iter()
                .map(|&seed| {
                    seed_rows(experiment, env.as_ref(), &decisions, seed, cache, |_| {
                        Ok((exact.clone(), OracleValues::Exact, Some(&facts)))
                    })
                })
                .collect::<Result<_, _>>()?
        }
        TaskKind::Robot(env) => seeds
            .par_iter()
            .map(|&seed| {
                seed_rows(
                    experiment,
                    env.as_ref(),
                    &decisions,
                    seed,
                    cache,
                    |shared| {
                        let (spec, ea) = decisions[0];
                        let learners: Vec<DoubleQ> = (0..env.n_subtasks())
                            .map(|k| {
                                shared
                                    .subtask(&ea.pretrain, k)
                                    .map(|subtask| subtask.learner.clone())
                                    .ok_or_else(|| {
                                        RunError::new(
                                            &spec.label,
                                            seed,
                                            RunFailure::Learning(
                                                dql::DqlError::SubtaskOutOfRange {
                                                    index: k,
                                                    n_subtasks: env.n_subtasks(),
                                                },
                                            ),
                                        )
                                    })
                            })
                            .collect::<Result<_, _>>()?;
                        Ok((learners, OracleValues::PretrainedToConvergence, None))
                    },
                )
            })
            .collect::<Result<_, _>>()?,
    };
    // Decision-major, then initial before learned, then seed; then the sub-tasks alone.
    let mut rows = Vec::new();
    for index in 0..decisions.len() {
        for own in 0..2 {
            rows.extend(
                per_seed
                    .iter()
                    .map(|seed| seed.decisions[index][own].clone()),
            );
        }
    }
    let n_subtasks = per_seed.first().map_or(0, |seed| seed.alone.len());
    for k in 0..n_subtasks {
        rows.extend(per_seed.iter().map(|seed| seed.alone[k].clone()));
    }
    Ok(rows)
}

/// One seed's rows: per decision `[initial, learned]`, then per sub-task its row alone.
struct SeedRows {
    decisions: Vec<[OracleRow; 2]>,
    alone: Vec<OracleRow>,
}

/// What a maze's rows need beyond the values: the states the learner acts from, each one's
/// shortest-path actions, and the Manhattan distance.
struct MazeFacts {
    /// Per live state: its index and its shortest-path actions (as a bit set).
    live: Vec<(usize, u32)>,
    manhattan: u64,
}

impl MazeFacts {
    fn of(env: &mazes::MazeEnv) -> Self {
        let maze = env.maze();
        let target = maze.target();
        let to_target = maze.distances_from(target);
        let model = env.task_model();
        // Free tiles reachable from the start without passing the target (reaching it ends the
        // episode), the target excluded.
        let mut seen = vec![false; maze.n_tiles()];
        let start = maze.state_of(maze.start()).expect("the start is a tile");
        let mut stack = vec![start];
        seen[start] = true;
        let mut live = Vec::new();
        while let Some(state) = stack.pop() {
            let mut optimal = 0_u32;
            for action in 0..model.n_actions() {
                let step = model.transition(state, action);
                let closer = match (to_target[state], to_target[step.next]) {
                    (Some(here), Some(there)) => there + 1 == here,
                    _ => false,
                };
                if closer {
                    optimal |= 1 << action;
                }
                if !step.terminal && !seen[step.next] {
                    seen[step.next] = true;
                    stack.push(step.next);
                }
            }
            live.push((state, optimal));
        }
        live.sort_unstable();
        Self {
            live,
            manhattan: maze.start().manhattan(target) as u64,
        }
    }

    /// The mean over live states of the chance that an argmax of `values(state)` (ties broken
    /// uniformly) is a shortest-path action.
    fn optimal_share(&self, mut values: impl FnMut(usize) -> Vec<f64>) -> f64 {
        let total: f64 = self
            .live
            .iter()
            .map(|&(state, optimal)| {
                let row = values(state);
                let best = row.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let tied: Vec<usize> = (0..row.len()).filter(|&a| row[a] == best).collect();
                let good = tied.iter().filter(|&&a| optimal >> a & 1 == 1).count();
                good as f64 / tied.len().max(1) as f64
            })
            .sum();
        total / self.live.len().max(1) as f64
    }
}

/// Each sub-task's exact `Q*` on the maze, as a learner whose two tables both hold it.
fn exact_values(env: &mazes::MazeEnv, gamma: f64) -> Result<Vec<DoubleQ>, RunError> {
    let fail = |error| RunError::new("oracle", 0, RunFailure::Learning(error));
    (0..env.n_subtasks())
        .map(|k| {
            let model = env
                .subtask_model(k)
                .expect("k is below the task's sub-task count");
            let q = value_iteration(&model, gamma, TOLERANCE).map_err(fail)?.q;
            DoubleQ::from_tables(dql::DoubleQParams::default(), &q, &q).map_err(fail)
        })
        .collect()
}

/// The rows of one seed on the environment `env`; `values` gives the sub-tasks' learners, their
/// kind and (for a maze) its facts, from the seed's shared pre-training.
fn seed_rows<'f, E: TaskEnv>(
    experiment: &Experiment,
    env: &E,
    decisions: &[(&MethodSpec, &EaMadmConfig)],
    seed: u64,
    cache: &dyn PretrainingCache,
    values: impl FnOnce(
        &crate::runner::SharedPretraining,
    ) -> Result<(Vec<DoubleQ>, OracleValues, Option<&'f MazeFacts>), RunError>,
) -> Result<SeedRows, RunError> {
    let config = experiment.config();
    let methods: Vec<&MethodSpec> = decisions.iter().map(|(spec, _)| *spec).collect();
    let shared = experiment.share_pretraining_with(&methods, seed, cache);
    let (subtasks, kind, facts) = values(&shared)?;
    let (n_states, n_actions) = (env.n_states(), env.n_actions());
    let prior = match kind {
        OracleValues::Exact => {
            let tables: Vec<QTable> = subtasks.iter().map(DoubleQ::q1_table).collect();
            PriorTable::from_fn(n_states, n_actions, subtasks.len(), |k, s, a| {
                Some(tables[k].get(s, a))
            })
        }
        OracleValues::PretrainedToConvergence => {
            let (spec, ea) = decisions[0];
            let learners: Vec<&DoubleQ> = subtasks.iter().collect();
            build_prior(env, &learners, &ea.storage)
                .map_err(|error| RunError::new(&spec.label, seed, RunFailure::from(error)))?
                .0
        }
    };
    let row =
        |decision: &str, own_values, episode: &crate::record::EpisodeRecord, share| OracleRow {
            task: config.name.clone(),
            decision: decision.to_owned(),
            values: kind,
            own_values,
            seed,
            optimal_share: share,
            greedy_steps: episode.steps,
            reached: episode.reached,
            collisions: episode.collisions,
            task_return: episode.task_return,
            optimum_steps: experiment.task().optimum_steps(),
            manhattan_steps: facts.map(|facts| facts.manhattan),
            step_cap: experiment.task().step_cap(),
        };
    let mut rows = SeedRows {
        decisions: Vec::new(),
        alone: Vec::new(),
    };
    for (spec, ea) in decisions {
        let fail = |source: RunFailure| RunError::new(&spec.label, seed, source);
        let initial = DoubleQ::new(
            n_states,
            n_actions,
            config.learner,
            &mut stream_rng(seed, Stream::SourceInit),
        )
        .map_err(|error| fail(error.into()))?;
        let (_, learned) = experiment.run_with_learner(spec, seed, &shared)?;
        let mut pair = Vec::with_capacity(2);
        for (own_values, mut learner) in
            [(OwnValues::Initial, initial), (OwnValues::Learned, learned)]
        {
            let mut policy = EaMadmPolicy::new(prior.clone(), ea.epsilon, ea.weighting.clone())
                .map_err(|error| fail(error.into()))?
                .with_normalisation(ea.normalisation)
                .without_exploration();
            let (_, episode) = greedy_episode(
                &mut Counting::new(env.clone()),
                &mut learner,
                &mut policy,
                config.episodes,
                seed,
                false,
            )
            .map_err(|error| fail(error.into()))?;
            if let Some(error) = policy.failure() {
                return Err(fail(RunFailure::Decision(error.clone())));
            }
            let share = facts.map(|facts| {
                let mut own = vec![0.0; n_actions];
                facts.optimal_share(|state| {
                    learner.action_values(state, &mut own);
                    policy.evaluations(state, &own).to_vec()
                })
            });
            pair.push(row(&spec.label, own_values, &episode, share));
        }
        let learned = pair.pop().expect("two rows");
        let initial = pair.pop().expect("two rows");
        rows.decisions.push([initial, learned]);
    }
    for (k, subtask) in subtasks.iter().enumerate() {
        let label = format!("subtask{k}-alone");
        let mut learner = subtask.clone();
        let (_, episode) = greedy_episode(
            &mut Counting::new(env.clone()),
            &mut learner,
            &mut Greedy,
            config.episodes,
            seed,
            false,
        )
        .map_err(|error| RunError::new(&label, seed, RunFailure::Learning(error)))?;
        let share = facts.map(|facts| {
            let mut values = vec![0.0; n_actions];
            facts.optimal_share(|state| {
                subtask.action_values(state, &mut values);
                values.clone()
            })
        });
        rows.alone
            .push(row(&label, OwnValues::None, &episode, share));
    }
    Ok(rows)
}
