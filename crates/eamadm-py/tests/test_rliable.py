"""``eamadm.rliable_scores``: final scores in rliable's shape, ``{method: runs × tasks}``."""

import os

import numpy
import pytest

import eamadm
from test_experiment import small_task1


def _rliable():
    try:
        from rliable import library, metrics
    except ImportError:
        if os.environ.get("CI") == "true":
            raise
        pytest.skip("rliable is not installed (pip install -r crates/eamadm-py/requirements-test.txt)")
    return library, metrics


def test_the_folders_scores_are_runs_by_tasks(quick_out):
    scores = eamadm.rliable_scores(quick_out, "final_return")
    table = eamadm.read_scores(quick_out).final_scores
    tasks = list(dict.fromkeys(table["task"]))
    # By default, the methods run on every task: the paper's four.
    assert {"ea-madm", "epsilon-greedy", "epsilon-decreasing", "softmax"} <= set(scores)
    for method, matrix in scores.items():
        rows = table[table["method"] == method]
        seeds = sorted(set(rows["seed"]))
        assert matrix.dtype == numpy.float64
        assert matrix.shape == (len(seeds), len(tasks))
        for i, seed in enumerate(seeds):
            for j, task in enumerate(tasks):
                cell = rows[(rows["seed"] == seed) & (rows["task"] == task)]["final_return"]
                assert matrix[i, j] == float(cell.iloc[0])


def test_tasks_methods_and_normalisation(quick_out):
    both = eamadm.rliable_scores(quick_out, "final_steps", tasks=["task1", "task2"])
    assert "subtask0-alone" in both  # a maze control runs on both mazes
    raw = both["ea-madm"]
    scaled = eamadm.rliable_scores(
        quick_out,
        "final_steps",
        {"task1": (500.0, 58.0), "task2": (500.0, 70.0)},
        methods=["ea-madm"],
        tasks=["task1", "task2"],
    )
    assert list(scaled) == ["ea-madm"]
    numpy.testing.assert_allclose(scaled["ea-madm"][:, 0], (raw[:, 0] - 500.0) / (58.0 - 500.0))
    numpy.testing.assert_allclose(scaled["ea-madm"][:, 1], (raw[:, 1] - 500.0) / (70.0 - 500.0))


def test_results_of_run_give_the_same_shape():
    results = eamadm.run(small_task1(episodes=3, seeds=3), methods=["softmax", "ea-madm"])
    scores = eamadm.rliable_scores(results, "final_steps")
    assert list(scores) == ["softmax", "ea-madm"]
    assert all(matrix.shape == (3, 1) for matrix in scores.values())
    plain = eamadm.run(small_task1(episodes=3, seeds=3), methods=["softmax"], dataframe=False)
    numpy.testing.assert_array_equal(eamadm.rliable_scores(plain, "final_steps")["softmax"], scores["softmax"])
    # A nullable column's missing values (pandas' NA, numpy's NaN) are blanks, named as such.
    assert results.final_scores["collapse_episode"].isna().any()
    for source in (results, plain):
        with pytest.raises(ValueError, match="^metric: 'collapse_episode' is blank"):
            eamadm.rliable_scores(source, "collapse_episode")


def test_scores_feed_rliables_interval_estimates(quick_out):
    library, metrics = _rliable()
    scores = eamadm.rliable_scores(quick_out, "final_return", tasks=["task1", "task2"])

    def iqm(matrix):
        return numpy.array([metrics.aggregate_iqm(matrix)])

    estimates, intervals = library.get_interval_estimates(scores, iqm, reps=200)
    assert set(estimates) == set(scores)
    for method in scores:
        low, high = intervals[method][:, 0]
        assert low <= estimates[method][0] <= high


@pytest.mark.parametrize(
    "kwargs, error, argument",
    [
        ({"metric": "method"}, ValueError, "metric"),
        ({"metric": "no_such"}, ValueError, "metric"),
        ({"metric": 3}, TypeError, "metric"),
        ({"metric": "final_return", "tasks": ["task9"]}, ValueError, "tasks"),
        ({"metric": "final_return", "tasks": "task1"}, TypeError, "tasks"),
        ({"metric": "final_return", "methods": ["subtask0-alone"]}, ValueError, "methods"),
        ({"metric": "final_return", "normalise": {"task1": (0, 1)}}, ValueError, "normalise"),
        ({"metric": "final_return", "normalise": [1, 2]}, TypeError, "normalise"),
        ({"metric": "reach_time", "tasks": ["task1"]}, ValueError, "metric"),
    ],
)
def test_bad_arguments_name_themselves(quick_out, kwargs, error, argument):
    with pytest.raises(error, match=f"^{argument}: "):
        eamadm.rliable_scores(quick_out, **kwargs)


def test_a_folder_that_is_not_an_output_folder_is_refused(tmp_path):
    with pytest.raises(FileNotFoundError, match="^dir: "):
        eamadm.rliable_scores(tmp_path / "missing", "final_return")
    with pytest.raises(ValueError, match="^dir: .*final-scores.csv"):
        eamadm.rliable_scores(tmp_path, "final_return")
    with pytest.raises(TypeError, match="^source: "):
        eamadm.rliable_scores(42, "final_return")
