"""N copies of a maze, or of the robot, stepped in one call in Rust: Gymnasium 1.x vector envs.

Autoreset mode: ``AutoresetMode.NEXT_STEP`` (Gymnasium's default). When copy ``i`` terminates
or is truncated on step ``t``, step ``t + 1`` resets it instead of stepping it: its action is
ignored and it returns the start state, reward 0, ``terminated = truncated = False`` and the
reset's info. This is exactly what ``gymnasium.vector.SyncVectorEnv`` over N ``MazeEnv``\\ s
returns, array for array (tested).

``info`` holds ``subtask_rewards`` (float64, N x m), ``position`` (int64, N x 2), and the masks
``_subtask_rewards`` and ``_position`` (all true), in Gymnasium's vector-info layout.

Actions are integers only, exactly as the single environments take them: a list of ints or an
integer array; floats (even ``1.0``), bools and text are a ``TypeError``, values out of range a
``ValueError``. ``render_mode="rgb_array"`` renders one frame per copy.
"""

from __future__ import annotations

from typing import Any, Dict, Optional, Tuple

import gymnasium
import numpy as np
import numpy.typing as npt
from gymnasium import spaces
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from eamadm import _args
from eamadm._native import MazeVecCore, RobotVecCore
from eamadm.envs import MAX_SEED

#: What a vector ``reset()`` returns: states and info.
VectorReset = Tuple[npt.NDArray[np.int64], Dict[str, Any]]
#: What a vector ``step()`` returns: states, rewards, terminated, truncated and info.
VectorStep = Tuple[
    npt.NDArray[np.int64],
    npt.NDArray[np.float64],
    npt.NDArray[np.bool_],
    npt.NDArray[np.bool_],
    Dict[str, Any],
]


def _num_envs(num_envs: object) -> int:
    from eamadm._args import check_int

    return check_int(num_envs, "num_envs", minimum=1)


class MazeVectorEnv(gymnasium.vector.VectorEnv[Any, Any, Any]):
    """``num_envs`` copies of the maze :class:`eamadm.MazeEnv` describes with the same keyword
    arguments (``task``, ``map``, ``map_file``, ``rewards``, ``step_cap``, ``render_mode``).

    Actions: integers (a list or an integer array) of shape ``(num_envs,)`` with values in
    ``0..4``. ``render()`` returns one text maze (``"ansi"``) or RGB frame (``"rgb_array"``)
    per copy.

    Raises:
        TypeError: an argument of the wrong type.
        FileNotFoundError: ``map_file`` names no file.
        ValueError: an argument out of range, naming it.
    """

    metadata = {
        "render_modes": ["ansi", "rgb_array"],
        "autoreset_mode": AutoresetMode.NEXT_STEP,
    }

    def __init__(
        self,
        num_envs: int = 1,
        task: str = "task1",
        *,
        map: Optional[str] = None,
        map_file: Optional[_args.PathLike] = None,
        rewards: Optional[str] = None,
        step_cap: Optional[int] = None,
        render_mode: Optional[str] = None,
    ) -> None:
        count = _num_envs(num_envs)
        self.render_mode = _args.check_render_mode(render_mode, self.metadata["render_modes"])
        text = _args.text_or_file(map, "map", map_file, "map_file")
        self._core = MazeVecCore(
            count,
            _args.require_str(task, "task"),
            text,
            _args.check_str(rewards, "rewards"),
            _args.check_step_cap(step_cap),
        )
        self.num_envs = count
        self.single_observation_space = spaces.Discrete(self._core.n_states)
        self.single_action_space = spaces.Discrete(4)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._mask = np.ones(self.num_envs, dtype=np.bool_)

    def _info(
        self, subtask: npt.NDArray[np.float64], position: npt.NDArray[np.int64]
    ) -> Dict[str, Any]:
        return {
            "subtask_rewards": subtask,
            "_subtask_rewards": self._mask,
            "position": position,
            "_position": self._mask,
        }

    def reset(
        self, *, seed: Any = None, options: Optional[Dict[str, Any]] = None
    ) -> VectorReset:
        """Resets every copy (the mazes have no randomness; ``seed`` seeds ``np_random``)."""
        super().reset(seed=seed)
        states, _rewards, _terminated, _truncated, subtask, position = self._core.reset()
        return states, self._info(subtask, position)

    def step(self, actions: Any) -> VectorStep:
        """Steps every copy: arrays ``(states, rewards, terminated, truncated)`` and ``info``.

        Raises:
            TypeError: the actions are not integers.
            ValueError: wrong shape, or an action not in ``0..4``.
        """
        checked = _args.check_actions(actions, self.num_envs)
        states, rewards, terminated, truncated, subtask, position = self._core.step(checked)
        return states, rewards, terminated, truncated, self._info(subtask, position)

    def render(self) -> Optional[Tuple[Any, ...]]:
        """Each copy's maze as text (``render_mode="ansi"``) or as an RGB frame
        (``"rgb_array"``); ``None`` otherwise."""
        if self.render_mode == "ansi":
            return tuple(self._core.render(i) for i in range(self.num_envs))
        if self.render_mode == "rgb_array":
            return tuple(self._core.render_rgb(i) for i in range(self.num_envs))
        return None


