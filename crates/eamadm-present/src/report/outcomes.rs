//! Per task: how each run ended (converged, collapsed, …) with the collapsed seeds and the
//! exact paired tests on converging, and the facts about the controls that explain the
//! verdicts: EA-MADM paired with its strongest sub-task alone, the verdicts judged again
//! without the collapses, which EA-MADM variants end as a sub-task alone seed for seed (all
//! from the findings), where the pre-training budget goes, and why the maze's τ sweep cannot
//! exercise aggregation (from the methods' configs).

use std::fmt::Write as _;

use eamadm_eval::Role;
use eamadm_eval::claims;
use eamadm_eval::facts::{ControlFamily, ReportContext};
use eamadm_eval::findings::{self, TaskFindings, converged, outcomes};
use eamadm_eval::scores::{FinalScore, RunOutcome};
use eamadm_eval::stats;
use eamadm_eval::verdicts::{Verdicts, collapsed_seeds};

use super::format::{Align, MarkdownTable, format_fixed, list, p_value};
use super::words::name;

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

/// The collapsed seeds of `method` as `14 (ep. 64), 16 (ep. 122)`, or `—`.
fn collapsed_list(scores: &[FinalScore], task: &str, method: &str) -> String {
    let seeds = collapsed_seeds(scores, task, method);
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

/// Paired by seed: seeds both ran, only `method` converged, only `versus` converged, and of
/// those `method` collapsed on.
fn discordant(
    scores: &[FinalScore],
    task: &str,
    method: &str,
    versus: &str,
) -> (usize, u64, u64, u64) {
    let theirs = outcomes(scores, task, versus);
    let (mut paired, mut only_method, mut only_versus, mut collapsed) = (0, 0, 0, 0);
    for (seed, a) in outcomes(scores, task, method) {
        if let Some(&(_, b)) = theirs.iter().find(|(s, _)| *s == seed) {
            paired += 1;
            let (ca, cb) = (a == RunOutcome::Converged, b == RunOutcome::Converged);
            only_method += u64::from(ca && !cb);
            only_versus += u64::from(cb && !ca);
            collapsed += u64::from(cb && a == RunOutcome::Collapsed);
        }
    }
    (paired, only_method, only_versus, collapsed)
}

/// The per-seed outcome section of `task`: a table of the paper's methods, the EA-MADM
/// variants and the strongest frozen sub-task alone with outcome counts (Wilson 95 %
/// intervals) and collapsed seeds (a method that scores as an earlier one on every seed is
/// left out with a sentence), then EA-MADM's exact paired tests on converging against each
/// competitor and that sub-task alone, and the findings' sentences on them.
pub(crate) fn write_outcomes(
    text: &mut String,
    task: &str,
    context: &ReportContext,
    verdicts: &Verdicts,
    found: Option<&TaskFindings>,
) {
    let scores = &verdicts.scores;
    let alone = findings::strongest_subtask_alone(context, scores, task);
    let identical =
        |method: &str| found.and_then(|f| f.identical.iter().find(|i| i.method == method));
    let methods: Vec<&str> = claims::methods(scores, task)
        .into_iter()
        .filter(|&(m, role, kind)| {
            role == Role::Paper || claims::is_under_test(kind) || Some(m) == alone
        })
        .map(|(m, _, _)| m)
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
    let mut same: Vec<String> = Vec::new();
    for &method in &methods {
        if let Some(i) = identical(method) {
            same.push(format!("`{}` as {}", i.method, name(&i.same_as)));
            continue;
        }
        let seeds = outcomes(scores, task, method);
        let _ = table.push_row([
            eamadm_eval::paper_claims::method_title(method),
            count_cell(&seeds, RunOutcome::Converged),
            count_cell(&seeds, RunOutcome::Collapsed),
            count_cell(&seeds, RunOutcome::ReachesWhileLearning),
            count_cell(&seeds, RunOutcome::NeverReached),
            collapsed_list(scores, task, method),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
    if !same.is_empty() {
        let _ = writeln!(
            text,
            "Not listed, since every seed ends as that method's: {}.\n",
            list(&same)
        );
    }

    let Some(ea) = verdicts.paper_ea_madm(task) else {
        return;
    };
    let versus: Vec<&str> = claims::methods(scores, task)
        .into_iter()
        .filter(|&(m, role, kind)| claims::is_competitor(role, kind) || Some(m) == alone)
        .map(|(m, _, _)| m)
        .collect();
    if versus.is_empty() {
        return;
    }
    let _ = writeln!(
        text,
        "EA-MADM against each competitor{} on converging, paired by seed (exact sign test on \
         the seeds only one of the two converged on, McNemar's exact test; raw p):\n",
        alone.map_or_else(String::new, |a| format!(" and `{a}`"))
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
        let (paired, only_method, only_versus, collapsed) = discordant(scores, task, ea, other);
        let _ = table.push_row([
            eamadm_eval::paper_claims::method_title(other),
            paired.to_string(),
            only_method.to_string(),
            only_versus.to_string(),
            collapsed.to_string(),
            p_value(stats::sign_test(only_method, only_versus)),
        ]);
    }
    text.push_str(&table.render());
    text.push('\n');
    if let Some(found) = found {
        for sentence in subtask_pairing(found)
            .into_iter()
            .chain(collapses_rejudged(found))
        {
            let _ = writeln!(text, "{sentence}\n");
        }
    }
}

/// EA-MADM paired by seed with its strongest frozen sub-task alone on converging, in words.
pub(crate) fn subtask_pairing(found: &TaskFindings) -> Option<String> {
    let p = found.subtask_pairing.as_ref()?;
    let control = &p.control;
    if p.only_method == 0 && p.only_control == 0 {
        return Some(if p.both == 0 {
            format!(
                "Neither EA-MADM nor `{control}` (its pre-trained sub-task acting alone) \
                 converges on any of the {} paired seeds.",
                p.paired
            )
        } else {
            format!(
                "EA-MADM and `{control}` (its pre-trained sub-task acting alone) converge on \
                 the same {} of {} paired seeds.",
                p.both, p.paired
            )
        });
    }
    let reverse = if p.only_method == 0 {
        "never the reverse".to_owned()
    } else {
        format!("the reverse on {}", p.only_method)
    };
    Some(format!(
        "Paired by seed with `{control}` (its pre-trained sub-task acting alone), EA-MADM fails \
         to converge on {} of {} seeds where the sub-task alone converges ({} of them \
         collapsed), {reverse}.",
        p.only_control, p.paired, p.method_collapsed
    ))
}

/// EA-MADM's verdicts judged again without its collapsed seeds, in words.
pub(crate) fn collapses_rejudged(found: &TaskFindings) -> Option<String> {
    let collapses = found.collapses.as_ref()?;
    if collapses.rejudged.is_empty() {
        return None;
    }
    let words: Vec<String> = collapses
        .rejudged
        .iter()
        .map(|r| format!("{} {} (was {})", r.claim, r.now.name(), r.was.name()))
        .collect();
    Some(format!(
        "Judged again without EA-MADM's collapsed seeds (left out of every method, so still \
         paired; a diagnosis, never a verdict): {}.",
        list(&words)
    ))
}

/// Which EA-MADM variants end as a sub-task alone seed for seed: a sentence and a table (pairs
/// that end alike on at least half the seeds); empty when none does.
pub(crate) fn equalities(found: &TaskFindings) -> String {
    if found.equalities.is_empty() {
        return String::new();
    }
    let mut table = MarkdownTable::new([
        ("EA-MADM variant", Align::Left),
        ("sub-task alone", Align::Left),
        ("ends the same", Align::Right),
        ("the same all through", Align::Right),
        (
            "still differing, on the seeds that end the same",
            Align::Left,
        ),
    ]);
    for eq in &found.equalities {
        let differing: Vec<String> = eq
            .differing
            .iter()
            .map(|(part, n)| format!("{part} on {n}"))
            .collect();
        let _ = table.push_row([
            name(&eq.method),
            format!("`{}`", eq.other),
            format!("{}/{}", eq.end_same, eq.both),
            eq.all_through.to_string(),
            if differing.is_empty() {
                "—".to_owned()
            } else {
                differing.join(", ")
            },
        ]);
    }
    format!(
        "Seed for seed, these EA-MADM variants end exactly as a sub-task alone (the same \
         final-window steps and return, greedy episode and outcome), and on some of those seeds \
         run the same all through (every score but the environment steps, which count each \
         method's own pre-training). On those seeds the sub-task's own experience, without the \
         MADM step, ends where EA-MADM does; the way there (the training curve, a collapse \
         episode) may differ. Pairs that end alike on fewer than half the seeds are not \
         listed.\n\n{}\n",
        table.render()
    )
}

/// Methods whose per-seed scores equal an earlier method's on every seed, in one sentence.
pub(crate) fn identical(found: &TaskFindings) -> Option<String> {
    let mut groups: Vec<(&str, Vec<String>, usize)> = Vec::new();
    for i in &found.identical {
        match groups
            .iter_mut()
            .find(|(same_as, _, _)| *same_as == i.same_as)
        {
            Some((_, methods, _)) => methods.push(format!("`{}`", i.method)),
            None => groups.push((&i.same_as, vec![format!("`{}`", i.method)], i.seeds)),
        }
    }
    let parts: Vec<String> = groups
        .iter()
        .map(|(same_as, methods, seeds)| {
            format!(
                "{} {} exactly as {} on all {seeds} seeds",
                list(methods),
                if methods.len() == 1 {
                    "scores"
                } else {
                    "score"
                },
                name(same_as)
            )
        })
        .collect();
    (!parts.is_empty()).then(|| {
        format!(
            "{}: whatever differs between them changes no score here, and the tables show \
             each such group once.",
            super::words::capitalised(&list(&parts))
        )
    })
}

/// The frozen sub-task-alone controls of `task` with their sub-task, from their configs.
fn frozen_alone<'a>(context: &'a ReportContext, task: &str) -> Vec<&'a str> {
    context.experiment(task).map_or_else(Vec::new, |e| {
        e.methods
            .iter()
            .filter(|m| {
                m.role == Role::Control
                    && matches!(
                        m.control,
                        Some(ControlFamily::SubtaskAlone { learns: false, .. })
                    )
            })
            .map(|m| m.label.as_str())
            .collect()
    })
}

/// Where EA-MADM's pre-training steps go: each sub-task's share, read off the frozen
/// sub-task-alone controls (each pre-trains its sub-task exactly as the EA-MADM run of the
/// same seed), stated only when their pre-training steps add up to EA-MADM's on every seed.
pub(crate) fn pretraining_shares(
    task: &str,
    context: &ReportContext,
    verdicts: &Verdicts,
) -> Option<String> {
    let scores = &verdicts.scores;
    let ea = verdicts.paper_ea_madm(task)?;
    let alone: Vec<&str> = frozen_alone(context, task)
        .into_iter()
        .filter(|m| !outcomes(scores, task, m).is_empty())
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
            let c = converged(scores, task, m);
            format!(
                "{}% to the sub-task of `{m}` (which alone converges on {}/{} seeds)",
                format_fixed(100.0 * t as f64 / all as f64, 0),
                c.hits,
                ea_rows.len()
            )
        })
        .collect();
    Some(format!(
        "Of EA-MADM's sub-task pre-training steps (summed over seeds) {}.",
        list(&parts)
    ))
}

