//! The arena: walls, obstacles, and the robot body moving among them.
//!
//! The arena is the rectangle `[0, width] × [0, height]` surrounded by walls. Obstacles are
//! discs and axis-aligned rectangles, kept in one small flat list. The robot's body is a disc;
//! it *overlaps* the world when its clearance (distance from its centre to the nearest wall or
//! obstacle, minus its radius) is negative. Touching (clearance exactly 0) is not overlapping.

use nalgebra::{Isometry2, Point2, Vector2};
use serde::{Deserialize, Serialize};

use crate::geometry::{Circle, Rect};
use crate::kinematics::{FixedArc, Twist, integrate_arc, integrate_arc_centre};

/// One obstacle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Obstacle {
    /// A cylinder.
    Circle(Circle),
    /// An axis-aligned box.
    Rect(Rect),
}

impl Obstacle {
    /// Distance from `point` to the obstacle's footprint (0 inside it).
    #[must_use]
    pub fn distance_to(&self, point: &Point2<f64>) -> f64 {
        match self {
            Self::Circle(c) => c.distance_to(point),
            Self::Rect(r) => r.distance_to(point),
        }
    }

    /// Distance along a ray (unit `direction`) to the footprint, `None` on a miss.
    #[must_use]
    pub fn ray_distance(&self, origin: &Point2<f64>, direction: &Vector2<f64>) -> Option<f64> {
        match self {
            Self::Circle(c) => c.ray_distance(origin, direction),
            Self::Rect(r) => r.ray_distance(origin, direction),
        }
    }

    /// Centre of the footprint.
    #[must_use]
    pub fn centre(&self) -> Point2<f64> {
        match self {
            Self::Circle(c) => c.centre,
            Self::Rect(r) => r.centre(),
        }
    }

    /// Radius of the smallest disc about [`centre`](Self::centre) that holds the footprint.
    #[must_use]
    pub fn bounding_radius(&self) -> f64 {
        match self {
            Self::Circle(c) => c.radius,
            Self::Rect(r) => (r.max - r.min).norm() / 2.0,
        }
    }
}

/// A bounding disc, kept beside each obstacle to reject short rays cheaply.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bound {
    /// [`Obstacle::centre`].
    pub(crate) centre: Point2<f64>,
    /// [`Obstacle::bounding_radius`].
    pub(crate) radius: f64,
}

/// Where a body ended up after trying to move, and whether it hit something on the way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Motion {
    /// Final pose: the commanded one, or the last pose before contact on a hit.
    pub pose: Isometry2<f64>,
    /// The body would have overlapped a wall or an obstacle during the move.
    pub hit: bool,
    /// The clearance at `pose` ([`World::clearance`] with the body's radius) when the move
    /// computed it (every move that is not a hit), to be passed to the next move.
    pub clearance: Option<f64>,
}

/// Sub-step length (m) used near obstacles. Between two checked poses `h` apart, a disc of
/// radius `R` can graze an unseen corner by at most `h² / (8R)`: 0.014 mm for the e-puck.
pub const MAX_SUBSTEP: f64 = 0.002;

/// Bisection rounds that locate the contact on a hit: the contact is found to within
/// `MAX_SUBSTEP / 2⁴⁰` of arc length.
const CONTACT_BISECTIONS: u32 = 40;

/// Slack (m) of the broad phases: a wall or an obstacle is left out of a query only when it
/// is farther than the query can matter by this much, which is far above rounding (about
/// 10⁻¹⁶ m at arena sizes) and far below anything that matters physically.
pub(crate) const BROAD_PHASE_MARGIN: f64 = 1e-6;

/// The walls and obstacles (built from a [`Scenario`](crate::Scenario), which is the
/// serialisable form).
#[derive(Debug, Clone, PartialEq)]
pub struct World {
    arena: Rect,
    obstacles: Vec<Obstacle>,
    bounds: Vec<Bound>,
}

