//! Can a table learner reach the target? Plain tabular Q-learning on variants of the default
//! scenario over the paper's literal state (no target feature), and with the target feature
//! added back, as evidence for the crate docs' "What a table learner can and cannot do here".
//!
//! `cargo run --release -p wmr-model --example learnability -- [episodes] [seeds]`
//!
//! Q-learning with α = 0.1, γ = 0.95, ε = 0.1, zero initial values and random tie-breaking, on
//! the task reward. Per variant: training episodes that reached the target (mean per seed),
//! the fraction of the last 500 that did, the mean closest approach (m) over those 500, and how
//! many seeds' greedy policy reaches the target.

use dql::Environment;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wmr_model::{
    DEFAULT_TARGET_BINS, EpisodeStatus, ObstacleSpec, Scenario, StateParams, TaskReward, WmrEnv,
};

const WINDOW: usize = 500;

/// What one seed's training produced.
struct Learnt {
    reached: usize,
    reached_in_window: usize,
    closest_in_window: f64,
    greedy_reaches: bool,
}

fn greedy(q: &[f64], state: usize, actions: usize, rng: &mut ChaCha8Rng) -> usize {
    let row = &q[state * actions..(state + 1) * actions];
    let best = row.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let ties: Vec<usize> = (0..actions).filter(|&a| row[a] == best).collect();
    ties[rng.random_range(0..ties.len())]
}

fn learn(
    scenario: &Scenario,
    seed: u64,
    episodes: usize,
) -> Result<Learnt, wmr_model::ScenarioError> {
    let mut env = WmrEnv::new(scenario.clone())?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let actions = env.n_actions();
    let mut q = vec![0.0; env.n_states() * actions];
    let target = scenario.target_point();
    let mut learnt = Learnt {
        reached: 0,
        reached_in_window: 0,
        closest_in_window: 0.0,
        greedy_reaches: false,
    };
    for episode in 0..episodes {
        let mut state = env.reset(Some(seed * 1_000_000 + episode as u64));
        let mut closest = f64::INFINITY;
        loop {
            let action = if rng.random_bool(0.1) {
                rng.random_range(0..actions)
            } else {
                greedy(&q, state, actions, &mut rng)
            };
            let step = env.step(action);
            let centre = env.path().last().copied().unwrap_or(target);
            closest = closest.min((target - centre).norm());
            let next = &q[step.next_state * actions..(step.next_state + 1) * actions];
            let bootstrap = if step.terminated {
                0.0
            } else {
                next.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            };
            let value = &mut q[state * actions + action];
            *value += 0.1 * (step.reward + 0.95 * bootstrap - *value);
            state = step.next_state;
            if step.done() {
                break;
            }
        }
        let reached = env.status() == EpisodeStatus::Reached;
        learnt.reached += usize::from(reached);
        if episode + WINDOW >= episodes {
            learnt.reached_in_window += usize::from(reached);
            learnt.closest_in_window += closest / WINDOW.min(episodes) as f64;
        }
    }
    let mut state = env.reset(Some(seed));
    loop {
        let step = env.step(greedy(&q, state, actions, &mut rng));
        state = step.next_state;
        if step.done() {
            break;
        }
    }
    learnt.greedy_reaches = env.status() == EpisodeStatus::Reached;
    Ok(learnt)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let episodes: usize = args.next().map_or(Ok(2000), |s| s.parse())?;
    let seeds: u64 = args.next().map_or(Ok(5), |s| s.parse())?;
    let mut default = Scenario::default_scenario();
    default.state = StateParams::paper();
    let variant = |edit: &dyn Fn(&mut Scenario)| {
        let mut scenario = default.clone();
        edit(&mut scenario);
        scenario
    };
    let variants = [
        ("default", default.clone()),
        (
            "default, subtask_sum",
            variant(&|s| s.reward.task = TaskReward::SubtaskSum),
        ),
        ("first cylinder only", variant(&|s| s.obstacles.truncate(1))),
        (
            "one cylinder beside line",
            variant(&|s| {
                // 2.3 cm clearance from the straight route.
                s.obstacles.truncate(1);
                if let ObstacleSpec::Circle { y, .. } = &mut s.obstacles[0] {
                    *y = 0.6;
                }
            }),
        ),
        (
            "reach radius 0.1 m",
            variant(&|s| s.target.reach_radius = 0.1),
        ),
        (
            "losing costs -100",
            variant(&|s| s.reward.target_lost = -100.0),
        ),
        ("150 deg view", variant(&|s| s.camera.horizontal_fov = 2.6)),
        ("empty arena", variant(&|s| s.obstacles.clear())),
        (
            "target feature (default)",
            variant(&|s| s.state.target_bins = DEFAULT_TARGET_BINS),
        ),
        (
            "empty arena, subtask_sum",
            variant(&|s| {
                s.obstacles.clear();
                s.reward.task = TaskReward::SubtaskSum;
            }),
        ),
    ];
    println!(
        "Q-learning, {episodes} episodes x {seeds} seeds; last {} episodes",
        WINDOW.min(episodes)
    );
    println!(
        "{:<26} {:>12} {:>12} {:>10} {:>10}",
        "variant", "reached/run", "last frac", "closest", "greedy ok"
    );
    for (name, scenario) in &variants {
        let (mut reached, mut window, mut closest, mut greedy_ok) = (0.0, 0.0, 0.0, 0);
        for seed in 0..seeds {
            let learnt = learn(scenario, seed, episodes)?;
            reached += learnt.reached as f64 / seeds as f64;
            window +=
                learnt.reached_in_window as f64 / (WINDOW.min(episodes) as f64 * seeds as f64);
            closest += learnt.closest_in_window / seeds as f64;
            greedy_ok += usize::from(learnt.greedy_reaches);
        }
        println!(
            "{name:<26} {reached:>12.1} {window:>12.3} {closest:>10.3} {greedy_ok:>7}/{seeds}"
        );
    }
    Ok(())
}
