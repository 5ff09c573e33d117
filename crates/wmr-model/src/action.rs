//! The five actions of Sec. III.B and the wheel speeds that carry them out.

use serde::{Deserialize, Serialize};

use crate::kinematics::WheelSpeeds;

/// The robot's discrete actions, in the paper's order (their indices are the `dql` actions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Action {
    /// Both wheels forward at full speed.
    Forward = 0,
    /// Both wheels backward at full speed.
    Backward = 1,
    /// Both wheels still.
    Stop = 2,
    /// Forward while turning left (the right wheel faster).
    LeftForward = 3,
    /// Forward while turning right (the left wheel faster).
    RightForward = 4,
}

impl Action {
    /// Every action, in index order.
    pub const ALL: [Self; 5] = [
        Self::Forward,
        Self::Backward,
        Self::Stop,
        Self::LeftForward,
        Self::RightForward,
    ];

    /// Number of actions.
    pub const COUNT: usize = 5;

    /// The action's index, `0..Action::COUNT`.
    #[must_use]
    pub fn index(self) -> usize {
        self as usize
    }

    /// The action with index `index`, if there is one.
    #[must_use]
    pub fn from_index(index: usize) -> Option<Self> {
        Self::ALL.get(index).copied()
    }

    /// A short lowercase name (`"forward"`, `"left_forward"`, …).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Forward => "forward",
            Self::Backward => "backward",
            Self::Stop => "stop",
            Self::LeftForward => "left_forward",
            Self::RightForward => "right_forward",
        }
    }
}

/// Left and right wheel speeds as fractions of the maximum wheel speed, each in `[-1, 1]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelFractions {
    /// Left wheel, fraction of the maximum speed.
    pub left: f64,
    /// Right wheel, fraction of the maximum speed.
    pub right: f64,
}

impl WheelFractions {
    /// The pair `(left, right)`.
    #[must_use]
    pub const fn new(left: f64, right: f64) -> Self {
        Self { left, right }
    }
}

/// What each action does to the wheels.
///
/// Defaults: forward `(1, 1)`, backward `(−1, −1)`, stop `(0, 0)`, left-forward `(0.5, 1)`,
/// right-forward `(1, 0.5)`. With the e-puck figures the turns move at 0.094 m/s on an arc of
/// radius 7.8 cm, turning 1.21 rad/s: about 14° per 0.2 s control period, gentle enough to thread
/// a gap and quick enough to swerve round an obstacle within a few steps.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ActionSet {
    /// Wheels for [`Action::Forward`].
    pub forward: WheelFractions,
    /// Wheels for [`Action::Backward`].
    pub backward: WheelFractions,
    /// Wheels for [`Action::Stop`].
    pub stop: WheelFractions,
    /// Wheels for [`Action::LeftForward`].
    pub left_forward: WheelFractions,
    /// Wheels for [`Action::RightForward`].
    pub right_forward: WheelFractions,
}

impl Default for ActionSet {
    fn default() -> Self {
        Self {
            forward: WheelFractions::new(1.0, 1.0),
            backward: WheelFractions::new(-1.0, -1.0),
            stop: WheelFractions::new(0.0, 0.0),
            left_forward: WheelFractions::new(0.5, 1.0),
            right_forward: WheelFractions::new(1.0, 0.5),
        }
    }
}

impl ActionSet {
    /// The wheel fractions of `action`.
    #[must_use]
    pub fn fractions(&self, action: Action) -> WheelFractions {
        match action {
            Action::Forward => self.forward,
            Action::Backward => self.backward,
            Action::Stop => self.stop,
            Action::LeftForward => self.left_forward,
            Action::RightForward => self.right_forward,
        }
    }

    /// The wheel speeds (rad/s) of `action` for a robot whose top wheel speed is `max_wheel_speed`.
    #[must_use]
    pub fn wheel_speeds(&self, action: Action, max_wheel_speed: f64) -> WheelSpeeds {
        let f = self.fractions(action);
        WheelSpeeds {
            left: f.left * max_wheel_speed,
            right: f.right * max_wheel_speed,
        }
    }

    /// The five `(field name, fractions)` pairs, in action order (for validation messages).
    #[must_use]
    pub fn named(&self) -> [(&'static str, WheelFractions); 5] {
        Action::ALL.map(|a| (a.name(), self.fractions(a)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indices_round_trip_in_paper_order() {
        for (i, a) in Action::ALL.into_iter().enumerate() {
            assert_eq!(a.index(), i);
            assert_eq!(Action::from_index(i), Some(a));
        }
        assert_eq!(Action::from_index(5), None);
        assert_eq!(Action::LeftForward.name(), "left_forward");
    }

    #[test]
    #[expect(
        clippy::approx_constant,
        reason = "6.28 rad/s is the e-puck's maximum wheel speed, not an approximation of 2π"
    )]
    fn left_forward_turns_left() {
        let set = ActionSet::default();
        let w = set.wheel_speeds(Action::LeftForward, 6.28);
        assert!(w.right > w.left && w.left > 0.0);
        let w = set.wheel_speeds(Action::RightForward, 6.28);
        assert!(w.left > w.right && w.right > 0.0);
    }
}
