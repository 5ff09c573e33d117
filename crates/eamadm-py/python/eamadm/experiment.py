"""The paper's experiments from Python, computed by the Rust runner.

A config is the Rust runner's TOML schema: a :class:`Config` (``Config.from_toml(text)``,
``Config.from_file(path)``, ``Config.from_dict(d)``, or :func:`paper_config`), a dict of that
schema, or the path of a ``.toml`` file (a ``str`` or ``os.PathLike``: a string is always a
path, never TOML text). :func:`run` returns the same numbers ``cargo xtask reproduce-paper``
stores in ``runs/`` and writes to ``final-scores.csv`` for the same config and seeds, bit for
bit; ``<task>/curves.csv.gz`` writes the same curves with its reals at single precision.
"""

from __future__ import annotations

import json
import math
import sys
from typing import (
    Any,
    Callable,
    Dict,
    Iterable,
    List,
    Literal,
    Mapping,
    NamedTuple,
    Optional,
    Tuple,
    Union,
    final,
    overload,
)

import numpy

from eamadm import _args, _native, outputs


@final
class Config:
    """An experiment config, checked by the Rust runner: its task loads, every method fits it.

    Make one with :meth:`from_toml` (TOML text), :meth:`from_file` (a ``.toml`` file),
    :meth:`from_dict` (a dict of the same schema) or :func:`paper_config`. ``Config(text)`` is
    ``Config.from_toml(text)``. It pickles, compares equal to a config with the same settings
    (however written: defaults spelled out or not, keys in any order), and :meth:`to_toml` /
    :meth:`to_dict` give it back.

    Raises:
        TypeError: ``text`` is not a str.
        ValueError: the text is not a valid config (the message names the field).
    """

    __slots__ = ("_toml", "_canonical")

    def __init__(self, text: str) -> None:
        if not isinstance(text, str):
            raise TypeError(f"config: expected TOML text (a str), got {_args.type_name(text)}")
        _native.check_config(text)
        self._toml = text
        self._canonical: Optional[str] = None

    def _settings(self) -> str:
        """The config as the Rust runner writes it (every default spelled out): what
        equality compares."""
        if self._canonical is None:
            self._canonical = _native.config_from_json(_native.toml_to_json(self._toml))
        return self._canonical

    @classmethod
    def from_toml(cls, text: str) -> Config:
        """The config of the TOML text ``text``.

        Raises:
            TypeError: ``text`` is not a str.
            ValueError: naming the field (and the line of ``text``) that is wrong.
        """
        return cls(text)

    @classmethod
    def from_file(cls, path: _args.PathLike) -> Config:
        """The config in the TOML file ``path`` (a ``str`` or ``os.PathLike``).

        Raises:
            TypeError: ``path`` is not a path.
            FileNotFoundError: there is no such file.
            ValueError: the file cannot be read, or is not a valid config (naming the field).
        """
        return cls(_args.read_text(path, "config"))

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Config:
        """The config of a dict of the TOML schema (as :meth:`to_dict` gives); numpy scalars
        are taken as Python numbers, tuples as lists, ``None`` as an absent key.

        Raises:
            TypeError: ``data`` is not a mapping, or holds a key that is not a str or a value
                no TOML type holds (the message names its key).
            ValueError: a value is wrong (the message names its key, as written in ``data``).
        """
        if not isinstance(data, Mapping):
            raise TypeError(f"config: expected a dict, got {_args.type_name(data)}")
        plain = _plain(data, "")
        return cls(_native.config_from_json(json.dumps(plain, allow_nan=False)))

    def to_toml(self) -> str:
        """The config as TOML text."""
        return self._toml

    def to_dict(self) -> Dict[str, Any]:
        """The config as a dict of the TOML schema (edit it and make a config again with
        :meth:`from_dict`, or pass it to :func:`run`)."""
        data: Dict[str, Any] = json.loads(_native.toml_to_json(self._toml))
        return data

    @property
    def name(self) -> str:
        """The experiment's name (its output folder, the ``task`` column)."""
        return str(self.to_dict()["name"])

    def shortened(self, *, episodes: Optional[int] = None, quick: bool = False) -> Config:
        """This config shortened as :func:`run`'s ``episodes=`` and ``quick=`` shorten it (the
        Rust ``ExperimentConfig::shortened``, which ``cargo xtask reproduce-paper --quick``
        uses): see :func:`run`.

        Raises:
            TypeError: ``episodes`` is not an int, or ``quick`` not a bool.
            ValueError: ``episodes`` is below 1 or above the config's own.
        """
        count = None if episodes is None else _args.check_int(episodes, "episodes", minimum=1)
        text = _native.shortened_config(self._toml, count, _args.check_bool(quick, "quick"))
        return Config(text)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Config) and other._settings() == self._settings()

    def __hash__(self) -> int:
        return hash(self._settings())

    def __repr__(self) -> str:
        return f"<eamadm.Config {self.name!r}>"

    def __getstate__(self) -> str:
        return self._toml

    def __setstate__(self, state: str) -> None:
        _native.check_config(state)
        self._toml = state
        self._canonical = None


