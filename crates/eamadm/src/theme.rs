//! How each method looks in every figure: one colour and one dash per method, fixed here next
//! to the method list ([`paper::methods`](crate::paper::methods),
//! [`paper::controls`](crate::paper::controls)) so that a reader who learnt EA-MADM's colour in
//! one figure finds it in every other.
//!
//! Colours are the Okabe–Ito palette (Okabe & Ito, *Color Universal Design*, 2008), readable
//! with every common colour-vision deficiency. The dash says the method's [`Role`]: the
//! paper's methods are solid, ablations dashed, controls dotted (the reward-shaped controls
//! dash-dotted, so that a control never shares its look with the competitor-based control
//! of the same colour). The methods of the paper's presets have fixed looks chosen so that no
//! two of one role share a colour where they appear together; any other method (a config
//! file's, or one added later) gets its role's dash and a colour picked by a stable hash of its
//! label, so it too looks the same in every figure and every run.
//!
//! This module depends on nothing but [`Role`]; it draws nothing (the figures are drawn by
//! `xtask`). The paper's figure numbers are in [`paper`](crate::paper).
//!
//! ```
//! use eamadm::config::Role;
//! use eamadm::theme::{self, Dash};
//!
//! let ea_madm = theme::method_style("ea-madm", Role::Paper);
//! assert_eq!(ea_madm.colour, "#0072B2");
//! assert_eq!(ea_madm.dash, Dash::Solid);
//! assert_eq!(theme::method_style("ea-madm-table", Role::Ablation).dash, Dash::Dashed);
//! // A method nobody listed still gets one fixed look from its label and role.
//! let new = theme::method_style("my-variant", Role::Control);
//! assert_eq!(new, theme::method_style("my-variant", Role::Control));
//! assert_eq!(new.dash, Dash::Dotted);
//! ```

use crate::config::Role;

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::paper;

    /// Every preset method has its own look, its role's dash family, and no two methods of
    /// one preset share colour and dash.
    #[test]
    fn preset_methods_have_distinct_looks_of_their_role() {
        for preset in [
            paper::task1(),
            paper::task2(),
            paper::robot(),
            paper::robot_paper_state(),
            paper::aggregation_control(),
        ] {
            distinct_looks_of_their_role(&preset);
        }
        assert_eq!(method_style("ea-madm", Role::Paper).colour, OKABE_ITO[0]);
    }

    fn distinct_looks_of_their_role(preset: &crate::ExperimentConfig) {
        let mut seen = std::collections::BTreeMap::new();
        for spec in &preset.methods {
            assert!(
                LOOKS.iter().any(|(label, ..)| *label == spec.label),
                "{} has no fixed look",
                spec.label
            );
            let style = method_style(&spec.label, spec.role);
            let family = match style.dash {
                Dash::Solid => Role::Paper,
                Dash::Dashed => Role::Ablation,
                Dash::Dotted
                | Dash::DashDot
                | Dash::DashDotDot
                | Dash::LongDash
                | Dash::LongDashDot
                | Dash::LongDashDotDot => Role::Control,
            };
            assert_eq!(family, spec.role, "{}", spec.label);
            if let Some(other) = seen.insert((style.colour, style.dash), spec.label.clone()) {
                panic!("{} and {other} share a look in {}", spec.label, preset.name);
            }
        }
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
}
