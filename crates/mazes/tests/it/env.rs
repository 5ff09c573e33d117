//! The maze environment: dynamics, rewards, termination, truncation, the dql contract.

use crate::common;

use dql::{DqlError, Environment};
use mazes::{
    Action, Event, Maze, MazeEnv, Pos, Preset, RewardScheme, SpecError, Subtask, TaskSpec,
};
use proptest::prelude::*;

/// Independent reference dynamics: signed arithmetic and floating-point Euclidean
/// distances, not the crate's integer tables.
fn reference_transition(maze: &Maze, from: Pos, action: usize) -> (Pos, Event) {
    let (dx, dy): (i64, i64) = [(0, -1), (0, 1), (-1, 0), (1, 0)][action];
    let (x, y) = (from.x as i64 + dx, from.y as i64 + dy);
    let inside = x >= 0 && y >= 0 && x < maze.width() as i64 && y < maze.height() as i64;
    let next = Pos::new(x.max(0) as usize, y.max(0) as usize);
    if !inside || maze.is_obstacle(next) {
        return (from, Event::Bump);
    }
    if next == maze.target() {
        return (next, Event::Target);
    }
    let distance = |p: Pos| {
        let (dx, dy) = (
            p.x as f64 - maze.target().x as f64,
            p.y as f64 - maze.target().y as f64,
        );
        dx.hypot(dy)
    };
    let event = if distance(next) < distance(from) {
        Event::Closer
    } else {
        Event::Farther
    };
    (next, event)
}

fn scheme() -> impl Strategy<Value = RewardScheme> {
    (-1e3..1e3f64, -1e3..1e3f64, -1e3..1e3f64, -1e3..1e3f64).prop_map(
        |(closer, farther, bump, target)| RewardScheme {
            closer,
            farther,
            bump,
            target,
        },
    )
}

fn spec_with(reward: RewardScheme, subtasks: Vec<RewardScheme>, step_cap: u32) -> TaskSpec {
    TaskSpec {
        reward,
        subtasks: subtasks
            .into_iter()
            .enumerate()
            .map(|(i, reward)| Subtask {
                name: format!("sub-task {i}"),
                reward,
            })
            .collect(),
        step_cap,
    }
}

proptest! {
    /// A bump never moves the agent, and a move that does not move the agent is a bump.
    #[test]
    fn a_bump_never_moves_the_agent(
        maze in common::small_maze(8),
        actions in prop::collection::vec(0usize..4, 1..200),
    ) {
        let mut env = MazeEnv::new(maze.clone(), TaskSpec::task1()).unwrap();
        env.reset(None);
        for action in actions {
            let before = env.position();
            let step = env.step(action);
            let bumped = env.last_event() == Some(Event::Bump);
            prop_assert_eq!(bumped, env.position() == before);
            prop_assert_eq!(bumped, step.next_state == maze.state_of(before).unwrap());
            if bumped {
                let blocked = Action::from_index(action)
                    .unwrap()
                    .apply(before, maze.width(), maze.height())
                    .is_none_or(|next| maze.is_obstacle(next));
                prop_assert!(blocked);
            }
            if step.done() {
                env.reset(None);
            }
        }
    }

    /// Task and sub-task rewards, next state and termination match the reference
    /// dynamics and the schemes, for random schemes and random moves.
    #[test]
    fn rewards_match_the_scheme(
        maze in common::small_maze(8),
        task in scheme(),
        subtasks in prop::collection::vec(scheme(), 0..4),
        actions in prop::collection::vec(0usize..4, 1..200),
    ) {
        let spec = spec_with(task, subtasks.clone(), 2000);
        let mut env = MazeEnv::new(maze.clone(), spec).unwrap();
        prop_assert_eq!(env.n_subtasks(), subtasks.len());
        let mut at = maze.pos_of(env.reset(None)).unwrap();
        for action in actions {
            let (expected_next, event) = reference_transition(&maze, at, action);
            let step = env.step(action);
            prop_assert_eq!(step.next_state, maze.state_of(expected_next).unwrap());
            prop_assert_eq!(env.last_event(), Some(event));
            prop_assert_eq!(step.reward, task.reward(event));
            let expected: Vec<f64> = subtasks.iter().map(|s| s.reward(event)).collect();
            prop_assert_eq!(env.subtask_rewards(), expected.as_slice());
            prop_assert_eq!(step.terminated, event == Event::Target);
            prop_assert!(!step.truncated);
            at = expected_next;
            if step.done() {
                at = maze.pos_of(env.reset(None)).unwrap();
            }
        }
    }

    /// Truncation comes exactly at the step cap, never together with termination.
    #[test]
    fn truncation_at_the_step_cap(
        maze in common::small_maze(8),
        cap in 1u32..30,
        actions in prop::collection::vec(0usize..4, 30..31),
    ) {
        let mut env = MazeEnv::new(maze, spec_with(RewardScheme::TASK_I, vec![], cap)).unwrap();
        env.reset(Some(7));
        for (taken, action) in (1u32..).zip(actions) {
            let step = env.step(action);
            prop_assert_eq!(env.steps(), taken);
            prop_assert!(!(step.terminated && step.truncated));
            prop_assert_eq!(step.truncated, !step.terminated && taken >= cap);
            if step.done() {
                break;
            }
        }
    }
}

