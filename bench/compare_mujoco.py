#!/usr/bin/env python3
"""Side-by-side figures: Articula's physics benchmark (ODE) and MuJoCo (PyPI mujoco) on the same
scene, in one session.

    .venv/bin/python bench/compare_mujoco.py [--build build] [--bench-binary PATH] [--runs 10] [--json]

The scene is issue 5's benchmark: the MK2 arm of robots/mk2plus.json (DH table, link shapes, home
pose, motor limits and coupling, read from the file here) plus a 3 cm cube resting on the ground,
1 ms steps, 10 s simulated (10,000 steps), one thread. Two MuJoCo models of it:

  (a) position-driven, like ours: each link with shapes is a mocap body whose pose is set, every
      step, to its DH frame at the step-quantized motor positions; the cube is the only dynamic body.
  (b) servo-driven: the arm is a chain of hinge joints (the DH frames: one hinge about z(i) per row,
      row 4, the parallelogram's theta4 = -(shoulder + elbow), a 4th joint) driven by stiff position
      actuators (kp 1000 N m/rad, critically damped) towards the same step-quantized targets; what the
      issue's reference figure (MuJoCo about 267,000 steps/s) was measured on.
Each also with MuJoCo's sleeping on (mjENBL_SLEEP, off by default): the counterpart of ODE's
auto-disable, which ours uses, so that a cube at rest is no longer integrated.

The moves (both variants, and "idle" runs that hold the home pose): from home, coordinated
trapezoidal moves in motor space (every motor starts and stops together; 90 deg/s and 360 deg/s^2
on the motor that moves most) through the motors' ranges, (0, 90, 0) -> (75, 120, 10) ->
(-75, 45, -40) -> (30, 60, -25) -> (-30, 110, 12) -> (0, 90, 0) deg (base, shoulder, elbow motor),
0.25 s pause after each, repeated until 10 s; positions rounded to whole motor steps (the robot
file's steps per degree). The arm never touches the cube (its lowest point stays above 60 mm).

Checked first: the MuJoCo body frames of model (b) at 24 poses equal the DH frames computed here in
numpy (and those of `articula fk --json` when build/host/cli/articula exists) to 1e-6 m, and the
link geoms of (a) and (b) coincide. Timed: only the stepping, best of --runs runs of 10,000 steps,
the variants interleaved: MuJoCo's rollout (mj_step in its C++ loop, the per-step controls or mocap
poses precomputed) and, for reference, a Python loop of mj_step calls. Then runs build/bench/bench_physics
(--benchmark_filter=BM_SimMk2Cube) and prints a table with the ratios and the issue's target.

A benchmark helper, not a test: nothing in ctest needs MuJoCo.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGET_STEPS_PER_S = 300_000
# Issue 5's reference figures (servo-driven arm of the same size, this machine kind).
REFERENCE = {"ODE dWorldStep": 213_000, "MuJoCo": 267_000}

DT = 0.001
SIM_SECONDS = 10.0
CUBE_MM = 30.0
CUBE_XYZ_MM = (200.0, 0.0, CUBE_MM / 2)
PLA_DENSITY = 1240.0  # kg/m^3, robots/README.md's default
SERVO_KP = 1000.0  # N m/rad: as stiff as 1 ms steps allow (3000 diverges)
MOVE_VMAX = 90.0  # deg/s, motor angles
MOVE_AMAX = 360.0  # deg/s^2
MOVE_PAUSE = 0.25  # s
WAYPOINTS = [(0, 90, 0), (75, 120, 10), (-75, 45, -40), (30, 60, -25), (-30, 110, 12)]
FRAME_TOLERANCE_M = 1e-6


class RobotFileError(Exception):
    pass


# ---------------------------------------------------------------------------------------------
# The robot file and its DH kinematics (modified DH, Craig; robots/README.md)

def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def rot_rpy(rpy_deg):
    """R = Rz(yaw) Ry(pitch) Rx(roll), fixed X-Y-Z angles in degrees (robots/README.md)."""
    r, p, y = (math.radians(v) for v in rpy_deg)
    cp, sp = math.cos(p), math.sin(p)
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    return rot_z(y) @ ry @ rot_x(r)


def transform(R, p):
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


class Mk2Model:
    """What this comparison needs from a robot file: revolute rows (theta a joint, linked or
    constant), constant a, alpha, d; motors with coupling; link shapes (box, cylinder, sphere)."""

    def __init__(self, path):
        self.path = path
        with open(path) as f:
            try:
                doc = json.load(f)
            except json.JSONDecodeError as e:
                raise RobotFileError(f"{path}: line {e.lineno}: not JSON: {e.msg}")
        self.name = doc.get("name", os.path.basename(path))
        # (a m, alpha rad, d m, theta): theta ("joint", k), ("linked", {k: gain}, offset rad) or ("const", rad)
        self.rows = []
        self.joint_names = []
        self.joint_limits = []  # deg
        for i, row in enumerate(doc.get("dh", [])):
            ptr = f"/dh/{i}"
            a = row.get("a")
            if isinstance(a, dict):
                a = a.get("value")
            for key, v in (("a", a), ("alpha", row.get("alpha")), ("d", row.get("d"))):
                if not isinstance(v, (int, float)):
                    raise RobotFileError(f"{path}: {ptr}/{key}: only constants are supported here")
            th = row.get("theta")
            if isinstance(th, (int, float)):
                theta = ("const", math.radians(th))
            elif isinstance(th, dict) and "joint" in th:
                self.joint_names.append(th["joint"])
                self.joint_limits.append((th["min"], th["max"]))
                theta = ("joint", len(self.joint_names) - 1)
            elif isinstance(th, dict) and "linked" in th:
                theta = ("linked", th["linked"], math.radians(th.get("offset", 0)))
            else:
                raise RobotFileError(f"{path}: {ptr}/theta: expected a number, a joint or a linked parameter")
            self.rows.append((a / 1000.0, math.radians(row["alpha"]), row["d"] / 1000.0, theta))
        if not self.rows:
            raise RobotFileError(f"{path}: /dh: no rows")
        # Linked gains by joint index.
        for i, (a, al, d, th) in enumerate(self.rows):
            if th[0] == "linked":
                gains = {}
                for name, g in th[1].items():
                    if name not in self.joint_names:
                        raise RobotFileError(f"{path}: /dh/{i}/theta/linked/{name}: no such joint")
                    gains[self.joint_names.index(name)] = g
                self.rows[i] = (a, al, d, ("linked", gains, th[2]))
        n = len(self.joint_names)
        home = doc.get("home", {})
        self.home_deg = np.array([home.get(name, 0.0) for name in self.joint_names], dtype=float)
        motors = doc.get("motors", [])
        if len(motors) != n:
            raise RobotFileError(f"{path}: /motors: {len(motors)} motors for {n} joints")
        self.coupling = np.array(doc.get("coupling", np.eye(n).tolist()), dtype=float)
        if self.coupling.shape != (n, n):
            raise RobotFileError(f"{path}: /coupling: expected a {n}x{n} matrix")
        self.motor_limits = [(m["min"], m["max"]) for m in motors]
        self.motor_zero = np.array([m.get("zero", 0.0) for m in motors], dtype=float)
        # Output degrees per whole step: 360 / (steps * microsteps) * motor teeth / output teeth.
        self.deg_per_step = np.array([360.0 / (m["steps_per_rev"] * m.get("microsteps", 1)) *
                                      m["gear"][1] / m["gear"][0] for m in motors])
        self.links = []  # (frame, [(type, size_m, xyz_m, R, mass_or_None, density)])
        for li, link in enumerate(doc.get("links", [])):
            shapes = []
            for si, s in enumerate(link.get("shapes", [])):
                ptr = f"/links/{li}/shapes/{si}"
                if s.get("type") not in ("box", "cylinder", "sphere"):
                    raise RobotFileError(f"{path}: {ptr}/type: {s.get('type')!r} is not supported by this comparison")
                shapes.append((s["type"], np.array(s["size"], dtype=float) / 1000.0,
                               np.array(s.get("xyz", [0, 0, 0]), dtype=float) / 1000.0,
                               rot_rpy(s.get("rpy", [0, 0, 0])), s.get("mass"), s.get("density", PLA_DENSITY)))
            if not 0 <= link["frame"] <= len(self.rows):
                raise RobotFileError(f"{path}: /links/{li}/frame: no frame {link['frame']}")
            self.links.append((link["frame"], shapes))

    def thetas(self, q_deg):
        """Every row's theta (rad) for joint values q (deg)."""
        out = []
        for _, _, _, th in self.rows:
            if th[0] == "const":
                out.append(th[1])
            elif th[0] == "joint":
                out.append(math.radians(q_deg[th[1]]))
            else:
                out.append(th[2] + sum(g * math.radians(q_deg[k]) for k, g in th[1].items()))
        return out

    def frames(self, q_deg):
        """T_base_frame[i], i = 0..rows, 4x4, metres (Craig 3.6)."""
        T = [np.eye(4)]
        for (a, alpha, d, _), theta in zip(self.rows, self.thetas(q_deg)):
            T.append(T[-1] @ transform(rot_x(alpha), [a, 0, 0]) @ transform(rot_z(theta), [0, 0, d]))
        return T

    def joints_from_motors(self, m_deg):
        return self.coupling @ np.asarray(m_deg, dtype=float)

    def motors_from_joints(self, q_deg):
        return np.linalg.solve(self.coupling, np.asarray(q_deg, dtype=float))

    def quantize(self, m_deg):
        """Motor angles rounded to whole steps (step 0 is each motor's zero angle)."""
        return self.motor_zero + np.round((m_deg - self.motor_zero) / self.deg_per_step) * self.deg_per_step


