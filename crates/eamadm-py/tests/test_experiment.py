"""Experiments from Python: presets, configs as text or dict, equality with the Rust runner."""

import csv
import gzip
import math

import numpy
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


def same(a, b):
    """Whether two results of ``run(..., dataframe=False)`` hold equal columns, bit for bit
    (NaN equal to NaN)."""
    for x, y in zip(a, b):
        if list(x) != list(y):
            return False
        for name in x:
            u, v = numpy.asarray(x[name]), numpy.asarray(y[name])
            if u.dtype != v.dtype or u.shape != v.shape:
                return False
            if u.dtype.kind == "f":
                if u.tobytes() != v.tobytes():
                    return False
            elif not (u == v).all():
                return False
    return True


def test_paper_configs():
    episodes = {
        "task1": 200,
        "task2": 200,
        "robot": 500,
        "robot-paper-state": 500,
        "aggregation-control": 200,
    }
    for name, count in episodes.items():
        config = eamadm.paper_config(name)
        assert isinstance(config, eamadm.Config) and config.name == name
        assert f'name = "{name}"' in config.to_toml()
        as_dict = eamadm.paper_config(name, as_dict=True)
        assert as_dict["name"] == name and as_dict["episodes"] == count
        # The same settings, however written (from_dict spells every default out).
        assert eamadm.Config.from_dict(as_dict) == config
        assert eamadm.Config.from_dict(eamadm.Config.from_dict(as_dict).to_dict()) == config
        _native.check_config(config.to_toml())
    assert sorted(episodes) == sorted(eamadm.experiment.paper_tasks())
    with pytest.raises(ValueError, match="^name: "):
        eamadm.paper_config("task3")
    with pytest.raises(TypeError, match="^name: "):
        eamadm.paper_config(1)


# The curves' real columns: single precision in curves.csv.gz, every bit in the run store.
REAL_CURVES = ["task_return", "learning_return", "time", "average_reward", "time_to_reach", "retention_time"]


def test_python_run_equals_the_rust_runner_bit_for_bit(tmp_path, xtask):
    config = small_task1()
    config_file = tmp_path / "task1-small.toml"
    config_file.write_text(eamadm.Config.from_dict(config).to_toml())
    out = tmp_path / "out"
    run_xtask(xtask, "reproduce-paper", "--config", str(config_file), "--out", str(out))
    [curves_csv] = list(out.rglob("curves.csv.gz"))
    with gzip.open(curves_csv, "rt", newline="") as file:
        rust_rows = list(csv.DictReader(file))

    ours = eamadm.run(config_file, threads=2, dataframe=False).curves
    stored_runs = eamadm.load_runs(out, dataframe=False)
    runs = len(config["methods"]) * config["seeds"]
    assert len(rust_rows) == len(ours["episode"]) == runs * 6
    for column in ours:
        values = ours[column]
        assert isinstance(values, numpy.ndarray), column
        for i, rust_row in enumerate(rust_rows):
            cell, value = rust_row[column], values[i]
            if values.dtype == bool:
                assert cell == str(bool(value)).lower(), (column, i)
            elif values.dtype.kind == "f":
                if cell == "":
                    assert math.isnan(value), (column, i)
                else:
                    # The table's reals are single precision, shortest round-trip text: equal
                    # floats parse to the very same f32 bits.
                    read, single = numpy.float32(cell), numpy.float32(value)
                    assert read.tobytes() == single.tobytes(), (column, i, cell, value)
            else:
                assert cell == str(value), (column, i)
        if column in REAL_CURVES:
            # The run store keeps every bit: the same doubles, run after run.
            stored = numpy.concatenate(stored_runs[column])
            assert [float(v).hex() for v in stored] == [float(v).hex() for v in values], column

    # The final scores are the main job's final-scores.csv, byte for byte.
    text = _native.run_config(eamadm.Config.from_dict(config).to_toml())
    assert text["final_scores"] == (out / "final-scores.csv").read_text(encoding="utf-8")