#[test]
fn the_dql_contract_on_task1() {
    let mut env = Preset::Task1.env();
    assert_eq!(env.n_states(), 900);
    assert_eq!(env.n_actions(), 4);
    assert_eq!(env.n_subtasks(), 2);
    assert_eq!(
        env.subtask_names(),
        ["reach the target faster", "do not hit obstacles"]
    );
    assert_eq!(env.subtask_rewards(), &[0.0, 0.0]);
    assert_eq!(env.state_features(29 * 30 + 7), vec![7, 29]);
    let start = env.reset(Some(1));
    assert_eq!(start, 0);
    assert_eq!(env.reset(None), start);

    // Follow the BFS path: every step is closer or the target, and the episode
    // terminates on the last one.
    let path = env.maze().shortest_path();
    let mut total = 0.0;
    for pair in path.windows(2) {
        let action = Action::between(pair[0], pair[1]).unwrap();
        let step = env.step(action.index());
        total += step.reward;
        assert_eq!(env.position(), pair[1]);
        assert_eq!(step.done(), pair[1] == env.maze().target());
        assert_ne!(env.last_event(), Some(Event::Bump));
    }
    assert_eq!(env.last_event(), Some(Event::Target));
    assert_eq!(env.subtask_rewards(), &[100.0, 0.0]);
    // A 58-move monotone path: 57 closer moves (+1) and the target (+100).
    assert_eq!(path.len() - 1, 58);
    assert_eq!(total, 157.0);

    // Stepping a finished episode does not panic and stays finite.
    let step = env.step(Action::Up.index());
    assert!(step.reward.is_finite());
    env.reset(None);
    assert_eq!((env.steps(), env.last_event()), (0, None));
    assert_eq!(env.subtask_rewards(), &[0.0, 0.0]);
}

#[test]
fn task_ii_pays_minus_one_for_a_bump() {
    let mut env = Preset::Task2.env();
    env.reset(None);
    let step = env.step(Action::Left.index());
    assert_eq!(env.last_event(), Some(Event::Bump));
    assert_eq!(step.reward, -1.0);
    assert_eq!(env.subtask_rewards(), &[-1.0, -100.0]);
}

#[test]
fn a_random_walk_is_truncated_at_2000_steps() {
    // Bumping the wall forever never reaches the target.
    let mut env = Preset::Task1.env();
    env.reset(None);
    for taken in 1..=2000 {
        let step = env.step(Action::Up.index());
        assert_eq!(step.truncated, taken == 2000);
        assert!(!step.terminated);
    }
}

#[test]
fn an_action_outside_the_range_is_an_error_and_does_not_step() {
    let mut env = Preset::Task1.env();
    let start = env.reset(None);
    let error = env.try_step(4).unwrap_err();
    assert_eq!(
        error,
        DqlError::IndexOutOfRange {
            argument: "action",
            index: 4,
            len: 4
        }
    );
    assert_eq!(env.steps(), 0);
    assert_eq!(env.state(), start);
    assert!(env.try_step(Action::Up.index()).is_ok());
}

