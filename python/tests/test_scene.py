"""Scenes from files and dicts: the same validation and the same messages as the command line."""

import json

import numpy as np
import pytest

import vascsim
from conftest import run_cli


def test_a_scene_file_loads_with_its_names(block_path):
    scene = vascsim.load_scene(block_path)
    assert scene.name == "pressed-block"
    assert scene.model == "quasi_static"
    assert scene.tools == ["ball"]
    assert scene.regions == ["base"]
    assert scene.file == str(block_path)
    assert scene.document["quasi_static"]["load_steps"] == 4


def test_overrides_and_the_model_choice_apply_like_set(block_path):
    scene = vascsim.load_scene(block_path, overrides={"quasi_static.load_steps": 2}, model="xpbd")
    assert scene.model == "xpbd"
    assert scene.document["quasi_static"]["load_steps"] == 2
    same = vascsim.load_scene(block_path, overrides=["quasi_static.load_steps=2", "model=xpbd"])
    assert same.document == scene.document


def test_a_dict_is_validated_like_the_file(block_path):
    doc = json.loads(block_path.read_text())
    from_dict = vascsim.parse_scene(doc, file=str(block_path))
    assert from_dict.document == vascsim.load_scene(block_path).document
    # NumPy values in the dict are plain JSON numbers and lists.
    doc["obstacles"][0]["centre_m"] = np.array([0.0015, 0.0015, 0.003])
    doc["material"]["poisson_ratio"] = np.float64(0.45)
    assert vascsim.parse_scene(doc).tools == ["ball"]


@pytest.mark.parametrize("override", ["material.poisson_ratio=0.7", "model=no_such_model",
                                      "quasi_static.load_stepz=3"])
def test_bad_input_raises_input_error_with_the_cli_message(block_path, override):
    with pytest.raises(vascsim.InputError) as caught:
        vascsim.load_scene(block_path, overrides=[override])
    assert isinstance(caught.value, ValueError)
    code, _, err = run_cli("run", block_path, "--set", override, "--out", "/nonexistent/never-written")
    assert code == 2
    assert err.strip() == f"vascsim: error: {caught.value}"


def test_a_bad_dict_names_the_given_file_and_the_key():
    with pytest.raises(vascsim.InputError, match=r"^my-scene\.json: .*geometry"):
        vascsim.parse_scene({"name": "x"}, file="my-scene.json")
    with pytest.raises(vascsim.InputError, match="not a JSON document"):
        vascsim.parse_scene({"name": float("nan")}, file="my-scene.json")


def test_a_missing_file_raises_input_error(tmp_path):
    with pytest.raises(vascsim.InputError, match="cannot open the scene file"):
        vascsim.load_scene(tmp_path / "missing.json")


def test_models_come_from_the_registry():
    models = {m["name"]: m for m in vascsim.models()}
    assert models["implicit"]["device_driven"] and models["implicit"]["dynamic"]
    assert not models["explicit"]["device_driven"] and not models["explicit"]["takes_tools"]
    assert not models["quasi_static"]["dynamic"]


def test_the_version_is_the_projects_and_the_clis():
    code, out, _ = run_cli("--version")
    assert code == 0
    assert out.splitlines()[0] == f"vascsim {vascsim.__version__}"
    import os
    if "VASCSIM_PROJECT_VERSION" in os.environ:
        assert vascsim.__version__ == os.environ["VASCSIM_PROJECT_VERSION"]
    info = vascsim.build_info()
    assert info["version"] == vascsim.__version__
    assert f"bundled files: {info['bundled_files']}" in out.splitlines()


def test_set_threads_has_the_bound_of_the_command_line():
    # The bound of `vascsim -j` (1..256): beyond it OpenMP may end the process when it cannot start a team.
    before = vascsim.threads()
    for bad in (0, 257, 1024):
        with pytest.raises(vascsim.InputError, match="outside 1..256"):
            vascsim.set_threads(bad)
    vascsim.set_threads(1)
    assert vascsim.threads() == 1
    vascsim.set_threads(before)
