"""articula.Robot: loading, the robot file's facts, and the kinematics against the CLI and
against each other (batch against one pose, Jacobian against finite differences)."""

import json
import math

import numpy as np
import pytest

import articula
from conftest import REPO, ROBOTS, cli_json


@pytest.mark.parametrize("name", ROBOTS)
def test_every_shipped_robot_loads_by_name_and_by_path(name):
    a = articula.Robot.load(name)
    b = articula.Robot.load(str(REPO / "robots" / f"{name}.json"))
    assert a.name == b.name and a.num_joints == b.num_joints > 0
    assert len(a.joint_names) == a.num_joints == len(a.joints) == a.limits.shape[0]
    assert a.home.shape == (a.num_joints,)
    assert a.within_limits(a.home)
    assert len(a.dh) == a.num_rows


@pytest.mark.parametrize("name", ROBOTS)
def test_fk_and_frames_agree_with_the_cli(name):
    robot = articula.Robot.load(name)
    rng = np.random.default_rng(7)
    lo, hi = robot.limits[:, 0], robot.limits[:, 1]
    for _ in range(3):
        q = lo + (hi - lo) * rng.random(robot.num_joints)
        doc = cli_json("fk", name, "--q", ",".join(repr(float(v)) for v in q))
        T = robot.fk(q)
        assert T.shape == (4, 4)
        np.testing.assert_allclose(T[:3, 3], doc["tool"]["position"], atol=1e-9)
        np.testing.assert_allclose(T[:3, :3], doc["tool"]["rotation"], atol=1e-12)
        np.testing.assert_allclose(articula.rpy_deg(T), doc["tool"]["rpy"], atol=1e-9)
        F = robot.frames(q)
        assert F.shape == (robot.num_rows + 2, 4, 4)
        for i, f in enumerate(doc["frames"]):
            np.testing.assert_allclose(F[i, :3, 3], f["position"], atol=1e-9)
        np.testing.assert_array_equal(F[-1], T)


def test_mk2_home_and_a_documented_pose():
    mk2 = articula.Robot.load("mk2plus")
    np.testing.assert_allclose(mk2.fk([0, 90, -90])[:3, 3], [235, 0, 213], atol=1e-9)
    # README: articula fk mk2plus --q 30,60,-80 -> tool (254.295, 146.817, 144.636)
    np.testing.assert_allclose(mk2.fk([30, 60, -80])[:3, 3], [254.295, 146.817, 144.636], atol=5e-4)
    # a list, a tuple and arrays of other dtypes give the same
    for q in ([30, 60, -80], (30.0, 60.0, -80.0), np.array([30, 60, -80]), np.array([30, 60, -80], np.float32)):
        np.testing.assert_allclose(mk2.fk(q), mk2.fk(np.array([30.0, 60.0, -80.0])), atol=1e-12)


def _micro_arm_published_ik(x, y, ohm, elbow_up=True):
    """The inverse kinematics T-Kuhn's ESP32 Micro Robot Arm publishes (MicroRobotArm/RobotArmIK.cpp, public
    domain), written out here as the reference for robots/micro-arm-28byj48.json: a point (x, y) in the arm's plane,
    mm, the tool's direction ohm (rad, 0 = pointing down, pi/2 = forward), to its three joint tilts (rad, from
    straight up, clockwise seen from the front), with its links 43, 60, 70 and 54 mm."""
    l1, l2, l3, l4 = 43.0, 60.0, 70.0, 54.0
    ex = x if elbow_up else -x
    bx, by = ex - math.sin(ohm) * l4, y + math.cos(ohm) * l4
    d, e = bx, by - l1
    phi, c = math.atan2(e, d), math.hypot(d, e)
    gamma = math.acos((l2 * l2 + l3 * l3 - c * c) / (2 * l2 * l3))
    alpha = math.acos((l2 * l2 + c * c - l3 * l3) / (2 * l2 * c))
    beta = math.pi - gamma - alpha
    lam = [math.pi / 2 - (phi + alpha), math.pi - gamma, math.pi - ((math.pi / 2 - phi) + beta) - ohm]
    return lam if elbow_up else [-v for v in lam]


