//! The maze family's figure and text (issue 33, docs/paper-notes.md §22): per layout, the
//! effect of EA-MADM against each paper competitor against the layout's detour ratio, and the
//! `family/REPORT.md` section with the pooled verdicts.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use eamadm_eval::Role;
pub use eamadm_eval::family::LayoutPoint;
use eamadm_eval::family::{
    FamilyFindings, FamilyVerdicts, LayoutEffect, PooledComparison, PooledVerdict,
};
use eamadm_eval::findings::Findings;
use mazes::LayoutKind;

use crate::chart::{escape, px, text_element};
use crate::theme::method_style;

/// A layout kind's data name (`perfect_maze`) as people read it (`perfect maze`).
#[must_use]
pub fn kind_title(kind: &str) -> &str {
    match LayoutKind::from_name(kind) {
        Some(known) => known.title(),
        None => kind,
    }
}

/// The experiments whose verdicts the family is set beside: the paper's two mazes.
const PAPER_MAZES: [&str; 2] = ["task1", "task2"];

const WIDTH: f64 = 880.0;
const HEIGHT: f64 = 460.0;
const LEFT: f64 = 80.0;
const RIGHT: f64 = 560.0;
const TOP: f64 = 60.0;
const BOTTOM: f64 = 390.0;
const FONT: f64 = 12.0;
/// How far inside the frame the data range starts (more than a marker's dodge plus its radius).
const INSET: f64 = 14.0;

/// The marker of a layout kind (so kinds are told apart without colour).
fn marker(svg: &mut String, kind: &str, (x, y): (f64, f64), colour: &str, method: &str) {
    let r = 4.5;
    let common = format!(
        "class=\"sample\" data-method=\"{}\" fill=\"{colour}\" fill-opacity=\"0.8\"",
        escape(method)
    );
    let _ = match kind {
        "uniform" => writeln!(
            svg,
            "<circle {common} cx=\"{}\" cy=\"{}\" r=\"{}\"/>",
            px(x),
            px(y),
            px(r)
        ),
        "perfect_maze" => writeln!(
            svg,
            "<rect {common} x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>",
            px(x - r),
            px(y - r),
            px(2.0 * r),
            px(2.0 * r)
        ),
        "rooms" => writeln!(
            svg,
            "<polygon {common} points=\"{},{} {},{} {},{}\"/>",
            px(x),
            px(y - r - 1.0),
            px(x - r - 1.0),
            px(y + r),
            px(x + r + 1.0),
            px(y + r)
        ),
        _ => writeln!(
            svg,
            "<polygon {common} points=\"{},{} {},{} {},{} {},{}\"/>",
            px(x),
            px(y - r - 1.0),
            px(x + r + 1.0),
            px(y),
            px(x),
            px(y + r + 1.0),
            px(x - r - 1.0),
            px(y)
        ),
    };
}

/// A round step near `span / 5`.
fn step(span: f64) -> f64 {
    let raw = (span / 5.0).max(f64::MIN_POSITIVE);
    let power = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * power)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * power)
}

