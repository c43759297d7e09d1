"""Protocol fuzz: `python -m hil.harness fuzz [--lines N] [--seed S] [--port DEV] [--report FILE]`.

Sends N seeded random and malformed lines to the firmware (the virtual Nano by default, or a
Nano on a serial port) and holds every one to docs/protocol.md: exactly one reply (`ok` or
`error:N`), no reset, no hang, no motion from a rejected line, and on the virtual Nano the
motor driver pins where the status report says the motors are.

How lines are framed. A fuzz line is the bytes before one LF (0x0A) plus that LF: the
generator never puts an LF inside a line, so every fuzz line is exactly one protocol line
and must get exactly one reply. Every other byte value (0x00-0xFF, CR included) may appear
in a line, except the realtime bytes `?` and `!`: they are put in on purpose by the
`realtime` class (at most one `?` and one `!` a line, anywhere before the LF), so the
checker knows how many status reports to expect and when the arm was told to stop.

Classes (the share of lines, roughly): valid lines the arm must accept (`valid`, 12 %: small
`L`, `M` within the limits, reachable `P`, `G`, `S`, `H`, `I`, `$`, comments, a command padded
to exactly 64 bytes, CRLF), random bytes (`random`), overlong lines (`overlong`, 65-300 bytes,
some of them valid commands padded with blanks or a comment: `error:7` and no motion), bad
numbers, NaN and inf, bad joint indices, out-of-range targets (`L`/`M` beyond a limit, `P` out
of reach, `G`, `S`), missing and extra arguments, unknown command letters, control and
non-ASCII bytes, empty lines, setting lines with bad values (and a few good ones, each
followed by a line that puts the old value back), realtime bytes mid-line (`realtime`: a line
of another class with `?` and/or `!` inserted; its reply must be that line's), and `stop`: a
long `M` and a `!` while it runs (the arm decelerates; the commanded angles become those of
the steps reached, as the protocol says, and the fuzz goes on from there).

For each line the fuzz knows the reply it must get where the protocol fixes it (every class
but `random`, whose lines only need one reply of either kind). The arm is at rest before
every line (after an accepted move the fuzz polls `?` until `Idle`: the protocol's flow
control), so the steps in the status report after a rejected line must equal those before
it, and no coil may have changed on the pins. A valid `L` or `M` must end on the steps the
protocol's rounding gives (actuation.h, recomputed here in integers).

The run's settings: `$0=4000`, `$1=100000`, `$5=0` (short moves, no gripper pause), set
before the first fuzz line; on a real port the arm's own settings are put back at the end.
"""

from .generate import Axis, FuzzLine, Generator, MAX_LINE, millideg
from .oracle import Exchange, Finding, check, is_reply
from .run import Fuzzer, Summary
from .command import report_doc, run_fuzz

__all__ = ["Axis", "FuzzLine", "Generator", "MAX_LINE", "millideg", "Exchange", "Finding", "check", "is_reply",
           "Fuzzer", "Summary", "report_doc", "run_fuzz"]
