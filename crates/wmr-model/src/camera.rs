//! The range camera: is the target in view, and where is the nearest obstacle (Sec. III.A, Eq. 5)?
//!
//! The camera sits `offset` metres ahead of the robot's centre, `height` metres above the
//! floor, looking horizontally along the heading. It reports:
//!
//! * whether the target is inside the horizontal field of view (the target is a beacon seen
//!   over the obstacles: only the field of view decides, not occlusion);
//! * the nearest obstacle whose *feature point* is in view and within `obstacle_range`. The
//!   feature point is the obstacle's bottom centre: where the line of sight from the camera to
//!   the obstacle's centre first meets its footprint on the floor. An obstacle is in view when
//!   that line of sight is inside the horizontal field of view: one whose centre lies outside
//!   it is not reported even if its edge shows, because the paper's feature-point method cannot
//!   place it. Walls are not obstacles here;
//! * for that obstacle, the image ratio δ of Eq. 5 and the angle between the robot's heading
//!   and the line from the robot's centre to the feature point.
//!
//! # Reading Eq. 5
//!
//! Fig. 2 of the paper is a side view: `A` is the camera, `AB` the horizontal line of sight to
//! the obstacle, `β₁` the half field of view measured from that horizontal, `C` the feature
//! point on the floor, `β` the angle `BAC` below the horizon. Then
//! `δ = ½ (AB tan β₁ + AB tan β) / (AB tan β₁) = ½ (tan β / tan β₁ + 1)` is C's position down the
//! image (0 at the top edge, ½ on the horizon, 1 at the bottom edge), and `tan β = height / d`
//! for a feature point at horizontal distance `d`. So δ encodes the obstacle's *distance*, and
//! the angle feature its *bearing*: together a polar fix of the obstacle. This is
//! [`DeltaAxis::Vertical`], the default. Read as a top view instead (β the horizontal bearing,
//! β₁ the horizontal half field of view, δ across the image width), δ would repeat the bearing;
//! that reading is kept as [`DeltaAxis::Horizontal`]. A feature point below the image's bottom
//! edge (an obstacle closer than `height / tan β₁`) is still an obstacle in view, with δ clamped
//! to 1.

use nalgebra::{Isometry2, Point2, Vector2};
use serde::{Deserialize, Serialize};

use crate::world::{BROAD_PHASE_MARGIN, Obstacle, World};

/// Which image axis δ of Eq. 5 measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum DeltaAxis {
    /// Side view (Fig. 2): δ is the feature point's height in the image, `[½, 1]` on the floor.
    #[default]
    Vertical,
    /// Top view: δ is the feature point's position across the image, `[0, 1]` left to right.
    Horizontal,
}

impl DeltaAxis {
    /// The interval δ can take for a feature point in view.
    #[must_use]
    pub fn range(self) -> (f64, f64) {
        match self {
            Self::Vertical => (0.5, 1.0),
            Self::Horizontal => (0.0, 1.0),
        }
    }
}

/// Camera mount and optics.
///
/// Defaults describe an RGB-D camera of the Intel `RealSense` D435 class (depth field of view
/// 87° × 58°) on top of the e-puck: 5 cm above the floor, 3 cm ahead of the centre. The paper's
/// robot carries an RGB-D camera, and the wide view leaves room to sidestep obstacles without
/// losing the target. The e-puck's own 0.84 rad camera also solves the default scenario, with
/// little slack: the planner's route grows from 34 to 39 steps and a random policy loses the
/// target after 9 steps on average instead of 17.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraParams {
    /// Horizontal field of view (rad), in `(0, π)`.
    pub horizontal_fov: f64,
    /// Vertical field of view (rad), in `(0, π)`; `β₁` of Eq. 5 is half of it.
    pub vertical_fov: f64,
    /// Height of the optical centre above the floor (m).
    pub height: f64,
    /// Distance of the camera ahead of the robot's centre (m), at most the body radius.
    pub offset: f64,
    /// Obstacles whose feature point is farther than this from the camera are not reported (m).
    pub obstacle_range: f64,
    /// Which image axis δ measures.
    pub delta_axis: DeltaAxis,
}

