"""The studio's tests drive the real page in Debian's headless Chromium through Playwright (its
own browser download is not needed). The page is the static site (studio/web/dist) as a user
gets it from any web server: a plain file server (Python's http.server) serves it under a
sub-path of another name, and no articula process runs. The arm-in-the-loop tests start
articula-studio (`python -m articula.studio`), which serves the same site and connects the arm."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time
from pathlib import Path

import pytest

from engines import STATUS_LINES_JS, TOUR_DONE, answered_act, as_tested, console_error, driver_made, leave_for_the_icon

REPO = Path(__file__).resolve().parents[2]
CHROMIUM = os.environ.get("ARTICULA_CHROMIUM", "/usr/bin/chromium")
SHOTS = Path(os.environ.get("ARTICULA_SCREENSHOTS") or REPO / "docs" / "img")
SHOTS.mkdir(parents=True, exist_ok=True)
ARTICULA = REPO / "build" / "host" / "cli" / "articula"


def cli_path() -> str:
    """The articula CLI the tests compare the page with (ARTICULA_CLI: an installed one)."""
    return os.environ.get("ARTICULA_CLI") or str(ARTICULA)


def cli_json(*args: str) -> dict:
    """`articula ARGS --json`'s answer (exit 0, or 1 for a result that says no)."""
    import json

    p = subprocess.run([cli_path(), *args, "--json"], capture_output=True, text=True, cwd=REPO, timeout=60)
    assert p.returncode in (0, 1), p.stderr
    return json.loads(p.stdout)
# A browser that died under a test (WebKitGTK's web process once segfaulted in Mesa's software
# renderer, swrast_dri.so, in its compositor thread: the kernel's log said so, and WebDriver
# then answered "invalid session id") is no verdict on the page: such a test runs once more in
# a new browser, and the run says so. Only that error: a failed assertion never runs again.
BROWSER_GONE = ("invalid session id", "invalidsessionidexception")


def _browser_died(reports) -> bool:
    return any(r.failed and any(s in str(r.longrepr).lower() for s in BROWSER_GONE) for r in reports)


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_protocol(item, nextitem):
    from _pytest.runner import runtestprotocol

    item.ihook.pytest_runtest_logstart(nodeid=item.nodeid, location=item.location)
    reports = runtestprotocol(item, nextitem=nextitem, log=False)
    if _browser_died(reports):
        tr = item.config.pluginmanager.get_plugin("terminalreporter")
        if tr:
            tr.write_line(f"\n{item.nodeid}: the browser died under the test (WebDriver: invalid session id); "
                          "running it once more in a new browser", yellow=True)
        item._initrequest()
        reports = runtestprotocol(item, nextitem=nextitem, log=False)
    for r in reports:
        item.ihook.pytest_runtest_logreport(report=r)
    item.ihook.pytest_runtest_logfinish(nodeid=item.nodeid, location=item.location)
    return True


DIST = REPO / "studio" / "web" / "dist"
# The page's simulated world (the live physics and the virtual Nano) at four times real time, as
# the Speed beside Run (or ?speed=4 in a link) gives a student: for the tests whose long runs check
# where the arm and the ink end, not how long that takes. The others run it in real time (and
# test_studio.py checks that the virtual Nano keeps it).
FAST = "&speed=4"
# A wait's timeout guards against a hang; it is not a speed check. Every wait gets this many
# times what it names, so that a busy machine (two test jobs on two cores) still passes.
PATIENCE = float(os.environ.get("ARTICULA_TEST_PATIENCE", "4"))


def wait_with_progress(page, done: str, progress: str, still: float, what: str) -> None:
    """Until `done` (an expression in the Playwright page) holds, for as long as `progress` (an
    expression) keeps changing: the budget, `still` seconds times PATIENCE, starts again at each
    change, so a long job on a slow or busy machine passes while a stalled one fails soon,
    saying where it stood."""
    budget = still * PATIENCE
    last, since = None, time.monotonic()
    while True:
        is_done, now_at = page.evaluate(f"() => [!!({done}), JSON.stringify({progress})]")
        if is_done:
            return
        if now_at != last:
            last, since = now_at, time.monotonic()
        elif time.monotonic() - since > budget:
            raise AssertionError(f"{what} did not happen: no progress for {budget:.0f} s (it stood at {last})")
        time.sleep(0.25)