/// The τ sweep on a maze: a state is the token set of its column and row, so two states'
/// Jaccard similarity is 0, 1/3 or 1; a threshold above 1/3 merges no two states and one at or
/// below merges whole rows or columns. Stated with how the EA-MADM controls with a tree
/// threshold below 1 (from their configs) came out.
pub(crate) fn tau_caveat(
    task: &str,
    context: &ReportContext,
    verdicts: &Verdicts,
    found: Option<&TaskFindings>,
) -> Option<String> {
    let scores = &verdicts.scores;
    let ea = verdicts.paper_ea_madm(task)?;
    let mut parts = Vec::new();
    for method in &context.experiment(task)?.methods {
        let Some(tau) = method.tree_threshold.filter(|t| *t < 1.0) else {
            continue;
        };
        if method.role != Role::Control || !claims::is_under_test(&method.kind) {
            continue;
        }
        let label = method.label.as_str();
        let seeds = outcomes(scores, task, label).len();
        if seeds == 0 {
            continue;
        }
        let equal = findings::equality(scores, task, label, ea).end_same;
        let same_as_ea = found.is_some_and(|f| {
            f.identical
                .iter()
                .any(|i| i.method == label && i.same_as == ea)
        });
        parts.push(if tau > 1.0 / 3.0 {
            format!(
                "τ = {tau} (above 1/3, exact) ends as EA-MADM on {equal}/{seeds} seeds{}",
                if same_as_ea {
                    " and scores as it on every one"
                } else {
                    ""
                }
            )
        } else {
            format!(
                "τ = {tau} (at or below 1/3, it merges whole rows or columns) converges on \
                 {}/{seeds} seeds",
                converged(scores, task, label).hits
            )
        });
    }
    (!parts.is_empty()).then(|| {
        format!(
            "The τ sweep cannot exercise aggregation on a maze: a state is the token set of its \
             column and row, so two states' Jaccard similarity takes only the values 0, 1/3 and \
             1, and no threshold merges a few similar states. Here {}.",
            list(&parts)
        )
    })
}