# Every pose of the original's demo programs (MicroRobotArm.ino: repeatabilityTest, drillingUpElbowUpAndDown,
# lookingUpAndDown, drillingLeft, slidingAlongFloor): x, y (mm), ohm (rad), elbow up.
MICRO_ARM_DEMO_POSES = [
    (120, 90, math.pi / 2, True), (140, 60, math.pi / 2, True), (140, 90, math.pi / 2, True),
    (140, 120, math.pi / 2, True), (85, 40, 0, True), (75, 20, 0, True), (95, 20, 0, True), (115, 20, 0, True),
    (50, 190, math.pi, True), (50, 170, math.pi, True), (50, 190, math.pi, False), (50, 170, math.pi, False),
    (134, 60, math.pi / 2 + 0.4, True), (144, 94, math.pi / 2, True), (144, 94, math.pi / 2 - 0.4, True),
    (124, 74, math.pi / 2, True), (144, 74, math.pi / 2, True), (94, 10, 0, True), (74, 10, 0, True)]


def test_the_micro_arm_is_the_published_arm_at_every_pose_of_its_demo_programs():
    robot = articula.Robot.load("micro-arm-28byj48")
    spec = json.loads((REPO / "robots" / "micro-arm-28byj48.json").read_text())
    np.testing.assert_allclose(robot.fk(robot.home)[:3, 3], [0, 0, 43 + 60 + 70 + 54], atol=1e-9)
    for x, y, ohm, up in MICRO_ARM_DEMO_POSES:
        tilts = np.degrees(_micro_arm_published_ik(x, y, ohm, up))
        q = np.array([90 - tilts[0], -tilts[1], -tilts[2]])
        assert robot.within_limits(q), (x, y, q)
        T = robot.fk(q)
        # the tool's point where the original puts it, in the x-z plane, and its approach direction ohm
        np.testing.assert_allclose(T[:3, 3], [x, 0, y], atol=1e-9)
        np.testing.assert_allclose(T[:3, 2], [math.sin(ohm), 0, -math.cos(ohm)], atol=1e-12)
        # a motor's step count has the original's sign: a positive step tilts its link clockwise
        u = robot.motors_from_joints(q)
        for m, motor in enumerate(spec["motors"]):
            per_deg = motor["steps_per_rev"] * motor["microsteps"] * motor["gear"][0] / motor["gear"][1] / 360
            steps = motor["direction"] * (u[m] - motor["zero"]) * per_deg
            assert steps == pytest.approx(tilts[m] * per_deg, abs=1e-6)


def test_the_micro_arms_repeatability_program_is_the_originals_repeatability_test():
    """programs/micro-arm-repeatability.arm: the original's repeatabilityTest as joint angles. Each M line's ideal
    tool point is the published point (its angles are rounded to 0.01 deg), and the whole steps stay within
    0.2 mm of it."""
    ready, second = (120, 90, math.pi / 2), (85, 40, 0)
    points = [ready, (140, 60, math.pi / 2), (140, 90, math.pi / 2), (140, 120, math.pi / 2), None,
              (140, 90, math.pi / 2), (140, 60, math.pi / 2), second, (75, 20, 0), (95, 20, 0), (115, 20, 0),
              (95, 20, 0), (75, 20, 0), None, second]
    robot = articula.Robot.load("micro-arm-28byj48")
    records = robot.predict("programs/micro-arm-repeatability.arm").to_dict()["records"]
    assert [r["reply"] for r in records] == ["ok"] * len(points) + ["ok"]
    for point, rec in zip(points, records):
        if point is None:
            assert rec["command"].startswith("D ")
            continue
        x, z, ohm = point
        tilts = np.degrees(_micro_arm_published_ik(x, z, ohm))
        np.testing.assert_allclose(rec["commanded_deg"], [90 - tilts[0], -tilts[1], -tilts[2]], atol=0.005)
        np.testing.assert_allclose(rec["tool_ideal_mm"], [x, 0, z], atol=0.01)
        assert np.linalg.norm(np.subtract(rec["tool_quantized_mm"], [x, 0, z])) < 0.2
    np.testing.assert_allclose(records[-1]["tool_quantized_mm"], [0, 0, 227], atol=1e-9)  # home


@pytest.mark.parametrize("name", ROBOTS)
def test_batch_forms_equal_the_one_pose_forms(name):
    robot = articula.Robot.load(name)
    rng = np.random.default_rng(3)
    lo, hi = robot.limits[:, 0], robot.limits[:, 1]
    Q = lo + (hi - lo) * rng.random((50, robot.num_joints))
    T = robot.fk_batch(Q)
    J = robot.jacobian_batch(Q)
    assert T.shape == (50, 4, 4) and J.shape == (50, 6, robot.num_joints)
    for i in range(50):
        np.testing.assert_array_equal(T[i], robot.fk(Q[i]))
        np.testing.assert_array_equal(J[i], robot.jacobian(Q[i]))
    assert robot.fk_batch(np.zeros((0, robot.num_joints))).shape == (0, 4, 4)


