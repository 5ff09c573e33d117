//! Per task: how each run ended (converged, collapsed, …) with the collapsed seeds and the
//! exact paired tests, and the facts about the controls that explain the verdicts: which
//! EA-MADM variants equal a sub-task alone seed for seed, where the pre-training budget goes,
//! and why the maze's τ sweep cannot exercise aggregation.

use std::fmt::Write as _;

use super::Verdicts;
use super::format::{Align, MarkdownTable, format_fixed, p_value};
use eamadm_eval::Role;
use eamadm_eval::claims::{self, SUBTASK_ALONE};
use eamadm_eval::paper_claims::method_title;
use eamadm_eval::scores::{FinalScore, RunOutcome};
use eamadm_eval::stats;

/// The outcomes of `method`'s seeds on `task`, by seed.
pub(crate) fn outcomes(scores: &[FinalScore], task: &str, method: &str) -> Vec<(u64, RunOutcome)> {
    let mut seeds: Vec<(u64, RunOutcome)> = scores
        .iter()
        .filter(|s| s.task == task && s.method == method)
        .map(|s| (s.seed, s.outcome))
        .collect();
    seeds.sort_unstable();
    seeds
}

/// Paired by seed: (seeds where `method` converged and `versus` did not, the reverse), and the
/// seeds of the first kind on which `method` collapsed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Discordant {
    /// Seeds both ran.
    pub(crate) paired: usize,
    /// Seeds only `method` converged on.
    pub(crate) only_method: u64,
    /// Seeds only `versus` converged on.
    pub(crate) only_versus: u64,
    /// Seeds `versus` converged on while `method` collapsed.
    pub(crate) method_collapsed: u64,
}

pub(crate) fn discordant(
    scores: &[FinalScore],
    task: &str,
    method: &str,
    versus: &str,
) -> Discordant {
    let mine = outcomes(scores, task, method);
    let theirs = outcomes(scores, task, versus);
    let mut d = Discordant {
        paired: 0,
        only_method: 0,
        only_versus: 0,
        method_collapsed: 0,
    };
    for &(seed, a) in &mine {
        if let Some(&(_, b)) = theirs.iter().find(|(s, _)| *s == seed) {
            d.paired += 1;
            let (ca, cb) = (a == RunOutcome::Converged, b == RunOutcome::Converged);
            d.only_method += u64::from(ca && !cb);
            d.only_versus += u64::from(cb && !ca);
            d.method_collapsed += u64::from(cb && a == RunOutcome::Collapsed);
        }
    }
    d
}

fn count_cell(seeds: &[(u64, RunOutcome)], outcome: RunOutcome) -> String {
    let hits = seeds.iter().filter(|(_, o)| *o == outcome).count() as u64;
    let trials = seeds.len() as u64;
    match stats::wilson(hits, trials, 0.95) {
        Ok(w) => format!(
            "{hits}/{trials} [{}, {}]%",
            format_fixed(w.low * 100.0, 0),
            format_fixed(w.high * 100.0, 0)
        ),
        Err(_) => format!("{hits}/{trials}"),
    }
}

