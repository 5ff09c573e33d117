//! Runs a paper preset for a few seeds and prints each method's final-window summary.
//!
//! `cargo run --release -p eamadm --example compare -- [task1|task2|robot] [seeds] [episodes]`

use eamadm::{DEFAULT_FINAL_WINDOW, Experiment, summarise};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let mut config = match args.next().as_deref() {
        None | Some("task1") => eamadm::paper::task1(),
        Some("task2") => eamadm::paper::task2(),
        Some("robot") => eamadm::paper::robot(),
        Some(other) => return Err(format!("unknown task {other:?}").into()),
    };
    if let Some(seeds) = args.next() {
        config.seeds = seeds.parse()?;
    }
    if let Some(episodes) = args.next() {
        config.episodes = episodes.parse()?;
    }
    let experiment = Experiment::new(config)?;
    let started = std::time::Instant::now();
    let records = experiment.run_all()?;
    let elapsed = started.elapsed();
    println!(
        "{}: {} runs in {:.2} s; BFS optimum {:?} steps",
        experiment.config().name,
        records.len(),
        elapsed.as_secs_f64(),
        experiment.task().optimum_steps()
    );
    println!(
        "{:<20} {:>16} {:>16} {:>10} {:>10} {:>9} {:>12}",
        "method", "final steps", "final return", "collisions", "eval steps", "eval ok", "env steps"
    );
    for summary in summarise(&records, DEFAULT_FINAL_WINDOW)? {
        let ci = |s: &eamadm::SeedSummary| {
            format!("{:.1} ± {:.1}", s.mean, s.ci95_half_width.unwrap_or(0.0))
        };
        println!(
            "{:<20} {:>16} {:>16} {:>10.2} {:>10.1} {:>9.2} {:>12.0}",
            summary.method,
            ci(&summary.final_steps),
            ci(&summary.final_return),
            summary.final_collisions.mean,
            summary.evaluation_steps.mean,
            summary.evaluation_reached,
            summary.total_env_steps.mean,
        );
        if let Some(robot) = summary.robot {
            println!(
                "{:<20} average reward {} per s, time to reach {}, retention {} s, reached {:.2}",
                "",
                ci(&robot.average_reward),
                robot.time_to_reach.as_ref().map_or("-".to_owned(), ci),
                ci(&robot.retention_time),
                summary.final_reached.mean,
            );
        }
    }
    Ok(())
}
