"""articula-studio: serves Articula Studio's static site (studio/web/dist: the page, its
engine, the virtual Nano and the flasher, all of which run in the browser) on 127.0.0.1.
It holds no session and no arm: the page drives the arm itself, over Web Serial, with the
browser asking the user's permission for each port (docs/studio.md, "Security"). Its rules:

  - it binds 127.0.0.1 unless told otherwise (then it warns);
  - it answers only to its own Host names (no DNS rebinding);
  - a robot file given on the command line (and the meshes beside it) is served under a
    random token in the page's URL; the site itself is static and public, as on any web host.
"""

from __future__ import annotations

import os
import secrets
from pathlib import Path
from urllib.parse import quote

from aiohttp import web

REPO = Path(__file__).resolve().parents[3]


def shipped_robots() -> list[str]:
    d = Path(os.environ.get("ARTICULA_ROBOTS") or REPO / "robots")
    return sorted(p.stem for p in d.glob("*.json") if not p.stem.endswith(".schema"))


def web_dir() -> Path:
    """The built site: inside the installed package, or the tree's studio/web/dist."""
    packaged = Path(__file__).with_name("web")
    if (packaged / "index.html").is_file():
        return packaged
    return REPO / "studio" / "web" / "dist"


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
        self.app = web.Application()
        self.app.router.add_get("/t/{token}/files/{path:.+}", self.files)
        self.app.router.add_get("/", self.index)
        self.app.router.add_get("/{path:.+}", self.static)
        self.runner: web.AppRunner | None = None

    # ---- the rules

    def allowed_hosts(self) -> set[str]:
        names = {"127.0.0.1", "localhost", self.host}
        return {f"{n}:{self.port}" for n in names}

    def host_ok(self, request: web.Request) -> bool:
        return request.headers.get("Host", "") in self.allowed_hosts()

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
