//! The robot's sections: the C4 metrics over reaching episodes with the methods that reach
//! (a point-estimate ranking, not tested), C4's verdict per method under test with its
//! evidence (per-seed reaching, the exact test, and why from the diagnosis), "why each method
//! behaves as it does" from [`MethodBehaviour`] (success with its Wilson interval, the final
//! window's endings and action shares, and for EA-MADM its agreement with each sub-task's best
//! action), and the diagnosis: what each sub-task's reward definition (Eq. 6–8, and with each set of
//! repairs) makes of reaching, ending the episode at once and idling, beside what
//! its learner learned to expect from the start ([`RewardReference`]).

use std::fmt::Write as _;

use super::format::{Align, MarkdownTable, format_fixed, interval, number, p_value};
use super::task::estimate_cell;
use super::{ExperimentFacts, Play, RewardReference, SubtaskReference, Verdicts};
use eamadm_eval::Role;
use eamadm_eval::behaviour::MethodBehaviour;
use eamadm_eval::claims::{Judgement, MethodOverview, Verdict};
use eamadm_eval::findings::TaskFindings;
use eamadm_eval::paper_claims::method_title;
use eamadm_eval::stats::Interval;

pub(crate) fn write_robot(
    text: &mut String,
    experiment: &ExperimentFacts,
    overviews: &[&MethodOverview],
    verdicts: &Verdicts,
    found: Option<&TaskFindings>,
) {
    let task = experiment.name.as_str();
    let _ = writeln!(
        text,
        "Robot metrics over reaching episodes (C4; Fig. 13–15 analogues), IQM over the seeds \
         that reach [95%]:\n"
    );
    let mut table = MarkdownTable::new([
        ("method", Align::Left),
        ("seeds reaching in training", Align::Right),
        ("average reward", Align::Right),
        ("reaching time (s)", Align::Right),
        ("retention decay (s / episode)", Align::Right),
    ]);
    // The methods that never reach in training have no C4 value: one sentence names them.
    let mut rows = 0;
    for o in overviews.iter().filter(|o| o.reaching_seeds > 0) {
        let _ = table.push_row([
            method_title(&o.method),
            format!("{}/{}", o.reaching_seeds, o.seeds),
            estimate_cell(verdicts, task, &o.method, "reach_average_reward"),
            estimate_cell(verdicts, task, &o.method, "reach_time"),
            estimate_cell(verdicts, task, &o.method, "retention_decay"),
        ]);
        rows += 1;
    }
    if rows > 0 {
        text.push_str(&table.render());
        text.push('\n');
    }
    let _ = writeln!(text, "{}\n", robot_ranking(task, overviews, verdicts));
    write_c4_verdicts(text, experiment, overviews, verdicts, found);
}

/// The metric the robot's methods are ranked by (an estimate stated for every method:
/// `claims::OVERVIEW_COLUMNS`).
pub(crate) const RANKING_METRIC: &str = "reach_average_reward";