@pytest.mark.parametrize("name", ROBOTS)
def test_jacobian_is_the_derivative_of_fk_per_degree_or_mm(name):
    robot = articula.Robot.load(name)
    q = robot.home + 0.3
    J = robot.jacobian(q)
    h = 1e-6
    for j in range(robot.num_joints):
        dq = np.zeros(robot.num_joints)
        dq[j] = h
        Tp, Tm = robot.fk(q + dq), robot.fk(q - dq)
        np.testing.assert_allclose(J[:3, j], (Tp[:3, 3] - Tm[:3, 3]) / (2 * h), rtol=1e-5, atol=1e-6)
        # rotation: dR R^T is the skew matrix of the rotation vector, per unit of q (deg/deg for angles)
        W = (Tp[:3, :3] - Tm[:3, :3]) / (2 * h) @ robot.fk(q)[:3, :3].T
        w = np.array([W[2, 1], W[0, 2], W[1, 0]])
        # a revolute joint: rad per rad, and J's angles per degree; a prismatic one turns nothing
        if robot.joints[j]["unit"] == "deg":
            np.testing.assert_allclose(J[3:, j], w * 180 / np.pi, rtol=1e-5, atol=1e-7)
        else:
            np.testing.assert_allclose(J[3:, j], [0, 0, 0], atol=1e-9)
            np.testing.assert_allclose(w, [0, 0, 0], atol=1e-9)


def test_dh_table_fills_in_variables_and_links():
    mk2 = articula.Robot.load("mk2plus")
    t = mk2.dh_table([10, 60, -80])
    assert t.shape == (4, 4)
    np.testing.assert_allclose(t[:, 3], [10, 60, -80, 20])  # theta4 = -(theta2 + theta3)
    np.testing.assert_allclose(t[:, 0], [0, 0, 135, 147])
    assert mk2.dh[3]["theta"] == {"linked": {"shoulder": -1.0, "elbow": -1.0}, "offset": 0.0}
    assert mk2.dh[0]["theta"]["joint"] == "base"


def test_robot_facts_match_the_file():
    mk2 = articula.Robot.load("mk2plus")
    doc = json.loads((REPO / "robots" / "mk2plus.json").read_text())
    assert mk2.name == doc["name"]
    assert [m["name"] for m in mk2.motors] == [m["name"] for m in doc["motors"]]
    assert mk2.motors[0]["gear"] == tuple(doc["motors"][0]["gear"])
    assert mk2.motors[0]["deg_per_step"] == pytest.approx(0.316667, abs=1e-6)
    assert mk2.coupling.shape == (3, 3)
    assert mk2.gripper["max_opening_mm"] > 0
    assert any(link["shapes"] for link in mk2.links)
    panda = articula.Robot.load("panda")
    # a robot file with no motors and no gripper (robots/panda.json has neither)
    assert panda.num_motors == 0 and panda.motors == [] and panda.gripper is None


# ---- errors: a clear Python exception, never a crash or a silent wrong answer ----

def test_a_missing_file_names_it():
    with pytest.raises(articula.RobotFileError) as e:
        articula.Robot.load("robots/no-such-arm.json")
    assert "robots/no-such-arm.json" in str(e.value) and "not found" in str(e.value)
    assert e.value.file == "robots/no-such-arm.json"
    assert isinstance(e.value, ValueError)


def test_a_malformed_robot_names_file_json_path_and_problem(tmp_path):
    doc = json.loads((REPO / "robots" / "mk2plus.json").read_text())
    doc["dh"][1]["theta"]["min"] = 200  # above max
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    with pytest.raises(articula.RobotFileError) as e:
        articula.Robot.load(str(bad))
    assert e.value.file == str(bad)
    assert e.value.json_path == "/dh/1/theta/min"
    assert "limits inverted" in e.value.problem
    assert str(e.value).startswith(f"{bad}: /dh/1/theta/min: ")
    not_json = tmp_path / "broken.json"
    not_json.write_text('{"name": "x", ')
    with pytest.raises(articula.RobotFileError, match="broken.json"):
        articula.Robot.load(str(not_json))
    with pytest.raises(articula.RobotFileError, match="<text>"):
        articula.Robot.parse('{"name": "x"}')


