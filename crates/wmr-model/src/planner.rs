//! A breadth-first search over the discrete actions through the exact dynamics: proof that a
//! scenario is solvable, and a reference for the shortest time to the target.
//!
//! Nodes are continuous poses; each expansion applies one action for one control period with
//! the environment's own collision, camera and reach rules. Poses are pruned by a coarse grid
//! over `(x, y, heading)`: the first pose to land in a cell claims it. The grid makes the
//! search finite and fast but means the result is the shortest plan *found*, an upper bound on
//! the true optimum (a finer grid tightens it). `Stop` is never expanded (it cannot shorten a
//! plan). A grid that would exceed [`MAX_GRID_CELLS`] cells (an arena much larger than the
//! default 1 m²) is coarsened: the position cell grows until the grid fits.

use nalgebra::{Isometry2, Point2};
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::action::Action;
use crate::camera::Camera;
use crate::scenario::Scenario;
use crate::state::Discretiser;

/// Search resolution and budget.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlannerParams {
    /// Side of a position cell (m). Default 0.005.
    pub cell: f64,
    /// Number of heading cells over a full turn. Default 72 (5° each).
    pub heading_cells: u32,
    /// Give up after expanding this many nodes. Default 2 000 000.
    pub max_expansions: usize,
}

impl Default for PlannerParams {
    fn default() -> Self {
        Self {
            cell: 0.005,
            heading_cells: 72,
            max_expansions: 2_000_000,
        }
    }
}

/// A plan that reaches the target without a hit and without losing the target.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The actions, one per control period.
    pub actions: Vec<Action>,
    /// The poses: the start, then one after each action.
    pub poses: Vec<Isometry2<f64>>,
    /// Nodes expanded by the search.
    pub expanded: usize,
}

impl Plan {
    /// Time the plan takes (s).
    #[must_use]
    pub fn duration(&self, control_period: f64) -> f64 {
        let steps = self.actions.len() as f64;
        steps * control_period
    }
}

struct Node {
    pose: Isometry2<f64>,
    parent: usize,
    action: Action,
}

/// Largest visited grid [`search`] allocates (one byte per cell).
pub const MAX_GRID_CELLS: usize = 1 << 27;

/// Largest `heading_cells` [`search`] accepts.
pub const MAX_HEADING_CELLS: u32 = 3600;

/// Why [`search`] found no plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum PlanError {
    /// `cell` is not a positive finite length, or `heading_cells` is 0 or above
    /// [`MAX_HEADING_CELLS`].
    #[error("the planner's parameters are unusable (cell > 0, 1 ≤ heading_cells ≤ 3600)")]
    InvalidParams,
    /// Every reachable cell was expanded without reaching the target: no route exists at the
    /// planner's resolution.
    #[error("all {expanded} reachable poses searched")]
    NoRoute {
        /// Nodes expanded.
        expanded: usize,
    },
    /// The expansion budget ran out first.
    #[error("budget of {expanded} expansions used up")]
    BudgetExhausted {
        /// Nodes expanded.
        expanded: usize,
    },
}

/// Searches `scenario` (assumed valid) for the shortest action sequence, breadth first; `None`
/// when [`search`] fails.
#[must_use]
pub fn shortest_plan(scenario: &Scenario, params: &PlannerParams) -> Option<Plan> {
    search(scenario, params).ok()
}

/// Searches `scenario` (assumed valid, in particular with an arena of finite, bounded size)
/// for the shortest action sequence, breadth first.
///
/// # Errors
/// [`PlanError`]: unusable `params`, no route, or the expansion budget used up.
pub fn search(scenario: &Scenario, params: &PlannerParams) -> Result<Plan, PlanError> {
    if !params.cell.is_finite()
        || params.cell <= 0.0
        || params.heading_cells == 0
        || params.heading_cells > MAX_HEADING_CELLS
    {
        return Err(PlanError::InvalidParams);
    }
    let world = scenario.world();
    let camera = Camera::new(scenario.camera);
    let robot = scenario.robot;
    let target = scenario.target_point();
    let dt = scenario.control_period;
    let moves: Vec<(Action, _)> = Action::ALL
        .into_iter()
        .filter(|&a| a != Action::Stop)
        .map(|a| {
            (
                a,
                robot.twist(scenario.actions.wheel_speeds(a, robot.max_wheel_speed)),
            )
        })
        .collect();

    let nh = params.heading_cells as usize;
    let (width, height) = (scenario.arena.width, scenario.arena.height);
    #[expect(
        clippy::cast_precision_loss,
        reason = "MAX_GRID_CELLS / heading cells is far below 2⁵³"
    )]
    let max_position_cells = (MAX_GRID_CELLS / nh) as f64;
    // Coarsen the position cell until (w / cell + 2) · (h / cell + 2) cells fit.
    let mut cell = params.cell;
    while (width / cell + 2.0) * (height / cell + 2.0) > max_position_cells {
        cell *= 1.25;
    }
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "extent / cell is positive and, after coarsening, below MAX_GRID_CELLS"
    )]
    let cells_along = |extent: f64| (extent / cell).ceil() as usize + 1;
    let (nx, ny) = (cells_along(width), cells_along(height));
    let cells = nx * ny * nh;
    let mut visited = vec![false; cells];
    let cell_of = |pose: &Isometry2<f64>| {
        let t = pose.translation.vector;
        let turn = std::f64::consts::TAU;
        let h = pose.rotation.angle().rem_euclid(turn) / turn;
        let (ix, iy, ih) = (
            ((t.x / cell) as usize).min(nx - 1),
            ((t.y / cell) as usize).min(ny - 1),
            ((h * nh as f64) as usize).min(nh - 1),
        );
        (ix * ny + iy) * nh + ih
    };

    let start = scenario.start_pose();
    visited[cell_of(&start)] = true;
    let mut nodes = vec![Node {
        pose: start,
        parent: usize::MAX,
        action: Action::Stop,
    }];
    let mut next = 0;
    while next < nodes.len() && next < params.max_expansions {
        let pose = nodes[next].pose;
        for (action, twist) in &moves {
            let motion = world.move_disc(&pose, *twist, dt, robot.body_radius);
            if motion.hit {
                continue;
            }
            let centre = Point2::from(motion.pose.translation.vector);
            let reached = (target - centre).norm() <= scenario.target.reach_radius;
            if !reached && !camera.sees(&motion.pose, &target) {
                continue;
            }
            let cell = cell_of(&motion.pose);
            if visited[cell] && !reached {
                continue;
            }
            visited[cell] = true;
            nodes.push(Node {
                pose: motion.pose,
                parent: next,
                action: *action,
            });
            if reached {
                return Ok(unwind(&nodes, next + 1));
            }
        }
        next += 1;
    }
    if next < nodes.len() {
        Err(PlanError::BudgetExhausted { expanded: next })
    } else {
        Err(PlanError::NoRoute { expanded: next })
    }
}

