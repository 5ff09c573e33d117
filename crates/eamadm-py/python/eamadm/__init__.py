"""EA-MADM from Python: the paper's tasks as Gymnasium environments and its experiments.

Importing the package registers three Gymnasium ids:

* ``eamadm/MazeTaskI-v0`` and ``eamadm/MazeTaskII-v0``: the 30 x 30 and 39 x 36 mazes of the
  paper's Sec. VI.A (:class:`MazeEnv`; also as a native vector env, :class:`MazeVectorEnv`,
  through ``gymnasium.make_vec(..., vectorization_mode="vector_entry_point")``);
* ``eamadm/Robot-v0``: the wheeled robot among obstacles of Sec. VI.B (:class:`RobotEnv`; also
  as a native vector env, :class:`RobotVectorEnv`).

:func:`run` runs an experiment :class:`Config` (the TOML schema of the Rust runner; also a
dict or a ``.toml`` file) on the Rust runner, with a progress bar if asked and stopping on
Ctrl-C; :func:`paper_config` returns the paper's presets. :func:`load_runs` reads the run store
of an output folder of ``cargo xtask reproduce-paper`` and :func:`read_scores` its
``final-scores.csv`` and ``claims.csv``, typed by its ``datapackage.json``; :func:`report`
renders ``REPORT.md`` (and its verdicts) of such a folder, byte for byte, or of :func:`run`'s
results with their figures; :func:`figures` draws the main job's figures of either, with the
main job's code; :func:`rliable_scores` gives the scores in rliable's ``{method: runs × tasks}``
shape. ``python -m eamadm reproduce|report|figures DIR`` runs the main job's commands without
Rust. Everything is computed by the Rust crates; the numbers are bit-identical to
``cargo xtask reproduce-paper``.

Bad input raises Python's exceptions: ``TypeError`` for a value of the wrong type,
``ValueError`` for a wrong value (the message starts with the argument's name, and for a config
names the key as written), ``FileNotFoundError`` for a missing file or folder.
"""

from __future__ import annotations

import gymnasium

from eamadm import _native
from eamadm.envs import MazeEnv, RobotEnv
from eamadm.experiment import Config, Results, paper_config, run
from eamadm.figures import figures
from eamadm.outputs import Scores, data_package, load_runs, read_scores
from eamadm.report import Report, report
from eamadm.scores import rliable_scores
from eamadm.vector import MazeVectorEnv, RobotVectorEnv

__all__ = [
    "ENV_IDS",
    "Config",
    "MazeEnv",
    "MazeVectorEnv",
    "Report",
    "Results",
    "RobotEnv",
    "RobotVectorEnv",
    "Scores",
    "__version__",
    "data_package",
    "figures",
    "load_runs",
    "paper_config",
    "read_scores",
    "report",
    "rliable_scores",
    "run",
]

#: The package's version: the Rust crates' (``Cargo.toml``'s ``workspace.package.version``).
__version__: str = _native.__version__

#: The Gymnasium ids this package registers on import.
ENV_IDS: tuple[str, ...] = ("eamadm/MazeTaskI-v0", "eamadm/MazeTaskII-v0", "eamadm/Robot-v0")


def _register() -> None:
    """Registers the three ids (once; re-importing is harmless)."""
    registry = gymnasium.envs.registration.registry
    if "eamadm/MazeTaskI-v0" not in registry:
        gymnasium.register(
            id="eamadm/MazeTaskI-v0",
            entry_point="eamadm.envs:MazeEnv",
            vector_entry_point="eamadm.vector:MazeVectorEnv",
            kwargs={"task": "task1"},
        )
    if "eamadm/MazeTaskII-v0" not in registry:
        gymnasium.register(
            id="eamadm/MazeTaskII-v0",
            entry_point="eamadm.envs:MazeEnv",
            vector_entry_point="eamadm.vector:MazeVectorEnv",
            kwargs={"task": "task2"},
        )
    if "eamadm/Robot-v0" not in registry:
        gymnasium.register(
            id="eamadm/Robot-v0",
            entry_point="eamadm.envs:RobotEnv",
            vector_entry_point="eamadm.vector:RobotVectorEnv",
        )


_register()
