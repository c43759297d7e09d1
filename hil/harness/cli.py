"""python -m hil.harness: run test plans on the arm or the virtual Nano and compare what
happens with the prediction (`articula.Robot.predict`, as `articula predict`)."""

from __future__ import annotations

import argparse
import datetime
import os
import shlex
import signal
import sys
import time
from pathlib import Path

from . import fuzz, report
from .measured import MeasuredError, load_measured
from .plan import PlanError, parse_plan
from .prediction import PredictError
from .progress import Progress
from .randplan import generate
from .robot import Robot
from .runner import Runner
from .targets import SerialTarget, TargetError, VirtualNanoTarget

REPO = Path(__file__).resolve().parents[2]

DESCRIPTION = """\
Runs test plans (hil/plans/*.arm: protocol lines with #@ directives, hil/plans/README.md)
on the arm or on the virtual Nano and compares, command by command, what the prediction
(the `articula` package's Robot.predict, the same as `articula predict`) says with what the
firmware reports (`?` until Idle) and, on the virtual Nano, with what its motor driver pins
did. Writes a report folder (report.md, report.html, PNG plots, commands.csv) and prints a
summary.

By default the plans run on the virtual Nano (articula-vnano, the firmware's ELF in simavr),
started afresh for each plan; --port runs them on a Nano on a serial port instead (the same
code: both are opened with pyserial)."""

EPILOG = """\
examples:
  python -m hil.harness run hil/plans/*.arm
  python -m hil.harness run --random 200 --seed 7 --settings 0=4000,1=100000,5=20
  python -m hil.harness run hil/plans/thesis-single-joint.arm --port /dev/ttyUSB0 \\
      --measured my-measurements.csv
  python -m hil.harness generate 50 --seed 3 -o plan.arm
  python -m hil.harness fuzz --lines 10000 --seed 1 --report fuzz.json

binaries: --vnano and --elf, else $ARTICULA_VNANO and $ARTICULA_NANO_ELF, else the
repository's build/ (build/virtual-nano/articula-vnano, build/avr/firmware/articula-nano.elf); a
robot on STEP/DIR drivers runs the CNC shield's build beside it (articula-cnc.elf). The
prediction is the `articula` Python package (make builds it into python/).

exit status: 0 every command matched (prediction = firmware, = pins on the virtual Nano) and
no fault; 1 a mismatch or a fault (error reply the plan did not expect, timeout, vanished
port, firmware reset, coil fault); 2 a usage error (bad option, plan, robot file or binary)."""


def _find(explicit: str | None, env: str, candidates: list[Path], what: str) -> str:
    if explicit:
        p = Path(explicit)
        if not p.exists():
            raise TargetError(f"no {what} at {explicit}")
        return str(p)
    v = os.environ.get(env)
    if v:
        if not Path(v).exists():
            raise TargetError(f"no {what} at ${env}={v}")
        return v
    for c in candidates:
        if c.exists():
            return str(c)
    raise TargetError(f"no {what}: build it (cmake --build build) or give its path "
                      f"(looked in {', '.join(str(c) for c in candidates)}; ${env} not set)")