/// The collapsed seeds of `method` as `seed 14 (ep. 64), seed 16 (ep. 122)`, or `—`.
pub(crate) fn collapsed_list(scores: &[FinalScore], task: &str, method: &str) -> String {
    let seeds = eamadm_eval::verdicts::collapsed_seeds(scores, task, method);
    if seeds.is_empty() {
        return "—".to_owned();
    }
    seeds
        .iter()
        .map(|(seed, episode)| match episode {
            Some(e) => format!("{seed} (ep. {e})"),
            None => format!("{seed}"),
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The per-seed outcome section of `task`: a table of the paper's methods, the EA-MADM
/// variants and [`SUBTASK_ALONE`] with outcome counts (Wilson 95 % intervals) and collapsed
/// seeds, then EA-MADM's exact paired tests on converging against each competitor and
/// [`SUBTASK_ALONE`].
pub(crate) fn write_outcomes(text: &mut String, task: &str, verdicts: &Verdicts) {
    let scores = &verdicts.scores;
    let methods: Vec<(&str, Role, &str)> = claims::methods(scores, task)
        .into_iter()
        .filter(|&(m, role, kind)| {
            role == Role::Paper || claims::is_under_test(kind) || m == SUBTASK_ALONE
        })
        .collect();
    if methods.is_empty() {
        return;
    }
    let _ = writeln!(
        text,
        "How each run ended (see the glossary; seeds with Wilson 95% intervals; a collapsed \
         seed with the episode from which it never reached again):\n"
    );
    let mut table = MarkdownTable::new([
        ("method", Align::Left),
        ("converged", Align::Right),
        ("collapsed", Align::Right),
        ("reaches while learning", Align::Right),
        ("never reached", Align::Right),
        ("collapsed seeds (episode)", Align::Left),
    ]);
    for &(method, _, _) in &methods {
        let seeds = outcomes(scores, task, method);
        let _ = table.push_row([
            method_title(method),
            count_cell(&seeds, RunOutcome::Converged),
            count_cell(&seeds, RunOutcome::Collapsed),
            count_cell(&seeds, RunOutcome::ReachesWhileLearning),
            count_cell(&seeds, RunOutcome::NeverReached),
            collapsed_list(scores, task, method),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');

    let Some(ea) = verdicts.paper_ea_madm(task) else {
        return;
    };
    let versus: Vec<&str> = claims::methods(scores, task)
        .into_iter()
        .filter(|&(m, role, kind)| claims::is_competitor(role, kind) || m == SUBTASK_ALONE)
        .map(|(m, _, _)| m)
        .collect();
    if versus.is_empty() {
        return;
    }
    let _ = writeln!(
        text,
        "EA-MADM against each competitor and `{SUBTASK_ALONE}` on converging, paired by seed \
         (exact sign test on the seeds only one of the two converged on, McNemar's exact test; \
         raw p):\n"
    );
    let mut table = MarkdownTable::new([
        ("versus", Align::Left),
        ("paired seeds", Align::Right),
        ("only EA-MADM converged", Align::Right),
        ("only the other converged", Align::Right),
        ("of which EA-MADM collapsed", Align::Right),
        ("p", Align::Right),
    ]);
    for other in versus {
        let d = discordant(scores, task, ea, other);
        let _ = table.push_row([
            method_title(other),
            d.paired.to_string(),
            d.only_method.to_string(),
            d.only_versus.to_string(),
            d.method_collapsed.to_string(),
            p_value(stats::sign_test(d.only_method, d.only_versus)),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
    for sentence in subtask_pairing(scores, task, ea)
        .into_iter()
        .chain(collapses_rejudged(verdicts, task, ea))
    {
        let _ = writeln!(text, "{sentence}\n");
    }
}

/// EA-MADM paired by seed with [`SUBTASK_ALONE`] on converging, in words: where one converges
/// and the other does not, or that they converge on the same seeds (none: neither converges);
/// `None` when the sub-task alone was not run.
pub(crate) fn subtask_pairing(scores: &[FinalScore], task: &str, ea: &str) -> Option<String> {
    let d = discordant(scores, task, ea, SUBTASK_ALONE);
    if d.paired == 0 {
        return None;
    }
    if d.only_method == 0 && d.only_versus == 0 {
        let both = outcomes(scores, task, ea)
            .iter()
            .filter(|(_, o)| *o == RunOutcome::Converged)
            .count();
        return Some(if both == 0 {
            format!(
                "Neither EA-MADM nor `{SUBTASK_ALONE}` (its pre-trained sub-task acting alone) \
                 converges on any of the {} paired seeds.",
                d.paired
            )
        } else {
            format!(
                "EA-MADM and `{SUBTASK_ALONE}` (its pre-trained sub-task acting alone) converge \
                 on the same {both} of {} paired seeds.",
                d.paired
            )
        });
    }
    let reverse = if d.only_method == 0 {
        "never the reverse".to_owned()
    } else {
        format!("the reverse on {}", d.only_method)
    };
    Some(format!(
        "Paired by seed with `{SUBTASK_ALONE}` (its pre-trained sub-task acting alone), EA-MADM \
         fails to converge on {} of {} seeds where the sub-task alone converges ({} of them \
         collapsed), {reverse}.",
        d.only_versus, d.paired, d.method_collapsed
    ))
}

/// The paper EA-MADM's verdicts judged again without its collapsed seeds (left out of every
/// method), in words: which would be better, which not; `None` when none was judged again.
pub(crate) fn collapses_rejudged(verdicts: &Verdicts, task: &str, ea: &str) -> Option<String> {
    let again: Vec<&claims::Judgement> = verdicts
        .without_collapses
        .iter()
        .filter(|j| j.task == task && j.method == ea)
        .collect();
    if again.is_empty() {
        return None;
    }
    let words: Vec<String> = again
        .iter()
        .map(|j| {
            let before = verdicts
                .judgements
                .iter()
                .find(|b| b.task == task && b.method == ea && b.claim.id == j.claim.id)
                .map_or("—", |b| b.verdict.name());
            format!("{} {} (was {before})", j.claim.id, j.verdict.name())
        })
        .collect();
    Some(format!(
        "Judged again without EA-MADM's collapsed seeds (left out of every method, so still \
         paired; a diagnosis, never a verdict): {}.",
        super::format::list(&words)
    ))
}

/// `subtaskN-alone`: one pre-trained sub-task acting alone with frozen values, the same
/// learner as in the EA-MADM run of the seed (the `-learning` variants keep learning).
fn is_frozen_subtask_alone(label: &str) -> bool {
    label
        .strip_prefix("subtask")
        .and_then(|rest| rest.strip_suffix("-alone"))
        .is_some_and(|n| n.parse::<usize>().is_ok())
}

/// A method as a sentence names it: the paper's methods by title, others by label in code.
fn label(method: &str) -> String {
    let title = method_title(method);
    if title == method {
        format!("`{method}`")
    } else {
        title
    }
}

/// Whether two runs of one seed end the same: final-window steps and return, the greedy
/// episode and the outcome (the training curves before may differ, e.g. a collapse episode).
fn same_scores(a: &FinalScore, b: &FinalScore) -> bool {
    a.seed == b.seed
        && a.final_steps == b.final_steps
        && a.final_return == b.final_return
        && a.greedy_steps == b.greedy_steps
        && a.outcome == b.outcome
}

/// The parts of two runs of one seed that end the same ([`same_scores`]) which still differ,
/// named as a sentence names them; empty when the runs are the same all through (every score
/// but the environment steps, which count each method's own pre-training).
fn differing_parts(a: &FinalScore, b: &FinalScore) -> Vec<&'static str> {
    let mut parts = Vec::new();
    if a.fluctuation_steps != b.fluctuation_steps || a.fluctuation_return != b.fluctuation_return {
        parts.push("the training curve's SD");
    }
    if a.collapse_episode != b.collapse_episode || a.reaching_episodes != b.reaching_episodes {
        parts.push("the collapse episode or the count of reaching episodes");
    }
    if a.greedy_evaluations != b.greedy_evaluations
        || a.stable_reaching != b.stable_reaching
        || a.fluctuation_greedy_steps != b.fluctuation_greedy_steps
        || a.fluctuation_greedy_return != b.fluctuation_greedy_return
    {
        parts.push("the greedy evaluations");
    }
    if a.success_rate != b.success_rate {
        parts.push("the final-window success");
    }
    if a.reach_average_reward != b.reach_average_reward
        || a.reach_time != b.reach_time
        || a.reach_retention_time != b.reach_retention_time
        || a.retention_decay != b.retention_decay
    {
        parts.push("the robot's reaching scores");
    }
    parts
}

/// How far two methods' runs agree seed for seed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Equality {
    /// Seeds both ran.
    pub(crate) both: usize,
    /// Seeds on which the two end the same ([`same_scores`]).
    pub(crate) end_same: usize,
    /// Of those, seeds on which they are the same all through ([`differing_parts`] empty).
    pub(crate) all_through: usize,
    /// Of those that end the same, on how many seeds each part still differs, in the order of
    /// [`differing_parts`].
    pub(crate) differing: Vec<(&'static str, usize)>,
}

/// How far `method` and `other` agree seed for seed on `task`.
pub(crate) fn equality(scores: &[FinalScore], task: &str, method: &str, other: &str) -> Equality {
    let rows = |m: &str| -> Vec<&FinalScore> {
        scores
            .iter()
            .filter(|s| s.task == task && s.method == m)
            .collect()
    };
    let theirs = rows(other);
    let mut eq = Equality {
        both: 0,
        end_same: 0,
        all_through: 0,
        differing: Vec::new(),
    };
    for a in rows(method) {
        let Some(b) = theirs.iter().find(|b| b.seed == a.seed) else {
            continue;
        };
        eq.both += 1;
        if !same_scores(a, b) {
            continue;
        }
        eq.end_same += 1;
        let parts = differing_parts(a, b);
        eq.all_through += usize::from(parts.is_empty());
        for part in parts {
            match eq.differing.iter_mut().find(|(p, _)| *p == part) {
                Some((_, n)) => *n += 1,
                None => eq.differing.push((part, 1)),
            }
        }
    }
    eq
}

/// Seeds on which `method` and `other` end the same, and the seeds both ran.
pub(crate) fn equal_seeds(
    scores: &[FinalScore],
    task: &str,
    method: &str,
    other: &str,
) -> (usize, usize) {
    let eq = equality(scores, task, method, other);
    (eq.end_same, eq.both)
}

/// Which EA-MADM variants end as a sub-task alone seed for seed, on how many seeds, and on how
/// many of those they are the same all through (with what still differs): pairs that end the
/// same on at least half the seeds, in one sentence.
pub(crate) fn equalities_with_subtasks(task: &str, verdicts: &Verdicts) -> Option<String> {
    let scores = &verdicts.scores;
    let methods = claims::methods(scores, task);
    let mut pairs = Vec::new();
    for &(method, _, kind) in &methods {
        if !claims::is_under_test(kind) {
            continue;
        }
        for &(other, role, _) in &methods {
            if role != Role::Control || !is_frozen_subtask_alone(other) {
                continue;
            }
            let eq = equality(scores, task, method, other);
            if eq.both > 0 && 2 * eq.end_same >= eq.both {
                let differing: Vec<String> = eq
                    .differing
                    .iter()
                    .map(|(part, n)| format!("{part} on {n}"))
                    .collect();
                pairs.push(format!(
                    "{} = `{other}` on {}/{}, all through on {}{}",
                    label(method),
                    eq.end_same,
                    eq.both,
                    eq.all_through,
                    if differing.is_empty() {
                        String::new()
                    } else {
                        format!(" (still differing: {})", differing.join(", "))
                    }
                ));
            }
        }
    }
    (!pairs.is_empty()).then(|| {
        format!(
            "Seed for seed, these EA-MADM variants end exactly as a sub-task alone (the same \
             final-window steps and return, greedy episode and outcome), and on some of those \
             seeds run the same all through (every score but the environment steps, which \
             count each method's own pre-training): {}. On the seeds they end alike the \
             sub-task's own experience, without the MADM step, ends where EA-MADM does; the \
             way there (the training curve, a collapse episode) may differ (pairs that end \
             alike on fewer than half the seeds are not listed).",
            pairs.join("; ")
        )
    })
}

/// Where EA-MADM's pre-training steps go: each sub-task's share, read off the `subtaskN-alone`
/// controls (each pre-trains its sub-task exactly as the EA-MADM run of the same seed), stated
/// only when their pre-training steps add up to EA-MADM's on every seed.
pub(crate) fn pretraining_shares(task: &str, verdicts: &Verdicts) -> Option<String> {
    let scores = &verdicts.scores;
    let ea = verdicts.paper_ea_madm(task)?;
    let alone: Vec<&str> = claims::methods(scores, task)
        .into_iter()
        .filter(|&(m, role, _)| role == Role::Control && is_frozen_subtask_alone(m))
        .map(|(m, _, _)| m)
        .collect();
    if alone.is_empty() {
        return None;
    }
    let rows = |m: &str| -> Vec<&FinalScore> {
        scores
            .iter()
            .filter(|s| s.task == task && s.method == m)
            .collect()
    };
    let ea_rows = rows(ea);
    let mut totals = vec![0_u64; alone.len()];
    for row in &ea_rows {
        let mut sum = 0;
        for (i, m) in alone.iter().enumerate() {
            let steps = rows(m)
                .iter()
                .find(|s| s.seed == row.seed)
                .map(|s| s.pretrain_env_steps)?;
            totals[i] += steps;
            sum += steps;
        }
        if sum != row.pretrain_env_steps {
            return None;
        }
    }
    let all: u64 = totals.iter().sum();
    if all == 0 {
        return None;
    }
    let parts: Vec<String> = alone
        .iter()
        .zip(&totals)
        .map(|(m, &t)| {
            let converged = outcomes(scores, task, m)
                .iter()
                .filter(|(_, o)| *o == RunOutcome::Converged)
                .count();
            format!(
                "{}% to the sub-task of `{m}` (which alone converges on {converged}/{} seeds)",
                format_fixed(100.0 * t as f64 / all as f64, 0),
                ea_rows.len()
            )
        })
        .collect();
    Some(format!(
        "Of EA-MADM's sub-task pre-training steps (summed over seeds) {}.",
        super::format::list(&parts)
    ))
}

/// The τ sweep on a maze: a state is the token set of its column and row, so two states'
/// Jaccard similarity is 0, 1/3 or 1; a threshold above 1/3 merges no two states and one at or
/// below merges whole rows or columns. Stated with how the `ea-madm-tau*` controls came out.
pub(crate) fn tau_caveat(task: &str, verdicts: &Verdicts) -> Option<String> {
    let scores = &verdicts.scores;
    let ea = verdicts.paper_ea_madm(task)?;
    let mut parts = Vec::new();
    for (method, _, kind) in claims::methods(scores, task) {
        let Some(tau) = method
            .strip_prefix("ea-madm-tau")
            .and_then(|t| t.parse::<f64>().ok())
        else {
            continue;
        };
        if !claims::is_under_test(kind) {
            continue;
        }
        let (equal, both) = equal_seeds(scores, task, method, ea);
        let converged = outcomes(scores, task, method)
            .iter()
            .filter(|(_, o)| *o == RunOutcome::Converged)
            .count();
        parts.push(if tau > 1.0 / 3.0 {
            format!("τ = {tau} (above 1/3, exact) equals EA-MADM on {equal}/{both} seeds")
        } else {
            format!(
                "τ = {tau} (at or below 1/3, it merges whole rows or columns) converges on \
                 {converged}/{both} seeds"
            )
        });
    }
    (!parts.is_empty()).then(|| {
        format!(
            "The τ sweep cannot exercise aggregation on a maze: a state is the token set of its \
             column and row, so two states' Jaccard similarity takes only the values 0, 1/3 and \
             1, and no threshold merges a few similar states. Here {}.",
            super::format::list(&parts)
        )
    })
}

#[cfg(test)]
mod tests {
    use super::super::tests::{options, row};
    use super::*;

    fn verdicts(scores: Vec<FinalScore>) -> Verdicts {
        Verdicts {
            scores,
            judgements: Vec::new(),
            estimates: Vec::new(),
            overviews: Vec::new(),
            controls: Vec::new(),
            against_strongest: Vec::new(),
            without_collapses: Vec::new(),
            survives_readings: Vec::new(),
            options: options(),
            sensitivity: Vec::new(),
        }
    }

    /// EA-MADM and its two sub-tasks alone on 4 seeds: sub-task 0 pre-trains `p0` steps,
    /// sub-task 1 `p1`, EA-MADM `p0 + p1 + extra`.
    fn pretraining(p0: u64, p1: u64, extra: u64) -> Vec<FinalScore> {
        let mut rows = Vec::new();
        for seed in 0..4 {
            let mut ea = row("task1", "ea-madm", Role::Paper, "ea_madm", seed, 60.0);
            ea.pretrain_env_steps = p0 + p1 + extra;
            rows.push(ea);
            let mut a = row(
                "task1",
                "subtask0-alone",
                Role::Control,
                "subtask_greedy",
                seed,
                60.0,
            );
            a.pretrain_env_steps = p0;
            rows.push(a);
            let mut b = row(
                "task1",
                "subtask1-alone",
                Role::Control,
                "subtask_greedy",
                seed,
                2000.0,
            );
            b.pretrain_env_steps = p1;
            b.outcome = RunOutcome::NeverReached;
            rows.push(b);
        }
        rows
    }

    #[test]
    fn pretraining_shares_are_stated_only_when_the_sub_tasks_add_up() {
        let text = pretraining_shares("task1", &verdicts(pretraining(50, 950, 0))).unwrap();
        assert_eq!(
            text,
            "Of EA-MADM's sub-task pre-training steps (summed over seeds) 5% to the sub-task of \
             `subtask0-alone` (which alone converges on 4/4 seeds) and 95% to the sub-task of \
             `subtask1-alone` (which alone converges on 0/4 seeds)."
        );
        assert_eq!(
            pretraining_shares("task1", &verdicts(pretraining(50, 950, 1))),
            None
        );
    }

    #[test]
    fn equalities_count_the_seeds_a_variant_equals_a_sub_task_alone() {
        let mut rows = pretraining(50, 950, 0);
        for seed in 0..4 {
            let mut u = row(
                "task1",
                "ea-madm-uniform",
                Role::Ablation,
                "ea_madm",
                seed,
                60.0,
            );
            if seed == 3 {
                u.final_steps = 61.0;
            }
            // Ends the same, but the way there differs.
            if seed == 0 {
                u.fluctuation_steps += 1.0;
                u.collapse_episode = Some(7);
            }
            rows.push(u);
            rows.push(row(
                "task1",
                "ea-madm-distance",
                Role::Ablation,
                "ea_madm",
                seed,
                70.0 + seed as f64,
            ));
        }
        let text = equalities_with_subtasks("task1", &verdicts(rows)).unwrap();
        assert!(
            text.contains(
                ": EA-MADM = `subtask0-alone` on 4/4, all through on 4; `ea-madm-uniform` = \
                 `subtask0-alone` on 3/4, all through on 2 (still differing: the training \
                 curve's SD on 1, the collapse episode or the count of reaching episodes on 1)."
            ),
            "{text}"
        );
        assert!(!text.contains("distance"), "{text}");
        let none = pretraining(50, 950, 0)
            .into_iter()
            .filter(|r| r.method != "subtask0-alone")
            .collect();
        assert_eq!(equalities_with_subtasks("task1", &verdicts(none)), None);
    }

    #[test]
    fn the_tau_caveat_names_exact_and_merging_thresholds() {
        let mut rows = Vec::new();
        for seed in 0..4 {
            rows.push(row("task1", "ea-madm", Role::Paper, "ea_madm", seed, 60.0));
            rows.push(row(
                "task1",
                "ea-madm-tau0.5",
                Role::Control,
                "ea_madm",
                seed,
                60.0,
            ));
            let mut low = row(
                "task1",
                "ea-madm-tau0.33",
                Role::Control,
                "ea_madm",
                seed,
                2000.0,
            );
            if seed > 0 {
                low.outcome = RunOutcome::Collapsed;
            }
            rows.push(low);
        }
        let text = tau_caveat("task1", &verdicts(rows.clone())).unwrap();
        assert!(
            text.contains("takes only the values 0, 1/3 and 1"),
            "{text}"
        );
        assert!(
            text.ends_with(
                "Here τ = 0.5 (above 1/3, exact) equals EA-MADM on 4/4 seeds and τ = 0.33 (at \
                 or below 1/3, it merges whole rows or columns) converges on 1/4 seeds."
            ),
            "{text}"
        );
        rows.retain(|r| !r.method.starts_with("ea-madm-tau"));
        assert_eq!(tau_caveat("task1", &verdicts(rows)), None);
    }

    #[test]
    fn the_outcome_tables_count_collapses_and_pair_with_the_sub_task() {
        let mut rows = pretraining(50, 950, 0);
        rows.retain(|r| r.method != "subtask1-alone");
        for seed in 0..4 {
            rows.push(row("task1", "softmax", Role::Paper, "softmax", seed, 60.0));
        }
        for r in rows
            .iter_mut()
            .filter(|r| r.method == "ea-madm" && r.seed == 2)
        {
            r.outcome = RunOutcome::Collapsed;
            r.collapse_episode = Some(122);
        }
        let mut text = String::new();
        write_outcomes(&mut text, "task1", &verdicts(rows));
        let ea = text.lines().find(|l| l.starts_with("| EA-MADM")).unwrap();
        assert!(ea.contains(" 3/4 [30, 95]% | 1/4 [5, 70]% "), "{ea}");
        assert!(ea.contains("| 2 (ep. 122) "), "{ea}");
        // The paired table comes second.
        let alone = text
            .lines()
            .rfind(|l| l.starts_with("| subtask0-alone"))
            .unwrap();
        let cells: Vec<&str> = alone.split('|').map(str::trim).collect();
        assert_eq!(&cells[2..7], ["4", "0", "1", "1", "1.000"], "{alone}");
    }
}
