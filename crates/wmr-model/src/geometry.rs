//! Flat 2D shapes and the exact queries the robot needs: ray casts and clearances.
//!
//! Everything is analytic: a ray against a circle solves the quadratic, a ray against an
//! axis-aligned rectangle uses the slab method, and the arena's walls are the inside of a
//! rectangle. Distances are in metres, and the rays' directions must be unit vectors.

use nalgebra::{Point2, Vector2};
use serde::{Deserialize, Serialize};

/// A disc: a cylindrical obstacle seen from above.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Circle {
    /// Centre.
    pub centre: Point2<f64>,
    /// Radius (m), positive.
    pub radius: f64,
}

/// An axis-aligned rectangle: a box obstacle seen from above (boxes are not rotated).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rect {
    /// Corner with the smallest coordinates.
    pub min: Point2<f64>,
    /// Corner with the largest coordinates.
    pub max: Point2<f64>,
}

impl Circle {
    /// A circle from its centre and radius.
    #[must_use]
    pub fn new(centre: Point2<f64>, radius: f64) -> Self {
        Self { centre, radius }
    }

    /// Distance from `point` to the disc (0 inside it).
    #[must_use]
    pub fn distance_to(&self, point: &Point2<f64>) -> f64 {
        ((point - self.centre).norm() - self.radius).max(0.0)
    }

    /// Distance along the ray `origin + t·direction` (unit `direction`, `t ≥ 0`) to the first
    /// point of the disc, or `None` when the ray misses it. An origin inside the disc gives 0.
    #[must_use]
    pub fn ray_distance(&self, origin: &Point2<f64>, direction: &Vector2<f64>) -> Option<f64> {
        // |o + t u − c|² = r²  ⇔  t² + 2 t (u·w) + |w|² − r² = 0 with w = o − c.
        let w = origin - self.centre;
        let c = w.norm_squared() - self.radius * self.radius;
        if c <= 0.0 {
            return Some(0.0);
        }
        let b = w.dot(direction);
        if b >= 0.0 {
            return None; // outside and moving away
        }
        let discriminant = b * b - c;
        if discriminant < 0.0 {
            return None;
        }
        // Entry root −b − √disc, written in the cancellation-free form c / (−b + √disc).
        Some(c / (-b + discriminant.sqrt()))
    }
}

impl Rect {
    /// A rectangle from its centre and its full width (x) and height (y).
    #[must_use]
    pub fn from_centre(centre: Point2<f64>, width: f64, height: f64) -> Self {
        let half = Vector2::new(width / 2.0, height / 2.0);
        Self {
            min: centre - half,
            max: centre + half,
        }
    }

    /// Centre of the rectangle.
    #[must_use]
    pub fn centre(&self) -> Point2<f64> {
        nalgebra::center(&self.min, &self.max)
    }

    /// Distance from `point` to the rectangle (0 inside it).
    #[must_use]
    pub fn distance_to(&self, point: &Point2<f64>) -> f64 {
        let dx = (self.min.x - point.x).max(point.x - self.max.x).max(0.0);
        let dy = (self.min.y - point.y).max(point.y - self.max.y).max(0.0);
        (dx * dx + dy * dy).sqrt()
    }

    /// Distance along the ray `origin + t·direction` (`t ≥ 0`) to the first point of the
    /// rectangle, or `None` when the ray misses it. An origin inside gives 0. Slab method;
    /// a ray grazing an edge counts as a hit.
    #[must_use]
    pub fn ray_distance(&self, origin: &Point2<f64>, direction: &Vector2<f64>) -> Option<f64> {
        let mut t_enter = 0.0_f64;
        let mut t_exit = f64::INFINITY;
        for axis in 0..2 {
            let (o, d, lo, hi) = (
                origin[axis],
                direction[axis],
                self.min[axis],
                self.max[axis],
            );
            if d == 0.0 {
                if o < lo || o > hi {
                    return None;
                }
            } else {
                let (t0, t1) = ((lo - o) / d, (hi - o) / d);
                let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
                t_enter = t_enter.max(near);
                t_exit = t_exit.min(far);
                if t_enter > t_exit {
                    return None;
                }
            }
        }
        Some(t_enter)
    }

    /// Distance along a ray from a point *inside* the rectangle to its boundary (the walls of
    /// an arena seen from within). Returns 0 for an origin outside or on the boundary.
    #[must_use]
    pub fn ray_exit_distance(&self, origin: &Point2<f64>, direction: &Vector2<f64>) -> f64 {
        let mut t = f64::INFINITY;
        for axis in 0..2 {
            let d = direction[axis];
            if d > 0.0 {
                t = t.min((self.max[axis] - origin[axis]) / d);
            } else if d < 0.0 {
                t = t.min((self.min[axis] - origin[axis]) / d);
            }
        }
        t.max(0.0)
    }

