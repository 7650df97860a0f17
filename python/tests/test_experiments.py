"""The experiments from Python write what the command line writes."""

import json

import pytest

import vascsim


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
