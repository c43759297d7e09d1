"""The two bindings offer the same operations (as MuJoCo's bindings test holds its Python
binding to its C API). Python (python/src) and the web engine (wasm/src) are thin doors to
one host library; an operation added to one and not the other, or a name that drifts, fails
here. Each operation is listed once, with its name on each side; what only one side has is
listed with the reason."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import articula
from articula import _core

REPO = Path(__file__).resolve().parents[2]
WASM_DIR = Path(os.environ.get("ARTICULA_WASM_DIR", REPO / "build" / "wasm" / "wasm"))

# (Python, web): the same operation of the host library. Python names are attributes of
# articula._core ("Robot.fk"), web names are the engine module's exports ("Robot.pose",
# "predict"). Several Python names may share one web call that answers them at once.
SAME = [
    # robots: files, description, poses, IK, motors
    ("Robot.load", "Robot.load"),
    ("Robot.parse", "Robot.parse"),
    ("Robot.from_legacy", "Robot.fromLegacy"),
    ("Robot.with_link_lengths", "Robot.setLinkLengths"),
    ("Robot.name", "Robot.info"), ("Robot.description", "Robot.info"), ("Robot.source", "Robot.info"),
    ("Robot.import_notes", "Robot.info"), ("Robot.num_joints", "Robot.info"), ("Robot.num_rows", "Robot.info"),
    ("Robot.num_motors", "Robot.info"), ("Robot.joint_names", "Robot.info"), ("Robot.motor_names", "Robot.info"),
    ("Robot.dh", "Robot.info"), ("Robot.joints", "Robot.info"), ("Robot.limits", "Robot.info"),
    ("Robot.home", "Robot.info"), ("Robot.motors", "Robot.info"), ("Robot.links", "Robot.info"),
    ("Robot.gripper", "Robot.info"), ("Robot.tool_offset", "Robot.info"), ("Robot.reach_mm", "Robot.info"),
    ("Robot.wiring", "Robot.info"), ("Robot.example_places", "Robot.info"),
    ("Robot.fk", "Robot.pose"), ("Robot.frames", "Robot.pose"), ("Robot.dh_table", "Robot.pose"),
    ("Robot.within_limits", "Robot.pose"), ("Robot.finger_poses", "Robot.pose"),
    ("Robot.jacobian", "Robot.jacobian"),
    ("Robot.ik", "Robot.ik"),
    ("Robot.joints_from_motors", "Robot.jointsFromMotors"),
    ("Robot.motors_from_joints", "Robot.motorsFromJoints"),
    ("Robot.to_urdf", "Robot.urdf"),
    ("Robot.nano_config", "Robot.nanoConfig"),
    # programs
    ("Robot.predict", "predict"),
    ("Robot.run", "run"),
    ("Robot.quantize", "quantize"),
    ("detect_format", "programFormat"),
    ("Robot.parse_program", "parseProgram"),
    ("Robot.program_fit", "programFit"),
    ("Robot.blocks_program", "blocksProgram"),
    ("Robot.program_actions", "programActions"),
    ("Robot.protocol_line", "protocolLine"),
    ("Robot.move_line", "moveLine"),
    ("Robot.draw", "drawing"),
    ("Robot.reach_map", "reachMap"),
    ("Robot.ink", "ink"),
    ("Robot.drawing_check", "drawingCheck"),
    ("Robot.timeline", "Timeline.make"),
    ("Timeline.at", "Timeline.at"),
    ("Timeline.duration", "Timeline.duration"),
    ("Timeline.records", "Timeline.make"), ("Timeline.start_q", "Timeline.make"), ("Timeline.samples", "Timeline.make"),
    # physics
    ("Sim.__init__", "Sim.create"),
    ("Sim.reset", "Sim.reset"),
    ("Sim.restart", "Sim.restart"),
    ("Sim.step", "Sim.step"),
    ("Sim.step_path", "Sim.stepPath"),
    ("Sim.run_until", "Sim.runUntil"),
    ("Sim.load_program", "Sim.loadProgram"),
    ("Sim.command", "Sim.command"),
    ("Sim.events", "Sim.events"),
    ("Sim.state", "Sim.state"),
    ("Sim.objects", "Sim.objects"),
    ("Sim.drag", "Sim.drag"),
    ("Sim.release", "Sim.release"),
    ("Sim.set_belt", "Sim.setBelt"),
    ("Sim.time", "Sim.time"),
    ("Sim.dt", "Sim.dt"),
    ("Sim.busy", "Sim.busy"),
    ("Sim.done", "Sim.done"),
    ("Sim.end_time", "Sim.endTime"),
    ("Sim.scene_name", "Sim.sceneName"),
    ("Cell.__init__", "Cell.create"),
    ("Cell.reset", "Cell.reset"),
    ("Cell.step", "Cell.step"),
    ("Cell.run_until", "Cell.runUntil"),
    ("Cell.run", "Cell.run"),
    ("Cell.arm", "Cell.arm"),
    ("Cell.arms", "Cell.arms"),
    ("Cell.state", "Cell.state"),
    ("Cell.events", "Cell.events"),
    ("Cell.name", "Cell.name"),
    ("Cell.time", "Cell.time"),
    ("Cell.done", "Cell.done"),
    ("Cell.end_time", "Cell.endTime"),
    ("Cell.deadlock", "Cell.deadlock"),
    ("Cell.mat_svg", "Cell.matSvg"),
    ("Cell.predict", "Cell.predict"),
    ("Cell.objects", "Cell.objects"),
    # the arm's protocol
    ("_status_table", "statusTable"),
    ("_status_table", "statusText"),
    ("_settings_table", "settingsTable"),
    ("_pen_fields", "penFields"),
    ("parse_arm_line", "parseArmLine"),
    ("first_interval_s", "firstIntervalS"),
    ("line_command", "lineCommand"),
    ("STEP_TICK_HZ", "stepTickHz"),
    # the sim-vs-real experiment
    ("axis_errors", "axisErrors"),
    ("table4", "table4"),
    ("measurement_question", "measurementQuestion"),
    ("parse_plan", "parsePlan"),
    ("table5", "table5"),
    ("joint_verdicts", "jointVerdicts"),
    ("experiment_csv", "experimentCsv"),
    ("repeat_chains", "repeatChains"),
    ("tool_points", "toolPoints"),
]

# What one side has alone, and why.
PYTHON_ONLY = {
    "Robot.fk_batch": "numpy batches: many poses in one call without a Python loop (the page asks one pose at a time)",
    "Robot.jacobian_batch": "numpy batches",
    "Robot.ik_batch": "numpy batches",
    "Robot.check_program": "reads a program without running it; the page loads programs through predict or run",
    "Robot.coupling": "the coupling matrix as numpy; the web's info carries the motors and joints it maps",
    "Sim.run": "runs a loaded program to its end in one call, for scripts; the page steps in real time",
    "Sim.steps": "the count of world steps, for scripts",
    "rpy_deg": "roll, pitch, yaw of a numpy rotation; the web's poses carry rpy already",
    "protocol_number": "the harness's random plans and fuzz put numbers into lines of their own making; the page "
                       "writes whole lines (Robot.protocolLine, the same writer)",
}
WEB_ONLY = {
    "Robot.loaded": "JavaScript holds an empty Robot before a load succeeds; Python only makes loaded ones",
    "Robot.scratch": "the hot paths' heap array (a typed-array view, no JSON per call)",
    "Robot.fkScratch": "the hot path of fk on the heap array",
    "Robot.ikScratch": "the hot path of ik on the heap array",
}
# Python's own plumbing, not operations.
PYTHON_PLUMBING = {"ProgramError", "RobotFileError", "SceneError", "CellError", "LegacyError", "IkResult"}


def python_ops() -> set[str]:
    ops = set()
    for name in dir(_core):
        if name.startswith("__") or name in PYTHON_PLUMBING:
            continue
        obj = getattr(_core, name)
        if isinstance(obj, type):
            for attr in dir(obj):
                if attr.startswith("_") and attr != "__init__":
                    continue
                if attr == "__init__" and type(obj.__dict__.get("__init__")).__name__ != "nb_method":
                    continue  # no constructor of its own: made by a loader (Robot.load) or a call (Robot.timeline)
                ops.add(f"{name}.{attr}")
        else:
            ops.add(name)
    return ops


def web_ops() -> set[str]:
    script = f"""
