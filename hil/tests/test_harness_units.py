"""The harness's parts without the virtual Nano: plans, the prediction (with lines the parser
refuses), the robot's tool positions against the prediction's, the first step interval,
random plans, measured CSVs, status parsing, and reset detection on a scripted serial port.
Needs the `articula` package built (make); run by ctest with test_harness.py."""

import os
import sys
from pathlib import Path

import pytest

SOURCE = Path(os.environ.get("ARTICULA_SOURCE_DIR") or Path(__file__).resolve().parents[2])
sys.path.insert(0, str(SOURCE))

from articula.link import Link, parse_info, parse_setting, parse_status  # noqa: E402
from hil.harness.measured import MeasuredError, load_measured  # noqa: E402
from hil.harness.plan import PlanError, parse_plan  # noqa: E402
from hil.harness.prediction import first_interval_s, predict_plan  # noqa: E402
from hil.harness.randplan import generate  # noqa: E402
from hil.harness.robot import Robot  # noqa: E402
from hil.harness.runner import Runner  # noqa: E402

ROBOT = Robot(SOURCE / "robots" / "mk2plus.json")


def plan_from(tmp_path, text, name="p.arm"):
    path = tmp_path / name
    path.write_text(text)
    return parse_plan(path)


# ---- plans

def test_plan_directives(tmp_path):
    p = plan_from(tmp_path, "#@ title T\n#@ note one\n# comment\n\nL 0 10  # move\n#@ expect error:9\n"
                            "#@ timeout 2.5\nL 1 100\n#@ single-joint 2 140\nL 2 7\n#@ repeat 3 back\nL 0 -5\n")
    assert p.title == "T" and p.notes == ["one"]
    assert [c.line for c in p.commands] == [5, 8, 10, 12]
    assert p.commands[0].text == "L 0 10  # move" and p.commands[0].expect == "ok"
    assert p.commands[1].expect == "error:9" and p.commands[1].timeout == 2.5
    assert p.commands[2].single_joint == (2, 140.0) and p.commands[2].kind == "single-joint"
    assert p.commands[3].repeat == (3, "back")


@pytest.mark.parametrize("text,message", [
    ("#@ expct ok\nL 0 1\n", "unknown directive"),
    ("L 0 1\n#@ expect ok\n", "directive without a command line"),
    ("L 0 1 # really?\n", "realtime byte"),
    ("#@ expect maybe\nL 0 1\n", "#@ expect takes"),
    ("#@ timeout -1\nL 0 1\n", "above 0"),
    ("#@ repeat 1 sideways\nL 0 1\n", "#@ repeat takes"),
    ("# nothing\n", "no command lines"),
])
def test_plan_errors_name_the_line(tmp_path, text, message):
    with pytest.raises(PlanError, match=message) as e:
        plan_from(tmp_path, text)
    assert "p.arm" in str(e.value)


def test_shipped_plans_parse():
    plans = sorted((SOURCE / "hil" / "plans").glob("*.arm"))
    assert {p.name for p in plans} >= {"thesis-single-joint.arm", "thesis-repeatability.arm", "tool-points.arm"}
    for path in plans:
        plan = parse_plan(path)
        assert plan.title != path.stem
        for c in plan.commands:
            assert len(c.text.encode()) <= 64, (path, c.line)


def test_shipped_plans_predictions_meet_their_expectations():
    for path in sorted((SOURCE / "hil" / "plans").glob("*.arm")):
        plan = parse_plan(path)
        preds, _ = predict_plan(ROBOT, path, None)
        for c in plan.commands:
            assert preds[c.line].reply == c.expect, (path.name, c.line, c.text)
    # The thesis's single-joint angles: 4 + 3 + 2 accepted, 5 refused.
    sj = [c for c in parse_plan(SOURCE / "hil" / "plans" / "thesis-single-joint.arm").commands if c.single_joint]
    assert sum(c.expect == "ok" for c in sj) == 9 and sum(c.expect == "error:9" for c in sj) == 5
    assert sorted(a for j, a in (c.single_joint for c in sj) if j == 0) == [0, 10, 30, 90, 120, 180]
    assert sorted(a for j, a in (c.single_joint for c in sj) if j == 1) == [15, 50, 65, 90, 105]
    assert sorted(a for j, a in (c.single_joint for c in sj) if j == 2) == [130, 140, 147]


