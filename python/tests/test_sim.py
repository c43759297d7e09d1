"""articula.Sim: what `articula sim` prints, reproduced step by step from Python; protocol
lines one at a time; a drag; reset; and the errors."""

import csv
import io
import json

import numpy as np
import pytest

import articula
from conftest import cli


def test_the_grasp_and_lift_run_equals_articula_sim(tmp_path):
    events_file = tmp_path / "events.jsonl"
    out = cli("sim", "mk2plus", "programs/grasp-and-lift.arm", "--scene", "grasp-and-lift", "--sample", "100",
              "--events", str(events_file)).stdout
    rows = list(csv.DictReader(io.StringIO(out)))
    sim = articula.Sim(articula.Robot.load("mk2plus"), "grasp-and-lift")
    sim.load_program(articula.Program.load("programs/grasp-and-lift.arm"))
    names = sim.robot_joint_names if hasattr(sim, "robot_joint_names") else ["base", "shoulder", "elbow"]
    for row in rows:
        sim.run_until(float(row["t_s"]))
        s = sim.state()
        assert s["t"] == pytest.approx(float(row["t_s"]), abs=1e-9)
        for j, name in enumerate(names):
            assert s["joints"][j] == pytest.approx(float(row[f"{name}_deg"]), abs=6e-5)
        assert s["gripper_mm"] == pytest.approx(float(row["gripper_mm"]), abs=6e-5)
        block = s["objects"][0]
        assert block["name"] == "block"
        for k, axis in enumerate("xyz"):
            assert block["pose"][k, 3] == pytest.approx(float(row[f"block_{axis}"]), abs=6e-5)
            assert s["tool"][k, 3] == pytest.approx(float(row[f"tool_{axis}"]), abs=6e-5)
    sim.run()
    cli_events = [json.loads(line) for line in events_file.read_text().splitlines()]
    assert [e.to_dict() for e in sim.events()] == cli_events
    kinds = [e.kind for e in sim.events()]
    assert "grasp" in kinds and "release" in kinds
    assert sim.done and not sim.busy


def test_commands_one_at_a_time_answer_as_the_arm():
    sim = articula.Sim(articula.Robot.load("mk2plus"))
    assert sim.command("L 0 10") == "ok"
    assert sim.busy
    assert sim.command("L 1 150") == "error:9"
    assert sim.command("L 7 1") == "error:6"
    assert sim.command("hello") == "error:2"
    sim.step(2000)
    s = sim.state()
    assert s["counted_steps"] == [32, 0, 0] and not s["busy"]
    assert s["joints"][0] == pytest.approx(10.1333, abs=1e-4)
    rejected = [e for e in sim.events() if e.kind == "rejected"]
    assert [e.a for e in rejected] == ["L 1 150", "L 7 1", "hello"]
    assert "target beyond a joint limit" in rejected[0].detail
    # queued after what the arm is doing: two moves end where their sum does
    assert sim.command("L 0 -20") == "ok" and sim.command("L 0 10") == "ok"
    sim.step(3000)
    assert sim.state()["counted_steps"] == [0, 0, 0]


def test_a_robot_without_motors_follows_joint_targets():
    panda = articula.Robot.load("panda")
    sim = articula.Sim(panda)
    assert sim.command("M 10 -20 0 -120 0 100 45") == "ok"
    sim.step(5000)
    np.testing.assert_allclose(sim.state()["joints"], [10, -20, 0, -120, 0, 100, 45], atol=1e-9)
    np.testing.assert_allclose(sim.state()["tool"], panda.fk([10, -20, 0, -120, 0, 100, 45]), atol=1e-9)


def test_a_dragged_box_follows_the_mouse_and_falls_back_to_rest():
    sim = articula.Sim(articula.Robot.load("mk2plus"), "push")
    box = sim.state()["objects"][0]
    assert box["name"] == "box" and box["movable"]
    start = box["pose"][:3, 3].copy()
    sim.step(200)  # settle
    sim.drag("box", start + [0, 100, 100])
    sim.step(1500)
    held = sim.state()["objects"][0]["pose"][:3, 3]
    np.testing.assert_allclose(held, start + [0, 100, 100], atol=3)
    sim.release()
    sim.step(2000)
    rest = sim.state()["objects"][0]["pose"]
    assert rest[2, 3] == pytest.approx(40, abs=1.0)  # a 80 mm box stands on the ground
    assert abs(rest[1, 3] - (start[1] + 100)) < 30
    # dragged into the ground, it stops at the ground: a body among bodies
    sim.drag(0, [rest[0, 3], rest[1, 3], -200])
    sim.step(1000)
    assert sim.state()["objects"][0]["pose"][2, 3] > 35
    sim.release()
    let_go = sim.state()["objects"][0]["pose"]
    # restart: from t = 0 with the box where the drag let go of it; reset: where the scene has it
    sim.restart()
    assert sim.time == 0
    np.testing.assert_allclose(sim.state()["objects"][0]["pose"], let_go, atol=1e-9)
    sim.reset()
    assert sim.time == 0
    np.testing.assert_allclose(sim.state()["objects"][0]["pose"][:3, 3], start, atol=1e-9)


