"""The fuzz's checker: one line's exchange with the arm held to docs/protocol.md (one reply,
the expected one where the protocol fixes it, no reset, no motion from a rejected line, the
pins where the status report says the motors are)."""

from __future__ import annotations

from dataclasses import dataclass, field

from articula.link import Status, parse_info, parse_setting, parse_status
from .generate import SETTING_DEFAULTS, FuzzLine


# ---------------------------------------------------------------------------------------
# The checker: one line's transcript against the protocol.

@dataclass
class Exchange:
    """What came back for one line: every line from the arm from sending it up to the
    status report that ends its check, the reports the fuzz asked for itself (`polls`), the
    status before and after, and the pins (rows seen, decoded positions) before and after."""
    received: list[str] = field(default_factory=list)
    polls: int = 0
    before: Status | None = None
    after: Status | None = None
    pins_before: tuple[int, list[int]] | None = None
    pins_after: tuple[int, list[int]] | None = None
    coil_faults: list[str] = field(default_factory=list)
    coil_moves: int = 0  # coil events other than the idle release ($5), while the line ran
    timeout: str = ""
    vanished: str = ""
    first_report: bool = False  # the run's first status report is in `received` (W:14 allowed)


@dataclass
class Finding:
    kind: str        # replies, reply, reset, hang, motion, pins, steps, reports, unexpected, coil, vanished
    index: int       # the line's number in the run (1-based)
    line: FuzzLine
    message: str

    def describe(self) -> str:
        return f"line {self.index} ({self.line.cls}, {self.line.kind}) b'{self.line.text()}': {self.kind}: {self.message}"


def is_reply(text: str) -> bool:
    if text == "ok":
        return True
    if text.startswith("error:"):
        code = text[6:]
        return code.isdigit()
    return False


def check(index: int, line: FuzzLine, ex: Exchange) -> tuple[str | None, list[Finding]]:
    """The reply (None when there was none) and every way the exchange breaks the protocol."""
    out: list[Finding] = []

    def bad(kind: str, msg: str) -> None:
        out.append(Finding(kind, index, line, msg))

    if ex.vanished:
        bad("vanished", ex.vanished)
    if ex.timeout:
        bad("hang", ex.timeout)
    replies = [t for t in ex.received if is_reply(t)]
    reply = replies[0] if replies else None
    if len(replies) != 1 and not ex.timeout and not ex.vanished:
        bad("replies", f"{len(replies)} replies ({', '.join(replies) or 'none'}), the protocol says exactly one")
    reports = 0
    infos = settings = 0
    for t in ex.received:
        if is_reply(t):
            continue
        st = parse_status(t)
        if st is not None:
            reports += 1
            if st.warning == 14 and not (ex.first_report and reports == 1):
                bad("reset", f"settings reset to defaults (W:14) after the first report: the firmware started "
                             f"again ({t})")
            continue
        info = parse_info(t)
        if info is not None:
            infos += 1
            if not line.info or infos > 1:
                bad("reset", f"an info line nobody asked for: the firmware started again? ({t})")
            elif info.warning == 14:
                bad("reset", f"settings reset to defaults (W:14) in an info line ({t})")
            continue
        if t.startswith("$") and parse_setting(t) is not None and line.listing:
            settings += 1
            continue
        bad("unexpected", f"a line the protocol does not send here: '{t}'")
    if line.listing and reply == "ok" and settings != len(SETTING_DEFAULTS):
        bad("unexpected", f"{settings} setting lines for `$`, {len(SETTING_DEFAULTS)} expected")
    if line.info and reply == "ok" and infos != 1:
        bad("unexpected", f"{infos} info lines for `I`, 1 expected")
    expected_reports = line.queries + ex.polls
    if not ex.timeout and not ex.vanished and reports != expected_reports:
        bad("reports", f"{reports} status reports for {line.queries} '?' in the line and {ex.polls} sent after it")
    if reply is not None and line.expect is not None and reply not in line.expect:
        bad("reply", f"reply {reply}, the protocol says {' or '.join(sorted(line.expect))}")

    b, a = ex.before, ex.after
    if a is not None and b is not None and a.steps is not None and b.steps is not None:
        if reply is not None and reply != "ok" and a.steps != b.steps:
            bad("motion", f"a rejected line ({reply}) moved the motors: steps {b.steps} -> {a.steps}")
        if line.moves and reply == "ok" and line.target is not None and not line.stop_after and a.steps != line.target:
            bad("steps", f"the move ended on steps {a.steps}, the protocol's rounding gives {line.target}")
        if line.stop_after and reply == "ok" and line.start is not None and line.target is not None:
            for i, (s0, s, t) in enumerate(zip(line.start, a.steps, line.target)):
                if not min(s0, t) <= s <= max(s0, t):
                    bad("steps", f"after ! motor {i} is on step {s}, off the move from {s0} to {t}")
        if not a.at_rest and not ex.timeout:
            bad("hang", f"not at rest after the line: {a.text}")
    if ex.pins_before is not None and ex.pins_after is not None:
        rows0, _ = ex.pins_before
        rows1, pins = ex.pins_after
        # (the coils' release after $5 ms at rest may fall in any line's time: not the line's doing)
        if reply is not None and reply != "ok" and ex.coil_moves:
            bad("motion", f"a rejected line ({reply}) changed the coils: {ex.coil_moves} coil event(s)")
        if a is not None and a.steps is not None and pins != a.steps:
            bad("pins", f"the pins say the motors are on steps {pins}, the status report {a.steps}")
    for f in ex.coil_faults:
        bad("coil", f)
    return reply, out
