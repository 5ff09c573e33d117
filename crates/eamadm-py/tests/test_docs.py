"""``help()`` of every public function of the package says what it raises, and the module docs
describe what exists (no placeholder for a function that has since arrived)."""

import inspect

import pytest

import eamadm
from eamadm import outputs

#: Public callables whose docs must have a Raises section: the package's functions, the
#: classes whose constructors check arguments, and their methods that take input.
FUNCTIONS = [getattr(eamadm, name) for name in eamadm.__all__ if inspect.isfunction(getattr(eamadm, name))]
CHECKED = [
    *FUNCTIONS,
    eamadm.Config,
    eamadm.Config.from_toml,
    eamadm.Config.from_file,
    eamadm.Config.from_dict,
    eamadm.Config.shortened,
    eamadm.MazeEnv,
    eamadm.MazeEnv.reset,
    eamadm.MazeEnv.step,
    eamadm.RobotEnv,
    eamadm.RobotEnv.reset,
    eamadm.RobotEnv.step,
    eamadm.MazeVectorEnv,
    eamadm.MazeVectorEnv.step,
    eamadm.RobotVectorEnv,
    eamadm.RobotVectorEnv.reset,
    eamadm.RobotVectorEnv.step,
]


def test_every_public_function_is_checked():
    names = {function.__name__ for function in FUNCTIONS}
    assert names >= {"run", "paper_config", "load_runs", "read_scores", "data_package", "report", "rliable_scores"}


@pytest.mark.parametrize("item", CHECKED, ids=lambda item: item.__qualname__)
def test_help_says_what_it_raises(item):
    doc = inspect.getdoc(item) or ""
    assert "Raises:" in doc, f"{item.__qualname__} documents no Raises section"
    section = doc.split("Raises:", 1)[1]
    assert "Error" in section, f"{item.__qualname__}: the Raises section names no exception"


def test_the_outputs_module_doc_describes_report_as_it_is():
    assert "A place is kept" not in (outputs.__doc__ or "")
    assert "eamadm.report" in (outputs.__doc__ or "")