/// Which method has the highest point estimate of the robot's average reward, among methods
/// that reach the target in at least two seeds; never a ranking of methods that do not reach
/// it. No test compares these methods with each other, and the sentence says so.
pub(crate) fn robot_ranking(
    task: &str,
    overviews: &[&MethodOverview],
    verdicts: &Verdicts,
) -> String {
    let reaching: Vec<(&MethodOverview, Interval)> = overviews
        .iter()
        .filter_map(|o| {
            verdicts
                .estimate(task, &o.method, RANKING_METRIC)
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
        Some((best, i)) if reaching.len() == 1 => format!(
            "Only {} reaches the target in two or more seeds; its IQM average reward over its \
             reaching episodes is {}.{never_text}",
            method_title(&best.method),
            interval(i)
        ),
        Some((best, i)) => format!(
            "Among the {} methods that reach the target in two or more seeds, {} has the \
             highest point estimate of the IQM average reward over its reaching episodes ({}; \
             not tested: these methods are not compared with each other, and their intervals \
             are in the table).{never_text}",
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

/// The number that decides `judgement`, in words (the findings' deciding comparison).
fn deciding_number(judgement: &Judgement) -> String {
    let finding = eamadm_eval::findings::verdict_finding(judgement);
    super::words::deciding_or_reason(
        finding.deciding.as_ref(),
        &finding.reason,
        &judgement.method,
        true,
    )
}

/// What C4's verdict says of the paper's claim.
fn reproduced(verdict: Verdict) -> &'static str {
    match verdict {
        Verdict::Supported => "reproduced",
        Verdict::Contradicted => "not reproduced",
        Verdict::Equivalent => "not reproduced (equivalent, not better)",
        Verdict::Inconclusive => "not shown",
        Verdict::Untestable => "not testable here",
    }
}

/// `a`, `a and b`, `a, b and c`.
fn join(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// Whether a method reached the target on no seed at all (no training episode, no greedy
/// episode): the methods C4's metrics cannot describe.
fn never_reaches(overview: &MethodOverview) -> bool {
    overview.reaching_seeds == 0 && overview.greedy_success.successes == 0
}

/// C4's verdict for each method under test on this task, each with its evidence and, for a
/// method that never reaches, why (from the diagnosis).
fn write_c4_verdicts(
    text: &mut String,
    experiment: &ExperimentFacts,
    overviews: &[&MethodOverview],
    verdicts: &Verdicts,
    found: Option<&TaskFindings>,
) {
    // A method that scores as an earlier one on every seed has its verdicts; its sentence
    // would repeat the earlier one's.
    let judgements: Vec<&Judgement> = verdicts
        .judgements
        .iter()
        .filter(|j| j.task == experiment.name && j.claim.id == "C4")
        .filter(|j| {
            j.versus_set != eamadm_eval::claims::VersusSet::Paper
                || found.is_none_or(|f| !f.identical.iter().any(|i| i.method == j.method))
        })
        .collect();
    if judgements.is_empty() {
        return;
    }
    let _ = writeln!(
        text,
        "C4 for each method under test, with the evidence that decides it:\n"
    );
    let mut explained = Vec::new();
    for judgement in judgements {
        let _ = writeln!(
            text,
            "- {}",
            c4_sentence(judgement, experiment, overviews, &mut explained)
        );
    }
    text.push('\n');
}

/// One method's C4 verdict in words: reproduced or not, the per-seed reaching counts with the
/// exact test when it is judged on reaching (else the deciding comparison), and for a method
/// that never reaches the diagnosis of its sub-task rewards. `explained` holds `(rewards,
/// method)` of the references already explained in the list, so a later method on the same
/// sub-task rewards refers to the first instead of repeating it.
pub(crate) fn c4_sentence(
    judgement: &Judgement,
    experiment: &ExperimentFacts,
    overviews: &[&MethodOverview],
    explained: &mut Vec<(String, String)>,
) -> String {
    let who = if judgement.role == Role::Paper {
        format!(
            "**{}** (the paper's method)",
            method_title(&judgement.method)
        )
    } else {
        format!("`{}`", judgement.method)
    };
    let evidence = match judgement.reaching.first() {
        _ if judgement.verdict == Verdict::Untestable => judgement.reason.clone(),
        None => deciding_number(judgement),
        Some(first) => {
            let against: Vec<String> = judgement
                .reaching
                .iter()
                .map(|r| {
                    format!(
                        "{} on {}/{} (Holm p {})",
                        method_title(&r.versus),
                        r.reached.1,
                        r.n,
                        p_value(r.p_holm)
                    )
                })
                .collect();
            format!(
                "it reaches the target on {}/{} seeds, against {}: exact paired sign test on the \
                 seeds only one of the two reaches on, Holm-adjusted over the competitors",
                first.reached.0,
                first.n,
                join(&against)
            )
        }
    };
    let never = overviews
        .iter()
        .any(|o| o.method == judgement.method && never_reaches(o));
    let rewards = experiment
        .reward_references
        .iter()
        .find(|r| r.methods.iter().any(|m| m == &judgement.method))
        .map(rewards_name);
    let why = match rewards {
        Some(rewards) if never => {
            if let Some((_, first)) = explained.iter().find(|(r, _)| *r == rewards) {
                format!(" Why: the same sub-task rewards as {first} above.")
            } else {
                explained.push((rewards, method_title(&judgement.method)));
                why_never(experiment, &judgement.method)
                    .map_or_else(String::new, |why| format!(" {why}"))
            }
        }
        _ => String::new(),
    };
    format!(
        "{who}: C4 is **{}** (verdict `{}`); {evidence}.{why}",
        reproduced(judgement.verdict),
        judgement.verdict.name()
    )
}

/// How a sentence names a version of the sub-task rewards.
fn rewards_name(rewards: &RewardReference) -> String {
    if rewards.repairs.is_empty() {
        "the paper's sub-task rewards (Eq. 6–8)".to_owned()
    } else {
        format!("the sub-task rewards with {}", join(&rewards.repairs))
    }
}

/// A rewards's name in a table cell.
fn rewards_cell(rewards: &RewardReference) -> String {
    if rewards.repairs.is_empty() {
        "paper (Eq. 6–8)".to_owned()
    } else {
        rewards.repairs.join(" + ")
    }
}

/// The behaviour whose sub-tasks learned from `rewards`: `preferred` when it is one of them
/// and has sub-tasks, else the first of the rewards's methods that has.
fn learner_of<'a>(
    experiment: &'a ExperimentFacts,
    rewards: &RewardReference,
    preferred: Option<&str>,
) -> Option<&'a MethodBehaviour> {
    let with_subtasks = |label: &str| {
        experiment
            .behaviour
            .iter()
            .find(|b| b.method == label && b.subtasks.len() == rewards.subtasks.len())
    };
    preferred
        .filter(|p| rewards.methods.iter().any(|m| m == p))
        .and_then(with_subtasks)
        .or_else(|| rewards.methods.iter().find_map(|m| with_subtasks(m)))
}

/// Why `method` (which never reaches) does not, from the version of the sub-task rewards it
/// learns from; `None` when it learns from none.
pub(crate) fn why_never(experiment: &ExperimentFacts, method: &str) -> Option<String> {
    let rewards = experiment
        .reward_references
        .iter()
        .find(|r| r.methods.iter().any(|m| m == method))?;
    let values: Vec<String> = rewards
        .subtasks
        .iter()
        .map(|s| format!("*{}* {}", s.name, s.best_play().words()))
        .collect();
    let learned = learner_of(experiment, rewards, Some(method)).map_or_else(String::new, |b| {
        let closest: Vec<String> = rewards
            .subtasks
            .iter()
            .zip(&b.subtasks)
            .map(|(s, learned)| {
                format!(
                    "*{}* {}",
                    s.name,
                    s.closest_play(learned.learned_start_value).words()
                )
            })
            .collect();
        format!(
            "; their learners' start values are closest to {}",
            join(&closest)
        )
    });
    let paying = rewards
        .subtasks
        .iter()
        .filter(|s| s.reaching_pays())
        .count();
    Some(if paying == 0 {
        format!(
            "Why: under {} no sub-task's reward values reaching above both ending the episode \
             at once and idling (each values most: {}){learned}, so no aggregation of their \
             values leads to the target (the diagnosis below).",
            rewards_name(rewards),
            join(&values)
        )
    } else {
        format!(
            "Why: under {} {} of {} sub-tasks value reaching most (each values most: {}){learned}; \
             the aggregation of their values still does not lead to the target (the diagnosis \
             below).",
            rewards_name(rewards),
            paying,
            rewards.subtasks.len(),
            join(&values)
        )
    })
}

/// How most of a method's final-window episodes ended, in a few words with the number that
/// shows it.
fn endings_groups(methods: &[MethodBehaviour], action_names: &[String]) -> Option<String> {
    let mut reach = Vec::new();
    let mut early = Vec::new();
    let mut cap = Vec::new();
    for m in methods.iter().filter(|m| m.final_episodes > 0) {
        let e = m.final_endings;
        let title = method_title(&m.method);
        if e.reached >= e.failed && e.reached >= e.truncated {
            reach.push(format!(
                "{title} ({})",
                percent(share_of(e.reached, m.final_episodes))
            ));
        } else if e.failed >= e.truncated {
            early.push(format!(
                "{title} ({} steps per episode)",
                format_fixed(m.mean_final_steps, 0)
            ));
        } else {
            let shares = &m.action_shares;
            let top = (0..shares.len())
                .fold(0, |best, a| if shares[a] > shares[best] { a } else { best });
            cap.push(format!(
                "{title} (`{}` in {} of steps)",
                action_names.get(top).map_or("?", String::as_str),
                percent(shares.get(top).copied().unwrap_or(0.0))
            ));
        }
    }
    let mut parts = Vec::new();
    for (group, words) in [
        (reach, "**reach the target**"),
        (
            early,
            "**end early** without reaching (a hit or the target lost)",
        ),
        (cap, "**run to the step cap**"),
    ] {
        if !group.is_empty() {
            parts.push(format!("{words}: {}", group.join(", ")));
        }
    }
    (!parts.is_empty()).then(|| format!("Most final-window episodes {}.", parts.join("; most ")))
}

#[expect(
    clippy::cast_precision_loss,
    reason = "episode counts stay far below 2⁵³"
)]
fn share_of(count: u64, total: u64) -> f64 {
    if total == 0 {
        0.0
    } else {
        count as f64 / total as f64
    }
}

