"""What the Python package's tests share: the repository, the articula CLI to compare with,
and the shipped robots and programs."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
ROBOTS = sorted(p.stem for p in (REPO / "robots").glob("*.json") if p.stem != "robot.schema")
PROGRAMS = sorted(str(p.relative_to(REPO)) for p in (REPO / "programs").iterdir() if p.suffix in (".arm", ".robosim"))
PLANS = sorted(str(p.relative_to(REPO)) for p in (REPO / "hil" / "plans").glob("*.arm"))


def cli_path() -> str:
    path = os.environ.get("ARTICULA_CLI") or str(REPO / "build" / "host" / "cli" / "articula")
    if not Path(path).exists():
        pytest.fail(f"the articula CLI is not built ({path}): run make")
    return path


def cli(*args: str, ok=(0, 1)) -> subprocess.CompletedProcess:
    p = subprocess.run([cli_path(), *args], capture_output=True, text=True, cwd=REPO, timeout=120)
    assert p.returncode in ok, f"articula {' '.join(args)}: exit {p.returncode}: {p.stderr}"
    return p


def cli_json(*args: str, ok=(0, 1)):
    return json.loads(cli(*args, "--json", ok=ok).stdout)


@pytest.fixture(autouse=True)
def _in_repo(monkeypatch):
    monkeypatch.chdir(REPO)