import {{ createRequire }} from "node:module";
import {{ readFileSync }} from "node:fs";
import {{ pathToFileURL }} from "node:url";
globalThis.require ??= createRequire(import.meta.url);
globalThis.__dirname ??= {json.dumps(str(WASM_DIR))};
const {{ default: create }} = await import(pathToFileURL({json.dumps(str(WASM_DIR / "engine.mjs"))}).href);
const M = await create({{ wasmBinary: readFileSync({json.dumps(str(WASM_DIR / "engine.wasm"))}) }});
const ops = [];
for (const cls of ["Robot", "Sim", "Timeline", "Cell"])
  for (const k of Object.getOwnPropertyNames(M[cls].prototype))
    if (!["constructor", "delete", "isDeleted", "clone", "isAliasOf", "deleteLater"].includes(k)) ops.push(`${{cls}}.${{k}}`);
for (const k of ["predict", "run", "quantize", "programFormat", "parseProgram", "programFit", "blocksProgram", "programActions", "protocolLine", "moveLine", "drawing", "reachMap", "ink", "drawingCheck", "statusText", "statusTable", "settingsTable", "penFields", "parseArmLine", "firstIntervalS", "lineCommand",
                 "axisErrors", "table4", "measurementQuestion", "parsePlan", "table5", "toolPoints", "jointVerdicts", "experimentCsv", "repeatChains"])
  if (typeof M[k] === "function") ops.push(k);