class StaticSite:
    """The built site behind a plain static file server, at /<subpath>/ (not /dist/)."""

    def __init__(self, root: Path, subpath: str = "articula-site", dist: Path = DIST):
        if not (dist / "index.html").is_file():
            raise AssertionError(f"the studio's site is not built ({dist}): run make")
        root.mkdir(parents=True, exist_ok=True)
        (root / subpath).symlink_to(dist, target_is_directory=True)
        self.proc = subprocess.Popen([sys.executable, "-u", "-m", "http.server", "0", "--bind", "127.0.0.1",
                                      "--directory", str(root)],
                                     # its request log goes nowhere: a pipe nobody reads fills
                                     # up (64 KB) and the server stops answering
                                     stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        line = self.proc.stdout.readline()
        m = re.search(r"port (\d+)", line)
        if not m:
            self.proc.kill()
            raise AssertionError(f"http.server did not say its port: {line!r}")
        self.port = int(m.group(1))
        self.url = f"http://127.0.0.1:{self.port}/{subpath}/"

    def stop(self) -> None:
        self.proc.terminate()
        try:
            self.proc.communicate(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()


@pytest.fixture(scope="session")
def site(tmp_path_factory):
    s = StaticSite(tmp_path_factory.mktemp("www"))
    yield s
    s.stop()


class Server:
    def __init__(self, *args: str):
        self.t0 = time.time()
        self.proc = subprocess.Popen([sys.executable, "-m", "articula.studio", *args, "--no-browser"],
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=REPO,
                                     env=dict(os.environ, PYTHONPATH=str(REPO / "python")))
        self.first_line = self.proc.stdout.readline().rstrip("\n")
        m = re.fullmatch(r"studio: (http://127\.0\.0\.1:(\d+)/\?token=([\w-]+)&robot=[^&\s]+(&scene=[\w-]+)?)",
                         self.first_line)
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
def playwright():
    """One Playwright for the session (its sync API allows one at a time)."""
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        yield pw


@pytest.fixture(scope="session")
def browser(playwright):
    if not Path(CHROMIUM).exists():
        pytest.fail(f"no Chromium at {CHROMIUM}: run scripts/bootstrap (Debian's chromium)")
    b = playwright.chromium.launch(executable_path=CHROMIUM, headless=True,
                                  args=["--no-sandbox", "--disable-background-networking", "--disable-component-update",
                                        "--disable-sync", "--no-first-run", "--disable-quic"])
    yield b
    b.close()


class PagePool:
    """Pages kept between tests. Opening a page in a new browser context costs about 2.4 CPU
    seconds (a new renderer process, the engine's WebAssembly compiled again); loading the studio
    again in a page that had it costs about 1.2. So a test's page, once the test passed, is
    parked: it leaves the studio for the site's icon, empties its origin's storage there (local,
    session, IndexedDB) and waits for the next test that asks for a page of the same shape. A page
    with its own init script, the tour, the service worker or no CSP always starts new, and so
    does every page after a failed test."""

    def __init__(self):
        self.idle: dict[tuple, list] = {}
        self.opened = 0
        self.reused = 0

    def take(self, key):
        kept = self.idle.get(key)
        while key is not None and kept:
            context, page = kept.pop()
            try:  # (a parked page can die while it waits: its renderer gone beside a failed test's)
                if not page.is_closed():
                    page.evaluate("1")
                    self.reused += 1
                    return context, page
            except Exception:
                pass
            try:
                context.close()
            except Exception:
                pass
        self.opened += 1
        return None

    def park(self, key, context, page) -> bool:
        try:
            context.set_offline(False)
            context.clear_permissions()
            page.unroute_all(behavior="ignoreErrors")
            left = leave_for_the_icon(context, page)  # (engines.py, as its parked pages)
            if left:
                raise RuntimeError(f"{left} stores left")
        except Exception:  # a page that cannot be cleaned is not kept
            context.close()
            return False
        self.idle.setdefault(key, []).append((context, page))
        return True


POOL = PagePool()


class Page:
    """A page of the studio (from the static site, or from articula-studio when `server` is
    given) with what its console said."""

    def __init__(self, browser, server_or_url, width=1600, height=900, tour=False, query="", init_script="",
                 touch=False, ready="window.articula.firstFrameAt > 0", bypass_csp=False, service_worker=False):
        self.server = server_or_url if isinstance(server_or_url, Server) else None
        url = server_or_url.url if self.server else server_or_url
        plain = not (tour or init_script or bypass_csp or service_worker)
        self.key = (id(browser), width, height, touch) if plain else None
        self.kept = True  # parked when closed, unless a test failed with it
        self.closed = False
        parked = POOL.take(self.key)
        if parked:
            self.context, self.page = parked
            self.page.set_viewport_size({"width": width, "height": height})
        else:
            # touch: a tablet or a phone (touch events, a coarse pointer, the page at the device's width)
            self.context = browser.new_context(viewport={"width": width, "height": height}, accept_downloads=True,
                                               bypass_csp=bypass_csp,
                                               **({"has_touch": True, "is_mobile": True} if touch else {}))
            if not tour:
                self.context.add_init_script(TOUR_DONE)
            if init_script:
                self.context.add_init_script(init_script)
            self.context.set_default_timeout(30000 * PATIENCE)
            self.page = self.context.new_page()
        self.errors: list[str] = []
        self.listening = {"console": lambda m: (e := console_error(m)) and self.errors.append(e),
                          "pageerror": lambda e: self.errors.append(str(e))}
        for event, f in self.listening.items():
            self.page.on(event, f)
        self.page.goto(as_tested(url + query, service_worker))
        try:
            self.page.wait_for_function(f"() => window.articula && window.articula.ready && {ready}", timeout=20000 * PATIENCE)
        except Exception as e:
            raise AssertionError(f"the page ({url + query}, {'a parked page' if parked else 'a new page'}) never "
                                 f"became ready ({ready}): {e}\nthe page: {self.state()}\nits console: {self.errors}") from None

    def state(self):
        """What the page was doing, for a failure: its history, the engine's unanswered requests,
        its errors, its robot and project, what its status lines say."""
        try:
            return self.page.evaluate("() => { const a = window.articula; if (!a) return 'no window.articula'; "
                                      "return { ready: a.ready, firstFrameAt: a.firstFrameAt, history: a.history, "
                                      "engine: a.engineWaiting && a.engineWaiting(), errors: a.pageErrors, "
                                      "robot: a.robot && a.robot.name, project: a.project && a.project.name, said: "
                                      + STATUS_LINES_JS + " }; }")
        except Exception as e2:  # the page is gone
            return f"(no page: {e2})"

    # Predicates go to the page as functions: the site's Content-Security-Policy forbids
    # evaluating a bare expression string in it (eval), as it would any script not its own.
    def hook(self, expr: str):
        return self.page.evaluate(f"() => {{ const a = window.articula; return {expr}; }}")

    def wait(self, expr: str, timeout=15000):
        """Until `expr` holds; else fails with what the page was doing (its history, the engine's
        unanswered requests, its errors), to tell a slow machine from a stuck page."""
        try:
            self.page.wait_for_function(f"() => {{ const a = window.articula; return {expr}; }}", timeout=timeout * PATIENCE)
        except Exception as e:
            raise AssertionError(f"{expr} did not happen: {e}\nthe page: {self.state()}") from None

    def tap_answered(self, selector: str, answered: str, within: float = 30.0, tries: int = 3) -> list:
        """A finger's tap on `selector` until the page answers (engines.answered_act): a tap the
        browser lost (on a busy machine) is told and made again, as a student taps again."""
        return answered_act(lambda: self.page.tap(selector), self.hook, selector, answered, "a tap", within, tries)

    def csp_refusals(self) -> list[str]:
        """What the site's Content-Security-Policy refused in this page: the page's own record
        (hook.pageErrors) and the console's."""
        try:
            kept = [e for e in self.page.evaluate("() => window.articula ? window.articula.pageErrors : []")
                    if "Content-Security-Policy" in e and not driver_made(e)]
        except Exception:  # the page is gone
            kept = []
        said = [e for e in self.errors if "Content Security Policy" in e or "Content-Security-Policy" in e]
        return kept + said

    def close(self, csp_refusals_expected=False):
        """Closes the page; fails if the Content-Security-Policy refused anything (the page
        writes no inline style or script: a refusal is a broken feature in some engine). A page
        closed while an exception is on its way (a test's `finally` after a failure) is not
        parked. Closing it again does nothing (a test's own `finally` and the fixture both close it:
        parked twice, one page would be handed to two tests)."""
        if self.closed:
            return
        self.closed = True
        if sys.exc_info()[0] is not None:
            self.kept = False
        refused = [] if csp_refusals_expected or self.context is None else self.csp_refusals()
        for event, f in self.listening.items():
            self.page.remove_listener(event, f)
        if not (self.key is not None and self.kept and not refused and POOL.park(self.key, self.context, self.page)):
            self.context.close()
        assert not refused, f"the page's Content-Security-Policy refused: {refused}"


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item, call):
    report = yield
    if report.when == "call":
        item.test_failed = report.failed
    return report


def pytest_terminal_summary(terminalreporter, config):
    opened, reused = POOL.opened, POOL.reused
    if hasattr(config, "engine_pages"):  # test_engines.py's Engines
        opened, reused = opened + config.engine_pages[0], reused + config.engine_pages[1]
    if opened or reused:
        terminalreporter.write_line(f"pages: {opened} opened new, {reused} were a passed test's page, "
                                    "parked (conftest.PagePool, engines.Engines)")


def _close_all(request, pages):
    """The pages a test opened: closed, or parked for the next test if it passed."""
    failed = getattr(request.node, "test_failed", True)
    for p in pages:
        p.kept = p.kept and not failed
        p.close()


@pytest.fixture
def open_page(request, browser, site):
    """The static site with a robot (and a scene: query="&scene=push")."""
    pages = []

    def open_(robot="mk2plus", query="", **kw) -> Page:
        p = Page(browser, f"{site.url}?robot={robot}{query}", **kw)
        pages.append(p)
        return p

    yield open_
    _close_all(request, pages)


@pytest.fixture
def open_served_page(request, browser, server_factory):
    """The site from articula-studio, which connects the arm (the virtual Nano, a serial port)."""
    pages = []

    def open_(robot="mk2plus", **kw) -> Page:
        p = Page(browser, server_factory(robot), **kw)
        pages.append(p)
        return p

    yield open_
    _close_all(request, pages)
