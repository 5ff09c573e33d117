//! The ratios of issue 24, printed in one run so that every later change is judged by the same
//! numbers (`cargo bench -p eamadm-benches --bench ratios`; `-- --tiny` for a quick smoke run,
//! `-- --only robot_over_maze` for one of them):
//!
//! 1. the maze EA-MADM family (every method that pre-trains: EA-MADM, its ablations, the
//!    sub-tasks alone) on Task I, with the pre-training shared per seed
//!    ([`eamadm::Experiment::share_pretraining`]) against each run pre-training for itself;
//! 2. a robot step ÷ a maze step (random actions, resetting at episode ends; medians of
//!    alternating rounds);
//! 3. ns per environment step of the Task I ε-greedy runs (learning only, in process; and end
//!    to end, `reproduce-paper --task task1 --method epsilon-greedy` with `--readings none`
//!    and with its default `--readings all`, store and report included, each divided by the
//!    steps of every run it executed, when the release `xtask` binary is built) ÷ the
//!    hand-written [`eamadm_benches::reference_double_q`] loop; and the `--readings none`
//!    command ÷ what the hand-written loops take for exactly its work, its learning steps at
//!    the cost of one of that loop's and its greedy evaluation steps at the cost of one of
//!    [`eamadm_benches::reference_double_q_evaluated`]'s. The `--readings none` ratios are
//!    medians of [`END_TO_END_ROUNDS`] rounds, each timing the reference loop and then the
//!    command, with the rounds' range.
//!
//! Everything runs on one thread (a one-thread rayon pool, `RAYON_NUM_THREADS=1` for the
//! subprocess), so the ratios compare work, not scheduling. Times are CPU times where Linux
//! gives them (`/proc/thread-self/schedstat` in process, `/usr/bin/time` for the subprocess),
//! wall-clock otherwise, so a shared machine slows the figures less; read the ratios, not the
//! absolute times.

#![allow(clippy::unwrap_used, reason = "benchmark set-up may unwrap")]
#![allow(clippy::print_stderr, reason = "the benchmark reports on the terminal")]

use std::hint::black_box;
use std::path::PathBuf;
use std::process::Command;
use std::time::{Duration, Instant};

use eamadm::dql::Environment;
use eamadm::mazes::Preset;
use eamadm::wmr_model::WmrEnv;
use eamadm::{Experiment, Method, MethodSpec, SharedPretraining};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn main() {
    let tiny = std::env::args().any(|arg| arg == "--tiny");
    // `-- --only robot_over_maze` (or `shared_pretraining`, `end_to_end`) runs one ratio.
    let only = std::env::args().skip_while(|arg| arg != "--only").nth(1);
    let runs = |name: &str| only.as_deref().is_none_or(|only| only == name);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    pool.install(|| {
        if runs("shared_pretraining") {
            shared_pretraining(tiny);
        }
        if runs("robot_over_maze") {
            robot_over_maze(tiny);
        }
        if runs("end_to_end") {
            end_to_end(tiny);
        }
    });
}

/// A clock of this thread's CPU time (nanoseconds on the CPU, from the kernel's scheduler
/// statistics), or of wall time where that file cannot be read.
struct Clock {
    cpu: Option<u64>,
    wall: Instant,
}

fn thread_cpu_ns() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    text.split_whitespace().next()?.parse().ok()
}

impl Clock {
    fn start() -> Self {
        Self {
            cpu: thread_cpu_ns(),
            wall: Instant::now(),
        }
    }

    /// The CPU time since `start`, or the wall time when the interval is too short for the
    /// CPU clock: the kernel brings that figure up to date at scheduler ticks (every 1–10 ms),
    /// so it is exact only to a tick.
    fn elapsed(&self) -> Duration {
        const SHORTEST_CPU_INTERVAL: Duration = Duration::from_millis(50);
        let wall = self.wall.elapsed();
        match (self.cpu, thread_cpu_ns()) {
            (Some(start), Some(now)) if wall >= SHORTEST_CPU_INTERVAL => {
                Duration::from_nanos(now.saturating_sub(start))
            }
            _ => wall,
        }
    }
}

fn per(duration: Duration, count: u64) -> f64 {
    duration.as_secs_f64() * 1e9 / count.max(1) as f64
}