# ---------------------------------------------------------------------------------------------
# MJCF

def fmt(v):
    return " ".join(f"{x:.17g}" for x in np.ravel(v))


def mat_to_quat(R):
    import mujoco
    q = np.zeros(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(R, dtype=float).ravel())
    return q


def geom_xml(shape, name):
    kind, size, xyz, R, mass, density = shape
    half = {"box": size / 2, "cylinder": np.array([size[0], size[1] / 2]), "sphere": size[:1]}[kind]
    inertia = f'mass="{mass:.17g}"' if mass is not None else f'density="{density:.17g}"'
    return (f'<geom name="{name}" type="{kind}" size="{fmt(half)}" pos="{fmt(xyz)}" '
            f'quat="{fmt(mat_to_quat(R))}" {inertia}/>')


def scene_xml(robot, variant, integrator, sleep=False):
    """variant 'mocap' (a) or 'servo' (b)."""
    frames_with_shapes = {}
    for frame, shapes in robot.links:
        frames_with_shapes.setdefault(frame, []).extend(shapes)
    base_geoms = "\n    ".join(geom_xml(s, f"f0_{k}") for k, s in enumerate(frames_with_shapes.get(0, [])))
    cube = np.array(CUBE_XYZ_MM) / 1000.0
    h = CUBE_MM / 2000.0
    body_lines = []
    excludes = []
    actuators = []
    if variant == "mocap":
        for frame in sorted(f for f in frames_with_shapes if f > 0):
            geoms = " ".join(geom_xml(s, f"f{frame}_{k}") for k, s in enumerate(frames_with_shapes[frame]))
            body_lines.append(f'<body name="frame{frame}" mocap="true">{geoms}</body>')
    else:
        depth = 0
        for i, (a, alpha, d, th) in enumerate(robot.rows, start=1):
            R = rot_x(alpha) @ (rot_z(th[1]) if th[0] == "const" else np.eye(3))
            pos = np.array([a, 0, 0]) + rot_x(alpha) @ np.array([0, 0, d])
            line = f'<body name="frame{i}" pos="{fmt(pos)}" quat="{fmt(mat_to_quat(R))}">'
            if th[0] != "const":
                jname = f"theta{i}"
                if th[0] == "joint":
                    lo, hi = robot.joint_limits[th[1]]
                    line += f'<joint name="{jname}" type="hinge" axis="0 0 1" range="{lo} {hi}"/>'
                    ctrl = f'ctrlrange="{math.radians(lo):.17g} {math.radians(hi):.17g}"'
                else:
                    line += f'<joint name="{jname}" type="hinge" axis="0 0 1"/>'
                    ctrl = ""
                actuators.append(f'<position joint="{jname}" kp="{SERVO_KP}" dampratio="1" {ctrl}/>')
            shapes = frames_with_shapes.get(i, [])
            line += " ".join(geom_xml(s, f"f{i}_{k}") for k, s in enumerate(shapes))
            if not shapes:  # a frame without a link (the MK2's turntable): a small mass so that it may move
                line += '<inertial pos="0 0 0" mass="0.001" diaginertia="1e-7 1e-7 1e-7"/>'
            body_lines.append(line)
            depth += 1
        body_lines.append("</body>" * depth)
        # Links adjacent in the chain do not collide (MuJoCo excludes parent-child pairs itself);
        # the base and the first link with shapes are adjacent through shape-less frames.
        first = min((f for f in frames_with_shapes if f > 0), default=None)
        if first is not None and 0 in frames_with_shapes:
            excludes.append(f'<exclude body1="world" body2="frame{first}"/>')
        prev = None
        for f in range(1, len(robot.rows) + 1):
            if f in frames_with_shapes:
                if prev is not None and f - prev > 1:
                    excludes.append(f'<exclude body1="frame{prev}" body2="frame{f}"/>')
                prev = f
    return f"""<mujoco model="{robot.name} + cube ({variant})">
  <compiler angle="degree"/>
  <option timestep="{DT}" integrator="{integrator}">{'<flag sleep="enable"/>' if sleep else ''}</option>
  <worldbody>
    <geom name="ground" type="plane" size="0 0 1"/>
    {base_geoms}
    {"".join(body_lines)}
    <body name="cube" pos="{fmt(cube)}">
      <freejoint/>
      <geom name="cube" type="box" size="{h} {h} {h}" density="{PLA_DENSITY}"/>
    </body>
  </worldbody>
  <contact>{"".join(excludes)}</contact>
  <actuator>{"".join(actuators)}</actuator>
</mujoco>
"""