# ---- prediction

def test_lines_the_parser_refuses_are_predicted_as_errors(tmp_path):
    path = tmp_path / "codec.arm"
    path.write_text("L 0 10\nL 0 1e3\nG 150\nX 1\nL 3 1\n" + "L 0 1 # " + "x" * 70 + "\nL 0 -10\n")
    preds, doc = predict_plan(ROBOT, path, {0: 800})
    assert [preds[n].reply for n in range(1, 8)] == ["ok", "error:3", "error:8", "error:2", "error:6", "error:7", "ok"]
    assert preds[3].steps == [32, 0, 0] and preds[3].codec_rejected
    assert preds[7].steps == [0, 0, 0]
    assert doc["settings"]["$0"] == 800


def test_fk_agrees_with_predict():
    preds, _ = predict_plan(ROBOT, SOURCE / "programs" / "demo.arm", None)
    for p in preds.values():
        for got, want in ((ROBOT.tool_from_actuators(p.actuator_deg), p.tool_quantized),
                          (ROBOT.tool_from_actuators(p.commanded_deg), p.tool_ideal)):
            assert max(abs(a - b) for a, b in zip(got, want)) < 1e-6, p.line


@pytest.mark.parametrize("settings", [{}, {0: 4000, 1: 100000}, {0: 100, 1: 50}, {0: 1, 1: 1}])
def test_first_interval_is_a_one_step_move(tmp_path, settings):
    path = tmp_path / "one.arm"
    path.write_text("L 0 0.3\n")  # one base step
    preds, _ = predict_plan(ROBOT, path, settings)
    assert preds[1].dominant_steps == 1
    assert first_interval_s({0: 600, 1: 2000, **settings}) == pytest.approx(preds[1].seconds, abs=1e-9)


# ---- random plans

def test_random_plans_are_valid_and_repeatable(tmp_path):
    for seed in (1, 2, 3):
        text = generate(ROBOT, 120, seed)
        assert text == generate(ROBOT, 120, seed)
        path = tmp_path / f"r{seed}.arm"
        path.write_text(text)
        plan = parse_plan(path)
        assert len(plan.commands) == 120
        preds, _ = predict_plan(ROBOT, path, None)
        for c in plan.commands:
            assert preds[c.line].reply == c.expect, (seed, c.line, c.text)
            assert len(c.text) <= 64
        assert sum(c.expect != "ok" for c in plan.commands) >= 5
    assert generate(ROBOT, 50, 1) != generate(ROBOT, 50, 2)


# ---- measured positions

def test_measured_csv(tmp_path):
    f = tmp_path / "m.csv"
    f.write_text("plan_line,x_mm,y_mm,z_mm,comment\n5,1,2,3,a\n5,3,4,5,b\n7,0,0,0,\n")
    m = load_measured(f, ["a.arm"])
    assert m[("a.arm", 5)] == ([2.0, 3.0, 4.0], 2) and m[("a.arm", 7)][1] == 1
    with pytest.raises(MeasuredError, match="plan"):
        load_measured(f, ["a.arm", "b.arm"])
    f.write_text("plan,plan_line,x_mm,y_mm,z_mm\nb,3,1,1,1\n")
    assert load_measured(f, ["a.arm", "b.arm"])[("b.arm", 3)][1] == 1
    f.write_text("plan_line,x_mm,y_mm\n1,2,3\n")
    with pytest.raises(MeasuredError, match="z_mm"):
        load_measured(f, ["a.arm"])
    f.write_text("plan_line,x_mm,y_mm,z_mm\nfive,1,2,3\n")
    with pytest.raises(MeasuredError, match=":2:"):
        load_measured(f, ["a.arm"])