#[test]
fn invalid_specs_are_typed_errors() {
    let maze = Maze::parse("ST\n").unwrap();
    let mut spec = TaskSpec::task1();
    spec.subtasks[1].reward.bump = f64::NAN;
    let error = MazeEnv::new(maze.clone(), spec).unwrap_err();
    assert!(matches!(
        &error,
        SpecError::NonFiniteReward { field, .. } if field == "subtasks[1].reward.bump"
    ));
    assert_eq!(
        error.to_string(),
        "`subtasks[1].reward.bump` must be a finite number, got NaN"
    );

    let mut spec = TaskSpec::task2();
    spec.reward.target = f64::INFINITY;
    assert_eq!(
        MazeEnv::new(maze.clone(), spec).unwrap_err().to_string(),
        "`reward.target` must be a finite number, got inf"
    );

    let spec = TaskSpec {
        step_cap: 0,
        ..TaskSpec::task1()
    };
    assert_eq!(
        MazeEnv::new(maze.clone(), spec).unwrap_err(),
        SpecError::StepCapOutOfRange { value: 0 }
    );
    let spec = TaskSpec {
        step_cap: mazes::MAX_STEP_CAP + 1,
        ..TaskSpec::task1()
    };
    assert_eq!(
        MazeEnv::new(maze.clone(), spec).unwrap_err().to_string(),
        "`step_cap` must be in [1, 100000], got 100001"
    );

    let mut spec = TaskSpec::task1();
    spec.subtasks[0].name = "  ".to_owned();
    assert_eq!(
        MazeEnv::new(maze.clone(), spec).unwrap_err(),
        SpecError::EmptySubtaskName { index: 0 }
    );

    let mut spec = TaskSpec::task1();
    spec.subtasks[1].name = spec.subtasks[0].name.clone();
    assert_eq!(
        MazeEnv::new(maze, spec).unwrap_err().to_string(),
        "`subtasks[1].name` repeats the name \"reach the target faster\" of `subtasks[0]`"
    );
}

#[test]
fn specs_round_trip_through_serde() {
    for spec in [TaskSpec::task1(), TaskSpec::task2()] {
        let json = serde_json::to_string(&spec).unwrap();
        assert_eq!(serde_json::from_str::<TaskSpec>(&json).unwrap(), spec);
    }
    insta::assert_snapshot!(serde_json::to_string_pretty(&TaskSpec::task1()).unwrap());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// A saved episode put back on another environment of the same task continues exactly.
    #[test]
    fn a_saved_episode_continues_exactly(
        before in prop::collection::vec(0..4usize, 0..300),
        after in prop::collection::vec(0..4usize, 1..100),
    ) {
        let mut original = Preset::Task2.env();
        original.reset(None);
        for &action in &before {
            original.step(action);
        }
        let (position, steps, last_event) = original.episode();
        let mut restored = Preset::Task2.env();
        restored.reset(None);
        restored.step(3);
        restored.set_episode(position, steps, last_event).unwrap();
        prop_assert_eq!(restored.episode(), original.episode());
        prop_assert_eq!(restored.subtask_rewards(), original.subtask_rewards());
        for &action in &after {
            let (a, b) = (original.step(action), restored.step(action));
            prop_assert_eq!(a.next_state, b.next_state);
            prop_assert_eq!(a.reward.to_bits(), b.reward.to_bits());
            prop_assert_eq!((a.terminated, a.truncated), (b.terminated, b.truncated));
            prop_assert_eq!(original.subtask_rewards(), restored.subtask_rewards());
        }
    }
}

#[test]
fn an_episode_that_cannot_be_on_the_maze_is_refused_and_changes_nothing() {
    let mut env = MazeEnv::new(
        Maze::parse("S.#\n..T\n").unwrap(),
        Preset::Task1.task_spec(),
    )
    .unwrap();
    env.step(3);
    let saved = env.episode();
    for (position, steps, event) in [
        (Pos::new(2, 0), 1, Some(Event::Bump)),   // an obstacle
        (Pos::new(5, 0), 1, Some(Event::Bump)),   // outside the grid
        (Pos::new(1, 0), 0, Some(Event::Closer)), // an event without a step
        (Pos::new(1, 0), 3, None),                // steps without an event
    ] {
        assert!(env.set_episode(position, steps, event).is_err());
        assert_eq!(env.episode(), saved);
    }
    env.set_episode(Pos::new(0, 0), 0, None).unwrap();
    assert_eq!(env.subtask_rewards(), &[0.0, 0.0]);
}