# ---------------------------------------------------------------------------------------------
# The program of moves

def trapezoid_fraction(t, T, D):
    """Fraction of the move done at time t for a trapezoid of distance D (deg) lasting T (s)."""
    if D == 0 or t >= T:
        return 1.0
    v = MOVE_VMAX
    ta = v / MOVE_AMAX
    if D < v * ta:  # triangle
        ta = T / 2
        v = MOVE_AMAX * ta
    if t < ta:
        s = 0.5 * MOVE_AMAX * t * t
    elif t < T - ta:
        s = 0.5 * MOVE_AMAX * ta * ta + v * (t - ta)
    else:
        s = D - 0.5 * MOVE_AMAX * (T - t) ** 2
    return s / D


def motor_program(robot, n_steps, idle):
    """Motor angles (deg, step-quantized) at the end of every step, shape (n_steps, nmotors)."""
    home_m = robot.motors_from_joints(robot.home_deg)
    out = np.empty((n_steps, len(home_m)))
    if idle:
        out[:] = robot.quantize(home_m)
        return out
    for k, (lo_hi, w) in enumerate(zip(robot.motor_limits, zip(*WAYPOINTS))):
        for v in w:
            if not lo_hi[0] <= v <= lo_hi[1]:
                raise ValueError(f"waypoint motor {k} = {v} deg is outside {lo_hi}")
    path = [np.array(w, dtype=float) for w in WAYPOINTS] + [np.array(WAYPOINTS[0], dtype=float)]
    segments = []  # (start, end, duration s, largest motor distance deg)
    t_total = 0.0
    i = 0
    while t_total < n_steps * DT:
        a, b = path[i % (len(path) - 1)], path[i % (len(path) - 1) + 1]
        D = float(np.max(np.abs(b - a)))
        T = 2 * math.sqrt(D / MOVE_AMAX) if D < MOVE_VMAX ** 2 / MOVE_AMAX else D / MOVE_VMAX + MOVE_VMAX / MOVE_AMAX
        segments.append((a, b, T, D))
        t_total += T + MOVE_PAUSE
        i += 1
    seg, t0 = 0, 0.0
    for k in range(n_steps):
        t = (k + 1) * DT
        while t > t0 + segments[seg][2] + MOVE_PAUSE:
            t0 += segments[seg][2] + MOVE_PAUSE
            seg += 1
        a, b, T, D = segments[seg]
        out[k] = robot.quantize(a + (b - a) * trapezoid_fraction(t - t0, T, D))
    return out


