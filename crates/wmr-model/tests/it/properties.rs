//! Laws of the model, checked on random inputs.

use dql::Environment;
use nalgebra::{Isometry2, Point2, Vector2};
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use wmr_model::reward::{RewardInputs, RewardParams};
use wmr_model::sensors::{DistanceSensors, SensorParams, standard_normalish};
use wmr_model::state::uniform_bin;
use wmr_model::world::MAX_SUBSTEP;
use wmr_model::{
    Camera, CameraParams, Circle, DeltaAxis, Discretiser, FixedArc, Obstacle, ObstacleSighting,
    ObstacleSpec, Rect, Scenario, StateParams, Twist, WmrEnv, World, integrate_arc,
    integrate_arc_centre,
};

fn obstacle() -> impl Strategy<Value = Obstacle> {
    prop_oneof![
        (0.0..1.0, 0.0..1.0, 0.001..0.1)
            .prop_map(|(x, y, r)| Obstacle::Circle(Circle::new(Point2::new(x, y), r))),
        // Includes plates as thin as 1 mm, the hardest case for tunnelling.
        (0.0..1.0, 0.0..1.0, 0.001..0.2, 0.001..0.2).prop_map(|(x, y, w, h)| {
            Obstacle::Rect(Rect::from_centre(Point2::new(x, y), w, h))
        }),
    ]
}

fn world() -> impl Strategy<Value = World> {
    prop::collection::vec(obstacle(), 0..6).prop_map(|obstacles| World::new(1.0, 1.0, obstacles))
}

fn centre(pose: &Isometry2<f64>) -> Point2<f64> {
    Point2::from(pose.translation.vector)
}

