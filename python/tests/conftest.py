"""Shared fixtures of the Python module's tests (ctest python_module_pytest sets PYTHONPATH to the build's
package, VASCSIM_CLI to the built `vascsim` and VASCSIM_PROJECT_VERSION to CMake's project version)."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "tests" / "data"


@pytest.fixture
def block_path():
    """A 3 x 3 x 1.5 mm block on a fixed base pressed 0.2 mm by a ball in 4 quasi-static steps (196 nodes)."""
    return DATA / "pressed-block.json"


@pytest.fixture
def haptic_block_path():
    """A 6 x 6 x 3 mm block with a 6 Fr catheter above it, xpbd, a haptics block (device-driven)."""
    return DATA / "haptic-block.json"


@pytest.fixture
def vessel_path():
    """A coarse 90 degree bend with a render surface, pushed inward in 2 quasi-static steps."""
    return DATA / "tiny-bent-vessel.json"


def run_cli(*args):
    """The built command line: (exit code, stdout, stderr)."""
    cli = os.environ.get("VASCSIM_CLI")
    if not cli:
        pytest.skip("VASCSIM_CLI is not set (run through ctest)")
    p = subprocess.run([cli, *map(str, args)], capture_output=True, text=True, check=False)
    return p.returncode, p.stdout, p.stderr
