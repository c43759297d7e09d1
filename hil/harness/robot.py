"""The robot file, as far as the harness needs it: motors (limits, zero angles), the
coupling from motor angles to joint values, and forward kinematics of the tool point.

The kinematics are the modified (Craig) DH of robots/README.md:
T(i-1, i) = Rot_x(alpha(i-1)) Trans_x(a(i-1)) Rot_z(theta(i)) Trans_z(d(i)), then the tool's
fixed offset. `articula predict` is the reference for every predicted figure; this module is
used where the harness needs a position of its own: the tool position a firmware status
report's angles give, and reachable targets for random P lines. test_harness_units.py holds
it to `articula predict`'s figures.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path


@dataclass
class Motor:
    name: str
    zero: float
    min: float
    max: float
    steps_per_rev: int
    microsteps: int
    gear: tuple[float, float]
    direction: int

    @property
    def deg_per_step(self) -> float:
        return 360.0 / (self.steps_per_rev * self.microsteps * self.gear[0] / self.gear[1])


def _matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def _rot_x(deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return [[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]]


def _rot_z(deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return [[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]


def _trans(x, y, z):
    return [[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]]


class Robot:
    """A robot file. Angles in degrees, lengths in millimetres."""

    def __init__(self, path: str | Path):
        self.path = Path(path)
        doc = json.loads(self.path.read_text())
        self.doc = doc
        self.name: str = doc["name"]
        self.rows = doc["dh"]
        # Joint variables in order of appearance: rows top to bottom, theta, d, alpha.
        self.joints: list[str] = []
        for row in self.rows:
            for key in ("theta", "d", "alpha"):
                p = row[key]
                if isinstance(p, dict) and "joint" in p:
                    self.joints.append(p["joint"])
        self.motors: list[Motor] = []
        for m in doc.get("motors", []):
            self.motors.append(Motor(
                name=m["name"], zero=float(m.get("zero", 0.0)),
                min=float(m.get("min", -180.0)), max=float(m.get("max", 180.0)),
                steps_per_rev=int(m.get("steps_per_rev", 200)), microsteps=int(m.get("microsteps", 1)),
                gear=tuple(m.get("gear", [1, 1])), direction=int(m.get("direction", 1))))
        n = len(self.joints)
        self.coupling = doc.get("coupling") or [[1.0 if i == j else 0.0 for j in range(n)] for i in range(n)]
        tool = doc.get("tool", {})
        self.tool_xyz = tool.get("xyz", [0.0, 0.0, 0.0])
        gripper = doc.get("gripper") or {}
        self.servo_closed = gripper.get("servo_closed")
        self.servo_open = gripper.get("servo_open")

    @property
    def zero_angles(self) -> list[float]:
        """The actuator angles of motor step 0 (the power-up pose)."""
        return [m.zero for m in self.motors]

    def joints_from_actuators(self, actuators: list[float]) -> list[float]:
        """Joint values (DH variables) from actuator angles: joint = C * motor angle."""
        return [sum(c * a for c, a in zip(row, actuators)) for row in self.coupling]

    def _param(self, p, values: dict[str, float]) -> float:
        if isinstance(p, (int, float)):
            return float(p)
        if "joint" in p:
            return values[p["joint"]]
        if "linked" in p:
            return float(p.get("offset", 0.0)) + sum(g * values[j] for j, g in p["linked"].items())
        if "value" in p:  # an adjustable length
            return float(p["value"])
        raise ValueError(f"{self.path}: a DH parameter the harness does not understand: {p}")

    def tool_position(self, joint_values: list[float]) -> tuple[float, float, float]:
        """The tool point in the base frame for these joint values."""
        values = dict(zip(self.joints, joint_values))
        t = [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]
        for row in self.rows:
            a = self._param(row["a"], values)
            alpha = self._param(row["alpha"], values)
            d = self._param(row["d"], values)
            theta = self._param(row["theta"], values)
            t = _matmul(t, _matmul(_matmul(_rot_x(alpha), _trans(a, 0, 0)), _matmul(_rot_z(theta), _trans(0, 0, d))))
        x, y, z = self.tool_xyz
        return tuple(t[i][0] * x + t[i][1] * y + t[i][2] * z + t[i][3] for i in range(3))

    def tool_from_actuators(self, actuators: list[float]) -> tuple[float, float, float]:
        return self.tool_position(self.joints_from_actuators(actuators))