def test_contacts_name_what_touches():
    sim = articula.Sim(articula.Robot.load("mk2plus"), "push")
    sim.step(100)
    assert {(c["a"], c["b"]) for c in sim.state()["contacts"]} == {("box", "ground")}


def test_the_tool_path_is_the_tool_point_after_those_steps():
    """step_path: the tool point after every `every`-th world step and the last, as a world
    stepped alike shows it (a pen's ink in the physics is drawn from this path)."""
    robot = articula.Robot.load("mk2plus")
    a, b = articula.Sim(robot), articula.Sim(robot)
    assert a.command("L 0 10") == "ok" and b.command("L 0 10") == "ok"
    path = a.step_path(1050, every=100)
    assert path.shape == (11, 3)
    for row in path[:10]:
        b.step(100)
        np.testing.assert_allclose(row, b.state()["tool"][:3, 3], atol=1e-9)
    b.step(50)
    np.testing.assert_allclose(path[10], b.state()["tool"][:3, 3], atol=1e-9)
    assert np.linalg.norm(path[-1] - path[0]) > 5  # the base turned: the tool moved


@pytest.mark.parametrize("call, exc, words", [
    (lambda s: s.drag("post", [0, 0, 0]), ValueError, "'post' is static"),
    (lambda s: s.drag("ghost", [0, 0, 0]), KeyError, "no object named 'ghost'"),
    (lambda s: s.drag(5, [0, 0, 0]), IndexError, "no object 5"),
    (lambda s: s.drag("box", [0, float("nan"), 0]), ValueError, "NaN"),
    (lambda s: s.drag("box", [0, 0]), ValueError, "target must be"),
    (lambda s: s.step(-1), ValueError, "n must be"),
    (lambda s: s.step_path(10, every=0), ValueError, "every must be"),
    (lambda s: s.load_program("programs/none.arm"), articula.ProgramError, "none.arm"),
])
def test_bad_sim_calls_raise(call, exc, words):
    sim = articula.Sim(articula.Robot.load("mk2plus"), "push")
    with pytest.raises(exc, match=words):
        call(sim)


def test_bad_scenes_and_options_raise(tmp_path):
    mk2 = articula.Robot.load("mk2plus")
    with pytest.raises(articula.SceneError, match="no-such-scene"):
        articula.Sim(mk2, "no-such-scene")
    bad = tmp_path / "bad.json"
    bad.write_text('{"objects": [{"type": "box", "size": [10, 0, 10], "xyz": [0, 0, 5]}]}')
    with pytest.raises(articula.SceneError) as e:
        articula.Sim(mk2, str(bad))
    assert e.value.json_path == "/objects/0/size/1"
    with pytest.raises(ValueError, match="dt"):
        articula.Sim(mk2, dt=0.5)
    with pytest.raises(ValueError, match="setting"):
        articula.Sim(mk2, settings={42: 1})


def test_a_belt_runs_at_the_speed_set_and_stops(tmp_path):
    """set_belt: a cube on a belt rides at its speed, and stays when it stops."""
    scene = tmp_path / "belt.json"
    scene.write_text(json.dumps({"objects": [
        {"name": "belt", "type": "box", "size": [1200, 80, 10], "xyz": [0, -500, 5], "belt": 1},
        {"name": "cube", "type": "box", "size": [25, 25, 25], "xyz": [-500, -500, 22.5], "movable": True, "mass": 0.02}]}))
    sim = articula.Sim(articula.Robot.load("mk2plus"), str(scene))
    sim.set_belt("belt", 100)
    sim.run_until(1.0)
    x = lambda: sim.state()["objects"][1]["pose"][0, 3]  # noqa: E731 (the cube's x, mm)
    x0 = x()
    sim.run_until(3.0)
    x1 = x()
    assert (x1 - x0) / 2 == pytest.approx(100, rel=0.05)
    sim.set_belt(0, 0)
    sim.run_until(3.5)
    x2 = x()
    sim.run_until(5.0)
    assert abs(x() - x2) < 0.5
    with pytest.raises(ValueError, match="not a belt"):
        sim.set_belt("cube", 10)
    with pytest.raises(ValueError, match="at most 1000 mm/s"):
        sim.set_belt("belt", 5000)