/// Ratio 1: the pre-training family, shared against unshared.
fn shared_pretraining(tiny: bool) {
    let mut config = eamadm::paper::task1();
    config.seeds = if tiny { 1 } else { 3 };
    if tiny {
        config.episodes = 5;
        for spec in &mut config.methods {
            match &mut spec.method {
                Method::EaMadm(ea) => ea.pretrain.episodes = 5,
                Method::SubtaskGreedy(alone) => alone.pretrain.episodes = 5,
                _ => {}
            }
        }
    }
    config
        .methods
        .retain(|spec| matches!(spec.method, Method::EaMadm(_) | Method::SubtaskGreedy(_)));
    let experiment = Experiment::new(config).unwrap();
    let methods: Vec<&MethodSpec> = experiment.config().methods.iter().collect();
    let seeds: Vec<u64> = experiment.config().seed_values().collect();
    let start = Clock::start();
    for &seed in &seeds {
        for method in &methods {
            black_box(experiment.run(method, seed).unwrap());
        }
    }
    let unshared = start.elapsed();
    let start = Clock::start();
    for &seed in &seeds {
        let shared = experiment.share_pretraining(&methods, seed);
        for method in &methods {
            black_box(experiment.run_shared(method, seed, &shared).unwrap());
        }
    }
    let shared = start.elapsed();
    black_box(SharedPretraining::none());
    eprintln!(
        "maze EA-MADM family ({} methods × {} seeds): shared {:.2} s, unshared {:.2} s, \
         shared ÷ unshared = {:.3}",
        methods.len(),
        seeds.len(),
        shared.as_secs_f64(),
        unshared.as_secs_f64(),
        shared.as_secs_f64() / unshared.as_secs_f64()
    );
}