def _settings(text: str | None) -> dict[int, float]:
    out: dict[int, float] = {}
    if not text:
        return out
    for part in text.split(","):
        n, eq, v = part.strip().partition("=")
        try:
            if not eq:
                raise ValueError
            out[int(n.lstrip("$"))] = float(v)
        except ValueError:
            raise argparse.ArgumentTypeError(f"--settings takes n=value,... (as 0=4000,1=100000), not '{part}'")
    return out


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="python -m hil.harness", description=DESCRIPTION, epilog=EPILOG,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", metavar="COMMAND")
    run = sub.add_parser("run", help="run plans and write a report", description=DESCRIPTION, epilog=EPILOG,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    run.add_argument("plans", nargs="*", metavar="PLAN", help="plan files (.arm protocol lines, #@ directives)")
    run.add_argument("--port", metavar="DEV", help="a real Nano on this serial port (default: the virtual Nano)")
    run.add_argument("--robot", metavar="FILE", default=str(REPO / "robots" / "mk2plus.json"),
                     help="the robot file the firmware was built for, or a shipped robot's name (default "
                          "robots/mk2plus.json)")
    run.add_argument("--expect-predicted", action="store_true",
                     help="each command must get the reply the prediction gives, not the plan's #@ expect (plans "
                          "written for another arm, such as hil/plans on the arms of hil/robots)")
    run.add_argument("--out", metavar="DIR", help="the report folder (default reports/hil-YYYYmmdd-HHMMSS in the "
                                                  "repository)")
    run.add_argument("--measured", metavar="CSV", help="measured tool positions: columns plan_line,x_mm,y_mm,z_mm "
                                                       "(and plan, with several plans); the studio's Experiment CSV "
                                                       "as it is exported")
    run.add_argument("--random", metavar="N", type=int, help="also run a random plan of N commands (saved in the "
                                                             "report folder)")
    run.add_argument("--seed", metavar="S", type=int, default=1, help="the random plan's seed (default 1)")
    run.add_argument("--settings", metavar="n=v,...", type=_settings,
                     help="settings sent before each plan, e.g. 0=4000,1=100000,5=20 (faster moves for tests); on "
                          "a real arm the ones it had are put back after each plan")
    run.add_argument("--elf", metavar="PATH", help="the firmware ELF for the virtual Nano (a robot on STEP/DIR drivers: articula-cnc.elf beside it)")
    run.add_argument("--vnano", metavar="PATH", help="the articula-vnano program")
    run.add_argument("--timeout", metavar="S", type=float, default=5.0,
                     help="seconds to wait for a reply; a command may take this plus 3x its predicted duration to "
                          "come to rest (default 5; a plan's #@ timeout overrides it for one command)")
    run.add_argument("--poll", metavar="S", type=float, default=0.01, help="seconds between status polls "
                                                                           "(default 0.01)")
    run.add_argument("--boot-wait", metavar="S", type=float, default=2.0,
                     help="with --port: seconds to wait after opening the port (a Nano resets; default 2)")
    run.add_argument("--keep-traces", action="store_true", help="keep the virtual Nano's step traces (CSV, large)")
    run.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")
    run.add_argument("--no-plots", action="store_true",
                     help="a report without its PNG plots (quicker: the tables have every figure)")
    gen = sub.add_parser("generate", help="write a random plan", description="Writes a random plan (see run --random).")
    gen.add_argument("n", type=int, metavar="N", help="commands")
    gen.add_argument("--seed", type=int, default=1, metavar="S")
    gen.add_argument("--robot", default=str(REPO / "robots" / "mk2plus.json"), metavar="FILE")
    gen.add_argument("-o", "--output", metavar="FILE", help="default: standard output")
    fz = sub.add_parser("fuzz", help="send random and malformed lines, check every reply",
                        description="Sends N seeded random and malformed lines (random bytes, overlong lines, "
                                    "bad numbers, NaN, out-of-range joints and targets, realtime bytes mid-line, "
                                    "and valid lines) to the virtual Nano or a Nano on --port, and checks each: "
                                    "exactly one reply, the one the protocol gives, no reset, no hang, no motion "
                                    "from a rejected line, pins = status. hil/README.md, \"Protocol fuzz\".",
                        epilog="exit status: 0 every line answered once as the protocol says, no reset, no hang, no "
                               "motion from a rejected line, pins = status; 1 otherwise; 2 a usage error.")
    fz.add_argument("--lines", metavar="N", type=int, default=10000, help="fuzz lines to send (default 10000)")
    fz.add_argument("--seed", metavar="S", type=int, default=1, help="the generator's seed (default 1)")
    fz.add_argument("--port", metavar="DEV", help="a real Nano on this serial port (default: the virtual Nano)")
    fz.add_argument("--report", metavar="FILE", help="write the summary and every finding as JSON")
    fz.add_argument("--robot", metavar="FILE", default=str(REPO / "robots" / "mk2plus.json"),
                    help="the robot file the firmware was built for (default robots/mk2plus.json)")
    fz.add_argument("--elf", metavar="PATH", help="the firmware ELF for the virtual Nano (a robot on STEP/DIR drivers: articula-cnc.elf beside it)")
    fz.add_argument("--vnano", metavar="PATH", help="the articula-vnano program")
    fz.add_argument("--timeout", metavar="S", type=float, default=5.0, help="seconds to wait for a reply (default 5)")
    fz.add_argument("--boot-wait", metavar="S", type=float, default=2.0,
                    help="with --port: seconds to wait after opening the port (default 2)")
    fz.add_argument("--bursts", action="store_true",
                    help="also send bursts: moves streamed to fill the queue, then a line held until there is room")
    fz.add_argument("--no-progress", action="store_true", help="no progress on stderr")
    return ap


def main(argv: list[str] | None = None) -> int:
    ap = parser()
    try:
        args = ap.parse_args(argv)
    except SystemExit as e:
        return int(e.code or 0) and 2
    if args.cmd is None:
        ap.print_help()
        return 2
    try:
        if args.cmd == "generate":
            return _generate(args)
        if args.cmd == "fuzz":
            return _fuzz(args, argv)
        return _run(args, argv)
    except (TargetError, PlanError, MeasuredError, PredictError) as e:
        print(f"python -m hil.harness: {e}", file=sys.stderr)
        return 2


def _generate(args) -> int:
    if args.n < 1:
        raise PlanError("N must be at least 1")
    robot = Robot(args.robot)
    text = generate(robot, args.n, args.seed)
    if args.output:
        Path(args.output).write_text(text)
    else:
        sys.stdout.write(text)
    return 0


def _fuzz(args, argv) -> int:
    if args.lines < 1:
        raise PlanError("--lines N needs N >= 1")
    try:
        robot = Robot(args.robot)
    except (OSError, ValueError, KeyError) as e:
        raise PlanError(f"{args.robot}: not a robot file the harness can read ({e})") from None
    vnano = elf = None
    if not args.port:
        vnano, elf = _vnano_and_elf(args, robot)
    cmdline = "python -m hil.harness " + " ".join(shlex.quote(a) for a in (argv if argv is not None else sys.argv[1:]))
    return fuzz.run_fuzz(args, robot, vnano, elf, cmdline)


def _vnano_and_elf(args, robot: Robot) -> tuple[str, str | None]:
    """The virtual Nano and the firmware ELF for the robot's drive: the Nano build's, or for
    STEP/DIR drivers the CNC shield build's (articula-cnc.elf beside the Nano's), for servos the
    servo build's (articula-servo.elf)."""
    vnano = _find(args.vnano, "ARTICULA_VNANO", [REPO / "build" / "virtual-nano" / "articula-vnano"],
                  "virtual Nano (articula-vnano)")
    elf_default = REPO / "build" / "avr" / "firmware" / "articula-nano.elf"
    elf = args.elf or os.environ.get("ARTICULA_NANO_ELF") or (str(elf_default) if elf_default.exists() else None)
    if elf and robot.firmware != "articula-nano":
        elf = str(Path(elf).with_name(robot.firmware + ".elf"))
    if elf and not Path(elf).exists():
        raise TargetError(f"no firmware ELF at {elf}")
    return vnano, elf


def _run(args, argv) -> int:
    if not args.plans and not args.random:
        raise PlanError("no plan: give PLAN files or --random N")
    if args.random is not None and args.random < 1:
        raise PlanError("--random N needs N >= 1")
    try:
        robot = Robot(args.robot)
    except (OSError, ValueError, KeyError) as e:
        raise PlanError(f"{args.robot}: not a robot file the harness can read ({e})") from None
    if not robot.motors:
        raise PlanError(f"{args.robot}: the robot has no motors: nothing to run")
    started = datetime.datetime.now()
    out = Path(args.out) if args.out else REPO / "reports" / f"hil-{started:%Y%m%d-%H%M%S}"

    plans = [parse_plan(p) for p in args.plans]
    out.mkdir(parents=True, exist_ok=True)
    if args.random:
        rp = out / f"random-{args.random}-seed-{args.seed}.arm"
        rp.write_text(generate(robot, args.random, args.seed))
        plans.append(parse_plan(rp))
    names = [p.name for p in plans]
    if len(set(names)) != len(names):
        raise PlanError("two plans with the same file name: " + ", ".join(sorted(n for n in set(names)
                                                                                  if names.count(n) > 1)))
    measured = load_measured(args.measured, names) if args.measured else {}

    vnano = elf = None
    if args.port:
        target = SerialTarget(args.port, boot_wait=args.boot_wait)
    else:
        vnano, elf = _vnano_and_elf(args, robot)
        grip = (robot.servo_closed, robot.servo_open) if robot.servo_closed is not None and \
            robot.servo_open is not None else None
        target = VirtualNanoTarget(vnano, elf, len(robot.motors), gripper=grip, keep_traces=args.keep_traces,
                                   half_step=robot.half_step_motors, unipolar=robot.unipolar,
                                   cnc=robot.step_dir, servos=robot.servos)

    progress = Progress(sum(len(p.commands) for p in plans), enabled=not args.no_progress)
    runner = Runner(target, robot, out, settings=args.settings, timeout=args.timeout, poll=args.poll,
                    progress=progress, expect_predicted=args.expect_predicted)
    results = []
    t0 = time.monotonic()
    interrupted = False
    old = signal.signal(signal.SIGTERM, _interrupt)
    try:
        for plan in plans:
            progress.plan(plan.name, len(plan.commands))
            res = runner.run_plan(plan)
            for r in res.records:
                m = measured.get((plan.name, r.line))
                if m:
                    r.measured_xyz, r.measured_count = m
            results.append(res)
            if target.kind == "serial" and getattr(target, "dead", False):
                break
    except KeyboardInterrupt:
        interrupted = True
    finally:
        signal.signal(signal.SIGTERM, old)
        target.close()
        progress.finish()
    if not results:
        print("python -m hil.harness: interrupted before any plan finished", file=sys.stderr)
        return 1
    unknown = [k for k in measured if not any(res.plan.name == k[0] and res.plan.command_at(k[1])
                                               for res in results)]
    if unknown:
        print("python -m hil.harness: measured lines that are no command line of their plan: " +
              ", ".join(f"{p}:{n}" for p, n in unknown), file=sys.stderr)
    cmdline = "python -m hil.harness " + " ".join(shlex.quote(a) for a in (argv if argv is not None else sys.argv[1:]))
    run = report.Run(results=results, target=(f"serial port {args.port}" if args.port else "virtual Nano"),
                     robot_name=robot.name, robot_path=_rel(robot.path),
                     vnano=_rel(vnano) if vnano else None, elf=_rel(elf) if elf else None,
                     started=started.strftime("%Y-%m-%d %H:%M:%S"), wall_s=time.monotonic() - t0,
                     settings_override=args.settings or {}, measured_path=args.measured, has_pins=not args.port,
                     command_line=cmdline)
    md = report.build(run, out, robot, plots=not args.no_plots)
    print(report.summary_text(run, md))
    if interrupted:
        print("python -m hil.harness: interrupted; the report covers the plans that ran", file=sys.stderr)
        return 1
    return 0 if report.summary_figures(run)["ok"] and len(results) == len(plans) else 1


def _interrupt(signum, frame):
    raise KeyboardInterrupt  # SIGTERM ends the run like Ctrl-C: the report covers the plans done


def _rel(p) -> str:
    try:
        return str(Path(p).resolve().relative_to(REPO))
    except ValueError:
        return str(p)