proptest! {
    /// A fan of rays cast with one broad phase gives each ray's `ray_cast`, bit for bit.
    #[test]
    fn a_ray_fan_is_its_rays_cast_one_by_one(
        world in world(),
        (x, y) in (-0.1..1.1, -0.1..1.1),
        headings in prop::array::uniform8(-4.0..4.0),
        rim in 0.0..0.05,
        range in prop_oneof![0.001..0.2, Just(0.07), 0.5..2.0],
    ) {
        let centre = Point2::new(x, y);
        let directions = headings.map(|h: f64| Vector2::new(h.cos(), h.sin()));
        let fan = world.ray_cast_fan(&centre, rim, &directions, range);
        for (direction, distance) in directions.iter().zip(fan) {
            let one = world.ray_cast(&(centre + direction * rim), direction, range);
            prop_assert_eq!(one.to_bits(), distance.to_bits());
        }
    }

    /// Moving along a precomputed arc from a known clearance is `move_disc`, bit for bit,
    /// and the clearance it reports is the end pose's; chained as the environment chains them.
    #[test]
    fn moves_along_fixed_arcs_are_move_disc(
        world in world(),
        (x, y, heading) in (0.0..1.0, 0.0..1.0, -4.0..4.0),
        radius in 0.01..0.05,
        // `stop` and turns on the spot included: they keep the centre, and the clearance.
        twists in prop::collection::vec(
            (prop_oneof![Just(0.0), -0.2..0.2], prop_oneof![Just(0.0), -6.0..6.0]),
            1..12,
        ),
        duration in 0.01..0.3,
    ) {
        let mut pose = Isometry2::new(Vector2::new(x, y), heading);
        let mut known = None;
        for (linear, angular) in twists {
            let twist = Twist { linear, angular };
            let arc = FixedArc::new(twist, duration);
            prop_assert_eq!(arc.end(&pose), integrate_arc(&pose, twist, duration));
            let reference = world.move_disc(&pose, twist, duration, radius);
            let motion = world.move_disc_along(&pose, &arc, radius, known);
            prop_assert_eq!(motion.pose, reference.pose);
            prop_assert_eq!(motion.hit, reference.hit);
            if let Some(clearance) = motion.clearance {
                let direct = world.clearance(&centre(&motion.pose), radius);
                prop_assert_eq!(clearance.to_bits(), direct.to_bits());
            }
            pose = motion.pose;
            known = motion.clearance;
        }
    }

    /// The body is never left overlapping anything without a hit, and a move reported free
    /// never passed through anything: anywhere along the arc the body penetrates by at most
    /// half a sub-step (tunnelling through an obstacle would need a penetration of the whole
    /// body radius).
    #[test]
    fn moves_never_overlap_silently_or_tunnel(
        world in world(),
        (x, y, heading) in (0.0..1.0, 0.0..1.0, -4.0..4.0),
        radius in 0.01..0.05,
        (linear, angular, duration) in (-2.0..2.0, -20.0..20.0, 0.0..0.5),
    ) {
        let start = Isometry2::new(Vector2::new(x, y), heading);
        if world.clearance(&centre(&start), radius) < 0.0 {
            return Ok(()); // only moves from a free pose are meaningful
        }
        let twist = Twist { linear, angular };
        let motion = world.move_disc(&start, twist, duration, radius);
        prop_assert!(world.clearance(&centre(&motion.pose), radius) >= 0.0);
        if !motion.hit {
            prop_assert_eq!(motion.pose, integrate_arc(&start, twist, duration));
            for k in 0..=500 {
                let t = duration * f64::from(k) / 500.0;
                let clearance = world.clearance(&centre(&integrate_arc(&start, twist, t)), radius);
                prop_assert!(clearance >= -MAX_SUBSTEP / 2.0, "t = {}: {}", t, clearance);
            }
        }
    }

    /// Straight moves (and the e-puck's gentle arcs) graze by at most h² / (8R).
    #[test]
    fn straight_moves_graze_at_most_the_sagitta(
        world in world(),
        (x, y, heading) in (0.0..1.0, 0.0..1.0, -4.0..4.0),
        radius in 0.01..0.05,
        linear in -2.0..2.0,
    ) {
        let start = Isometry2::new(Vector2::new(x, y), heading);
        if world.clearance(&centre(&start), radius) < 0.0 {
            return Ok(());
        }
        let twist = Twist { linear, angular: 0.0 };
        let motion = world.move_disc(&start, twist, 0.2, radius);
        if !motion.hit {
            let bound = MAX_SUBSTEP * MAX_SUBSTEP / (8.0 * radius) + 1e-12;
            for k in 0..=500 {
                let t = 0.2 * f64::from(k) / 500.0;
                let clearance = world.clearance(&centre(&integrate_arc(&start, twist, t)), radius);
                prop_assert!(clearance >= -bound, "t = {}: {}", t, clearance);
            }
        }
    }

    /// In the default scenario, whatever the actions, the robot never overlaps anything, and
    /// everything the environment returns is in range and finite.
    #[test]
    fn the_environment_never_leaves_the_robot_overlapping(
        actions in prop::collection::vec(0usize..5, 1..120),
        seed in any::<u64>(),
    ) {
        let mut env = WmrEnv::default();
        env.reset(Some(seed));
        let radius = env.scenario().robot.body_radius;
        for action in actions {
            let step = env.step(action);
            prop_assert!(env.world().clearance(&centre(env.pose()), radius) >= 0.0);
            prop_assert!(step.next_state < env.n_states());
            prop_assert!(step.reward.is_finite());
            prop_assert!(env.sensor_values().iter().all(|c| (0.0..=1.0).contains(c)));
            if step.done() {
                break;
            }
        }
    }

    /// Bins always land in range, whatever the observation (even NaN and infinities), and
    /// the index encodes them faithfully.
    #[test]
    fn discretisation_lands_in_range(
        (distance_bins, image_bins, angle_bins) in (1u32..30, 1u32..30, 1u32..30),
        target_bins in 0u32..12,
        target_ratio in prop_oneof![-1.0..2.0, Just(f64::NAN), Just(f64::INFINITY)],
        distance_max in 0.01..5.0,
        horizontal_fov in 0.01..3.1,
        vertical in any::<bool>(),
        distance in prop_oneof![-10.0..10.0, Just(f64::NAN), Just(f64::INFINITY)],
        seen in prop::option::of((
            prop_oneof![-2.0..3.0, Just(f64::NAN), Just(f64::NEG_INFINITY)],
            prop_oneof![-4.0..4.0, Just(f64::NAN), Just(f64::INFINITY)],
        )),
    ) {
        let params = StateParams { distance_bins, distance_max, image_bins, angle_bins, target_bins };
        let camera = CameraParams {
            horizontal_fov,
            delta_axis: if vertical { DeltaAxis::Vertical } else { DeltaAxis::Horizontal },
            ..CameraParams::default()
        };
        let discretiser = Discretiser::new(params, &camera);
        let sighting = seen.map(|(delta, angle)| ObstacleSighting {
            index: 0,
            feature: Point2::origin(),
            distance: 0.1,
            delta,
            angle,
        });
        let bins = discretiser.bins(distance, target_ratio, sighting.as_ref());
        prop_assert!(bins.distance < distance_bins);
        prop_assert!(bins.target < target_bins.max(1));
        if let Some((image, angle)) = bins.obstacle {
            prop_assert!(image < image_bins && angle < angle_bins);
        }
        let index = discretiser.index(bins);
        prop_assert!(index < discretiser.n_states());
        prop_assert_eq!(discretiser.bins_of(index), Some(bins));
        let features = discretiser.features(index);
        prop_assert_eq!(features.len(), if target_bins == 0 { 3 } else { 4 });
        prop_assert!(features[0] < distance_bins);
        prop_assert!(features[1] <= image_bins && features[2] <= angle_bins);
    }

    /// The camera's δ is always inside its axis' range and the angle inside the field of view.
    #[test]
    fn camera_readings_stay_in_the_image(
        world in world(),
        (x, y, heading) in (0.05..0.95, 0.05..0.95, -4.0..4.0),
        horizontal_fov in 0.1..3.0,
        vertical in any::<bool>(),
    ) {
        let camera = Camera::new(CameraParams {
            horizontal_fov,
            delta_axis: if vertical { DeltaAxis::Vertical } else { DeltaAxis::Horizontal },
            ..CameraParams::default()
        });
        let pose = Isometry2::new(Vector2::new(x, y), heading);
        if world.clearance(&centre(&pose), 0.037) < 0.0 {
            return Ok(());
        }
        let view = camera.observe(&world, &pose, &Point2::new(0.5, 0.5));
        if let Some(seen) = view.obstacle {
            let (lo, hi) = camera.params().delta_axis.range();
            prop_assert!((lo..=hi).contains(&seen.delta), "{}", seen.delta);
            prop_assert!(seen.angle.abs() <= horizontal_fov / 2.0 + 1e-12);
            prop_assert!(seen.distance >= 0.0 && seen.distance <= camera.params().obstacle_range);
        }
    }
}