def test_the_studios_experiment_csv_is_read_as_measurements(tmp_path):
    """The Experiment panel's CSV (the host library's experiment_csv): its first section is
    the measurements; the tables after it are not measurements."""
    import articula
    pt = lambda line, joint, m: {"joint": joint, "angle": 15, "line": line, "command": f"L {joint} 15",
                                 "ideal": [200, 10, 150], "quant": [200.5, 10, 150], "measured": m}
    e = {"plan": "a.arm", "title": "T, with a comma", "robot": "MK2", "when": "now",
         "points": [pt(5, 0, [201, 10.5, 149]), pt(7, 1, None), pt(9, 1, [199, 9, 151.25])],
         "chains": [{"chain": 1, "moves": 1, "back_moves": 1, "line_before": 9, "line_out": 11, "line_back": 12,
                     "start": [199, 9, 151], "dest_quant": [210, 0, 100], "dest_ideal": [210, 0, 100],
                     "back_quant": [199, 9, 151], "start_measured": [199, 9, 151.25], "dest_measured": [211, 0, 99],
                     "back_measured": None, "steps_back": True}], "targets": []}
    text = articula.experiment_csv(e)
    assert text.startswith('# T, with a comma; robot MK2; now\nplan,plan_line,x_mm,y_mm,z_mm\na.arm,5,201,10.5,149\n')
    f = tmp_path / "page.csv"
    f.write_text(text)
    m = load_measured(f, ["a.arm"])
    # every measured pose once (line 9 is a point and the chain's start), nothing from the tables
    assert m == {("a.arm", 5): ([201.0, 10.5, 149.0], 1), ("a.arm", 9): ([199.0, 9.0, 151.25], 1),
                 ("a.arm", 11): ([211.0, 0.0, 99.0], 1)}
    assert "\ntable,joint,axis,poses,max_pct,max_mm,avg_mm\nmeasured_vs_model,0,x,1," in text
    assert "\nchain,moves,back_moves," in text
    # a bad row names its line in the file, the comment counted
    f.write_text(text.replace("a.arm,5,201", "a.arm,five,201"))
    with pytest.raises(MeasuredError, match=":3:"):
        load_measured(f, ["a.arm"])


def test_joint_verdicts():
    import articula
    p = lambda joint, m: {"joint": joint, "ideal": [200, 0, 100], "quant": [200.4, 0, 100], "measured": m}
    v = articula.joint_verdicts([p(0, [203, 0, 100]), p(1, [209, 0, 100]), p(2, None)])
    assert [(x["joint"], x["measured"], x["within"]) for x in v] == [(0, True, True), (1, True, False), (2, False, False)]
    assert v[0]["text"] == "as simulated: the arm is within 2.60 mm of the model on every axis (whole steps alone: 0.40 mm)."
    assert v[1]["text"].startswith("differs from the model by up to 8.60 mm") and "check this joint's zero" in v[1]["text"]
    assert v[2]["text"] == "not measured; whole steps alone leave up to 0.40 mm."


# ---- the serial line

def test_parse_reports():
    st = parse_status("<Run|S:32,0,-8|A:10.133,90.000,-5.821|G:50|Q:7|C:1|W:14>")
    assert (st.state, st.steps, st.angles, st.gripper, st.queue, st.coils, st.warning) == \
        ("Run", [32, 0, -8], [10.133, 90.0, -5.821], 50, 7, 1, 14)
    assert parse_status("<Idle|S:1,x>") is None and parse_status("ok") is None
    info = parse_info("[Articula|V:0.1.0|P:2|J:3|R:MK2 Plus]")
    assert (info.version, info.protocol, info.joints, info.robot, info.warning) == ("0.1.0", 2, 3, "MK2 Plus", None)
    assert parse_info("[Articula|V:0.1|P:2|J:3|R:MK2 Plus]") is None  # the firmware's parser: V has three parts
    assert parse_setting("$5=300.000") == (5, 300.0) and parse_setting("$x=1") is None


