"""The paper's experiments from Python, computed by the Rust runner.

A config is the Rust runner's TOML schema, given as text, as a dict of the same shape, or as
a path to a ``.toml`` file. :func:`run` returns the same numbers ``cargo xtask reproduce-paper``
writes to ``<task>/curves.csv.gz`` and ``final-scores.csv`` for the same config and seeds, bit
for bit.
"""

from __future__ import annotations

import json
import os
import pathlib
from typing import Any, Iterable, NamedTuple, Optional, Union

import numpy

from eamadm import _native
from eamadm import outputs

Config = Union[str, dict, "os.PathLike[str]"]

class Results(NamedTuple):
    """What :func:`run` returns: two tables, each a pandas ``DataFrame`` (or a dict of numpy
    arrays when pandas is missing or ``dataframe=False``)."""

    #: One row per (run, episode): the columns of the Rust runner's ``curves.csv.gz``
    #: (a column with blank cells, such as the robot's metrics on a maze, is ``float64`` with
    #: NaN).
    curves: Any
    #: One row per run: the columns of the main job's ``final-scores.csv``, computed by the
    #: same library code (``eamadm::scores::final_scores``) and typed by its data package
    #: (``docs/outputs.md`` explains every column).
    final_scores: Any


class _RunResults(Results):
    """:class:`Results` that also carry what :func:`eamadm.report` needs of the runs (the
    experiment's facts and its ``final-scores.csv`` rows, as the Rust runner computed them);
    still a 2-tuple, so ``curves, final_scores = run(...)`` unpacks as before."""

    #: Opaque to Python: handed back to the Rust report.
    report_input: Any = None


def paper_config(name: str, *, as_dict: bool = False) -> Union[str, dict]:
    """The paper's preset ``"task1"``, ``"task2"``, ``"robot"`` or ``"robot-paper-state"`` (Tables 1 and 2) as TOML
    text, or as a dict when ``as_dict`` is true."""
    if not isinstance(name, str):
        raise ValueError(f"name: expected a str, got {type(name).__name__}")
    text = _native.paper_config_toml(name)
    return json.loads(_native.toml_to_json(text)) if as_dict else text


def config_toml(config: Config) -> str:
    """The config as TOML text (a dict goes through the same parser as text)."""
    if isinstance(config, dict):
        try:
            dumped = json.dumps(config)
        except (TypeError, ValueError) as error:
            raise ValueError(f"config: not serialisable: {error}") from error
        return _native.json_to_toml(dumped)
    if isinstance(config, os.PathLike):
        try:
            return pathlib.Path(config).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as error:
            raise ValueError(f"config: cannot read {os.fspath(config)!r}: {error}") from error
    if isinstance(config, str):
        return config
    raise ValueError(
        f"config: expected TOML text, a dict or a path, got {type(config).__name__}"
    )


def _seed_list(seeds: Optional[Iterable[int]]) -> Optional[list]:
    if seeds is None:
        return None
    if isinstance(seeds, (str, bytes)) or not hasattr(seeds, "__iter__"):
        raise ValueError(f"seeds: expected an iterable of ints, got {seeds!r}")
    out = []
    for seed in seeds:
        if isinstance(seed, bool) or not hasattr(seed, "__index__"):
            raise ValueError(f"seeds: expected ints, got {seed!r}")
        seed = int(seed)
        if not 0 <= seed < 2**64:
            raise ValueError(f"seeds: expected ints in 0..2**64, got {seed}")
        out.append(seed)
    return out


def _positive(value: Any, name: str) -> Optional[int]:
    if value is None:
        return None
    if isinstance(value, bool) or not hasattr(value, "__index__") or int(value) < 1:
        raise ValueError(f"{name}: expected a positive int, got {value!r}")
    return int(value)


