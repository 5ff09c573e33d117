//! How each method looks in every figure: a colour and a dash per method, so that a reader who
//! learnt EA-MADM's colour in one figure finds it in every other, and no two methods of one
//! figure share a colour.
//!
//! Colours are the Okabe–Ito palette (Okabe & Ito, *Color Universal Design*, 2008), readable
//! with every common colour-vision deficiency. The dash says the method's [`Role`]: the
//! paper's methods are solid, ablations dashed, controls dotted (the controls on shaped
//! rewards dash-dotted and their variants with dashes of their own, so that the line style is
//! a second channel beside the colour). The paper's four methods have fixed colours in every
//! figure; every other method has a preferred colour (a fixed one for the methods of the
//! paper's presets, otherwise one picked by a stable hash of its label), and [`assign`] gives
//! each method of a set of figures its preferred colour unless an earlier method of one of its
//! figures has it already, then the first free one. A method other than the paper's is drawn
//! in one figure of its experiment (its role's figure), so it too has one colour everywhere.
//!
//! This module depends on nothing but [`Role`]; it draws nothing ([`crate::chart`] does).
//!
//! ```
//! use eamadm_eval::Role;
//! use eamadm_present::theme::{self, Dash};
//!
//! let ea_madm = theme::method_style("ea-madm", Role::Paper);
//! assert_eq!(ea_madm.colour, "#0072B2");
//! assert_eq!(ea_madm.dash, Dash::Solid);
//! assert_eq!(theme::method_style("ea-madm-table", Role::Ablation).dash, Dash::Dashed);
//! // A method nobody listed still gets one fixed look from its label and role.
//! let new = theme::method_style("my-variant", Role::Control);
//! assert_eq!(new, theme::method_style("my-variant", Role::Control));
//! assert_eq!(new.dash, Dash::Dotted);
//! // Two figures: a method keeps its colour, and no two methods of a figure share one.
//! let looks = theme::assign(&[
//!     vec![("ea-madm", Role::Paper), ("ea-madm-tau0.33", Role::Control)],
//! ]);
//! assert_ne!(looks["ea-madm-tau0.33"].colour, looks["ea-madm"].colour);
//! ```

use std::collections::BTreeMap;

use eamadm_eval::Role;

/// How a method's line is stroked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Dash {
    /// A solid line: the paper's own methods.
    Solid,
    /// Long dashes: ablations of EA-MADM.
    Dashed,
    /// Dots: controls the paper does not run.
    Dotted,
    /// Dash and dot: the reward-shaped controls, and a sub-task alone that goes on learning.
    DashDot,
    /// Dash and two dots: the controls learning from the plain sum of the sub-task rewards.
    DashDotDot,
    /// Long dashes: the controls learning from the repaired sub-task rewards.
    LongDash,
    /// Long dash and dot: the controls learning from the sub-task rewards with the goal bonus.
    LongDashDot,
    /// Long dash and two dots: the controls learning from the sub-task rewards with the end
    /// penalties.
    LongDashDotDot,
}

impl Dash {
    /// The SVG `stroke-dasharray` value (in units of the stroke's width 2 px), `None` for a
    /// solid line.
    #[must_use]
    pub fn dasharray(self) -> Option<&'static str> {
        match self {
            Self::Solid => None,
            Self::Dashed => Some("9 5"),
            Self::Dotted => Some("2 4"),
            Self::DashDot => Some("9 4 2 4"),
            Self::DashDotDot => Some("9 3 2 3 2 3"),
            Self::LongDash => Some("16 4"),
            Self::LongDashDot => Some("16 4 2 4"),
            Self::LongDashDotDot => Some("16 3 2 3 2 3"),
        }
    }

    /// The dash of a method of `role` that has no look of its own.
    #[must_use]
    pub fn of_role(role: Role) -> Self {
        match role {
            Role::Paper => Self::Solid,
            Role::Ablation => Self::Dashed,
            Role::Control => Self::Dotted,
        }
    }
}

/// A method's look: its colour (an SVG `#RRGGBB`) and its dash.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct MethodStyle {
    /// `#RRGGBB`, one of [`OKABE_ITO`].
    pub colour: &'static str,
    /// The line's dash.
    pub dash: Dash,
}

/// The eight Okabe–Ito colours: blue, vermillion, bluish green, reddish purple, orange, sky
/// blue, black, yellow (yellow last: it is the faintest on white).
pub const OKABE_ITO: [&str; 8] = [
    "#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000", "#F0E442",
];

