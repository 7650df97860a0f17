"""Simulation: advancing output points, device-driven frames with a tool pose, node positions as NumPy views,
the mapped surface, region and tool forces, the solver's statistics, its progress and warnings."""

import csv
import json
import logging
import warnings

import numpy as np
import pytest

import vascsim
from conftest import run_cli

# The ball of pressed-block.json 7 mm above its path: its motion never reaches the block.
BALL_AWAY = {"obstacles.0.centre_m": [0.0015, 0.0015, 0.01]}


def test_solve_reaches_equilibrium_between_the_tool_and_the_base(block_path):
    sim = vascsim.Simulation(vascsim.load_scene(block_path))
    assert sim.num_steps == 4
    records = sim.solve()
    assert [r["step"] for r in records] == [1, 2, 3, 4]
    assert all(r["converged"] for r in records)
    last = records[-1]
    tool = last["tools"]["ball"]["force_vector_n"]    # the ball's force on the tissue, N
    base = last["regions"]["base"]["force_vector_n"]  # the support's reaction on the tissue, N
    assert tool[2] < 0 and last["tools"]["ball"]["contacts"] > 0
    # Static equilibrium without gravity: the two external forces cancel. The Newton solve stops at a relative
    # residual of 1e-8 (the scene's rel_tolerance); 1e-6 of the force leaves room for the residual's norm.
    assert np.linalg.norm(tool + base) < 1e-6 * np.linalg.norm(tool)
    with pytest.raises(ValueError, match="all 4 output points"):
        sim.advance()


def test_positions_are_a_read_only_view_updated_in_place(block_path):
    sim = vascsim.Simulation(vascsim.load_scene(block_path))
    x = sim.positions
    assert x.shape == (sim.num_nodes, 3) and x.dtype == np.float64
    assert not x.flags.writeable
    assert not x.flags.owndata  # a view, not a copy
    rest = sim.rest_positions
    assert np.array_equal(x, rest)
    before = np.array(x)  # a copy of the rest state
    sim.advance()
    # The same array shows the new state: the nodes under the ball follow its first 0.05 mm step down (-z);
    # within half of it either way (the contact's tolerance, the wall's bulge), not unmoved.
    dz = x[:, 2] - before[:, 2]
    assert 0.5 * 5e-5 < -dz.min() < 1.5 * 5e-5
    assert np.array_equal(x, sim.positions)
    with pytest.raises(ValueError):
        x[0, 0] = 1.0


def test_the_python_records_equal_the_force_displacement_experiment(block_path, tmp_path):
    scene = vascsim.load_scene(block_path)
    records = vascsim.Simulation(scene).solve()
    result = vascsim.force_displacement(scene, tmp_path)
    assert (tmp_path / "force_displacement.csv").exists()
    assert result["png"] is None  # plot=False
    # The experiment's curve: the tool's travel and the tissue's force on it along the reversed push (+z here).
    np.testing.assert_allclose(result["displacement_m"], [0, 5e-5, 1e-4, 1.5e-4, 2e-4], rtol=1e-12)
    # force_n is one number with one meaning in both: the ball's force on the tissue along its push (-z).
    expected = [0.0] + [r["tools"]["ball"]["force_n"] for r in records]
    # The same computation on one thread (OMP_NUM_THREADS=1): equal to rounding.
    np.testing.assert_allclose(result["force_n"], expected, rtol=1e-12, atol=0)
    assert result["summary"]["force_displacement"]["tool"] == "ball"


