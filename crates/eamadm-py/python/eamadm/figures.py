"""The main job's figures from Python, drawn by its own Rust code.

:func:`figures` returns the SVG figures of an output folder of ``cargo xtask reproduce-paper``
(drawn again from its run store, byte for byte the folder's own files) or of what
:func:`eamadm.run` returned (drawn when the runs were made), as ``{path: SVG text}`` with
paths ``<experiment>/<file>.svg`` (a folder with ``--suite family`` adds the maze family's
``family/effect-C1.svg`` and ``family/effect-C2.svg``, judged again from its scores), and
writes them into a folder when asked.
"""

from __future__ import annotations

import os
import pathlib
from typing import Dict, Iterable, Optional, Union

from eamadm import _args, _native, outputs
from eamadm.experiment import Results

Source = Union[_args.PathLike, Results, Iterable[Results]]


def _figure_files(results: Source) -> Dict[str, str]:
    """The figures drawn with one :class:`Results` or an iterable of them."""
    items = [results] if isinstance(results, Results) else results
    if isinstance(items, (str, bytes)) or not isinstance(items, Iterable):
        raise TypeError(
            "source: expected an output folder, a Results of eamadm.run or a list of them, "
            f"got {_args.type_name(results)}"
        )
    files: Dict[str, str] = {}
    for item in items:
        drawn = getattr(item, "figure_files", None)
        if not isinstance(item, Results) or drawn is None:
            raise TypeError(
                f"source: expected what eamadm.run returns (a Results), got {_args.type_name(item)}"
            )
        for path, svg in drawn:
            if path in files:
                raise ValueError(
                    f"source: two results draw {path}: run an experiment's methods and seeds in "
                    "one eamadm.run call"
                )
            files[path] = svg
    return files


def write(files: Dict[str, str], out: _args.PathLike) -> None:
    """Writes ``files`` (``{relative path: text}``) under the folder ``out``, making folders.

    Raises:
        TypeError: ``out`` is not a path.
        OSError: a file cannot be written.
    """
    root = pathlib.Path(_args.check_path(out, "out"))
    for path, text in files.items():
        target = root / path
        target.parent.mkdir(parents=True, exist_ok=True)
        target.write_text(text, encoding="utf-8")


def figures(source: Source, out: Optional[_args.PathLike] = None) -> Dict[str, str]:
    """The main job's figures of an output folder or of runs.

    Args:
        source: the output folder of ``cargo xtask reproduce-paper`` (its ``--out``): its
            figures are drawn again from its run store and ``report-context.toml``, the same
            bytes as its SVG files; or what :func:`eamadm.run` returned, for one experiment or
            a list of them.
        out: a folder to write the figures into (``<out>/<experiment>/<file>.svg``; folders
            are made); ``None`` writes nothing.

    Returns:
        ``{path: SVG text}``, paths relative to the output folder.

    Raises:
        TypeError: ``source`` is neither a path nor what :func:`eamadm.run` returns, or
            ``out`` is not a path.
        FileNotFoundError: the folder does not exist.
        ValueError: naming the argument: the folder lacks its run store (``runs/``) or
            ``report-context.toml``, or two results draw the same file.
    """
    if out is not None:
        _args.check_path(out, "out")
    if isinstance(source, (str, os.PathLike)):
        files = dict(_native.figures_of_folder(os.fspath(outputs.folder(source))))
    else:
        files = _figure_files(source)
    if out is not None:
        write(files, out)
    return files
