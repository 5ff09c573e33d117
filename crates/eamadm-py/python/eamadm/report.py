"""``REPORT.md`` from Python, as the main job writes it.

:func:`report` renders the report with the Rust text the main job uses (``eamadm_present::report``);
nothing of it is re-derived in Python. Given an output folder of ``cargo xtask reproduce-paper``
it judges the claims again from the folder's ``final-scores.csv`` and renders them with the
folder's ``report-context.toml`` (tasks, experiments, figures with captions, the robot's
behaviour) and, for a folder of ``--suite family``, the maze family judged again from
``family/final-scores.csv`` and ``layouts.csv``, so the text equals the folder's ``REPORT.md``
byte for byte. Given results of
:func:`eamadm.run`, it renders the report of those runs with their figures, drawn by the main
job's code (:attr:`Report.figures`; :meth:`Report.save` writes the report and its figures),
opening with what made it (``eamadm.report`` in Python, not the main job's command).
"""

from __future__ import annotations

import csv
import io
import os
from typing import Any, Dict, Iterable, List, NamedTuple, Tuple, Union

from eamadm import _args, _native, outputs
from eamadm.figures import figures as _draw
from eamadm.figures import write as _write
from eamadm.experiment import Results, _RunResults


class Report(NamedTuple):
    """What :func:`report` returns."""

    #: The text of ``REPORT.md``.
    markdown: str
    #: The rows of ``claims.csv`` (every estimate, comparison and verdict; its ``verdict``
    #: column holds the verdicts): a pandas ``DataFrame``, or a list of dicts of strings when
    #: pandas is missing or ``dataframe=False``.
    verdicts: Any
    #: The text of ``claims.csv``.
    claims_csv: str
    #: The text of ``final-scores.csv`` (one row per task, method and seed).
    scores_csv: str
    #: The figures the report shows, ``{path: SVG text}`` (paths relative to the report,
    #: ``<experiment>/<file>.svg``): drawn with the runs of :func:`eamadm.run`; empty for an
    #: output folder, which holds its own (:func:`eamadm.figures` draws them again).
    figures: Dict[str, str] = {}

    def save(self, out: Union[str, "os.PathLike[str]"]) -> None:
        """Writes ``REPORT.md`` and the report's figures into the folder ``out`` (made when
        missing), so that its links resolve."""
        import pathlib

        folder = pathlib.Path(out)
        folder.mkdir(parents=True, exist_ok=True)
        (folder / "REPORT.md").write_text(self.markdown, encoding="utf-8")
        _write(self.figures, folder)


def results_list(results: object) -> List[_RunResults]:
    """One :class:`Results` or an iterable of them, checked, as a list.

    Raises:
        TypeError: ``results`` is not what :func:`eamadm.run` returns, nor a list of it.
        ValueError: the list is empty.
    """
    items = [results] if isinstance(results, Results) else results
    if isinstance(items, (str, bytes)) or not isinstance(items, Iterable):
        raise TypeError(
            "results: expected an output folder, a Results of eamadm.run or a list of them, "
            f"got {_args.type_name(results)}"
        )
    runs: List[_RunResults] = []
    for item in items:
        if not isinstance(item, _RunResults) or item.report_input is None:
            raise TypeError(
                "results: expected what eamadm.run returns (a Results), got "
                f"{_args.type_name(item)}"
            )
        runs.append(item)
    if not runs:
        raise ValueError("results: expected the results of at least one run")
    return runs


def report_inputs(results: object) -> List[Tuple[str, str]]:
    """The Rust report inputs of one :class:`Results` or an iterable of them.

    Raises:
        TypeError: ``results`` is not what :func:`eamadm.run` returns, nor a list of it.
        ValueError: the list is empty.
    """
    return [_input_of(run) for run in results_list(results)]


def _input_of(run: _RunResults) -> Tuple[str, str]:
    # results_list admits only results that carry their report input.
    if run.report_input is None:
        raise TypeError("results: these Results carry no report input (not made by eamadm.run)")
    return run.report_input


def report(
    source: Union[_args.PathLike, Results, Iterable[Results]],
    *,
    quick: bool = False,
    dataframe: bool = True,
) -> Report:
    """The report of an output folder or of runs.

    Args:
        source: the output folder of ``cargo xtask reproduce-paper`` (its ``--out``; the text
            is the folder's ``REPORT.md``), or what :func:`eamadm.run` returned, for one
            experiment or a list of them (one per experiment, in report order).
        quick: for results, mark the report as a ``--quick`` smoke run (a folder's report
            knows whether it was one).
        dataframe: the verdicts as a pandas ``DataFrame`` when pandas is installed (``False``:
            a list of dicts).

    Returns:
        a :class:`Report`: the Markdown text, the verdicts, the ``claims.csv`` and
        ``final-scores.csv`` texts, and for runs their figures (:meth:`Report.save` writes the
        report beside them).

    Raises:
        TypeError: ``source`` is neither a path nor results of :func:`eamadm.run`.
        FileNotFoundError: the folder does not exist.
        ValueError: naming the argument: the folder is not an output folder of the main job
            (or lacks ``report-context.toml``), two results of one experiment, or ``quick``
            given with a folder.
    """
    quick = _args.check_bool(quick, "quick")
    dataframe = _args.check_bool(dataframe, "dataframe")
    figures: Dict[str, str] = {}
    if isinstance(source, (str, os.PathLike)):
        if quick:
            raise ValueError("quick: a folder's report knows whether it was a --quick run")
        markdown, claims, scores = _native.report_of_folder(os.fspath(outputs.folder(source)))
    else:
        runs = results_list(source)
        markdown, claims, scores, _context = _native.report_of_runs(
            [_input_of(run) for run in runs], quick
        )
        figures = _draw(runs)
    verdicts: Any = None
    if dataframe:
        try:
            import pandas
        except ImportError:
            pass
        else:
            verdicts = pandas.read_csv(io.StringIO(claims))
    if verdicts is None:
        verdicts = list(csv.DictReader(io.StringIO(claims)))
    return Report(markdown, verdicts, claims, scores, figures)
