//! The eight ray-cast distance sensors and their sensor model.
//!
//! Sensor `i` sits on the rim of the body at heading `θ_i` (robot frame, 0 = forward,
//! counter-clockwise positive) and looks outward along that heading. Its ray is cast against
//! walls and obstacles up to `range`; the noise-free value is the *proximity*
//! `1 − distance / range`: 0 when nothing is within range, 1 at contact. The noisy value adds
//! `C_noise · ξ` with ξ an approximately standard normal draw (see [`standard_normalish`]) and
//! clamps to `[0, 1]`, so an idle sensor reads a small positive noise floor, like a real IR
//! sensor. These values are the `C_n` of Eq. 6 and 7.

use nalgebra::{Isometry2, Point2, Vector2};
use rand::Rng;
use serde::{Deserialize, Serialize};

use crate::world::World;

/// Number of distance sensors (Table 2).
pub const SENSOR_COUNT: usize = 8;

/// The e-puck's sensor headings in degrees, numbered clockwise from the front right (ps0…ps7).
pub const EPUCK_SENSOR_HEADINGS_DEG: [f64; SENSOR_COUNT] =
    [-17.0, -46.0, -90.0, -151.5, 151.5, 90.0, 46.0, 17.0];

/// Sensor layout and sensor model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SensorParams {
    /// Headings of the eight sensors (rad, robot frame). Default: the e-puck's.
    pub headings: [f64; SENSOR_COUNT],
    /// Range of each sensor, measured from the body's rim (m). e-puck: about 0.07.
    pub range: f64,
    /// `C_noise`: standard deviation of the additive sensor noise (proximity units), also the
    /// constant of Eq. 6 and 7. Default 0.02, 2 % of full scale.
    pub noise: f64,
}

impl Default for SensorParams {
    fn default() -> Self {
        Self {
            headings: EPUCK_SENSOR_HEADINGS_DEG.map(f64::to_radians),
            range: 0.07,
            noise: 0.02,
        }
    }
}

/// The sensor ring with its ray directions precomputed.
#[derive(Debug, Clone, PartialEq)]
pub struct DistanceSensors {
    params: SensorParams,
    directions: [Vector2<f64>; SENSOR_COUNT],
}

impl DistanceSensors {
    /// Sensors laid out by `params`.
    #[must_use]
    pub fn new(params: SensorParams) -> Self {
        Self {
            params,
            directions: params.headings.map(|h| Vector2::new(h.cos(), h.sin())),
        }
    }

    /// The layout and sensor model.
    #[must_use]
    pub fn params(&self) -> &SensorParams {
        &self.params
    }

    /// Distances (m) each sensor's ray travels from the rim before meeting a wall or an
    /// obstacle, capped at the range. `body_radius` places the sensors on the rim.
    #[must_use]
    pub fn distances(
        &self,
        world: &World,
        pose: &Isometry2<f64>,
        body_radius: f64,
    ) -> [f64; SENSOR_COUNT] {
        let centre = Point2::from(pose.translation.vector);
        // Loops rather than `array::map` here and below: its machinery costs more than the
        // arithmetic on the hot path.
        let mut directions = self.directions;
        for direction in &mut directions {
            *direction = pose.rotation * *direction;
        }
        world.ray_cast_fan(&centre, body_radius, &directions, self.params.range)
    }

    /// Noise-free proximity values `1 − distance / range`, each in `[0, 1]`.
    #[must_use]
    pub fn proximities(
        &self,
        world: &World,
        pose: &Isometry2<f64>,
        body_radius: f64,
    ) -> [f64; SENSOR_COUNT] {
        let range = self.params.range;
        let mut proximities = self.distances(world, pose, body_radius);
        for proximity in &mut proximities {
            // A ray that met nothing reads `range / range = 1` exactly (for a finite, non-zero
            // range), so its proximity is 0 without the division.
            *proximity = if *proximity == range {
                0.0
            } else {
                (1.0 - *proximity / range).clamp(0.0, 1.0)
            };
        }
        proximities
    }

    /// Adds `C_noise · ξ` to each value and clamps to `[0, 1]`.
    pub fn add_noise<R: Rng + ?Sized>(&self, sensor_values: &mut [f64; SENSOR_COUNT], rng: &mut R) {
        if self.params.noise == 0.0 {
            return;
        }
        // The draws first, in order, then the arithmetic over them: a loop without calls,
        // which the compiler can run two values at a time. Same draws, same operations.
        let mut draws = [0; SENSOR_COUNT];
        for draw in &mut draws {
            *draw = rng.next_u64();
        }
        for (value, bits) in sensor_values.iter_mut().zip(draws) {
            *value = (*value + self.params.noise * normalish_from_bits(bits)).clamp(0.0, 1.0);
        }
    }
}

