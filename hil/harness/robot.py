"""The robot file, as the harness uses it: a thin view of `articula.Robot` (the Python package
over the host library), with the motors as records and the tool position of motor angles.
Every kinematic figure is the core's (shared/articula/dh.h, actuation.h): the harness has no
kinematics of its own."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import articula


@dataclass
class Motor:
    name: str
    zero: float
    min: float
    max: float
    steps_per_rev: int
    microsteps: int
    gear: tuple[int, int]
    direction: int
    deg_per_step: float


class Robot:
    """A robot file. Angles in degrees, lengths in millimetres."""

    def __init__(self, name_or_path: str | Path):
        """A robot file, or a shipped robot's name (`mk2plus`)."""
        self.model = articula.Robot.load(str(name_or_path))
        self.path = Path(self.model.source)
        self.name: str = self.model.name
        self.joints: list[str] = self.model.joint_names
        self.motors: list[Motor] = [
            Motor(name=m["name"], zero=m["zero"], min=m["min"], max=m["max"], steps_per_rev=m["steps_per_rev"],
                  microsteps=m["microsteps"], gear=tuple(m["gear"]), direction=m["direction"],
                  deg_per_step=m["deg_per_step"])
            for m in self.model.motors]
        # The Nano's configuration for this robot (docs/protocol.md, "Robot configuration"), or
        # why there is none.
        self.config: dict = {}
        self.config_error = ""
        try:
            self.config = self.model.nano_config()
        except ValueError as e:
            self.config_error = str(e)
        gripper = self.model.gripper or {}
        self.servo_closed = gripper.get("servo_closed_deg")
        self.servo_open = gripper.get("servo_open_deg")

    @property
    def unipolar(self) -> bool:
        """The motors are 28BYJ-48s on ULN2003 boards (the virtual Nano decodes that table)."""
        return bool(self.model.motors) and all(m["driver"]["kind"] == "uln2003" for m in self.model.motors)

    @property
    def step_dir(self) -> bool:
        """The motors are on STEP/DIR drivers in a CNC shield's sockets (the shield's firmware build)."""
        return self.firmware == "articula-cnc"

    @property
    def servos(self) -> list[tuple[int, str, float]]:
        """A servo arm's servos: (motor, signal pin, pulse at step 0 in us) each (the servo build)."""
        return [(i, m["driver"]["pin"], float(m["driver"]["at"][0][0])) for i, m in enumerate(self.model.motors)
                if m["driver"]["kind"] == "servo"]

    @property
    def firmware(self) -> str:
        """The firmware build that drives this robot (`articula-nano`, `articula-cnc`,
        `articula-servo`: Robot.wiring())."""
        return self.model.wiring()["firmware"]

    @property
    def half_step_motors(self) -> list[int]:
        """The motors driven in half steps (the virtual Nano decodes their coils so)."""
        return [i for i, m in enumerate(self.motors) if m.microsteps == 2]

    @property
    def zero_angles(self) -> list[float]:
        """The actuator angles of motor step 0 (the power-up pose)."""
        return [m.zero for m in self.motors]

    def joints_from_actuators(self, actuators: list[float]) -> list[float]:
        """Joint values (DH variables) from actuator angles: joint = C * motor angle."""
        return self.model.joints_from_motors(actuators).tolist()

    def tool_position(self, joint_values: list[float]) -> tuple[float, float, float]:
        """The tool point in the base frame for these joint values."""
        return tuple(self.model.fk(joint_values)[:3, 3].tolist())

    def tool_from_actuators(self, actuators: list[float]) -> tuple[float, float, float]:
        return self.tool_position(self.joints_from_actuators(actuators))
