"""Articula Studio's server: aiohttp on 127.0.0.1, the page's static files and one WebSocket
(`/ws`) per page, each with its own Session (session.py). docs/studio.md describes the
messages and the security rules:

  - it binds 127.0.0.1 unless told otherwise (then it warns);
  - the page's URL carries a random token; the page and the WebSocket need it;
  - the WebSocket refuses a foreign Origin and a foreign Host (no other site, and no DNS
    rebinding, can drive the arm);
  - every message is validated; a bad one gets an error reply, never a crash.
"""

from __future__ import annotations

import asyncio
import json
import logging
import secrets
import time
from pathlib import Path

from aiohttp import WSMsgType, web

import articula

from .session import REPO, BadMessage, Session, _flat

log = logging.getLogger("articula.studio")

MAX_MESSAGE = 2_000_000  # bytes of one WebSocket message (a robot file or program inside)
FRAME_S = 1 / 60         # playback and animation: one pose a display frame
# What the page asks of the arm that, with physics on, goes to the simulated controller.
PHYSICS_INTENTS = {"set_joint", "set_joints", "home", "zero", "ik", "gripper", "drag", "release", "physics_run",
                   "physics_pause", "physics_step", "physics_reset", "program_load", "play", "pause"}


def web_dir() -> Path:
    """The built page: inside the installed package, or the tree's studio/web/dist."""
    packaged = Path(__file__).with_name("web")
    if (packaged / "index.html").is_file():
        return packaged
    return REPO / "studio" / "web" / "dist"


class Studio:
    def __init__(self, robot: str | None, *, scene: str | None = None, host: str = "127.0.0.1", port: int = 0,
                 token: str | None = None):
        self.robot = robot
        self.scene = scene
        self.host = host
        self.port = port
        self.token = token or secrets.token_urlsafe(18)
        self.web = web_dir()
        self.app = web.Application(client_max_size=MAX_MESSAGE)
        self.app.router.add_get("/", self.index)
        self.app.router.add_get("/ws", self.websocket)
        self.app.router.add_get("/mesh/{session}/{key}", self.mesh)
        if (self.web / "assets").is_dir():
            self.app.router.add_static("/assets/", self.web / "assets")
        self.sessions: dict[str, Session] = {}
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

    # ---- HTTP

    async def index(self, request: web.Request) -> web.StreamResponse:
        if not self.host_ok(request):
            return web.Response(status=403, text="articula studio: this host name is not the studio's")
        if not self.token_ok(request):
            return web.Response(status=403, content_type="text/html", text=(
                "<!doctype html><title>Articula Studio</title><body style='font:16px system-ui;margin:3em'>"
                "<h1>Articula Studio needs its token</h1><p>Open the address that <code>articula-studio</code> "
                "(or <code>make studio</code>) printed: it ends in <code>?token=...</code>.</p>"))
        index = self.web / "index.html"
        if not index.is_file():
            return web.Response(status=500, text=f"the studio's page is not built ({index}): run make")
        return web.FileResponse(index, headers={"Cache-Control": "no-store"})

    async def mesh(self, request: web.Request) -> web.StreamResponse:
        if not (self.token_ok(request) and self.host_ok(request)):
            return web.Response(status=403, text="forbidden")
        session = self.sessions.get(request.match_info["session"])
        path = session.meshes.get(request.match_info["key"]) if session else None
        if not path or not Path(path).is_file():
            return web.Response(status=404, text="no such mesh")
        return web.FileResponse(path)

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
        sid = secrets.token_hex(8)
        conn = Connection(self, ws, sid)
        self.sessions[sid] = conn.session
        try:
            await conn.serve()
        finally:
            conn.stop_tasks()
            if conn.physics:
                conn.physics.cancel()
            await conn.arm_disconnect({}, quiet=True)
            self.sessions.pop(sid, None)
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
        return f"http://{host}:{self.port}/?token={self.token}"

    async def stop(self) -> None:
        if self.runner:
            await self.runner.cleanup()


