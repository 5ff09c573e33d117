"""`eamadm.report`: the main job's REPORT.md from its folder, byte for byte, and reports of runs."""

import pytest

import eamadm
from conftest import run_xtask


@pytest.fixture(scope="module")
def quick_folder(tmp_path_factory, xtask):
    """An output folder of `reproduce-paper --quick --task task1 --seeds 2`, made by the Rust tooling."""
    out = tmp_path_factory.mktemp("quick") / "out"
    run_xtask(xtask, "reproduce-paper", "--quick", "--task", "task1", "--seeds", "2", "--out", str(out))
    return out


def test_report_of_a_folder_is_its_report_md(quick_folder):
    report = eamadm.report(quick_folder)
    assert report.markdown == (quick_folder / "REPORT.md").read_text(encoding="utf-8")
    assert report.claims_csv == (quick_folder / "claims.csv").read_text(encoding="utf-8")
    assert report.scores_csv == (quick_folder / "final-scores.csv").read_text(encoding="utf-8")
    # The gallery links figures that exist.
    assert "task1/steps.svg" in report.markdown and (quick_folder / "task1" / "steps.svg").is_file()
    verdicts = eamadm.report(str(quick_folder), dataframe=False).verdicts
    assert verdicts and set(verdicts[0]) >= {"claim", "task", "method", "verdict"}
    assert {row["task"] for row in verdicts} == {"task1"}


def test_a_changed_score_changes_the_report(quick_folder, tmp_path):
    # The report is judged from final-scores.csv, not copied from REPORT.md.
    import shutil

    copy = tmp_path / "copy"
    shutil.copytree(quick_folder, copy)
    (copy / "REPORT.md").write_text("stale", encoding="utf-8")
    lines = (copy / "final-scores.csv").read_text(encoding="utf-8").splitlines(keepends=True)
    header = lines[0].rstrip("\n").split(",")
    column = header.index("final_steps")
    cells = lines[1].rstrip("\n").split(",")
    cells[column] = repr(float(cells[column]) + 1000.0)
    lines[1] = ",".join(cells) + "\n"
    (copy / "final-scores.csv").write_text("".join(lines), encoding="utf-8")
    report = eamadm.report(copy)
    assert report.markdown != (quick_folder / "REPORT.md").read_text(encoding="utf-8")
    assert report.markdown.startswith("# EA-MADM reproduction report")


def test_report_of_runs_draws_its_figures_and_saves_them(tmp_path):
    config = eamadm.paper_config("task1", as_dict=True)
    config["task"]["step_cap"] = 300
    results = eamadm.run(config, episodes=6, seeds=2, methods=["ea-madm", "epsilon-greedy"])
    curves, finals = results  # still a pair
    report = eamadm.report(results, quick=True)
    assert "--quick" in report.markdown
    # The figures are drawn by the main job's code and linked; there are no tables.
    assert "![steps](task1/steps.svg)" in report.markdown
    assert report.figures["task1/steps.svg"].startswith("<svg")
    assert report.figures == eamadm.figures(results)
    assert "curves.csv.gz" not in report.markdown
    assert "No tables were written for `task1`" in report.markdown
    # It opens with what made it, not with the main job's "rerun the command".
    opening = report.markdown.split("\n\n")[1]
    assert opening.startswith("Made by `eamadm.report` from runs of `eamadm.run` in Python --quick")
    assert "cargo xtask" not in opening and "rerun" not in opening
    assert set(report.verdicts["method"]) <= {"ea-madm", "epsilon-greedy"}
    assert report.scores_csv.count("\ntask1,") == 4
    report.save(tmp_path / "saved")
    assert (tmp_path / "saved" / "REPORT.md").read_text(encoding="utf-8") == report.markdown
    assert (tmp_path / "saved" / "task1" / "steps.svg").read_text(encoding="utf-8") == report.figures[
        "task1/steps.svg"
    ]


def test_report_of_robot_runs_has_the_reward_diagnosis():
    # The facts of a report of runs are gathered by the main job's own builder, so a robot's
    # report explains with its sub-task rewards why EA-MADM does not reach (it used to lack
    # the diagnosis).
    config = eamadm.paper_config("robot", as_dict=True)
    results = eamadm.run(config, episodes=3, seeds=1, methods=["ea-madm", "softmax"])
    report = eamadm.report(results)
    assert "The diagnosis: each sub-task's reward definition values" in report.markdown
    assert "paper (Eq. 6–8)" in report.markdown


def test_report_errors_name_the_argument(tmp_path):
    with pytest.raises(ValueError, match="^dir: .*no REPORT.md or final-scores.csv"):
        eamadm.report(tmp_path)
    (tmp_path / "final-scores.csv").write_text("task\n", encoding="utf-8")
    with pytest.raises(ValueError, match="^dir: .*report-context.toml.*rerun"):
        eamadm.report(tmp_path)
    with pytest.raises(TypeError, match="^results: "):
        eamadm.report([{"curves": []}])
    with pytest.raises(FileNotFoundError, match="^dir: "):
        eamadm.report(tmp_path / "missing")
    with pytest.raises(ValueError, match="^results: "):
        eamadm.report([])
    with pytest.raises(ValueError, match="^quick: "):
        eamadm.report(tmp_path, quick=True)


@pytest.fixture(scope="module")
def family_folder(tmp_path_factory, xtask):
    """An output folder of `reproduce-paper --quick --task task2 --readings none --suite family
    --family-size 2`, made by the Rust tooling."""
    out = tmp_path_factory.mktemp("family") / "out"
    run_xtask(
        xtask,
        "reproduce-paper",
        "--quick",
        "--task",
        "task2",
        "--readings",
        "none",
        "--suite",
        "family",
        "--family-size",
        "2",
        "--out",
        str(out),
    )
    return out


def test_report_and_figures_of_a_family_folder_are_its_files(family_folder):
    # The family is judged again from family/final-scores.csv and layouts.csv, as the main job
    # judges it: the same report (with its "The maze family" section) and the same figures.
    report = eamadm.report(family_folder)
    assert report.markdown == (family_folder / "REPORT.md").read_text(encoding="utf-8")
    assert "## The maze family" in report.markdown
    drawn = eamadm.figures(family_folder)
    for name in ("effect-C1.svg", "effect-C2.svg"):
        path = f"family/{name}"
        assert drawn[path] == (family_folder / "family" / name).read_text(encoding="utf-8"), path
