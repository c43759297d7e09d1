#!/usr/bin/env python3
"""Turns a robot file (robots/README.md) into firmware/robot_config.h for the Nano.

    robot_config.py ROBOT.json OUTPUT.h

The header holds the robot's constants as plain C initialisers; the firmware builds the
core's structures from them at start-up (articula::Model, Actuation, YppArm), so every
computation on them is the shared core's, the same as on the host. This script only
transcribes: degrees become radians or millidegrees, names become indices. The host
loader (host/lib/robot_file.cpp) is the full validator; a test checks that the header
this script writes describes the same arm as the loader reads.

Used by CMake (the AVR build and the native tests) and by PlatformIO (extra_script).
Standard library only.
"""
import json
import math
import os
import sys

MAX_MOTORS = 3  # the Nano's pin map (firmware/src/pins.h) wires three motors
PARAMS = ("theta", "d", "alpha")  # the order joint variables are numbered in a row


class ConfigError(Exception):
    pass


def fail(path, problem):
    raise ConfigError(f"{path}: {problem}")


def number(value, path):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        fail(path, f"expected a finite number, got {value!r}")
    return float(value)


def c_float(x):
    """A float literal that rounds to the same float as the double x."""
    text = repr(float(x))
    if "e" not in text and "." not in text:
        text += ".0"
    return text + "f"


def millideg(deg):
    """Degrees to millidegrees, rounded half away from zero (as articula::to_millideg)."""
    m = deg * 1000.0
    r = int(m)  # truncates toward zero
    frac = m - r
    if frac >= 0.5:
        r += 1
    if frac <= -0.5:
        r -= 1
    return r


