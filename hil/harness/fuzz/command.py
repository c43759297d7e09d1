"""`python -m hil.harness fuzz`: the run on the virtual Nano or a serial port, its progress and
its report (JSON)."""

from __future__ import annotations

import json
import tempfile
import time
from pathlib import Path

from articula.link import LinkTimeout, LinkVanished
from ..robot import Robot
from .generate import FuzzLine
from .oracle import Finding
from .run import Fuzzer, Summary


def report_doc(summary: Summary, seed: int, target: str, command_line: str) -> dict:
    return {"seed": seed, "target": target, "command": command_line, "summary": summary.figures(),
            "findings": [{"kind": f.kind, "line": f.index, "class": f.line.cls, "what": f.line.kind,
                          "bytes": f.line.text(), "message": f.message} for f in summary.findings],
            "vnano": summary.vnano}


def run_fuzz(args, robot: Robot, vnano: str | None, elf: str | None, command_line: str) -> int:
    """The `fuzz` sub-command (cli.py finds the binaries)."""
    from ..targets import SerialTarget, VirtualNanoTarget

    tmp = None
    if args.port:
        target = SerialTarget(args.port, boot_wait=args.boot_wait)
        out_dir = Path(tempfile.mkdtemp(prefix="articula-fuzz-"))
    else:
        grip = (robot.servo_closed, robot.servo_open) if robot.servo_closed is not None and \
            robot.servo_open is not None else None
        target = VirtualNanoTarget(vnano, elf, len(robot.motors), gripper=grip, half_step=robot.half_step_motors,
                                   unipolar=robot.unipolar, cnc=robot.step_dir, servos=robot.servos)
        tmp = tempfile.TemporaryDirectory(prefix="articula-fuzz-")
        out_dir = Path(tmp.name)
    summary = Summary()
    try:
        link = target.start_plan("fuzz", out_dir)
        pins = coil_events = None
        if target.trace is not None:
            trace = target.trace

            def pins():
                return trace.sync()

            def coil_events(a, b):
                return [r for r in trace.rows[a:b] if r.is_coil]

        progress = _progress_printer(args.lines) if not args.no_progress else None
        fz = Fuzzer(link, robot, args.seed, pins=pins, coil_events=coil_events, timeout=args.timeout,
                    progress=progress, bursts=getattr(args, "bursts", False))
        try:
            fz.start(restore_settings=bool(args.port))
            summary = fz.run(args.lines)
        except (LinkTimeout, LinkVanished) as e:
            summary = fz.summary
            summary.aborted = summary.aborted or f"{e}"
        fz.finish()
        if progress:
            progress(None, None)
    finally:
        rep = target.end_plan()
        target.close()
    if rep is not None:
        motors = rep.get("motors") or []
        summary.vnano = {"exit": rep.get("_exit"), "steps": [m.get("steps") for m in motors],
                         "coil_faults": sum(m.get("faults", 0) for m in motors)}
        if summary.pins_end is not None and summary.vnano["steps"] != summary.pins_end:
            summary.findings.append(Finding("pins", summary.lines, FuzzLine("end", b"", None, "end of run"),
                                            f"the virtual Nano's report says steps {summary.vnano['steps']}, the "
                                            f"trace {summary.pins_end}"))
        if summary.vnano["coil_faults"]:
            summary.findings.append(Finding("coil", summary.lines, FuzzLine("end", b"", None, "end of run"),
                                            f"{summary.vnano['coil_faults']} coil fault(s) in the virtual Nano's report"))
    if tmp is not None:
        tmp.cleanup()
    print(summary.text())
    if args.report:
        Path(args.report).write_text(json.dumps(report_doc(summary, args.seed, "serial port " + args.port if args.port
                                                           else "virtual Nano", command_line), indent=1) + "\n")
        print(f"  report: {args.report}")
    return 0 if summary.ok else 1


def _progress_printer(total: int):
    import sys

    state = {"last": 0.0}
    tty = sys.stderr.isatty()

    def show(i, n):
        if i is None:
            if tty:
                sys.stderr.write("\n")
            return
        now = time.monotonic()
        if now - state["last"] < 0.5 and i != n:
            return
        state["last"] = now
        msg = f"fuzz: {i}/{n} lines"
        if tty:
            sys.stderr.write("\r" + msg)
        elif i == n or i % 1000 == 0:
            sys.stderr.write(msg + "\n")
        sys.stderr.flush()

    return show
