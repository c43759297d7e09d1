"""articula-studio: serves Articula Studio's static site (studio/web/dist: the page and its
engine, which runs in the browser) on 127.0.0.1, and one WebSocket (`/ws`) per page for what
a web page cannot yet do by itself: the arm in the loop (a serial port, the virtual Nano in
simavr). docs/studio.md describes the messages and the security rules:

  - it binds 127.0.0.1 unless told otherwise (then it warns);
  - the page's URL carries a random token; the WebSocket and the robot file given on the
    command line need it (the site itself is static and public, as on any web host);
  - the WebSocket refuses a foreign Origin and a foreign Host (no other site, and no DNS
    rebinding, can drive the arm);
  - every message is validated; a bad one gets an error reply, never a crash.
"""

from __future__ import annotations

import asyncio
import json
import logging
import math
import os
import secrets
import tempfile
import time
from pathlib import Path
from urllib.parse import quote

import numpy as np
from aiohttp import WSMsgType, web

import articula

log = logging.getLogger("articula.studio")

REPO = Path(__file__).resolve().parents[3]
MAX_MESSAGE = 2_000_000  # bytes of one WebSocket message (a robot file or program inside)
ARM_MESSAGES = {"arm_ports", "arm_connect", "arm_disconnect", "arm_send", "arm_stop", "arm_run"}


class BadMessage(Exception):
    """A message the server does not take: the reply names the problem."""


def _flat(T: np.ndarray) -> list[float]:
    return [round(float(x), 6) for x in np.asarray(T).reshape(-1)]


def shipped_robots() -> list[str]:
    d = Path(os.environ.get("ARTICULA_ROBOTS") or REPO / "robots")
    return sorted(p.stem for p in d.glob("*.json") if not p.stem.endswith(".schema"))


def web_dir() -> Path:
    """The built site: inside the installed package, or the tree's studio/web/dist."""
    packaged = Path(__file__).with_name("web")
    if (packaged / "index.html").is_file():
        return packaged
    return REPO / "studio" / "web" / "dist"


def robot_from(spec, robot_file: Path | None = None) -> articula.Robot:
    """The robot the page shows, for the arm: {"name": a shipped robot}, {"text", "filename"}
    (a robot file's JSON), the same with "legacy": true and "scale" (appendix C), or {"file"}:
    the robot file articula-studio was started with."""
    if not isinstance(spec, dict):
        raise BadMessage("'robot' must be {name} or {text, filename}")
    try:
        if "file" in spec and robot_file is not None:
            return articula.Robot.load(str(robot_file))
        if isinstance(spec.get("name"), str):
            if spec["name"] not in shipped_robots():
                raise BadMessage(f"no shipped robot '{spec['name']}'")
            return articula.Robot.load(spec["name"])
        text, filename = spec.get("text"), spec.get("filename", "robot.json")
        if not isinstance(text, str) or not isinstance(filename, str) or len(text) > MAX_MESSAGE:
            raise BadMessage("'robot' must be {name} or {text, filename}")
        if spec.get("legacy"):
            scale = spec.get("scale")
            if isinstance(scale, bool) or not isinstance(scale, (int, float)) or not 0 < scale < math.inf:
                raise BadMessage("'scale' must be a number above 0")
            with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
                f.write(text)
            try:
                return articula.Robot.from_legacy(f.name, scale)
            finally:
                os.unlink(f.name)
        return articula.Robot.parse(text, filename)
    except (articula.RobotFileError, articula.LegacyError) as e:
        raise BadMessage(str(e)) from None