proptest! {
    /// `World::clearance` (with its broad phase) is the nearest wall or obstacle minus the
    /// radius, every obstacle taken, bit for bit; `overlaps` is its sign.
    #[test]
    fn clearance_is_the_nearest_surface_of_all(
        world in world(),
        (x, y) in (-0.1..1.1, -0.1..1.1),
        radius in 0.0..0.1,
    ) {
        let point = Point2::new(x, y);
        let clearance = world.clearance(&point, radius);
        let every = every_surface_clearance(&world, &point, radius);
        prop_assert_eq!(clearance.to_bits(), every.to_bits());
        prop_assert_eq!(world.overlaps(&point, radius), every < 0.0);
    }

    /// The same laws where the broad phase decides: points within a hair of an obstacle's
    /// bounding disc grown by the radius (for a disc obstacle, the contact the contact
    /// search closes in on).
    #[test]
    fn overlaps_is_negative_clearance_at_contact(
        world in world(),
        index in any::<prop::sample::Index>(),
        angle in -4.0..4.0,
        radius in 0.01..0.05,
        gap in prop_oneof![-1e-9..1e-9, Just(0.0), -1e-3..1e-3],
    ) {
        let Some(obstacle) = world.obstacles().get(index.index(world.obstacles().len().max(1)))
        else {
            return Ok(());
        };
        let centre = obstacle.centre();
        let reach = match obstacle {
            Obstacle::Circle(c) => c.radius,
            Obstacle::Rect(r) => (r.max - r.min).norm() / 2.0,
        };
        let angle: f64 = angle;
        let point = centre + Vector2::new(angle.cos(), angle.sin()) * (reach + radius + gap);
        let every = every_surface_clearance(&world, &point, radius);
        prop_assert_eq!(world.clearance(&point, radius).to_bits(), every.to_bits());
        prop_assert_eq!(world.overlaps(&point, radius), every < 0.0);
    }

    /// `integrate_arc_centre` is the translation of `integrate_arc`, bit for bit.
    #[test]
    fn arc_centres_are_the_arcs_translations(
        (x, y, heading) in (-2.0..2.0, -2.0..2.0, -4.0..4.0),
        (linear, angular) in (-0.5..0.5, prop_oneof![Just(0.0), -8.0..8.0]),
        duration in 0.0..0.5,
    ) {
        let pose = Isometry2::new(Vector2::new(x, y), heading);
        let twist = Twist { linear, angular };
        let full = integrate_arc(&pose, twist, duration);
        let centre_only = integrate_arc_centre(&pose, twist, duration);
        prop_assert_eq!(centre_only.x.to_bits(), full.translation.vector.x.to_bits());
        prop_assert_eq!(centre_only.y.to_bits(), full.translation.vector.y.to_bits());
    }

    /// `move_disc` is conservative advancement written plainly (full poses, the clearance of
    /// every surface, contact bisection on the clearance's sign), bit for bit.
    #[test]
    fn moves_are_plain_conservative_advancement(
        world in world(),
        (x, y, heading) in (0.0..1.0, 0.0..1.0, -4.0..4.0),
        radius in 0.01..0.05,
        (linear, angular, duration) in (-1.0..1.0, prop_oneof![Just(0.0), -10.0..10.0], 0.0..0.4),
    ) {
        let pose = Isometry2::new(Vector2::new(x, y), heading);
        let twist = Twist { linear, angular };
        let motion = world.move_disc(&pose, twist, duration, radius);
        let (plain_pose, plain_hit) = plain_move(&world, &pose, twist, duration, radius);
        prop_assert_eq!(motion.pose, plain_pose);
        prop_assert_eq!(motion.hit, plain_hit);
    }

    /// The camera with its broad phase sees what it sees taking every obstacle in turn,
    /// written plainly, bit for bit.
    #[test]
    fn the_camera_sees_what_every_obstacle_in_turn_shows(
        world in world(),
        (x, y, heading) in (0.0..1.0, 0.0..1.0, -4.0..4.0),
        horizontal_fov in 0.1..3.0,
        obstacle_range in prop_oneof![0.01..0.3, Just(0.5), 0.5..2.0],
        vertical in any::<bool>(),
    ) {
        let params = CameraParams {
            horizontal_fov,
            obstacle_range,
            delta_axis: if vertical { DeltaAxis::Vertical } else { DeltaAxis::Horizontal },
            ..CameraParams::default()
        };
        let camera = Camera::new(params);
        let pose = Isometry2::new(Vector2::new(x, y), heading);
        let view = camera.observe(&world, &pose, &Point2::new(0.5, 0.5));
        let plain = plain_sighting(&world, &params, &pose);
        // `{:?}` prints every float's shortest round trip: equal text is equal bits.
        prop_assert_eq!(format!("{:?}", view.obstacle), format!("{plain:?}"));
    }

    /// The sensor noise's integer sum is the sum of its four uniforms, bit for bit.
    #[test]
    fn noise_is_the_sum_of_four_uniforms(seed in any::<u64>()) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut same = rng.clone();
        for _ in 0..8 {
            let draw = standard_normalish(&mut rng);
            let bits = same.next_u64();
            let mut sum = 0.0;
            for k in 0..4 {
                let chunk = ((bits >> (16 * k)) & 0xFFFF) as f64;
                sum += (chunk + 0.5) / 65_536.0;
            }
            prop_assert_eq!(draw.to_bits(), ((sum - 2.0) * 3.0_f64.sqrt()).to_bits());
        }
    }

    /// `add_noise` (draws first, then the arithmetic) adds `C_noise · ξ` value by value,
    /// each ξ a `standard_normalish` draw in sensor order, and clamps, bit for bit.
    #[test]
    fn noise_is_added_draw_by_draw(
        sensor_values in prop::array::uniform8(0.0..=1.0),
        noise in prop_oneof![Just(0.02), 0.0..1.0],
        seed in any::<u64>(),
        skip in 0usize..3,
    ) {
        let sensors = DistanceSensors::new(SensorParams { noise, ..SensorParams::default() });
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        for _ in 0..skip {
            rng.next_u32();
        }
        let mut same = rng.clone();
        let mut noisy = sensor_values;
        sensors.add_noise(&mut noisy, &mut rng);
        for (value, noisy) in sensor_values.iter().zip(noisy) {
            let plain = if noise == 0.0 {
                *value
            } else {
                (value + noise * standard_normalish(&mut same)).clamp(0.0, 1.0)
            };
            prop_assert_eq!(noisy.to_bits(), plain.to_bits());
        }
        prop_assert_eq!(rng.next_u64(), same.next_u64());
    }

    /// `uniform_bin` is the floor of the scaled value, clamped to the end bins.
    #[test]
    fn uniform_bins_are_floors(
        x in prop_oneof![-1.0..2.0, Just(f64::NAN), Just(f64::INFINITY)],
        (lo, width) in (-1.0..1.0, 0.001..2.0),
        bins in 1u32..40,
    ) {
        let (x, lo, width): (f64, f64, f64) = (x, lo, width);
        let fraction = (x - lo) / width;
        let floor = if fraction.is_nan() || fraction <= 0.0 {
            0
        } else {
            (fraction * f64::from(bins)).floor().min(f64::from(bins - 1)) as u32
        };
        prop_assert_eq!(uniform_bin(x, lo, lo + width, bins), floor);
    }
}