impl Default for CameraParams {
    fn default() -> Self {
        Self {
            horizontal_fov: 87.0_f64.to_radians(),
            vertical_fov: 58.0_f64.to_radians(),
            height: 0.05,
            offset: 0.03,
            obstacle_range: 0.5,
            delta_axis: DeltaAxis::Vertical,
        }
    }
}

/// The nearest obstacle in view.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ObstacleSighting {
    /// Index of the obstacle in the scenario's list.
    pub index: usize,
    /// The feature point (bottom centre) in world coordinates.
    pub feature: Point2<f64>,
    /// Horizontal distance from the camera to the feature point (m).
    pub distance: f64,
    /// Image ratio δ of Eq. 5, clamped to the image.
    pub delta: f64,
    /// Signed angle from the robot's heading to the line from its centre to the feature
    /// point (rad, counter-clockwise positive, in `(−π, π]`).
    pub angle: f64,
}

/// What the camera sees from one pose.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CameraView {
    /// The target is inside the horizontal field of view.
    pub target_in_view: bool,
    /// The target's horizontal image position `δ_T`: Eq. 5 in its horizontal form,
    /// `½ (tan β_T / tan β₁ʰ + 1)` with `β_T` the target's bearing from the optical axis
    /// (clockwise positive) and `β₁ʰ` half the horizontal field of view: 0 at the image's left
    /// edge, ½ straight ahead, 1 at its right edge. Clamped to `[0, 1]`; a target behind the
    /// camera gets the edge on its side. The state's optional target feature bins it.
    pub target_ratio: f64,
    /// The nearest obstacle in view, if any.
    pub obstacle: Option<ObstacleSighting>,
}

/// δ of Eq. 5: `½ (tan β / tan β₁ + 1)`, with `β` the angle to the point and `β₁` the half field
/// of view (both measured from the optical axis, radians). Not clamped.
#[must_use]
pub fn image_ratio(beta: f64, half_fov: f64) -> f64 {
    0.5 * (beta.tan() / half_fov.tan() + 1.0)
}

/// The camera with its trigonometry precomputed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    params: CameraParams,
    tan_half_horizontal: f64,
    tan_half_vertical: f64,
}

impl Camera {
    /// A camera described by `params` (validated by the scenario).
    #[must_use]
    pub fn new(params: CameraParams) -> Self {
        Self {
            params,
            tan_half_horizontal: (params.horizontal_fov / 2.0).tan(),
            tan_half_vertical: (params.vertical_fov / 2.0).tan(),
        }
    }

    /// Mount and optics.
    #[must_use]
    pub fn params(&self) -> &CameraParams {
        &self.params
    }

    /// Where the camera is for the robot at `pose`.
    #[must_use]
    pub fn position(&self, pose: &Isometry2<f64>) -> Point2<f64> {
        pose * Point2::new(self.params.offset, 0.0)
    }

    /// Whether a point given in the camera's frame (x forward, y left) lies inside the
    /// horizontal field of view. Points on the edge are in view.
    fn in_view_local(&self, local: &Vector2<f64>) -> bool {
        local.x > 0.0 && local.y.abs() <= local.x * self.tan_half_horizontal
    }

    /// Whether `point` is inside the horizontal field of view from `pose`.
    #[must_use]
    pub fn sees(&self, pose: &Isometry2<f64>, point: &Point2<f64>) -> bool {
        let local = pose.rotation.inverse() * (point - self.position(pose));
        self.in_view_local(&local)
    }