/// The effect-versus-detour-ratio figure of `claim` (`C1`, `C2`) as SVG: one marker per layout
/// and competitor (colour: the competitor, shape: the layout's kind; competitors a few pixels
/// apart at each layout), the zero line, and each competitor's pooled effect in the legend. `None` when there is
/// no effect of `claim`.
#[must_use]
pub fn effect_figure(
    verdicts: &FamilyVerdicts,
    layouts: &[LayoutPoint],
    claim: &str,
) -> Option<String> {
    let by_name: BTreeMap<&str, &LayoutPoint> =
        layouts.iter().map(|l| (l.layout.as_str(), l)).collect();
    let effects: Vec<(&LayoutEffect, &LayoutPoint)> = verdicts
        .layouts
        .iter()
        .filter(|e| e.claim == claim && e.effect.is_finite())
        .filter_map(|e| by_name.get(e.layout.as_str()).map(|l| (e, *l)))
        .collect();
    let metric = effects.first()?.0.metric.clone();
    let (mut x_low, mut x_high) = (1.0f64, 1.0f64);
    let (mut y_low, mut y_high) = (0.0f64, 0.0f64);
    for (effect, layout) in &effects {
        x_low = x_low.min(layout.detour_ratio);
        x_high = x_high.max(layout.detour_ratio);
        y_low = y_low.min(effect.effect);
        y_high = y_high.max(effect.effect);
    }
    if x_high - x_low < 1e-9 {
        x_high = x_low + 1.0;
    }
    if y_high - y_low < 1e-9 {
        y_high = y_low + 1.0;
    }
    let y_step = step(y_high - y_low);
    let (y_low, y_high) = (
        (y_low / y_step).floor() * y_step,
        (y_high / y_step).ceil() * y_step,
    );
    let x_step = step(x_high - x_low);
    let (x_low, x_high) = (
        (x_low / x_step).floor() * x_step,
        (x_high / x_step).ceil() * x_step,
    );
    // The data sit `INSET` pixels inside the frame, so a marker at an end of the range (dodged
    // sideways, or at the top of the y range) is drawn inside the frame, not across it.
    let sx = |x: f64| LEFT + INSET + (x - x_low) / (x_high - x_low) * (RIGHT - LEFT - 2.0 * INSET);
    let sy =
        |y: f64| BOTTOM - INSET - (y - y_low) / (y_high - y_low) * (BOTTOM - TOP - 2.0 * INSET);

    let mut svg = String::new();
    let _ = writeln!(
        svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\" font-family=\"sans-serif\">",
        px(WIDTH),
        px(HEIGHT),
        px(WIDTH),
        px(HEIGHT)
    );
    let _ = writeln!(
        svg,
        "<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"#ffffff\"/>",
        px(WIDTH),
        px(HEIGHT)
    );
    let better = if metric == "final_steps" {
        "below 0: EA-MADM needs fewer steps"
    } else {
        "above 0: EA-MADM earns more"
    };
    text_element(
        &mut svg,
        (LEFT, 24.0),
        15.0,
        "start",
        "#111111",
        &format!("Maze family, {claim}: EA-MADM − competitor in {metric}, per layout"),
    );
    text_element(
        &mut svg,
        (LEFT, 44.0),
        FONT,
        "start",
        "#444444",
        &format!("mean over seeds of the paired difference; {better}"),
    );
    // Axes and grid.
    let _ = writeln!(
        svg,
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888888\"/>",
        px(LEFT),
        px(TOP),
        px(RIGHT - LEFT),
        px(BOTTOM - TOP)
    );
    let mut y = y_low;
    while y <= y_high + y_step * 1e-6 {
        let _ = writeln!(
            svg,
            "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#eeeeee\"/>",
            px(LEFT),
            px(sy(y)),
            px(RIGHT),
            px(sy(y))
        );
        text_element(
            &mut svg,
            (LEFT - 6.0, sy(y) + 4.0),
            FONT,
            "end",
            "#111111",
            &format!("{}", (y / y_step).round() * y_step),
        );
        y += y_step;
    }
    let mut x = x_low;
    while x <= x_high + x_step * 1e-6 {
        text_element(
            &mut svg,
            (sx(x), BOTTOM + 16.0),
            FONT,
            "middle",
            "#111111",
            &format!(
                "{}",
                ((x / x_step).round() * x_step * 100.0).round() / 100.0
            ),
        );
        x += x_step;
    }
    text_element(
        &mut svg,
        ((LEFT + RIGHT) / 2.0, BOTTOM + 38.0),
        FONT,
        "middle",
        "#111111",
        "detour ratio (BFS optimum / Manhattan distance)",
    );
    let _ = writeln!(
        svg,
        "<line class=\"zero\" x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#111111\" stroke-width=\"1.5\"/>",
        px(LEFT),
        px(sy(0.0)),
        px(RIGHT),
        px(sy(0.0))
    );
    // Markers, competitor by competitor.
    let mut competitors: Vec<&str> = effects.iter().map(|(e, _)| e.competitor.as_str()).collect();
    competitors.sort_unstable();
    competitors.dedup();
    // Competitors side by side at a layout (a few pixels apart), so equal effects stay visible.
    let dodge = |competitor: &str| {
        let index = competitors
            .iter()
            .position(|c| *c == competitor)
            .unwrap_or(0);
        (index as f64 - (competitors.len() as f64 - 1.0) / 2.0) * 7.0
    };
    for (effect, layout) in &effects {
        let colour = method_style(&effect.competitor, Role::Paper).colour;
        marker(
            &mut svg,
            &layout.kind,
            (
                sx(layout.detour_ratio) + dodge(&effect.competitor),
                sy(effect.effect),
            ),
            colour,
            &effect.competitor,
        );
    }
    // Legend: competitors (colour) with their pooled effect, then kinds (shape).
    let mut ly = TOP + 10.0;
    let lx = RIGHT + 24.0;
    text_element(
        &mut svg,
        (lx, ly),
        FONT,
        "start",
        "#111111",
        "versus (pooled effect)",
    );
    for competitor in &competitors {
        ly += 20.0;
        let colour = method_style(competitor, Role::Paper).colour;
        marker(
            &mut svg,
            "uniform",
            (lx + 5.0, ly - 4.0),
            colour,
            competitor,
        );
        let pooled = verdicts
            .pooled
            .iter()
            .find(|p| p.claim == claim && p.competitor == *competitor)
            .map_or_else(String::new, |p| format!(" ({:.1})", p.effect));
        text_element(
            &mut svg,
            (lx + 16.0, ly),
            FONT,
            "start",
            "#111111",
            &format!("{competitor}{pooled}"),
        );
    }
    ly += 34.0;
    text_element(&mut svg, (lx, ly), FONT, "start", "#111111", "layout kind");
    for kind in LayoutKind::ALL {
        ly += 20.0;
        marker(&mut svg, kind.name(), (lx + 5.0, ly - 4.0), "#666666", "");
        text_element(
            &mut svg,
            (lx + 16.0, ly),
            FONT,
            "start",
            "#111111",
            kind.title(),
        );
    }
    svg.push_str("</svg>\n");
    Some(svg)
}

