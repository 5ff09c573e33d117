"""The single Gymnasium environments: checker, seeding, info, rendering, bad arguments."""

import warnings

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import eamadm

SMALL_MAP = """\
S..#
.#..
...T
"""


@pytest.mark.parametrize("env_id", eamadm.ENV_IDS)
def test_check_env_passes_without_warnings(env_id):
    env = gym.make(env_id, render_mode="ansi")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(env.unwrapped, skip_render_check=False)
    env.close()


@pytest.mark.parametrize("env_id", eamadm.ENV_IDS)
def test_same_seed_same_episode(env_id):
    def rollout(seed):
        env = gym.make(env_id)
        state, _ = env.reset(seed=seed)
        env.action_space.seed(seed)
        out = [state]
        for _ in range(200):
            state, reward, terminated, truncated, info = env.step(env.action_space.sample())
            out.append((state, reward, terminated, truncated, tuple(info["subtask_rewards"])))
            if terminated or truncated:
                state, _ = env.reset()
                out.append(state)
        return out

    assert rollout(7) == rollout(7)


def test_robot_seed_drives_the_sensor_noise():
    env = gym.make("eamadm/Robot-v0")
    readings = []
    for seed in (1, 2, 1):
        env.reset(seed=seed)
        readings.append(env.unwrapped._core.render())
    assert readings[0] == readings[2]
    assert readings[0] != readings[1]


def test_maze_info_and_subtasks():
    env = gym.make("eamadm/MazeTaskI-v0", map=SMALL_MAP)
    state, info = env.reset()
    assert state == 0
    assert info["position"].tolist() == [0, 0]
    assert info["subtask_rewards"].tolist() == [0.0, 0.0]
    # Up from the top-left corner is a bump: the agent stays, Task I pays -100.
    state, reward, terminated, truncated, info = env.step(0)
    assert (state, reward, terminated, truncated) == (0, -100.0, False, False)
    assert info["event"] == "bump"
    assert info["subtask_rewards"].dtype == np.float64
    assert env.unwrapped.subtask_names == ["reach the target faster", "do not hit obstacles"]


def test_maze_reaches_target_and_truncates():
    env = gym.make("eamadm/MazeTaskI-v0", map=SMALL_MAP, step_cap=50)
    env.reset()
    for action in (1, 1, 3, 3):  # down, down, right, right
        state, reward, terminated, truncated, info = env.step(action)
    assert not terminated
    state, reward, terminated, truncated, info = env.step(3)
    assert terminated and not truncated and reward == 100.0
    assert info["position"].tolist() == [3, 2]
    capped = gym.make("eamadm/MazeTaskI-v0", map=SMALL_MAP, step_cap=2).unwrapped
    capped.reset()
    assert capped.step(0)[3] is False
    assert capped.step(0)[3] is True


def test_map_file_and_rewards(tmp_path):
    path = tmp_path / "small.map"
    path.write_text(SMALL_MAP)
    task1 = gym.make("eamadm/MazeTaskI-v0", map_file=path)
    task2 = gym.make("eamadm/MazeTaskI-v0", map_file=str(path), rewards="task2")
    task1.reset()
    task2.reset()
    assert task1.observation_space.n == 12
    assert task1.step(0)[1] != task2.step(0)[1]


def test_ansi_render_shows_the_path():
    env = gym.make("eamadm/MazeTaskI-v0", map=SMALL_MAP, render_mode="ansi")
    env.reset()
    env.step(1)
    text = env.render()
    assert text.splitlines()[0].startswith("S")
    assert len(text.splitlines()) == 3


def test_robot_info_and_state_override():
    # The default state adds the target's image position in 7 bins to the paper's
    # distance x (obstacle image x angle + no obstacle) state.
    env = gym.make("eamadm/Robot-v0", state={"distance_bins": 5}, step_cap=3)
    assert env.observation_space.n == 5 * (4 * 6 + 1) * 7
    paper_state = gym.make("eamadm/Robot-v0", state={"distance_bins": 5, "target_bins": 0})
    assert paper_state.observation_space.n == 5 * (4 * 6 + 1)
    _, info = env.reset(seed=0)
    assert info["position"].shape == (2,)
    assert info["subtask_rewards"].shape == (3,)
    for _ in range(3):
        _, _, terminated, truncated, info = env.step(0)
    assert truncated and not terminated
    assert info["metrics"]["steps"] == 3
    assert info["metrics"]["outcome"] == "truncated"
    assert "distance_bins = 5" in env.unwrapped.scenario_toml


def test_robot_scenario_text_round_trips():
    default = eamadm.RobotEnv()
    again = eamadm.RobotEnv(scenario=default.scenario_toml)
    assert again.scenario_toml == default.scenario_toml


@pytest.mark.parametrize(
    "kwargs, error, argument",
    [
        ({"step_cap": 0}, ValueError, "step_cap"),
        ({"step_cap": -3}, ValueError, "step_cap"),
        ({"step_cap": "500"}, TypeError, "step_cap"),
        ({"step_cap": 2.0}, TypeError, "step_cap"),
        ({"map": "S.#\nxx"}, ValueError, "map"),
        ({"map": 42}, TypeError, "map"),
        ({"map_file": "/nonexistent/eamadm.map"}, FileNotFoundError, "map_file"),
        ({"map_file": 3}, TypeError, "map_file"),
        ({"map": SMALL_MAP, "map_file": "x.map"}, ValueError, "map_file"),
        ({"rewards": "task3"}, ValueError, "rewards"),
        ({"rewards": 2}, TypeError, "rewards"),
        ({"render_mode": "human"}, ValueError, "render_mode"),
        ({"render_mode": 1}, TypeError, "render_mode"),
    ],
)
def test_bad_maze_arguments_name_the_argument(kwargs, error, argument):
    with pytest.raises(error, match=f"^{argument}: "):
        eamadm.MazeEnv(**kwargs)


@pytest.mark.parametrize(
    "kwargs, error, argument",
    [
        ({"scenario": "not = [valid"}, ValueError, "scenario"),
        ({"scenario_file": "/nonexistent/scenario.toml"}, FileNotFoundError, "scenario_file"),
        ({"state": {"distance_bins": 0}}, ValueError, "state"),
        ({"state": {"no_such_field": 1}}, ValueError, "state"),
        ({"state": {"distance_bins": [1]}}, TypeError, "state"),
        ({"state": [1]}, TypeError, "state"),
        ({"step_cap": 0}, ValueError, "step_cap"),
        ({"step_cap": "500"}, TypeError, "step_cap"),
    ],
)
def test_bad_robot_arguments_name_the_argument(kwargs, error, argument):
    with pytest.raises(error, match=f"^{argument}: "):
        eamadm.RobotEnv(**kwargs)


@pytest.mark.parametrize("env_id", eamadm.ENV_IDS)
@pytest.mark.parametrize(
    "action, error",
    [(-1, ValueError), (99, ValueError), (1.5, TypeError), (1.0, TypeError), ("up", TypeError), (True, TypeError)],
)
def test_bad_actions_name_the_argument(env_id, action, error):
    env = gym.make(env_id, disable_env_checker=True)
    env.reset(seed=0)
    with pytest.raises(error, match="^action: "):
        env.step(action)


def test_bad_seed_names_the_argument():
    env = eamadm.RobotEnv()
    with pytest.raises(ValueError, match="^seed: "):
        env.reset(seed=2**64)
    with pytest.raises(TypeError, match="^seed: "):
        env.reset(seed="3")
    with pytest.raises(TypeError, match="^seed: "):
        eamadm.MazeEnv().reset(seed=1.5)