    /// δ for a feature point at horizontal distance `distance` and camera-frame direction
    /// `local_direction` (unit), clamped to the image.
    fn delta(&self, distance: f64, local_direction: &Vector2<f64>) -> f64 {
        match self.params.delta_axis {
            DeltaAxis::Vertical => {
                // tan β = height / distance; clamp to the bottom edge when β > β₁.
                let scaled = distance * self.tan_half_vertical;
                if self.params.height >= scaled {
                    1.0
                } else {
                    0.5 * (self.params.height / scaled + 1.0)
                }
            }
            DeltaAxis::Horizontal => {
                // Image columns run left to right, i.e. towards negative (clockwise) bearings.
                let tan_beta = -local_direction.y / local_direction.x;
                (0.5 * (tan_beta / self.tan_half_horizontal + 1.0)).clamp(0.0, 1.0)
            }
        }
    }

    /// What the camera sees from `pose` in `world` with the target at `target`.
    #[must_use]
    pub fn observe(
        &self,
        world: &World,
        pose: &Isometry2<f64>,
        target: &Point2<f64>,
    ) -> CameraView {
        let camera = self.position(pose);
        let to_local = pose.rotation.inverse();
        let target_local = to_local * (target - camera);
        let target_in_view = self.in_view_local(&target_local);
        let target_ratio = self.horizontal_ratio(&target_local);

        // The nearest so far: index, distance, camera-frame line of sight and its length (the
        // unit direction is divided out once, for the winner).
        let mut best: Option<(usize, f64, Vector2<f64>, f64)> = None;
        for (index, (obstacle, bound)) in world.obstacles().iter().zip(world.bounds()).enumerate() {
            let to_centre = bound.centre - camera;
            // Broad phase: the feature point lies in the bounding disc, so an obstacle whose
            // disc is beyond the range, or beyond the nearest obstacle so far, is neither
            // reported nor nearer.
            let nearest = best.map_or(self.params.obstacle_range, |(_, nearest, _, _)| nearest);
            let limit = nearest + bound.radius + BROAD_PHASE_MARGIN;
            if to_centre.norm_squared() > limit * limit {
                continue;
            }
            let local = to_local * to_centre;
            if !self.in_view_local(&local) {
                continue;
            }
            let norm = to_centre.norm();
            let distance = match obstacle {
                Obstacle::Circle(c) => (norm - c.radius).max(0.0),
                Obstacle::Rect(r) => r.ray_distance(&camera, &(to_centre / norm)).unwrap_or(0.0),
            };
            if distance <= self.params.obstacle_range
                && best.is_none_or(|(_, nearest, _, _)| distance < nearest)
            {
                best = Some((index, distance, local, norm));
            }
        }
        let obstacle = best.map(|(index, distance, local, norm)| {
            let local_direction = local / norm;
            // The feature point in the robot's frame: camera offset plus the line of sight.
            let in_robot = Vector2::new(self.params.offset, 0.0) + local_direction * distance;
            ObstacleSighting {
                index,
                feature: pose * Point2::from(in_robot),
                distance,
                delta: self.delta(distance, &local_direction),
                angle: in_robot.y.atan2(in_robot.x),
            }
        });
        CameraView {
            target_in_view,
            target_ratio,
            obstacle,
        }
    }

    /// `δ_T` of a point given in the camera's frame (x forward, y left), clamped to `[0, 1]`.
    fn horizontal_ratio(&self, local: &Vector2<f64>) -> f64 {
        if local.x <= 0.0 {
            // Beside or behind the camera: the edge on its side (left edge for y ≥ 0).
            return if local.y >= 0.0 { 0.0 } else { 1.0 };
        }
        let tan_beta = -local.y / local.x;
        (0.5 * (tan_beta / self.tan_half_horizontal + 1.0)).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Circle, Rect};
    use std::f64::consts::FRAC_PI_4;