for (const k of ["stepTickHz"])  // the core's constants
  if (typeof M[k] === "number") ops.push(k);
console.log(JSON.stringify(ops));
"""
    p = subprocess.run(["node", "--no-experimental-fetch", "--input-type=module", "-e", script], capture_output=True, text=True,
                       timeout=120)
    assert p.returncode == 0, p.stderr
    return set(json.loads(p.stdout))


def test_every_operation_is_on_both_sides():
    py, web = python_ops(), web_ops()
    missing_py = sorted({p for p, _ in SAME} - py)
    missing_web = sorted({w for _, w in SAME} - web)
    assert missing_py == [], f"listed as shared, missing from Python: {missing_py}"
    assert missing_web == [], f"listed as shared, missing from the web engine: {missing_web}"


def test_no_operation_on_one_side_only_unless_listed():
    py, web = python_ops(), web_ops()
    unlisted_py = sorted(py - {p for p, _ in SAME} - set(PYTHON_ONLY))
    unlisted_web = sorted(web - {w for _, w in SAME} - set(WEB_ONLY))
    assert unlisted_py == [], f"Python has operations the web engine lacks (bind them in wasm/src, or list why): {unlisted_py}"
    assert unlisted_web == [], f"the web engine has operations Python lacks (bind them in python/src, or list why): {unlisted_web}"
    assert set(PYTHON_ONLY) <= py and set(WEB_ONLY) <= web, "a listed one-sided operation no longer exists"


# Single-joint poses (joint, value, reference): appendix K's joint 0 errors, and a y near 0.
POINTS = [(0, (14.095, 158.479, 8.4975), (14.0, 158.0, 8.0)), (0, (40.27, 158.48, 10.0), (37.6, 158.0, 8.0)),
          (2, (100.0, 0.3, -50.0), (99.0, 0.1, -51.0))]


# Repeatability chains: one measured throughout (back against its measured start), one not.
CHAINS = [{"chain": 1, "moves": 2, "back_moves": 2, "start": [300, 0, 150], "dest_quant": [250.4, 60.1, 150],
           "dest_ideal": [250.0, 60.0, 150], "back_quant": [300, 0, 150], "start_measured": [301, 0.5, 149],
           "dest_measured": [251, 61, 150.5], "back_measured": [301.5, 0.2, 149.3]},
          {"chain": 2, "moves": 1, "back_moves": 0, "start": [300, 0, 150], "dest_quant": [280, 10, 150],
           "dest_ideal": [280, 10, 150], "back_quant": None, "start_measured": None, "dest_measured": None,
           "back_measured": None}]


# Tool points: one measured 2 mm above its target.
TARGETS = [{"line": 14, "target": [171, 120, 185], "quant": [171.5, 119.8, 185.2], "ideal": [171, 120, 185],
            "measured": [171, 120, 187]},
           {"line": 15, "target": [150, -70, 169], "quant": [150, -70, 169], "ideal": [150, -70, 169], "measured": None}]


# Block actions as the studio unrolls them: a move, a refused joint, a line, the gripper, a speed.
BLOCK_OPS = [
    {"op": "joints", "values": [0, 90, -110], "block": "a"},
    {"op": "joint_to", "joint": 1, "value": 140, "block": "b"},
    {"op": "line_to", "xyz": [235, 0, 213], "speed": 30, "block": "c"},
    {"op": "gripper", "percent": 40, "block": "d"},
    {"op": "speed", "percent": 50, "block": "e"},
]


def test_both_sides_answer_alike():
    """The same question through both doors: the same numbers and the same refusals."""
    mk2 = articula.Robot.load("mk2plus")
    script = "const POINTS = " + json.dumps(POINTS) + ";\nconst CHAINS = " + json.dumps(CHAINS) + ";\nconst TARGETS = " + json.dumps(TARGETS) + ";\n" + \
        "const BLOCK_OPS = " + json.dumps(BLOCK_OPS) + ";\n" + f"""