/// Appends the behaviour section of a robot experiment to `text`: its methods' behaviour
/// (`experiment.behaviour`, from [`behaviour()`](eamadm_eval::behaviour()) or a
/// [`BehaviourAccumulator`](eamadm_eval::BehaviourAccumulator) fed its runs), how their episodes end,
/// EA-MADM's sub-tasks, and the diagnosis of the sub-task rewards (`experiment.reward_references`);
/// `action_names` in the order of the action shares; `ea` is the paper's EA-MADM, whose
/// sub-tasks are detailed. A method that scores as an earlier one on every seed (`found`) is
/// one row of the table: its group's.
pub(crate) fn write_robot_behaviour(
    text: &mut String,
    experiment: &ExperimentFacts,
    overviews: &[&MethodOverview],
    action_names: &[String],
    ea: Option<&str>,
    found: Option<&TaskFindings>,
) {
    let methods = experiment.behaviour.as_slice();
    let gamma = experiment.gamma;
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
        (
            "seeds reaching in the final window".to_owned(),
            Align::Right,
        ),
        ("mean steps".to_owned(), Align::Right),
    ];
    columns.extend(
        action_names
            .iter()
            .map(|action| (action.clone(), Align::Right)),
    );
    let mut table = MarkdownTable::new(columns);
    for method in methods
        .iter()
        .filter(|m| found.is_none_or(|f| !f.identical.iter().any(|i| i.method == m.method)))
    {
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
    if let Some(sentence) = endings_groups(methods, action_names) {
        let _ = writeln!(text, "{sentence}\n");
    }

    // The sub-task detail of the paper's EA-MADM only; the ablations' action shares are above.
    for method in methods
        .iter()
        .filter(|m| !m.subtasks.is_empty() && Some(m.method.as_str()) == ea)
    {
        write_subtasks(text, method, gamma, action_names);
    }
    write_diagnosis(text, experiment, overviews, ea);
}