/// A number for the text, rounded to `digits` decimals.
fn n(value: f64, digits: usize) -> String {
    format!("{value:.digits$}")
}

fn verdict_words(verdict: PooledVerdict) -> &'static str {
    match verdict {
        PooledVerdict::FavoursEaMadm => "favours EA-MADM",
        PooledVerdict::FavoursCompetitor => "favours the competitor",
        PooledVerdict::Equivalent => "equivalent",
        PooledVerdict::Inconclusive => "inconclusive",
    }
}

/// The "Maze family" report (`family/REPORT.md`), rendered from `findings` (its `family`; the
/// paper mazes' verdicts from its tasks): what was run, the pooled verdicts table, how the
/// per-layout effects are spread, and the paper mazes' verdicts of the same run beside them.
/// `None` when no family ran.
#[must_use]
pub fn family_report(findings: &Findings) -> Option<String> {
    let family = findings.family.as_ref()?;
    let mut text = String::from("# The maze family\n\n");
    let _ = writeln!(
        text,
        "{} generated layouts (docs/paper-notes.md §7.1, §22), Task II's rewards, {} \
         training episodes and {} seeds for every method on every layout. Each (layout, \
         seed) pairs EA-MADM with a competitor; the effect is the mean over layouts of each \
         layout's mean paired difference (EA-MADM − competitor). Intervals: 95 % two-level \
         bootstrap (layouts, then seeds within each; conservative) and, beside it, the \
         layouts-only (cluster) bootstrap. Verdict: the two-level interval wholly beyond the \
         metric's margin on one side favours that side; wholly inside (−margin, margin) is \
         equivalent; otherwise inconclusive (no Holm adjustment across the three \
         competitors). C3 and C4 are not pooled (§22).\n",
        family.layouts.len(),
        family.episodes,
        family.seeds
    );
    text.push_str(
        "| claim | metric | versus | layouts | pairs | effect | 95 % two-level | 95 % layouts only | margin | layouts EA-MADM better | verdict |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for p in &family.pooled {
        let _ = writeln!(
            text,
            "| {} | {} | {} | {} | {} | {} | [{}, {}] | [{}, {}] | {} | {}/{} | {} |",
            p.claim,
            p.metric,
            p.competitor,
            p.layouts,
            p.pairs,
            n(p.effect, 2),
            n(p.low, 2),
            n(p.high, 2),
            n(p.layouts_only_low, 2),
            n(p.layouts_only_high, 2),
            p.margin.map_or_else(|| "—".to_owned(), |m| n(m, 2)),
            p.layouts_favouring_ea_madm,
            p.layouts,
            verdict_words(p.verdict)
        );
    }
    text.push_str("\n## Per-layout effects\n\n");
    text.push_str(
        "Spread of the per-layout effects (EA-MADM − competitor), by claim and competitor: \
         minimum, median, maximum over layouts, and by layout kind the mean effect.\n\n",
    );
    let kinds = kinds_of(family);
    let _ = writeln!(
        text,
        "| claim | versus | min | median | max |{}\n|---|---|---|---|---|{}",
        kinds
            .iter()
            .map(|k| format!(" {} |", kind_title(k)))
            .collect::<String>(),
        "---|".repeat(kinds.len())
    );
    for spread in &family.spread {
        let by_kind: String = kinds
            .iter()
            .map(|kind| {
                let mean = spread
                    .by_kind
                    .iter()
                    .find(|k| k.kind == *kind)
                    .map_or_else(|| "—".to_owned(), |k| n(k.mean, 2));
                format!(" {mean} |")
            })
            .collect();
        let _ = writeln!(
            text,
            "| {} | {} | {} | {} | {} |{by_kind}",
            spread.claim,
            spread.competitor,
            n(spread.min, 2),
            n(spread.median, 2),
            n(spread.max, 2),
        );
    }
    text.push_str(
        "\nFigures: `effect-C1.svg`, `effect-C2.svg` (per layout and competitor, against the \
         detour ratio; marker shape = layout kind).\n",
    );
    text.push_str("\n## Beside the paper's two mazes\n\n");
    let paper = paper_verdicts(findings);
    if paper.is_empty() {
        text.push_str("The paper's mazes were not run in this plan.\n");
    } else {
        text.push_str(
            "EA-MADM's verdicts on the paper's mazes in the same run (claims.csv), for \
             comparison with the pooled ones above (which hold over the family's layouts, \
             whose detour ratios the paper's two — both at 1 — do not span):\n\n\
             | task | claim | verdict |\n|---|---|---|\n",
        );
        for (task, claim, verdict) in paper {
            let _ = writeln!(text, "| {task} | {claim} | {verdict} |");
        }
    }
    Some(text)
}