import {{ nodeEngine }} from {json.dumps(str(REPO / "wasm" / "js" / "node.mjs"))};
const e = await nodeEngine({json.dumps(str(WASM_DIR))});
const r = e.robot("mk2plus");
const out = {{ jac: r.jacobian([10, 70, -60]), tl: e.timeline(r, "L 0 30\\nL 1 -20\\n", "t.arm", [0, 90, -90]).at(0.4),
  samples: e.timeline(r, "P 250 -100 100\\nP 250 100 100\\n", "s.arm", [0, 90, -90]).doc.samples,
  arm: e.parseArmLine("<Run|S:95,0,0|A:30.083,90.000,0.000|G:100|Q:7|C:1>"), first: e.firstIntervalS(800, 3000),
  t4: e.table4(POINTS.map(([joint, value, reference]) => ({{ joint, value, reference }}))),
  ax: e.axisErrors([10.5, 0.4, -201], [10, 0.5, -200]), q: e.measurementQuestion([23.5, 0, 21.3], [235, 0, 213], 370),
  qnan: e.measurementQuestion([NaN, 0, 213], [235, 0, 213], 370), cfg: r.nanoConfig(),
  t5: e.table5(CHAINS), tp: e.toolPoints(TARGETS),
  blocks: r.blocksProgram(BLOCK_OPS), back: r.programActions("# hi\\nM 10 80 -20\\nG 40\\n", "b.arm"),
  line: r.protocolLine("T", [250.12345, -30, 150, 30]), move: r.moveLine([10, 80, -100]),
  drawing: r.draw({{ text: "Hi", width: 30, at: [260, 0], z: 0, pen: 120 }}),
  far: r.draw({{ shape: "star", width: 40, at: [120, 0], z: 0, pen: 120 }}),
  map: r.reachMap({{ paper: "A5", at: [225, 0], z: 0, pen: 120, cell: 10 }}),
  ink: r.ink({{ steps: [0, 0, 0, 40, -300, 200, 41, -300, 200], z: 0, pen: 120 }}),
  check: r.drawingCheck({{ program: r.draw({{ shape: "square", width: 30, at: [250, 0], z: 0, pen: 120 }}).program,
                          target: {{ shape: "square", width: 40, at: [250, 0] }}, z: 0, pen: 120, tolerance: 3 }}),
  plan: e.parsePlan("#@ title T\\n#@ single-joint 1 15\\nL 1 0\\n#@ repeat 2 out\\nP 1 2 3\\n", "p.arm") }};
