"""Reading the main job's output folder: the run store, the typed tables, the data package."""

import csv
import math

import numpy
import pytest

import eamadm


def csv_rows(path):
    with open(path, newline="", encoding="utf-8") as file:
        return list(csv.DictReader(file))


def fields(resource):
    package = eamadm.data_package()
    entry = next(e for e in package["resources"] if e["name"] == resource)
    return entry["schema"]["fields"]


def test_the_folder_carries_the_library_package(quick_out):
    assert (quick_out / "datapackage.json").is_file()
    assert eamadm.data_package(quick_out) == eamadm.data_package()
    for resource in eamadm.data_package()["resources"]:
        with open(quick_out / resource["path"], newline="", encoding="utf-8") as file:
            header = next(csv.reader(file))
        assert header == [field["name"] for field in resource["schema"]["fields"]]
        for field in resource["schema"]["fields"]:
            assert field["description"], field["name"]
            assert field["type"] in ("string", "integer", "number", "boolean")


def test_frictionless_validates_the_package(quick_out):
    import frictionless
    report = frictionless.validate(str(quick_out / "datapackage.json"))
    assert report.valid, report.flatten(["resourceName", "rowNumber", "fieldName", "type", "note"])


@pytest.mark.parametrize("resource, index", [("final-scores", 0), ("claims", 1)])
def test_read_scores_types_every_column(quick_out, resource, index):
    table = eamadm.read_scores(quick_out)[index]
    rows = csv_rows(quick_out / f"{resource}.csv")
    assert len(table) == len(rows) > 0
    for field in fields(resource):
        name, kind = field["name"], field["type"]
        column = table[name]
        required = field.get("constraints", {}).get("required", False)
        blanks = [row[name] == "" for row in rows]
        # A column without a "blank when" rule is never blank.
        assert not (required and any(blanks)), name
        assert list(column.isna()) == blanks, name
        if kind == "integer":
            assert str(column.dtype) in ("int64", "Int64"), (name, column.dtype)
            for value, row in zip(column, rows):
                if row[name]:
                    assert value == int(row[name]), name
        elif kind == "number":
            assert column.dtype == numpy.float64, name
            for value, row in zip(column, rows):
                if row[name]:
                    assert float(row[name]).hex() == float(value).hex(), name
        elif kind == "boolean":
            assert str(column.dtype) in ("bool", "boolean"), (name, column.dtype)
            for value, row in zip(column, rows):
                if row[name]:
                    assert value == (row[name] == "true"), name
        else:
            for value, row in zip(column, rows):
                if row[name]:
                    assert value == row[name], name
        if "enum" in field.get("constraints", {}):
            assert set(column.dropna()) <= set(field["constraints"]["enum"]), name


def test_step_cap_is_always_filled(quick_out):
    scores = eamadm.read_scores(quick_out).final_scores
    assert scores["step_cap"].notna().all()
    for _, task in scores.groupby("task"):
        assert task["step_cap"].nunique() == 1
    at_cap = scores[scores["final_steps"] == scores["step_cap"]]
    assert (at_cap["success_rate"] == 0).all()


def test_load_runs_has_one_row_per_stored_run_with_numpy_curves(quick_out):
    runs = eamadm.load_runs(quick_out)
    scores = eamadm.read_scores(quick_out).final_scores
    # The readings of the paper rerun some methods under their own experiment names
    # (`<task>-reading-<reading>`); they feed sensitivity.csv, not final-scores.csv.
    reading = runs["task"].str.contains("-reading-")
    assert reading.any()
    assert set(runs[reading]["task"].str.split("-reading-").str[0]) <= set(scores["task"])
    runs = runs[~reading].reset_index(drop=True)
    assert len(runs) == len(scores)
    key = ["task", "method", "seed"]
    assert sorted(map(tuple, runs[key].values.tolist())) == sorted(
        map(tuple, scores[key].values.tolist())
    )
    assert runs["key"].is_unique
    merged = runs.merge(scores, on=key, suffixes=("", "_score"))
    assert len(merged) == len(runs)
    for _, run in merged.iterrows():
        steps = run["steps"]
        assert isinstance(steps, numpy.ndarray) and steps.dtype == numpy.int64
        assert len(steps) == len(run["task_return"]) == run["episodes"]
        assert run["reached"].dtype == bool
        assert (run["role"], run["kind"]) == (run["role_score"], run["kind_score"])
        assert run["env_steps"][-1] == run["total_env_steps"] == run["env_steps_total"]
        assert run["greedy_reached"] == run["greedy_reached_score"]
        window = steps[-run["final_window"] :]
        assert math.isclose(window.mean(), run["final_steps"], rel_tol=1e-12)
        assert math.isclose(run["reached"][-run["final_window"] :].mean(), run["success_rate"])
        if run["task"].startswith("robot"):
            assert not numpy.isnan(run["time"]).any()
        else:
            assert numpy.isnan(run["time"]).all()
    # A method's curves stack into a seeds × episodes matrix.
    first = runs[(runs["task"] == runs["task"].iloc[0]) & (runs["method"] == runs["method"].iloc[0])]
    assert numpy.stack(first["steps"]).shape == (len(first), first["episodes"].iloc[0])


def test_load_runs_without_pandas_gives_lists_and_arrays(quick_out):
    columns = eamadm.load_runs(quick_out, dataframe=False)
    assert isinstance(columns["method"], list)
    assert all(isinstance(steps, numpy.ndarray) for steps in columns["steps"])


@pytest.mark.parametrize(
    "reader", [eamadm.load_runs, eamadm.read_scores, eamadm.data_package, eamadm.report]
)
def test_a_bad_folder_is_named(tmp_path, reader):
    with pytest.raises(FileNotFoundError, match="^dir: "):
        reader(tmp_path / "missing")
    with pytest.raises(TypeError, match="^(dir|results): "):
        reader(42)
    # A folder that is not an output folder of the main job is refused, not read as empty.
    with pytest.raises(ValueError, match="^dir: .*(not an output folder|no REPORT.md)"):
        reader(tmp_path)
    (tmp_path / "file").write_text("x")
    with pytest.raises(ValueError, match="^dir: "):
        reader(tmp_path / "file")


def test_read_scores_names_a_missing_table(tmp_path):
    with pytest.raises(ValueError, match="^dir: .*final-scores.csv"):
        eamadm.read_scores(tmp_path)


def test_the_store_folder_itself_is_read(quick_out):
    assert len(eamadm.load_runs(quick_out / "runs")) == len(eamadm.load_runs(quick_out))