    #[test]
    fn eq5_hand_values() {
        // β = 0: the horizon, the middle of the image.
        assert!((image_ratio(0.0, 0.3) - 0.5).abs() < 1e-15);
        // β = β₁: the bottom edge.
        assert!((image_ratio(0.3, 0.3) - 1.0).abs() < 1e-15);
        // β = −β₁: the top edge.
        assert!(image_ratio(-0.3, 0.3).abs() < 1e-15);
        // β₁ = 45°, β = atan(½): δ = ½ (½ / 1 + 1) = 0.75.
        assert!((image_ratio(0.5_f64.atan(), FRAC_PI_4) - 0.75).abs() < 1e-15);
        // β₁ = 30°, β = 15°: δ = ½ (tan 15° / tan 30° + 1) = ½ ((2 − √3) √3 + 1) = √3 − 1.
        let delta = image_ratio(15.0_f64.to_radians(), 30.0_f64.to_radians());
        assert!((delta - (3.0_f64.sqrt() - 1.0)).abs() < 1e-15, "{delta}");
    }

    fn camera(axis: DeltaAxis) -> Camera {
        Camera::new(CameraParams {
            horizontal_fov: std::f64::consts::FRAC_PI_2,
            vertical_fov: std::f64::consts::FRAC_PI_2,
            height: 0.1,
            offset: 0.02,
            obstacle_range: 1.0,
            delta_axis: axis,
        })
    }

    #[test]
    fn vertical_delta_follows_the_floor_geometry() {
        // Cylinder r = 0.05 centred 0.42 ahead of the camera: feature point 0.37 away,
        // tan β = 0.1 / 0.37, tan β₁ = 1, δ = ½ (0.1 / 0.37 + 1).
        let world = World::new(
            2.0,
            2.0,
            vec![Obstacle::Circle(Circle::new(Point2::new(0.94, 1.0), 0.05))],
        );
        let cam = camera(DeltaAxis::Vertical);
        let pose = Isometry2::new(Vector2::new(0.5, 1.0), 0.0);
        let view = cam.observe(&world, &pose, &Point2::new(1.9, 1.0));
        assert!(view.target_in_view);
        let seen = view.obstacle.expect("in view");
        assert_eq!(seen.index, 0);
        assert!((seen.distance - 0.37).abs() < 1e-12);
        assert!((seen.delta - 0.5 * (0.1 / 0.37 + 1.0)).abs() < 1e-12);
        assert!(seen.angle.abs() < 1e-12);
        assert!((seen.feature - Point2::new(0.89, 1.0)).norm() < 1e-12);
        // Closer than height / tan β₁ = 0.1: below the image, clamped to 1.
        let close = World::new(
            2.0,
            2.0,
            vec![Obstacle::Circle(Circle::new(Point2::new(0.6, 1.0), 0.05))],
        );
        let seen = cam
            .observe(&close, &pose, &Point2::new(1.9, 1.0))
            .obstacle
            .expect("in view");
        assert_eq!(seen.delta, 1.0);
    }

    #[test]
    fn angle_is_measured_from_the_robot_centre() {
        // Box whose near face is at x = 0.82 (robot at 0.5, camera at 0.52), centre 0.3 to the
        // left at y = 1.3 ⇒ line of sight from (0.52, 1) to (0.87, 1.3); the entry point is
        // where it crosses x = 0.82, i.e. (0.82, 1 + 0.3 · 0.30/0.35).
        let world = World::new(
            2.0,
            2.0,
            vec![Obstacle::Rect(Rect::from_centre(
                Point2::new(0.87, 1.3),
                0.1,
                0.1,
            ))],
        );
        let cam = camera(DeltaAxis::Vertical);
        let pose = Isometry2::new(Vector2::new(0.5, 1.0), 0.0);
        let seen = cam
            .observe(&world, &pose, &Point2::new(1.9, 1.0))
            .obstacle
            .expect("in view");
        let feature = Point2::new(0.82, 1.0 + 0.3 * 0.30 / 0.35);
        assert!(
            (seen.feature - feature).norm() < 1e-12,
            "{:?}",
            seen.feature
        );
        let expected_angle = (feature.y - 1.0).atan2(feature.x - 0.5);
        assert!((seen.angle - expected_angle).abs() < 1e-12);
        assert!((seen.distance - (feature - Point2::new(0.52, 1.0)).norm()).abs() < 1e-12);
    }