# ---------------------------------------------------------------------------------------------

# key: (arm, integrator, sleep, label). implicitfast for the servos: their damping (kv) is then
# implicit; with Euler, kp 1000 diverges. Sleep (mjENBL_SLEEP) is MuJoCo's counterpart of ODE's
# auto-disable, which ours uses: a body at rest stops being integrated until something touches it.
VARIANTS = {
    "a": ("mocap", "Euler", False, "MuJoCo (a) mocap arm"),
    "a_sleep": ("mocap", "Euler", True, "MuJoCo (a) mocap arm, sleep on"),
    "b": ("servo", "implicitfast", False, "MuJoCo (b) servo arm"),
    "b_sleep": ("servo", "implicitfast", True, "MuJoCo (b) servo arm, sleep on"),
}


def build_models(robot):
    import mujoco
    models = {}
    for key, (arm, integrator, sleep, _) in VARIANTS.items():
        xml = scene_xml(robot, arm, integrator, sleep)
        try:
            models[key] = mujoco.MjModel.from_xml_string(xml)
        except ValueError as e:
            sys.exit(f"compare_mujoco: MuJoCo rejected model {key}: {e}")
    return models


def mocap_controls(robot, m, q_deg_rows):
    """Per step: every mocap body's position then quaternion (mjSTATE_MOCAP_POS | MOCAP_QUAT order)."""
    import mujoco
    bodies = [int(np.where(m.body_mocapid == k)[0][0]) for k in range(m.nmocap)]
    frames = [int(mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, b)[len("frame"):]) for b in bodies]
    out = np.empty((len(q_deg_rows), m.nmocap * 7))
    for s, q in enumerate(q_deg_rows):
        T = robot.frames(q)
        for k, f in enumerate(frames):
            out[s, 3 * k:3 * k + 3] = T[f][:3, 3]
            out[s, 3 * m.nmocap + 4 * k:3 * m.nmocap + 4 * k + 4] = mat_to_quat(T[f][:3, :3])
    return out