def test_dict_and_text_configs_give_the_same_run():
    config = small_task1(episodes=4, seeds=1)
    from_dict = eamadm.run(config, methods=["ea-madm", "softmax"], dataframe=False)
    text = eamadm.Config.from_toml(eamadm.Config.from_dict(config).to_toml())
    from_text = eamadm.run(text, methods=["ea-madm", "softmax"], threads=1, dataframe=False)
    assert same(from_dict, from_text)
    assert list(from_dict.final_scores["method"]) == ["ea-madm", "softmax"]


def test_seeds_methods_and_final_scores():
    config = small_task1(episodes=25, seeds=1)
    result = eamadm.run(config, seeds=[3, 4], methods=["softmax"])
    curves, final_scores = result
    assert list(final_scores["seed"]) == [3, 4]
    assert set(curves["method"]) == {"softmax"}
    for seed in (3, 4):
        run = curves[curves["seed"] == seed]
        row = final_scores[final_scores["seed"] == seed].iloc[0]
        # The final window is the last 20 episodes, as in the main job's final-scores.csv.
        assert row["final_window"] == 20
        assert math.isclose(row["final_steps"], run["steps"].iloc[-20:].mean(), rel_tol=1e-12)
        assert row["step_cap"] == 300 and row["episodes"] == 25
    # Typed by the data package: ints, booleans, text, and blanks as missing values.
    assert str(final_scores["seed"].dtype) == "int64"
    assert final_scores["greedy_reached"].dtype == bool
    assert str(final_scores["collapse_episode"].dtype) in ("Int64", "int64")
    assert final_scores["reach_time"].isna().all()
    assert curves["steps"].dtype == numpy.int64 and curves["reached"].dtype == bool


def test_pandas_opt_out_returns_column_dicts():
    result = eamadm.run(small_task1(episodes=2, seeds=1), methods=["softmax"], dataframe=False)
    assert isinstance(result.curves, dict) and isinstance(result.final_scores, dict)
    assert list(result.curves)[:4] == ["experiment", "method", "seed", "episode"]
    assert all(isinstance(values, numpy.ndarray) for values in result.curves.values())
    assert all(isinstance(values, numpy.ndarray) for values in result.final_scores.values())
    assert result.final_scores["seed"].dtype == numpy.int64
    assert result.final_scores["greedy_reached"].dtype in (bool, object)
    names = [field["name"] for field in eamadm.data_package()["resources"][0]["schema"]["fields"]]
    assert list(result.final_scores) == names


@pytest.mark.parametrize(
    "kwargs, error, argument",
    [
        ({"config": 42}, TypeError, "config"),
        ({"config": {"name": None}}, ValueError, "config"),
        ({"config": {"name": "x", "episodes": {1, 2}}}, TypeError, "config"),
        ({"config": {3: "x"}}, TypeError, "config"),
        ({"config": 'name = "x"\nepisodes = "many"'}, FileNotFoundError, "config"),
        ({"config": "no-such-file.toml"}, FileNotFoundError, "config"),
        ({"methods": ["no-such-method"]}, ValueError, "methods"),
        ({"methods": "softmax"}, TypeError, "methods"),
        ({"methods": [1]}, TypeError, "methods"),
        ({"seeds": [-1]}, ValueError, "seeds"),
        ({"seeds": 0}, ValueError, "seeds"),
        ({"seeds": True}, TypeError, "seeds"),
        ({"seeds": "3"}, TypeError, "seeds"),
        ({"seeds": [1.5]}, TypeError, "seeds"),
        ({"seeds": []}, ValueError, "seeds"),
        ({"episodes": 0}, ValueError, "episodes"),
        ({"episodes": 3}, ValueError, "episodes"),
        ({"episodes": "ten"}, TypeError, "episodes"),
        ({"episodes": 2.5}, TypeError, "episodes"),
        ({"quick": 1}, TypeError, "quick"),
        ({"threads": 0}, ValueError, "threads"),
        ({"threads": "two"}, TypeError, "threads"),
        ({"dataframe": "no"}, TypeError, "dataframe"),
    ],
)
def test_bad_run_arguments_name_the_argument(kwargs, error, argument):
    call = {"config": small_task1(episodes=2, seeds=1), **kwargs}
    config = call.pop("config")
    with pytest.raises(error, match=f"^{argument}: "):
        eamadm.run(config, **call)


