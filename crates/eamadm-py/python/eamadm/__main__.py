"""``python -m eamadm``: the main job's commands for users without Rust, run through the package.

* ``python -m eamadm reproduce DIR [--quick] [--task NAME ...] [--seeds N] [--threads N]``:
  the main job's plan (the paper's presets, their methods in the main job's order) run with
  :func:`eamadm.run`, and written to ``DIR``: ``REPORT.md``, ``final-scores.csv``,
  ``claims.csv``, ``datapackage.json``, ``report-context.toml`` and the report's figures
  (``<experiment>/<file>.svg``, drawn by the main job's code). ``final-scores.csv`` and
  ``claims.csv`` equal ``cargo xtask reproduce-paper``'s byte for byte for the same options;
  the report has no sensitivity to the paper's readings (the main job reruns those), and says
  what made it.
* ``python -m eamadm report DIR [--out FILE]``: the ``REPORT.md`` of an output folder
  (:func:`eamadm.report`), printed or written to ``FILE``.
* ``python -m eamadm figures DIR [--out OUT]``: the figures of an output folder of the main
  job drawn again from its run store (:func:`eamadm.figures`), written into ``OUT`` (default
  ``DIR``).

Exit status: 0 on success, 1 on an error (its message on stderr), 2 on a usage error,
130 on Ctrl-C.
"""

from __future__ import annotations

import argparse
import os
import pathlib
import sys
import tempfile
from typing import List, Optional, Sequence

import eamadm
from eamadm import _native, experiment, outputs
from eamadm.report import report_inputs

#: What the main job keeps in an output folder that this command must not overwrite.
_MAIN_JOB_ENTRIES = ("runs", ".outputs", ".reproduce-paper.lock")


def _write_atomic(path: pathlib.Path, text: str) -> None:
    """Writes ``text`` to ``path`` through a temporary file in the same folder, so a reader
    sees the old file or the new one, never half of it."""
    handle, temporary = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline="") as file:
            file.write(text)
        os.replace(temporary, path)
    except BaseException:
        try:
            os.unlink(temporary)
        except FileNotFoundError:
            pass
        raise


def method_order() -> List[str]:
    """The method labels of the paper's presets in order of first appearance: the order the
    main job runs and lists them in."""
    labels: List[str] = []
    for task in experiment.paper_tasks():
        for method in experiment.paper_config(task, as_dict=True)["methods"]:
            if method["label"] not in labels:
                labels.append(method["label"])
    return labels


def reproduce(arguments: argparse.Namespace) -> int:
    """The ``reproduce`` command."""
    out = pathlib.Path(arguments.dir)
    if out.exists() and not out.is_dir():
        raise ValueError(f"DIR: {arguments.dir!r} is a file, not a folder")
    for entry in _MAIN_JOB_ENTRIES:
        if (out / entry).exists():
            raise ValueError(
                f"DIR: {arguments.dir!r} holds the outputs of `cargo xtask reproduce-paper` "
                f"({entry}): choose another folder"
            )
    tasks = arguments.task or experiment.paper_tasks()
    order = method_order()
    results = []
    for task in tasks:
        config = experiment.paper_config(task)
        labels = [label for label in order if label in {m["label"] for m in config.to_dict()["methods"]}]
        results.append(
            experiment.run(
                config,
                quick=arguments.quick,
                seeds=arguments.seeds,
                methods=labels,
                threads=arguments.threads,
                progress=not arguments.no_progress,
                dataframe=False,
            )
        )
    markdown, claims, scores, context = _native.report_of_runs(
        report_inputs(results), arguments.quick, True
    )
    drawn = eamadm.figures(results)
    out.mkdir(parents=True, exist_ok=True)
    # The figures before the report that links them.
    for path, svg in drawn.items():
        (out / path).parent.mkdir(parents=True, exist_ok=True)
        _write_atomic(out / path, svg)
    for name, text in (
        ("final-scores.csv", scores),
        ("claims.csv", claims),
        (outputs.DATA_PACKAGE, _native.data_package_json()),
        ("report-context.toml", context),
        ("REPORT.md", markdown),
    ):
        _write_atomic(out / name, text)
    print(
        f"wrote {out / 'REPORT.md'}, its tables and {len(drawn)} figures "
        f"({len(results)} experiments)"
    )
    return 0