class RobotVectorEnv(gymnasium.vector.VectorEnv[Any, Any, Any]):
    """``num_envs`` copies of the robot :class:`eamadm.RobotEnv` describes with the same keyword
    arguments (``scenario``, ``scenario_file``, ``state``, ``step_cap``, ``render_mode``),
    stepped in one Rust call, autoreset mode ``NEXT_STEP``.

    ``reset(seed=s)`` seeds copy ``i``'s sensor noise with ``s + i``, as
    ``SyncVectorEnv`` seeds its copies; an unseeded first reset draws each copy's seed from
    ``np_random``. ``info`` has the single env's keys (``subtask_rewards``, ``position``,
    ``heading``, ``metrics``) batched by Gymnasium's own ``VectorEnv._add_info``, so it has
    exactly ``SyncVectorEnv``'s layout. ``render()`` returns one line (``"ansi"``) or RGB frame
    (``"rgb_array"``) per copy.

    Raises:
        TypeError: an argument of the wrong type.
        FileNotFoundError: ``scenario_file`` names no file.
        ValueError: an argument out of range, naming it.
    """

    metadata = {
        "render_modes": ["ansi", "rgb_array"],
        "autoreset_mode": AutoresetMode.NEXT_STEP,
    }

    def __init__(
        self,
        num_envs: int = 1,
        *,
        scenario: Optional[str] = None,
        scenario_file: Optional[_args.PathLike] = None,
        state: Optional[Dict[str, Any]] = None,
        step_cap: Optional[int] = None,
        render_mode: Optional[str] = None,
    ) -> None:
        count = _num_envs(num_envs)
        self.render_mode = _args.check_render_mode(render_mode, self.metadata["render_modes"])
        text = _args.text_or_file(scenario, "scenario", scenario_file, "scenario_file")
        if state is not None and not isinstance(state, dict):
            raise TypeError(f"state: expected a dict, got {type(state).__name__}")
        self._core = RobotVecCore(count, text, state, _args.check_step_cap(step_cap))
        self.num_envs = count
        self.single_observation_space = spaces.Discrete(self._core.n_states)
        self.single_action_space = spaces.Discrete(self._core.n_actions)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._seeded = False

    def _infos(self) -> Dict[str, Any]:
        infos: Dict[str, Any] = {}
        for i in range(self.num_envs):
            x, y, heading = self._core.pose(i)
            info = {
                "subtask_rewards": self._core.subtask_rewards(i),
                "position": np.array([x, y], dtype=np.float64),
                "heading": heading,
                "metrics": self._core.metrics(i),
            }
            infos = self._add_info(infos, info, i)
        return infos

    def reset(self, *, seed: Any = None, options: Optional[Dict[str, Any]] = None) -> VectorReset:
        """Resets every copy; ``seed`` (an int) seeds copy ``i`` with ``seed + i``.

        Raises:
            TypeError: ``seed`` is not an int.
            ValueError: ``seed`` is not in ``0..2**64 - num_envs``.
        """
        if seed is not None:
            seed = _args.check_int(seed, "seed", maximum=MAX_SEED - self.num_envs + 1)
        super().reset(seed=seed)
        seeds: list[Optional[int]]
        if seed is not None:
            seeds = [seed + i for i in range(self.num_envs)]
        elif not self._seeded:
            seeds = [int(s) for s in self.np_random.integers(0, 2**63, size=self.num_envs)]
        else:
            seeds = [None] * self.num_envs
        self._seeded = True
        states = self._core.reset(seeds)
        return states, self._infos()

    def step(self, actions: Any) -> VectorStep:
        """Steps every copy: arrays ``(states, rewards, terminated, truncated)`` and ``info``.

        Raises:
            TypeError: the actions are not integers.
            ValueError: wrong shape, or an action not in ``0..5``.
        """
        checked = _args.check_actions(actions, self.num_envs)
        states, rewards, terminated, truncated = self._core.step(checked)
        return states, rewards, terminated, truncated, self._infos()

    def render(self) -> Optional[Tuple[Any, ...]]:
        """Each copy as one line of text (``render_mode="ansi"``) or its arena as an RGB frame
        (``"rgb_array"``); ``None`` otherwise."""
        if self.render_mode == "ansi":
            return tuple(self._core.render(i) for i in range(self.num_envs))
        if self.render_mode == "rgb_array":
            return tuple(self._core.render_rgb(i) for i in range(self.num_envs))
        return None
