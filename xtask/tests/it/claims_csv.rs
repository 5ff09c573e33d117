//! `claims.csv` recomputed from `final-scores.csv` with the statistics library: every estimate,
//! interval, p-value and Holm family of a small run (black box; moved from xtask's `reproduce`
//! unit tests).

use crate::Folder;

/// Splits a line of a CSV without quoted fields (the claim and score tables have none).
fn cells(line: &str) -> Vec<&str> {
    line.split(',').collect()
}

#[test]
fn claims_csv_can_be_recomputed_from_final_scores_csv() {
    use eamadm::stats::{self, Bootstrap, Statistic};
    let folder = Folder::new();
    folder.succeeds(&[
        "reproduce-paper",
        "--seeds",
        "3",
        "--task",
        "task1",
        "--method",
        "ea-madm",
        "--method",
        "softmax",
        "--method",
        "epsilon-greedy",
        "--out",
        "out",
        "--quick",
        "--pretrained-cache",
        "cache",
    ]);
    let out = folder.path("out");
    let scores =
        eamadm::scores::read_csv(std::fs::File::open(out.join("final-scores.csv")).unwrap())
            .unwrap();
    assert_eq!(scores.len(), 9);
    let claims = std::fs::read_to_string(out.join("claims.csv")).unwrap();
    let mut lines = claims.lines();
    let header = cells(lines.next().unwrap());
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap();
    // Per seed (in seed order) the value of `metric`, where the cell is not empty.
    let seeded = |method: &str, metric: &str| -> Vec<(u64, f64)> {
        let mut v: Vec<(u64, f64)> = scores
            .iter()
            .filter(|s| s.method == method)
            .filter_map(|s| Some((s.seed, s.value(metric)?)))
            .collect();
        v.sort_by_key(|&(seed, _)| seed);
        v
    };
    let of = |method: &str, metric: &str| -> Vec<f64> {
        seeded(method, metric).into_iter().map(|(_, v)| v).collect()
    };
    let number = |cell: &str| cell.parse::<f64>().unwrap();
    let (mut singles, mut comparisons, mut outcomes, mut per_seed) = (0, 0, 0, 0);
    // Holm groups: (claim, method, what): the deciding comparisons with C3's per-seed tests
    // (one family), and the secondary ones (empty verdict); uninformative comparisons
    // take no part.
    type HolmGroup<'a> = (String, String, &'a str);
    let mut raw_p: std::collections::BTreeMap<HolmGroup<'_>, Vec<(f64, f64)>> =
        std::collections::BTreeMap::new();
    for line in lines {
        let row = cells(line);
        let (method, metric, versus) = (
            row[column("method")],
            row[column("metric")],
            row[column("versus")],
        );
        if row[column("claim")] == "outcome" {
            // The per-run outcome rows: converged share, and the exact sign test paired by
            // seed, recomputed from final-scores.csv's `outcome` column.
            let converged = |m: &str| -> Vec<(u64, bool)> {
                let mut v: Vec<(u64, bool)> = scores
                    .iter()
                    .filter(|s| s.method == m)
                    .map(|s| (s.seed, s.outcome == eamadm::scores::RunOutcome::Converged))
                    .collect();
                v.sort_unstable();
                v
            };
            let mine = converged(method);
            if versus.is_empty() {
                let hits = mine.iter().filter(|(_, c)| *c).count() as f64;
                assert_eq!(number(row[column("estimate")]), hits / mine.len() as f64);
            } else {
                let theirs = converged(versus);
                let wins = mine
                    .iter()
                    .zip(&theirs)
                    .filter(|(a, b)| a.1 && !b.1)
                    .count();
                let losses = mine
                    .iter()
                    .zip(&theirs)
                    .filter(|(a, b)| b.1 && !a.1)
                    .count();
                assert_eq!(
                    number(row[column("p_value")]),
                    stats::sign_test(wins as u64, losses as u64),
                    "{line}"
                );
            }
            outcomes += 1;
            continue;
        }
        if metric == "stable_reaching" || metric == "reached" {
            // A per-seed test, paired by seed: the exact sign test on the discordant seeds,
            // recomputed from the `stable_reaching` column (or, for `reached`, from
            // `greedy_reached` and `reaching_episodes`); an empty cell is not stable.
            let flag = |m: &str| -> Vec<(u64, bool)> {
                let mut v: Vec<(u64, bool)> = scores
                    .iter()
                    .filter(|s| s.method == m)
                    .map(|s| {
                        let yes = if metric == "stable_reaching" {
                            s.stable_reaching == Some(true)
                        } else {
                            s.greedy_reached || s.reaching_episodes > 0
                        };
                        (s.seed, yes)
                    })
                    .collect();
                v.sort_unstable();
                v
            };
            let (mine, theirs) = (flag(method), flag(versus));
            let wins = mine
                .iter()
                .zip(&theirs)
                .filter(|(a, b)| a.1 && !b.1)
                .count();
            let losses = mine
                .iter()
                .zip(&theirs)
                .filter(|(a, b)| b.1 && !a.1)
                .count();
            let hits = |v: &[(u64, bool)]| v.iter().filter(|(_, y)| *y).count() as f64;
            let p = stats::sign_test(wins as u64, losses as u64);
            assert_eq!(number(row[column("p_value")]), p, "{line}");
            assert_eq!(
                number(row[column("estimate")]),
                (hits(&mine) - hits(&theirs)) / mine.len() as f64,
                "{line}"
            );
            // C3's stable-reaching tests share one Holm family with its deciding
            // comparisons (issue 34).
            raw_p
                .entry((
                    row[column("claim")].to_owned(),
                    method.to_owned(),
                    "deciding",
                ))
                .or_default()
                .push((p, number(row[column("p_holm")])));
            per_seed += 1;
            continue;
        }
        let x = of(method, metric);
        if versus.is_empty() && x.is_empty() {
            // No seed has a value (e.g. no stable-reaching seed): an empty estimate.
            assert_eq!(row[column("estimate")], "", "{line}");
            singles += 1;
        } else if versus.is_empty() {
            // A single-method row: the IQM over seeds and its bootstrap interval.
            let interval = Bootstrap::default().interval(&x, Statistic::Iqm).unwrap();
            assert_eq!(
                number(row[column("estimate")]),
                stats::iqm(&x).unwrap(),
                "{line}"
            );
            assert_eq!(number(row[column("ci_low")]), interval.low, "{line}");
            assert_eq!(number(row[column("ci_high")]), interval.high, "{line}");
            singles += 1;
        } else {
            let y = of(versus, metric);
            // Descriptive: the IQM difference with its bootstrap interval.
            let difference = Bootstrap::default()
                .difference(&x, &y, Statistic::Iqm)
                .unwrap();
            assert_eq!(
                number(row[column("iqm_difference")]),
                stats::iqm(&x).unwrap() - stats::iqm(&y).unwrap(),
                "{line}"
            );
            assert_eq!(number(row[column("iqm_ci_low")]), difference.low, "{line}");
            assert_eq!(
                number(row[column("iqm_ci_high")]),
                difference.high,
                "{line}"
            );
            // Deciding: paired by seed, the seeds where both have a value; the mean
            // difference with its exact sign-flip interval and beyond-margin p.
            let theirs = seeded(versus, metric);
            let (px, py): (Vec<f64>, Vec<f64>) = seeded(method, metric)
                .into_iter()
                .filter_map(|(seed, a)| {
                    theirs
                        .iter()
                        .find(|(s, _)| *s == seed)
                        .map(|&(_, b)| (a, b))
                })
                .unzip();
            let paired = eamadm::stats::paired::differences(&px, &py).unwrap();
            let means = eamadm::stats::SignFlipMeans::exact(&paired).unwrap();
            let margin = row[column("margin")].parse::<f64>().unwrap_or(0.0);
            assert_eq!(
                number(row[column("estimate")]),
                stats::mean(&paired).unwrap(),
                "{line}"
            );
            let (low, high) = means.interval(0.95).unwrap();
            let cell = |name: &str| row[column(name)].parse::<f64>().ok();
            assert_eq!((cell("ci_low"), cell("ci_high")), (low, high), "{line}");
            let p = means.beyond_margin(margin).unwrap();
            assert_eq!(number(row[column("p_value")]), p, "{line}");
            assert_eq!(
                number(row[column("paired_p_value")]),
                eamadm::stats::SignFlipTest::default()
                    .p_value(
                        &paired,
                        Statistic::Mean,
                        eamadm::stats::Alternative::TwoSided
                    )
                    .unwrap(),
                "{line}"
            );
            if row[column("informative")] == "false" {
                // Left out of Holm.
                assert_eq!(row[column("p_holm")], "", "{line}");
                comparisons += 1;
                continue;
            }
            let group = if row[column("verdict")].is_empty() {
                "secondary"
            } else {
                "deciding"
            };
            raw_p
                .entry((row[column("claim")].to_owned(), method.to_owned(), group))
                .or_default()
                .push((p, number(row[column("p_holm")])));
            comparisons += 1;
        }
    }
    // C1, C2: one metric; C3: two deciding and two secondary. Three methods, one under
    // test, two competitors.
    assert_eq!(singles, 3 * (1 + 1 + 2 + 2));
    // C3's greedy fluctuation is compared with a competitor when both sides have 2 or
    // more stable-reaching seeds (and the method under test must have them to be compared
    // at all).
    let greedy = |m: &str| of(m, "fluctuation_greedy_steps").len() >= 2;
    let c3 = if greedy("ea-madm") {
        2 * ["softmax", "epsilon-greedy"]
            .iter()
            .filter(|m| greedy(m))
            .count()
    } else {
        0
    };
    assert_eq!(comparisons, 2 * (1 + 1 + 2) + c3);
    // C3's stable-reaching test against each competitor.
    assert_eq!(per_seed, 2);
    // One share per method, and the method under test against each competitor.
    assert_eq!(outcomes, 3 + 2);
    for ((claim, method, group), pairs) in raw_p {
        let raw: Vec<f64> = pairs.iter().map(|(p, _)| *p).collect();
        let holm: Vec<f64> = pairs.iter().map(|(_, h)| *h).collect();
        assert_eq!(stats::holm(&raw).unwrap(), holm, "{claim} {method} {group}");
    }
    let report = std::fs::read_to_string(out.join("REPORT.md")).unwrap();
    assert!(
        report.contains("## Verdicts on the paper's claims"),
        "{report}"
    );
}