#[cfg(test)]
mod tests {
    use super::super::tests::{context, method, options, row};
    use super::*;
    use eamadm_eval::findings::Findings;

    /// The context with Task I's methods of these tests, by their configs: the sub-tasks
    /// alone (frozen), two ablations, and EA-MADM with tree thresholds 0.5 and 0.33 as
    /// controls (labels that say nothing of what they are).
    fn context_of() -> ReportContext {
        let mut context = context();
        let alone = |subtask| {
            Some(ControlFamily::SubtaskAlone {
                subtask,
                learns: false,
            })
        };
        let mut high = method("wide", Role::Control, "ea_madm", None);
        high.tree_threshold = Some(0.5);
        let mut low = method("narrow", Role::Control, "ea_madm", None);
        low.tree_threshold = Some(0.33);
        context.experiments[0].methods = vec![
            method("ea-madm", Role::Paper, "ea_madm", None),
            method("first", Role::Control, "subtask_greedy", alone(0)),
            method("second", Role::Control, "subtask_greedy", alone(1)),
            method("ea-madm-uniform", Role::Ablation, "ea_madm", None),
            method("ea-madm-distance", Role::Ablation, "ea_madm", None),
            high,
            low,
        ];
        context
    }

    fn verdicts(scores: Vec<FinalScore>) -> Verdicts {
        Verdicts::compute(scores, &options(), &context_of()).unwrap()
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
                "first",
                Role::Control,
                "subtask_greedy",
                seed,
                60.0,
            );
            a.pretrain_env_steps = p0;
            rows.push(a);
            let mut b = row(
                "task1",
                "second",
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
        let context = context_of();
        let text =
            pretraining_shares("task1", &context, &verdicts(pretraining(50, 950, 0))).unwrap();
        assert_eq!(
            text,
            "Of EA-MADM's sub-task pre-training steps (summed over seeds) 5% to the sub-task of \
             `first` (which alone converges on 4/4 seeds) and 95% to the sub-task of `second` \
             (which alone converges on 0/4 seeds)."
        );
        assert_eq!(
            pretraining_shares("task1", &context, &verdicts(pretraining(50, 950, 1))),
            None
        );
    }