def show_report(arguments: argparse.Namespace) -> int:
    """The ``report`` command."""
    text = eamadm.report(arguments.dir, dataframe=False).markdown
    if arguments.out is None:
        sys.stdout.write(text)
    else:
        _write_atomic(pathlib.Path(arguments.out), text)
        print(f"wrote {arguments.out}")
    return 0


def figures(arguments: argparse.Namespace) -> int:
    """The ``figures`` command."""
    out = arguments.out if arguments.out is not None else arguments.dir
    drawn = eamadm.figures(arguments.dir, out)
    print(f"drew {len(drawn)} figures into {out}")
    return 0


def _positive(text: str) -> int:
    try:
        value = int(text)
    except ValueError as error:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from error
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {value}")
    return value


def parser() -> argparse.ArgumentParser:
    """The command line."""
    top = argparse.ArgumentParser(
        prog="python -m eamadm",
        description=(
            "EA-MADM's reproduction from Python (the Rust runner inside the package): the main "
            "job's commands for machines without Rust."
        ),
    )
    top.add_argument("--version", action="version", version=f"eamadm {eamadm.__version__}")
    commands = top.add_subparsers(dest="command", required=True, metavar="COMMAND")
    run = commands.add_parser(
        "reproduce",
        help="run the paper's experiments and write REPORT.md and its tables into DIR",
        description=(
            "Runs the main job's plan (the paper's presets, their methods in its order) and "
            "writes REPORT.md, final-scores.csv, claims.csv, datapackage.json and "
            "report-context.toml and the report's figures into DIR; the tables equal "
            "`cargo xtask reproduce-paper`'s byte for byte for the same options. No readings' "
            "sensitivity (the main job's)."
        ),
    )
    run.add_argument("dir", metavar="DIR", help="the output folder (made if missing)")
    run.add_argument(
        "--quick",
        action="store_true",
        help="a smoke run, as `--quick` of the main job: 30 episodes, 3 seeds, maze step cap 500",
    )
    run.add_argument(
        "--task",
        action="append",
        choices=experiment.paper_tasks(),
        help="run only this preset (repeat for more; default: all)",
    )
    run.add_argument("--seeds", type=_positive, help="seeds per method (default 20; 3 with --quick)")
    run.add_argument("--threads", type=_positive, help="worker threads (default: one per core)")
    run.add_argument("--no-progress", action="store_true", help="no progress bar")
    run.set_defaults(handler=reproduce)
    show = commands.add_parser(
        "report",
        help="print REPORT.md of an output folder (judged again from its final-scores.csv)",
        description="Prints (or writes to --out) the REPORT.md of an output folder.",
    )
    show.add_argument("dir", metavar="DIR", help="an output folder of the main job or of `reproduce`")
    show.add_argument("--out", metavar="FILE", help="write the report here instead of printing it")
    show.set_defaults(handler=show_report)
    draw = commands.add_parser(
        "figures",
        help="draw the figures of an output folder of the main job again from its runs",
        description=(
            "Draws the figures of an output folder of `cargo xtask reproduce-paper` again from "
            "its run store (eamadm.figures), byte for byte its own SVG files."
        ),
    )
    draw.add_argument("dir", metavar="DIR", help="an output folder of the main job (with runs/)")
    draw.add_argument("--out", metavar="OUT", help="where to draw them (default: DIR)")
    draw.set_defaults(handler=figures)
    return top


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Runs the command line ``argv`` (default ``sys.argv[1:]``); returns the exit status."""
    arguments = parser().parse_args(argv)
    try:
        status: int = arguments.handler(arguments)
        return status
    except KeyboardInterrupt:
        print("interrupted: nothing was written", file=sys.stderr)
        return 130
    except (OSError, ValueError, TypeError, RuntimeError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