impl World {
    /// A world with the arena `[0, width] × [0, height]` and the given obstacles.
    #[must_use]
    pub fn new(width: f64, height: f64, obstacles: Vec<Obstacle>) -> Self {
        let bounds = obstacles
            .iter()
            .map(|o| Bound {
                centre: o.centre(),
                radius: o.bounding_radius(),
            })
            .collect();
        Self {
            arena: Rect {
                min: Point2::origin(),
                max: Point2::new(width, height),
            },
            obstacles,
            bounds,
        }
    }

    /// The arena's rectangle (inside of the walls).
    #[must_use]
    pub fn arena(&self) -> &Rect {
        &self.arena
    }

    /// The obstacles, in scenario order.
    #[must_use]
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.obstacles
    }

    /// The obstacles' bounding discs, in scenario order.
    pub(crate) fn bounds(&self) -> &[Bound] {
        &self.bounds
    }

    /// Clearance of a disc of `radius` at `centre`: the distance to the nearest wall or
    /// obstacle minus `radius`. Negative exactly when the disc overlaps something.
    #[must_use]
    pub fn clearance(&self, centre: &Point2<f64>, radius: f64) -> f64 {
        let mut nearest = self.arena.inner_clearance(centre);
        for (obstacle, bound) in self.obstacles.iter().zip(&self.bounds) {
            // An obstacle whose bounding disc is farther than the nearest surface so far cannot
            // be nearer (its distance is at least the distance to that disc): leave out its
            // square root. The minimum is the same value whichever order, and whichever of
            // the farther ones, it is taken over.
            let limit = nearest + bound.radius + BROAD_PHASE_MARGIN;
            if (bound.centre - centre).norm_squared() > limit * limit {
                continue;
            }
            nearest = nearest.min(obstacle.distance_to(centre));
        }
        nearest - radius
    }

    /// Whether a disc of `radius` at `centre` overlaps a wall or an obstacle:
    /// `clearance(centre, radius) < 0`, exactly (a difference `a − b` of floats is negative
    /// exactly when `a < b`), answered by the first surface closer than `radius` and without
    /// the obstacles whose bounding disc is farther.
    #[must_use]
    pub fn overlaps(&self, centre: &Point2<f64>, radius: f64) -> bool {
        if self.arena.inner_clearance(centre) < radius {
            return true;
        }
        self.obstacles
            .iter()
            .zip(&self.bounds)
            .any(|(obstacle, bound)| {
                let limit = radius + bound.radius + BROAD_PHASE_MARGIN;
                (bound.centre - centre).norm_squared() <= limit * limit
                    && obstacle.distance_to(centre) < radius
            })
    }

    /// The obstacles among the first 64 whose bounding disc comes within `reach` of `centre`
    /// (give or take [`BROAD_PHASE_MARGIN`]), as a bit set by index: those a disc of radius
    /// `r` whose centre stays within `reach − r` of `centre` may overlap.
    fn obstacles_near(&self, centre: &Point2<f64>, reach: f64) -> u64 {
        let mut near = 0;
        for (index, bound) in self.bounds.iter().take(64).enumerate() {
            let limit = reach + bound.radius + BROAD_PHASE_MARGIN;
            // Written as "not beyond" so that a NaN keeps the obstacle in.
            let beyond = (bound.centre - centre).norm_squared() > limit * limit;
            if !beyond {
                near |= 1 << index;
            }
        }
        near
    }

    /// [`overlaps`](Self::overlaps) asking only the walls, the obstacles in the bit set
    /// `near` (from [`obstacles_near`](Self::obstacles_near)) and any past the 64th: the same
    /// answer for a centre within the reach `near` was taken for.
    fn overlaps_among(&self, centre: &Point2<f64>, radius: f64, near: u64) -> bool {
        if self.arena.inner_clearance(centre) < radius {
            return true;
        }
        let overlaps_obstacle = |index: usize| {
            let bound = &self.bounds[index];
            let limit = radius + bound.radius + BROAD_PHASE_MARGIN;
            (bound.centre - centre).norm_squared() <= limit * limit
                && self.obstacles[index].distance_to(centre) < radius
        };
        let mut left = near;
        while left != 0 {
            let index = left.trailing_zeros() as usize;
            left &= left - 1;
            if overlaps_obstacle(index) {
                return true;
            }
        }
        (64..self.obstacles.len()).any(overlaps_obstacle)
    }

    /// Distance along the ray from `origin` in the unit `direction` to the first wall or
    /// obstacle, capped at `max_range`.
    #[must_use]
    pub fn ray_cast(&self, origin: &Point2<f64>, direction: &Vector2<f64>, max_range: f64) -> f64 {
        let mut nearest = self
            .arena
            .ray_exit_distance(origin, direction)
            .min(max_range);
        for index in 0..self.obstacles.len() {
            nearest = self.ray_nearer(index, origin, direction, nearest);
        }
        nearest
    }

    /// [`ray_cast`](Self::ray_cast) of the rays leaving the rim of the disc of radius `rim`
    /// about `centre` along each unit direction of `directions` (ray `i` starts at
    /// `centre + directions[i] · rim`), each capped at `max_range`: the same distances, bit
    /// for bit.
    ///
    /// One broad phase serves every ray: walls and obstacles farther from `centre` than the
    /// rays can reach (with a 1 µm margin, far above rounding) are left out, which
    /// [`ray_cast`](Self::ray_cast) would have skipped or capped at `max_range` anyway.
    #[must_use]
    pub fn ray_cast_fan<const N: usize>(
        &self,
        centre: &Point2<f64>,
        rim: f64,
        directions: &[Vector2<f64>; N],
        max_range: f64,
    ) -> [f64; N] {
        let reach = rim + max_range + BROAD_PHASE_MARGIN;
        let arena = &self.arena;
        let walls_beyond = arena.inner_clearance(centre) > reach;
        // Each wall on its own: a ray's exit distance through a wall beyond reach is beyond
        // `max_range`, so it cannot be the capped minimum. Written as "not beyond" so that a
        // NaN keeps everything in (and as `ray_cast` does).
        let beyond = |gap: f64| gap > reach;
        let walls_near = [
            !beyond(centre.x - arena.min.x),
            !beyond(arena.max.x - centre.x),
            !beyond(centre.y - arena.min.y),
            !beyond(arena.max.y - centre.y),
        ];
        // Obstacles the fan may reach, as a bit set over the first 64 (more are always
        // checked, in order, as `ray_cast` checks them).
        let mut near: u64 = 0;
        for (index, bound) in self.bounds.iter().enumerate().take(64) {
            let limit = reach + bound.radius;
            let beyond = (bound.centre - centre).norm_squared() > limit * limit;
            if !beyond {
                near |= 1 << index;
            }
        }
        if walls_beyond && near == 0 && self.bounds.len() <= 64 {
            // Nothing within reach (the common case away from walls and obstacles): every ray
            // below would start at `max_range` and skip every obstacle.
            return [max_range; N];
        }
        // A loop rather than `directions.map`: the array adaptor's machinery cost more than
        // the rays themselves.
        let mut distances = [max_range; N];
        for (distance, direction) in distances.iter_mut().zip(directions) {
            let origin = centre + direction * rim;
            let mut nearest = if walls_beyond {
                max_range
            } else {
                ray_exit_distance_near(arena, &origin, direction, walls_near).min(max_range)
            };
            // The near obstacles in index order (the order `ray_cast` takes them in), then
            // any past the 64th.
            let mut left = near;
            while left != 0 {
                let index = left.trailing_zeros() as usize;
                left &= left - 1;
                nearest = self.ray_nearer(index, &origin, direction, nearest);
            }
            for index in 64..self.obstacles.len() {
                nearest = self.ray_nearer(index, &origin, direction, nearest);
            }
            *distance = nearest;
        }
        distances
    }

    /// One obstacle's turn in [`ray_cast`](Self::ray_cast): the distance to obstacle `index`
    /// along the ray when it is nearer than `nearest`, else `nearest`.
    #[inline]
    fn ray_nearer(
        &self,
        index: usize,
        origin: &Point2<f64>,
        direction: &Vector2<f64>,
        nearest: f64,
    ) -> f64 {
        let bound = &self.bounds[index];
        // Obstacles wholly beyond the current nearest hit cannot be hit first.
        let reach = nearest + bound.radius;
        if (bound.centre - origin).norm_squared() > reach * reach {
            return nearest;
        }
        match self.obstacles[index].ray_distance(origin, direction) {
            Some(t) => nearest.min(t),
            None => nearest,
        }
    }

    /// Moves a disc of `radius` from `pose` along the exact arc of `twist` for `duration`.
    ///
    /// If the disc would overlap a wall or an obstacle anywhere along the way (checked by
    /// conservative advancement: free stretches are skipped by the current clearance,
    /// stretches closer than [`MAX_SUBSTEP`] are sub-stepped), the motion stops at the last
    /// pose found free before contact, and `hit` is set. The returned pose never overlaps
    /// when `hit` is false, and never overlaps more than the start pose did when it is true.
    #[must_use]
    pub fn move_disc(
        &self,
        pose: &Isometry2<f64>,
        twist: Twist,
        duration: f64,
        radius: f64,
    ) -> Motion {
        self.move_disc_along(pose, &FixedArc::new(twist, duration), radius, None)
    }

    /// [`move_disc`](Self::move_disc) along a precomputed arc, given the clearance at `pose`
    /// if it is known (the previous move's [`Motion::clearance`]): the same motion, bit for
    /// bit, without recomputing the arc's trigonometry or the start clearance.
    #[must_use]
    pub fn move_disc_along(
        &self,
        pose: &Isometry2<f64>,
        arc: &FixedArc,
        radius: f64,
        start_clearance: Option<f64>,
    ) -> Motion {
        let (twist, duration) = (arc.twist(), arc.duration());
        let centre_of = |p: &Isometry2<f64>| Point2::from(p.translation.vector);
        let start_clearance =
            start_clearance.unwrap_or_else(|| self.clearance(&centre_of(pose), radius));
        if start_clearance < 0.0 {
            return Motion {
                pose: *pose,
                hit: true,
                clearance: Some(start_clearance),
            };
        }
        let length = (twist.linear * duration).abs();
        let end = arc.end(pose);
        if length <= start_clearance {
            let end_centre = centre_of(&end);
            let start_centre = centre_of(pose);
            // A move that leaves the centre where it was, bit for bit (a `stop`, a turn on
            // the spot), keeps its clearance.
            let end_clearance = if end_centre.x.to_bits() == start_centre.x.to_bits()
                && end_centre.y.to_bits() == start_centre.y.to_bits()
            {
                start_clearance
            } else {
                self.clearance(&end_centre, radius)
            };
            if end_clearance >= 0.0 {
                // The centre moves at most `length` (an arc is never shorter than its chord).
                return Motion {
                    pose: end,
                    hit: false,
                    clearance: Some(end_clearance),
                };
            }
        }
        let pose_at = |s: f64| integrate_arc(pose, twist, duration * (s / length));
        // Where the centre is after `s` of arc: `pose_at(s)`'s translation, bit for bit.
        let centre_at = |s: f64| integrate_arc_centre(pose, twist, duration * (s / length));
        let mut travelled = 0.0;
        let mut clearance = start_clearance;
        // The centre after `travelled`.
        let mut centre = centre_of(pose);
        loop {
            let remaining = length - travelled;
            let advance = clearance.max(MAX_SUBSTEP).min(remaining);
            let next = travelled + advance;
            let next_centre = if advance >= remaining {
                centre_of(&end)
            } else {
                centre_at(next)
            };
            let next_clearance = self.clearance(&next_centre, radius);
            if next_clearance < 0.0 {
                // Contact lies in (travelled, next]: bisect, keeping the free end. Every
                // centre tried is within `advance` of `centre` (an arc is never shorter
                // than its chord), so only the obstacles within that reach can overlap it.
                let near = self.obstacles_near(&centre, radius + advance);
                let (mut free, mut blocked) = (travelled, next);
                for _ in 0..CONTACT_BISECTIONS {
                    let mid = 0.5 * (free + blocked);
                    if self.overlaps_among(&centre_at(mid), radius, near) {
                        blocked = mid;
                    } else {
                        free = mid;
                    }
                }
                let stop = if free > 0.0 { pose_at(free) } else { *pose };
                return Motion {
                    pose: stop,
                    hit: true,
                    clearance: None,
                };
            }
            if advance >= remaining {
                return Motion {
                    pose: end,
                    hit: false,
                    clearance: Some(next_clearance),
                };
            }
            travelled = next;
            clearance = next_clearance;
            centre = next_centre;
        }
    }
}