class Connection:
    """One page: its session, the messages in, and the tasks that stream poses out (program
    playback, the Jacobian transpose animated)."""

    def __init__(self, studio: Studio, ws: web.WebSocketResponse, sid: str):
        self.studio, self.ws, self.sid = studio, ws, sid
        self.session = Session(studio.robot, scene=studio.scene,
                               mesh_url=lambda key: f"/mesh/{sid}/{key}?token={studio.token}")
        self.lock = asyncio.Lock()
        self.task: asyncio.Task | None = None
        self.t = 0.0          # the time line's clock, s
        self.speed = 1.0
        # Live physics: the loop that steps the simulation in real time, whether it runs, and
        # the newest slider or IK target waiting for the simulated arm to be idle.
        self.physics: asyncio.Task | None = None
        self.physics_running = True
        self.pending_move: str | None = None
        self.pending_grip: str | None = None
        # The arm in the loop (arm.py): the connection, the lines it accepted since (for the
        # prediction beside its replies), and the task that streams its status to the page.
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
        kind = msg.get("type") if isinstance(msg, dict) else None
        if self.session.sim is not None and kind in PHYSICS_INTENTS:
            await self.physics_intent(kind, msg)
            return
        if kind in ("play", "pause", "step", "seek", "rewind", "jt_animate", "stop_animation"):
            await getattr(self, kind)(msg)
            return
        if kind in ("drag", "release", "physics_run", "physics_pause", "physics_step", "physics_reset"):
            raise BadMessage("no physics: choose a scene first")
        if kind in ("arm_ports", "arm_connect", "arm_disconnect", "arm_send", "arm_stop", "arm_run"):
            await getattr(self, kind)(msg)
            return
        if kind in ("set_joint", "set_joints", "ik", "home", "zero", "load_robot", "program_load", "set_lengths"):
            self.stop_tasks()  # the user took the arm: playback and animations stop
        replies = self.session.handle(msg)
        await self.send(replies)
        if kind in ("scene", "load_robot", "hello"):
            self.ensure_physics()

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
        r = self.session.robot
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
        self.arm, self.arm_history = arm, []
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
        r = self.session.robot
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
        second arm drawn from it, and how far its tool is from the model's."""
        ses = self.session
        while self.arm is not None and not self.ws.closed:
            await self.arm_event.wait()
            self.arm_event.clear()
            arm = self.arm
            if arm is None:
                return
            if not arm.running:
                await self.send([{"type": "arm", "connected": False, "error": arm.error, "lost": True}])
                await self.arm_disconnect({}, quiet=True)
                return
            st = arm.status
            if st is None or st.angles is None or len(st.angles) != ses.robot.num_motors:
                continue
            q = ses.robot.joints_from_motors(st.angles)
            frames = ses.robot.frames(q)
            model_tool = ses.robot.fk(ses.q)[:3, 3]
            msg = {"type": "arm_status", "state": st.state, "steps": st.steps, "angles": st.angles,
                   "q": q.tolist(), "frames": [_flat(f) for f in frames],
                   "diff_mm": float(((frames[-1][:3, 3] - model_tool) ** 2).sum() ** 0.5), "text": st.text,
                   "rtt_ms": arm.rtt_ms, "sent_ms": time.time() * 1000}
            if self.stop_sent_at and st.state == "Idle":
                msg["stop_to_idle_ms"] = (arm.status_at - self.stop_sent_at) * 1000
                self.stop_sent_at = 0.0
                # After a stop the commanded angles are those of the steps reached: the
                # prediction starts from there.
                self.arm_history = ["M " + " ".join(f"{a:.3f}" for a in st.angles)]
            await self.send([msg])

    # ---- live physics

    def ensure_physics(self) -> None:
        if self.session.sim is not None and (self.physics is None or self.physics.done()):
            self.physics = asyncio.create_task(self._physics())

    async def physics_intent(self, kind: str, msg) -> None:
        """With physics on, the arm is the simulated controller's: a pose from a slider, Home,
        Zero or the IK becomes an `M` line for it (the newest waits until the arm is idle),
        the gripper a `G` line; programs run in the simulation; objects can be dragged."""
        ses = self.session
        sim = ses.sim
        if kind in ("set_joint", "set_joints", "home", "zero", "ik"):
            replies = ses.handle(msg)  # the target pose (ses.q), and for ik the solver's answer
            self.pending_move = ses.move_line(ses.q)
            await self.send([m for m in replies if m["type"] != "pose"] +
                            [{"type": "sim_command", "line": self.pending_move, "seq": msg.get("seq")}])
        elif kind == "gripper":
            pct = msg.get("percent")
            if isinstance(pct, bool) or not isinstance(pct, (int, float)) or not 0 <= pct <= 100:
                raise BadMessage("'percent' must be within 0 .. 100")
            self.pending_grip = f"G {pct:g}"
        elif kind == "drag":
            target = msg.get("target")
            try:
                sim.drag(msg.get("object"), target)
            except (KeyError, IndexError, ValueError, TypeError) as e:
                raise BadMessage(f"drag: {e}".replace('"', "'")) from None
        elif kind == "release":
            sim.release()
        elif kind == "physics_run":
            self.physics_running = True
        elif kind == "physics_pause":
            self.physics_running = False
        elif kind == "physics_step":
            self.physics_running = False
            sim.step(int(round(0.1 / sim.dt)))  # 100 ms
            await self.send([ses.pose_message(), ses.physics_message()])
        elif kind == "physics_reset":
            sim.reset()
            ses.events_sent = 0
            self.pending_move = self.pending_grip = None
            await self.send([ses.physics_message(), ses.pose_message()])
        elif kind == "program_load":
            replies = ses.handle(msg)
            if replies and replies[0]["type"] == "timeline":
                sim.reset()
                ses.events_sent = 0
                self.pending_move = self.pending_grip = None
                sim.load_program(articula.Program.parse(msg["text"], msg.get("name") or "program.arm"))
                self.physics_running = False
            await self.send(replies + [ses.physics_message()])
        elif kind == "play":
            self.physics_running = True
            await self.send([{"type": "playing", "t": sim.time, "playing": True}])
        elif kind == "pause":
            self.physics_running = False
            await self.send([{"type": "playing", "t": sim.time, "playing": False}])
        else:
            raise BadMessage(f"'{kind}' does not apply while the physics runs")

    async def _physics(self) -> None:
        """Steps the simulation in real time and streams the world to the page, one message a
        display frame. Never behind real time without saying so: `rtf` is simulated time over
        wall time (1.0 when keeping up), `capacity` how many times real time the stepping alone
        could run; `behind` when it cannot keep up."""
        ses = self.session
        last = time.monotonic()
        due = last  # frames are due on a fixed 60 Hz clock (sleeping a frame after the work would drift below it)
        window: list[tuple[float, float, float]] = []  # (wall, simulated, stepping) per frame
        while ses.sim is not None and not self.ws.closed:
            sim = ses.sim
            now = time.monotonic()
            wall = now - last
            last = now
            stepped = busy_s = 0.0
            if self.physics_running:
                if not sim.busy:
                    if self.pending_move:
                        sim.command(self.pending_move)
                        self.pending_move = None
                    elif self.pending_grip:
                        sim.command(self.pending_grip)
                        self.pending_grip = None
                n = int(round(min(wall, 0.1) / sim.dt))
                t0 = time.monotonic()
                sim.step(n)
                busy_s = time.monotonic() - t0
                stepped = n * sim.dt
            window.append((wall, stepped, busy_s))
            window = window[-60:]
            w, st, bz = (sum(x[i] for x in window) for i in range(3))
            rtf = st / w if w > 0 else 0.0
            capacity = st / bz if bz > 0 else None
            behind = bool(self.physics_running and (wall > 0.1 or (capacity is not None and capacity < 1.0)))
            msg = ses.physics_message(rtf=rtf, behind=behind)
            msg["capacity"] = capacity
            msg["running"] = self.physics_running
            await self.send([ses.pose_message(), msg])
            due = max(due + FRAME_S, time.monotonic() - FRAME_S)
            await asyncio.sleep(max(0.0, due - time.monotonic()))

    # ---- playback of a program's time line

    def stop_tasks(self) -> None:
        if self.task and not self.task.done():
            self.task.cancel()
        self.task = None

    def _timeline(self) -> dict:
        if not self.session.timeline:
            raise BadMessage("no program loaded: send program_load first")
        return self.session.timeline

    async def play(self, msg) -> None:
        tl = self._timeline()
        if "speed" in msg:
            speed = msg["speed"]
            if isinstance(speed, bool) or not isinstance(speed, (int, float)) or not 0.05 <= speed <= 20:
                raise BadMessage("'speed' must be within 0.05 .. 20")
            self.speed = float(speed)
        self.stop_tasks()
        if self.t >= tl["duration"]:
            self.t = 0.0
        self.task = asyncio.create_task(self._play())

    async def _play(self) -> None:
        tl = self.session.timeline
        last = time.monotonic()
        await self.send([{"type": "playing", "t": self.t, "playing": True}])
        while True:
            now = time.monotonic()
            self.t = min(tl["duration"], self.t + (now - last) * self.speed)
            last = now
            await self.send([self.session.pose_at(self.t)])
            if self.t >= tl["duration"]:
                break
            await asyncio.sleep(FRAME_S)
        await self.send([{"type": "playing", "t": self.t, "playing": False, "ended": True}])

    async def pause(self, msg) -> None:
        self.stop_tasks()
        await self.send([{"type": "playing", "t": self.t, "playing": False}])

    async def step(self, msg) -> None:
        """To the end of the next action (a line)."""
        tl = self._timeline()
        self.stop_tasks()
        ends = sorted({r["end_s"] for r in tl["records"]} | {r["start_s"] for r in tl["records"]})
        nxt = next((e for e in ends if e > self.t + 1e-9), tl["duration"])
        line_end = next((r["end_s"] for r in tl["records"] if r["end_s"] > self.t + 1e-9), nxt)
        self.t = line_end
        await self.send([self.session.pose_at(self.t), {"type": "playing", "t": self.t, "playing": False}])

    async def seek(self, msg) -> None:
        tl = self._timeline()
        t = msg.get("t")
        if isinstance(t, bool) or not isinstance(t, (int, float)) or not 0 <= t <= tl["duration"] + 1e-9:
            raise BadMessage(f"'t' must be within 0 .. {tl['duration']:.3f} s")
        self.stop_tasks()
        self.t = float(t)
        await self.send([self.session.pose_at(self.t), {"type": "playing", "t": self.t, "playing": False}])

    async def rewind(self, msg) -> None:
        self._timeline()
        self.stop_tasks()
        self.t = 0.0
        await self.send([self.session.pose_at(0.0), {"type": "playing", "t": 0.0, "playing": False}])

    # ---- the Jacobian transpose, iteration by iteration

    async def jt_animate(self, msg) -> None:
        self.stop_tasks()
        steps = self.session.jt_steps(msg)  # validates now: a bad target is an error reply
        first = next(steps)
        self.task = asyncio.create_task(self._jt(first, steps, msg.get("seq")))

    async def _jt(self, first, steps, seq) -> None:
        item = first
        while True:
            res, i, done = item
            reply = self.session._ik_reply(res, seq)
            reply.update(type="jt_frame", iteration=i + 1, done=done)
            await self.send([reply, self.session.pose_message(seq=seq)])
            if done:
                return
            await asyncio.sleep(FRAME_S)
            try:
                item = next(steps)
            except StopIteration:
                return

    async def stop_animation(self, msg) -> None:
        self.stop_tasks()
        await self.send([self.session.pose_message()])
