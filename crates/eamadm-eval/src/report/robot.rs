//! The robot's sections: the C4 metrics over reaching episodes with the ranking of the methods
//! that reach, and "why each method behaves as it does" from [`MethodBehaviour`] (success
//! with its Wilson interval, the final window's action shares, and for EA-MADM its agreement
//! with each sub-task's best action and what each sub-task's learner learned to expect from
//! the start).

use std::fmt::Write as _;

use super::Verdicts;
use super::format::{Align, MarkdownTable, format_fixed, interval};
use super::task::estimate_cell;
use crate::behaviour::MethodBehaviour;
use crate::claims::MethodOverview;
use crate::paper_claims::method_title;
use crate::stats::Interval;

pub(crate) fn write_robot(
    text: &mut String,
    task: &str,
    overviews: &[&MethodOverview],
    verdicts: &Verdicts,
) {
    let _ = writeln!(
        text,
        "Robot metrics over reaching episodes (C4; Fig. 13–15 analogues), IQM over the seeds \
         that reach [95%]:\n"
    );
    let mut table = MarkdownTable::new([
        ("method", Align::Left),
        ("seeds reaching", Align::Right),
        ("average reward", Align::Right),
        ("reaching time (s)", Align::Right),
        ("retention decay (s / episode)", Align::Right),
    ]);
    for o in overviews {
        let _ = table.push_row([
            method_title(&o.method),
            format!("{}/{}", o.reaching_seeds, o.seeds),
            estimate_cell(verdicts, task, &o.method, "reach_average_reward"),
            estimate_cell(verdicts, task, &o.method, "reach_time"),
            estimate_cell(verdicts, task, &o.method, "retention_decay"),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
    let _ = writeln!(text, "{}\n", robot_ranking(task, overviews, verdicts));
}

/// Which method leads on the robot's average reward, among methods that reach the target in
/// at least two seeds; never a ranking of methods that do not reach it.
pub(crate) fn robot_ranking(
    task: &str,
    overviews: &[&MethodOverview],
    verdicts: &Verdicts,
) -> String {
    let reaching: Vec<(&MethodOverview, Interval)> = overviews
        .iter()
        .filter_map(|o| {
            verdicts
                .estimate(task, &o.method, "reach_average_reward")
                .filter(|e| e.n >= 2)
                .and_then(|e| e.iqm)
                .map(|i| (*o, i))
        })
        .collect();
    let never: Vec<String> = overviews
        .iter()
        .filter(|o| o.reaching_seeds == 0)
        .map(|o| method_title(&o.method))
        .collect();
    let never_text = if never.is_empty() {
        String::new()
    } else {
        format!(" Never reaches the target: {}.", never.join(", "))
    };
    match reaching
        .iter()
        .max_by(|a, b| a.1.estimate.total_cmp(&b.1.estimate))
    {
        None => format!(
            "No method reaches the target in two or more seeds, so the robot's methods are not \
             ranked and C4's metrics cannot be compared here.{never_text}"
        ),
        Some((best, i)) => format!(
            "Among the {} methods that reach the target in two or more seeds, {} has the \
             highest IQM average reward over its reaching episodes ({}).{never_text}",
            reaching.len(),
            method_title(&best.method),
            interval(i)
        ),
    }
}

fn percent(share: f64) -> String {
    format!("{}%", format_fixed(share * 100.0, 0))
}

fn success(method: &MethodBehaviour) -> String {
    match &method.success {
        Some(interval) if method.final_endings.reached == 0 => format!(
            "never reached (0 of {}; 95% CI {}–{})",
            method.final_episodes,
            percent(interval.low),
            percent(interval.high)
        ),
        Some(interval) => format!(
            "{} of {}: {} (95% CI {}–{})",
            method.final_endings.reached,
            method.final_episodes,
            percent(interval.estimate),
            percent(interval.low),
            percent(interval.high)
        ),
        None => "no episodes".to_owned(),
    }
}

/// Appends the behaviour section of a robot experiment (its `methods`' behaviour, from
/// [`behaviour()`](crate::behaviour()) or a [`BehaviourAccumulator`](crate::BehaviourAccumulator)
/// fed its runs; discount `gamma` of the learners; `action_names` in the order of the action
/// shares) to `text`.
pub(crate) fn write_robot_behaviour(
    text: &mut String,
    methods: &[MethodBehaviour],
    gamma: f64,
    action_names: &[String],
) {
    if methods.is_empty() {
        return;
    }
    let _ = writeln!(
        text,
        "Why each method behaves as it does (final window, episodes pooled over seeds; success \
         with its 95% Wilson interval; action shares count every step, exploring ones \
         included):\n"
    );
    let mut columns = vec![
        ("method".to_owned(), Align::Left),
        ("success".to_owned(), Align::Left),
        ("seeds reaching".to_owned(), Align::Right),
        ("mean steps".to_owned(), Align::Right),
    ];
    columns.extend(
        action_names
            .iter()
            .map(|action| (action.clone(), Align::Right)),
    );
    let mut table = MarkdownTable::new(columns);
    for method in methods {
        let mut row = vec![
            method_title(&method.method),
            success(method),
            format!("{} of {}", method.seeds_reaching, method.seeds),
            format_fixed(method.mean_final_steps, 0),
        ];
        row.extend(method.action_shares.iter().map(|&s| percent(s)));
        let _ = table.push_row(row);
    }
    text.push_str(&table.render());
    text.push('\n');

    // The sub-task detail of the paper's EA-MADM only; the ablations' action shares are above.
    for method in methods
        .iter()
        .filter(|m| !m.subtasks.is_empty() && m.method == "ea-madm")
    {
        write_subtasks(text, method, gamma, action_names);
    }
}

fn write_subtasks(
    text: &mut String,
    method: &MethodBehaviour,
    gamma: f64,
    action_names: &[String],
) {
    let action = |index: usize| action_names.get(index).map_or("?", String::as_str);
    let _ = writeln!(
        text,
        "{}: {} decisions (exploitation steps) in the final windows; per sub-task, how often the \
         decision was one of its greedy actions, its learner's best value at the start (mean \
         over seeds) and that value as a reward per step kept forever (× (1 − γ), γ = {}), and \
         its greedy policy run alone:\n",
        method_title(&method.method),
        method.decisions,
        format_fixed(gamma, 2)
    );
    let mut table = MarkdownTable::new([
        ("sub-task", Align::Left),
        ("agrees", Align::Right),
        ("best start action", Align::Left),
        ("its start value", Align::Right),
        ("per step", Align::Right),
        ("alone: mean steps", Align::Right),
        ("alone: reached / failed / cut", Align::Left),
    ]);
    for subtask in &method.subtasks {
        let best = subtask
            .start_values
            .get(subtask.best_start_action)
            .copied()
            .unwrap_or(f64::NAN);
        let endings = subtask.greedy_alone_endings;
        let _ = table.push_row([
            subtask.name.clone(),
            percent(subtask.agreement),
            action(subtask.best_start_action).to_owned(),
            format_fixed(best, 1),
            format_fixed(best * (1.0 - gamma), 2),
            format_fixed(subtask.greedy_alone_steps, 0),
            format!(
                "{} / {} / {}",
                endings.reached, endings.failed, endings.truncated
            ),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
    let shares = &method.action_shares;
    let top = (0..shares.len()).fold(0, |best, a| if shares[a] > shares[best] { a } else { best });
    if let Some(dominant) = method.dominant_subtask.and_then(|k| method.subtasks.get(k)) {
        let _ = writeln!(
            text,
            "The dominant sub-task is *{}*: {} of the decisions agree with it. Its learner's best \
             start action is `{}`, worth {} per step for ever; alone it ran {} steps on average \
             ({} of {} greedy episodes cut at the step cap). {} took `{}` in {} of its \
             final-window steps.\n",
            dominant.name,
            percent(dominant.agreement),
            action(dominant.best_start_action),
            format_fixed(
                dominant
                    .start_values
                    .get(dominant.best_start_action)
                    .copied()
                    .unwrap_or(f64::NAN)
                    * (1.0 - gamma),
                2
            ),
            format_fixed(dominant.greedy_alone_steps, 0),
            dominant.greedy_alone_endings.truncated,
            method.seeds,
            method_title(&method.method),
            action(top),
            percent(shares.get(top).copied().unwrap_or(0.0)),
        );
    }
}

#[cfg(test)]
mod tests {
    use crate::Endings;
    use crate::stats::wilson;

    use super::*;

    fn method(reached: u64, episodes: u64) -> MethodBehaviour {
        MethodBehaviour {
            method: "softmax".to_owned(),
            seeds: 2,
            final_episodes: episodes,
            final_endings: Endings {
                reached,
                failed: episodes - reached,
                truncated: 0,
            },
            success: wilson(reached, episodes, 0.95).ok(),
            seeds_reaching: usize::from(reached > 0),
            mean_final_steps: 40.0,
            action_shares: vec![0.5, 0.25, 0.0, 0.125, 0.125],
            subtasks: Vec::new(),
            dominant_subtask: None,
            decisions: 0,
        }
    }

    #[test]
    fn success_states_the_count_share_and_interval_or_never() {
        assert_eq!(
            success(&method(0, 40)),
            "never reached (0 of 40; 95% CI 0%–9%)"
        );
        let text = success(&method(10, 40));
        assert!(text.starts_with("10 of 40: 25% (95% CI "), "{text}");
        assert_eq!(success(&method(0, 0)), "no episodes");
    }

    #[test]
    fn no_methods_write_nothing() {
        let mut text = String::new();
        write_robot_behaviour(&mut text, &[], 0.95, &[]);
        assert!(text.is_empty());
    }
}
