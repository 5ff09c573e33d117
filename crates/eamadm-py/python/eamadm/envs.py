"""The paper's tasks as ``gymnasium.Env``: the two mazes and the wheeled robot.

Seeding (Gymnasium's contract): ``reset(seed=s)`` seeds ``self.np_random`` with ``s`` and, for
the robot, re-seeds the Rust ``ChaCha8`` stream of the sensor noise with the same integer ``s``
(``0 <= s < 2**64``). The first ``reset()`` without a seed draws that integer from
``self.np_random`` (which Gymnasium seeds from the OS's entropy); later resets without a seed
continue the current stream. The mazes have no randomness: their episodes depend on the actions
only, whatever the seed.

Rendering: ``render_mode="ansi"`` gives text, ``render_mode="rgb_array"`` a small RGB frame
(``uint8``, height × width × 3, drawn in Rust: 8 pixels a tile for the mazes, 200 pixels a metre
for the robot's arena), so ``gymnasium.wrappers.RecordVideo`` and notebooks can show episodes.

Both environments pickle and deep-copy: the copy continues exactly as the original would
(the maze's episode; the robot's pose, metrics and sensor-noise stream, bit for bit), so an
environment can be checkpointed or sent to another process.
"""

from __future__ import annotations

from typing import Any, Dict, List, Optional, SupportsFloat, Tuple, Union

import gymnasium
import numpy as np
import numpy.typing as npt

from eamadm import _args
from eamadm._native import MazeCore, RobotCore

#: Largest seed the Rust side takes (an unsigned 64-bit integer).
MAX_SEED = 2**64 - 1

#: What ``render()`` returns: text (``"ansi"``), an RGB frame (``"rgb_array"``) or None.
RenderFrame = Union[str, npt.NDArray[np.uint8], None]
#: What ``reset()`` returns: the state and the info dict.
ResetResult = Tuple[int, Dict[str, Any]]
#: What ``step()`` returns: state, reward, terminated, truncated, info.
StepResult = Tuple[int, SupportsFloat, bool, bool, Dict[str, Any]]


def check_seed(seed: object) -> Optional[int]:
    """``seed`` must be None or an int in ``0..2**64``.

    Raises:
        TypeError: ``seed`` is not an int.
        ValueError: ``seed`` is out of range.
    """
    if seed is None:
        return None
    return _args.check_int(seed, "seed", maximum=MAX_SEED)


class MazeEnv(gymnasium.Env[int, int]):
    """A maze task of Sec. VI.A: states are tiles ``y * width + x``, actions 0 up, 1 down,
    2 left, 3 right.

    Keyword arguments:
        task: ``"task1"`` or ``"task2"``: the preset (layout, rewards, sub-tasks, step cap).
        map: a text map replacing the preset's layout (``S`` start, ``T`` target, ``#``
            obstacle, ``.`` free, ``;`` comments).
        map_file: a file holding such a map (not together with ``map``).
        rewards: whose rewards and sub-tasks to use, ``"task1"`` or ``"task2"`` (default
            ``task``).
        step_cap: steps after which an episode is truncated (default 2000).
        render_mode: ``None``, ``"ansi"`` (the maze as text, the episode's path marked) or
            ``"rgb_array"`` (the same as an RGB frame, 8 pixels a tile, the agent dark blue).

    ``info`` holds ``subtask_rewards`` (float64 array: "reach the target faster", "do not hit
    obstacles"), ``position`` (int64 array ``[x, y]``) and ``event`` (the last move's kind).

    Raises:
        TypeError: an argument of the wrong type (``step_cap="500"``).
        FileNotFoundError: ``map_file`` names no file.
        ValueError: an argument out of range or a map that does not parse, naming the argument.
    """

    metadata = {"render_modes": ["ansi", "rgb_array"], "render_fps": 4}

    def __init__(
        self,
        task: str = "task1",
        *,
        map: Optional[str] = None,
        map_file: Optional[_args.PathLike] = None,
        rewards: Optional[str] = None,
        step_cap: Optional[int] = None,
        render_mode: Optional[str] = None,
    ) -> None:
        self.render_mode = _args.check_render_mode(render_mode, self.metadata["render_modes"])
        text = _args.text_or_file(map, "map", map_file, "map_file")
        self._core = MazeCore(
            _args.require_str(task, "task"),
            text,
            _args.check_str(rewards, "rewards"),
            _args.check_step_cap(step_cap),
        )
        self.observation_space = _args.discrete(self._core.n_states)
        self.action_space = _args.discrete(self._core.n_actions)

    @property
    def subtask_names(self) -> List[str]:
        """The sub-tasks' names, in the order of ``info["subtask_rewards"]``."""
        return self._core.subtask_names

    def _info(self) -> Dict[str, Any]:
        return {
            "subtask_rewards": self._core.subtask_rewards(),
            "position": np.array(self._core.position(), dtype=np.int64),
            "event": self._core.last_event() or "reset",
        }

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> ResetResult:
        """Puts the agent on the start tile (``seed`` only seeds ``self.np_random``).

        Raises:
            TypeError: ``seed`` is not an int.
            ValueError: ``seed`` is out of range.
        """
        super().reset(seed=check_seed(seed))
        state = self._core.reset()
        return state, self._info()

    def step(self, action: Any) -> StepResult:
        """Moves the agent: ``(state, reward, terminated, truncated, info)``.

        Raises:
            TypeError: ``action`` is not an int (a float, even ``1.0``, is not an action).
            ValueError: ``action`` is not in ``0..4``.
        """
        state, reward, terminated, truncated = self._core.step(_args.check_action(action))
        return state, reward, terminated, truncated, self._info()

    def render(self) -> RenderFrame:
        """The maze as text (``render_mode="ansi"``) or an RGB frame (``"rgb_array"``);
        ``None`` without a render mode."""
        if self.render_mode == "ansi":
            return self._core.render()
        if self.render_mode == "rgb_array":
            return self._core.render_rgb()
        return None


