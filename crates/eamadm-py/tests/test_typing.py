"""The package is typed: ``mypy --strict`` passes on it and on the README's Python examples,
and ``stubtest`` finds the stubs of the Rust module ``eamadm._native`` equal to it.

mypy is pinned in requirements-test.txt; without it (a hand-made virtualenv) these tests skip,
except under ``CI=true``, where a skip would hide a missing check.
"""

import os
import pathlib
import subprocess
import sys

import pytest

from conftest import ROOT
from test_readme import python_snippets

PACKAGE = ROOT / "crates" / "eamadm-py"


def _mypy_available():
    try:
        import mypy  # noqa: F401
    except ImportError:
        if os.environ.get("CI") == "true":
            raise
        pytest.skip("mypy is not installed (pip install -r crates/eamadm-py/requirements-test.txt)")


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    """One mypy cache for the module's runs (numpy, gymnasium and pandas are analysed once)."""
    return tmp_path_factory.mktemp("mypy-cache")


def _run(args, cwd):
    done = subprocess.run(
        [sys.executable, "-m", *args], cwd=cwd, capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stdout + done.stderr
    return done


def test_mypy_strict_passes_on_the_package(cache):
    _mypy_available()
    # The configuration ([tool.mypy] of pyproject.toml) says strict and which files.
    _run(["mypy", "--cache-dir", str(cache)], cwd=PACKAGE)


def test_stubtest_finds_the_stubs_equal_to_the_extension(tmp_path):
    _mypy_available()
    # From an empty folder, so that `eamadm` is the installed package.
    _run(
        ["mypy.stubtest", "eamadm._native", "--mypy-config-file", str(PACKAGE / "pyproject.toml")],
        cwd=tmp_path,
    )


def test_mypy_strict_passes_on_the_readme_examples(tmp_path, cache):
    _mypy_available()
    files = []
    for index, snippet in enumerate(python_snippets()):
        path = tmp_path / f"readme_{index}.py"
        path.write_text(snippet, encoding="utf-8")
        files.append(str(path))
    _run(
        [
            "mypy",
            "--strict",
            "--config-file",
            str(PACKAGE / "pyproject.toml"),
            "--cache-dir",
            str(cache),
            *files,
        ],
        cwd=tmp_path,
    )
