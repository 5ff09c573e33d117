"""N copies of a maze, or of the robot, stepped in one call in Rust: Gymnasium 1.x vector envs.

Autoreset mode: ``AutoresetMode.NEXT_STEP`` (Gymnasium's default). When copy ``i`` terminates
or is truncated on step ``t``, step ``t + 1`` resets it instead of stepping it: its action is
ignored and it returns the start state, reward 0, ``terminated = truncated = False`` and the
reset's info. This is exactly what ``gymnasium.vector.SyncVectorEnv`` over N ``MazeEnv``\\ s
returns, array for array (tested).

``info`` holds ``subtask_rewards`` (float64, N x m), ``position`` (int64, N x 2), and the masks
``_subtask_rewards`` and ``_position`` (all true), in Gymnasium's vector-info layout.
"""

from __future__ import annotations

from typing import Any, Optional

import gymnasium
import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode
from gymnasium.vector.utils import batch_space

from eamadm import _args
from eamadm._native import MazeVecCore, RobotVecCore
from eamadm.envs import MAX_SEED


class MazeVectorEnv(gymnasium.vector.VectorEnv):
    """``num_envs`` copies of the maze :class:`eamadm.MazeEnv` describes with the same keyword
    arguments (``task``, ``map``, ``map_file``, ``rewards``, ``step_cap``, ``render_mode``).

    Actions: any integer array of shape ``(num_envs,)`` with values in ``0..4``.
    ``render()`` (``render_mode="ansi"``) returns one text maze per copy.
    """

    metadata = {"render_modes": ["ansi"], "autoreset_mode": AutoresetMode.NEXT_STEP}

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
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
            raise ValueError(f"num_envs: expected a positive int, got {num_envs!r}")
        self.render_mode = _args.check_render_mode(render_mode, self.metadata["render_modes"])
        text = _args.text_or_file(map, "map", map_file, "map_file")
        self._core = MazeVecCore(
            int(num_envs),
            _args.check_str(task, "task"),
            text,
            _args.check_str(rewards, "rewards"),
            _args.check_step_cap(step_cap),
        )
        self.num_envs = int(num_envs)
        self.single_observation_space = spaces.Discrete(self._core.n_states)
        self.single_action_space = spaces.Discrete(4)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._mask = np.ones(self.num_envs, dtype=np.bool_)

    def _info(self, subtask: np.ndarray, position: np.ndarray) -> dict:
        return {
            "subtask_rewards": subtask,
            "_subtask_rewards": self._mask,
            "position": position,
            "_position": self._mask,
        }

    def reset(
        self, *, seed: Any = None, options: Optional[dict] = None
    ) -> tuple:
        """Resets every copy (the mazes have no randomness; ``seed`` seeds ``np_random``)."""
        super().reset(seed=seed)
        states, _rewards, _terminated, _truncated, subtask, position = self._core.reset()
        return states, self._info(subtask, position)

    def step(self, actions: Any) -> tuple:
        """Steps every copy: arrays ``(states, rewards, terminated, truncated)`` and ``info``."""
        try:
            actions = np.asarray(actions, dtype=np.int64)
        except (TypeError, ValueError, OverflowError) as error:
            raise ValueError(f"actions: expected integers, got {error}") from error
        if actions.shape != (self.num_envs,):
            raise ValueError(
                f"actions: expected shape ({self.num_envs},), got {actions.shape}"
            )
        if not actions.flags.c_contiguous:
            actions = np.ascontiguousarray(actions)
        states, rewards, terminated, truncated, subtask, position = self._core.step(actions)
        return states, rewards, terminated, truncated, self._info(subtask, position)

    def render(self) -> Optional[tuple]:
        """Each copy's maze as text (``render_mode="ansi"``); ``None`` otherwise."""
        if self.render_mode == "ansi":
            return tuple(self._core.render(i) for i in range(self.num_envs))
        return None


class RobotVectorEnv(gymnasium.vector.VectorEnv):
    """``num_envs`` copies of the robot :class:`eamadm.RobotEnv` describes with the same keyword
    arguments (``scenario``, ``scenario_file``, ``state``, ``step_cap``, ``render_mode``),
    stepped in one Rust call, autoreset mode ``NEXT_STEP``.

    ``reset(seed=s)`` seeds copy ``i``'s sensor noise with ``s + i``, as
    ``SyncVectorEnv`` seeds its copies; an unseeded first reset draws each copy's seed from
    ``np_random``. ``info`` has the single env's keys (``subtask_rewards``, ``position``,
    ``heading``, ``metrics``) batched by Gymnasium's own ``VectorEnv._add_info``, so it has
    exactly ``SyncVectorEnv``'s layout. ``render()`` returns one line per copy.
    """

    metadata = {"render_modes": ["ansi"], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(
        self,
        num_envs: int = 1,
        *,
        scenario: Optional[str] = None,
        scenario_file: Optional[_args.PathLike] = None,
        state: Optional[dict] = None,
        step_cap: Optional[int] = None,
        render_mode: Optional[str] = None,
    ) -> None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
            raise ValueError(f"num_envs: expected a positive int, got {num_envs!r}")
        self.render_mode = _args.check_render_mode(render_mode, self.metadata["render_modes"])
        text = _args.text_or_file(scenario, "scenario", scenario_file, "scenario_file")
        if state is not None and not isinstance(state, dict):
            raise ValueError(f"state: expected a dict, got {type(state).__name__}")
        self._core = RobotVecCore(int(num_envs), text, state, _args.check_step_cap(step_cap))
        self.num_envs = int(num_envs)
        self.single_observation_space = spaces.Discrete(self._core.n_states)
        self.single_action_space = spaces.Discrete(self._core.n_actions)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._seeded = False

    def _infos(self) -> dict:
        infos: dict = {}
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

    def reset(self, *, seed: Any = None, options: Optional[dict] = None) -> tuple:
        """Resets every copy; ``seed`` (an int) seeds copy ``i`` with ``seed + i``."""
        if seed is not None and (
            isinstance(seed, bool)
            or not isinstance(seed, (int, np.integer))
            or not 0 <= int(seed) <= MAX_SEED - self.num_envs + 1
        ):
            raise ValueError(
                f"seed: expected None or an int in 0..2**64 - num_envs, got {seed!r}"
            )
        super().reset(seed=seed)
        if seed is not None:
            seeds = [int(seed) + i for i in range(self.num_envs)]
        elif not self._seeded:
            seeds = [int(s) for s in self.np_random.integers(0, 2**63, size=self.num_envs)]
        else:
            seeds = [None] * self.num_envs
        self._seeded = True
        states = self._core.reset(seeds)
        return states, self._infos()

    def step(self, actions: Any) -> tuple:
        """Steps every copy: arrays ``(states, rewards, terminated, truncated)`` and ``info``."""
        try:
            actions = np.asarray(actions, dtype=np.int64)
        except (TypeError, ValueError, OverflowError) as error:
            raise ValueError(f"actions: expected integers, got {error}") from error
        if actions.shape != (self.num_envs,):
            raise ValueError(
                f"actions: expected shape ({self.num_envs},), got {actions.shape}"
            )
        states, rewards, terminated, truncated = self._core.step(np.ascontiguousarray(actions))
        return states, rewards, terminated, truncated, self._infos()

    def render(self) -> Optional[tuple]:
        """Each copy as one line of text (``render_mode="ansi"``); ``None`` otherwise."""
        if self.render_mode == "ansi":
            return tuple(self._core.render(i) for i in range(self.num_envs))
        return None