@pytest.mark.parametrize("bad, exc, words", [
    ([0, 90], ValueError, "q has 2 values; MK2 Plus has 3 joint variables (base, shoulder, elbow)"),
    ([0, 90, -90, 0], ValueError, "q has 4 values"),
    ([0, float("nan"), -90], ValueError, "q[1] (shoulder) is NaN"),
    ([0, 90, float("inf")], ValueError, "q[2] (elbow) is infinite"),
    ([0, "ninety", -90], TypeError, "q[1] (shoulder) is not a number"),
    (np.zeros((3, 1)), ValueError, "1-D"),
])
def test_bad_joint_values_raise_and_name_the_joint(bad, exc, words):
    mk2 = articula.Robot.load("mk2plus")
    for f in (mk2.fk, mk2.frames, mk2.jacobian, mk2.dh_table):
        with pytest.raises(exc) as e:
            f(bad)
        assert words in str(e.value)


def test_bad_batches_raise():
    mk2 = articula.Robot.load("mk2plus")
    with pytest.raises(ValueError, match=r"Q must have shape \(N, 3\).*got \(4, 2\)"):
        mk2.fk_batch(np.zeros((4, 2)))
    with pytest.raises(ValueError, match=r"got \(3,\)"):
        mk2.fk_batch(np.zeros(3))
    Q = np.zeros((5, 3))
    Q[3, 2] = np.nan
    with pytest.raises(ValueError, match=r"Q\[3, 2\] \(elbow\) is NaN"):
        mk2.jacobian_batch(Q)


def test_urdf_is_the_clis(tmp_path):
    out = tmp_path / "mk2.urdf"
    from conftest import cli
    cli("export-urdf", "mk2plus", "-o", str(out), ok=(0,))
    assert articula.Robot.load("mk2plus").to_urdf() == out.read_text()


def test_legacy_import_is_the_clis(tmp_path):
    from conftest import cli
    src = REPO / "docs" / "examples" / "thesis-example.legacy.txt"
    out = tmp_path / "thesis.json"
    cli("import-legacy", str(src), "--scale", "10", "-o", str(out), ok=(0,))
    via_cli = articula.Robot.load(str(out))
    direct = articula.Robot.from_legacy(str(src), 10)
    assert direct.dh == via_cli.dh and direct.joint_names == via_cli.joint_names
    assert len(direct.import_notes) == 28
    q = direct.home + 5
    np.testing.assert_allclose(direct.fk(q), via_cli.fk(q), atol=1e-12)
    with pytest.raises(ValueError, match="scale"):
        articula.Robot.from_legacy(str(src), 0)
    with pytest.raises(ValueError, match="cannot read"):
        articula.Robot.from_legacy(str(tmp_path / "none.txt"), 10)


def test_adjustable_link_lengths(tmp_path):
    doc = json.loads((REPO / "docs" / "examples" / "first-arm" / "step2-elbow.json").read_text())
    doc["dh"][2]["a"] = {"value": 135, "min": 100, "max": 200}
    robot = articula.Robot.parse(json.dumps(doc), "adjustable.json")
    longer = robot.with_link_lengths([180])
    assert longer.dh[2]["a"] == {"value": 180.0, "min": 100.0, "max": 200.0}
    assert robot.dh[2]["a"]["value"] == 135.0  # a copy: the robot itself is unchanged
    # at shoulder 90 the upper arm points straight up: 45 mm longer, the tool 45 mm higher
    q = [0, 90, 0]
    np.testing.assert_allclose(longer.fk(q)[:3, 3] - robot.fk(q)[:3, 3], [0, 0, 45], atol=1e-9)
    # the same as RoboSim's l in a program
    run = robot.run(articula.Program.parse("l\n180\nm\n0\n90\n0\n", "l.robosim"))
    np.testing.assert_allclose(run.records[-1].tool.position, longer.fk(q)[:3, 3], atol=1e-9)
    with pytest.raises(ValueError, match=r"a of row 3: 300 mm is outside its range 100 .. 200 mm"):
        robot.with_link_lengths([300])
    with pytest.raises(ValueError, match="1 adjustable link length"):
        robot.with_link_lengths([150, 150])


def test_finger_poses_sit_at_the_tool():
    mk2 = articula.Robot.load("mk2plus")
    F = mk2.finger_poses([0, 90, -90], 30)
    T = mk2.fk([0, 90, -90])
    g = mk2.gripper
    assert F.shape == (2, 4, 4)
    for side, f in zip((+1, -1), F):
        local = np.linalg.inv(T) @ f
        np.testing.assert_allclose(local[:3, 3], [g["finger_length_mm"] / 2, side * (30 + g["finger_thickness_mm"]) / 2, 0],
                                   atol=1e-9)
    with pytest.raises(ValueError, match="has no gripper"):
        articula.Robot.load("panda").finger_poses(np.zeros(7), 10)


