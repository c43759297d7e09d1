"""articula-studio [ROBOT] [--scene S] [--port N] [--host H] [--no-browser]

Serves Articula Studio's static site on 127.0.0.1 and opens the page. The page does the rest,
the arm included (the virtual Nano, a Nano over Web Serial, flashing). The first line printed is exactly
`studio: http://127.0.0.1:N/?token=T&robot=R[&scene=S]` (scripts and tests read it)."""

from __future__ import annotations

import argparse
import asyncio
import os
import signal
import sys
import webbrowser

import articula

from .server import Studio, shipped_robots, web_dir


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog="articula-studio",
        description="Articula Studio: see a robot arm in 3D, move it with sliders and by dragging an IK "
                    "target, run programs on it with the controller's real timing and in live physics. "
                    "The studio is a static site that runs in your browser (its engine is WebAssembly); "
                    "this serves it on 127.0.0.1. The page drives the virtual Nano, and a real Nano over Web "
                    "Serial (Chrome, Edge), which it can also flash.",
        epilog="A robot file given here is served under a random token in the page's address. "
               "docs/studio.md explains the studio, what runs where, and its security.")
    ap.add_argument("robot", nargs="?", default="mk2plus",
                    help=f"a shipped robot ({', '.join(shipped_robots())}) or a robot file (default mk2plus)")
    ap.add_argument("--scene", metavar="S", help="start with live physics in this scene (a shipped scene's name, "
                                                  "e.g. grasp-and-lift, or a scene file)")
    ap.add_argument("--port", type=int, default=0, metavar="N", help="the port (default: a free one)")
    ap.add_argument("--host", default="127.0.0.1", metavar="H",
                    help="the address to listen on (default 127.0.0.1: this computer only)")
    ap.add_argument("--no-browser", action="store_true", help="do not open a browser")
    return ap


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    if not 0 <= args.port <= 65535:
        print(f"articula-studio: --port {args.port}: a port is 0 .. 65535", file=sys.stderr)
        return 2
    try:
        articula.Robot.load(args.robot)
    except articula.RobotFileError as e:
        print(f"articula-studio: {e}", file=sys.stderr)
        return 2
    if not (web_dir() / "index.html").is_file():
        print(f"articula-studio: the site is not built ({web_dir()}): run make (or make web)", file=sys.stderr)
        return 2
    if args.host not in ("127.0.0.1", "localhost"):
        print(f"articula-studio: warning: listening on {args.host}: other computers that reach it can load the "
              "studio (and the robot file, with the token); their browsers offer no Web Serial away from "
              "localhost or https", file=sys.stderr)
    if args.scene:
        try:
            articula.Sim(articula.Robot.load(args.robot), args.scene)
        except (articula.SceneError, ValueError) as e:
            print(f"articula-studio: --scene {args.scene}: {e}", file=sys.stderr)
            return 2
    studio = Studio(args.robot, scene=args.scene, host=args.host, port=args.port)

    async def run() -> None:
        url = await studio.start()
        print(f"studio: {url}", flush=True)
        print("  (Ctrl-C stops it)", file=sys.stderr, flush=True)
        if not args.no_browser and (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")
                                    or sys.platform == "darwin"):
            webbrowser.open(url)
        stop = asyncio.Event()
        loop = asyncio.get_running_loop()
        for sig in (signal.SIGINT, signal.SIGTERM):
            loop.add_signal_handler(sig, stop.set)
        await stop.wait()
        await studio.stop()

    try:
        asyncio.run(run())
    except OSError as e:
        print(f"articula-studio: cannot listen on {args.host}:{args.port}: {e.strerror}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
