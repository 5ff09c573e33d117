"""The native vector env equals N single envs under Gymnasium's SyncVectorEnv, step by step."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode

import eamadm

SMALL_MAP = "S..#\n.#..\n...T\n"


@pytest.mark.parametrize(
    "kwargs",
    [{"map": SMALL_MAP, "step_cap": 7}, {"step_cap": 100}],
    ids=["small-map-cap-7", "task1-cap-100"],
)
def test_vector_env_equals_sync_vector_env(kwargs):
    n = 6
    native = gym.make_vec(
        "eamadm/MazeTaskI-v0", num_envs=n, vectorization_mode="vector_entry_point", **kwargs
    )
    sync = gym.make_vec("eamadm/MazeTaskI-v0", num_envs=n, vectorization_mode="sync", **kwargs)
    assert native.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    assert sync.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    assert native.observation_space == sync.observation_space
    assert native.action_space == sync.action_space
    a_obs, a_info = native.reset(seed=3)
    b_obs, b_info = sync.reset(seed=3)
    np.testing.assert_array_equal(a_obs, b_obs)
    rng = np.random.default_rng(0)
    ends = 0
    for _ in range(300):
        actions = rng.integers(0, 4, size=n)
        a = native.step(actions)
        b = sync.step(actions)
        for x, y in zip(a[:4], b[:4]):
            np.testing.assert_array_equal(x, y)
            assert x.dtype == y.dtype
        for key in ("subtask_rewards", "position", "_subtask_rewards", "_position"):
            np.testing.assert_array_equal(a[4][key], b[4][key])
        ends += int(a[2].sum() + a[3].sum())
    assert ends > 0, "the comparison must cover autoresets"


def test_vector_env_bad_arguments():
    with pytest.raises(ValueError, match="^num_envs: "):
        eamadm.MazeVectorEnv(0)
    with pytest.raises(ValueError, match="^step_cap: "):
        eamadm.MazeVectorEnv(2, step_cap=0)
    env = eamadm.MazeVectorEnv(3)
    env.reset()
    with pytest.raises(ValueError, match="^actions: "):
        env.step(np.array([0, 1]))
    with pytest.raises(ValueError, match="^actions: "):
        env.step(np.array([0, 1, 4]))
    with pytest.raises(TypeError, match="^actions: "):
        env.step(["a", "b", "c"])
    with pytest.raises(TypeError, match="^num_envs: "):
        eamadm.MazeVectorEnv("3")


@pytest.mark.parametrize(
    "actions",
    [[0.9, 1.7, 2.2], np.array([0.0, 1.0, 2.0]), [True, False, True], [0, 1, 2.5]],
    ids=["floats", "float-array", "bools", "mixed"],
)
def test_vector_actions_are_integers_only_as_the_single_envs(actions):
    # The single env refuses 1.0 with a TypeError; so does the vector env, for every copy.
    env = eamadm.MazeVectorEnv(3)
    env.reset()
    with pytest.raises(TypeError, match="^actions: "):
        env.step(actions)
    robots = eamadm.RobotVectorEnv(3)
    robots.reset(seed=0)
    with pytest.raises(TypeError, match="^actions: "):
        robots.step(actions)
    single = eamadm.MazeEnv()
    single.reset()
    with pytest.raises(TypeError, match="^action: "):
        single.step(np.asarray(actions)[0].item() if np.asarray(actions).dtype.kind == "f" else actions[0])


def test_vector_actions_may_be_a_list_of_ints_or_any_integer_array():
    steps = []
    for actions in ([3, 1], np.array([3, 1], dtype=np.uint8), np.array([3, 1], dtype=np.int32)):
        env = eamadm.MazeVectorEnv(2, map=SMALL_MAP)
        env.reset()
        steps.append(env.step(actions)[0].tolist())
    assert steps == [[1, 4]] * 3


def test_vector_render():
    env = eamadm.MazeVectorEnv(2, map=SMALL_MAP, render_mode="ansi")
    env.reset()
    env.step(np.array([1, 3]))
    first, second = env.render()
    assert first != second


def _assert_infos_equal(a, b, path="info"):
    assert sorted(a) == sorted(b), path
    for key in a:
        x, y = a[key], b[key]
        if isinstance(x, dict):
            _assert_infos_equal(x, y, f"{path}[{key!r}]")
        else:
            assert x.dtype == y.dtype, f"{path}[{key!r}]"
            assert x.shape == y.shape, f"{path}[{key!r}]"
            if x.dtype == object:
                assert [repr(v) for v in x] == [repr(v) for v in y], f"{path}[{key!r}]"
            else:
                np.testing.assert_array_equal(x, y, err_msg=f"{path}[{key!r}]")


@pytest.mark.parametrize("step_cap", [15, 60])
def test_robot_vector_env_equals_sync_vector_env(step_cap):
    n = 4
    native = gym.make_vec(
        "eamadm/Robot-v0", num_envs=n, vectorization_mode="vector_entry_point", step_cap=step_cap
    )
    sync = gym.make_vec("eamadm/Robot-v0", num_envs=n, vectorization_mode="sync", step_cap=step_cap)
    assert isinstance(native.unwrapped, eamadm.RobotVectorEnv)
    assert native.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    assert native.observation_space == sync.observation_space
    assert native.action_space == sync.action_space
    a_obs, a_info = native.reset(seed=11)
    b_obs, b_info = sync.reset(seed=11)
    np.testing.assert_array_equal(a_obs, b_obs)
    assert a_obs.dtype == b_obs.dtype
    _assert_infos_equal(a_info, b_info)
    rng = np.random.default_rng(1)
    ends = 0
    for _ in range(120):
        actions = rng.integers(0, native.single_action_space.n, size=n)
        a = native.step(actions)
        b = sync.step(actions)
        for x, y in zip(a[:4], b[:4]):
            np.testing.assert_array_equal(x, y)
            assert x.dtype == y.dtype
        _assert_infos_equal(a[4], b[4])
        ends += int(a[2].sum() + a[3].sum())
    assert ends > 0, "the comparison must cover autoresets"


def test_robot_vector_env_bad_arguments():
    with pytest.raises(ValueError, match="^num_envs: "):
        eamadm.RobotVectorEnv(0)
    with pytest.raises(ValueError, match="^step_cap: "):
        eamadm.RobotVectorEnv(2, step_cap=0)
    with pytest.raises(TypeError, match="^state: "):
        eamadm.RobotVectorEnv(2, state=[1])
    env = eamadm.RobotVectorEnv(2, render_mode="ansi")
    with pytest.raises(ValueError, match="^seed: "):
        env.reset(seed=-1)
    env.reset(seed=0)
    with pytest.raises(ValueError, match="^actions: "):
        env.step(np.array([0]))
    with pytest.raises(ValueError, match="^actions: "):
        env.step(np.array([0, 9]))
    assert len(env.render()) == 2
