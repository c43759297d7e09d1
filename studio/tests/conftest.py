"""The studio's tests: each starts the real server (`python -m articula.studio`, as
`articula-studio` runs) and drives the real page in Debian's headless Chromium through
Playwright (its own browser download is not needed)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
CHROMIUM = os.environ.get("ARTICULA_CHROMIUM", "/usr/bin/chromium")
SHOTS = Path(os.environ.get("ARTICULA_SCREENSHOTS") or REPO / "docs" / "img")
SHOTS.mkdir(parents=True, exist_ok=True)


class Server:
    def __init__(self, *args: str):
        self.t0 = time.time()
        self.proc = subprocess.Popen([sys.executable, "-m", "articula.studio", *args, "--no-browser"],
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=REPO,
                                     env=dict(os.environ, PYTHONPATH=str(REPO / "python")))
        self.first_line = self.proc.stdout.readline().rstrip("\n")
        m = re.fullmatch(r"studio: (http://127\.0\.0\.1:(\d+)/\?token=([\w-]+))", self.first_line)
        if not m:
            self.proc.kill()
            raise AssertionError(f"the studio's first line is not its address: {self.first_line!r} "
                                 f"{self.proc.stderr.read()}")
        self.url, self.port, self.token = m.group(1), int(m.group(2)), m.group(3)

    def stop(self) -> str:
        self.proc.terminate()
        try:
            _, err = self.proc.communicate(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            _, err = self.proc.communicate()
        return err


@pytest.fixture
def server_factory():
    servers = []

    def start(*args: str) -> Server:
        s = Server(*args)
        servers.append(s)
        return s

    yield start
    for s in servers:
        err = s.stop()
        assert "Traceback" not in err, err


@pytest.fixture(scope="session")
def browser():
    from playwright.sync_api import sync_playwright

    if not Path(CHROMIUM).exists():
        pytest.fail(f"no Chromium at {CHROMIUM}: run scripts/bootstrap (Debian's chromium)")
    with sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=CHROMIUM, headless=True,
                               args=["--no-sandbox", "--disable-background-networking", "--disable-component-update",
                                     "--disable-sync", "--no-first-run", "--disable-quic"])
        yield b
        b.close()


class Page:
    """A page of the studio with what its console said."""

    def __init__(self, browser, server: Server, width=1440, height=900, tour=False, query=""):
        self.server = server
        self.context = browser.new_context(viewport={"width": width, "height": height}, accept_downloads=True)
        if not tour:
            self.context.add_init_script("localStorage.setItem('articula.studio.tour.done', '1')")
        self.page = self.context.new_page()
        self.errors: list[str] = []
        self.page.on("console", lambda m: m.type == "error" and self.errors.append(m.text))
        self.page.on("pageerror", lambda e: self.errors.append(str(e)))
        self.page.goto(server.url + query)
        self.page.wait_for_function("window.articula && window.articula.ready && window.articula.firstFrameAt > 0",
                                    timeout=20000)

    def hook(self, expr: str):
        return self.page.evaluate(f"(() => {{ const a = window.articula; return {expr}; }})()")

    def wait(self, expr: str, timeout=15000):
        self.page.wait_for_function(f"(() => {{ const a = window.articula; return {expr}; }})()", timeout=timeout)

    def close(self):
        self.context.close()


@pytest.fixture
def open_page(browser, server_factory):
    pages = []

    def open_(robot="mk2plus", **kw) -> Page:
        p = Page(browser, server_factory(robot), **kw)
        pages.append(p)
        return p

    yield open_
    for p in pages:
        p.close()
