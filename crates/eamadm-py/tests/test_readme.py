"""Every Python snippet of the README's "Python" section runs."""

import re

import pytest

from conftest import ROOT


def python_snippets():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text.split("\n## Python\n", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```python\n(.*?)```", section, flags=re.DOTALL)


def test_the_readme_has_python_snippets():
    assert len(python_snippets()) >= 3


@pytest.mark.parametrize("index", range(3))
def test_readme_snippet_runs(index, capsys):
    snippet = python_snippets()[index]
    exec(compile(snippet, f"README.md python snippet {index}", "exec"), {"__name__": "readme"})
    assert capsys.readouterr().out.strip()
