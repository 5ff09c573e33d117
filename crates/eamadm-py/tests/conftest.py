"""Shared helpers of the eamadm test suite."""

import os
import pathlib
import subprocess

import pytest

#: The workspace root (crates/eamadm-py/tests -> ../../..).
ROOT = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture(scope="session")
def xtask():
    """A command list running the Rust tooling: the binary `cargo xtask test` runs from, or
    `cargo run -p xtask --release --` when pytest is started by hand."""
    exe = os.environ.get("EAMADM_XTASK")
    if exe:
        return [exe]
    return ["cargo", "run", "--quiet", "-p", "xtask", "--release", "--"]


def run_xtask(xtask, *args):
    """Runs the tooling in the workspace root; fails the test with its output on error."""
    done = subprocess.run(
        [*xtask, *args], cwd=ROOT, capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return done


@pytest.fixture(scope="session")
def quick_out(tmp_path_factory, xtask):
    """An output folder of the main job's `--quick` plan, made once per session, at
    `<tmp>/target/reproduce-paper` (the README's examples read `target/reproduce-paper` from
    the folder they run in)."""
    out = tmp_path_factory.mktemp("main-job") / "target" / "reproduce-paper"
    run_xtask(xtask, "reproduce-paper", "--quick", "--out", str(out))
    return out