/// The nearest wall or obstacle minus `radius`, every surface taken in turn.
fn every_surface_clearance(world: &World, point: &Point2<f64>, radius: f64) -> f64 {
    let mut nearest = world.arena().inner_clearance(point);
    for obstacle in world.obstacles() {
        nearest = nearest.min(obstacle.distance_to(point));
    }
    nearest - radius
}

/// `World::move_disc` without its shortcuts: full poses everywhere, every surface's
/// clearance, bisection on the clearance's sign.
fn plain_move(
    world: &World,
    pose: &Isometry2<f64>,
    twist: Twist,
    duration: f64,
    radius: f64,
) -> (Isometry2<f64>, bool) {
    let clearance_at = |p: &Isometry2<f64>| every_surface_clearance(world, &centre(p), radius);
    let start_clearance = clearance_at(pose);
    if start_clearance < 0.0 {
        return (*pose, true);
    }
    let length = (twist.linear * duration).abs();
    let end = integrate_arc(pose, twist, duration);
    if length <= start_clearance && clearance_at(&end) >= 0.0 {
        return (end, false);
    }
    let pose_at = |s: f64| integrate_arc(pose, twist, duration * (s / length));
    let (mut travelled, mut clearance) = (0.0, start_clearance);
    loop {
        let remaining = length - travelled;
        let advance = clearance.max(MAX_SUBSTEP).min(remaining);
        let next = travelled + advance;
        let next_pose = if advance >= remaining {
            end
        } else {
            pose_at(next)
        };
        let next_clearance = clearance_at(&next_pose);
        if next_clearance < 0.0 {
            let (mut free, mut blocked) = (travelled, next);
            for _ in 0..40 {
                let mid = 0.5 * (free + blocked);
                if clearance_at(&pose_at(mid)) < 0.0 {
                    blocked = mid;
                } else {
                    free = mid;
                }
            }
            return (if free > 0.0 { pose_at(free) } else { *pose }, true);
        }
        if advance >= remaining {
            return (end, false);
        }
        travelled = next;
        clearance = next_clearance;
    }
}

