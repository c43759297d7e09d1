"""Test plans: protocol programs (docs/protocol.md, one command a line) with `#@` directives.

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

import re
from dataclasses import dataclass, field
from pathlib import Path


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
        t = self.text.split("#", 1)[0].strip()
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


_C_SPACE = " \t\n\v\f\r"
_EXPECT = re.compile(r"^(ok|error:\d{1,3})$")


def _number(text: str, where: str, what: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise PlanError(f"{where}: {what} must be a number, not '{text}'") from None
    if v != v or v in (float("inf"), float("-inf")):
        raise PlanError(f"{where}: {what} must be a finite number, not '{text}'")
    return v


def parse_plan(path: str | Path, text: str | None = None) -> Plan:
    """Reads a plan. Raises PlanError naming file:line for anything it cannot run."""
    path = Path(path)
    if text is None:
        try:
            text = path.read_text(encoding="ascii", errors="surrogateescape")
        except OSError as e:
            raise PlanError(f"{path}: cannot read: {e.strerror}") from None
    title = path.stem
    notes: list[str] = []
    commands: list[Command] = []
    pending: dict = {}
    pending_line = 0
    for n, raw in enumerate(text.splitlines(), start=1):
        where = f"{path}:{n}"
        line = raw.rstrip("\r")
        stripped = line.strip()
        if stripped.startswith("#@"):
            body = stripped[2:].strip()
            name, _, rest = body.partition(" ")
            rest = rest.strip()
            args = rest.split()
            if name == "title":
                if not rest:
                    raise PlanError(f"{where}: #@ title needs a text")
                title = rest
                continue
            if name == "note":
                if not rest:
                    raise PlanError(f"{where}: #@ note needs a text")
                notes.append(rest)
                continue
            if not pending:
                pending_line = n
            if name == "expect":
                if len(args) != 1 or not _EXPECT.match(args[0]):
                    raise PlanError(f"{where}: #@ expect takes ok or error:N, not '{rest}'")
                pending["expect"] = args[0]
            elif name == "timeout":
                if len(args) != 1:
                    raise PlanError(f"{where}: #@ timeout takes one number of seconds")
                t = _number(args[0], where, "the timeout")
                if t <= 0:
                    raise PlanError(f"{where}: the timeout must be above 0 s")
                pending["timeout"] = t
            elif name == "single-joint":
                if len(args) != 2 or not args[0].isdigit():
                    raise PlanError(f"{where}: #@ single-joint takes a joint index and the thesis's angle")
                pending["single_joint"] = (int(args[0]), _number(args[1], where, "the thesis's angle"))
            elif name == "repeat":
                if len(args) != 2 or not args[0].isdigit() or args[1] not in ("out", "back"):
                    raise PlanError(f"{where}: #@ repeat takes a chain number and out or back")
                pending["repeat"] = (int(args[0]), args[1])
            else:
                raise PlanError(f"{where}: unknown directive '#@ {name}' (title, note, expect, timeout, "
                                "single-joint, repeat)")
            continue
        if not stripped or stripped.startswith("#"):
            continue
        # The arm acts on '?' and '!' wherever they come, comments included: a plan line must
        # not hold them (the harness sends them itself, '?' to poll the status).
        if "?" in line or "!" in line:
            raise PlanError(f"{where}: '{line}' holds a realtime byte (? or !), which the arm would act on")
        if "\n" in line:
            raise PlanError(f"{where}: a line end inside a line")
        # Sent as `articula predict` reads it: without the blanks around it (C isspace).
        commands.append(Command(line=n, text=line.strip(_C_SPACE), **pending))
        pending = {}
    if pending:
        raise PlanError(f"{path}:{pending_line}: directive without a command line after it")
    if not commands:
        raise PlanError(f"{path}: no command lines")
    return Plan(path=path, title=title, commands=commands, notes=notes)
