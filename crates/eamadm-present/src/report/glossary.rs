//! The report's glossary: each term the text uses, defined once.

use std::fmt::Write as _;

use super::Verdicts;
use eamadm_eval::scores;

/// The glossary section. Its numbers (final window, resamples) come from the run's
/// settings, so it cannot drift from the rule it defines.
pub(crate) fn write_glossary(text: &mut String, verdicts: &Verdicts) {
    let _ = writeln!(text, "### Glossary\n");
    let terms: [(&str, String); 17] = [
        (
            "IQM",
            "interquartile mean over seeds: the mean of the middle half (a quarter of the seeds \
             is trimmed from each end), so it hides a failure rate up to 25 %."
                .to_owned(),
        ),
        (
            "paired difference",
            "per seed, the method's value minus the other method's on the same seed (runs of \
             one seed share their random streams); their mean decides every comparison, with \
             its exact sign-flip 95% interval and sign-flip p-values (see the rule)."
                .to_owned(),
        ),
        (
            "Holm",
            "the Holm step-down adjustment of p-values across the informative comparisons of \
             one claim × task × method (and C3's stable-reaching tests), so that the chance of \
             any false \"favours\" stays below α."
                .to_owned(),
        ),
        (
            "margin, TOST",
            "the region of practical equivalence of a metric on a task, derived from the \
             task's rewards and control period (each with its reason in the margins list under \
             the rule); TOST tests whether the mean paired difference lies inside ± the margin \
             (two one-sided sign-flip tests at α/2: the within-margin p)."
                .to_owned(),
        ),
        (
            "favours",
            format!(
                "a comparison favours a side when its Holm-adjusted p that the mean paired \
                 difference lies beyond the margin is below {}: its exact interval then lies \
                 beyond the margin on that side.",
                verdicts.options.alpha
            ),
        ),
        (
            "supported, contradicted, equivalent, inconclusive, untestable",
            "the verdicts of the rule under the verdict table: every comparison favours EA-MADM; \
             one favours the other side; every comparison is equivalent (Holm-adjusted \
             within-margin p below α); none of these; no data to compare."
                .to_owned(),
        ),
        (
            "converged",
            "the run's greedy policy after training reaches the target.".to_owned(),
        ),
        (
            "collapsed",
            "the greedy policy after training does not reach, no episode of the final window \
             reaches, but an earlier training episode did; the collapse episode is one past the \
             last reaching one."
                .to_owned(),
        ),
        (
            "reaches_while_learning",
            "the greedy policy after training does not reach, but final-window training \
             episodes still do (online updates break the loops the frozen policy falls into)."
                .to_owned(),
        ),
        (
            "never_reached",
            "no training episode and not the greedy episode reached the target.".to_owned(),
        ),
        (
            "ever reached in training",
            "at least one training episode of the seed reached the target.".to_owned(),
        ),
        (
            "reached in the final window",
            format!(
                "at least one of the seed's last {} training episodes reached the target.",
                scores::FINAL_WINDOW
            ),
        ),
        (
            "reward-matched control",
            "a competitor that learns from the shaped sub-task rewards EA-MADM's sub-tasks get \
             (config `signal = \"standardised\"`: the signal EA-MADM's source task learns \
             from; or `\"subtask_sum\"`) instead of the task reward."
                .to_owned(),
        ),
        (
            "budget-matched control",
            "a competitor that first trains on the task for as many environment steps as \
             EA-MADM's sub-task pre-training takes (config `warmup_env_steps`)."
                .to_owned(),
        ),
        (
            "sub-task alone",
            "one sub-task pre-trained exactly as in the EA-MADM run of the same seed, then \
             acting alone (ε-greedy on its own values, EA-MADM's schedule), with no MADM step \
             (config `kind = \"subtask_greedy\"`; frozen, or still learning with `learn = \
             true`)."
                .to_owned(),
        ),
        (
            "strongest control",
            "on a claim × task, the control (not an EA-MADM variant) with the best IQM of the \
             claim's deciding metric; EA-MADM is judged against it alone by the same rule."
                .to_owned(),
        ),
        (
            "Monte-Carlo tolerance",
            format!(
                "the verdicts' numbers (mean paired differences, their intervals and p-values) \
                 are exact for up to 24 paired seeds: every sign vector is counted, nothing is \
                 resampled, and another seed changes no bit (`crates/eamadm-eval/tests/it/\
                 monte_carlo.rs` reruns the claims with other seeds). Beyond 24 pairs {} sign \
                 vectors are drawn per comparison, and claims.csv gives the p-value's \
                 Monte-Carlo standard error. The descriptive IQM intervals are bootstrap \
                 intervals from {} resamples with seed {}: the same seed gives the same bits, \
                 another seed moves their endpoints (docs/paper-notes.md §10.1).",
                verdicts.options.sign_flip.resamples,
                verdicts.options.bootstrap.resamples,
                verdicts.options.bootstrap.seed
            ),
        ),
    ];
    for (term, definition) in terms {
        let _ = writeln!(text, "- **{term}**: {definition}");
    }
    text.push('\n');
}