/// The diagnosis: per version of the sub-task rewards (the paper's, or with repairs), what each sub-task's reward definition
/// makes of three ways to play beside what its learner learned, then sentences from it.
fn write_diagnosis(
    text: &mut String,
    experiment: &ExperimentFacts,
    overviews: &[&MethodOverview],
    ea: Option<&str>,
) {
    let Some(first) = experiment.reward_references.first() else {
        return;
    };
    let _ = writeln!(
        text,
        "The diagnosis: each sub-task's reward definition values three ways to play an episode \
         (Σ γᵗ rₜ, γ = {}): reaching by a straight full-speed run ({} steps, nothing sensed), \
         ending the episode at once by losing the target, and idling at the start to the step \
         cap ({} steps). Beside them, what its learner learned: the mean over seeds of its \
         largest Q-value at the start state (the value of its greedy policy from the start), \
         and the way of playing that value is closest to:\n",
        format_fixed(experiment.gamma, 2),
        first.reach_steps,
        first.step_cap
    );
    let mut table = MarkdownTable::new([
        ("sub-task rewards", Align::Left),
        ("sub-task", Align::Left),
        ("reach", Align::Right),
        ("end at once", Align::Right),
        ("idle", Align::Right),
        ("values most", Align::Left),
        ("learned start value", Align::Right),
        ("closest to", Align::Left),
        ("learned by", Align::Left),
    ]);
    for rewards in &experiment.reward_references {
        let learner = learner_of(experiment, rewards, ea);
        for (k, s) in rewards.subtasks.iter().enumerate() {
            let learned = learner
                .and_then(|b| b.subtasks.get(k))
                .map(|b| b.learned_start_value);
            let _ = table.push_row([
                rewards_cell(rewards),
                s.name.clone(),
                number(s.reach),
                number(s.lose_at_once),
                number(s.idle),
                s.best_play().words().to_owned(),
                learned.map_or_else(|| "—".to_owned(), number),
                learned.map_or_else(|| "—".to_owned(), |v| s.closest_play(v).words().to_owned()),
                learner.map_or_else(|| "—".to_owned(), |b| format!("`{}`", b.method)),
            ]);
        }
    }
    text.push_str(&table.render());
    text.push('\n');
    for rewards in &experiment.reward_references {
        let learner = learner_of(experiment, rewards, ea);
        if rewards.repairs.is_empty() {
            for (k, s) in rewards.subtasks.iter().enumerate() {
                let learned = learner
                    .and_then(|b| b.subtasks.get(k))
                    .map(|b| b.learned_start_value);
                let _ = writeln!(
                    text,
                    "- {}",
                    subtask_sentence(s, learned, &experiment.behaviour)
                );
            }
        }
        let _ = writeln!(text, "- {}", rewards_outcome(rewards, overviews));
    }
    text.push('\n');
}

