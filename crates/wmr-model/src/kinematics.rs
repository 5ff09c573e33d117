//! Differential-drive kinematics with exact arc integration.
//!
//! Two wheels of radius `r` on an axle of length `L` turning at `ω_l`, `ω_r` (rad/s) move the
//! body at linear speed `v = r (ω_l + ω_r) / 2` and angular speed `ω = r (ω_r − ω_l) / L`
//! (counter-clockwise positive). Held for a time `t`, those speeds trace an exact circular arc
//! of radius `v / ω` (a straight line when `ω = 0`, a spin in place when `v = 0`); we integrate
//! that arc in closed form, so there is no integration error however long the control period.

use nalgebra::{Isometry2, Point2, Vector2};
use serde::{Deserialize, Serialize};

/// The robot's body and drive, in SI units. Defaults are the Webots e-puck's public figures.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RobotParams {
    /// Wheel radius `r` (m). e-puck: 0.020.
    pub wheel_radius: f64,
    /// Distance between the wheels `L` (m). e-puck: 0.052.
    pub axle_length: f64,
    /// Radius of the round body used for collisions and sensor placement (m). e-puck: 0.037.
    pub body_radius: f64,
    /// Largest wheel speed (rad/s). e-puck: 6.28, i.e. about 0.126 m/s at the rim.
    pub max_wheel_speed: f64,
}

impl Default for RobotParams {
    fn default() -> Self {
        Self {
            wheel_radius: 0.020,
            axle_length: 0.052,
            body_radius: 0.037,
            // Webots' e-puck MAX_SPEED, which happens to be close to 2π.
            #[expect(
                clippy::approx_constant,
                reason = "6.28 rad/s is Webots' e-puck MAX_SPEED, not an approximation of 2π"
            )]
            max_wheel_speed: 6.28,
        }
    }
}

/// Angular speeds of the two wheels (rad/s, positive drives forward).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WheelSpeeds {
    /// Left wheel.
    pub left: f64,
    /// Right wheel.
    pub right: f64,
}

/// The body's velocity: forward speed and turn rate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Twist {
    /// Forward speed `v` (m/s).
    pub linear: f64,
    /// Turn rate `ω` (rad/s, counter-clockwise positive).
    pub angular: f64,
}

impl RobotParams {
    /// The body velocity produced by `wheels`: `v = r (ω_l + ω_r) / 2`, `ω = r (ω_r − ω_l) / L`.
    #[must_use]
    pub fn twist(&self, wheels: WheelSpeeds) -> Twist {
        Twist {
            linear: self.wheel_radius * (wheels.left + wheels.right) / 2.0,
            angular: self.wheel_radius * (wheels.right - wheels.left) / self.axle_length,
        }
    }

    /// Top forward speed `r · ω_max` (m/s).
    #[must_use]
    pub fn max_linear_speed(&self) -> f64 {
        self.wheel_radius * self.max_wheel_speed
    }
}

impl Twist {
    /// Radius of the arc this twist traces, `v / ω` (signed: positive turns left), or `None`
    /// for a straight line (`ω = 0`).
    #[must_use]
    pub fn arc_radius(&self) -> Option<f64> {
        (self.angular != 0.0).then(|| self.linear / self.angular)
    }
}

/// The pose reached from `pose` by holding `twist` for `duration` seconds, integrated exactly.
///
/// In the body frame the displacement is `(v sin θ / ω, v (1 − cos θ) / ω)` with `θ = ω t`,
/// evaluated as `v t · sin θ / θ` and `v t · 2 sin²(θ/2) / θ`, which stay accurate (and
/// finite) as `ω → 0`.
#[must_use]
pub fn integrate_arc(pose: &Isometry2<f64>, twist: Twist, duration: f64) -> Isometry2<f64> {
    pose * arc_displacement(twist, duration)
}

/// The centre of the pose [`integrate_arc`] reaches, bit for bit its translation, without
/// the turn: the trigonometry of the heading (one `sin_cos`) is left out. Collision checks
/// along an arc need only where the body's centre is.
#[must_use]
pub fn integrate_arc_centre(pose: &Isometry2<f64>, twist: Twist, duration: f64) -> Point2<f64> {
    // `Isometry2 * Isometry2` moves the translation by the rotated displacement, as here.
    let (offset, _) = arc_offset(twist, duration);
    Point2::from(pose.translation.vector + pose.rotation.transform_vector(&offset))
}

/// The body-frame pose change of holding `twist` for `duration` ([`integrate_arc`] composes it
/// with the start pose).
fn arc_displacement(twist: Twist, duration: f64) -> Isometry2<f64> {
    let (offset, theta) = arc_offset(twist, duration);
    Isometry2::new(offset, theta)
}

/// The body-frame displacement of holding `twist` for `duration`, and the angle turned.
fn arc_offset(twist: Twist, duration: f64) -> (Vector2<f64>, f64) {
    let theta = twist.angular * duration;
    let distance = twist.linear * duration;
    let (sin_over, one_minus_cos_over) = if theta == 0.0 {
        (1.0, 0.0)
    } else {
        // 1 − cos θ = 2 sin²(θ/2) avoids the cancellation of the direct form for small θ.
        let half_sin = (theta / 2.0).sin();
        (theta.sin() / theta, 2.0 * half_sin * half_sin / theta)
    };
    (
        Vector2::new(distance * sin_over, distance * one_minus_cos_over),
        theta,
    )
}

