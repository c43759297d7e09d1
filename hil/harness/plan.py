"""Test plans: protocol programs (docs/protocol.md, one command a line) with `#@` directives,
read by the host library (articula.parse_plan, host/lib/plan.h).

A plan is an ordinary `.arm` program: `articula predict` and the arm read it as it is (a
directive is a comment to them). hil/plans/README.md describes the format; in short, a line
`#@ NAME ARGS` is a directive; `title` and `note` describe the plan, every other directive
applies to the next command line:

    #@ title TEXT              the plan's title in the report
    #@ note TEXT               a paragraph for the report (any number)
    #@ expect ok|error:N       the reply the next command must get (default ok)
    #@ timeout SECONDS         the next command's time limit, line sent to Idle
    #@ single-joint J ANGLE    the next command is a single-joint test of actuator J at the
                               thesis's angle ANGLE (thesis 5.2, Table 4)
    #@ repeat N out|back       the next command is a move of repeatability chain N, on its
                               way out or back (thesis 5.3, Table 5)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import articula


class PlanError(Exception):
    """A plan the harness cannot run: the message names file:line."""


@dataclass
class Command:
    line: int                      # 1-based line number in the plan file
    text: str                      # the line as sent: without its line end and surrounding blanks
    expect: str = "ok"             # "ok" or "error:N"
    timeout: float | None = None   # seconds from sending to Idle; None: the default
    single_joint: tuple[int, float] | None = None   # (actuator, thesis angle)
    repeat: tuple[int, str] | None = None           # (chain, "out" or "back")

    @property
    def word(self) -> str:
        """The command word: one upper-case letter, or "$"."""
        t = articula.line_command(self.text)
        return t[:1].upper() if t else ""

    @property
    def kind(self) -> str:
        if self.single_joint:
            return "single-joint"
        if self.repeat:
            return "repeat-" + self.repeat[1]
        if self.word == "P":
            return "target"
        return ""


@dataclass
class Plan:
    path: Path
    title: str
    commands: list[Command]
    notes: list[str] = field(default_factory=list)

    @property
    def name(self) -> str:
        return self.path.name

    def command_at(self, line: int) -> Command | None:
        for c in self.commands:
            if c.line == line:
                return c
        return None


def parse_plan(path: str | Path, text: str | None = None) -> Plan:
    """Reads a plan (the host library's reader, host/lib/plan.h, the studio's too). Raises
    PlanError naming file:line for anything it cannot run."""
    path = Path(path)
    if text is None:
        try:
            text = path.read_text(encoding="ascii", errors="surrogateescape")
        except OSError as e:
            raise PlanError(f"{path}: cannot read: {e.strerror}") from None
    try:
        doc = articula.parse_plan(text, str(path))
    except ValueError as e:
        raise PlanError(str(e)) from None
    commands = [Command(line=c["line"], text=c["text"], expect=c["expect"], timeout=c["timeout_s"],
                        single_joint=(c["single_joint"][0], float(c["single_joint"][1])) if c["single_joint"] else None,
                        repeat=(c["repeat"][0], c["repeat"][1]) if c["repeat"] else None)
                for c in doc["commands"]]
    return Plan(path=path, title=doc["title"], commands=commands, notes=list(doc["notes"]))