/// The looks of the methods of the paper's presets, by label.
const LOOKS: [(&str, usize, Dash); 40] = [
    // The paper's methods: EA-MADM blue, its three competitors.
    ("ea-madm", 0, Dash::Solid),
    ("epsilon-greedy", 1, Dash::Solid),
    ("epsilon-decreasing", 2, Dash::Solid),
    ("softmax", 3, Dash::Solid),
    // The ablations (drawn with EA-MADM): four colours none of them shares.
    ("ea-madm-table", 4, Dash::Dashed),
    ("ea-madm-uniform", 5, Dash::Dashed),
    ("ea-madm-literal", 6, Dash::Dashed),
    ("ea-madm-distance", 3, Dash::Dashed),
    // The controls: a competitor's controls take its colour.
    ("subtask0-alone", 6, Dash::Dotted),
    ("subtask1-alone", 4, Dash::Dotted),
    ("epsilon-greedy-budget", 1, Dash::Dotted),
    ("epsilon-decreasing-budget", 2, Dash::Dotted),
    ("softmax-budget", 3, Dash::Dotted),
    ("epsilon-greedy-shaped", 1, Dash::DashDot),
    ("epsilon-decreasing-shaped", 2, Dash::DashDot),
    ("softmax-shaped", 3, Dash::DashDot),
    ("ea-madm-tau0.5", 5, Dash::Dotted),
    ("ea-madm-tau0.33", 0, Dash::Dotted),
    // The plain aggregators (EA-MADM with another aggregation: EA-MADM's blue, and black).
    ("subtasks-mean", 0, Dash::DashDotDot),
    ("subtasks-max", 6, Dash::DashDotDot),
    // The robot's repaired readings (ablations, drawn with the four above).
    ("ea-madm-goal-bonus", 1, Dash::Dashed),
    ("ea-madm-end-penalties", 2, Dash::Dashed),
    ("ea-madm-normalised", 7, Dash::Dashed),
    ("ea-madm-repaired", 0, Dash::Dashed),
    // The robot's controls: a sub-task's learning variant keeps its colour and dash-dots; the
    // competitors' controls keep the competitor's colour with a dash of their own.
    ("subtask2-alone", 5, Dash::Dotted),
    ("subtask0-alone-learning", 6, Dash::DashDot),
    ("subtask1-alone-learning", 4, Dash::DashDot),
    ("subtask2-alone-learning", 5, Dash::DashDot),
    ("epsilon-greedy-shaped-sum", 1, Dash::DashDotDot),
    ("epsilon-decreasing-shaped-sum", 2, Dash::DashDotDot),
    ("softmax-shaped-sum", 3, Dash::DashDotDot),
    ("epsilon-greedy-shaped-repaired", 1, Dash::LongDash),
    ("epsilon-decreasing-shaped-repaired", 2, Dash::LongDash),
    ("softmax-shaped-repaired", 3, Dash::LongDash),
    ("epsilon-greedy-shaped-goal-bonus", 1, Dash::LongDashDot),
    ("epsilon-decreasing-shaped-goal-bonus", 2, Dash::LongDashDot),
    ("softmax-shaped-goal-bonus", 3, Dash::LongDashDot),
    (
        "epsilon-greedy-shaped-end-penalties",
        1,
        Dash::LongDashDotDot,
    ),
    (
        "epsilon-decreasing-shaped-end-penalties",
        2,
        Dash::LongDashDotDot,
    ),
    ("softmax-shaped-end-penalties", 3, Dash::LongDashDotDot),
];

/// The look of the method labelled `label` with role `role`: the fixed look of a preset
/// method, otherwise the role's dash ([`Dash::of_role`]) and the Okabe–Ito colour at a
/// stable hash (64-bit FNV-1a) of the label.
#[must_use]
pub fn method_style(label: &str, role: Role) -> MethodStyle {
    if let Some(&(_, colour, dash)) = LOOKS.iter().find(|(known, ..)| *known == label) {
        return MethodStyle {
            colour: OKABE_ITO[colour],
            dash,
        };
    }
    let hash = label.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |hash, byte| {
        (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3)
    });
    // Seven colours: yellow is kept for the preset looks that need an eighth.
    let colour = (hash % 7) as usize;
    MethodStyle {
        colour: OKABE_ITO[colour],
        dash: Dash::of_role(role),
    }
}