def servo_controls(robot, m, q_deg_rows):
    """Per step: every hinge's target (rad) in actuator order (row order: theta1..theta4)."""
    out = np.empty((len(q_deg_rows), m.nu))
    for s, q in enumerate(q_deg_rows):
        th = robot.thetas(q)
        out[s] = [th[i] for i, row in enumerate(robot.rows) if row[3][0] != "const"]
    return out


def set_pose(robot, m, d, variant, q_deg):
    import mujoco
    if variant == "mocap":
        c = mocap_controls(robot, m, [q_deg])[0]
        d.mocap_pos[:] = c[:3 * m.nmocap].reshape(-1, 3)
        d.mocap_quat[:] = c[3 * m.nmocap:].reshape(-1, 4)
    else:
        d.qpos[:m.nu] = servo_controls(robot, m, [q_deg])[0]
        d.ctrl[:] = d.qpos[:m.nu]
    mujoco.mj_kinematics(m, d)


def check_frames(robot, models, articula):
    """Worst differences (m, rotation-matrix entry) between MuJoCo's frames and the DH frames."""
    import mujoco
    rng = np.random.default_rng(20261121)
    poses = [robot.home_deg]
    for _ in range(23):
        mo = [rng.uniform(lo, hi) for lo, hi in robot.motor_limits]
        poses.append(robot.joints_from_motors(mo))
    ms, mm = models["b"], models["a"]
    ds, dm = mujoco.MjData(ms), mujoco.MjData(mm)
    worst_p = worst_R = worst_geom = 0.0
    for q in poses:
        T = robot.frames(q)
        set_pose(robot, ms, ds, "servo", q)
        for i in range(1, len(robot.rows) + 1):
            b = mujoco.mj_name2id(ms, mujoco.mjtObj.mjOBJ_BODY, f"frame{i}")
            worst_p = max(worst_p, np.max(np.abs(ds.xpos[b] - T[i][:3, 3])))
            worst_R = max(worst_R, np.max(np.abs(ds.xmat[b].reshape(3, 3) - T[i][:3, :3])))
        set_pose(robot, mm, dm, "mocap", q)
        for g in range(mm.ngeom):
            name = mujoco.mj_id2name(mm, mujoco.mjtObj.mjOBJ_GEOM, g)
            gs = mujoco.mj_name2id(ms, mujoco.mjtObj.mjOBJ_GEOM, name)
            worst_geom = max(worst_geom, np.max(np.abs(dm.geom_xpos[g] - ds.geom_xpos[gs])),
                             np.max(np.abs(dm.geom_xmat[g] - ds.geom_xmat[gs])))
    worst_cli = cli_error = None
    if articula:
        worst_cli = 0.0
        for q in poses[:6]:
            p = subprocess.run([articula, "fk", robot.path, "--q", ",".join(f"{v:.12g}" for v in q), "--json"],
                               capture_output=True, text=True)
            if p.returncode != 0:
                worst_cli, cli_error = None, f"{articula} fk failed: {p.stderr.strip()}"
                break
            frames = json.loads(p.stdout)["frames"]
            T = robot.frames(q)
            for i, f in enumerate(frames):
                worst_cli = max(worst_cli, np.max(np.abs(np.array(f["position"]) / 1000.0 - T[i][:3, 3])),
                                np.max(np.abs(np.array(f["rotation"]) - T[i][:3, :3])))
    return {"poses": len(poses), "body_vs_dh_m": worst_p, "body_vs_dh_rot": worst_R,
            "mocap_vs_chain_geoms": worst_geom, "numpy_vs_articula_fk": worst_cli, "articula_fk_error": cli_error}


