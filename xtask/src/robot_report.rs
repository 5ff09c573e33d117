//! The robot section's "why each method behaves as it does": formats [`eamadm::MethodBehaviour`]
//! (computed in the library) as markdown — success with its Wilson interval, the final
//! window's action shares, and for EA-MADM its agreement with each sub-task's best action and
//! what each sub-task's learner learned to expect from the start.

use std::fmt::Write as _;

use eamadm::MethodBehaviour;
use eamadm::wmr_model::Action;

use crate::report::{Align, MarkdownTable, format_fixed};
use eamadm::paper::method_title;

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
/// [`eamadm::behaviour()`] or a [`BehaviourAccumulator`](eamadm::BehaviourAccumulator) fed its
/// runs; discount `gamma` of the learners) to `text`.
pub(crate) fn write_robot_behaviour(text: &mut String, methods: &[MethodBehaviour], gamma: f64) {
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
        Action::ALL
            .iter()
            .map(|action| (action.name().to_owned(), Align::Right)),
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
        write_subtasks(text, method, gamma);
    }
}

fn write_subtasks(text: &mut String, method: &MethodBehaviour, gamma: f64) {
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
            Action::ALL
                .get(subtask.best_start_action)
                .map_or("?", |a| a.name())
                .to_owned(),
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
            Action::ALL
                .get(dominant.best_start_action)
                .map_or("?", |a| a.name()),
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
            Action::ALL.get(top).map_or("?", |a| a.name()),
            percent(shares.get(top).copied().unwrap_or(0.0)),
        );
    }
}

#[cfg(test)]
mod tests {
    use eamadm::Endings;
    use eamadm::stats::wilson;

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
        write_robot_behaviour(&mut text, &[], 0.95);
        assert!(text.is_empty());
    }
}
