"""Every Python snippet of README.md and of the package's README (the wheel's description)
runs (each in a fresh namespace) and prints something."""

import re

import pytest

from conftest import ROOT


#: The READMEs whose Python blocks must run: the project's and the package's.
READMES = (ROOT / "README.md", ROOT / "crates" / "eamadm-py" / "README.md")


def python_snippets():
    snippets = []
    for readme in READMES:
        text = readme.read_text(encoding="utf-8")
        snippets += re.findall(r"^```python\n(.*?)^```$", text, flags=re.DOTALL | re.MULTILINE)
    return snippets


def test_the_readme_has_python_snippets():
    assert len(python_snippets()) >= 3


@pytest.mark.parametrize("index", range(len(python_snippets())))
def test_readme_snippet_runs(index, capsys, monkeypatch, quick_out):
    # The snippets that read the main job's output find it at target/reproduce-paper.
    monkeypatch.chdir(quick_out.parents[1])
    snippet = python_snippets()[index]
    exec(compile(snippet, f"README.md python snippet {index}", "exec"), {"__name__": "readme"})
    assert capsys.readouterr().out.strip()
