"""``python -m eamadm``: the main job's commands from the package."""

import re
import subprocess
import sys

import pytest

import eamadm
from eamadm import __main__ as cli
from conftest import run_xtask


def python_m(*args, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "eamadm", *args], capture_output=True, text=True, cwd=cwd, check=False
    )


def test_help_lists_the_commands():
    done = python_m("--help")
    assert done.returncode == 0, done.stderr
    for command in ("reproduce", "report", "figures"):
        assert command in done.stdout
    for command in ("reproduce", "report", "figures"):
        sub = python_m(command, "--help")
        assert sub.returncode == 0 and "DIR" in sub.stdout, sub.stderr
    assert python_m("--version").stdout.strip() == f"eamadm {eamadm.__version__}"


def test_the_method_order_is_the_main_jobs():
    order = cli.method_order()
    assert order[:4] == ["ea-madm", "epsilon-greedy", "epsilon-decreasing", "softmax"]
    assert len(order) == len(set(order))


@pytest.fixture(scope="module")
def both_quick_task1(tmp_path_factory, xtask):
    """`--quick --task task1` by the main job and by `python -m eamadm reproduce`."""
    root = tmp_path_factory.mktemp("cli")
    rust, python = root / "rust", root / "python"
    run_xtask(xtask, "reproduce-paper", "--quick", "--task", "task1", "--out", str(rust))
    done = python_m("reproduce", str(python), "--quick", "--task", "task1", "--no-progress")
    assert done.returncode == 0, done.stderr
    return rust, python


def test_reproduce_writes_the_main_jobs_tables_byte_for_byte(both_quick_task1):
    rust, python = both_quick_task1
    for name in ("final-scores.csv", "claims.csv", "datapackage.json"):
        assert (python / name).read_text(encoding="utf-8") == (rust / name).read_text(encoding="utf-8"), name
    report = (python / "REPORT.md").read_text(encoding="utf-8")
    assert report.splitlines()[2].startswith("Made by `python -m eamadm reproduce` --quick")
    assert "cargo xtask reproduce-paper`" not in report.splitlines()[2]
    # The figures the report links are written beside it, drawn by the main job's code from
    # the same runs: the main job's own files.
    linked = re.findall(r"\]\((task1/[^)]+\.svg)\)", report)
    assert "task1/steps.svg" in linked
    for path in linked:
        assert (python / path).read_text(encoding="utf-8") == (rust / path).read_text(encoding="utf-8"), path


def test_figures_draws_the_main_jobs_folder_again(both_quick_task1, tmp_path):
    rust, python = both_quick_task1
    done = python_m("figures", str(rust), "--out", str(tmp_path / "drawn"))
    assert done.returncode == 0, done.stderr
    on_disk = sorted(p.relative_to(rust).as_posix() for p in rust.rglob("*.svg"))
    assert on_disk and on_disk == sorted(
        p.relative_to(tmp_path / "drawn").as_posix() for p in (tmp_path / "drawn").rglob("*.svg")
    )
    for path in on_disk:
        assert (tmp_path / "drawn" / path).read_bytes() == (rust / path).read_bytes(), path
    # A folder of `reproduce` keeps no runs to draw from: it says so.
    done = python_m("figures", str(python))
    assert done.returncode == 1 and "has no run store (runs/)" in done.stderr, done.stderr


def test_report_of_the_reproduced_folder_is_its_report(both_quick_task1):
    _, python = both_quick_task1
    done = python_m("report", str(python))
    assert done.returncode == 0, done.stderr
    assert done.stdout == (python / "REPORT.md").read_text(encoding="utf-8")
    assert eamadm.read_scores(python).final_scores.shape[0] > 0


def test_reproduce_refuses_the_main_jobs_folder(both_quick_task1):
    rust, _ = both_quick_task1
    done = python_m("reproduce", str(rust), "--quick", "--no-progress")
    assert done.returncode == 1 and "choose another folder" in done.stderr


def test_report_and_figures_fail_clearly(tmp_path):
    done = python_m("report", str(tmp_path / "missing"))
    assert done.returncode == 1 and done.stderr.startswith("error: dir: ")
    done = python_m("figures", str(tmp_path))
    assert done.returncode == 1 and done.stderr.startswith("error: dir: "), done.stderr
    assert "no run store" in done.stderr
    done = python_m("figures", str(tmp_path / "missing"))
    assert done.returncode == 1 and done.stderr.startswith("error: dir: "), done.stderr
    assert python_m("reproduce").returncode == 2  # usage: DIR is required
