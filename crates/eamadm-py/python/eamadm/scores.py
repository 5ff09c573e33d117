"""Final scores in the shape rliable takes: ``{method: runs × tasks array}``.

`rliable <https://github.com/google-research/rliable>`_ (Agarwal et al., 2021) estimates
aggregate metrics (IQM, optimality gap, …) with stratified bootstrap intervals from a dict
mapping each method to a ``(runs, tasks)`` score matrix. :func:`rliable_scores` makes that
dict from an output folder of the main job or from :func:`eamadm.run`'s results::

    from rliable import library, metrics
    scores = eamadm.rliable_scores("target/reproduce-paper", "final_return")
    iqm = lambda x: numpy.array([metrics.aggregate_iqm(x)])
    estimates, intervals = library.get_interval_estimates(scores, iqm, reps=2000)
"""

from __future__ import annotations

import math
import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Tuple, Union

import numpy
import numpy.typing as npt

from eamadm import _args, outputs
from eamadm.experiment import Results


def _columns(source: object) -> Dict[str, List[Any]]:
    """The final scores of ``source`` as one list per column."""
    if isinstance(source, (str, os.PathLike)):
        root = outputs.run_folder(source)
        package = outputs.data_package(root)
        path = root / outputs.FINAL_SCORES
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as error:
            raise ValueError(f"dir: cannot read {path}: {error}") from error
        return outputs.typed_columns(text, outputs.fields(package, "final-scores"))
    items = [source] if isinstance(source, Results) else source
    if isinstance(items, (str, bytes)) or not hasattr(items, "__iter__"):
        raise TypeError(
            "source: expected an output folder, a Results of eamadm.run or a list of them, got "
            f"{_args.type_name(source)}"
        )
    columns: Dict[str, List[Any]] = {}
    for item in items:
        if not isinstance(item, Results):
            raise TypeError(
                f"source: expected what eamadm.run returns (a Results), got {_args.type_name(item)}"
            )
        table = item.final_scores
        names = list(table.columns) if hasattr(table, "columns") else list(table)
        for name in names:
            values = table[name]
            cells = values.tolist() if hasattr(values, "tolist") else list(values)
            columns.setdefault(name, []).extend(cells)
    if not columns:
        raise ValueError("source: expected the results of at least one run")
    return columns


def _labels(value: object, name: str) -> Optional[List[str]]:
    if value is None:
        return None
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise TypeError(f"{name}: expected an iterable of str, got {_args.type_name(value)}")
    labels = list(value)
    for label in labels:
        if not isinstance(label, str):
            raise TypeError(f"{name}: expected str, got {_args.type_name(label)} {label!r}")
    if not labels:
        raise ValueError(f"{name}: expected at least one")
    return labels


def _missing(value: Any) -> bool:
    """A blank cell: None, NaN, or pandas' missing value of a nullable column (``pd.NA``)."""
    if value is None or type(value).__name__ == "NAType":
        return True
    return isinstance(value, (float, numpy.floating)) and math.isnan(value)