/// `Camera::observe`'s obstacle, every obstacle taken in turn, each unit direction divided
/// out as it is met.
fn plain_sighting(
    world: &World,
    params: &CameraParams,
    pose: &Isometry2<f64>,
) -> Option<ObstacleSighting> {
    let tan_half_horizontal = (params.horizontal_fov / 2.0).tan();
    let tan_half_vertical = (params.vertical_fov / 2.0).tan();
    let in_view =
        |local: &Vector2<f64>| local.x > 0.0 && local.y.abs() <= local.x * tan_half_horizontal;
    let camera = pose * Point2::new(params.offset, 0.0);
    let to_local = pose.rotation.inverse();
    let mut best: Option<(usize, f64, Vector2<f64>)> = None;
    for (index, obstacle) in world.obstacles().iter().enumerate() {
        let to_centre = obstacle.centre() - camera;
        let local = to_local * to_centre;
        if !in_view(&local) {
            continue;
        }
        let norm = to_centre.norm();
        let direction = to_centre / norm;
        let distance = match obstacle {
            Obstacle::Circle(c) => (norm - c.radius).max(0.0),
            Obstacle::Rect(r) => r.ray_distance(&camera, &direction).unwrap_or(0.0),
        };
        if distance <= params.obstacle_range
            && best.is_none_or(|(_, nearest, _)| distance < nearest)
        {
            best = Some((index, distance, local / norm));
        }
    }
    best.map(|(index, distance, local_direction)| {
        let in_robot = Vector2::new(params.offset, 0.0) + local_direction * distance;
        let delta = match params.delta_axis {
            DeltaAxis::Vertical => {
                let scaled = distance * tan_half_vertical;
                if params.height >= scaled {
                    1.0
                } else {
                    0.5 * (params.height / scaled + 1.0)
                }
            }
            DeltaAxis::Horizontal => {
                let tan_beta = -local_direction.y / local_direction.x;
                (0.5 * (tan_beta / tan_half_horizontal + 1.0)).clamp(0.0, 1.0)
            }
        };
        ObstacleSighting {
            index,
            feature: pose * Point2::from(in_robot),
            distance,
            delta,
            angle: in_robot.y.atan2(in_robot.x),
        }
    })
}

