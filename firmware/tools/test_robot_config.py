"""Tests firmware/tools/robot_config.py: the header it writes and every error it reports."""
import copy
import json
import pathlib
import subprocess
import sys

import pytest

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(HERE))
import robot_config  # noqa: E402

MK2 = json.loads((ROOT / "robots" / "mk2plus.json").read_text())


def generate(robot):
    return robot_config.generate(robot, "test.json")


def test_mk2_header_has_the_motor_table():
    text = generate(MK2)
    assert "#define ARTICULA_NUM_JOINTS 3" in text
    assert "{200, 1, 1, 108, 19, 0, -90000, 90000}, /* base */" in text
    assert "{200, 1, 1, 47, 19, 90000, 36000, 130000}, /* shoulder */" in text
    assert "{3, 0, 0.0f, {0.0f, -1.0f, -1.0f}}" in text  # the level-keeping link


def test_millidegrees_round_half_away_from_zero():
    assert robot_config.millideg(0.0005) == 1
    assert robot_config.millideg(-0.0005) == -1
    assert robot_config.millideg(12.3454) == 12345
    assert robot_config.millideg(-90) == -90000


def error_of(robot):
    with pytest.raises(robot_config.ConfigError) as e:
        generate(robot)
    return str(e.value)


def test_no_motors():
    r = copy.deepcopy(MK2)
    del r["motors"]
    assert error_of(r) == "/motors: the firmware needs motors"


def test_half_step_only():
    r = copy.deepcopy(MK2)
    r["motors"][1]["microsteps"] = 16
    assert "/motors/1/microsteps" in error_of(r) and "full steps (1) or half steps (2)" in error_of(r)


def test_more_motors_than_pins():
    r = copy.deepcopy(MK2)
    r["dh"].insert(0, {"a": 0, "alpha": 0, "d": 0, "theta": {"joint": "extra", "min": -10, "max": 10}})
    r["motors"].append(dict(r["motors"][0], name="extra"))
    assert "4 motors, but the Nano's pin map wires 3" in error_of(r)


def test_motor_count_must_match_joints():
    r = copy.deepcopy(MK2)
    r["motors"].pop()
    assert error_of(r) == "/motors: 2 motors for 3 joint variables"


def test_linked_names_an_unknown_joint():
    r = copy.deepcopy(MK2)
    r["dh"][3]["theta"]["linked"] = {"wrist": -1}
    assert error_of(r).startswith("/dh/3/theta/linked/wrist: no joint variable")


def test_non_finite_number():
    r = copy.deepcopy(MK2)
    r["dh"][0]["d"] = float("nan")
    assert error_of(r).startswith("/dh/0/d: expected a finite number")


def test_limits_required_with_coupling():
    r = copy.deepcopy(MK2)
    del r["motors"][2]["min"]
    assert "min and max are required" in error_of(r)


def run_cli(*args):
    return subprocess.run([sys.executable, str(HERE / "robot_config.py"), *args], capture_output=True, text=True)


def test_cli_writes_the_file_and_reports_errors(tmp_path):
    out = tmp_path / "robot_config.h"
    ok = run_cli(str(ROOT / "robots" / "mk2plus.json"), str(out))
    assert ok.returncode == 0 and out.read_text().startswith("// Generated from mk2plus.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"name": "x",\n "dh": [}')
    r = run_cli(str(bad), str(out))
    assert r.returncode == 1 and "bad.json: line 2, column" in r.stderr
    missing = run_cli(str(tmp_path / "nope.json"), str(out))
    assert missing.returncode == 1 and "nope.json" in missing.stderr
    kinematic = run_cli(str(ROOT / "robots" / "thesis-example.json"), str(out))
    assert kinematic.returncode == 1 and "/motors: the firmware needs motors" in kinematic.stderr