def rliable_scores(
    source: Union[_args.PathLike, Results, Iterable[Results]],
    metric: str,
    normalise: Optional[Mapping[str, Tuple[float, float]]] = None,
    *,
    methods: Optional[Iterable[str]] = None,
    tasks: Optional[Iterable[str]] = None,
) -> Dict[str, npt.NDArray[numpy.float64]]:
    """``{method: scores}``, each a ``float64`` array of shape ``(runs, tasks)``, of the
    numeric column ``metric`` of ``final-scores.csv``: what ``rliable.library.
    get_interval_estimates`` and its plots take.

    Row ``i`` of a method's matrix is its ``i``-th seed (seeds ascending), column ``j`` the
    ``j``-th task (``tasks`` order, default the order of the table: the report's). The seeds
    pair across tasks, as the main job runs the same seeds on every task.

    Args:
        source: an output folder of the main job (``--out``), or :func:`eamadm.run`'s results
            (one, or a list of them, one per experiment).
        metric: a numeric column of ``final-scores.csv``, e.g. ``"final_return"``,
            ``"final_steps"``, ``"success_rate"`` (``docs/outputs.md`` lists them; which
            direction is better is the metric's own).
        normalise: ``{task: (low, high)}`` for every task: each score becomes
            ``(score - low) / (high - low)`` (rliable's normalised scores, e.g. a random and
            an expert score, so that tasks of other scales aggregate); None keeps raw scores.
        methods: the methods (default: every method run on all of ``tasks``, in table order).
        tasks: the tasks (default: every task of the table, in its order).

    Raises:
        TypeError: an argument of the wrong type.
        FileNotFoundError: the folder does not exist.
        ValueError: the folder is not an output folder; ``metric`` is not a numeric column; a
            method lacks a task or a (seed, task) cell, or a cell is blank; ``normalise``
            lacks a task or has ``low == high``.
    """
    if not isinstance(metric, str):
        raise TypeError(f"metric: expected a str, got {_args.type_name(metric)}")
    columns = _columns(source)
    numeric = [
        field["name"]
        for field in outputs.fields(outputs.data_package(), "final-scores")
        if field["type"] in ("integer", "number")
    ]
    if metric not in numeric or metric not in columns:
        raise ValueError(f"metric: {metric!r} is not a numeric column; these are: {numeric}")
    rows = list(zip(columns["task"], columns["method"], columns["seed"], columns[metric]))
    all_tasks = list(dict.fromkeys(task for task, _, _, _ in rows))
    wanted_tasks = _labels(tasks, "tasks") or all_tasks
    for task in wanted_tasks:
        if task not in all_tasks:
            raise ValueError(f"tasks: no runs of {task!r}; the tasks are {all_tasks}")
    ran: Dict[str, set[str]] = {}
    for task, method, _, _ in rows:
        ran.setdefault(method, set()).add(task)
    wanted_methods = _labels(methods, "methods")
    if wanted_methods is None:
        wanted_methods = [m for m, done in ran.items() if set(wanted_tasks) <= done]
        if not wanted_methods:
            raise ValueError(f"tasks: no method ran on all of {wanted_tasks}")
    for method in wanted_methods:
        lacking = [task for task in wanted_tasks if task not in ran.get(method, set())]
        if lacking:
            raise ValueError(f"methods: {method!r} has no runs on {lacking}")
    scale: Dict[str, Tuple[float, float]] = {}
    if normalise is not None:
        if not isinstance(normalise, Mapping):
            raise TypeError(f"normalise: expected a dict {{task: (low, high)}}, got {_args.type_name(normalise)}")
        for task in wanted_tasks:
            if task not in normalise:
                raise ValueError(f"normalise: no (low, high) for the task {task!r}")
            pair = normalise[task]
            if not isinstance(pair, (tuple, list)) or len(pair) != 2:
                raise TypeError(f"normalise: {task!r}: expected (low, high), got {pair!r}")
            low, high = (float(v) for v in pair)
            if not (math.isfinite(low) and math.isfinite(high)) or low == high:
                raise ValueError(f"normalise: {task!r}: expected finite low != high, got {pair!r}")
            scale[task] = (low, high)
    cells: Dict[Tuple[str, str, int], Any] = {}
    for task, method, seed, value in rows:
        key = (method, task, int(seed))
        if key in cells:
            raise ValueError(f"source: two runs of {method!r} on {task!r} with seed {seed}")
        cells[key] = value
    out: Dict[str, npt.NDArray[numpy.float64]] = {}
    for method in wanted_methods:
        seeds = sorted({s for (m, t, s) in cells if m == method and t in wanted_tasks})
        matrix = numpy.empty((len(seeds), len(wanted_tasks)), dtype=numpy.float64)
        for i, seed in enumerate(seeds):
            for j, task in enumerate(wanted_tasks):
                if (method, task, seed) not in cells:
                    raise ValueError(
                        f"source: {method!r} has no run with seed {seed} on {task!r} (the "
                        "seeds must pair across tasks)"
                    )
                value = cells[(method, task, seed)]
                if _missing(value):
                    raise ValueError(
                        f"metric: {metric!r} is blank for {method!r} on {task!r} with seed "
                        f"{seed} (docs/outputs.md says when it is)"
                    )
                number = float(value)
                if task in scale:
                    low, high = scale[task]
                    number = (number - low) / (high - low)
                matrix[i, j] = number
        out[method] = matrix
    return out