class Run:
    """One variant on one program: the initial state at home and the per-step controls (the
    mocap poses or the servo targets), precomputed so that only MuJoCo's stepping is timed."""

    def __init__(self, robot, m, arm, controls):
        import mujoco
        self.m, self.arm, self.controls = m, arm, controls
        self.d = mujoco.MjData(m)
        set_pose(robot, m, self.d, arm, robot.home_deg)
        mujoco.mj_forward(m, self.d)
        self.full = mujoco.mjtState.mjSTATE_FULLPHYSICS.value
        self.spec = (mujoco.mjtState.mjSTATE_MOCAP_POS.value | mujoco.mjtState.mjSTATE_MOCAP_QUAT.value
                     if arm == "mocap" else mujoco.mjtState.mjSTATE_CTRL.value)
        self.x0 = np.empty(mujoco.mj_stateSize(m, self.full))
        mujoco.mj_getState(m, self.d, self.x0, self.full)
        self.state = np.empty((1, len(controls), len(self.x0)))
        self.times, self.py_times = [], []

    def time_rollout(self, pool):
        """mj_step in MuJoCo's C++ rollout loop, 10,000 steps from the initial state."""
        t0 = time.perf_counter()
        pool.rollout(self.m, self.d, self.x0[None], self.controls[None], control_spec=self.spec, state=self.state)
        self.times.append(time.perf_counter() - t0)

    def _apply(self, k):
        m, d, c = self.m, self.d, self.controls
        if self.arm == "mocap":
            d.mocap_pos[:] = c[k, :3 * m.nmocap].reshape(-1, 3)
            d.mocap_quat[:] = c[k, 3 * m.nmocap:].reshape(-1, 4)
        else:
            d.ctrl[:] = c[k]

    def time_python_loop(self):
        """The same steps as a Python loop of mj_step calls (includes the bindings' overhead)."""
        import mujoco
        m, d, n = self.m, self.d, len(self.controls)
        mujoco.mj_setState(m, d, self.x0, self.full)
        if self.arm == "mocap":
            pos = self.controls[:, :3 * m.nmocap].reshape(n, -1, 3).copy()
            quat = self.controls[:, 3 * m.nmocap:].reshape(n, -1, 4).copy()
            t0 = time.perf_counter()
            for k in range(n):
                d.mocap_pos[:] = pos[k]
                d.mocap_quat[:] = quat[k]
                mujoco.mj_step(m, d)
        else:
            ctrl = self.controls
            t0 = time.perf_counter()
            for k in range(n):
                d.ctrl[:] = ctrl[k]
                mujoco.mj_step(m, d)
        self.py_times.append(time.perf_counter() - t0)

    def result(self):
        """Figures and the sanity of the last rollout: no NaN, the cube stayed put, the servos tracked."""
        import mujoco
        m, d, n = self.m, self.d, len(self.controls)
        qpos = self.state[0][:, 1:1 + m.nq]  # state: time, qpos, qvel, ...
        cube_adr = m.jnt_qposadr[int(np.where(m.jnt_type == mujoco.mjtJoint.mjJNT_FREE)[0][0])]
        cube_moved = qpos[-1, cube_adr:cube_adr + 3] - self.x0[1 + cube_adr:1 + cube_adr + 3]
        track = float(np.max(np.abs(qpos[:, :m.nu] - self.controls))) if self.arm == "servo" else None
        # Contacts per step, in one more pass (not timed).
        mujoco.mj_setState(m, d, self.x0, self.full)
        ncon = 0
        for k in range(n):
            self._apply(k)
            mujoco.mj_step(m, d)
            ncon += d.ncon
        best = min(self.times)
        return {"steps": n, "runs_s": self.times, "best_s": best, "steps_per_s": n / best,
                "python_loop_steps_per_s": n / min(self.py_times), "nan": bool(np.isnan(self.state).any()),
                "unstable_warnings": int(d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number),
                "cube_slid_mm": float(np.linalg.norm(cube_moved[:2])) * 1000.0,
                "cube_sank_mm": float(-cube_moved[2]) * 1000.0,
                "max_tracking_error_deg": None if track is None else math.degrees(track),
                "mean_contacts": ncon / n}


