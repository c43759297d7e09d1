"""Articula from Python: robot files, modified DH kinematics, IK, programs, the controller's
step-exact prediction and the ODE physics, over the same C++ core the Nano firmware and the
`articula` command run. Lengths are millimetres and angles degrees everywhere.

>>> import articula
>>> mk2 = articula.Robot.load("mk2plus")
>>> mk2.fk([0, 90, -90])[:3, 3]
array([235.,   0., 213.])

docs/python.md is the tutorial.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import NamedTuple

# An installed package carries the shipped robots, scenes and cells; the tree's build finds them
# where they are. Names ("mk2plus", "grasp-and-lift") resolve through these variables.
_data = Path(__file__).with_name("data")
if (_data / "robots").is_dir():
    os.environ.setdefault("ARTICULA_ROBOTS", str(_data / "robots"))
if (_data / "scenes").is_dir():
    os.environ.setdefault("ARTICULA_SCENES", str(_data / "scenes"))
if (_data / "cells").is_dir():
    os.environ.setdefault("ARTICULA_CELLS", str(_data / "cells"))

from . import _core  # noqa: E402
from ._core import (  # noqa: E402
    Cell,
    CellError,
    IkResult,
    LegacyError,
    ProgramError,
    Robot,
    RobotFileError,
    SceneError,
    Sim,
    axis_errors,
    experiment_csv,
    repeat_chains,
    joint_verdicts,
    line_command,
    measurement_question,
    parse_plan,
    protocol_number,
    rpy_deg,
    table4,
    table5,
    tool_points,
)
from ._records import Record  # noqa: E402

__all__ = [
    "Robot", "IkResult", "Program", "Sim", "Cell", "Record", "Status", "STATUS", "status_text",
    "RobotFileError", "ProgramError", "SceneError", "CellError", "LegacyError", "IK_STATUS", "rpy_deg",
    "axis_errors", "table4", "measurement_question", "parse_plan", "table5", "tool_points", "joint_verdicts",
    "experiment_csv", "repeat_chains", "protocol_number", "line_command", "REPLY", "DEFAULT_SETTINGS", "STEP_TICK_HZ",
]
__version__ = "0.1.0"


class Status(NamedTuple):
    """One row of the protocol's status table (docs/protocol.md): code, name, text."""
    code: int
    name: str
    text: str


#: The protocol's status codes, from shared/articula/status.h (the firmware's own table):
#: ``STATUS[9].text == "target beyond a joint limit"``.
STATUS: dict[int, Status] = {code: Status(code, name, text) for code, (name, text) in _core._status_table.items()}

#: Each status's reply by its name in the table: ``REPLY["JointLimit"] == "error:9"``,
#: ``REPLY["Ok"] == "ok"``: code that expects a reply names it, never its number.
REPLY: dict[str, str] = {s.name: "ok" if s.code == 0 else f"error:{s.code}" for s in STATUS.values()}

#: The controller's settings' defaults, ``{0: 600, 1: 2000, ...}`` ($0 .. $7), from
#: shared/articula/settings.h (the firmware's own table), in the units ``$n=v`` sets.
DEFAULT_SETTINGS: dict[int, int] = {n: fallback for n, (_, _, fallback) in _core._settings_table.items()}

#: The firmware's step timer, ticks a second (shared/articula/motion.h): record times count in them.
STEP_TICK_HZ: int = _core.STEP_TICK_HZ

#: The codes of Robot.ik_batch's status array.
IK_STATUS = ("reached", "unreachable", "limited", "budget")


def status_text(reply: int | str) -> str:
    """The meaning of a status code or a reply: ``status_text("error:9")`` and
    ``status_text(9)`` are "target beyond a joint limit"; ``status_text("ok")`` is "ok"."""
    if isinstance(reply, str):
        reply = reply.strip()
        if reply == "ok":
            return STATUS[0].text
        head, sep, code = reply.partition(":")
        if head != "error" or not sep:
            raise ValueError(f"'{reply}' is not a reply (ok or error:N)")
        try:
            reply = int(code)
        except ValueError:
            raise ValueError(f"'{reply}': the code after 'error:' must be a number") from None
    if reply not in STATUS:
        return "unknown status"
    return STATUS[reply].text


class Program:
    """A program: RoboSim (thesis appendix B, ``.robosim``) or the arm's protocol lines
    (``.arm``). It is read against a robot when it runs (argument counts follow the robot):
    ``robot.predict(program)``, ``robot.run(program)``, ``Sim.load_program(program)``, or
    ``robot.check_program(program)`` to check it alone.

    >>> p = Program.parse("L 0 10\\nL 1 -20\\n", name="two-moves.arm")
    >>> p.format
    'protocol'
    """

    def __init__(self, text: str | bytes, source: str = "<text>"):
        self.text = text
        self.source = source

    @classmethod
    def load(cls, path: str | os.PathLike) -> "Program":
        path = os.fspath(path)
        try:
            data = Path(path).read_bytes()
        except OSError as e:
            raise ProgramError(f"{path}:0: cannot read the file ({e.strerror})") from None
        try:
            return cls(data.decode("utf-8"), path)
        except UnicodeDecodeError:  # kept as bytes: the parser names the line with the bad byte
            return cls(data, path)

    @classmethod
    def parse(cls, text: str | bytes, name: str = "<text>") -> "Program":
        """A program from text (str, or bytes taken as they are); the name's extension (.arm,
        .robosim) picks the language, else the first command does."""
        return cls(text, name)

    @property
    def format(self) -> str:
        """'robosim' or 'protocol'."""
        return _core.detect_format(self.text, self.source)

    @property
    def lines(self) -> list:
        return self.text.splitlines()

    def __repr__(self) -> str:
        return f"<Program {self.source!r}: {self.format}, {len(self.lines)} lines>"
