"""Experiments from Python: presets, configs as text or dict, equality with the Rust runner."""

import csv
import gzip
import math

import pytest

import eamadm
from eamadm import _native
from conftest import ROOT, run_xtask


def small_task1(episodes=6, seeds=2):
    """The Task I preset, shortened: few episodes and seeds, step cap 300, short pre-training."""
    config = eamadm.paper_config("task1", as_dict=True)
    config["name"] = "task1-small"
    config["episodes"] = episodes
    config["seeds"] = seeds
    config["task"]["step_cap"] = 300
    for method in config["methods"]:
        if "pretrain" in method:
            method["pretrain"]["episodes"] = episodes
    return config


def test_paper_configs():
    episodes = {"task1": 200, "task2": 200, "robot": 500, "robot-paper-state": 500}
    for name, count in episodes.items():
        text = eamadm.paper_config(name)
        assert isinstance(text, str) and f'name = "{name}"' in text
        as_dict = eamadm.paper_config(name, as_dict=True)
        assert as_dict["name"] == name and as_dict["episodes"] == count
        _native.check_config(text)
    with pytest.raises(ValueError, match="^name: "):
        eamadm.paper_config("task3")


def test_python_run_equals_the_rust_runner_bit_for_bit(tmp_path, xtask):
    config = small_task1()
    config_file = tmp_path / "task1-small.toml"
    config_file.write_text(_native.json_to_toml(__import__("json").dumps(config)))
    out = tmp_path / "out"
    run_xtask(xtask, "reproduce-paper", "--config", str(config_file), "--out", str(out))
    [curves_csv] = list(out.rglob("curves.csv.gz"))
    with gzip.open(curves_csv, "rt", newline="") as file:
        rust_rows = list(csv.DictReader(file))

    ours = eamadm.run(config_file, threads=2, dataframe=False).curves
    runs = len(config["methods"]) * config["seeds"]
    assert len(rust_rows) == len(ours["episode"]) == runs * 6
    for column in ours:
        for i, rust_row in enumerate(rust_rows):
            cell, value = rust_row[column], ours[column][i]
            if value is None:
                assert cell == "", (column, i)
            elif isinstance(value, bool):
                assert cell == str(value).lower(), (column, i)
            elif isinstance(value, float):
                # Shortest round-trip text: equal floats parse to the very same bits.
                assert float(cell).hex() == value.hex(), (column, i, cell, value)
            else:
                assert cell == str(value), (column, i)


def test_dict_and_text_configs_give_the_same_run():
    config = small_task1(episodes=4, seeds=1)
    from_dict = eamadm.run(config, methods=["ea-madm", "softmax"], dataframe=False)
    text = _native.json_to_toml(__import__("json").dumps(config))
    from_text = eamadm.run(text, methods=["ea-madm", "softmax"], threads=1, dataframe=False)
    assert from_dict == from_text
    assert from_dict.finals["method"] == ["ea-madm", "softmax"]


def test_seeds_methods_and_finals():
    config = small_task1(episodes=5, seeds=1)
    result = eamadm.run(config, seeds=[3, 4], methods=["softmax"], window=2)
    curves, finals = result
    assert list(finals["seed"]) == [3, 4]
    assert set(curves["method"]) == {"softmax"}
    for seed in (3, 4):
        run = curves[curves["seed"] == seed]
        expected = run["steps"].iloc[-2:].mean()
        got = finals[finals["seed"] == seed]["final_steps"].iloc[0]
        assert math.isclose(got, expected, rel_tol=1e-12)


def test_pandas_opt_out_returns_column_dicts():
    result = eamadm.run(small_task1(episodes=2, seeds=1), methods=["softmax"], dataframe=False)
    assert isinstance(result.curves, dict) and isinstance(result.finals, dict)
    assert list(result.curves)[:4] == ["experiment", "method", "seed", "episode"]


@pytest.mark.parametrize(
    "kwargs, argument",
    [
        ({"config": 'name = "x"\nepisodes = "many"'}, "config"),
        ({"config": 42}, "config"),
        ({"config": {"name": None}}, "config"),
        ({"methods": ["no-such-method"]}, "methods"),
        ({"methods": "softmax"}, "methods"),
        ({"seeds": [-1]}, "seeds"),
        ({"seeds": 0}, "seeds"),
        ({"seeds": True}, "seeds"),
        ({"episodes": 0}, "episodes"),
        ({"episodes": "ten"}, "episodes"),
        ({"episodes": 2.5}, "episodes"),
        ({"seeds": []}, "seeds"),
        ({"threads": 0}, "threads"),
        ({"window": 0}, "window"),
    ],
)
def test_bad_run_arguments_name_the_argument(kwargs, argument):
    call = {"config": small_task1(episodes=2, seeds=1), **kwargs}
    config = call.pop("config")
    with pytest.raises(ValueError, match=f"^{argument}: "):
        eamadm.run(config, **call)


def test_invalid_field_is_named():
    config = small_task1()
    config["learner"]["alpha"] = 7.0
    with pytest.raises(ValueError, match="learner.alpha"):
        eamadm.run(config)


def test_episodes_and_seeds_shortcuts_equal_editing_the_config():
    config = small_task1(episodes=6, seeds=3)
    by_hand = small_task1(episodes=3, seeds=2)
    shortcut = eamadm.run(config, episodes=3, seeds=2, methods=["ea-madm"], dataframe=False)
    edited = eamadm.run(by_hand, methods=["ea-madm"], dataframe=False)
    assert shortcut == edited
    assert sorted(set(shortcut.finals["seed"])) == [0, 1]
    assert max(shortcut.curves["episode"]) == 2


def test_version_is_the_crates_version():
    manifest = (ROOT / "Cargo.toml").read_text(encoding="utf-8")
    package = manifest.split("[workspace.package]", 1)[1]
    line = next(l for l in package.splitlines() if l.startswith("version"))
    assert eamadm.__version__ == line.split('"')[1]