    /// Distance from a point inside the rectangle to its boundary (negative outside).
    #[must_use]
    pub fn inner_clearance(&self, point: &Point2<f64>) -> f64 {
        (point.x - self.min.x)
            .min(self.max.x - point.x)
            .min(point.y - self.min.y)
            .min(self.max.y - point.y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(x: f64, y: f64) -> Vector2<f64> {
        Vector2::new(x, y).normalize()
    }

    #[test]
    fn ray_hits_circle_head_on_at_near_surface() {
        let circle = Circle::new(Point2::new(3.0, 0.0), 1.0);
        let t = circle.ray_distance(&Point2::origin(), &unit(1.0, 0.0));
        assert_eq!(t, Some(2.0));
    }

    #[test]
    fn ray_hits_circle_off_axis_by_pythagoras() {
        // Centre (3, 0.6), r = 1: the ray along x meets x = 3 − √(1 − 0.36) = 2.2.
        let circle = Circle::new(Point2::new(3.0, 0.6), 1.0);
        let t = circle
            .ray_distance(&Point2::origin(), &unit(1.0, 0.0))
            .expect("hits");
        assert!((t - 2.2).abs() < 1e-12, "{t}");
    }

    #[test]
    fn ray_at_45_degrees_hits_circle() {
        // Centre (2, 2), r = 1 on the diagonal: distance 2√2 − 1.
        let circle = Circle::new(Point2::new(2.0, 2.0), 1.0);
        let t = circle
            .ray_distance(&Point2::origin(), &unit(1.0, 1.0))
            .expect("hits");
        assert!((t - (2.0 * 2.0_f64.sqrt() - 1.0)).abs() < 1e-12, "{t}");
    }

    #[test]
    fn ray_misses_circle_beside_or_behind() {
        let circle = Circle::new(Point2::new(3.0, 1.5), 1.0);
        assert_eq!(
            circle.ray_distance(&Point2::origin(), &unit(1.0, 0.0)),
            None
        );
        let behind = Circle::new(Point2::new(-3.0, 0.0), 1.0);
        assert_eq!(
            behind.ray_distance(&Point2::origin(), &unit(1.0, 0.0)),
            None
        );
    }

    #[test]
    fn ray_from_inside_circle_is_zero() {
        let circle = Circle::new(Point2::new(0.1, 0.0), 1.0);
        assert_eq!(
            circle.ray_distance(&Point2::origin(), &unit(0.0, 1.0)),
            Some(0.0)
        );
    }

    #[test]
    fn ray_hits_rectangle_faces_and_corner() {
        let rect = Rect::from_centre(Point2::new(3.0, 0.0), 2.0, 2.0); // [2,4]×[−1,1]
        assert_eq!(
            rect.ray_distance(&Point2::origin(), &unit(1.0, 0.0)),
            Some(2.0)
        );
        // Diagonal ray from (0, −3) towards (2, −1): hits the corner at distance 2√2.
        let t = rect
            .ray_distance(&Point2::new(0.0, -3.0), &unit(1.0, 1.0))
            .expect("hits corner");
        assert!((t - 2.0 * 2.0_f64.sqrt()).abs() < 1e-12, "{t}");
        // A slanted ray: from (0, 0.5) at slope 0.25 it reaches x = 2 at y = 1.0, on the edge.
        let t = rect
            .ray_distance(&Point2::new(0.0, 0.5), &unit(4.0, 1.0))
            .expect("hits top-left edge");
        assert!((t - 2.0_f64.hypot(0.5)).abs() < 1e-12, "{t}");
        assert_eq!(rect.ray_distance(&Point2::origin(), &unit(0.0, 1.0)), None);
        assert_eq!(
            rect.ray_distance(&Point2::new(0.0, 1.5), &unit(1.0, 0.0)),
            None
        );
    }

    #[test]
    fn ray_exits_arena_at_the_first_wall() {
        let arena = Rect {
            min: Point2::origin(),
            max: Point2::new(1.0, 2.0),
        };
        let t = arena.ray_exit_distance(&Point2::new(0.5, 0.5), &unit(1.0, 1.0));
        assert!((t - 0.5 * 2.0_f64.sqrt()).abs() < 1e-12, "{t}");
        assert_eq!(
            arena.ray_exit_distance(&Point2::new(0.5, 0.5), &unit(0.0, -1.0)),
            0.5
        );
        assert_eq!(arena.inner_clearance(&Point2::new(0.2, 1.0)), 0.2);
    }

    #[test]
    fn point_distances() {
        let rect = Rect::from_centre(Point2::new(0.0, 0.0), 2.0, 2.0);
        assert_eq!(rect.distance_to(&Point2::new(4.0, 5.0)), 5.0);
        assert_eq!(rect.distance_to(&Point2::new(0.5, 0.5)), 0.0);
        let circle = Circle::new(Point2::new(0.0, 0.0), 1.0);
        assert_eq!(circle.distance_to(&Point2::new(3.0, 4.0)), 4.0);
    }
}