class RobotEnv(gymnasium.Env[int, int]):
    """The wheeled robot among obstacles (Sec. III and VI.B): a discrete state of target
    distance and the obstacle in the camera's view, five wheel-speed actions, three sub-tasks
    (Eq. 6–8).

    Keyword arguments:
        scenario: a scenario as TOML text (default: the embedded analogue of the paper's
            Fig. 12; the Rust crate ``wmr-model`` documents the format).
        scenario_file: a file holding such a scenario (not together with ``scenario``).
        state: entries overriding the scenario's ``[state]`` table, e.g.
            ``{"distance_bins": 12, "angle_bins": 8}`` (whatever that table accepts).
        step_cap: steps after which an episode is truncated (default: the scenario's).
        render_mode: ``None``, ``"ansi"`` (one line: time, pose, state, readings) or
            ``"rgb_array"`` (the arena from above, 200 pixels a metre: obstacles gray, the
            target's reach disc yellow, the episode's path blue, the robot red with its heading).

    ``info`` holds ``subtask_rewards`` (float64 array), ``position`` (float64 ``[x, y]`` in
    metres), ``heading`` (radians) and ``metrics`` (the episode's metrics of Sec. VI.B).

    Raises:
        TypeError: an argument of the wrong type.
        FileNotFoundError: ``scenario_file`` names no file.
        ValueError: an argument out of range or a scenario that is not valid, naming the
            argument.
    """

    metadata = {"render_modes": ["ansi", "rgb_array"], "render_fps": 5}

    def __init__(
        self,
        *,
        scenario: Optional[str] = None,
        scenario_file: Optional[_args.PathLike] = None,
        state: Optional[Dict[str, Any]] = None,
        step_cap: Optional[int] = None,
        render_mode: Optional[str] = None,
    ) -> None:
        self.render_mode = _args.check_render_mode(render_mode, self.metadata["render_modes"])
        text = _args.text_or_file(scenario, "scenario", scenario_file, "scenario_file")
        if state is not None and not isinstance(state, dict):
            raise TypeError(f"state: expected a dict, got {type(state).__name__}")
        self._core = RobotCore(text, state, _args.check_step_cap(step_cap))
        self.observation_space = _args.discrete(self._core.n_states)
        self.action_space = _args.discrete(self._core.n_actions)
        self._seeded = False

    @property
    def subtask_names(self) -> List[str]:
        """The sub-tasks' names, in the order of ``info["subtask_rewards"]``."""
        return self._core.subtask_names

    @property
    def scenario_toml(self) -> str:
        """The scenario in use, overrides applied, as TOML text."""
        return self._core.scenario_toml

    def _info(self) -> Dict[str, Any]:
        x, y, heading = self._core.pose()
        return {
            "subtask_rewards": self._core.subtask_rewards(),
            "position": np.array([x, y], dtype=np.float64),
            "heading": heading,
            "metrics": self._core.metrics(),
        }

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[Dict[str, Any]] = None
    ) -> ResetResult:
        """Puts the robot at the start pose; see the module docs for how ``seed`` is used.

        Raises:
            TypeError: ``seed`` is not an int.
            ValueError: ``seed`` is not in ``0..2**64``.
        """
        seed = check_seed(seed)
        super().reset(seed=seed)
        if seed is not None:
            rust_seed: Optional[int] = seed
        elif not self._seeded:
            rust_seed = int(self.np_random.integers(0, 2**63))
        else:
            rust_seed = None
        self._seeded = True
        state = self._core.reset(rust_seed)
        return state, self._info()

    def step(self, action: Any) -> StepResult:
        """Holds the action for one control period: ``(state, reward, terminated, truncated,
        info)``.

        Raises:
            TypeError: ``action`` is not an int.
            ValueError: ``action`` is not in ``0..5``.
        """
        state, reward, terminated, truncated = self._core.step(_args.check_action(action))
        return state, reward, terminated, truncated, self._info()

    def render(self) -> RenderFrame:
        """One line of text (``render_mode="ansi"``) or the arena as an RGB frame
        (``"rgb_array"``); ``None`` without a render mode."""
        if self.render_mode == "ansi":
            return self._core.render()
        if self.render_mode == "rgb_array":
            return self._core.render_rgb()
        return None
