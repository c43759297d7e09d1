"""One studio page's state on the server (MeshCat's pattern: the server holds the scene, the
page draws it and sends intents). Every pose the page shows is computed here by the
`articula` package; the page never computes kinematics.

A Session answers messages (dicts, docs/studio.md "Messages") with lists of messages. It knows
nothing of HTTP or WebSockets, so tests can drive it directly.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any, Callable

import numpy as np

import articula

REPO = Path(__file__).resolve().parents[3]

# Robot files the page may load by name: the shipped ones.
def shipped_robots() -> list[str]:
    d = Path(os.environ.get("ARTICULA_ROBOTS") or REPO / "robots")
    return sorted(p.stem for p in d.glob("*.json") if not p.stem.endswith(".schema"))


def shipped_scenes() -> list[str]:
    d = Path(os.environ.get("ARTICULA_SCENES") or REPO / "scenes")
    return sorted(p.stem for p in d.glob("*.json") if not p.stem.endswith(".schema"))


def shipped_programs() -> dict[str, Path]:
    d = REPO / "programs"
    packaged = Path(articula.__file__).with_name("data") / "programs"
    if packaged.is_dir():
        d = packaged
    return {p.name: p for p in sorted(d.iterdir()) if p.suffix in (".arm", ".robosim")}


MAX_UPLOAD = 1_000_000  # bytes of a robot file or program sent by the page


class BadMessage(Exception):
    """A message the server does not take: the reply names the problem."""


def _num(msg: dict, key: str, lo: float = -math.inf, hi: float = math.inf) -> float:
    v = msg.get(key)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise BadMessage(f"'{key}' must be a finite number")
    if not lo <= v <= hi:
        raise BadMessage(f"'{key}' must be within {lo:g} .. {hi:g}")
    return float(v)


def _numbers(msg: dict, key: str, count: int | tuple[int, ...]) -> list[float]:
    v = msg.get(key)
    counts = (count,) if isinstance(count, int) else count
    if not isinstance(v, list) or len(v) not in counts:
        raise BadMessage(f"'{key}' must be a list of {' or '.join(map(str, counts))} numbers")
    out = []
    for i, x in enumerate(v):
        if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
            raise BadMessage(f"'{key}[{i}]' must be a finite number")
        out.append(float(x))
    return out


def _text(msg: dict, key: str, limit: int = MAX_UPLOAD) -> str:
    v = msg.get(key)
    if not isinstance(v, str):
        raise BadMessage(f"'{key}' must be text")
    if len(v.encode("utf-8", "surrogatepass")) > limit:
        raise BadMessage(f"'{key}' is larger than {limit:,} bytes")
    return v


def _flat(T: np.ndarray) -> list[float]:
    return [round(float(x), 6) for x in np.asarray(T).reshape(-1)]


class Session:
    def __init__(self, robot: str | None = None, *, scene: str | None = None,
                 mesh_url: Callable[[str], str] | None = None):
        self.mesh_url = mesh_url or (lambda path: path)
        self.meshes: dict[str, str] = {}  # url key -> file path, for the server to serve
        self.robot: articula.Robot | None = None
        self.q = np.zeros(0)
        self.gripper = 100.0  # percent open
        self.timeline: dict[str, Any] | None = None
        # Live physics (docs/studio.md, "Physics"): the scene's name and its simulation, or None.
        self.scene: str | None = scene
        self.sim: articula.Sim | None = None
        self.events_sent = 0
        self.load(articula.Robot.load(robot or "mk2plus"))

    # ---- robot

    def load(self, robot: articula.Robot) -> None:
        self.robot = robot
        self.q = robot.home.copy()
        self.gripper = 100.0
        self.timeline = None
        self.meshes = {}
        if self.scene is not None:
            self.start_physics(self.scene)

    def robot_message(self) -> dict:
        r = self.robot
        links = []
        for link in r.links:
            shapes = []
            for s in link["shapes"]:
                shape = {"type": s["type"], "size": list(s["size"]), "pose": _flat(s["pose"])}
                if s["type"] == "mesh":
                    key = str(len(self.meshes))
                    self.meshes[key] = s["mesh"]
                    shape["url"] = self.mesh_url(key)
                    shape["format"] = Path(s["mesh"]).suffix.lower().lstrip(".")
                shapes.append(shape)
            links.append({"frame": link["frame"], "shapes": shapes})
        return {
            "type": "robot", "name": r.name, "description": r.description, "source": r.source,
            "joints": r.joints, "dh": r.dh, "num_rows": r.num_rows, "home": r.home.tolist(),
            "motors": [m["name"] for m in r.motors], "links": links, "gripper": r.gripper,
            "reach_mm": r.reach_mm, "robots": shipped_robots(), "programs": sorted(shipped_programs()),
            "scenes": shipped_scenes(), "import_notes": r.import_notes,
        }

    def pose_message(self, q: np.ndarray | None = None, **extra) -> dict:
        r = self.robot
        q = self.q if q is None else q
        frames = r.frames(q)
        tool = frames[-1]
        msg = {
            "type": "pose", "q": q.tolist(), "frames": [_flat(f) for f in frames],
            "tool": {"xyz": tool[:3, 3].tolist(), "rpy": list(articula.rpy_deg(tool))},
            "dh_table": r.dh_table(q).tolist(), "gripper": self.gripper,
            "within_limits": r.within_limits(q),
        }
        if r.gripper:
            opening = r.gripper["max_opening_mm"] * self.gripper / 100
            msg["fingers"] = [_flat(f) for f in r.finger_poses(q, opening)]
        msg.update(extra)
        return msg

    # ---- messages

    def handle(self, msg: Any) -> list[dict]:
        if not isinstance(msg, dict):
            raise BadMessage("a message is a JSON object with a 'type'")
        kind = msg.get("type")
        handler = getattr(self, f"on_{kind}", None) if isinstance(kind, str) and kind.isidentifier() else None
        if handler is None:
            raise BadMessage(f"unknown message type {kind!r}")
        return handler(msg)

    def on_hello(self, msg) -> list[dict]:
        return [self.robot_message(), self.scene_message(), self.physics_message(), self.pose_message()]

    def on_set_joint(self, msg) -> list[dict]:
        j = int(_num(msg, "joint", 0, self.robot.num_joints - 1))
        if j != msg["joint"]:
            raise BadMessage("'joint' must be a whole number")
        lo, hi = self.robot.limits[j]
        v = min(max(_num(msg, "value"), lo), hi)
        self.q[j] = v
        return [self.pose_message(seq=msg.get("seq"))]

    def on_set_joints(self, msg) -> list[dict]:
        q = np.array(_numbers(msg, "q", self.robot.num_joints))
        self.q = np.clip(q, self.robot.limits[:, 0], self.robot.limits[:, 1])
        return [self.pose_message(seq=msg.get("seq"))]

    def on_home(self, msg) -> list[dict]:
        self.q = self.robot.home.copy()
        return [self.pose_message()]

    def power_up_q(self) -> np.ndarray:
        """Where a robot with motors powers up: every motor at step 0, its zero angle."""
        return self.robot.joints_from_motors([m["zero"] for m in self.robot.motors])

    def on_zero(self, msg) -> list[dict]:
        """The motors' zero angles (where the real arm powers up), or all joint variables 0
        (clamped into the limits) for a robot without motors."""
        r = self.robot
        if r.num_motors:
            self.q = self.power_up_q()
        else:
            self.q = np.clip(np.zeros(r.num_joints), r.limits[:, 0], r.limits[:, 1])
        return [self.pose_message()]

    def on_gripper(self, msg) -> list[dict]:
        if not self.robot.gripper:
            raise BadMessage(f"{self.robot.name} has no gripper")
        self.gripper = _num(msg, "percent", 0, 100)
        return [self.pose_message()]

    def _ik_args(self, msg) -> dict:
        target = _numbers(msg, "target", (3, 6))
        solver = msg.get("solver", "auto")
        if solver not in ("auto", "closed", "lm", "jt"):
            raise BadMessage("'solver' must be auto, closed, lm or jt")
        args = {"target": target, "solver": solver, "start": self.q}
        if msg.get("weights") is not None:
            args["weights"] = _numbers(msg, "weights", (self.robot.num_joints, self.robot.num_motors))
        return args

    def _ik_reply(self, res: articula.IkResult, seq=None) -> dict:
        return {"type": "ik", "status": res.status, "solver": res.solver,
                "position_error_mm": res.position_error_mm, "orientation_error_deg": res.orientation_error_deg,
                "iterations": res.iterations, "limited_by": res.limited_by + res.limited_by_motors,
                "beyond_reach": res.beyond_reach, "seq": seq}

    def on_ik(self, msg) -> list[dict]:
        """Solve for a target and move there (to the best pose found when not reached)."""
        args = self._ik_args(msg)
        try:
            res = self.robot.ik(**args)
        except ValueError as e:
            raise BadMessage(str(e)) from None
        self.q = res.q
        return [self._ik_reply(res, msg.get("seq")), self.pose_message(seq=msg.get("seq"))]

    def jt_steps(self, msg, steps: int = 400, per_frame: int = 1):
        """The thesis's Jacobian transpose, iteration by iteration (for the page to animate):
        yields (result, pose message) after each `per_frame` iterations until it stops."""
        args = self._ik_args(msg)
        args["solver"] = "jt"
        for i in range(steps):
            args["start"] = self.q
            try:
                res = self.robot.ik(**args, max_iterations=per_frame)
            except ValueError as e:
                raise BadMessage(str(e)) from None
            moved = float(np.abs(res.q - self.q).max())
            self.q = res.q
            done = res.status != "budget" or moved < 1e-9
            if done and res.status == "budget":
                # It stopped moving short of the target: the solver's own verdict from here
                # (limited by which joint, or unreachable), as a whole solve gives it.
                args["start"] = self.q
                res = self.robot.ik(**args)
                self.q = res.q
            yield res, i, done
            if done:
                return

    # ---- programs

    def on_program_open(self, msg) -> list[dict]:
        name = _text(msg, "name", 200)
        programs = shipped_programs()
        if name not in programs:
            raise BadMessage(f"no shipped program '{name}'")
        return [{"type": "program_text", "name": name, "text": programs[name].read_text()}]

    def on_program_load(self, msg) -> list[dict]:
        """Predict (robots with motors) or run (kinematic robots) a program: the time line the
        page plays. A program that cannot be read is an error naming the line."""
        text = _text(msg, "text")
        name = _text(msg, "name", 200) or "program.arm"
        program = articula.Program.parse(text, name)
        r = self.robot
        try:
            if r.num_motors:
                doc = r.predict(program).to_dict()
                records = doc["records"]
            else:
                doc = r.run(program).to_dict()
                records = self._timed(doc["records"])
        except articula.ProgramError as e:
            return [{"type": "program_error", "message": str(e), "line": e.line}]
        except ValueError as e:
            return [{"type": "program_error", "message": str(e), "line": 0}]
        start = self.q.copy()
        steps = []
        for rec in records:
            q_real = np.array(rec["joints"])
            q_ideal = np.array(rec.get("joints_ideal", rec["joints"]))
            item = {
                "line": rec["line"], "command": rec["command"], "reply": rec["reply"], "code": rec["code"],
                "error": rec.get("error", ""), "note": rec.get("note", ""),
                "start_s": rec["start_s"], "end_s": rec["end_s"], "q": q_real.tolist(), "q_ideal": q_ideal.tolist(),
                "tool": r.fk(q_real)[:3, 3].tolist(), "tool_ideal": r.fk(q_ideal)[:3, 3].tolist(),
                "error_mm": rec.get("error_mm", 0.0), "steps": rec.get("steps"),
                "gripper": rec.get("gripper_percent"),
            }
            steps.append(item)
        first_q = self.power_up_q() if r.num_motors else start
        self.timeline = {"records": steps, "start_q": first_q, "duration": steps[-1]["end_s"] if steps else 0.0}
        self.q = first_q.copy()
        return [{"type": "timeline", "name": name, "format": program.format, "records": steps,
                 "duration": self.timeline["duration"], "joints": r.joint_names,
                 "summary": doc["summary"]}, self.pose_message(t=0.0, line=0)]

    @staticmethod
    def _timed(records: list[dict], deg_per_s: float = 60.0, mm_per_s: float = 100.0) -> list[dict]:
        """A robot without motors has no controller timing: each move lasts as its largest
        joint change at 60 deg/s (100 mm/s), as `articula sim` moves such robots; a gripper
        action 0.3 s."""
        t, prev = 0.0, None
        out = []
        for rec in records:
            rec = dict(rec)
            q = np.array(rec["joints"])
            dur = 0.0
            if rec["reply"] == "ok":
                if prev is not None:
                    dur = float(np.abs(q - prev).max()) / deg_per_s
                if rec["command"][:1] in ("G", "S", "h"):
                    dur = max(dur, 0.3)
                prev = q
            rec["start_s"], rec["end_s"] = t, t + dur
            t += dur
            out.append(rec)
        return out

    def pose_at(self, t: float) -> dict:
        """The arm at time t of the time line: each action moves from the pose before it to
        its own in its time (joint values linear in time: a drawing of the move, not the
        motors' speed profile), the whole-step pose and the ideal one (the ghost)."""
        tl = self.timeline
        recs = tl["records"]
        q_prev, qi_prev, line, steps, err, grip = tl["start_q"], tl["start_q"], 0, None, 0.0, None
        q, qi = q_prev, qi_prev
        for rec in recs:
            if rec["reply"] != "ok":
                if rec["start_s"] <= t:
                    line = rec["line"]
                continue
            a, b = rec["start_s"], rec["end_s"]
            if t >= b:
                q_prev, qi_prev = np.array(rec["q"]), np.array(rec["q_ideal"])
                q, qi, line, steps, err = q_prev, qi_prev, rec["line"], rec["steps"], rec["error_mm"]
                grip = rec["gripper"] if rec["gripper"] is not None else grip
                continue
            if t >= a:
                f = (t - a) / (b - a) if b > a else 1.0
                q = q_prev + f * (np.array(rec["q"]) - q_prev)
                qi = qi_prev + f * (np.array(rec["q_ideal"]) - qi_prev)
                line = rec["line"]
            break
        self.q = np.asarray(q, dtype=float)
        if grip is not None:
            self.gripper = float(grip)
        ghost = [_flat(f) for f in self.robot.frames(np.asarray(qi, dtype=float))]
        return self.pose_message(t=t, line=line, steps=steps, error_mm=err, ghost=ghost)

    def on_teach(self, msg) -> list[dict]:
        """The current pose as a program line (RoboSim's Teach): `M` with the motor angles
        (joint variables for a robot without motors), or RoboSim's `m` and one value a line."""
        fmt = msg.get("format", "protocol")
        r = self.robot
        if fmt == "robosim":
            line = "m\n" + "\n".join(f"{v:.3f}" for v in self.q)
        else:
            values = r.motors_from_joints(self.q) if r.num_motors else self.q
            line = "M " + " ".join(f"{v:.3f}" for v in values)
        return [{"type": "teach", "line": line}]

    # ---- files

    def on_load_robot(self, msg) -> list[dict]:
        """A shipped robot by name, or a robot file's text (JSON, or a thesis appendix C file
        with its scale). A file that cannot be used keeps the robot that was there."""
        try:
            if "name" in msg:
                name = _text(msg, "name", 200)
                if name not in shipped_robots():
                    raise BadMessage(f"no shipped robot '{name}'")
                robot = articula.Robot.load(name)
            else:
                text = _text(msg, "text")
                filename = _text(msg, "filename", 200) if "filename" in msg else "robot.json"
                if msg.get("legacy"):
                    import tempfile
                    scale = _num(msg, "scale", 1e-6, 1e6)
                    with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
                        f.write(text)
                    try:
                        robot = articula.Robot.from_legacy(f.name, scale)
                    finally:
                        os.unlink(f.name)
                else:
                    robot = articula.Robot.parse(text, filename)
        except (articula.RobotFileError, articula.LegacyError) as e:
            return [{"type": "robot_error", "message": str(e).replace(str(Path(os.sep, "tmp")), "")}]
        self.load(robot)
        return [self.robot_message(), self.pose_message()]

    def on_set_lengths(self, msg) -> list[dict]:
        """RoboSim's l: the lengths a(i-1) of the rows the robot file lets change, in row order."""
        rows = [row["a"] for row in self.robot.dh if isinstance(row["a"], dict)]
        values = _numbers(msg, "values", len(rows))
        try:
            robot = self.robot.with_link_lengths(values)
        except ValueError as e:
            raise BadMessage(str(e)) from None
        q, gripper = self.q, self.gripper
        self.load(robot)
        self.q, self.gripper = q, gripper
        reply = self.robot_message()
        reply["keep_view"] = True
        return [reply, self.pose_message(seq=msg.get("seq"))]

    def on_export_urdf(self, msg) -> list[dict]:
        return [{"type": "urdf", "name": self.robot.name, "xml": self.robot.to_urdf()}]

    # ---- live physics

    def start_physics(self, scene: str | None) -> None:
        """The arm in a scene, simulated from power-up (a robot with motors at its motors' zero
        steps); None: no physics, the kinematic model as before."""
        self.scene = scene
        self.events_sent = 0
        if scene is None:
            self.sim = None
            return
        self.sim = articula.Sim(self.robot, None if scene == "" else scene)
        self.q = self.sim.state()["joints"]

    def scene_message(self) -> dict:
        sim = self.sim
        return {"type": "scene", "name": self.scene, "title": sim.scene_name if sim else "",
                "objects": sim.objects if sim else [], "scenes": shipped_scenes()}

    def on_scene(self, msg) -> list[dict]:
        name = msg.get("name")
        if name is not None:
            name = _text(msg, "name", 200)
            if name and name not in shipped_scenes():
                raise BadMessage(f"no shipped scene '{name}'")
        try:
            self.start_physics(name)
        except (articula.SceneError, ValueError) as e:
            raise BadMessage(str(e)) from None
        self.timeline = None
        return [self.scene_message(), self.physics_message(), self.pose_message()]

    def physics_message(self, rtf: float | None = None, behind: bool = False) -> dict:
        """The simulated world now: the arm (as a pose message's frames), the objects, what
        touches what, and the events since the last message."""
        if not self.sim:
            return {"type": "physics", "on": False}
        st = self.sim.state()
        self.q = np.asarray(st["joints"])
        if self.robot.gripper:
            self.gripper = 100 * st["gripper_mm"] / self.robot.gripper["max_opening_mm"]
        fresh = self.events_sent == 0  # a new or reset simulation: the page starts its event log anew
        events = self.sim.events(self.events_sent)
        self.events_sent += len(events)
        return {
            "type": "physics", "on": True, "fresh": fresh, "t": st["t"], "busy": st["busy"],
            "objects": [{"name": o["name"], "pose": _flat(o["pose"]), "carried": o["carried"],
                         "removed": o["removed"], "movable": o["movable"]} for o in st["objects"]],
            "contacts": [[c["a"], c["b"]] for c in st["contacts"]],
            "events": [e.to_dict() for e in events], "steps": st["counted_steps"], "lost": st["lost_steps"],
            "rtf": rtf, "behind": behind,
        }

    def move_line(self, q) -> str:
        """The protocol line that moves the (simulated) arm to joint values q: `M` with the
        motor angles, or the joint variables of a robot without motors."""
        r = self.robot
        values = r.motors_from_joints(q) if r.num_motors else q
        return "M " + " ".join(f"{v:.3f}" for v in values)

    def on_status_text(self, msg) -> list[dict]:
        code = int(_num(msg, "code", 0, 255))
        return [{"type": "status_text", "code": code, "text": articula.status_text(code)}]