class Studio:
    def __init__(self, robot: str | None, *, scene: str | None = None, host: str = "127.0.0.1", port: int = 0,
                 token: str | None = None):
        self.robot = robot or "mk2plus"
        self.scene = scene
        self.host = host
        self.port = port
        self.token = token or secrets.token_urlsafe(18)
        self.web = web_dir()
        # A robot file given on the command line: the page's worker fetches it (and the meshes
        # beside it) from /t/<token>/files/, its folder.
        self.robot_file = Path(self.robot).resolve() if self.robot not in shipped_robots() else None
        self.app = web.Application(client_max_size=MAX_MESSAGE)
        self.app.router.add_get("/ws", self.websocket)
        self.app.router.add_get("/t/{token}/files/{path:.+}", self.files)
        self.app.router.add_get("/", self.index)
        self.app.router.add_get("/{path:.+}", self.static)
        self.runner: web.AppRunner | None = None

    # ---- the rules

    def allowed_hosts(self) -> set[str]:
        names = {"127.0.0.1", "localhost", self.host}
        return {f"{n}:{self.port}" for n in names}

    def token_ok(self, request: web.Request) -> bool:
        return secrets.compare_digest(request.query.get("token", ""), self.token)

    def host_ok(self, request: web.Request) -> bool:
        return request.headers.get("Host", "") in self.allowed_hosts()

    def origin_ok(self, request: web.Request) -> bool:
        origin = request.headers.get("Origin")
        return origin is None or origin in {f"http://{h}" for h in self.allowed_hosts()}

    # ---- HTTP: the static site

    async def index(self, request: web.Request) -> web.StreamResponse:
        return await self._serve(request, "index.html")

    async def static(self, request: web.Request) -> web.StreamResponse:
        return await self._serve(request, request.match_info["path"])

    async def _serve(self, request: web.Request, rel: str) -> web.StreamResponse:
        if not self.host_ok(request):
            return web.Response(status=403, text="articula studio: this host name is not the studio's")
        root = self.web.resolve()
        path = (root / rel).resolve()
        if root not in path.parents and path != root or not path.is_file():
            if rel == "index.html":
                return web.Response(status=500, text=f"the studio's page is not built ({path}): run make")
            return web.Response(status=404, text="not found")
        headers = {"Cache-Control": "no-cache"}
        if path.suffix == ".wasm":
            headers["Content-Type"] = "application/wasm"
        return web.FileResponse(path, headers=headers)

    async def files(self, request: web.Request) -> web.StreamResponse:
        if not (self.host_ok(request) and secrets.compare_digest(request.match_info["token"], self.token)):
            return web.Response(status=403, text="forbidden")
        if self.robot_file is None:
            return web.Response(status=404, text="no robot file")
        root = self.robot_file.parent
        path = (root / request.match_info["path"]).resolve()
        if root not in path.parents or not path.is_file():
            return web.Response(status=404, text="no such file")
        return web.FileResponse(path, headers={"Cache-Control": "no-store"})

    # ---- the WebSocket

    async def websocket(self, request: web.Request) -> web.StreamResponse:
        if not self.host_ok(request):
            return web.Response(status=403, text="foreign Host")
        if not self.origin_ok(request):
            return web.Response(status=403, text="foreign Origin")
        if not self.token_ok(request):
            return web.Response(status=403, text="no or wrong token")
        ws = web.WebSocketResponse(max_msg_size=MAX_MESSAGE, heartbeat=30)
        await ws.prepare(request)
        conn = Connection(ws, self.robot_file)
        try:
            await conn.serve()
        finally:
            await conn.arm_disconnect({}, quiet=True)
        return ws

    # ---- running

    async def start(self) -> str:
        self.runner = web.AppRunner(self.app, access_log=None)
        await self.runner.setup()
        site = web.TCPSite(self.runner, self.host, self.port)
        await site.start()
        self.port = site._server.sockets[0].getsockname()[1]  # the port chosen when 0 was asked
        return self.url

    @property
    def url(self) -> str:
        host = "127.0.0.1" if self.host in ("127.0.0.1", "0.0.0.0", "") else self.host
        robot = (f"t/{self.token}/files/{quote(self.robot_file.name)}" if self.robot_file else self.robot)
        url = f"http://{host}:{self.port}/?token={self.token}&robot={quote(robot, safe='/')}"
        return url + (f"&scene={quote(self.scene)}" if self.scene else "")

    async def stop(self) -> None:
        if self.runner:
            await self.runner.cleanup()