class ScriptedArm:
    """A pyserial stand-in: answers like the firmware for I, $, ? and moves; `script` may
    replace the answer to the n-th plan line (1-based, counting moves only)."""

    def __init__(self, script=None):
        self.timeout = 0.05
        self.out = b""
        self.inbuf = b""
        self.steps = [0, 0, 0]
        self.moves = 0
        self.script = script or {}

    @property
    def in_waiting(self):
        return len(self.out)

    def write(self, data):
        for b in data:
            c = bytes([b])
            if c == b"?":
                a = ",".join(f"{m.zero + m.direction * s * m.deg_per_step:.3f}" for m, s in zip(ROBOT.motors, self.steps))
                self.out += f"<Idle|S:{','.join(map(str, self.steps))}|A:{a}|G:0|Q:8|C:1>\n".encode()
            elif c == b"\n":
                self.line(self.inbuf.decode())
                self.inbuf = b""
            else:
                self.inbuf += c

    def line(self, text):
        if text == "I":
            self.out += b"[Articula|V:0.1.0|P:2|J:3|R:MK2 Plus|W:14]\nok\n"
        elif text == "$":
            self.out += b"$0=600.000\n$1=2000.000\n$2=2000.000\n$3=0.000\n$4=200.000\n$5=300.000\nok\n"
        else:
            self.moves += 1
            action = self.script.get(self.moves)
            if action == "banner":
                self.out += b"[Articula|V:0.1.0|P:2|J:3|R:MK2 Plus|W:14]\n"
                self.steps = [0, 0, 0]
            elif action == "zero":
                self.steps = [0, 0, 0]
                self.out += b"ok\n"
                return
            elif action == "silent":
                return
            elif action == "lazy":  # answers ok and moves nothing
                self.out += b"ok\n"
                return
            if text.startswith("L 0"):
                self.steps[0] += 32 if "-" not in text else -32
            self.out += b"ok\n"

    def read(self, n):
        d, self.out = self.out[:n], self.out[n:]
        return d

    def flush(self):
        pass

    def reset_input_buffer(self):
        self.out = b""

    def close(self):
        pass


class ScriptedTarget:
    kind = "scripted"
    has_pins = False
    trace = None

    def __init__(self, arm):
        self.arm = arm
        self.fresh = True

    def start_plan(self, name, out_dir):
        return Link(self.arm)

    def alive(self, settle=0.0):
        return True

    def end_plan(self, vanished=False):
        return None

    def close(self):
        pass


@pytest.mark.parametrize("action,kind,text", [
    ("banner", "reset", "an info line nobody asked for"),
    ("zero", "reset", "every motor back at step 0 (it was on [32, 0, 0])"),
    ("silent", "timeout", "no reply within 0.5 s"),
])
def test_reset_and_silence_are_faults_with_the_plan_line(tmp_path, action, kind, text):
    plan = plan_from(tmp_path, "L 0 10\nL 0 10\nL 0 -10\nL 0 -10\n")
    arm = ScriptedArm({2: action})
    runner = Runner(ScriptedTarget(arm), ROBOT, tmp_path, timeout=0.5)
    res = runner.run_plan(plan)
    faults = [f for f in res.faults if f.kind == kind]
    assert faults and faults[0].line == 2 and text in faults[0].message, res.faults
    assert res.records[0].matched and res.records[0].reply == "ok"
    assert not res.records[3].sent  # the plan stopped
    assert "stopped at p.arm:2" in res.aborted


def test_a_step_mismatch_is_reported(tmp_path):
    from hil.harness import report

    plan = plan_from(tmp_path, "L 0 10\nL 0 10\nL 0 -10\n")
    res = Runner(ScriptedTarget(ScriptedArm({2: "lazy"})), ROBOT, tmp_path, timeout=0.5).run_plan(plan)
    assert not res.faults and not res.aborted
    assert [r.matched for r in res.records] == [True, False, False]
    assert res.records[1].fw_steps == [32, 0, 0] and res.records[1].pred.steps == [63, 0, 0]
    run = report.Run(results=[res], target="scripted port", robot_name=ROBOT.name, robot_path="mk2plus.json",
                     vnano=None, elf=None, started="now", wall_s=0.1, settings_override={},
                     measured_path=None, has_pins=False, command_line="test")
    md = report.build(run, tmp_path / "out", ROBOT)
    summary = report.summary_text(run, md)
    assert "steps matched: 1/3 (prediction = firmware)" in summary and "MISMATCH OR FAULT" in summary
    assert "| 2 | `L 0 10` | ok | ok | ok | 63 0 0 | 32 0 0 | **no** |" in md.read_text()
    assert (tmp_path / "out" / "steps.png").stat().st_size > 0


