"""`eamadm.figures`: the main job's figures, drawn from Python by the main job's code."""

import pytest

import eamadm


def test_figures_of_a_folder_are_its_svg_files(quick_out, tmp_path):
    drawn = eamadm.figures(quick_out)
    on_disk = {
        path.relative_to(quick_out).as_posix(): path.read_text(encoding="utf-8")
        for path in quick_out.rglob("*.svg")
    }
    assert len(on_disk) >= 20
    # The same files, byte for byte: the same runs in the same order through the same code.
    assert sorted(drawn) == sorted(on_disk)
    for path, svg in on_disk.items():
        assert drawn[path] == svg, path
    written = eamadm.figures(quick_out, tmp_path / "again")
    assert written == drawn
    assert (tmp_path / "again" / "task1" / "steps.svg").read_text(encoding="utf-8") == drawn[
        "task1/steps.svg"
    ]


def test_figures_of_runs_are_drawn_with_the_runs():
    config = eamadm.paper_config("task1", as_dict=True)
    config["task"]["step_cap"] = 300
    results = eamadm.run(config, episodes=6, seeds=2, methods=["ea-madm", "softmax"])
    drawn = eamadm.figures(results)
    assert {"task1/steps.svg", "task1/return.svg", "task1/trajectories.svg"} <= set(drawn)
    assert all(svg.startswith("<svg") for svg in drawn.values())


def test_figures_errors_name_the_argument(tmp_path):
    with pytest.raises(ValueError, match="^dir: .*no run store"):
        eamadm.figures(tmp_path)
    (tmp_path / "runs").mkdir()
    with pytest.raises(ValueError, match="^dir: .*report-context.toml"):
        eamadm.figures(tmp_path)
    with pytest.raises(FileNotFoundError, match="^dir: "):
        eamadm.figures(tmp_path / "missing")
    with pytest.raises(TypeError, match="^source: "):
        eamadm.figures([{"curves": []}])
    with pytest.raises(TypeError, match="^source: "):
        eamadm.figures(42)  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="^out: "):
        eamadm.figures(tmp_path, out=3)  # type: ignore[arg-type]