    #[test]
    fn target_ratio_is_eq5_across_the_image() {
        let cam = camera(DeltaAxis::Vertical);
        let world = World::new(2.0, 2.0, vec![]);
        let pose = Isometry2::new(Vector2::new(0.5, 1.0), 0.0);
        let camera_at = Point2::new(0.52, 1.0);
        // Straight ahead: the image's middle.
        let ahead = cam.observe(&world, &pose, &Point2::new(1.5, 1.0));
        assert!((ahead.target_ratio - 0.5).abs() < 1e-15);
        // 30° to the left with a 45° half view: ½ (tan(−30°) / tan 45° + 1) = ½ (1 − 1/√3).
        let bearing = 30.0_f64.to_radians();
        let left = camera_at + Vector2::new(bearing.cos(), bearing.sin()) * 0.4;
        let seen = cam.observe(&world, &pose, &left);
        assert!((seen.target_ratio - 0.5 * (1.0 - 1.0 / 3.0_f64.sqrt())).abs() < 1e-12);
        // Outside the view: clamped to the edge on its side.
        let behind_right = cam.observe(&world, &pose, &Point2::new(0.3, 0.5));
        assert!(!behind_right.target_in_view);
        assert_eq!(behind_right.target_ratio, 1.0);
        let far_left = cam.observe(&world, &pose, &Point2::new(0.6, 1.9));
        assert_eq!(far_left.target_ratio, 0.0);
    }

    #[test]
    fn horizontal_delta_is_the_bearing_across_the_image() {
        // Obstacle 30° to the left of the camera axis, half field of view 45°:
        // δ = ½ (tan(−30°) / tan 45° + 1) = ½ (1 − 1/√3).
        let cam = camera(DeltaAxis::Horizontal);
        let bearing = 30.0_f64.to_radians();
        let camera_at = Point2::new(0.52, 1.0);
        let centre = camera_at + Vector2::new(bearing.cos(), bearing.sin()) * 0.5;
        let world = World::new(2.0, 2.0, vec![Obstacle::Circle(Circle::new(centre, 0.05))]);
        let pose = Isometry2::new(Vector2::new(0.5, 1.0), 0.0);
        let seen = cam
            .observe(&world, &pose, &Point2::new(1.9, 1.0))
            .obstacle
            .expect("in view");
        assert!((seen.delta - 0.5 * (1.0 - 1.0 / 3.0_f64.sqrt())).abs() < 1e-12);
    }

    #[test]
    fn field_of_view_edges_and_nearest_obstacle() {
        let cam = camera(DeltaAxis::Vertical);
        let pose = Isometry2::new(Vector2::new(0.5, 1.0), 0.0);
        // 45° half field of view from the camera at (0.52, 1).
        assert!(cam.sees(&pose, &Point2::new(1.02, 1.49)));
        assert!(!cam.sees(&pose, &Point2::new(1.02, 1.51)));
        assert!(!cam.sees(&pose, &Point2::new(0.4, 1.0)));
        let world = World::new(
            2.0,
            2.0,
            vec![
                Obstacle::Circle(Circle::new(Point2::new(1.2, 1.0), 0.05)),
                Obstacle::Circle(Circle::new(Point2::new(0.9, 1.1), 0.05)),
                Obstacle::Circle(Circle::new(Point2::new(0.2, 1.0), 0.05)), // behind
                Obstacle::Circle(Circle::new(Point2::new(0.6, 1.6), 0.05)), // outside the FOV
            ],
        );
        let view = cam.observe(&world, &pose, &Point2::new(1.9, 1.0));
        assert_eq!(view.obstacle.map(|s| s.index), Some(1));
        let far = Camera::new(CameraParams {
            obstacle_range: 0.2,
            ..*cam.params()
        });
        assert_eq!(
            far.observe(&world, &pose, &Point2::new(1.9, 1.0)).obstacle,
            None
        );
    }
}