def time_all(runs_by_key, n_runs):
    """Best of n_runs, the variants interleaved so that the machine's load falls on all alike."""
    from mujoco import rollout
    with rollout.Rollout(nthread=0) as pool:
        for r in runs_by_key.values():  # warm-up
            r.time_rollout(pool)
            r.times.clear()
        for _ in range(n_runs):
            for r in runs_by_key.values():
                r.time_rollout(pool)
    for _ in range(max(1, n_runs // 2)):
        for r in runs_by_key.values():
            r.time_python_loop()
    return {key: r.result() for key, r in runs_by_key.items()}


def run_ours(binary):
    if not os.path.exists(binary):
        return None, f"{binary} does not exist: build it (cmake --build build --target bench_physics)"
    p = subprocess.run([binary, "--benchmark_filter=BM_SimMk2Cube", "--benchmark_format=json"],
                       capture_output=True, text=True)
    if p.returncode != 0:
        return None, f"{binary} failed (exit {p.returncode}): {p.stderr.strip()[-500:]}"
    try:
        doc = json.loads(p.stdout)
    except json.JSONDecodeError as e:
        return None, f"{binary}: output is not JSON ({e})"
    best = {}
    for b in doc.get("benchmarks", []):
        if b.get("run_type", "iteration") != "iteration" or "items_per_second" not in b:
            continue
        name = b["name"].split("/")[0]
        best[name] = max(best.get(name, 0.0), b["items_per_second"])
    if not best:
        return None, f"{binary}: no BM_SimMk2Cube* benchmark with items_per_second in its output"
    return best, None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(REPO, "build"))
    ap.add_argument("--bench-binary", help="our benchmark (default BUILD/bench/bench_physics)")
    ap.add_argument("--robot", default=os.path.join(REPO, "robots", "mk2plus.json"))
    ap.add_argument("--runs", type=int, default=10, help="timed runs per variant, the best is kept")
    ap.add_argument("--json", action="store_true", help="print one JSON document instead of the table")
    args = ap.parse_args()
    if args.runs < 1:
        ap.error("--runs must be >= 1")
    binary = args.bench_binary or os.path.join(args.build, "bench", "bench_physics")
    articula = os.path.join(args.build, "host", "cli", "articula")
    articula = articula if os.path.exists(articula) else None

    try:
        import mujoco
    except ImportError:
        sys.exit("compare_mujoco: mujoco is not installed: run scripts/bootstrap --bench")
    try:
        robot = Mk2Model(args.robot)
    except (OSError, RobotFileError, KeyError, TypeError) as e:
        sys.exit(f"compare_mujoco: {e}" if not isinstance(e, KeyError) else
                 f"compare_mujoco: {args.robot}: missing field {e}")

    # MuJoCo's warnings (an unstable step) are counted in mjData; keep them out of MUJOCO_LOG.TXT.
    warnings = []
    mujoco.set_mju_user_warning(warnings.append)
    models = build_models(robot)
    check = check_frames(robot, models, articula)
    worst = max(check["body_vs_dh_m"], check["mocap_vs_chain_geoms"], check["numpy_vs_articula_fk"] or 0.0)

    n_steps = int(round(SIM_SECONDS / DT))
    runs = {}
    for program in ("moves", "idle"):
        try:
            motors = motor_program(robot, n_steps, program == "idle")
        except ValueError as e:
            sys.exit(f"compare_mujoco: {args.robot}: the program of moves does not fit this robot: {e}")
        q_rows = [robot.joints_from_motors(mo) for mo in motors]
        for key, (arm, _, _, _) in VARIANTS.items():
            m = models[key]
            ctl = (mocap_controls if arm == "mocap" else servo_controls)(robot, m, q_rows)
            runs[(key, program)] = Run(robot, m, arm, ctl)
    results = {key: {} for key in VARIANTS}
    for (key, program), r in time_all(runs, args.runs).items():
        results[key][program] = r

    ours, ours_error = run_ours(binary)
    # Exit status 1 when the models disagree with the DH frames or a MuJoCo run went unstable.
    status = int(worst > FRAME_TOLERANCE_M or
                 any(r["nan"] or r["unstable_warnings"] for v in results.values() for r in v.values()))

    doc = {"mujoco": mujoco.__version__, "numpy": np.__version__, "robot": args.robot, "timestep_s": DT,
           "steps": n_steps, "runs": args.runs, "frame_check": check, "mujoco_results": results,
           "ours": ours, "ours_error": ours_error, "target_steps_per_s": TARGET_STEPS_PER_S,
           "issue_reference_steps_per_s": REFERENCE, "mujoco_warnings": sorted(set(warnings)),
           "model": {v: {"nbody": m.nbody, "ngeom": m.ngeom, "nv": m.nv, "nu": m.nu, "nmocap": m.nmocap,
                         "integrator": ["Euler", "RK4", "implicit", "implicitfast"][m.opt.integrator],
                         "sleep": VARIANTS[v][2], "servo_kp": SERVO_KP if m.nu else None}
                     for v, m in models.items()}}
    if args.json:
        print(json.dumps(doc, indent=2))
        return status

    print(f"MuJoCo {mujoco.__version__} (PyPI), numpy {np.__version__}; {robot.name} + a {CUBE_MM:.0f} mm cube, "
          f"{DT * 1000:.0f} ms steps, {n_steps:,} steps per run, best of {args.runs} runs, one thread")
    cli = ("" if check["numpy_vs_articula_fk"] is None else
           f", numpy DH vs `articula fk` {check['numpy_vs_articula_fk']:.1e}")
    print(f"Same model check over {check['poses']} poses: MuJoCo body frames vs DH frames "
          f"{check['body_vs_dh_m']:.1e} m and {check['body_vs_dh_rot']:.1e} (rotation entries), geoms of (a) vs (b) "
          f"{check['mocap_vs_chain_geoms']:.1e}{cli}: {'ok' if worst <= FRAME_TOLERANCE_M else 'FAILED'} "
          f"(tolerance {FRAME_TOLERANCE_M:g} m)")
    if check["articula_fk_error"]:
        print(f"  (not compared with `articula fk`: {check['articula_fk_error']})")
    for w in sorted(set(warnings)):
        print(f"  MuJoCo warning: {w}")
    for key, per in results.items():
        for program, r in per.items():
            extra = ("" if r["max_tracking_error_deg"] is None else
                     f", servo tracking error <= {r['max_tracking_error_deg']:.3f} deg")
            print(f"  {key} {program}: NaN {'yes' if r['nan'] else 'no'}, unstable-step warnings "
                  f"{r['unstable_warnings']}, cube slid {r['cube_slid_mm']:.4f} mm, sank {r['cube_sank_mm']:.3f} mm "
                  f"(soft contact), {r['mean_contacts']:.2f} contacts per step{extra}; "
                  f"Python loop of mj_step {r['python_loop_steps_per_s']:,.0f} steps/s")
    print()
    if ours_error:
        print(f"Ours: not measured: {ours_error}\n")
    ours = ours or {}
    o_move, o_idle = ours.get("BM_SimMk2Cube"), ours.get("BM_SimMk2CubeIdle")

    def num(v):
        return f"{v:,.0f}" if v else "not measured"

    def us(v):
        return f"{1e6 / v:.2f}" if v else ""

    def ratio(a, b):
        return f"{a / b:.2f}" if a and b else ""

    print("| steps/s, 10,000 steps of 1 ms | moves | us per step | idle | ours / this, moves | ours / this, idle |")
    print("|---|---|---|---|---|---|")
    print(f"| ours (ODE, kinematic arm): BM_SimMk2Cube, ...Idle | {num(o_move)} | {us(o_move)} | "
          f"{num(o_idle)} | | |")
    for key, per in results.items():
        mv, idl = per["moves"]["steps_per_s"], per["idle"]["steps_per_s"]
        print(f"| {VARIANTS[key][3]} | {num(mv)} | {us(mv)} | {num(idl)} | {ratio(o_move, mv)} | "
              f"{ratio(o_idle, idl)} |")
    t = TARGET_STEPS_PER_S
    print(f"| issue 5 target | {num(t)} | {us(t)} | | {ratio(o_move, t)} | |")
    for k, v in REFERENCE.items():
        print(f"| issue 5 reference: {k}, servo arm (another session) | {num(v)} | {us(v)} | | {ratio(o_move, v)} | |")
    if o_move:
        print(f"\nTarget (>= {t:,} steps/s with moves): {'met' if o_move >= t else 'NOT met'} ({o_move:,.0f}).")
    return status


if __name__ == "__main__":
    sys.exit(main())
