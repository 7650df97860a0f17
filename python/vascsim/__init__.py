"""vascsim: point-primitive vascular tissue simulation (Zhang et al. 2021), from Python.

    import vascsim
    scene = vascsim.load_scene(vascsim.bundled_file("scenes/vein-indent.json"), model="quasi_static")
    sim = vascsim.Simulation(scene)
    for record in sim.solve():
        print(record["load_factor"], record["regions"]["indenter"]["force_n"])  # N, along the indenter's push
    x = sim.positions            # (N, 3) node positions, m: a read-only view

Units are SI throughout (m, kg, s, Pa, N). Records use summary.json's names: force_n is the scalar force (N)
along a region's direction or a tool's motion, force_vector_n the (3,) vector, both the force on the tissue.
Bad input raises InputError (a ValueError) with the same one-line message as the command line; a numerical
failure raises NumericalError (a RuntimeError). What the command line prints as warnings is issued through
warnings.warn as VascsimWarning (a UserWarning); progress, one record per output point, and the library's other
log lines go to the logger "vascsim" of Python's logging (logging.basicConfig(level=logging.INFO) shows them).
The reference is docs/api.md ("Python module").
"""

import json as _json
import os as _os
import tempfile as _tempfile

from ._vascsim import (  # noqa: F401  (the compiled module)
    InputError,
    NumericalError,
    Scene,
    Simulation,
    VascsimWarning,
    build_info,
    models,
    set_log_level,
    set_threads,
    threads,
    version,
)
from . import _vascsim

__version__ = version()

__all__ = [
    "InputError", "NumericalError", "Scene", "Simulation", "VascsimWarning", "build_info", "models", "set_log_level",
    "set_threads", "threads", "version", "load_scene", "parse_scene", "bundled_file", "run", "force_displacement",
    "compare_models", "validate_mls",
]


def _overrides(overrides=None, model=None):
    """--set style overrides "path.to.key=value" from a dict {path: value} or a list of strings."""
    out = []
    if overrides is None:
        pass
    elif isinstance(overrides, dict):
        for key, value in overrides.items():
            out.append(f"{key}={_json.dumps(value, default=_json_default, allow_nan=False)}")
    elif isinstance(overrides, str):
        out.append(overrides)
    else:
        out.extend(str(o) for o in overrides)
    if model is not None:
        out.append(f"model={model}")
    return out


def _json_default(value):
    # NumPy arrays and scalars in a scene dict become JSON lists and numbers.
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"{type(value).__name__} is not a JSON value")


def load_scene(path, overrides=None, model=None):
    """Reads and validates a scene file, as `vascsim run PATH --set ...` does.

    overrides: {"path.to.key": value} or ["path.to.key=value", ...] (the command line's --set); model: a
    registry name (vascsim.models()) replacing the scene's. Raises InputError naming the file and key.
    """
    return _vascsim._load_scene(_os.fspath(path), _overrides(overrides, model))


def parse_scene(document, file="scene.json", overrides=None, model=None):
    """Validates a scene given as a dict (or JSON text) with the same checks and messages as a file.

    file: the name messages use; relative paths in the scene (mesh files, trajectories) are resolved against
    its folder. overrides and model as for load_scene.
    """
    if isinstance(document, (str, bytes)):
        text = document if isinstance(document, str) else document.decode()
    else:
        try:
            text = _json.dumps(document, default=_json_default, allow_nan=False)
        except (TypeError, ValueError) as e:
            raise InputError(f"{file}: not a JSON document: {e}") from None
    return _vascsim._parse_scene(text, _os.fspath(file), _overrides(overrides, model))


def bundled_file(relative):
    """A file that ships with vascsim (e.g. "scenes/vein-indent.json"): in the source tree of a build, in
    PREFIX/share/vascsim when installed (the folder build_info()["bundled_files"] names)."""
    return _os.path.join(build_info()["bundled_files"], relative)


def run(scene, out_dir, on_step=None):
    """Runs a scene headless as `vascsim run` and writes the same files into out_dir (summary.json,
    probes.csv, VTK if asked). Returns summary.json's content. on_step(record, total) after every output point.
    Each line of summary.json's "warnings" is also issued as a VascsimWarning (as the run finds it, or at its end)."""
    return _vascsim._run(scene, _os.fspath(out_dir), on_step)


def force_displacement(scene, out_dir=None, tool=None, plot=False, python="/usr/bin/python3", on_step=None):
    """The force-displacement experiment (`vascsim experiment force-displacement`; the paper's Fig. 10 with
    scenes/hand-dorsal-vein-catheter.json): the tool presses the wall step by step.

    Returns a dict: displacement_m (the tool's travel, m) and force_n (N) as arrays, force_n being summary.json's:
    the force the tool exerts on the tissue along its motion, positive while it presses (the tissue resists the
    tool with as much); out_dir, csv (force_displacement.csv), png (with plot=True and matplotlib, else None),
    plot_problem and summary (summary.json's content). on_step(record, total) after every output point; each line
    of summary.json's "warnings" is also issued as a VascsimWarning.

    The files go to out_dir; without one, to a new folder in the system's temporary folder
    (tempfile.mkdtemp, "vascsim-force-displacement-*"), which is kept: its path is the result's out_dir.
    """
    if out_dir is None:
        out_dir = _tempfile.mkdtemp(prefix="vascsim-force-displacement-")
    out_dir = _os.fspath(out_dir)
    result = _vascsim._force_displacement(scene, out_dir, tool or "", plot, python, on_step)
    result["out_dir"] = out_dir
    return result


def compare_models(scene_path, models, out_dir, reference="quasi_static", overrides=None, tool=None, reuse=False,
                   plot=False, python="/usr/bin/python3"):
    """Force-displacement of several models against a reference model (`vascsim experiment force-displacement
    --models`): per model its curve and RMS error; files in out_dir (docs/replicate.md)."""
    return _vascsim._compare_models(_os.fspath(scene_path), list(models), _os.fspath(out_dir), reference,
                                    _overrides(overrides), tool or "", reuse, plot, python)


def validate_mls(scene_paths, overrides=None, tight_factor=1.0):
    """The MLS map checks of `vascsim validate mls` (reproduction error and conditioning guards) per scene."""
    return _vascsim._validate_mls([_os.fspath(p) for p in scene_paths], _overrides(overrides), tight_factor)