def _plain(value: Any, path: str) -> Any:
    """``value`` as JSON-ready Python data; a ``TypeError`` naming the key ``path`` for what
    no TOML type holds."""
    where = path or "the config"
    if isinstance(value, Mapping):
        out = {}
        for key, item in value.items():
            if not isinstance(key, str):
                raise TypeError(f"config: `{where}` has a key that is not a str: {key!r}")
            if item is None:
                continue
            out[key] = _plain(item, f"{path}.{key}" if path else key)
        return out
    if isinstance(value, (list, tuple)):
        return [_plain(item, f"{path}[{index}]") for index, item in enumerate(value)]
    if isinstance(value, (bool, numpy.bool_)):
        return bool(value)
    if isinstance(value, (int, numpy.integer)):
        return int(value)
    if isinstance(value, (float, numpy.floating)):
        if not math.isfinite(float(value)):
            raise ValueError(f"config: `{where}` = {value}: expected a finite number")
        return float(value)
    if isinstance(value, str):
        return value
    raise TypeError(
        f"config: `{where}` is a {_args.type_name(value)}: expected a dict, list, str, int, "
        "float or bool"
    )


#: What :func:`run` takes as a config.
ConfigLike = Union[Config, Mapping[str, Any], _args.PathLike]


def as_config(config: object) -> Config:
    """``config`` (a :class:`Config`, a dict, or a path) as a :class:`Config`.

    Raises:
        TypeError: ``config`` is none of these.
        FileNotFoundError: a path that names no file.
        ValueError: the config is not valid (naming the field).
    """
    if isinstance(config, Config):
        return config
    if isinstance(config, Mapping):
        return Config.from_dict(config)
    if isinstance(config, str) and "\n" in config:
        raise FileNotFoundError(
            "config: a str names a TOML file, and this one looks like TOML text: give "
            "eamadm.Config.from_toml(text) instead"
        )
    if isinstance(config, (str, bytes)) or hasattr(config, "__fspath__"):
        return Config.from_file(config)
    raise TypeError(
        "config: expected an eamadm.Config, a dict or a path (str or os.PathLike), got "
        f"{_args.type_name(config)}"
    )


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
    report_input: Optional[Tuple[str, str]] = None
    #: The runs' figures as the main job draws them: ``(path, SVG text)`` pairs, paths
    #: ``<experiment>/<file>.svg`` (what :func:`eamadm.figures` returns for these results).
    figure_files: Optional[List[Tuple[str, str]]] = None


@overload
def paper_config(name: str, *, as_dict: Literal[False] = ...) -> Config: ...


@overload
def paper_config(name: str, *, as_dict: Literal[True]) -> Dict[str, Any]: ...


def paper_config(name: str, *, as_dict: bool = False) -> Union[Config, Dict[str, Any]]:
    """The paper's preset ``"task1"``, ``"task2"``, ``"robot"`` or ``"robot-paper-state"``
    (Tables 1 and 2), or the positive control ``"aggregation-control"`` (a maze on which
    combining sub-tasks should help; paper-notes §21), as a :class:`Config`, or as a dict when
    ``as_dict`` is true (edit it and pass it to :func:`run`).

    Raises:
        TypeError: ``name`` is not a str.
        ValueError: ``name`` is not one of the five presets.
    """
    if not isinstance(name, str):
        raise TypeError(f"name: expected a str, got {_args.type_name(name)}")
    config = Config(_native.paper_config_toml(name))
    return config.to_dict() if _args.check_bool(as_dict, "as_dict") else config


def paper_tasks() -> List[str]:
    """The names of the paper's presets, in the order the main job runs them."""
    return list(_native.paper_tasks())


def _seeds(seeds: object) -> Tuple[Optional[List[int]], Optional[int]]:
    """``seeds=`` as (explicit seeds, a count)."""
    if seeds is None:
        return None, None
    if _args.is_int(seeds):
        return None, _args.check_int(seeds, "seeds", minimum=1, maximum=2**32 - 1)
    if isinstance(seeds, (str, bytes, bool)) or not hasattr(seeds, "__iter__"):
        raise TypeError(
            f"seeds: expected an int (a count) or an iterable of ints, got {_args.type_name(seeds)}"
        )
    values = [_args.check_int(seed, "seeds", maximum=2**64 - 1) for seed in seeds]
    if not values:
        raise ValueError("seeds: expected at least one seed")
    return values, None


def _methods(methods: object) -> Optional[List[str]]:
    if methods is None:
        return None
    if isinstance(methods, (str, bytes)) or not hasattr(methods, "__iter__"):
        raise TypeError(
            f"methods: expected an iterable of labels (str), got {_args.type_name(methods)}"
        )
    labels = list(methods)
    for label in labels:
        if not isinstance(label, str):
            raise TypeError(f"methods: expected str labels, got {_args.type_name(label)} {label!r}")
    return labels


#: A progress callback: called with (runs done, runs in all) after each finished run.
Progress = Callable[[int, int], object]