/// An approximately standard normal draw from one `u64`: the Irwin–Hall sum of four 16-bit
/// uniforms, centred and scaled to unit variance. Bounded by `±2√3 ≈ ±3.46`, symmetric, and
/// cheap (no logarithm or trigonometry), which is all a sensor noise model needs.
pub fn standard_normalish<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    normalish_from_bits(rng.next_u64())
}

/// [`standard_normalish`] of the draw `bits`.
fn normalish_from_bits(bits: u64) -> f64 {
    // Each uniform is (chunk + ½) / 2¹⁶ ∈ (0, 1), mean ½, variance ≈ 1/12. Their sum,
    // centred, is (Σ chunk + 4 · ½ − 2 · 2¹⁶) / 2¹⁶; every term and partial sum of it is a
    // multiple of 2⁻¹⁷ below 4, exact in f64, so it is computed in integers: the four
    // 16-bit chunks added pairwise in two 32-bit lanes, then the lanes.
    const LOW_CHUNKS: u64 = 0x0000_FFFF_0000_FFFF;
    let pairs = (bits & LOW_CHUNKS) + ((bits >> 16) & LOW_CHUNKS);
    let chunks = (pairs & 0xFFFF_FFFF) + (pairs >> 32);
    // chunks < 2¹⁸: fits a `u32` (whose conversion is one instruction, a `u64`'s several)
    // and is exact in f64
    #[expect(clippy::cast_possible_truncation, reason = "below 2¹⁸")]
    let chunks = chunks as u32;
    let centred = (f64::from(chunks) - 131_070.0) / 65_536.0;
    centred * 3.0_f64.sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::Obstacle;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn front_sensor_sees_a_wall_at_the_hand_computed_distance() {
        // Robot at x = 0.9 facing +x in a 1 m arena: the ±17° sensors sit on the rim at
        // x = 0.9 + R cos 17° and their rays reach x = 1 after (0.1 − R cos 17°) / cos 17°.
        let world = World::new(1.0, 1.0, Vec::new());
        let sensors = DistanceSensors::new(SensorParams {
            range: 1.0,
            ..SensorParams::default()
        });
        let pose = Isometry2::new(Vector2::new(0.9, 0.5), 0.0);
        let d = sensors.distances(&world, &pose, 0.037);
        let c = 17.0_f64.to_radians().cos();
        let expected = (0.1 - 0.037 * c) / c;
        assert!((d[0] - expected).abs() < 1e-12, "{}", d[0]);
        assert!((d[7] - expected).abs() < 1e-12, "{}", d[7]);
        // The ±90° sensors look at y = 0 and y = 1 from y = 0.5 ∓ R.
        assert!((d[2] - (0.5 - 0.037)).abs() < 1e-12);
        assert!((d[5] - (0.5 - 0.037)).abs() < 1e-12);
    }

    #[test]
    fn proximity_is_one_minus_relative_distance() {
        // A cylinder of radius 0.01 straight to the right of the robot, 0.05 from the rim.
        let world = World::new(
            1.0,
            1.0,
            vec![Obstacle::Circle(crate::geometry::Circle::new(
                Point2::new(0.5, 0.5 - 0.037 - 0.05 - 0.01),
                0.01,
            ))],
        );
        let sensors = DistanceSensors::new(SensorParams::default());
        let pose = Isometry2::new(Vector2::new(0.5, 0.5), 0.0);
        let p = sensors.proximities(&world, &pose, 0.037);
        assert!((p[2] - (1.0 - 0.05 / 0.07)).abs() < 1e-12, "{}", p[2]);
        for (i, value) in p.iter().enumerate() {
            if i != 2 {
                assert_eq!(*value, 0.0, "sensor {i}");
            }
        }
    }

    #[test]
    fn normalish_draws_have_unit_variance_and_zero_mean() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let n = 200_000;
        let draws: Vec<f64> = (0..n).map(|_| standard_normalish(&mut rng)).collect();
        let nf = n as f64;
        let mean = draws.iter().sum::<f64>() / nf;
        let var = draws.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / nf;
        assert!(mean.abs() < 0.01, "{mean}");
        assert!((var - 1.0).abs() < 0.02, "{var}");
        assert!(draws.iter().all(|x| x.abs() <= 2.0 * 3.0_f64.sqrt()));
    }
}