def test_records_have_the_names_and_meanings_of_summary_json(block_path, tmp_path):
    scene = vascsim.load_scene(block_path)
    records = vascsim.Simulation(scene).solve()
    steps = vascsim.run(scene, tmp_path)["steps"][1:]  # summary.json lists the tools with the regions
    with open(tmp_path / "probes.csv") as f:
        rows = list(csv.DictReader(f))[1:]
    for record, step, row in zip(records, steps, rows, strict=True):
        for kind in ("regions", "tools"):
            for name, values in record[kind].items():
                saved = step["regions"][name]
                # One thread (OMP_NUM_THREADS=1): the same computation, equal to rounding.
                np.testing.assert_allclose(values["force_n"], saved["force_n"], rtol=1e-12, atol=1e-15)
                np.testing.assert_allclose(values["force_vector_n"], saved["force_vector_n"], rtol=1e-12, atol=1e-15)
                np.testing.assert_allclose(values["force_n"], float(row[f"{name}_force_n"]), rtol=1e-8, atol=1e-15)
        ball = record["tools"]["ball"]
        np.testing.assert_allclose(ball["torque_vector_n_m"], step["regions"]["ball"]["torque_vector_n_m"],
                                   rtol=1e-12, atol=1e-18)
        # On the tissue, along the push (-z): positive while the ball presses.
        assert ball["force_n"] > 0
        assert ball["force_n"] == pytest.approx(-ball["force_vector_n"][2], rel=1e-12)


def test_solve_logs_a_progress_record_per_load_step(block_path, caplog):
    caplog.set_level(logging.INFO, logger="vascsim")
    vascsim.Simulation(vascsim.load_scene(block_path)).solve()
    progress = [r.getMessage() for r in caplog.records if r.name == "vascsim" and " of 4: " in r.getMessage()]
    assert [m.split(": ")[1] for m in progress] == ["step 1 of 4", "step 2 of 4", "step 3 of 4", "step 4 of 4"]
    assert progress[0].startswith("pressed-block: ") and "Newton" in progress[0]


def test_a_tool_that_never_reaches_the_tissue_warns_through_python(block_path):
    sim = vascsim.Simulation(vascsim.load_scene(block_path, overrides=BALL_AWAY))
    with pytest.warns(vascsim.VascsimWarning, match="'ball'") as caught:
        sim.solve()
    assert issubclass(vascsim.VascsimWarning, UserWarning)
    assert caught[0].filename == __file__  # the warning names the line that called solve()


def test_a_warning_the_filter_makes_an_error_stops_solve(block_path):
    sim = vascsim.Simulation(vascsim.load_scene(block_path, overrides=BALL_AWAY))
    with warnings.catch_warnings():
        warnings.simplefilter("error", vascsim.VascsimWarning)
        with pytest.raises(vascsim.VascsimWarning, match="'ball'"):
            sim.solve()


def test_statistics_report_the_solver(block_path):
    sim = vascsim.Simulation(vascsim.load_scene(block_path))
    sim.advance()
    s = sim.statistics
    assert s["model"] == "quasi_static" and s["steps_done"] == 1 and s["nodes"] == sim.num_nodes
    assert s["iterations"] >= 1 and s["converged"] and s["residual"] <= 1e-8
    assert s["info"]["newton_iterations"] >= s["iterations"]
    assert s["total_wall_s"] > 0


def test_another_model_is_chosen_by_name(block_path):
    sim = vascsim.Simulation(vascsim.load_scene(block_path), model="tensor_mass")
    assert sim.model == "tensor_mass" and sim.scene.model == "tensor_mass"
    with pytest.raises(vascsim.InputError, match="no_such_model"):
        vascsim.Simulation(vascsim.load_scene(block_path), model="no_such_model")


def test_a_device_drives_the_tool_into_the_block(haptic_block_path):
    sim = vascsim.Simulation(vascsim.load_scene(haptic_block_path))  # xpbd: device-driven
    assert sim.device_driven and sim.frame_length_s == pytest.approx(1e-3)
    tip_above = np.array([0.003, 0.003, 0.0032])  # the catheter tip's rest position, 0.2 mm above the block
    sim.set_tool_pose(tip_above)
    sim.step()
    assert sim.tool_loads()[0]["contacts"] == 0
    depths, forces = [1e-4, 2e-4], []
    for depth in depths:
        sim.set_tool_pose(tip_above - [0, 0, 2e-4 + depth], tool="catheter")
        for _ in range(60):
            record = sim.step()
        load = sim.tool_loads()[0]
        assert load["name"] == "catheter" and load["contacts"] > 0
        # The record measures the same frame's tool force.
        np.testing.assert_array_equal(record["tools"]["catheter"]["force_vector_n"], load["force_vector_n"])
        forces.append(-load["force_vector_n"][2])  # the tissue pushes the tool up (+z)
    assert sim.frames_done == 121 and sim.time_s == pytest.approx(0.121)
    assert 0 < forces[0] < forces[1]  # deeper, harder
    assert sim.positions[:, 2].min() < 0.003 - 5e-5  # the top surface is pressed in