def generate(robot, source):
    name = robot.get("name")
    if not isinstance(name, str) or not name:
        fail("/name", "missing or empty")
    rows = robot.get("dh")
    if not isinstance(rows, list) or not rows:
        fail("/dh", "missing or empty")

    # Joint variables, in the loader's order: rows top to bottom, theta, d, alpha.
    joints, linked, consts = [], [], []
    for i, row in enumerate(rows):
        path = f"/dh/{i}"
        if not isinstance(row, dict):
            fail(path, "expected an object")
        const = {"a": number(row.get("a"), path + "/a")}
        for p in PARAMS:
            v = row.get(p)
            unit_angle = p != "d"
            if isinstance(v, dict) and "joint" in v:
                lo = number(v.get("min"), f"{path}/{p}/min")
                hi = number(v.get("max"), f"{path}/{p}/max")
                if unit_angle:
                    lo, hi = math.radians(lo), math.radians(hi)
                joints.append({"name": v["joint"], "row": i, "param": PARAMS.index(p), "lo": lo, "hi": hi})
                const[p] = 0.0
            elif isinstance(v, dict) and "linked" in v:
                linked.append({"row": i, "param": PARAMS.index(p), "gains": v["linked"],
                               "offset": number(v.get("offset", 0), f"{path}/{p}/offset"), "angle": unit_angle,
                               "path": f"{path}/{p}"})
                const[p] = 0.0
            else:
                x = number(v, f"{path}/{p}")
                const[p] = math.radians(x) if unit_angle else x
        consts.append(const)
    names = [j["name"] for j in joints]
    index = {n: k for k, n in enumerate(names)}

    motors = robot.get("motors")
    if not isinstance(motors, list) or not motors:
        fail("/motors", "the firmware needs motors")
    if len(motors) > MAX_MOTORS:
        fail("/motors", f"{len(motors)} motors, but the Nano's pin map wires {MAX_MOTORS}")
    if len(motors) != len(joints):
        fail("/motors", f"{len(motors)} motors for {len(joints)} joint variables")

    coupling = robot.get("coupling") or [[1.0 if r == c else 0.0 for c in range(len(motors))] for r in
                                         range(len(motors))]
    identity = all(coupling[r][c] == (1 if r == c else 0) for r in range(len(motors)) for c in range(len(motors)))

    motor_specs = []
    for k, m in enumerate(motors):
        path = f"/motors/{k}"
        micro = int(m.get("microsteps", 1))
        if micro not in (1, 2):
            fail(path + "/microsteps", f"{micro}: an L298N drives full steps (1) or half steps (2) only")
        gear = m.get("gear", [1, 1])
        lo_deg = m.get("min")
        hi_deg = m.get("max")
        if lo_deg is None or hi_deg is None:
            if not identity:
                fail(path, "min and max are required when the coupling is not the identity")
            j = joints[k]
            to_deg = math.degrees if j["param"] != 1 else (lambda x: x)
            lo_deg, hi_deg = to_deg(j["lo"]), to_deg(j["hi"])
        motor_specs.append({
            "name": m.get("name", f"motor{k}"),
            "steps": int(m.get("steps_per_rev", 200)), "micro": micro,
            "dir": int(m.get("direction", 1)), "num": int(gear[0]), "den": int(gear[1]),
            "zero": millideg(number(m.get("zero", 0), path + "/zero")),
            "min": millideg(number(lo_deg, path + "/min")), "max": millideg(number(hi_deg, path + "/max")),
        })

    home = robot.get("home", {})
    home_q = []
    for k, j in enumerate(joints):
        if j["name"] in home:
            v = number(home[j["name"]], f"/home/{j['name']}")
            home_q.append(math.radians(v) if j["param"] != 1 else v)
        else:
            home_q.append(min(max(0.0, j["lo"]), j["hi"]))

    tool = robot.get("tool", {})
    xyz = [number(v, f"/tool/xyz/{i}") for i, v in enumerate(tool.get("xyz", [0, 0, 0]))]
    rpy = [math.radians(number(v, f"/tool/rpy/{i}")) for i, v in enumerate(tool.get("rpy", [0, 0, 0]))]

    gripper = robot.get("gripper", {})
    servo_open = number(gripper.get("servo_open", 90), "/gripper/servo_open")
    servo_closed = number(gripper.get("servo_closed", 90), "/gripper/servo_closed")

    n, rows_n = len(joints), len(rows)
    lines = []
    out = lines.append
    out(f"// Generated from {source} by firmware/tools/robot_config.py. Do not edit: change the")
    out("// robot file and rebuild. Units: mm and radians (float), angles of motors in millidegrees.")
    out("#ifndef ARTICULA_ROBOT_CONFIG_H")
    out("#define ARTICULA_ROBOT_CONFIG_H")
    out("")
    out(f"#define ARTICULA_ROBOT_NAME {json.dumps(name[:24])}")
    out(f"#define ARTICULA_NUM_JOINTS {n}")
    out(f"#define ARTICULA_NUM_ROWS {rows_n}")
    out(f"#define ARTICULA_NUM_LINKED {len(linked)}")
    out("")
    out("// articula::DhRow {a, alpha, d, theta}; variable and linked entries are 0.")
    out("#define ARTICULA_DH_ROWS { \\")
    for c in consts:
        out(f"  {{{c_float(c['a'])}, {c_float(c['alpha'])}, {c_float(c['d'])}, {c_float(c['theta'])}}}, \\")
    out("}")
    out("// articula::JointSpec {row, param (0 theta, 1 d, 2 alpha), lo, hi}: " + ", ".join(names))
    out("#define ARTICULA_JOINTS { \\")
    for j in joints:
        out(f"  {{{j['row']}, {j['param']}, {c_float(j['lo'])}, {c_float(j['hi'])}}}, \\")
    out("}")
    out("// articula::LinkedParam {row, param, offset, {gain per joint}}")
    out("#define ARTICULA_LINKED { \\")
    for l in linked:
        gains = [0.0] * n
        for jn, g in l["gains"].items():
            if jn not in index:
                fail(l["path"] + "/linked/" + jn, "no joint variable of that name")
            gj = number(g, l["path"] + "/linked/" + jn)
            # Gains are in the parameter's unit per the joint's unit: convert deg to rad.
            p_angle, j_angle = l["angle"], joints[index[jn]]["param"] != 1
            if p_angle and not j_angle:
                gj = math.radians(gj)
            elif j_angle and not p_angle:
                gj = gj / math.radians(1.0)
            gains[index[jn]] = gj
        offset = math.radians(l["offset"]) if l["angle"] else l["offset"]
        out(f"  {{{l['row']}, {l['param']}, {c_float(offset)}, {{{', '.join(c_float(g) for g in gains)}}}}}, \\")
    out("}")
    out(f"#define ARTICULA_TOOL_XYZ {{{', '.join(c_float(v) for v in xyz)}}}")
    out(f"#define ARTICULA_TOOL_RPY {{{', '.join(c_float(v) for v in rpy)}}}")
    out("")
    out("// articula::MotorSpec {full_steps_per_rev, microsteps, direction, gear_num, gear_den, zero, min, max}")
    out("#define ARTICULA_MOTORS { \\")
    for m in motor_specs:
        out(f"  {{{m['steps']}, {m['micro']}, {m['dir']}, {m['num']}, {m['den']}, {m['zero']}, {m['min']}, {m['max']}}}, "
            f"/* {m['name']} */ \\")
    out("}")
    out("// q = C u: joint variables from actuator angles, row-major")
    out("#define ARTICULA_COUPLING { \\")
    for r in coupling:
        out(f"  {{{', '.join(c_float(number(v, '/coupling')) for v in r)}}}, \\")
    out("}")
    out(f"#define ARTICULA_HOME_Q {{{', '.join(c_float(v) for v in home_q)}}}")
    out("")
    out(f"#define ARTICULA_SERVO_OPEN_DEG {c_float(servo_open)}")
    out(f"#define ARTICULA_SERVO_CLOSED_DEG {c_float(servo_closed)}")
    out("")
    out("#endif  // ARTICULA_ROBOT_CONFIG_H")
    return "\n".join(lines) + "\n"


def main(argv):
    if len(argv) != 3 or argv[1] in ("-h", "--help"):
        print(__doc__.strip().splitlines()[0])
        print("usage: robot_config.py ROBOT.json OUTPUT.h")
        return 0 if len(argv) == 2 else 2
    src, dst = argv[1], argv[2]
    try:
        with open(src, encoding="utf-8") as f:
            robot = json.load(f)
        text = generate(robot, os.path.basename(src))
    except OSError as e:
        print(f"robot_config.py: {src}: {e.strerror}", file=sys.stderr)
        return 1
    except json.JSONDecodeError as e:
        print(f"robot_config.py: {src}: line {e.lineno}, column {e.colno}: {e.msg}", file=sys.stderr)
        return 1
    except ConfigError as e:
        print(f"robot_config.py: {src}: {e}", file=sys.stderr)
        return 1
    # Write only when the text changes, so builds do not redo work for nothing.
    try:
        with open(dst, encoding="utf-8") as f:
            if f.read() == text:
                return 0
    except OSError:
        pass
    os.makedirs(os.path.dirname(os.path.abspath(dst)), exist_ok=True)
    with open(dst, "w", encoding="utf-8") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
