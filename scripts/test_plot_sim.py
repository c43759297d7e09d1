"""scripts/plot-sim on a real run of `articula sim` (the thesis's Fig. 20 scene), and its
errors. Run by ctest as host.plot_sim; needs ARTICULA_CLI (the built articula)."""

import os
import runpy
import subprocess
import sys
from pathlib import Path

import pytest

SOURCE = Path(os.environ.get("ARTICULA_SOURCE_DIR", Path(__file__).resolve().parents[1]))
SCRIPT = SOURCE / "scripts" / "plot-sim"
plot_sim = runpy.run_path(str(SCRIPT), run_name="plot_sim")


def run_script(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True, timeout=120)


@pytest.fixture(scope="module")
def sim_run(tmp_path_factory):
    cli = os.environ.get("ARTICULA_CLI")
    if not cli or not Path(cli).exists():
        pytest.fail("ARTICULA_CLI must name the built articula")
    d = tmp_path_factory.mktemp("sim")
    p = subprocess.run([cli, "sim", "mk2plus", str(SOURCE / "programs" / "grasp-and-lift.arm"), "--scene",
                        "grasp-and-lift", "-o", str(d / "run.csv"), "--events", str(d / "run.jsonl")],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    return d


def test_plots_a_real_run(sim_run):
    p = run_script(sim_run / "run.csv", "--events", sim_run / "run.jsonl", "-o", sim_run / "run.png")
    assert p.returncode == 0, p.stderr
    png = (sim_run / "run.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 20000
    head, data = plot_sim["read_trajectory"](sim_run / "run.csv")
    events = plot_sim["read_events"](sim_run / "run.jsonl")
    assert f"({len(data)} samples, {len(events)} events)" in p.stdout
    assert {"grasp", "release"} <= {e["kind"] for e in events}
    # The block is lifted in the trajectory the plot reads.
    z = plot_sim["columns"](head, data, ["block_z"])["block_z"]
    assert max(z) - z[0] > 50


def test_errors_name_the_file_and_line(sim_run, tmp_path):
    p = run_script(sim_run / "run.jsonl")
    assert p.returncode == 2 and "run.jsonl:1: not a trajectory" in p.stderr
    bad = tmp_path / "bad.csv"
    rows = (sim_run / "run.csv").read_text().splitlines()
    bad.write_text("\n".join(rows[:3] + [rows[3].replace(",", ",x", 1)]) + "\n")
    p = run_script(bad)
    assert p.returncode == 2 and "bad.csv:4: not a number" in p.stderr
    p = run_script(sim_run / "run.csv", "--events", bad)
    assert p.returncode == 2 and "bad.csv:1: not an event line" in p.stderr
    p = run_script(tmp_path / "missing.csv")
    assert p.returncode == 2 and "missing.csv" in p.stderr
