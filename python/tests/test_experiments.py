"""The experiments from Python write what the command line writes."""

import json
import os
import pathlib
import tempfile
import warnings

import pytest

import vascsim

# The ball of pressed-block.json 7 mm above its path: its motion never reaches the block.
BALL_AWAY = {"obstacles.0.centre_m": [0.0015, 0.0015, 0.01]}


def test_run_writes_the_summary_of_the_command_line(block_path, tmp_path):
    seen = []
    summary = vascsim.run(vascsim.load_scene(block_path), tmp_path, on_step=lambda r, total: seen.append((r["step"], total)))
    assert seen == [(0, 4), (1, 4), (2, 4), (3, 4), (4, 4)]  # the rest state, then the 4 load steps
    assert summary == json.loads((tmp_path / "summary.json").read_text())
    assert summary["unconverged_steps"] == 0 and (tmp_path / "probes.csv").exists()


def test_a_callback_error_stops_the_experiment(block_path, tmp_path):
    def stop(record, total):
        raise KeyError("stop here")
    with pytest.raises(KeyError, match="stop here"):
        vascsim.force_displacement(vascsim.load_scene(block_path), tmp_path, on_step=stop)


def test_force_displacement_needs_a_moving_tool(vessel_path, tmp_path):
    with pytest.raises(vascsim.InputError, match="the scene has no tool"):
        vascsim.force_displacement(vascsim.load_scene(vessel_path), tmp_path)


def test_compare_models_checks_its_model_list(block_path, tmp_path):
    with pytest.raises(vascsim.InputError):
        vascsim.compare_models(block_path, [], tmp_path)


def test_run_issues_every_warning_of_its_summary(block_path, tmp_path):
    scene = vascsim.load_scene(block_path, overrides=BALL_AWAY)
    with pytest.warns(vascsim.VascsimWarning) as caught:
        summary = vascsim.run(scene, tmp_path)
    issued = [str(w.message) for w in caught if w.category is vascsim.VascsimWarning]
    assert len(summary["warnings"]) >= 2  # the ball cannot reach the block; it never touched it
    assert set(summary["warnings"]) <= set(issued)
    assert len(issued) == len(set(issued))  # each once, though the run both logs and lists some
    # They name the caller's line, not the package's.
    assert all(w.filename == __file__ for w in caught if w.category is vascsim.VascsimWarning)


def test_a_warning_the_filter_makes_an_error_stops_the_experiment(block_path, tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error", vascsim.VascsimWarning)
        with pytest.raises(vascsim.VascsimWarning, match="'ball'"):
            vascsim.force_displacement(vascsim.load_scene(block_path, overrides=BALL_AWAY), tmp_path)


def test_force_displacement_writes_to_a_new_temporary_folder_by_default(block_path, tmp_path, monkeypatch):
    cwd, temp = tmp_path / "cwd", tmp_path / "temp"
    cwd.mkdir()
    temp.mkdir()
    monkeypatch.chdir(cwd)  # as from the checkout's root: nothing may land here
    monkeypatch.setattr(tempfile, "tempdir", str(temp))
    result = vascsim.force_displacement(vascsim.load_scene(block_path))
    assert os.listdir(cwd) == []
    out = pathlib.Path(result["out_dir"])
    assert out.parent == temp and out.name.startswith("vascsim-force-displacement-")
    assert pathlib.Path(result["csv"]) == out / "force_displacement.csv" and (out / "summary.json").exists()
    # A second call gets a folder of its own.
    assert vascsim.force_displacement(vascsim.load_scene(block_path))["out_dir"] != result["out_dir"]


def test_the_fig10_example_describes_itself_whole_in_its_help():
    import subprocess
    import sys
    example = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python" / "fig10_force_displacement.py"
    p = subprocess.run([sys.executable, example, "--help"], capture_output=True, text=True, check=True)
    assert "the force on it is drawn against its travel." in " ".join(p.stdout.split())