def _shortened(config: Config, episodes: Optional[int], seeds: Optional[int]) -> Config:
    """``config`` with the ``episodes=`` and ``seeds=`` shortcuts applied (as a dict)."""
    if episodes is None and seeds is None:
        return config
    data = json.loads(_native.toml_to_json(config_toml(config)))
    if seeds is not None:
        data["seeds"] = seeds
    if episodes is not None:
        before = data.get("episodes", episodes)
        data["episodes"] = episodes
        trajectories = data.get("trajectories")
        if isinstance(trajectories, dict) and isinstance(trajectories.get("episodes"), list):
            trajectories["episodes"] = [e for e in trajectories["episodes"] if e < episodes]
        for method in data.get("methods", []):
            # As `cargo xtask reproduce-paper --quick` shortens: pre-training gets at most as
            # many episodes, and a warm-up budget shrinks with the episodes.
            pretrain = method.get("pretrain")
            if isinstance(pretrain, dict) and isinstance(pretrain.get("episodes"), int):
                fewest = pretrain["episodes"]
                pretrain["episodes"] = min(fewest, episodes)
                # A stopping rule's cap shrinks in the same proportion, never below the fewest.
                until = pretrain.get("until")
                if isinstance(until, dict) and isinstance(until.get("max_episodes"), int):
                    scaled = until["max_episodes"] * pretrain["episodes"] // max(fewest, 1)
                    until["max_episodes"] = max(scaled, pretrain["episodes"])
            warmup = method.get("warmup_env_steps")
            if isinstance(warmup, int) and isinstance(before, int) and episodes < before:
                method["warmup_env_steps"] = warmup * episodes // max(before, 1)
    return data


def run(
    config: Config,
    *,
    seeds: Union[int, Iterable[int], None] = None,
    episodes: Optional[int] = None,
    methods: Optional[Iterable[str]] = None,
    threads: Optional[int] = None,
    dataframe: bool = True,
) -> Results:
    """Runs ``config`` on the Rust runner, with Python's GIL released.

    Args:
        config: TOML text, a dict of the same schema, or a path to a TOML file.
        seeds: an int ``n`` runs the config's first ``n`` seeds (``base_seed + i`` for
            ``i < n``); an iterable runs exactly those seeds, e.g. ``range(3)``; default: the
            config's own ``seeds``.
        episodes: training episodes per run instead of the config's; pre-training gets at
            most as many, and a warm-up budget shrinks in proportion (as ``--quick`` does).
        methods: the labels of the methods to run (default: all, in the config's order).
        threads: worker threads (default: one per core). Results do not depend on it.
        dataframe: return pandas DataFrames when pandas is installed (``False``: dicts of
            numpy arrays, one per column).

    Runs come in job order: method by method, seed by seed.
    """
    episodes = _positive(episodes, "episodes")
    seed_count = None
    if isinstance(seeds, int) and not isinstance(seeds, bool):
        seed_count = _positive(seeds, "seeds")
        seeds = None
    text = config_toml(_shortened(config, episodes, seed_count))
    if methods is not None:
        if isinstance(methods, str) or not hasattr(methods, "__iter__"):
            raise ValueError(f"methods: expected an iterable of labels, got {methods!r}")
        methods = list(methods)
        if not all(isinstance(label, str) for label in methods):
            raise ValueError(f"methods: expected str labels, got {methods!r}")
    columns = _native.run_config(text, _seed_list(seeds), methods, _positive(threads, "threads"))
    curves = {
        name: outputs.signed(values)
        if isinstance(values, numpy.ndarray)
        else numpy.array(values, dtype=object)
        for name, values in columns["curves"].items()
    }
    fields = outputs._fields(outputs.data_package(), "final-scores")
    scores = outputs.typed_columns(columns["final_scores"], fields)
    if dataframe:
        try:
            import pandas
        except ImportError:
            pass
        else:
            results = _RunResults(pandas.DataFrame(curves), outputs.as_frame(scores, fields))
            results.report_input = columns["report_input"]
            return results
    results = _RunResults(curves, outputs.as_arrays(scores, fields))
    results.report_input = columns["report_input"]
    return results