def test_device_calls_need_a_device_driven_model_and_a_valid_pose(vessel_path, haptic_block_path):
    sim = vascsim.Simulation(vascsim.load_scene(vessel_path), model="explicit")  # no tools, no device
    assert not sim.device_driven
    with pytest.raises(vascsim.InputError, match="cannot be driven by a device; use one of: .*implicit"):
        sim.step()
    driven = vascsim.Simulation(vascsim.load_scene(haptic_block_path))
    with pytest.raises(vascsim.InputError, match="no obstacle named 'nope'"):
        driven.set_tool_pose([0, 0, 0], tool="nope")
    with pytest.raises(vascsim.InputError, match="quaternion"):
        driven.set_tool_pose([0, 0, 0], orientation=[0, 0, 0, 0])
    with pytest.raises(vascsim.InputError, match="finite"):
        driven.set_tool_pose([np.nan, 0, 0])


def test_the_surface_is_mapped_from_the_nodes(vessel_path):
    sim = vascsim.Simulation(vascsim.load_scene(vessel_path))
    rest = sim.surface()
    v, t, n = rest["vertices"], rest["triangles"], rest["normals"]
    assert v.shape[1] == 3 and t.shape[1] == 3 and n.shape == v.shape
    assert t.min() >= 0 and t.max() < len(v)
    assert not t.flags.writeable and not t.flags.owndata  # the triangles are a view
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-12)
    # The MLS map reproduces the rest state: the surface at rest does not move.
    assert np.abs(rest["displacements"]).max() == 0.0
    sim.solve()
    pressed = sim.surface()
    assert np.array_equal(pressed["triangles"], t)
    # The indenter pushes 0.2 mm inward; the mapped surface follows by about that much at the patch.
    moved = np.linalg.norm(pressed["displacements"], axis=1).max()
    assert 1e-4 < moved < 4e-4
    np.testing.assert_allclose(pressed["vertices"], v + pressed["displacements"], atol=1e-15)


def test_two_simulations_run_in_two_threads(block_path, vessel_path):
    import threading
    scenes = [vascsim.load_scene(block_path), vascsim.load_scene(vessel_path)]
    serial = [vascsim.Simulation(s).solve()[-1] for s in scenes]
    parallel, errors = [None, None], []

    def solve(i):
        try:
            parallel[i] = vascsim.Simulation(scenes[i]).solve()[-1]
        except Exception as e:  # noqa: BLE001 (reported below)
            errors.append(e)

    threads = [threading.Thread(target=solve, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    # Each Simulation owns its state, and one thread each (OMP_NUM_THREADS=1) computes bit for bit as alone.
    for alone, together in zip(serial, parallel):
        assert together["iterations"] == alone["iterations"]
        for kind in ("regions", "tools"):
            for name, values in alone[kind].items():
                np.testing.assert_array_equal(together[kind][name]["force_vector_n"], values["force_vector_n"])


def test_solve_warns_what_a_finished_run_finds_as_the_command_line_does(block_path, tmp_path):
    # The ball's Hertz contact spans 1.3 spacings of the 0.5 mm lattice at its first 0.1 mm: `vascsim run` ends
    # with that warning in summary.json, and solve() issues the same text once its last load step is solved.
    code, _, _ = run_cli("-q", "run", block_path, "--out", tmp_path)
    assert code == 0
    expected = json.loads((tmp_path / "summary.json").read_text())["warnings"]
    ending = [w for w in expected if "narrower than the lattice resolves" in w]
    assert len(ending) == 1
    sim = vascsim.Simulation(vascsim.load_scene(block_path))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for _ in range(3):
            sim.advance()
        before_last = [str(w.message) for w in caught]
        sim.advance()
    assert ending[0] not in before_last  # said once the run is finished, not before
    assert [str(w.message) for w in caught if issubclass(w.category, vascsim.VascsimWarning)][-1] == ending[0]