def test_a_str_names_a_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    text = eamadm.Config.from_dict(small_task1(episodes=2, seeds=1)).to_toml()
    (tmp_path / "t1.toml").write_text(text, encoding="utf-8")
    by_name = eamadm.run("t1.toml", methods=["softmax"], dataframe=False)
    by_path = eamadm.run(tmp_path / "t1.toml", methods=["softmax"], dataframe=False)
    by_text = eamadm.run(eamadm.Config.from_toml(text), methods=["softmax"], dataframe=False)
    assert same(by_name, by_path) and same(by_name, by_text)
    assert eamadm.Config.from_file("t1.toml") == eamadm.Config.from_toml(text)


def test_a_dict_configs_errors_name_the_key_the_user_wrote():
    config = small_task1()
    config["episodes"] = "many"
    with pytest.raises(ValueError, match="^config: `episodes`: invalid type") as caught:
        eamadm.run(config)
    assert "line" not in str(caught.value) and "TOML" not in str(caught.value)
    config = small_task1()
    config["methods"][1]["no_such_key"] = 1
    with pytest.raises(ValueError, match=r"^config: `methods\[1\]`.*no_such_key") as caught:
        eamadm.Config.from_dict(config)
    assert "line" not in str(caught.value)
    config = small_task1()
    config["task"]["step_cap"] = 0
    with pytest.raises(ValueError, match="task.step_cap"):
        eamadm.Config.from_dict(config)
    config["task"]["step_cap"] = float("nan")
    with pytest.raises(ValueError, match="^config: `task.step_cap` = nan"):
        eamadm.Config.from_dict(config)


def test_toml_texts_errors_name_the_line_of_that_text():
    with pytest.raises(ValueError, match="^config: .*line 2") as caught:
        eamadm.Config.from_toml('name = "x"\nepisodes = "many"\n')
    assert "episodes" in str(caught.value)
    with pytest.raises(TypeError, match="^config: "):
        eamadm.Config.from_toml(3)


def test_configs_pickle_and_compare():
    import pickle

    config = eamadm.paper_config("task2")
    again = pickle.loads(pickle.dumps(config))
    assert again == config and hash(again) == hash(config) and again.name == "task2"
    assert config != eamadm.paper_config("task1")
    assert "task2" in repr(config)


def test_quick_is_the_main_jobs_quick_run(quick_out):
    # `run(preset, quick=True)` with the main job's method order equals the `--quick` run's
    # rows of final-scores.csv, byte for byte: one definition of `--quick` (Shortening::QUICK).
    from eamadm.__main__ import method_order

    config = eamadm.paper_config("task1")
    labels = [label for label in method_order() if label in {m["label"] for m in config.to_dict()["methods"]}]
    results = eamadm.run(config, quick=True, methods=labels, dataframe=False)
    ours = eamadm.report(results, quick=True).scores_csv.splitlines()
    theirs = (quick_out / "final-scores.csv").read_text(encoding="utf-8").splitlines()
    assert ours[0] == theirs[0]
    assert ours[1:] == [line for line in theirs[1:] if line.startswith("task1,")]
    assert set(results.final_scores["seed"]) == {0, 1, 2}


def test_shortened_says_what_it_shortens():
    preset = eamadm.paper_config("task1")
    quick = preset.shortened(quick=True).to_dict()
    assert quick["episodes"] == 30 and quick["task"]["step_cap"] == 500
    shorter = preset.shortened(episodes=30).to_dict()
    assert shorter["episodes"] == 30 and "step_cap" not in shorter["task"]
    with pytest.raises(ValueError, match="^episodes: 500 is more than the config's 200"):
        preset.shortened(episodes=500)


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
    assert same(shortcut, edited)
    assert sorted(set(shortcut.final_scores["seed"])) == [0, 1]
    assert max(shortcut.curves["episode"]) == 2


def test_version_is_the_crates_version():
    manifest = (ROOT / "Cargo.toml").read_text(encoding="utf-8")
    package = manifest.split("[workspace.package]", 1)[1]
    line = next(l for l in package.splitlines() if l.startswith("version"))
    assert eamadm.__version__ == line.split('"')[1]
