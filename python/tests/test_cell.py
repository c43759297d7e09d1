"""articula.Cell: a cell of arms from Python gives what `articula sim CELL --json` gives; each
arm by name; programs in place of the file's; the errors name what is wrong."""

import json

import pytest

import articula
from conftest import cli


def test_the_handover_equals_articula_sim_cell():
    out = json.loads(cli("sim", "handover", "--json").stdout)
    cell = articula.Cell("handover")
    assert cell.arms == ["giver", "taker"]
    cell.run()
    assert cell.done
    assert [e.to_dict() for e in cell.events()] == out["events"]
    state = cell.state()
    assert state.t == pytest.approx(out["t"])
    for mine, theirs in zip(state.arms, out["arms"]):
        assert mine.to_dict() == theirs
    assert [e.arm for e in cell.events() if e.kind == "grasp"] == ["giver", "taker"]
    taken = [e for e in cell.events() if e.kind == "grasp" and e.arm == "taker"][0]
    assert "taken from giver" in taken.detail
    assert state.objects[0].carried_by is None


def test_the_shared_zone_takes_turns_and_a_deadlock_is_told(tmp_path):
    cell = articula.Cell("shared-zone")
    cell.run()
    assert [e.kind for e in cell.events()] == []  # no collision: the wires keep them apart
    assert cell.deadlock == ""
    # Its signals: the left arm waits twice, the right once, each wait ended by the other's O.
    left, right = cell.arm("left").signals, cell.arm("right").signals
    assert [(s.kind, s.name) for s in left] == [("wait", "go"), ("output", "done"), ("wait", "go"), ("output", "done")]
    assert [(s.kind, s.name, s.level) for s in right] == [("output", "done", 0), ("wait", "go", 0), ("output", "done", 1)]
    assert 0 <= left[0].end_t - right[0].t <= 0.001
    assert 0 <= right[1].end_t - left[1].t <= 0.001
    assert 0 <= left[2].end_t - right[2].t <= 0.001
    # Each arm predicted in the cell (articula predict CELL ARM): its O and W lines begin, and its
    # W lines end, at the very times of the run.
    for name, signals in (("left", left), ("right", right)):
        p = cell.predict(name)
        timed = [r for r in p.records if r.command[0] in "OW"]
        assert [r.line for r in timed] == [s.line for s in signals]
        for r, s in zip(timed, signals):
            assert r.start_s == pytest.approx(s.t, abs=1e-9), (name, r.command)
            if s.kind == "wait":
                assert r.end_s == pytest.approx(s.end_t, abs=1e-9), (name, r.command)
                assert "a wire drives" in r.note
        assert p.records[-1].steps == cell.arm(name).counted_steps
    with pytest.raises(KeyError, match=r"no arm 'middle' \(its arms: left, right\)"):
        cell.predict("middle")
    # Each arm waits for the other first: told in words, as an event, until a wait runs out.
    (tmp_path / "left.arm").write_text("W 15 0 2\nO 14 0\n")
    (tmp_path / "right.arm").write_text("W 15 0 3\nO 14 0\n")
    stuck = articula.Cell("shared-zone", {"left": tmp_path / "left.arm", "right": tmp_path / "right.arm"})
    stuck.run()
    assert stuck.deadlock == "left waits for `done` from right (low), which waits for `done` from left (low)"
    deadlocks = [e for e in stuck.events() if e.kind == "deadlock"]
    assert len(deadlocks) == 1 and deadlocks[0].detail == stuck.deadlock
    assert deadlocks[0].t < 0.01


def test_two_builds_one_signal_the_mearm_waits_for_the_mk2():
    """The servo build (the meArm) reads a wire from the 4-wire build (the MK2): its W ends at the
    first look after the MK2's O, in the run and in its prediction in the cell."""
    cell = articula.Cell("signal")
    cell.run()
    mk2, mearm = cell.arm("mk2"), cell.arm("mearm")
    assert [(s.kind, s.name, s.level) for s in mk2.signals] == [("output", "placed", 0)]
    assert [(s.kind, s.name, s.level) for s in mearm.signals] == [("wait", "go", 0)]
    assert mk2.signals[0].t > 2  # after the MK2 set the block down and went home
    assert 0 <= mearm.signals[0].end_t - mk2.signals[0].t <= 0.001
    predicted = cell.predict("mearm")
    assert predicted.records[0].command == "W 14 0 30"
    assert predicted.records[0].end_s == pytest.approx(mearm.signals[0].end_t, abs=1e-9)
    assert predicted.records[1].start_s >= predicted.records[0].end_s
    assert not [e for e in cell.events() if e.kind in ("collision", "rejected")]