/// What one sub-task's reward values most, what its learner learned, and how it plays alone.
pub(crate) fn subtask_sentence(
    reference: &SubtaskReference,
    learned: Option<f64>,
    behaviour: &[MethodBehaviour],
) -> String {
    let best = reference.best_play();
    let others: Vec<String> = [Play::Reach, Play::LoseAtOnce, Play::Idle]
        .into_iter()
        .filter(|&p| p != best)
        .map(|p| format!("{} at {}", p.words(), number(reference.value(p))))
        .collect();
    let mut sentence = format!(
        "*{}* values {} most: {}, against {}.",
        reference.name,
        best.words(),
        number(reference.value(best)),
        join(&others)
    );
    if let Some(value) = learned {
        let _ = write!(
            sentence,
            " Its learner's start value, {}, is closest to {}.",
            number(value),
            reference.closest_play(value).words()
        );
    }
    for (label, learns) in &reference.alone {
        if let Some(m) = behaviour.iter().find(|m| &m.method == label) {
            let e = m.final_endings;
            let _ = write!(
                sentence,
                " Alone{} (`{label}`), its final-window episodes last {} steps on average: {} of \
                 {} reach, {} end early, {} are cut at the step cap.",
                if *learns { " and learning" } else { ", frozen" },
                format_fixed(m.mean_final_steps, 0),
                e.reached,
                m.final_episodes,
                e.failed,
                e.truncated
            );
        }
    }
    sentence
}

