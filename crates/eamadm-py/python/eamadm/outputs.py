"""Reading what the main job (``cargo xtask reproduce-paper``) writes into its output folder.

* :func:`load_runs`: the run store ``<out>/runs/`` (read and checked by the Rust crate
  ``eamadm-runs``), one row per stored run with its per-episode curves as numpy arrays;
* :func:`read_scores`: ``final-scores.csv`` and ``claims.csv``, typed by the Frictionless data
  package ``datapackage.json`` written beside them (integers as integers, booleans as
  booleans, blank cells as missing values);
* :func:`data_package`: that package as a dict (every column's type, unit, meaning and when
  it is blank).

:func:`eamadm.report` (in :mod:`eamadm.report`) renders the folder's ``REPORT.md`` and its
verdicts; :func:`eamadm.rliable_scores` shapes its scores for rliable. Each refuses a folder
that is not an output folder of the main job: ``FileNotFoundError`` when it does not exist,
``ValueError`` naming what is missing when it is not one.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import pathlib
import warnings
from typing import Any, Dict, List, NamedTuple, Optional

import numpy
import numpy.typing as npt

from eamadm import _args, _native
from eamadm._args import PathLike

#: The file name of the data package beside the tables (``eamadm::output_names::DATA_PACKAGE``).
DATA_PACKAGE = "datapackage.json"


class Scores(NamedTuple):
    """What :func:`read_scores` returns: two pandas ``DataFrame`` objects."""

    #: ``final-scores.csv``: one row per run (task, method, seed).
    final_scores: Any
    #: ``claims.csv``: the paper's claims tested.
    claims: Any


def data_package(dir: Optional[PathLike] = None) -> Dict[str, Any]:
    """The Frictionless data package of ``final-scores.csv`` and ``claims.csv``: the
    ``datapackage.json`` of the output folder ``dir``, or when ``dir`` is None (or the output
    folder predates the package) the one this version of the package writes.

    Raises:
        TypeError: ``dir`` is not a path.
        FileNotFoundError: ``dir`` does not exist.
        ValueError: ``dir`` is not an output folder of the main job (no ``final-scores.csv``),
            or its ``datapackage.json`` cannot be read.
    """
    if dir is not None:
        folder = run_folder(dir)
        path = folder / DATA_PACKAGE
        if path.is_file():
            try:
                package: Dict[str, Any] = json.loads(path.read_text(encoding="utf-8"))
            except (OSError, UnicodeDecodeError, ValueError) as error:
                raise ValueError(f"dir: cannot read {path}: {error}") from error
            return package
    built_in: Dict[str, Any] = json.loads(_native.data_package_json())
    return built_in


#: The table every output folder of the main job holds.
FINAL_SCORES = "final-scores.csv"


def folder(dir: object) -> pathlib.Path:
    """``dir`` as an existing folder: ``TypeError`` if it is not a path, ``FileNotFoundError``
    if it does not exist, ``ValueError`` if it is a file."""
    path = pathlib.Path(_args.check_path(dir, "dir"))
    if not path.exists():
        raise FileNotFoundError(f"dir: {os.fspath(path)!r} does not exist (give the main job's --out)")
    if not path.is_dir():
        raise ValueError(f"dir: {os.fspath(path)!r} is not a folder (give the main job's --out)")
    return path


def run_folder(dir: object) -> pathlib.Path:
    """``dir`` as an output folder of the main job (one holding ``final-scores.csv``), as
    :func:`folder` checks it, and ``ValueError`` when it is a folder but not such a one."""
    path = folder(dir)
    if not (path / FINAL_SCORES).is_file():
        raise ValueError(
            f"dir: {os.fspath(path)!r} is not an output folder of `cargo xtask reproduce-paper` "
            f"(or `python -m eamadm reproduce`): it has no {FINAL_SCORES}"
        )
    return path


def fields(package: Dict[str, Any], resource: str) -> List[Dict[str, Any]]:
    """The Table Schema field descriptors of ``resource`` in the data package ``package``."""
    for entry in package.get("resources", []):
        if entry.get("name") == resource:
            found: List[Dict[str, Any]] = entry["schema"]["fields"]
            return found
    raise ValueError(f"dir: the data package has no resource {resource!r}")


def _cell(text: str, kind: str, column: str) -> Any:
    """One CSV cell as its Table Schema type; ``None`` for a blank cell."""
    if text == "":
        return None
    try:
        if kind == "integer":
            return int(text)
        if kind == "number":
            # Rust writes the shortest text that reads back to the same bits.
            return float(text)
        if kind == "boolean":
            return {"true": True, "false": False}[text]
    except (ValueError, KeyError) as error:
        raise ValueError(f"{column}: {text!r} is not a {kind}") from error
    return text


def typed_columns(text: str, fields: List[Dict[str, Any]]) -> Dict[str, List[Any]]:
    """The CSV ``text`` as one typed Python list per column (``None`` for a blank cell); its
    header must equal the names of ``fields`` (Table Schema field descriptors).

    Raises:
        ValueError: the header differs, or a cell is not of its column's type.
    """
    reader = csv.reader(io.StringIO(text, newline=""))
    header = next(reader, None)
    names = [field["name"] for field in fields]
    if header != names:
        raise ValueError(f"the header {header} is not the data package's columns {names}")
    kinds = [field["type"] for field in fields]
    columns: Dict[str, List[Any]] = {name: [] for name in names}
    for line, row in enumerate(reader, start=2):
        if len(row) != len(names):
            raise ValueError(f"line {line}: {len(row)} cells, expected {len(names)}")
        for name, kind, cell in zip(names, kinds, row):
            columns[name].append(_cell(cell, kind, f"line {line}, column {name}"))
    return columns


def as_arrays(
    columns: Dict[str, List[Any]], fields: List[Dict[str, Any]]
) -> Dict[str, npt.NDArray[Any]]:
    """Typed columns as numpy arrays: ``int64`` (``float64`` with NaN if a cell is blank),
    ``float64`` with NaN for blanks, ``bool`` (``object`` with None if a cell is blank), and
    ``object`` for text (None for blanks)."""
    arrays: Dict[str, npt.NDArray[Any]] = {}
    for field in fields:
        name, kind = field["name"], field["type"]
        values = columns[name]
        blank = any(value is None for value in values)
        if kind == "integer" and not blank and all(value < 2**63 for value in values):
            arrays[name] = numpy.array(values, dtype=numpy.int64)
        elif kind in ("integer", "number"):
            arrays[name] = numpy.array(
                [math.nan if value is None else value for value in values], dtype=numpy.float64
            )
        elif kind == "boolean" and not blank:
            arrays[name] = numpy.array(values, dtype=bool)
        else:
            arrays[name] = numpy.array(values, dtype=object)
    return arrays


def as_frame(columns: Dict[str, List[Any]], fields: List[Dict[str, Any]]) -> Any:
    """Typed columns as a pandas ``DataFrame``: ``int64`` (nullable ``Int64`` if a cell is
    blank), ``float64`` with NaN for blanks, ``bool`` (nullable ``boolean`` if a cell is
    blank), and text with missing values for blanks.

    Raises:
        ImportError: pandas is not installed.
    """
    pandas = _pandas("read the tables")
    data: Dict[str, Any] = {}
    for field in fields:
        name, kind = field["name"], field["type"]
        values = columns[name]
        blank = any(value is None for value in values)
        if kind == "integer" and all(value is None or value < 2**63 for value in values):
            data[name] = pandas.array(values, dtype="Int64" if blank else "int64")
        elif kind == "integer":
            data[name] = pandas.array(values, dtype=object)
        elif kind == "number":
            data[name] = numpy.array(
                [math.nan if value is None else value for value in values], dtype=numpy.float64
            )
        elif kind == "boolean":
            data[name] = pandas.array(values, dtype="boolean" if blank else "bool")
        else:
            data[name] = pandas.array(values, dtype=object)
    return pandas.DataFrame(data, columns=[field["name"] for field in fields])


def _pandas(purpose: str) -> Any:
    try:
        import pandas
    except ImportError as error:
        raise ImportError(
            f"pandas is needed to {purpose}: pip install 'eamadm[pandas]'"
        ) from error
    return pandas


def read_scores(dir: PathLike) -> Scores:
    """``final-scores.csv`` and ``claims.csv`` of the output folder ``dir`` as typed pandas
    ``DataFrame`` objects, by the column types of its ``datapackage.json`` (see
    :func:`as_frame`; ``docs/outputs.md`` explains every column).

    Raises:
        TypeError: ``dir`` is not a path.
        FileNotFoundError: ``dir`` does not exist.
        ValueError: ``dir`` is not an output folder of the main job, or a table cannot be
            read or does not match its data package (naming the file, line and column).
        ImportError: pandas is not installed.
    """
    root = run_folder(dir)
    package = data_package(root)
    tables = []
    for resource in ("final-scores", "claims"):
        entry = next(e for e in package["resources"] if e.get("name") == resource)
        path = root / entry["path"]
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as error:
            raise ValueError(f"dir: cannot read {path}: {error}") from error
        try:
            described = fields(package, resource)
            tables.append(as_frame(typed_columns(text, described), described))
        except ValueError as error:
            raise ValueError(f"dir: {path}: {error}") from error
    return Scores(*tables)


def load_runs(dir: PathLike, *, dataframe: bool = True) -> Any:
    """Every run stored in the output folder ``dir`` (its ``runs/``, read and checked by the
    Rust crate ``eamadm-runs``), one row per run in storage order (experiment by experiment,
    then the plan's job order: method by method, seed by seed).

    The readings of the paper (``sensitivity.csv``) rerun some methods under their own
    experiment name, ``<task>-reading-<reading>``, so their runs appear here with that
    ``task``; ``final-scores.csv`` holds only the presets' runs.

    Columns: ``task``, ``method``, ``role``, ``kind``, ``seed``, ``episodes``, ``key`` (the
    run's key in the store), ``pretrain_env_steps``, ``total_env_steps``, ``optimum_steps``
    (None when unknown), ``greedy_reached`` and ``greedy_steps`` (the greedy evaluation after
    training); then the per-episode curves, each cell one numpy array of that run's training
    episodes: ``steps``, ``task_return``, ``learning_return``, ``reached``, ``collisions``,
    ``env_steps`` (cumulative, pre-training included), and the robot's ``time``,
    ``average_reward``, ``time_to_reach`` and ``retention_time`` (NaN on a maze, and
    ``time_to_reach`` NaN for an episode that did not reach). ``numpy.stack`` of a method's
    ``steps`` gives a seeds × episodes matrix.

    Returns a pandas ``DataFrame`` (``dataframe=False``: a dict of columns, per-run columns
    as lists). A stored entry that fails its checks is skipped with a ``RuntimeWarning``.

    Raises:
        TypeError: ``dir`` is not a path.
        FileNotFoundError: ``dir`` does not exist.
        ValueError: ``dir`` is neither an output folder of the main job (no ``runs/``) nor a
            run store, or the store cannot be read.
        ImportError: pandas is not installed and ``dataframe`` is true.
        KeyboardInterrupt: on Ctrl-C while a large store is read.
    """
    root = folder(dir)
    dataframe = _args.check_bool(dataframe, "dataframe")
    columns, problems = _native.load_runs(os.fspath(root))
    columns = {
        name: [signed(v) for v in values] if _is_curve(values) else values
        for name, values in columns.items()
    }
    for problem in problems:
        warnings.warn(f"run store of {os.fspath(root)!r}: {problem}", RuntimeWarning, stacklevel=2)
    if not dataframe:
        return columns
    pandas = _pandas("load runs as a DataFrame")
    frame = pandas.DataFrame({name: values for name, values in columns.items() if not _is_curve(values)})
    for name, values in columns.items():
        if _is_curve(values):
            frame[name] = pandas.Series(values, dtype=object)
    frame = frame[list(columns)]
    for name in ("seed", "episodes", "pretrain_env_steps", "total_env_steps", "greedy_steps"):
        frame[name] = frame[name].astype("int64")
    frame["optimum_steps"] = pandas.array(columns["optimum_steps"], dtype="Int64")
    frame["greedy_reached"] = frame["greedy_reached"].astype(bool)
    return frame


def signed(values: npt.NDArray[Any]) -> npt.NDArray[Any]:
    """A ``uint64`` array (Rust's counts) as ``int64`` when every value fits, so that
    differences and means behave as numpy users expect; other arrays unchanged."""
    if values.dtype == numpy.uint64 and (values.size == 0 or values.max() < 2**63):
        return values.astype(numpy.int64)
    return values


def _is_curve(values: List[Any]) -> bool:
    return bool(values) and isinstance(values[0], numpy.ndarray)
