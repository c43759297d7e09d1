"""Robot.ik and ik_batch: the solvers of host/lib/ik.h through Python, against the CLI's
`articula ik --json` and against forward kinematics."""

import numpy as np
import pytest

import articula
from conftest import ROBOTS, cli_json


@pytest.mark.parametrize("name", ROBOTS)
def test_round_trips_on_every_robot(name):
    robot = articula.Robot.load(name)
    rng = np.random.default_rng(11)
    lo, hi = robot.limits[:, 0], robot.limits[:, 1]
    for _ in range(10):
        q = lo + (hi - lo) * (0.1 + 0.8 * rng.random(robot.num_joints))
        if not robot.within_limits(q):
            continue
        target = robot.fk(q)[:3, 3]
        res = robot.ik(target)
        assert res.status == "reached", res
        assert robot.within_limits(res.q)
        np.testing.assert_allclose(robot.fk(res.q)[:3, 3], target, atol=0.011)
        np.testing.assert_allclose(res.tool, robot.fk(res.q), atol=1e-9)


@pytest.mark.parametrize("name, target, solver", [
    ("mk2plus", "200,-150,150", "auto"),
    ("mk2plus", "600,0,100", "auto"),
    ("mk2plus", "200,50,150", "jt"),
    ("panda", "400,100,500,180,0,0", "auto"),
    ("three-link-8dof", "60,60,40", "lm"),
])
def test_results_equal_the_clis(name, target, solver):
    robot = articula.Robot.load(name)
    doc = cli_json("ik", name, "--target", target, "--solver", solver)
    res = robot.ik([float(v) for v in target.split(",")], solver=solver)
    assert res.to_dict() == doc
    assert res.status == doc["status"] and res.solver == doc["solver"]
    np.testing.assert_array_equal(res.q, doc["q"])
    assert res.position_error_mm == doc["position_error_mm"]
    assert res.iterations == doc["iterations"]


def test_unreachable_and_limited_say_how_far_and_which():
    mk2 = articula.Robot.load("mk2plus")
    far = mk2.ik([600, 0, 100])
    assert far.status == "unreachable" and not far.reached and far.position_error_mm > 250
    low = mk2.ik([150, 0, -150])
    assert low.status in ("limited", "unreachable")
    if low.status == "limited":
        assert low.limited_by or low.limited_by_motors
    # and in words, as the studio and the blocks say it
    assert far.why == f"it is farther than the arm is long; the nearest the tool comes is {far.position_error_mm:.1f} mm away"
    assert far.to_dict()["why"] == far.why
    assert mk2.ik([235, 0, 213]).why == ""


def test_targets_as_pose_and_as_matrix_agree():
    panda = articula.Robot.load("panda")
    T = panda.fk(panda.home + 10)
    a = panda.ik(T)
    assert a.reached
    np.testing.assert_allclose(panda.fk(a.q)[:3, 3], T[:3, 3], atol=0.011)
    np.testing.assert_allclose(panda.fk(a.q)[:3, :3], T[:3, :3], atol=2e-4)
    # the same target as x, y, z, roll, pitch, yaw (fixed X-Y-Z): the same answer
    R = T[:3, :3]
    pitch = np.degrees(np.arcsin(-R[2, 0]))
    roll = np.degrees(np.arctan2(R[2, 1], R[2, 2]))
    yaw = np.degrees(np.arctan2(R[1, 0], R[0, 0]))
    b = panda.ik([*T[:3, 3], roll, pitch, yaw])
    assert b.reached
    np.testing.assert_allclose(b.q, a.q, atol=1e-6)


def test_weights_freeze_a_joint():
    thesis = articula.Robot.load("thesis-example")
    n = thesis.num_joints
    w = np.ones(n)
    w[0] = 0
    start = thesis.home
    res = thesis.ik(thesis.fk(start + 3)[:3, 3], solver="lm", weights=w, start=start)
    assert res.q[0] == pytest.approx(start[0])


def test_batch_equals_one_at_a_time():
    panda = articula.Robot.load("panda")
    rng = np.random.default_rng(5)
    lo, hi = panda.limits[:, 0], panda.limits[:, 1]
    Q = lo + (hi - lo) * (0.2 + 0.6 * rng.random((20, 7)))
    T = panda.fk_batch(Q)
    b = panda.ik_batch(T)
    assert b["q"].shape == (20, 7) and b["status"].shape == (20,)
    for i in range(20):
        one = panda.ik(T[i])
        np.testing.assert_array_equal(b["q"][i], one.q)
        assert articula.IK_STATUS[b["status"][i]] == one.status
        assert b["iterations"][i] == one.iterations
    pos = panda.ik_batch(T[:, :3, 3])
    assert (pos["status"] == 0).all()


@pytest.mark.parametrize("kwargs, exc, words", [
    ({"target": [1, 2]}, ValueError, "target must be a position"),
    ({"target": [1, float("nan"), 3]}, ValueError, "NaN"),
    ({"target": [200, 0, 150], "solver": "newton"}, ValueError, "unknown solver 'newton'"),
    ({"target": [200, 0, 150], "weights": [1, -1, 1]}, ValueError, "weight"),
    ({"target": [200, 0, 150], "weights": [1, 1]}, ValueError, "weight"),
    ({"target": [200, 0, 150], "start": [0, 90]}, ValueError, "start has 2 values"),
    ({"target": [200, 0, 150], "tolerance_mm": 0}, ValueError, "tolerance_mm"),
])
def test_bad_ik_arguments_raise(kwargs, exc, words):
    mk2 = articula.Robot.load("mk2plus")
    with pytest.raises(exc, match=words):
        mk2.ik(**kwargs)


def test_closed_form_refused_where_it_does_not_apply():
    with pytest.raises(ValueError):
        articula.Robot.load("panda").ik([400, 0, 400], solver="closed")


def test_a_result_on_a_limit_is_within_the_limits():
    # IK answers on a limit come back in degrees a rounding off it: still within the limits.
    panda = articula.Robot.load("panda")
    q = panda.home.copy()
    q[3] = panda.limits[3, 1]  # q4 at its upper limit
    T = panda.fk(q)
    res = panda.ik(T)
    assert res.reached and panda.within_limits(res.q)
    q[3] = panda.limits[3, 1] + 1e-6
    assert not panda.within_limits(q)