/// [`Rect::ray_exit_distance`] through the walls marked near (left, right, bottom, top) only:
/// the same expression term for term, with the terms of the other walls left out.
fn ray_exit_distance_near(
    arena: &Rect,
    origin: &Point2<f64>,
    direction: &Vector2<f64>,
    [left, right, bottom, top]: [bool; 4],
) -> f64 {
    let mut t = f64::INFINITY;
    for (axis, low, high) in [(0, left, right), (1, bottom, top)] {
        let d = direction[axis];
        if d > 0.0 {
            if high {
                t = t.min((arena.max[axis] - origin[axis]) / d);
            }
        } else if d < 0.0 && low {
            t = t.min((arena.min[axis] - origin[axis]) / d);
        }
    }
    t.max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn world() -> World {
        World::new(
            1.0,
            1.0,
            vec![
                Obstacle::Circle(Circle::new(Point2::new(0.5, 0.5), 0.1)),
                Obstacle::Rect(Rect::from_centre(Point2::new(0.8, 0.2), 0.1, 0.002)),
            ],
        )
    }

    #[test]
    fn clearance_sees_walls_and_obstacles() {
        let w = world();
        assert!((w.clearance(&Point2::new(0.1, 0.5), 0.05) - 0.05).abs() < 1e-12);
        assert!((w.clearance(&Point2::new(0.3, 0.5), 0.05) - 0.05).abs() < 1e-12);
        assert!(w.clearance(&Point2::new(0.38, 0.5), 0.05) < 0.0);
    }

    #[test]
    fn ray_cast_takes_the_nearest_surface() {
        let w = world();
        let t = w.ray_cast(&Point2::new(0.1, 0.5), &Vector2::x(), 10.0);
        assert!((t - 0.3).abs() < 1e-12);
        let t = w.ray_cast(&Point2::new(0.1, 0.5), &-Vector2::x(), 10.0);
        assert!((t - 0.1).abs() < 1e-12);
        let t = w.ray_cast(&Point2::new(0.1, 0.5), &Vector2::x(), 0.07);
        assert_eq!(t, 0.07);
    }

    #[test]
    fn a_fast_move_does_not_tunnel_through_a_thin_wall() {
        let w = world();
        // A 2 mm thick plate at y = 0.2 spanning x ∈ [0.75, 0.85]; drive up through it fast.
        let start = Isometry2::new(Vector2::new(0.8, 0.1), std::f64::consts::FRAC_PI_2);
        let twist = Twist {
            linear: 2.0,
            angular: 0.0,
        };
        let motion = w.move_disc(&start, twist, 0.1, 0.03);
        assert!(motion.hit);
        let y = motion.pose.translation.vector.y;
        assert!((y - (0.199 - 0.03)).abs() < 1e-9, "{y}");
        assert!(w.clearance(&Point2::from(motion.pose.translation.vector), 0.03) >= 0.0);
    }

    #[test]
    fn free_moves_arrive_where_the_arc_says() {
        let w = world();
        let start = Isometry2::new(Vector2::new(0.2, 0.2), 0.0);
        let twist = Twist {
            linear: 0.1,
            angular: 0.5,
        };
        let motion = w.move_disc(&start, twist, 0.2, 0.037);
        assert!(!motion.hit);
        assert_eq!(motion.pose, integrate_arc(&start, twist, 0.2));
    }

    #[test]
    fn reversing_into_a_wall_is_a_hit() {
        let w = world();
        let start = Isometry2::new(Vector2::new(0.05, 0.7), 0.0);
        let twist = Twist {
            linear: -0.126,
            angular: 0.0,
        };
        let motion = w.move_disc(&start, twist, 0.2, 0.037);
        assert!(motion.hit);
        assert!((motion.pose.translation.vector.x - 0.037).abs() < 1e-9);
    }
}