fn unwind(nodes: &[Node], expanded: usize) -> Plan {
    let mut actions = Vec::new();
    let mut poses = Vec::new();
    let mut at = nodes.len() - 1;
    while at != 0 {
        actions.push(nodes[at].action);
        poses.push(nodes[at].pose);
        at = nodes[at].parent;
    }
    poses.push(nodes[0].pose);
    actions.reverse();
    poses.reverse();
    Plan {
        actions,
        poses,
        expanded,
    }
}

/// A state → action table that, followed from the start, reaches the target.
#[derive(Debug, Clone, PartialEq)]
pub struct TabularPolicy {
    /// The action of each state the run visits; `None` for states it never visits.
    pub actions: Vec<Option<Action>>,
    /// The run the table produces.
    pub plan: Plan,
}

/// Depth-first search for a *deterministic tabular policy over the discrete state* that
/// reaches the target without a hit and without losing the target, within `max_steps`.
///
/// Where [`shortest_plan`] proves the scenario physically solvable, this proves it solvable by
/// a learner that sees only the state (distance bin, image bin, angle bin): the run may visit
/// a state many times, and must take the same action each time. The search assigns an action
/// the first time the run meets a state and backtracks on failure; `Stop` is never assigned
/// (a deterministic policy that stops, stops forever). `None` when no table was found within
/// `budget` node expansions.
#[must_use]
pub fn tabular_policy(
    scenario: &Scenario,
    max_steps: usize,
    budget: usize,
) -> Option<TabularPolicy> {
    let world = scenario.world();
    let camera = Camera::new(scenario.camera);
    let discretiser = Discretiser::new(scenario.state, &scenario.camera);
    let robot = scenario.robot;
    let target = scenario.target_point();
    let moves = [
        Action::Forward,
        Action::LeftForward,
        Action::RightForward,
        Action::Backward,
    ]
    .map(|a| {
        (
            a,
            robot.twist(scenario.actions.wheel_speeds(a, robot.max_wheel_speed)),
        )
    });
    let state_of = |pose: &Isometry2<f64>| {
        let view = camera.observe(&world, pose, &target);
        let distance = (target - Point2::from(pose.translation.vector)).norm();
        discretiser.index(discretiser.bins(distance, view.target_ratio, view.obstacle.as_ref()))
    };

    let mut policy: Vec<Option<Action>> = vec![None; discretiser.n_states()];
    // The depth-first search keeps its own stack (runs can be long): one frame per pose on the
    // current run, and `trail[i]` is the move into `stack[i + 1]`.
    let start = scenario.start_pose();
    let start_state = state_of(&start);
    let mut stack = vec![Frame {
        pose: start,
        state: start_state,
        fresh: true,
        next: 0,
    }];
    let mut trail: Vec<(Action, Isometry2<f64>)> = Vec::new();
    let mut expanded = 1;
    loop {
        let depth = stack.len().checked_sub(1)?;
        let frame = stack.last_mut()?;
        if frame.next >= moves.len() || depth >= max_steps {
            if frame.fresh {
                policy[frame.state] = None;
            }
            stack.pop();
            trail.pop();
            continue;
        }
        let (action, twist) = moves[frame.next];
        frame.next += 1;
        if frame.fresh {
            policy[frame.state] = Some(action);
        } else if policy[frame.state] != Some(action) {
            continue;
        }
        let pose = frame.pose;
        let motion = world.move_disc(&pose, twist, scenario.control_period, robot.body_radius);
        if motion.hit {
            continue;
        }
        let centre = Point2::from(motion.pose.translation.vector);
        if (target - centre).norm() <= scenario.target.reach_radius {
            trail.push((action, motion.pose));
            let mut poses = vec![start];
            poses.extend(trail.iter().map(|(_, p)| *p));
            return Some(TabularPolicy {
                actions: policy,
                plan: Plan {
                    actions: trail.iter().map(|(a, _)| *a).collect(),
                    poses,
                    expanded,
                },
            });
        }
        if !camera.sees(&motion.pose, &target) || depth + 1 >= max_steps {
            continue;
        }
        if expanded >= budget {
            return None;
        }
        expanded += 1;
        let state = state_of(&motion.pose);
        stack.push(Frame {
            pose: motion.pose,
            state,
            fresh: policy[state].is_none(),
            next: 0,
        });
        trail.push((action, motion.pose));
    }
}

/// One pose on the current run of the tabular search.
struct Frame {
    pose: Isometry2<f64>,
    state: usize,
    /// This frame assigned its state's action (and undoes it when it backtracks).
    fresh: bool,
    /// Index of the next move to try.
    next: usize,
}