/// The looks of the methods of `figures` (each figure its methods, in drawing order): each
/// method's [`method_style`], with its colour replaced by the first [`OKABE_ITO`] colour free in
/// all of its figures when an earlier method of one of them has it already (a method keeps
/// the colour it got in an earlier figure). The paper's methods come first in their figures
/// and keep theirs. With at most eight methods per figure every method of a figure gets its
/// own colour; the dash stays the role's.
#[must_use]
pub fn assign(figures: &[Vec<(&str, Role)>]) -> BTreeMap<String, MethodStyle> {
    let mut looks: BTreeMap<String, MethodStyle> = BTreeMap::new();
    for figure in figures {
        // The paper's methods first, so that no other method takes their colours.
        let mut ordered: Vec<(&str, Role)> = figure.clone();
        ordered.sort_by_key(|(_, role)| *role != Role::Paper);
        for (label, role) in ordered {
            if looks.contains_key(label) {
                continue;
            }
            let taken: Vec<&str> = figures
                .iter()
                .filter(|f| f.iter().any(|(l, _)| *l == label))
                .flat_map(|f| f.iter())
                .filter_map(|(other, _)| looks.get(*other).map(|look| look.colour))
                .collect();
            let mut style = method_style(label, role);
            if taken.contains(&style.colour)
                && let Some(free) = OKABE_ITO.iter().find(|c| !taken.contains(c))
            {
                style.colour = free;
            }
            looks.insert(label.to_owned(), style);
        }
    }
    looks
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The methods of the paper's presets (`crates/eamadm/configs/*.toml`): label and role.
    fn preset_methods() -> Vec<(String, Vec<(String, Role)>)> {
        [
            ("task1", include_str!("../../eamadm/configs/task1.toml")),
            ("task2", include_str!("../../eamadm/configs/task2.toml")),
            ("robot", include_str!("../../eamadm/configs/robot.toml")),
            (
                "aggregation-control",
                include_str!("../../eamadm/configs/aggregation-control.toml"),
            ),
        ]
        .into_iter()
        .map(|(name, text)| {
            let mut methods = Vec::new();
            let mut label: Option<String> = None;
            let mut role = Role::Paper;
            let mut push = |label: &mut Option<String>, role: &mut Role| {
                if let Some(l) = label.take() {
                    methods.push((l, *role));
                }
                *role = Role::Paper;
            };
            for line in text.lines() {
                let line = line.split('#').next().unwrap_or("").trim();
                if line == "[[methods]]" {
                    push(&mut label, &mut role);
                } else if let Some(value) = line.strip_prefix("label = ") {
                    label = Some(value.trim_matches('"').to_owned());
                } else if let Some(value) = line.strip_prefix("role = ") {
                    role = match value.trim_matches('"') {
                        "ablation" => Role::Ablation,
                        "control" => Role::Control,
                        _ => Role::Paper,
                    };
                }
            }
            push(&mut label, &mut role);
            (name.to_owned(), methods)
        })
        .collect()
    }

    /// Every preset method has its own fixed look in its role's dash family, and within a
    /// preset no two methods of one role share colour and dash.
    #[test]
    fn preset_methods_have_fixed_looks_of_their_role() {
        let presets = preset_methods();
        assert!(presets.iter().all(|(_, methods)| methods.len() >= 8));
        for (name, methods) in presets {
            let mut seen = BTreeMap::new();
            for (label, role) in &methods {
                assert!(
                    LOOKS.iter().any(|(known, ..)| known == label),
                    "{label} has no fixed look"
                );
                let style = method_style(label, *role);
                let family = match style.dash {
                    Dash::Solid => Role::Paper,
                    Dash::Dashed => Role::Ablation,
                    _ => Role::Control,
                };
                assert_eq!(family, *role, "{label}");
                if let Some(other) = seen.insert((style.colour, style.dash), label.clone()) {
                    panic!("{label} and {other} share a look in {name}");
                }
            }
        }
        assert_eq!(method_style("ea-madm", Role::Paper).colour, OKABE_ITO[0]);
    }

    #[test]
    fn other_methods_get_their_roles_dash_and_a_stable_colour() {
        for role in [Role::Paper, Role::Ablation, Role::Control] {
            let style = method_style("robot-variant-x", role);
            assert_eq!(style.dash, Dash::of_role(role));
            assert_eq!(style.colour, method_style("robot-variant-x", role).colour);
            assert_ne!(style.colour, OKABE_ITO[7]);
        }
        assert!(Dash::Solid.dasharray().is_none());
        assert_ne!(Dash::Dotted.dasharray(), Dash::DashDot.dasharray());
    }

    /// The law of [`assign`]: in every figure of at most eight methods no two methods share a
    /// colour, a method has one look everywhere, the paper's methods keep their fixed colours
    /// and every method keeps its role's dash.
    #[test]
    fn assigned_colours_are_distinct_in_each_figure_and_fixed_per_method() {
        for (_, methods) in preset_methods() {
            let paper: Vec<(&str, Role)> = methods
                .iter()
                .filter(|(_, r)| *r == Role::Paper)
                .map(|(l, r)| (l.as_str(), *r))
                .collect();
            let mut figures = vec![paper.clone()];
            for role in [Role::Ablation, Role::Control] {
                let of_role: Vec<(&str, Role)> = methods
                    .iter()
                    .filter(|(_, r)| *r == role)
                    .map(|(l, r)| (l.as_str(), *r))
                    .collect();
                for chunk in of_role.chunks(7) {
                    let mut figure = vec![paper[0]];
                    figure.extend_from_slice(chunk);
                    figures.push(figure);
                }
            }
            let looks = assign(&figures);
            for figure in &figures {
                let mut colours: Vec<&str> = figure.iter().map(|(l, _)| looks[*l].colour).collect();
                colours.sort_unstable();
                colours.dedup();
                assert_eq!(colours.len(), figure.len(), "{figure:?}");
                for (label, role) in figure {
                    assert_eq!(looks[*label].dash, method_style(label, *role).dash);
                    if *role == Role::Paper {
                        assert_eq!(looks[*label], method_style(label, *role));
                    }
                }
            }
        }
    }
}
