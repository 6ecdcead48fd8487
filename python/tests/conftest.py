"""Shared fixtures of the Python tests: the command line of the same build
(DETEXTURE_CLI), a work folder, and a small textured cube made by it."""
import os
import pathlib
import subprocess

import pytest

CLI = os.environ.get("DETEXTURE_CLI", "detexture")


def run_cli(*args, check=True):
    return subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, check=check)


@pytest.fixture(scope="session")
def work(tmp_path_factory):
    base = os.environ.get("DETEXTURE_TEST_DIR")
    if base:
        path = pathlib.Path(base)
        path.mkdir(parents=True, exist_ok=True)
        return path
    return tmp_path_factory.mktemp("detexture")


@pytest.fixture(scope="session")
def cube(work):
    """A cube of side 1 with separated bumps (radius 0.06, height 0.02), 8000
    points with normals, written by `detexture synth`."""
    path = work / "cube.ply"
    run_cli("synth", "--shape", "cube", "--texture", "bumps", "--size", "0.06", "--amplitude",
            "0.02", "-n", "8000", "--ground-truth-points", "8000", "--seed", "5", "-o", path)
    return path