/// Ratio 2: a robot step against a maze step, each a step of the environment as the runner
/// uses it: a given action (drawn at random beforehand, so the draw is timed in neither), the
/// sub-task rewards read, a reset at each episode's end.
///
/// A maze step takes a few nanoseconds, so one burst of load on a shared machine would move
/// the ratio a lot. The two are therefore timed in alternating rounds of many steps each
/// (thread CPU time, every round about 0.1 s, far above the CPU clock's tick), the
/// environments carrying on from round to round; the per-step times are the medians over the
/// rounds, and the ratio is the median of the rounds' ratios (each round's two measurements
/// are back to back).
fn robot_over_maze(tiny: bool) {
    let (rounds, robot_steps, maze_steps) = if tiny {
        (3, 2_000, 20_000)
    } else {
        (15, 250_000, 25_000_000)
    };
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    // One action per robot step of every round, none repeated by cycling a short list: the
    // robot remembers steps by start pose and action, and an episode's course is a function
    // of its actions alone (the noise moves only the readings), so a cycled list would replay
    // whole episodes from the memo and time lookups instead of steps.
    let robot_actions: Vec<u8> = (0..rounds * robot_steps)
        .map(|_| rng.random_range(0..5))
        .collect();
    let maze_actions: Vec<usize> = (0..4096).map(|_| rng.random_range(0..4)).collect();
    let mut robot = WmrEnv::default();
    let mut maze = Preset::Task1.env();
    maze.reset(None);
    let mut total = 0.0;
    let (mut robot_ns, mut maze_ns, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
    for actions in robot_actions.chunks(robot_steps as usize) {
        let start = Clock::start();
        for &action in actions {
            let step = robot.step(black_box(usize::from(action)));
            total += step.reward + robot.subtask_rewards()[1];
            if step.done() {
                robot.reset(None);
            }
        }
        let robot_round = per(start.elapsed(), robot_steps);
        let start = Clock::start();
        for i in 0..maze_steps {
            let step = maze.step(black_box(maze_actions[i as usize % maze_actions.len()]));
            total += step.reward + maze.subtask_rewards()[1];
            if step.done() {
                maze.reset(None);
            }
        }
        let maze_round = per(start.elapsed(), maze_steps);
        robot_ns.push(robot_round);
        maze_ns.push(maze_round);
        ratios.push(robot_round / maze_round);
    }
    black_box(total);
    let (low, high) = (
        ratios.iter().copied().fold(f64::INFINITY, f64::min),
        ratios.iter().copied().fold(0.0, f64::max),
    );
    eprintln!(
        "robot step {:.1} ns, maze step {:.2} ns (medians of {rounds} rounds of {robot_steps} \
         and {maze_steps} steps): robot ÷ maze = {:.1} (rounds {low:.1} to {high:.1})",
        median(&mut robot_ns),
        median(&mut maze_ns),
        median(&mut ratios),
    );
}

/// The middle value (the upper middle of an even count).
fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Ratio 3: the ε-greedy runs per step against the hand-written loop.
///
/// `reproduce-paper --task task1 --method epsilon-greedy` runs the preset's ε-greedy runs and
/// then the readings' reruns of ε-greedy (ε = 0.95 and γ = 0.99, [`eamadm::paper::readings`]),
/// so its time is divided by the steps of all of them; `--readings none` runs the preset's
/// only. Both are measured, each against the steps of the runs it executed.
fn end_to_end(tiny: bool) {
    let seeds: u32 = if tiny { 5 } else { 1000 };
    let mut config = eamadm::paper::task1();
    config.seeds = seeds;
    config.methods.retain(|spec| spec.label == "epsilon-greedy");
    let epsilon = match config.methods[0].method {
        Method::EpsilonGreedy {
            epsilon: eamadm::dql::Schedule::Constant(epsilon),
            ..
        } => epsilon,
        _ => 0.1,
    };
    let episodes = config.episodes;
    let evaluate_every = config.evaluation.every(episodes);
    // The readings that rerun ε-greedy on Task I, as `reproduce-paper` plans them.
    let readings: Vec<eamadm::ExperimentConfig> = eamadm::paper::readings()
        .iter()
        .filter_map(|reading| reading.apply(&config))
        .collect();
    let learn = |config: eamadm::ExperimentConfig| {
        let experiment = Experiment::new(config).unwrap();
        let start = Clock::start();
        let records = experiment.run_all().unwrap();
        let time = start.elapsed();
        let steps: u64 = records.iter().map(|r| r.total_env_steps).sum();
        // The greedy episodes played without learning (every `evaluation.every` training
        // episodes, and the final one): work the runner does that the reference does not.
        let greedy: u64 = records
            .iter()
            .map(|r| r.evaluation.steps + r.greedy_evaluations.iter().map(|e| e.steps).sum::<u64>())
            .sum();
        (steps, greedy, time)
    };
    let (steps, greedy_steps, learning) = learn(config);
    let learning_ns = per(learning, steps);
    let (mut reading_steps, mut reading_learning) = (0, Duration::ZERO);
    for reading in readings {
        let (steps, _, time) = learn(reading);
        reading_steps += steps;
        reading_learning += time;
    }
    let all_steps = steps + reading_steps;
    let all_learning_ns = per(learning + reading_learning, all_steps);

    let env = Preset::Task1.env();
    let (reference, reference_steps) = time_reference(&env, seeds, episodes, epsilon);
    let reference_ns = per(reference, reference_steps);
    // The reference's cost of a greedy evaluation step, from the same loop with the runner's
    // evaluations (its learning episodes are the ones just timed).
    let (mut reference_greedy_steps, mut reference_greedy_time) = (0, Duration::ZERO);
    let mut evaluated_training_steps = 0;
    for seed in 0..u64::from(seeds) {
        let run = eamadm_benches::reference_double_q_evaluated(
            &env,
            episodes,
            epsilon,
            seed,
            Some(evaluate_every),
        );
        evaluated_training_steps += run.training_steps;
        reference_greedy_steps += run.greedy_steps;
        reference_greedy_time += run.greedy_time;
    }
    assert_eq!(
        evaluated_training_steps, reference_steps,
        "the greedy evaluations must leave the reference's learning episodes as they are"
    );
    let reference_greedy_ns = per(reference_greedy_time, reference_greedy_steps);
    let executed_ns = per(learning, steps + greedy_steps);
    eprintln!(
        "hand-written double Q: {reference_ns:.1} ns/step; runner (learning only, {seeds} \
         seeds): {learning_ns:.1} ns/step = {:.2}× (its greedy evaluations add {:.1} % to the \
         training steps: {executed_ns:.1} ns per step played = {:.2}×); with the readings' \
         reruns ({} training steps in all, {:.1} % of them the readings'): \
         {all_learning_ns:.1} ns/step = {:.2}×",
        learning_ns / reference_ns,
        100.0 * greedy_steps as f64 / steps.max(1) as f64,
        executed_ns / reference_ns,
        all_steps,
        100.0 * reading_steps as f64 / all_steps.max(1) as f64,
        all_learning_ns / reference_ns,
    );

    let xtask = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/release/xtask");
    if !xtask.exists() {
        eprintln!(
            "end to end: skipped ({} not built; `cargo build --release -p xtask`)",
            xtask.display()
        );
        return;
    }
    // `--readings none`, the measure: rounds of the reference loop and the command in
    // turn, a ratio per round and their median, so that the machine's drift moves both sides
    // of a ratio and one slow round cannot move the figure (one round is a single shot that
    // moved by ±3 % and more from run to run on the 2-core machine).
    let rounds = if tiny { 1 } else { END_TO_END_ROUNDS };
    let (mut per_trained, mut per_played, mut per_work) = (Vec::new(), Vec::new(), Vec::new());
    let mut whole_ns_rounds = Vec::new();
    for _ in 0..rounds {
        let (reference, reference_steps) = time_reference(&env, seeds, episodes, epsilon);
        let reference_ns = per(reference, reference_steps);
        let whole = reproduce_paper(&xtask, seeds, "none");
        let whole_ns = per(whole, steps);
        whole_ns_rounds.push(whole_ns);
        per_trained.push(whole_ns / reference_ns);
        // The runs' greedy evaluations are steps the plain reference does not take.
        per_played.push(per(whole, steps + greedy_steps) / reference_ns);
        // Like for like: the runner's learning steps at the hand-written loop's cost of a
        // learning step, and its greedy evaluation steps at the cost of a greedy one.
        let reference_work_ns =
            reference_ns * steps as f64 + reference_greedy_ns * greedy_steps as f64;
        per_work.push(whole.as_nanos() as f64 / reference_work_ns);
    }
    let spread = |ratios: &[f64]| {
        let (median, low, high) = median_and_range(ratios);
        format!("{median:.2}× (rounds {low:.2}–{high:.2}×)")
    };
    eprintln!(
        "end to end (reproduce-paper --readings none, {seeds} seeds, {steps} steps; median of \
         {rounds} rounds, each against the hand-written loop timed just before it): {:.1} \
         ns/step = {} the hand-written loop, {:.2}× its learning alone",
        median_and_range(&whole_ns_rounds).0,
        spread(&per_trained),
        median_and_range(&whole_ns_rounds).0 / learning_ns,
    );
    eprintln!(
        "end to end (reproduce-paper --readings none) per step played ({} steps: training and \
         greedy evaluation): {}",
        steps + greedy_steps,
        spread(&per_played),
    );
    eprintln!(
        "end to end (reproduce-paper --readings none) ÷ the hand-written loops doing its work \
         ({steps} learning steps at the reference's cost, {greedy_steps} greedy evaluation \
         steps at {reference_greedy_ns:.1} ns): {}",
        spread(&per_work),
    );
    let whole = reproduce_paper(&xtask, seeds, "all");
    let whole_ns = per(whole, all_steps);
    eprintln!(
        "end to end (reproduce-paper --readings all, {seeds} seeds, {all_steps} steps): \
         {whole_ns:.1} ns/step = {:.2}× the hand-written loop, {:.2}× its learning alone",
        whole_ns / reference_ns,
        whole_ns / all_learning_ns,
    );
}

/// Rounds of the `--readings none` ratio (one with `--tiny`).
const END_TO_END_ROUNDS: usize = 5;

/// The median of `values` (the mean of the middle two for an even count) and their range.
fn median_and_range(values: &[f64]) -> (f64, f64, f64) {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    let median = if n % 2 == 1 {
        sorted[n / 2]
    } else {
        (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0
    };
    (median, sorted[0], sorted[n - 1])
}

/// The time of the hand-written loop over `seeds` seeds, and the steps it took.
fn time_reference(
    env: &eamadm::mazes::MazeEnv,
    seeds: u32,
    episodes: u64,
    epsilon: f64,
) -> (Duration, u64) {
    let start = Clock::start();
    let mut steps = 0;
    for seed in 0..u64::from(seeds) {
        steps += eamadm_benches::reference_double_q(env, episodes, epsilon, seed);
    }
    (start.elapsed(), steps)
}

/// The CPU time (user + system; wall time without `/usr/bin/time`) of
/// `reproduce-paper --task task1 --method epsilon-greedy --seeds SEEDS --readings READINGS` on
/// one thread, into a temporary folder it removes.
fn reproduce_paper(xtask: &std::path::Path, seeds: u32, readings: &str) -> Duration {
    let out = std::env::temp_dir().join(format!("eamadm-bench-{}", std::process::id()));
    // `/usr/bin/time -f "%U %S"` reports the subprocess's CPU seconds; without it, wall time.
    let timer = PathBuf::from("/usr/bin/time");
    let mut command = if timer.exists() {
        let mut command = Command::new(&timer);
        command.args(["-f", "cpu %U %S"]).arg(xtask);
        command
    } else {
        Command::new(xtask)
    };
    let wall = Instant::now();
    let output = command
        .args([
            "reproduce-paper",
            "--task",
            "task1",
            "--method",
            "epsilon-greedy",
            "--readings",
            readings,
        ])
        .arg("--seeds")
        .arg(seeds.to_string())
        .arg("--out")
        .arg(&out)
        .env("RAYON_NUM_THREADS", "1")
        .stdout(std::process::Stdio::null())
        .output()
        .unwrap();
    let wall = wall.elapsed();
    let _ = std::fs::remove_dir_all(&out);
    assert!(
        output.status.success(),
        "reproduce-paper failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    let cpu = stderr.lines().rev().find_map(|line| {
        let mut fields = line.strip_prefix("cpu ")?.split_whitespace();
        let user: f64 = fields.next()?.parse().ok()?;
        let system: f64 = fields.next()?.parse().ok()?;
        Some(Duration::from_secs_f64(user + system))
    });
    cpu.unwrap_or(wall)
}