class Connection:
    """One page's arm: the connection to it, the lines it accepted since (for the prediction
    beside its replies), and the task that streams its status to the page."""

    def __init__(self, ws: web.WebSocketResponse, robot_file: Path | None = None):
        self.ws = ws
        self.robot_file = robot_file
        self.lock = asyncio.Lock()
        self.robot: articula.Robot | None = None
        self.arm = None
        self.arm_history: list[str] = []
        self.arm_event = asyncio.Event()
        self.arm_task: asyncio.Task | None = None
        self.arm_program: asyncio.Task | None = None
        self.stop_sent_at = 0.0

    async def send(self, msgs: list[dict]) -> None:
        async with self.lock:
            for m in msgs:
                if self.ws.closed:
                    return
                await self.ws.send_str(json.dumps(m, allow_nan=False))

    async def serve(self) -> None:
        async for raw in self.ws:
            if raw.type != WSMsgType.TEXT:
                if raw.type == WSMsgType.BINARY:
                    await self.send([{"type": "error", "message": "binary messages are not understood: send JSON text"}])
                continue
            try:
                msg = json.loads(raw.data)
            except (ValueError, RecursionError) as e:
                await self.send([{"type": "error", "message": f"not JSON: {e}"}])
                continue
            try:
                await self.dispatch(msg)
            except BadMessage as e:
                await self.send([{"type": "error", "message": str(e),
                                  "request": msg.get("type") if isinstance(msg, dict) else None}])
            except Exception as e:  # a bug must not end the page's connection
                log.exception("message %r", msg)
                await self.send([{"type": "error", "message": f"internal error: {type(e).__name__}: {e}"}])

    async def dispatch(self, msg) -> None:
        if not isinstance(msg, dict):
            raise BadMessage("a message is a JSON object with a 'type'")
        kind = msg.get("type")
        if kind not in ARM_MESSAGES:
            raise BadMessage(f"unknown message type {kind!r}: this server connects the arm "
                             f"({', '.join(sorted(ARM_MESSAGES))}); the studio's engine runs in the page")
        await getattr(self, kind)(msg)

    # ---- the arm in the loop

    async def arm_ports(self, msg) -> None:
        from .arm import ports
        await self.send([{"type": "arm_ports", "ports": await asyncio.to_thread(ports)}])

    async def arm_connect(self, msg) -> None:
        from .arm import Arm, ArmError
        port = msg.get("port")
        if not isinstance(port, str) or not port:
            raise BadMessage("'port' must name a port (see arm_ports)")
        await self.arm_disconnect({}, quiet=True)
        r = robot_from(msg.get("robot", {"name": "mk2plus"}), self.robot_file)
        if not r.num_motors:
            raise BadMessage(f"{r.name} has no motors: there is no arm to connect")
        g = r.gripper
        loop = asyncio.get_running_loop()
        arm = Arm(r.name, r.num_motors, (g["servo_closed_deg"], g["servo_open_deg"]) if g else None,
                  on_change=lambda: loop.call_soon_threadsafe(self.arm_event.set))
        await self.send([{"type": "arm", "connected": False, "connecting": True, "port": port}])
        try:
            info = await asyncio.to_thread(arm.open, port)
        except ArmError as e:
            await self.send([{"type": "arm", "connected": False, "port": port, "error": str(e)}])
            return
        self.arm, self.arm_history, self.robot = arm, [], r
        self.arm_task = asyncio.create_task(self._arm_stream())
        await self.send([{"type": "arm", "connected": True, "port": port, "label": arm.label, "info": info}])

    async def arm_disconnect(self, msg, quiet=False) -> None:
        arm, self.arm = self.arm, None
        if self.arm_program:
            self.arm_program.cancel()
        if self.arm_task:
            self.arm_task.cancel()
            self.arm_task = None
        if arm:
            await asyncio.to_thread(arm.close)
        if not quiet:
            await self.send([{"type": "arm", "connected": False}])

    def _arm_or_error(self):
        if self.arm is None:
            raise BadMessage("no arm connected: Connect first")
        return self.arm

    async def arm_send(self, msg) -> None:
        """The thesis's "send command": the line goes to the arm and, predicted, to the model;
        the page shows both answers side by side."""
        from .arm import ArmError
        arm = self._arm_or_error()
        line = msg.get("line")
        if not isinstance(line, str) or not line.strip() or len(line) > 200 or "\n" in line:
            raise BadMessage("'line' must be one protocol line (docs/protocol.md)")
        line = line.strip()
        predicted = self.predict_arm_line(line)
        try:
            reply = await asyncio.to_thread(arm.command, line)
        except ArmError as e:
            await self.send([{"type": "arm_reply", "line": line, "reply": None, "error": str(e), "predicted": predicted}])
            return
        if reply == "ok":
            self.arm_history.append(line)
        meaning = articula.status_text(reply)
        await self.send([{"type": "arm_reply", "line": line, "reply": reply, "meaning": meaning, "predicted": predicted}])

    def predict_arm_line(self, line: str) -> dict:
        """What the controller model says of this line after the ones the arm accepted."""
        r = self.robot
        text = "\n".join(self.arm_history + [line]) + "\n"
        try:
            rec = r.predict(articula.Program.parse(text, "arm.arm")).records[-1]
            return {"reply": "ok" if rec.reply == "ok" else f"error:{rec.code}", "steps": rec.steps,
                    "meaning": articula.status_text(rec.code), "seconds": rec.seconds}
        except articula.ProgramError:
            code = r.quantize([line])[0].code
            return {"reply": f"error:{code}", "steps": None, "meaning": articula.status_text(code)}

    async def arm_run(self, msg) -> None:
        """A protocol program on the arm, line by line with the protocol's flow control (as the
        harness runs plans): a line, its reply, then `?` until Idle before the next."""
        arm = self._arm_or_error()
        text = msg.get("text")
        if not isinstance(text, str) or len(text) > 1_000_000:
            raise BadMessage("'text' must be the program's text")
        program = articula.Program.parse(text, msg.get("name") if isinstance(msg.get("name"), str) else "program.arm")
        if program.format != "protocol":
            raise BadMessage("the arm runs protocol lines (.arm): RoboSim programs run on the model")
        if self.arm_program and not self.arm_program.done():
            raise BadMessage("the arm is already running a program: stop it first")
        self.arm_program = asyncio.create_task(self._arm_program(arm, text.splitlines()))

    async def _arm_program(self, arm, lines: list[str]) -> None:
        from .arm import ArmError
        sent = 0
        try:
            for n, raw in enumerate(lines, 1):
                line = raw.split("#", 1)[0].strip()
                if not line:
                    continue
                predicted = self.predict_arm_line(line)
                reply = await asyncio.to_thread(arm.command, line)
                if reply == "ok":
                    self.arm_history.append(line)
                sent += 1
                await self.send([{"type": "arm_program", "line": n, "command": line, "reply": reply,
                                  "meaning": articula.status_text(reply), "predicted": predicted}])
                if reply == "ok":
                    timeout = 3 * (predicted.get("seconds") or 0) + 5
                    if not await asyncio.to_thread(arm.wait_idle, timeout):
                        raise ArmError(arm.error or f"line {n}: the arm did not come to rest within {timeout:.0f} s")
            await self.send([{"type": "arm_program", "done": True, "sent": sent}])
        except ArmError as e:
            await self.send([{"type": "arm_program", "done": True, "sent": sent, "error": str(e)}])

    async def arm_stop(self, msg) -> None:
        from .arm import ArmError
        arm = self._arm_or_error()
        if self.arm_program and not self.arm_program.done():
            self.arm_program.cancel()  # no further line is sent
            await self.send([{"type": "arm_program", "done": True, "stopped": True}])
        try:
            self.stop_sent_at = await asyncio.to_thread(arm.stop)
        except ArmError as e:
            await self.send([{"type": "arm", "connected": False, "error": str(e)}])
            return
        await self.send([{"type": "arm_stopped"}])

    async def _arm_stream(self) -> None:
        """The arm's status to the page as it changes (the port's thread polls at 15 Hz): the
        second arm drawn from it (the page measures how far its tool is from the model's)."""
        while self.arm is not None and not self.ws.closed:
            await self.arm_event.wait()
            self.arm_event.clear()
            arm, robot = self.arm, self.robot
            if arm is None:
                return
            if not arm.running:
                await self.send([{"type": "arm", "connected": False, "error": arm.error, "lost": True}])
                await self.arm_disconnect({}, quiet=True)
                return
            st = arm.status
            if st is None or st.angles is None or len(st.angles) != robot.num_motors:
                continue
            q = robot.joints_from_motors(st.angles)
            msg = {"type": "arm_status", "state": st.state, "steps": st.steps, "angles": st.angles,
                   "q": q.tolist(), "frames": [_flat(f) for f in robot.frames(q)], "text": st.text,
                   "rtt_ms": arm.rtt_ms, "sent_ms": time.time() * 1000}
            if self.stop_sent_at and st.state == "Idle":
                msg["stop_to_idle_ms"] = (arm.status_at - self.stop_sent_at) * 1000
                self.stop_sent_at = 0.0
                # After a stop the commanded angles are those of the steps reached: the
                # prediction starts from there.
                self.arm_history = ["M " + " ".join(f"{a:.3f}" for a in st.angles)]
            await self.send([msg])