    #[test]
    fn equalities_are_a_table_of_variants_ending_as_a_sub_task_alone() {
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
            let distance = 70.0 + seed as f64;
            rows.push(row(
                "task1",
                "ea-madm-distance",
                Role::Ablation,
                "ea_madm",
                seed,
                distance,
            ));
        }
        let verdicts = verdicts(rows);
        let found = Findings::of(&context_of(), &verdicts);
        let text = equalities(&found.tasks[0]);
        let uniform = text
            .lines()
            .find(|l| l.starts_with("| `ea-madm-uniform`"))
            .unwrap();
        let cells: Vec<&str> = uniform.split('|').map(str::trim).collect();
        assert_eq!(
            cells[1..6],
            [
                "`ea-madm-uniform`",
                "`first`",
                "3/4",
                "2",
                "the training curve's SD on 1, the collapse episode or the count of reaching \
                 episodes on 1"
            ]
        );
        assert!(!text.contains("distance"), "{text}");
        // The sub-task alone is the one that converges on most seeds, by config.
        let pairing = subtask_pairing(&found.tasks[0]).unwrap();
        assert!(pairing.contains("`first`"), "{pairing}");
    }

    #[test]
    fn the_tau_caveat_names_exact_and_merging_thresholds_from_the_configs() {
        let mut rows = Vec::new();
        for seed in 0..4 {
            rows.push(row("task1", "ea-madm", Role::Paper, "ea_madm", seed, 60.0));
            rows.push(row("task1", "wide", Role::Control, "ea_madm", seed, 60.0));
            let mut low = row("task1", "narrow", Role::Control, "ea_madm", seed, 2000.0);
            low.outcome = RunOutcome::NeverReached;
            rows.push(low);
        }
        let verdicts = verdicts(rows);
        let found = Findings::of(&context_of(), &verdicts);
        let text = tau_caveat("task1", &context_of(), &verdicts, found.task("task1")).unwrap();
        assert!(
            text.ends_with(
                "Here τ = 0.5 (above 1/3, exact) ends as EA-MADM on 4/4 seeds and scores as it \
                 on every one and τ = 0.33 (at or below 1/3, it merges whole rows or columns) \
                 converges on 0/4 seeds."
            ),
            "{text}"
        );
        // Without the thresholds in the methods' facts, no caveat.
        let mut bare = context_of();
        bare.experiments[0]
            .methods
            .iter_mut()
            .for_each(|m| m.tree_threshold = None);
        assert_eq!(tau_caveat("task1", &bare, &verdicts, None), None);
    }
}