/// A random scenario built round the default one: random arena, start, target and obstacles,
/// the start heading pointed at the target so that most draws are valid.
fn scenario() -> impl Strategy<Value = Scenario> {
    (
        (0.5..3.0, 0.5..3.0),
        (0.0..1.0, 0.0..1.0, 0.0..1.0, 0.0..1.0, -0.5..0.5),
        prop::collection::vec(
            (0.0..1.0, 0.0..1.0, 0.005..0.2, 0.005..0.2, any::<bool>()),
            0..6,
        ),
        (0.1..3.0, 0.1..3.0, 0.0..0.2, -5.0..5.0, 0.1..9.0),
        (1u32..20, 1u32..20, 1u32..20),
    )
        .prop_map(
            |((w, h), (sx, sy, tx, ty, turn), obstacles, (hfov, vfov, noise, k, p), bins)| {
                let mut s = Scenario::default_scenario();
                s.name = format!("random {w:.3}x{h:.3}");
                s.arena.width = w;
                s.arena.height = h;
                s.start.x = 0.05 + sx * (w - 0.1);
                s.start.y = 0.05 + sy * (h - 0.1);
                s.target.x = 0.05 + tx * (w - 0.1);
                s.target.y = 0.05 + ty * (h - 0.1);
                s.start.heading = (s.target.y - s.start.y).atan2(s.target.x - s.start.x) + turn;
                s.obstacles = obstacles
                    .into_iter()
                    .map(|(x, y, a, b, round)| {
                        let (x, y) = (x * w, y * h);
                        if round {
                            ObstacleSpec::Circle {
                                x,
                                y,
                                radius: a / 2.0,
                            }
                        } else {
                            ObstacleSpec::Rectangle {
                                x,
                                y,
                                width: a,
                                height: b,
                            }
                        }
                    })
                    .collect();
                s.camera.horizontal_fov = hfov;
                s.camera.vertical_fov = vfov;
                s.sensors.noise = noise;
                s.reward.k = k;
                s.reward.p = p;
                (
                    s.state.distance_bins,
                    s.state.image_bins,
                    s.state.angle_bins,
                ) = bins;
                s
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Every scenario survives a TOML round trip exactly; valid ones stay valid.
    #[test]
    fn scenarios_survive_a_toml_round_trip(scenario in scenario()) {
        let text = scenario.to_toml_string().unwrap();
        let back: Scenario = toml::from_str(&text).unwrap();
        prop_assert_eq!(&back, &scenario);
        if scenario.validate().is_ok() {
            prop_assert_eq!(Scenario::from_toml_str(&text).unwrap(), scenario);
        }
    }

    /// Valid random scenarios give environments whose first steps are well formed.
    #[test]
    fn valid_scenarios_make_working_environments(scenario in scenario(), action in 0usize..5) {
        if scenario.validate().is_err() {
            return Ok(());
        }
        let mut env = WmrEnv::new(scenario).unwrap();
        let step = env.step(action);
        prop_assert!(step.next_state < env.n_states());
        prop_assert!(step.reward.is_finite());
    }
}

/// Everything an environment shows after a step, as text: `{:?}` prints every float's
/// shortest round trip, so equal text is equal bits.
fn everything_shown(env: &WmrEnv, step: &dql::Step) -> String {
    format!(
        "{step:?} {:?} {:?} {:?} {:?} {:?} {:?} {}",
        env.pose(),
        env.sensor_values(),
        env.camera_view(),
        env.subtask_rewards(),
        env.metrics(),
        env.path().last(),
        env.state(),
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// A step recalled from the step memo, or sensed from a pose already sensed, is the step
    /// computed afresh, bit for bit: an environment that played the earlier episodes (its
    /// memo filled by them) and a new environment for each episode, both reset with the
    /// episode's seed, show the same after every step. Episodes replay prefixes of the first
    /// one's actions, so that poses repeat.
    #[test]
    fn remembered_steps_are_the_steps_computed_afresh(
        scenario in scenario(),
        first in prop::collection::vec(0usize..5, 1..40),
        episodes in prop::collection::vec(
            (any::<prop::sample::Index>(), prop::collection::vec(0usize..5, 0..20), any::<u64>()),
            1..6,
        ),
    ) {
        prop_assume!(scenario.validate().is_ok());
        let mut seasoned = WmrEnv::new(scenario.clone()).unwrap();
        for (prefix, tail, seed) in episodes {
            let mut actions = first[..prefix.index(first.len() + 1)].to_vec();
            actions.extend(tail);
            let mut fresh = WmrEnv::new(scenario.clone()).unwrap();
            prop_assert_eq!(seasoned.reset(Some(seed)), fresh.reset(Some(seed)));
            prop_assert_eq!(format!("{:?}", seasoned.sensor_values()), format!("{:?}", fresh.sensor_values()));
            for action in actions {
                let (a, b) = (seasoned.step(action), fresh.step(action));
                prop_assert_eq!(everything_shown(&seasoned, &a), everything_shown(&fresh, &b));
                if a.done() {
                    break;
                }
            }
        }
    }

    /// Without noise, what the robot senses after every step (remembered or not) is what
    /// `observe` measures from its pose: the sensor values are the proximities, the view is the
    /// view, bit for bit.
    #[test]
    fn what_the_robot_senses_is_what_it_observes_from_its_pose(
        scenario in scenario(),
        actions in prop::collection::vec(0usize..5, 1..80),
    ) {
        let mut scenario = scenario;
        scenario.sensors.noise = 0.0;
        prop_assume!(scenario.validate().is_ok());
        let mut env = WmrEnv::new(scenario).unwrap();
        for action in actions {
            if env.step(action).done() {
                env.reset(None);
            }
            let seen = env.observe(env.pose());
            prop_assert_eq!(format!("{:?}", env.sensor_values()), format!("{:?}", seen.proximities));
            prop_assert_eq!(format!("{:?}", env.camera_view()), format!("{:?}", seen.view));
        }
    }

    /// The sub-task rewards share Eq. 6 and 7's sensor term, taken once: they are `reach`
    /// and `avoid`, bit for bit.
    #[test]
    fn subtask_rewards_are_eq_6_and_7(
        sensor_values in prop::array::uniform8(0.0..=1.0),
        (k, p, f) in (0.0..5.0, 0.1..9.0, 0.0..1.0),
        (target_distance, rad) in (0.0..3.0, 0.0..3.2),
        (hit, lost, reached) in (any::<bool>(), any::<bool>(), any::<bool>()),
    ) {
        let reward = RewardParams { k, p, f, ..RewardParams::default() };
        let inputs = RewardInputs {
            target_distance,
            sensor_values: &sensor_values,
            noise: 0.02,
            rad,
            hit,
            lost,
            reached,
        };
        let [reach, avoid, _] = reward.subtasks(&inputs);
        prop_assert_eq!(reach.to_bits(), reward.reach(&inputs).to_bits());
        prop_assert_eq!(avoid.to_bits(), reward.avoid(&inputs).to_bits());
    }

    /// A proximity is `1 − distance / range`, clamped, bit for bit (a ray that met nothing
    /// reads 0 without the division).
    #[test]
    fn proximities_are_one_minus_relative_distances(
        world in world(),
        (x, y, heading) in (0.0..1.0, 0.0..1.0, -4.0..4.0),
        range in prop_oneof![Just(0.07), 0.001..2.0],
    ) {
        let sensors = DistanceSensors::new(SensorParams { range, ..SensorParams::default() });
        let pose = Isometry2::new(Vector2::new(x, y), heading);
        let distances = sensors.distances(&world, &pose, 0.037);
        let proximities = sensors.proximities(&world, &pose, 0.037);
        for (distance, proximity) in distances.iter().zip(proximities) {
            let plain = (1.0 - distance / range).clamp(0.0, 1.0);
            prop_assert_eq!(proximity.to_bits(), plain.to_bits());
        }
    }
}

/// How a field may go wrong.
#[derive(Debug, Clone, Copy)]
enum Rule {
    /// Any finite number is fine.
    Finite,
    /// Must be positive and finite.
    Positive,
    /// Must lie in (0, π).
    Angle,
}

type Setter = fn(&mut Scenario, f64);

/// Fields with their rules, and how to set them.
const FIELDS: &[(&str, Rule, Setter)] = &[
    ("control_period", Rule::Positive, |s, v| {
        s.control_period = v;
    }),
    ("arena.width", Rule::Positive, |s, v| s.arena.width = v),
    ("arena.height", Rule::Positive, |s, v| s.arena.height = v),
    ("start.x", Rule::Finite, |s, v| s.start.x = v),
    ("start.heading", Rule::Finite, |s, v| s.start.heading = v),
    ("target.y", Rule::Finite, |s, v| s.target.y = v),
    ("target.reach_radius", Rule::Positive, |s, v| {
        s.target.reach_radius = v;
    }),
    ("obstacles[0].radius", Rule::Positive, |s, v| {
        if let ObstacleSpec::Circle { radius, .. } = &mut s.obstacles[0] {
            *radius = v;
        }
    }),
    ("obstacles[1].width", Rule::Positive, |s, v| {
        if let ObstacleSpec::Rectangle { width, .. } = &mut s.obstacles[1] {
            *width = v;
        }
    }),
    ("obstacles[2].y", Rule::Finite, |s, v| {
        if let ObstacleSpec::Rectangle { y, .. } = &mut s.obstacles[2] {
            *y = v;
        }
    }),
    ("robot.wheel_radius", Rule::Positive, |s, v| {
        s.robot.wheel_radius = v;
    }),
    ("robot.axle_length", Rule::Positive, |s, v| {
        s.robot.axle_length = v;
    }),
    ("robot.body_radius", Rule::Positive, |s, v| {
        s.robot.body_radius = v;
    }),
    ("robot.max_wheel_speed", Rule::Positive, |s, v| {
        s.robot.max_wheel_speed = v;
    }),
    ("sensors.range", Rule::Positive, |s, v| s.sensors.range = v),
    ("sensors.headings[3]", Rule::Finite, |s, v| {
        s.sensors.headings[3] = v;
    }),
    ("camera.horizontal_fov", Rule::Angle, |s, v| {
        s.camera.horizontal_fov = v;
    }),
    ("camera.vertical_fov", Rule::Angle, |s, v| {
        s.camera.vertical_fov = v;
    }),
    ("camera.height", Rule::Positive, |s, v| s.camera.height = v),
    ("camera.obstacle_range", Rule::Positive, |s, v| {
        s.camera.obstacle_range = v;
    }),
    ("state.distance_max", Rule::Positive, |s, v| {
        s.state.distance_max = v;
    }),
    ("reward.k", Rule::Finite, |s, v| s.reward.k = v),
    ("reward.p", Rule::Positive, |s, v| s.reward.p = v),
    ("reward.f", Rule::Finite, |s, v| s.reward.f = v),
    ("reward.goal_bonus", Rule::Finite, |s, v| {
        s.reward.goal_bonus = v;
    }),
    ("actions.left_forward.right", Rule::Finite, |s, v| {
        s.actions.left_forward.right = v;
    }),
    ("metrics.retention_progress", Rule::Finite, |s, v| {
        s.metrics.retention_progress = v;
    }),
];

fn bad_value(rule: Rule) -> BoxedStrategy<f64> {
    let non_finite = prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(f64::NEG_INFINITY)];
    match rule {
        Rule::Finite => non_finite.boxed(),
        Rule::Positive => prop_oneof![non_finite, Just(0.0), -10.0..0.0].boxed(),
        Rule::Angle => prop_oneof![non_finite, -1.0..=0.0, std::f64::consts::PI..10.0].boxed(),
    }
}

proptest! {
    /// Each bad value of each field is rejected with an error that names the field.
    #[test]
    fn invalid_scenarios_are_rejected_naming_the_field(
        (field, value) in (0..FIELDS.len()).prop_flat_map(|i| (Just(i), bad_value(FIELDS[i].1))),
    ) {
        let (name, _, set) = FIELDS[field];
        let mut scenario = Scenario::default_scenario();
        set(&mut scenario, value);
        let error = scenario.validate().expect_err("must be rejected");
        let message = error.to_string();
        prop_assert!(message.contains(name), "{}: {}", name, message);
        prop_assert!(WmrEnv::new(scenario).is_err());
    }
}