/// Which of the methods learning from `rewards` reach the target at all (any seed, training
/// or greedy), and whether those rewards value reaching.
pub(crate) fn rewards_outcome(rewards: &RewardReference, overviews: &[&MethodOverview]) -> String {
    let learners: Vec<&&MethodOverview> = overviews
        .iter()
        .filter(|o| rewards.methods.iter().any(|m| m == &o.method))
        .collect();
    let reaching: Vec<String> = learners
        .iter()
        .filter(|o| !never_reaches(o))
        .map(|o| {
            format!(
                "{} ({}/{} seeds in training)",
                method_title(&o.method),
                o.reaching_seeds,
                o.seeds
            )
        })
        .collect();
    let paying: Vec<String> = rewards
        .subtasks
        .iter()
        .filter(|s| s.reaching_pays())
        .map(|s| format!("*{}*", s.name))
        .collect();
    let values = if paying.is_empty() {
        "no sub-task's reward values reaching most".to_owned()
    } else {
        format!(
            "{} {} reaching most",
            join(&paying),
            if paying.len() == 1 { "values" } else { "value" }
        )
    };
    let labels: Vec<String> = learners.iter().map(|o| format!("`{}`", o.method)).collect();
    let outcome = match (learners.len(), reaching.len()) {
        (_, 0) if labels.len() == 1 => format!(
            "its only learner ({}) does not reach the target on any seed",
            labels.join("")
        ),
        (n, 0) => format!(
            "none of its {n} learners ({}) reaches the target on any seed",
            labels.join(", ")
        ),
        (n, k) => format!(
            "of its {n} learners, {k} {} the target: {}",
            if k == 1 { "reaches" } else { "reach" },
            join(&reaching)
        ),
    };
    let mut first = rewards_name(rewards);
    if let Some(c) = first.get(..1) {
        first = c.to_uppercase() + &first[1..];
    }
    format!("{first}: {values}, and {outcome}.")
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
    use eamadm_eval::stats::wilson;
    use eamadm_eval::{Endings, SubtaskBehaviour};

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

    fn experiment(
        behaviour: Vec<MethodBehaviour>,
        references: Vec<RewardReference>,
    ) -> ExperimentFacts {
        ExperimentFacts {
            name: "robot".to_owned(),
            title: "Robot".to_owned(),
            episodes: 200,
            seeds: 8,
            gamma: 0.95,
            figures: super::super::Figures::default(),
            behaviour,
            reward_references: references,
            final_epsilon: Vec::new(),
            margins: Vec::new(),
            methods: Vec::new(),
            paper_figures: eamadm_eval::facts::PaperFigures::default(),
            base_seed: 0,
            tables_written: false,
        }
    }

    #[test]
    fn no_methods_write_nothing() {
        let mut text = String::new();
        write_robot_behaviour(
            &mut text,
            &experiment(Vec::new(), Vec::new()),
            &[],
            &[],
            None,
            None,
        );
        assert!(text.is_empty());
    }

    fn reference(name: &str, [reach, lose_at_once, idle]: [f64; 3]) -> SubtaskReference {
        SubtaskReference {
            name: name.to_owned(),
            reach,
            lose_at_once,
            idle,
            alone: Vec::new(),
        }
    }

    /// The paper's rewards with the literal values of the default run (docs/paper-notes.md
    /// §8.6), and the goal-bonus repair under which *reach* values reaching most.
    fn references() -> Vec<RewardReference> {
        let mut reach = reference("reach", [-4.6, -0.78, -15.6]);
        reach.alone = vec![("subtask0-alone-learning".to_owned(), true)];
        vec![
            RewardReference {
                repairs: Vec::new(),
                methods: vec!["ea-madm".to_owned(), "subtask0-alone-learning".to_owned()],
                reach_steps: 14,
                step_cap: 250,
                subtasks: vec![
                    reach,
                    reference("avoid", [-3.0, -0.29, -5.9]),
                    reference("view", [20.5, -10.0, 40.0]),
                ],
            },
            RewardReference {
                repairs: vec!["goal bonus for reach".to_owned()],
                methods: vec!["ea-madm-goal-bonus".to_owned()],
                reach_steps: 14,
                step_cap: 250,
                subtasks: vec![
                    reference("reach", [45.0, -0.78, -15.6]),
                    reference("avoid", [-3.0, -0.29, -5.9]),
                    reference("view", [20.5, -10.0, 40.0]),
                ],
            },
        ]
    }

    fn subtask(name: &str, learned: f64) -> SubtaskBehaviour {
        SubtaskBehaviour {
            name: name.to_owned(),
            start_values: vec![learned - 1.0, learned],
            best_start_action: 1,
            learned_start_value: learned,
            agreement: 0.5,
            greedy_alone_steps: 100.0,
            greedy_alone_endings: Endings {
                reached: 0,
                failed: 1,
                truncated: 1,
            },
        }
    }

    fn behaviour() -> Vec<MethodBehaviour> {
        let mut ea = method(0, 160);
        ea.method = "ea-madm".to_owned();
        ea.final_endings = Endings {
            reached: 0,
            failed: 10,
            truncated: 150,
        };
        ea.action_shares = vec![0.1, 0.1, 0.0, 0.0, 0.8];
        ea.subtasks = vec![
            subtask("reach", -1.19),
            subtask("avoid", -0.12),
            subtask("view", 38.0),
        ];
        ea.decisions = 100;
        ea.dominant_subtask = Some(2);
        let mut alone = method(0, 160);
        alone.method = "subtask0-alone-learning".to_owned();
        alone.mean_final_steps = 2.0;
        let mut bonus = ea.clone();
        bonus.method = "ea-madm-goal-bonus".to_owned();
        bonus.subtasks[0].learned_start_value = -0.5;
        vec![ea, method(120, 160), alone, bonus]
    }

    /// Robot rows over 8 seeds: `reaching` methods reach in every seed, the others never.
    fn verdicts(methods: &[(&str, Role, &str, bool)]) -> Verdicts {
        let mut rows = Vec::new();
        for &(method, role, kind, reaching) in methods {
            for seed in 0..8 {
                let mut r = super::super::tests::row("robot", method, role, kind, seed, 250.0);
                r.greedy_reached = reaching;
                r.reaching_episodes = if reaching { 20 } else { 0 };
                r.reach_average_reward = reaching.then_some(10.0 + seed as f64);
                r.reach_time = reaching.then_some(8.0);
                r.retention_decay = reaching.then_some(-0.01);
                rows.push(r);
            }
        }
        Verdicts::compute(
            rows,
            &super::super::tests::options(),
            &super::super::tests::context(),
        )
        .unwrap()
    }

    const PAPER_SET: [(&str, Role, &str, bool); 4] = [
        ("ea-madm", Role::Paper, "ea_madm", false),
        ("softmax", Role::Paper, "softmax", true),
        ("ea-madm-goal-bonus", Role::Ablation, "ea_madm", false),
        (
            "subtask0-alone-learning",
            Role::Control,
            "subtask_greedy",
            false,
        ),
    ];

    #[test]
    fn c4_is_not_reproduced_with_the_counts_the_test_and_why() {
        let v = verdicts(&PAPER_SET);
        let overviews: Vec<&MethodOverview> = v.overviews.iter().collect();
        let facts = experiment(behaviour(), references());
        let judgement = |method: &str| {
            v.judgements
                .iter()
                .find(|j| j.claim.id == "C4" && j.method == method)
                .unwrap()
        };
        let mut explained = Vec::new();
        // 0/8 against 8/8: exact sign test p = 2 / 2⁸ = 0.0078.
        let paper = c4_sentence(judgement("ea-madm"), &facts, &overviews, &mut explained);
        assert!(
            paper.starts_with(
                "**EA-MADM** (the paper's method): C4 is **not reproduced** (verdict \
                 `contradicted`); it reaches the target on 0/8 seeds, against softmax on 8/8 \
                 (Holm p 0.008)"
            ),
            "{paper}"
        );
        assert!(
            paper.contains(
                "Why: under the paper's sub-task rewards (Eq. 6–8) no sub-task's reward values \
                 reaching above both"
            ),
            "{paper}"
        );
        assert!(
            paper.contains("*reach* ending the episode at once, *avoid* ending the episode at once and *view* idling to the step cap"),
            "{paper}"
        );
        // The repaired rewards: one sub-task values reaching, and the learned values follow
        // the variant's own sub-tasks.
        let bonus = c4_sentence(
            judgement("ea-madm-goal-bonus"),
            &facts,
            &overviews,
            &mut explained,
        );
        assert!(
            bonus.starts_with("`ea-madm-goal-bonus`: C4 is **not reproduced**"),
            "{bonus}"
        );
        assert!(
            bonus.contains("with goal bonus for reach 1 of 3 sub-tasks value reaching most"),
            "{bonus}"
        );
        assert!(
            bonus.contains("*reach* ending the episode at once"),
            "{bonus}"
        );
        // A later method on already explained rewards refers to the first.
        let again = c4_sentence(judgement("ea-madm"), &facts, &overviews, &mut explained);
        assert!(
            again.ends_with(" Why: the same sub-task rewards as EA-MADM above."),
            "{again}"
        );
        // Without sub-task rewards (a method on no sub-task rewards) there is no why.
        assert_eq!(
            why_never(&experiment(behaviour(), Vec::new()), "ea-madm"),
            None
        );
        // Nobody reaches: untestable, with the judgement's reason.
        let none = verdicts(&[
            ("ea-madm", Role::Paper, "ea_madm", false),
            ("softmax", Role::Paper, "softmax", false),
        ]);
        let overviews: Vec<&MethodOverview> = none.overviews.iter().collect();
        let j = none.judgements.iter().find(|j| j.claim.id == "C4").unwrap();
        let sentence = c4_sentence(j, &facts, &overviews, &mut Vec::new());
        assert!(
            sentence.contains("C4 is **not testable here** (verdict `untestable`); "),
            "{sentence}"
        );
        assert!(sentence.contains(&j.reason), "{sentence}");
    }

    #[test]
    fn the_verdict_table_states_a_reaching_verdict_by_its_test_alone() {
        let v = verdicts(&PAPER_SET);
        let context = super::super::tests::context();
        let findings = eamadm_eval::findings::Findings::of(&context, &v);
        let report = super::super::render(&context, &v, &findings);
        let row = report.lines().find(|l| l.starts_with("| C4 ")).unwrap();
        assert!(
            row.contains(
                "| EA-MADM reaches on 0/8 seeds, softmax on 8/8; exact paired sign test, Holm p \
                 0.008 "
            ),
            "{row}"
        );
        // Why the metrics could not be compared is the rule's (the appendix).
        assert!(!row.contains("value in 0 of"), "{row}");
    }

    #[test]
    fn the_answers_why_names_the_rewards_and_whether_any_sub_task_values_reaching() {
        let diagnosis = |repairs: &[&str], paying: [bool; 3]| eamadm_eval::findings::Diagnosis {
            repairs: repairs.iter().map(|r| (*r).to_owned()).collect(),
            subtasks: ["reach", "avoid", "view"]
                .into_iter()
                .zip(paying)
                .map(|(n, p)| (n.to_owned(), p))
                .collect(),
        };
        assert_eq!(
            super::super::answer::never_reaches_sentence(&diagnosis(&[], [false; 3])),
            "under the paper's sub-task rewards (Eq. 6–8) no sub-task's reward values reaching \
             the target above ending the episode at once or idling, so no aggregation of their \
             values leads to the target"
        );
        assert_eq!(
            super::super::answer::never_reaches_sentence(&diagnosis(
                &["goal bonus for reach"],
                [true, false, false]
            )),
            "under the sub-task rewards with goal bonus for reach only 1 of 3 sub-tasks value \
             reaching most, and the aggregation of their values still does not lead to the target"
        );
    }

    #[test]
    fn c4_of_a_method_that_reaches_is_decided_by_its_metrics() {
        let v = verdicts(&[
            ("ea-madm", Role::Paper, "ea_madm", true),
            ("softmax", Role::Paper, "softmax", true),
        ]);
        let overviews: Vec<&MethodOverview> = v.overviews.iter().collect();
        let j = v.judgements.iter().find(|j| j.claim.id == "C4").unwrap();
        assert!(j.reaching.is_empty());
        let sentence = c4_sentence(
            j,
            &experiment(behaviour(), references()),
            &overviews,
            &mut Vec::new(),
        );
        // Identical per seed: no comparison favours anyone.
        assert!(!sentence.contains("Why:"), "{sentence}");
        assert!(sentence.contains(&deciding_number(j)), "{sentence}");
        assert_eq!(reproduced(Verdict::Supported), "reproduced");
    }

    #[test]
    fn the_ranking_is_a_point_estimate_never_a_tested_claim() {
        let one = verdicts(&PAPER_SET[..2]);
        let overviews: Vec<&MethodOverview> = one.overviews.iter().collect();
        let sentence = robot_ranking("robot", &overviews, &one);
        assert!(sentence.starts_with("Only softmax reaches"), "{sentence}");
        assert!(!sentence.contains("highest"), "{sentence}");
        let two = verdicts(&[
            ("ea-madm", Role::Paper, "ea_madm", false),
            ("softmax", Role::Paper, "softmax", true),
            ("epsilon-greedy", Role::Paper, "epsilon_greedy", true),
        ]);
        let overviews: Vec<&MethodOverview> = two.overviews.iter().collect();
        let sentence = robot_ranking("robot", &overviews, &two);
        assert!(sentence.contains("highest point estimate"), "{sentence}");
        assert!(sentence.contains("not tested"), "{sentence}");
    }

    #[test]
    fn each_subtask_sentence_names_what_its_reward_values_most() {
        let [reach, avoid, view] =
            <[SubtaskReference; 3]>::try_from(references()[0].subtasks.clone()).unwrap();
        let sentence = subtask_sentence(&reach, Some(-1.19), &behaviour());
        assert_eq!(
            sentence,
            "*reach* values ending the episode at once most: -0.780, against reaching at -4.60 \
             and idling to the step cap at -15.6. Its learner's start value, -1.19, is closest \
             to ending the episode at once. Alone and learning (`subtask0-alone-learning`), its \
             final-window episodes last 2 steps on average: 0 of 160 reach, 160 end early, 0 are \
             cut at the step cap."
        );
        assert!(
            subtask_sentence(&view, Some(38.0), &[])
                .starts_with("*view* values idling to the step cap most: 40.0")
        );
        assert!(subtask_sentence(&avoid, None, &[]).ends_with("idling to the step cap at -5.90."));
        let pays = reference("reach", [45.0, -0.78, -15.6]);
        assert!(subtask_sentence(&pays, Some(44.0), &[]).contains("values reaching most: 45.0"));
        assert_eq!(pays.closest_play(44.0), Play::Reach);
    }

    #[test]
    fn a_rewards_outcome_lists_its_learners_that_reach_or_none() {
        let v = verdicts(&PAPER_SET);
        let overviews: Vec<&MethodOverview> = v.overviews.iter().collect();
        let paper = rewards_outcome(&references()[0], &overviews);
        assert_eq!(
            paper,
            "The paper's sub-task rewards (Eq. 6–8): no sub-task's reward values reaching most, \
             and none of its 2 learners (`ea-madm`, `subtask0-alone-learning`) reaches the \
             target on any seed."
        );
        let mut rewards = references()[1].clone();
        rewards.methods.push("softmax".to_owned());
        let bonus = rewards_outcome(&rewards, &overviews);
        assert!(bonus.starts_with("The sub-task rewards with goal bonus for reach: *reach* values reaching most, and of its 2 learners, 1 reaches the target: softmax (8/8 seeds in training)."), "{bonus}");
    }

    #[test]
    fn endings_sort_methods_by_how_most_episodes_end() {
        let names: Vec<String> = ["forward", "left", "right", "back", "stop"]
            .map(str::to_owned)
            .to_vec();
        let sentence = endings_groups(&behaviour(), &names).unwrap();
        assert_eq!(
            sentence,
            "Most final-window episodes **reach the target**: softmax (75%); most **end early** \
             without reaching (a hit or the target lost): subtask0-alone-learning (2 steps per \
             episode); most **run to the step cap**: EA-MADM (`stop` in 80% of steps), \
             ea-madm-goal-bonus (`stop` in 80% of steps)."
        );
        assert_eq!(endings_groups(&[], &names), None);
    }

    /// The robot's C4 and behaviour sections on a small fixture, as the report lays them out.
    #[test]
    fn the_robot_sections_read_as_pinned() {
        let v = verdicts(&PAPER_SET);
        let overviews: Vec<&MethodOverview> = v.overviews.iter().collect();
        let facts = experiment(behaviour(), references());
        let names: Vec<String> = ["forward", "left", "right", "back", "stop"]
            .map(str::to_owned)
            .to_vec();
        let mut text = String::new();
        write_robot(&mut text, &facts, &overviews, &v, None);
        write_robot_behaviour(&mut text, &facts, &overviews, &names, Some("ea-madm"), None);
        insta::assert_snapshot!(text);
    }
}