try {{ e.parsePlan("#@ expct ok\\nL 0 1\\n", "bad.arm"); }} catch (x) {{ out.badPlan = x.message; }}
try {{ e.robot("puma560").nanoConfig(); }} catch (x) {{ out.noNano = x.message; }}
try {{ e.table4([{{ joint: 0, value: [1, 2] }}]); }} catch (x) {{ out.badPoint = x.message; }}
try {{ r.pose([0, NaN, 0]); }} catch (x) {{ out.nan = x.message; }}
try {{ r.ik({{ target: [1, 2] }}); }} catch (x) {{ out.target = x.message; }}
console.log(JSON.stringify(out));
"""
    p = subprocess.run(["node", "--no-experimental-fetch", "--input-type=module", "-e", script], capture_output=True, text=True,
                       timeout=120)
    assert p.returncode == 0, p.stderr
    web = json.loads(p.stdout)
    import numpy as np
    np.testing.assert_allclose(mk2.jacobian([10, 70, -60]), web["jac"], atol=1e-12)
    tl = mk2.timeline(articula.Program.parse("L 0 30\nL 1 -20\n", "t.arm")).at(0.4)
    assert tl["line"] == web["tl"]["line"] and tl["steps"] == web["tl"]["steps"]
    np.testing.assert_allclose(tl["q"], web["tl"]["q"], atol=1e-12)
    # the path the plots draw: the same samples, the tool's curve and all
    samples = mk2.timeline(articula.Program.parse("P 250 -100 100\nP 250 100 100\n", "s.arm")).samples()
    assert samples["t"] == web["samples"]["t"] and samples["line"] == web["samples"]["line"]
    np.testing.assert_allclose(samples["tool"], web["samples"]["tool"], atol=1e-9)
    np.testing.assert_allclose(samples["q"], web["samples"]["q"], atol=1e-9)
    # blocks to a program and back, and the one line formatter: the same text, problems and actions
    assert mk2.blocks_program(BLOCK_OPS) == web["blocks"]
    assert web["blocks"]["problems"] and web["blocks"]["text"].count("\n") == len(BLOCK_OPS) + 1
    assert mk2.program_actions("# hi\nM 10 80 -20\nG 40\n", "b.arm") == web["back"]
    assert mk2.protocol_line("T", [250.12345, -30, 150, 30]) == web["line"] == "T 250.123 -30 150 30"
    assert mk2.move_line([10, 80, -100]) == web["move"]
    # the one number writer (the firmware's, shared/articula/protocol.h): thousandths, trimmed or every decimal
    assert [articula.protocol_number(v) for v in (12.5, -0.0004, 0.0005, -0.25, 1e9 / 1000, 7)] == \
        ["12.5", "0", "0.001", "-0.25", "1000000", "7"]
    assert articula.protocol_number(12.5, every_decimal=True) == "12.500"
    assert articula.protocol_number(-0.0004, every_decimal=True) == "0.000"  # no "-0.000"
    # a drawing: the same strokes, program and reach check (a moved star's advice too)
    hi = mk2.draw(text="Hi", width=30, at=(260, 0), z=0, pen=120)
    def same(a, b):  # equal, numbers to 1e-9 (two compilers' rounding)
        if isinstance(a, dict):
            return isinstance(b, dict) and a.keys() == b.keys() and all(same(a[k], b[k]) for k in a)
        if isinstance(a, list):
            return isinstance(b, list) and len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
        if isinstance(a, float) or isinstance(b, float):
            return abs(a - b) <= 1e-9 * max(1.0, abs(a))
        return a == b
    assert same(hi, web["drawing"]) and hi["reach"]["fits"] and hi["program"].count("\nT ") > 5
    # the line the arm will draw: the pen at every step, within the steps' reach of the drawing
    assert hi["ink"]["steps"] > 10 and 0 < hi["ink"]["worst_mm"] < 3 and hi["seconds"] > 1
    far = mk2.draw(shape="star", width=40, at=(120, 0), z=0, pen=120)
    assert same(far, web["far"]) and not far["reach"]["fits"] and far["program"] == ""
    assert "toward +x (away from the base)" in far["reach"]["advice"]
    # the sheet's reach map and the ink of step counts: the same
    assert mk2.reach_map(paper="A5", at=(225, 0), z=0, pen=120, cell=10) == web["map"] and "1" in web["map"]["reached"]
    assert same(mk2.ink(steps=[0, 0, 0, 40, -300, 200, 41, -300, 200], z=0, pen=120), web["ink"])
    sq30 = mk2.draw(shape="square", width=30, at=(250, 0), z=0, pen=120)["program"]
    check = mk2.drawing_check(program=sq30, target={"shape": "square", "width": 40, "at": [250, 0]}, z=0, pen=120, tolerance=3)
    assert same(check, web["check"]) and not check["met"] and check["ink_off_mm"] > 3
    assert _core.parse_arm_line("<Run|S:95,0,0|A:30.083,90.000,0.000|G:100|Q:7|C:1>") == web["arm"]
    assert _core.first_interval_s(800, 3000) == web["first"]
    # the experiment's numbers: the same to the digit
    assert articula.table4(POINTS) == web["t4"]
    assert articula.axis_errors((10.5, 0.4, -201), (10, 0.5, -200)) == web["ax"]
    assert articula.measurement_question((23.5, 0, 21.3), (235, 0, 213), 370) == web["q"]
    assert articula.measurement_question((float("nan"), 0, 213), (235, 0, 213), 370) == web["qnan"]
    assert web["qnan"].startswith("x is not a number")
    assert articula.table5(CHAINS) == web["t5"] and web["t5"][1]["measured_return_mm"] is None
    assert articula.tool_points(TARGETS) == web["tp"] and web["tp"][0]["measured_from_target_mm"] == 2.0
    # the Nano's configuration and the plan reader: the same, and the same refusals
    assert mk2.nano_config() == web["cfg"] and web["cfg"]["checksum"] == 21232
    plan = articula.parse_plan("#@ title T\n#@ single-joint 1 15\nL 1 0\n#@ repeat 2 out\nP 1 2 3\n", "p.arm")
    assert plan == web["plan"] and [c["kind"] for c in plan["commands"]] == ["single-joint", "repeat-out"]
    # (the robot's file is where each side keeps it: /robots/ in the engine's files)
    for call, message in ((lambda: articula.parse_plan("#@ expct ok\nL 0 1\n", "bad.arm"), web["badPlan"]),
                          (lambda: articula.Robot.load("puma560").nano_config(), web["noNano"])):
        try:
            call()
        except ValueError as e:
            assert str(e).replace(str(REPO), "") == message
        else:
            raise AssertionError(f"Python accepted what the web engine refused: {message}")
    assert web["badPoint"] == "point 0's value must be three numbers [x, y, z]"
    for call, message in ((lambda: mk2.fk([0, float("nan"), 0]), web["nan"]), (lambda: mk2.ik([1, 2]), web["target"])):
        try:
            call()
        except ValueError as e:
            assert str(e) == message
        else:
            raise AssertionError(f"Python accepted what the web engine refused: {message}")