def _progress(progress: object, name: str) -> Tuple[Optional[Progress], Callable[[], None]]:
    """The callback of ``progress=`` and what closes it: a tqdm bar (or a plain line on
    stderr without tqdm) for ``True``, the user's callable as given."""
    if progress is None or progress is False:
        return None, lambda: None
    if progress is True:
        try:
            from tqdm import tqdm
        except ImportError:
            state = {"shown": False}

            def line(done: int, total: int) -> None:
                state["shown"] = True
                sys.stderr.write(f"\r{name}: {done}/{total} runs")
                sys.stderr.flush()

            def end_line() -> None:
                if state["shown"]:
                    sys.stderr.write("\n")
                    sys.stderr.flush()

            return line, end_line
        bars: List[Any] = []

        def bar(done: int, total: int) -> None:
            if not bars:
                bars.append(tqdm(total=total, desc=name, unit="run"))
            bars[0].update(done - bars[0].n)

        def close() -> None:
            for each in bars:
                each.close()

        return bar, close
    if callable(progress):
        return progress, lambda: None
    raise TypeError(
        f"progress: expected True, False or a callable (done, total), got {_args.type_name(progress)}"
    )


def run(
    config: ConfigLike,
    *,
    seeds: Union[int, Iterable[int], None] = None,
    episodes: Optional[int] = None,
    quick: bool = False,
    methods: Optional[Iterable[str]] = None,
    threads: Optional[int] = None,
    progress: Union[bool, Progress] = False,
    dataframe: bool = True,
) -> Results:
    """Runs ``config`` on the Rust runner, with Python's GIL released; Ctrl-C stops it within
    a fraction of a second (``KeyboardInterrupt``; runs already started finish on their
    threads and are discarded).

    Args:
        config: a :class:`Config`, a dict of the TOML schema, or the path of a TOML file
            (``str`` or ``os.PathLike``; TOML text goes through :meth:`Config.from_toml`).
        seeds: an int ``n`` runs the config's first ``n`` seeds (``base_seed + i`` for
            ``i < n``); an iterable runs exactly those seeds, e.g. ``range(3)``; default: the
            config's own ``seeds`` (with ``quick``, at most 3 of them).
        episodes: at most this many training episodes per run (at most the config's own): the
            episodes part of the Rust ``ExperimentConfig::shortened``, the one rule
            ``--quick`` uses: pre-training gets at most as many episodes, a competitor's
            warm-up budget shrinks in proportion, trajectory episodes past the end are dropped.
            The step cap stays the config's.
        quick: shorten exactly as ``cargo xtask reproduce-paper --quick`` does
            (``Shortening::QUICK``): at most 30 episodes as above, maze episodes capped at 500
            steps, warm-ups at most 1 000 000 steps, and 3 seeds unless ``seeds`` is given.
            ``run(paper_config("task1"), quick=True)`` equals the ``--quick`` run's Task I.
        methods: the labels of the methods to run (default: all, in the config's order).
        threads: worker threads (default: one per core). Results do not depend on it.
        progress: ``True`` shows a progress bar (tqdm when installed, else a line on
            stderr); a callable is called with ``(runs done, runs in all)`` after each run
            (an exception it raises stops the call).
        dataframe: return pandas DataFrames when pandas is installed (``False``: dicts of
            numpy arrays, one per column).

    Returns:
        :class:`Results` ``(curves, final_scores)``, runs in job order: method by method,
        seed by seed.

    Raises:
        TypeError: an argument of the wrong type (``run(42)``, ``episodes="ten"``).
        FileNotFoundError: ``config`` names no file.
        ValueError: a value out of range or a config that is not valid, naming the argument
            (``config``: the key as the config writes it).
        KeyboardInterrupt: on Ctrl-C (nothing is written).
    """
    checked = as_config(config)
    count = None if episodes is None else _args.check_int(episodes, "episodes", minimum=1)
    quick = _args.check_bool(quick, "quick")
    explicit, seed_count = _seeds(seeds)
    labels = _methods(methods)
    workers = None if threads is None else _args.check_int(threads, "threads", minimum=1)
    dataframe = _args.check_bool(dataframe, "dataframe")
    callback, close = _progress(progress, checked.name)
    try:
        columns = _native.run_config(
            checked.to_toml(), explicit, labels, workers, count, quick, seed_count, callback
        )
    finally:
        close()
    curves = {
        name: outputs.signed(values)
        if isinstance(values, numpy.ndarray)
        else numpy.array(values, dtype=object)
        for name, values in columns["curves"].items()
    }
    fields = outputs.fields(outputs.data_package(), "final-scores")
    scores = outputs.typed_columns(columns["final_scores"], fields)
    report_input = columns["report_input"]
    figure_files = columns["figure_files"]
    if dataframe:
        try:
            import pandas
        except ImportError:
            pass
        else:
            results = _RunResults(pandas.DataFrame(curves), outputs.as_frame(scores, fields))
            results.report_input = report_input
            results.figure_files = figure_files
            return results
    results = _RunResults(curves, outputs.as_arrays(scores, fields))
    results.report_input = report_input
    results.figure_files = figure_files
    return results