/// The kinds of the family's layouts, in order of first appearance.
fn kinds_of(family: &FamilyFindings) -> Vec<&str> {
    let mut kinds: Vec<&str> = Vec::new();
    for layout in &family.layouts {
        if !kinds.contains(&layout.kind.as_str()) {
            kinds.push(layout.kind.as_str());
        }
    }
    kinds
}

/// EA-MADM's C1 and C2 verdicts on the paper's mazes: (task, claim, verdict).
fn paper_verdicts(findings: &Findings) -> Vec<(&str, &str, &str)> {
    findings
        .tasks
        .iter()
        .filter(|t| PAPER_MAZES.contains(&t.task.as_str()))
        .flat_map(|t| {
            t.verdicts
                .iter()
                .filter(|v| v.claim == "C1" || v.claim == "C2")
                .map(|v| (t.task.as_str(), v.claim.as_str(), v.verdict.name()))
        })
        .collect()
}

/// The main report's "The maze family" section, rendered from `findings`: what ran, the
/// pooled verdicts, one sentence setting them beside the paper mazes' verdicts of the same
/// run, and the link to `family/REPORT.md`. Nothing when no family ran.
pub fn write_family_section(text: &mut String, findings: &Findings) {
    let Some(family) = findings.family.as_ref() else {
        return;
    };
    let kinds = kinds_of(family)
        .into_iter()
        .map(|kind| {
            let count = family.layouts.iter().filter(|l| l.kind == kind).count();
            format!("{count} {}", kind_title(kind))
        })
        .collect::<Vec<_>>()
        .join(", ");
    let _ = writeln!(
        text,
        "## The maze family\n\n\
         EA-MADM against each of the paper's competitors on {} generated layouts ({kinds}; \
         Task II's rewards, {} episodes, {} seeds per layout), pooled over layouts: the effect \
         is the mean over layouts of the mean paired difference EA-MADM − competitor, with its \
         95 % two-level bootstrap interval (docs/paper-notes.md §22). The per-layout spread \
         and the effect-against-detour-ratio figures: [family/REPORT.md](family/REPORT.md).\n\n\
         | claim | versus | effect | 95 % two-level | layouts EA-MADM better | verdict |\n\
         |---|---|---|---|---|---|",
        family.layouts.len(),
        family.episodes,
        family.seeds
    );
    for p in &family.pooled {
        let _ = writeln!(
            text,
            "| {} ({}) | {} | {} | [{}, {}] | {}/{} | {} |",
            p.claim,
            p.metric,
            p.competitor,
            n(p.effect, 2),
            n(p.low, 2),
            n(p.high, 2),
            p.layouts_favouring_ea_madm,
            p.layouts,
            verdict_words(p.verdict)
        );
    }
    let count = |verdict: PooledVerdict| {
        family
            .pooled
            .iter()
            .filter(|p| p.verdict == verdict)
            .count()
    };
    let pooled = format!(
        "Pooled over the family, {} of the {} comparisons favour EA-MADM, {} favour the \
         competitor, {} are equivalent and {} inconclusive",
        count(PooledVerdict::FavoursEaMadm),
        family.pooled.len(),
        count(PooledVerdict::FavoursCompetitor),
        count(PooledVerdict::Equivalent),
        count(PooledVerdict::Inconclusive)
    );
    let paper = paper_verdicts(findings);
    if paper.is_empty() {
        let _ = writeln!(
            text,
            "\n{pooled}; the paper's mazes were not run in this plan, so nothing sets them \
             beside it.\n"
        );
    } else {
        let on_paper = paper
            .iter()
            .map(|(task, claim, verdict)| format!("{claim} {verdict} on {task}"))
            .collect::<Vec<_>>()
            .join(", ");
        let _ = writeln!(
            text,
            "\n{pooled}; on the paper's two mazes (both at detour ratio 1) the same run \
             judges EA-MADM's {on_paper}.\n"
        );
    }
}

