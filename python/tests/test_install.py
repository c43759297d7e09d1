"""`pip install .` gives a working package: the wheel is built from this tree by
scikit-build-core (the project's venv has it and nanobind, so no network is needed), installed
into a folder of its own, and imported from there with the shipped robots and scenes it
carries, not the tree's. The host libraries in it are the tree build's own (make compiled them
from the same sources with the same flags: cmake/prebuilt-host.cmake), so that `make test`
compiles nothing twice; the wheel compiles its module (python/src) and installs what a user's
`pip install .` installs. A user's build compiles the libraries too (Release, pyproject.toml)."""

import os
import subprocess
import sys
from pathlib import Path

from conftest import REPO

# The tree build whose libraries the wheel links: the one the tests run (ARTICULA_CLI is its CLI).
BUILD = Path(os.environ["ARTICULA_CLI"]).resolve().parents[2] if os.environ.get("ARTICULA_CLI") else REPO / "build"


def test_pip_install_gives_a_working_package(tmp_path):
    target = tmp_path / "site"
    p = subprocess.run([sys.executable, "-m", "pip", "install", "--quiet", "--no-build-isolation", "--no-deps",
                        f"--config-settings=cmake.define.ARTICULA_PREBUILT_DIR={BUILD}",
                        "--target", str(target), str(REPO)],
                       capture_output=True, text=True, timeout=900, cwd=tmp_path)
    assert p.returncode == 0, p.stdout + p.stderr
    files = {f.name for f in (target / "articula").iterdir()}
    assert {"__init__.py", "_records.py", "_core.pyi", "py.typed", "data"} <= files
    assert any(f.startswith("_core.") and f.endswith(".so") for f in files)
    env = {k: v for k, v in os.environ.items() if k not in ("ARTICULA_ROBOTS", "ARTICULA_SCENES")}
    env["PYTHONPATH"] = str(target)
    code = ("import articula, os; print(articula.__file__); print(os.environ['ARTICULA_ROBOTS']); "
            "print(articula.Robot.load('mk2plus').fk([0, 90, -90])[:3, 3].tolist()); "
            "print(articula.Sim(articula.Robot.load('mk2plus'), 'grasp-and-lift').objects[0]['name'])")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path,
                         timeout=60)
    assert run.returncode == 0, run.stderr
    out = run.stdout.splitlines()
    assert out[0] == str(target / "articula" / "__init__.py")
    assert out[1] == str(target / "articula" / "data" / "robots")
    assert out[2] == "[235.0, 0.0, 213.0]"
    assert out[3] == "block"