/// `twist` held for `duration`, with its body-frame pose change computed once: a robot's
/// actions repeat the same few arcs every control period, so their sines and cosines need
/// not be taken again at every step. [`end`](Self::end) is bit for bit [`integrate_arc`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedArc {
    twist: Twist,
    duration: f64,
    displacement: Isometry2<f64>,
}

impl FixedArc {
    /// The arc of `twist` held for `duration` seconds.
    #[must_use]
    pub fn new(twist: Twist, duration: f64) -> Self {
        Self {
            twist,
            duration,
            displacement: arc_displacement(twist, duration),
        }
    }

    /// The twist.
    #[must_use]
    pub fn twist(&self) -> Twist {
        self.twist
    }

    /// How long it is held (s).
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// The pose reached from `pose`: `integrate_arc(pose, twist, duration)`.
    #[must_use]
    pub fn end(&self, pose: &Isometry2<f64>) -> Isometry2<f64> {
        pose * self.displacement
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point2;

    const EPS: f64 = 1e-12;

    #[test]
    fn equal_wheel_speeds_go_straight_by_v_t() {
        let robot = RobotParams::default();
        let twist = robot.twist(WheelSpeeds {
            left: 5.0,
            right: 5.0,
        });
        assert_eq!(twist.angular, 0.0);
        assert!((twist.linear - 0.1).abs() < EPS);
        let start = Isometry2::new(Vector2::new(1.0, 2.0), std::f64::consts::FRAC_PI_6);
        let end = integrate_arc(&start, twist, 3.0);
        let moved = end.translation.vector - start.translation.vector;
        let heading = Vector2::new(
            std::f64::consts::FRAC_PI_6.cos(),
            std::f64::consts::FRAC_PI_6.sin(),
        );
        assert!((moved - heading * 0.3).norm() < EPS, "{moved:?}");
        assert!((end.rotation.angle() - start.rotation.angle()).abs() < EPS);
        assert_eq!(twist.arc_radius(), None);
    }

    #[test]
    fn opposite_wheel_speeds_spin_in_place() {
        let robot = RobotParams::default();
        let twist = robot.twist(WheelSpeeds {
            left: -2.0,
            right: 2.0,
        });
        assert_eq!(twist.linear, 0.0);
        // ω = r (ω_r − ω_l) / L = 0.02 · 4 / 0.052.
        assert!((twist.angular - 0.08 / 0.052).abs() < EPS);
        let start = Isometry2::new(Vector2::new(0.3, 0.4), 0.5);
        let end = integrate_arc(&start, twist, 0.5);
        assert!((end.translation.vector - start.translation.vector).norm() < EPS);
        let turned = end.rotation.angle() - start.rotation.angle();
        assert!((turned - 0.5 * 0.08 / 0.052).abs() < EPS, "{turned}");
    }

    #[test]
    fn arc_radius_matches_formula_and_the_path_stays_on_the_circle() {
        let robot = RobotParams::default();
        let wheels = WheelSpeeds {
            left: 3.0,
            right: 6.0,
        };
        let twist = robot.twist(wheels);
        // R = (L / 2) (ω_r + ω_l) / (ω_r − ω_l) = 0.026 · 9 / 3 = 0.078 m, to the left.
        let radius = twist.arc_radius().expect("turning");
        assert!((radius - 0.078).abs() < EPS, "{radius}");
        let start = Isometry2::new(Vector2::new(0.5, 0.5), 1.0);
        // The centre of the arc is R to the robot's left.
        let centre = start * Point2::new(0.0, radius);
        for k in 1..=20 {
            let pose = integrate_arc(&start, twist, 0.1 * f64::from(k));
            let r = (Point2::from(pose.translation.vector) - centre).norm();
            assert!((r - radius).abs() < 1e-12, "step {k}: {r}");
            // The heading stays tangent: perpendicular to the radius.
            let to_robot = Point2::from(pose.translation.vector) - centre;
            let heading = pose.rotation * Vector2::x();
            assert!(to_robot.dot(&heading).abs() < 1e-12);
        }
    }

    #[test]
    fn small_turn_rates_are_continuous_with_the_straight_line() {
        let start = Isometry2::new(Vector2::new(0.0, 0.0), 0.0);
        let straight = integrate_arc(
            &start,
            Twist {
                linear: 0.1,
                angular: 0.0,
            },
            1.0,
        );
        for omega in [1e-9, 1e-6, 9.99e-5, 1.01e-4, 1e-3] {
            let bent = integrate_arc(
                &start,
                Twist {
                    linear: 0.1,
                    angular: omega,
                },
                1.0,
            );
            let lateral = bent.translation.vector.y;
            // Exact lateral offset v (1 − cos ωt)/ω, by its series in ω (t = 1).
            let series = 0.1 * (omega / 2.0 - omega.powi(3) / 24.0 + omega.powi(5) / 720.0);
            assert!(
                (lateral - series).abs() < 1e-18,
                "{omega}: {lateral} vs {series}"
            );
            let gap = (bent.translation.vector - straight.translation.vector).norm();
            assert!(gap < 0.1 * omega, "{omega}: {gap}");
        }
    }
}