/// The pooled comparisons of `claim`, for a caller's own table.
#[must_use]
pub fn pooled_of<'a>(verdicts: &'a FamilyVerdicts, claim: &str) -> Vec<&'a PooledComparison> {
    verdicts
        .pooled
        .iter()
        .filter(|p| p.claim == claim)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use eamadm_eval::family::LayoutEffect;

    fn sample() -> (FamilyVerdicts, Vec<LayoutPoint>) {
        let kinds = ["uniform", "perfect_maze", "rooms", "trap"];
        let layouts: Vec<LayoutPoint> = (0..8)
            .map(|i| LayoutPoint {
                layout: format!("f{i:02}-x"),
                kind: kinds[i % 4].to_owned(),
                detour_ratio: 1.0 + i as f64 * 0.6,
            })
            .collect();
        let mut effects = Vec::new();
        for competitor in ["epsilon-decreasing", "softmax"] {
            for (i, layout) in layouts.iter().enumerate() {
                effects.push(LayoutEffect {
                    layout: layout.layout.clone(),
                    claim: "C1".to_owned(),
                    metric: "final_steps".to_owned(),
                    competitor: competitor.to_owned(),
                    seeds: 10,
                    effect: i as f64 * 7.5 - 20.0,
                });
            }
        }
        let pooled = vec![PooledComparison {
            claim: "C1".to_owned(),
            metric: "final_steps".to_owned(),
            competitor: "epsilon-decreasing".to_owned(),
            layouts: 8,
            pairs: 80,
            effect: 6.25,
            low: -3.0,
            high: 15.5,
            layouts_only_low: -2.0,
            layouts_only_high: 14.0,
            margin: Some(2.0),
            layouts_favouring_ea_madm: 3,
            verdict: PooledVerdict::Inconclusive,
        }];
        (
            FamilyVerdicts {
                pooled,
                layouts: effects,
            },
            layouts,
        )
    }

    #[test]
    fn the_figure_passes_the_checks_and_draws_every_effect() {
        let (verdicts, layouts) = sample();
        let svg = effect_figure(&verdicts, &layouts, "C1").unwrap();
        let problems =
            crate::checks::check_figures(&[("family/effect-C1.svg".to_owned(), svg.clone())]);
        assert!(problems.is_empty(), "{problems:?}");
        // 16 effects + 2 legend markers of competitors.
        assert_eq!(
            svg.matches("class=\"sample\" data-method=\"softmax\"")
                .count(),
            9
        );
        assert!(svg.contains("class=\"zero\""));
        assert!(effect_figure(&verdicts, &layouts, "C2").is_none());
    }

    /// The sample's findings: its family (one run row per layout and seed 0..10, 6400
    /// episodes) beside `paper` findings.
    fn findings(paper: &Findings) -> Findings {
        let (verdicts, layouts) = sample();
        let scores: Vec<eamadm_eval::scores::FinalScore> = layouts
            .iter()
            .flat_map(|layout| {
                (0..10).map(move |seed| {
                    let mut row = crate::report::tests::row(
                        &format!("family-{}", layout.layout),
                        "ea-madm",
                        Role::Paper,
                        "ea_madm",
                        seed,
                        100.0,
                    );
                    row.episodes = 6400;
                    row
                })
            })
            .collect();
        paper
            .clone()
            .with_family(eamadm_eval::family::family_findings(
                &verdicts, &layouts, &scores,
            ))
    }

    #[test]
    fn the_report_has_the_pooled_table_and_the_spread() {
        let (_, mut paper) =
            crate::report::tests::judged(crate::report::tests::scores(60.0, &[], 10.0));
        paper.tasks[0].task = "task2".to_owned();
        let findings = findings(&paper);
        let text = family_report(&findings).unwrap();
        assert!(
            text.starts_with("# The maze family\n\n8 generated layouts"),
            "{text}"
        );
        assert!(text.contains("6400 training episodes and 10 seeds"));
        assert!(text.contains(
            "| C1 | final_steps | epsilon-decreasing | 8 | 80 | 6.25 | [-3.00, 15.50] | [-2.00, 14.00] | 2.00 | 3/8 | inconclusive |"
        ));
        // Kinds by their display names, as columns in the order the layouts take them.
        assert!(
            text.contains(
                "| claim | versus | min | median | max | uniform | perfect maze | rooms | trap |"
            ),
            "{text}"
        );
        assert!(!text.contains("perfect_maze"));
        assert!(
            text.contains(
                "| C1 | epsilon-decreasing | -20.00 | 6.25 | 32.50 | -5.00 | 2.50 | 10.00 | 17.50 |"
            ),
            "{text}"
        );
        assert!(text.contains("| task2 | C1 | "), "{text}");
        assert!(family_report(&paper).is_none());
    }

    #[test]
    fn the_main_reports_section_reads_as_pinned() {
        let (_, mut paper) =
            crate::report::tests::judged(crate::report::tests::scores(60.0, &[], 10.0));
        paper.tasks[0].task = "task2".to_owned();
        let mut text = String::new();
        write_family_section(&mut text, &paper);
        assert_eq!(text, "", "no family, no section");
        write_family_section(&mut text, &findings(&paper));
        insta::assert_snapshot!(text);
    }
}