def test_each_arm_by_name_or_index_and_a_program_of_ones_own(tmp_path):
    program = tmp_path / "wave.arm"
    program.write_text("G 100\nM 30 100 0\n")
    cell = articula.Cell("two-arms", programs={"mearm": program})
    assert cell.arm("mearm").program == str(program)
    cell.run()
    mearm = cell.arm(1)
    assert mearm.name == "mearm" and mearm.robot == "meArm"
    assert mearm.joints[0] == pytest.approx(30, abs=1)
    assert cell.arm("mk2").line == 11  # grasp-and-lift.arm's last line
    cell.reset()
    assert cell.time == 0 and cell.arm("mearm").joints == pytest.approx([0, 90, -90], abs=1e-9)


def test_errors_name_the_arm_the_file_and_the_place(tmp_path):
    with pytest.raises(KeyError, match=r"no arm 'robot' \(its arms: mk2, mearm\)"):
        articula.Cell("two-arms", programs={"robot": "x.arm"})
    with pytest.raises(KeyError, match="no arm 'nobody'"):
        articula.Cell("handover").arm("nobody")
    with pytest.raises(IndexError):
        articula.Cell("handover").arm(2)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"name": "x", "arms": [
        {"name": "a", "robot": "mk2plus"}, {"name": "b", "robot": "mk2plus", "base": {"xyz": [50, 0, 0]}}]}))
    with pytest.raises(articula.CellError, match="the bases of \"b\" and \"a\" overlap") as err:
        articula.Cell(bad)
    assert err.value.json_path == "/arms/1/base"
    two = tmp_path / "two.arm"
    two.write_text("M 10 20\n")  # two angles for an arm of three motors
    with pytest.raises(articula.ProgramError, match="two.arm:1"):
        articula.Cell("two-arms", programs={"mk2": two})
    with pytest.raises(ValueError, match="dt"):
        articula.Cell("handover", dt=0)


def test_plot_cell_draws_a_run_and_names_a_bad_cell(tmp_path):
    import subprocess
    import sys
    from conftest import REPO

    png = tmp_path / "handover.png"
    p = subprocess.run([sys.executable, str(REPO / "scripts" / "plot-cell"), "handover", "--sample", "50", "-o", str(png)],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert "10 events" in p.stdout
    data = png.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20000
    bad = tmp_path / "bad.json"
    bad.write_text('{"name": "x", "arms": [{"name": "a", "robot": "robby"}]}')
    p = subprocess.run([sys.executable, str(REPO / "scripts" / "plot-cell"), str(bad)], capture_output=True, text=True,
                       timeout=120)
    assert p.returncode == 2
    assert "bad.json: /arms/0/robot: the robot cannot be used" in p.stderr


def test_a_cells_belt_and_light_barrier_from_python():
    """cells/conveyor.json: the arm runs the belt, the block breaks the barrier's beam, the
    arm's wait ends there and the belt stands (the same core as the CLI and the page)."""
    cell = articula.Cell("conveyor")
    cell.run()
    devices = [(e.a, e.b, e.detail) for e in cell.events() if e.kind == "device"]
    assert devices[:3] == [("conveyor", "", "runs"), ("gate", "block", "the beam is broken"), ("conveyor", "", "stands")]
    broken = next(e.t for e in cell.events() if e.kind == "device" and e.b == "block")
    wait = cell.arm("mk2").signals[1]
    assert wait.kind == "wait" and 0 <= wait.end_t - broken <= 0.002
    belt, gate = cell.state().devices
    assert (belt.kind, belt.running, gate.kind, gate.broken_by) == ("belt", False, "barrier", None)


def test_a_cells_mat_to_print_is_the_clis():
    """Cell.mat_svg: the table from above at 1:1, as `articula mat CELL` writes it."""
    svg = articula.Cell("station").mat_svg()
    assert svg.startswith("<?xml") and svg.rstrip().endswith("</svg>")
    assert "gate: light barrier, 10 mm up" in svg and "feeder: the feeder's 3 come out here" in svg
    assert cli("mat", "station", ok=(0,)).stdout == svg


def test_the_station_puts_three_blocks_into_the_bin():
    """cells/station.json from Python: the feeder puts out three blocks, one at a time as the arm
    asks, and each ends in the bin (inside its four walls)."""
    cell = articula.Cell("station")
    cell.run()
    fed = [e.b for e in cell.events() if e.kind == "device" and e.detail == "puts one out"]
    assert fed == ["block1", "block2", "block3"]
    blocks = [o for o in cell.state().objects if o.name.startswith("block")]
    assert all(138 < o.xyz_mm[0] < 262 and 114 < o.xyz_mm[1] < 246 and not o.removed for o in blocks), blocks
    assert not [e for e in cell.events() if e.kind in ("collision", "rejected")]