def test_an_svg_draws_what_it_shows_and_nothing_visible_is_refused():
    """Issue 41: an icon set's invisible 24 x 24 frame is not drawn (the plus alone fills the
    width); a file where nothing shows is refused by name."""
    mk2 = articula.Robot.load("mk2plus")
    icon = ('<svg xmlns="http://www.w3.org/2000/svg" width="24" height="24" viewBox="0 0 24 24" fill="none" '
            'stroke="currentColor"><path stroke="none" d="M0 0h24v24H0z" fill="none"/><path d="M4 12h16M12 4v16"/></svg>')
    d = mk2.draw(svg=icon, svg_name="plus.svg", width=60, at=(260, 0), z=0, pen=120)
    assert len(d["strokes"]) == 2
    xs = [p[0] for s in d["strokes"] for p in s]
    assert abs(min(xs) - 230) < 1e-6 and abs(max(xs) - 290) < 1e-6  # the plus spans the 60 mm, not 40 of them
    hidden = ('<svg xmlns="http://www.w3.org/2000/svg"><g opacity="0"><path d="M0 0h9" stroke="red"/></g>'
              '<rect width="9" height="9" visibility="hidden"/></svg>')
    with pytest.raises(ValueError, match="hidden.svg: nothing in it shows: its 2 shapes are invisible"):
        mk2.draw(svg=hidden, svg_name="hidden.svg", width=60, at=(260, 0), z=0, pen=120)


def test_an_svg_draws_what_defs_keep_only_where_a_use_shows_it():
    """Issue 41: <defs> (and <symbol>, <clipPath>, <mask>, <marker>) draw nothing of their own;
    a <use> draws what it names in its place; a file of nothing but kept shapes is refused."""
    mk2 = articula.Robot.load("mk2plus")
    ns = 'xmlns="http://www.w3.org/2000/svg" viewBox="0 0 24 24"'
    kept = '<defs><path id="bar" stroke="black" d="M2 12 h20"/></defs><symbol id="s"><path stroke="black" d="M12 2 v20"/></symbol>'
    d = mk2.draw(svg=f'<svg {ns}>{kept}<use href="#bar"/><use href="#s"/></svg>', svg_name="used.svg", width=60, at=(260, 0),
                 z=0, pen=120)
    assert len(d["strokes"]) == 2
    one = mk2.draw(svg=f'<svg {ns}>{kept}<use href="#bar"/></svg>', svg_name="one.svg", width=60, at=(260, 0), z=0, pen=120)
    assert len(one["strokes"]) == 1  # the symbol's line is not drawn without its use
    with pytest.raises(ValueError, match="kept.svg: nothing in it shows: its 2 shapes are invisible"):
        mk2.draw(svg=f"<svg {ns}>{kept}</svg>", svg_name="kept.svg", width=60, at=(260, 0), z=0, pen=120)


def test_wiring_follows_the_robot_files_board_and_drivers():
    """Robot.wiring(): the pins of the board the file names (robots/README.md, 'Drive')."""
    cnc = articula.Robot.load("mk2plus-cnc").wiring()
    assert cnc["board"] == "uno-cnc-v3" and cnc["given"]
    step = {w["motor"]: w["pin"] for w in cnc["wires"] if w["signal"] == "STEP"}
    assert step == {"base": "D2", "shoulder": "D3", "elbow": "D4"}
    assert [w["pin"] for w in cnc["wires"] if w["signal"] == "EN"] == ["D8"]
    nano = articula.Robot.load("mk2plus").wiring()
    assert [w["pin"] for w in nano["wires"] if w["motor"] == "base"] == ["D4", "D5", "D6", "D7", "D2"]
    assert articula.Robot.load("mk2plus").motors[0]["driver"] == {"kind": "l298n"}
    assert "no motors" in articula.Robot.load("panda").wiring()["error"]
    # the pins each drive leaves for signals (O and W), which the page's signal blocks offer
    assert nano["io_pins"] == [{"pin": 19, "name": "A5"}]
    assert [p["name"] for p in cnc["io_pins"]] == ["D12", "A0", "A1", "A2", "A4", "A5"]
    assert nano["header_pins"][0] == "D0" and nano["header_pins"][19] == "A5" and len(nano["header_pins"]) == 20