def test_the_reports_per_cent_rule_is_the_host_librarys():
    """report.py's words about the per cent and the numbers it prints come from one rule:
    host/lib/experiment.h's, through articula.axis_errors."""
    import articula
    from hil.harness.report import PCT_MIN_MM

    assert articula.axis_errors((2.0, 0, 0), (PCT_MIN_MM, 0, 0))["pct"][0] == 100.0
    assert articula.axis_errors((2.0, 0, 0), (PCT_MIN_MM - 0.001, 0, 0))["pct"][0] is None


# ---- a move's span on the pins

def test_a_servos_alternation_at_rest_is_not_part_of_its_move():
    """A servo at rest on a tick's edge can show one tick and back (two pulses decode apart). On a
    busy machine the host sends the next line, and looks at the pins after it, later in the
    virtual Nano's time: an alternation before or after the move must not stretch its span."""
    from hil.harness.runner import pin_span
    from hil.harness.trace import TraceRow

    def row(us, motor, steps):
        return TraceRow(cycle=int(us * 16), motor=motor, steps=steps, pattern="", event="step+", time_us=us)

    # motor 1 (a servo) moves 10 -> 14; it flickers to 11 and back 300 ms before the move, and to
    # 15 and back 400 ms after it; motor 0 (a stepper, no slack) moves 0 -> 2 inside the move.
    steps = [row(100_000, 1, 11), row(120_000, 1, 10),
             row(400_000, 1, 11), row(410_000, 0, 1), row(420_000, 1, 12), row(440_000, 1, 14),
             row(445_000, 0, 2),
             row(800_000, 1, 15), row(820_000, 1, 14)]
    assert pin_span(steps, [0, 1, 0], [0, 10, 0], [2, 14, 0]) == (400_000, 445_000)
    # with no slack (steppers only) every step counts
    assert pin_span(steps, [0, 0, 0], [0, 10, 0], [2, 14, 0]) == (100_000, 820_000)
    # a servo that never showed where it started: its first change is the move's
    assert pin_span(steps[2:6], [0, 1, 0], [0, 10, 0], [2, 14, 0]) == (400_000, 440_000)


def test_a_moves_rows_start_where_the_firmware_had_its_line():
    """The virtual Nano's clock runs on between one command and the next line (it sleeps through
    the wait, however long the host takes), so rows read after the line went out can still be
    from before the firmware had it. The trace's `line` row (the LF's receipt, in the Nano's
    time) divides them. A servo at 10 whose pin flipped to 9 before it, and stayed there, then
    moved 10 -> 6: the move is not dated from the flip (a CI run measured a move 2 s longer
    than predicted that way)."""
    from hil.harness.runner import after_line, pin_span
    from hil.harness.trace import TraceRow

    def row(us, motor, steps, event="step-"):
        return TraceRow(cycle=int(us * 16), motor=motor, steps=steps, pattern="", event=event, time_us=us)

    rows = [row(50_000, 0, 3, "step+"),  # read with the command before
            row(100_000, 1, 9), row(2_000_000, -1, 7, "line"),
            row(2_030_000, 1, 8), row(2_050_000, 1, 7), row(2_090_000, 1, 6)]
    at, pins = after_line(rows, 1, len(rows), [3, 10, 0])
    assert (at, pins) == (3, [3, 9, 0])
    assert pin_span(rows[at:], [0, 1, 0], pins, [3, 6, 0]) == (2_030_000, 2_090_000)
    # from every row since the send, from the pins then: dated from the flip, 1.93 s early
    assert pin_span([r for r in rows[1:] if r.is_step], [0, 1, 0], [3, 10, 0], [3, 6, 0])[0] == 100_000
    # no `line` row (an older virtual Nano): the rows since the send, the pins at the send
    assert after_line(rows[:2], 1, 2, [3, 10, 0]) == (1, [3, 10, 0])
