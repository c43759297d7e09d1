"""The page in each browser engine a class has, behind one small driver: Chromium and Firefox
through Playwright, WebKit (Safari's engine, as WebKitGTK's MiniBrowser) through Selenium's
WebDriver. Debian's own browsers (scripts/bootstrap installs them); Firefox and WebKit draw
WebGL only with an X display, so they get a virtual one (Xvfb) for the session.
../shared/notes/browsers.md (in the team's notes) says how each was made to work."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import time
from pathlib import Path
from urllib.parse import urljoin, urlparse

# The view drawn at low resolution (?quality=low) when the screenshots go elsewhere than docs/img
# (make test: the build tree): Chromium draws WebGL in software here (SwiftShader), and a frame
# at the page's own quality costs four times the CPU time. The screenshots for the docs
# (docs/img: ARTICULA_SCREENSHOTS unset or naming it) are taken at the page's own quality. An address that names
# its quality keeps it (the first `quality` wins). And at most 5 frames a second (?fps=5): the
# tests look at where the arm and the ink end, not at the motion, and the last pose is always
# drawn (bench/ measures the frame rates).
_SHOTS = os.environ.get("ARTICULA_SCREENSHOTS")
LOW = "&quality=low&fps=5" if _SHOTS and Path(_SHOTS).resolve() != Path(__file__).resolve().parents[2] / "docs" / "img" else ""

# Every status line the page shows ("id: text"): what a panel said last (a refusal included).
STATUS_LINES_JS = ("[...document.querySelectorAll('.status')].map((e) => e.id + ': ' + e.textContent)"
                   ".filter((t) => !t.endsWith(': '))")


def answered_act(act, hook, selector: str, answered: str, what: str, within: float = 30.0, tries: int = 3) -> list:
    """`act()` (a click or a tap on `selector`) until the page answers: `answered`, a hook
    expression, turns true within `within` s of it. Each act that got no answer is told on
    stderr with what was at the element's centre, whether it was disabled and what had the
    focus; after `tries` of them, a failure with all of that. Returns those told. (On a busy
    machine a click on the Draw button was lost in WebKit, and a tap in Chromium's tablet
    emulation: CIs of stops 46 and 47, and stop 48's; the page said nothing, nothing ran.)"""
    import sys

    where_js = ("(() => { const e = document.querySelector(" + json.dumps(selector) + "); if (!e) return 'no such element';"
                "const r = e.getBoundingClientRect(), t = document.elementFromPoint(r.left + r.width / 2, r.top + r.height / 2);"
                "return { box: [r.left, r.top, r.width, r.height].map(Math.round), view: [innerWidth, innerHeight],"
                " disabled: !!e.disabled, atCentre: t ? (t.id || t.tagName) + (t.className ? '.' + String(t.className).split(' ')[0] : '') : null,"
                " focus: document.activeElement && (document.activeElement.id || document.activeElement.tagName) }; })()")
    lost = []
    for attempt in range(tries):
        act()
        end = time.monotonic() + within
        while time.monotonic() < end:
            if hook(f"!!({answered})"):
                return lost
            time.sleep(0.1)
        lost.append(hook(where_js))
        print(f"{what} on {selector} got no answer within {within:.0f} s ({attempt + 1} of {tries}): {lost[-1]}",
              file=sys.stderr)
    raise AssertionError(f"{what}: {tries} on {selector} got no answer ({answered}); at each: {lost}; "
                         f"said: {hook(STATUS_LINES_JS)}")


def as_tested(url: str, service_worker: bool = False) -> str:
    """`url` with LOW among its query's parameters (before a #project=... link's fragment), and,
    unless the test is of the service worker, without it (?nosw): in a new browser profile it
    would fetch and keep every file of the site for offline use, about a CPU second of each
    page a test opens (test_studio.py tests the site offline)."""
    extra = LOW + ("" if service_worker else "&nosw")
    if not extra:
        return url
    base, hash_, fragment = url.partition("#")
    return base + (extra if "?" in base else "?" + extra[1:]) + hash_ + fragment

# What a parked page runs on the site's icon (its own origin, with no studio running): the
# origin's storage emptied, so that the next test's page starts as a new tab's would. Gives what
# is left (0). A promise: Playwright awaits it; WebDriver's async script passes its callback last.
EMPTY_STORAGE = """async () => {
    localStorage.clear();
    sessionStorage.clear();
    const dbs = indexedDB.databases ? await indexedDB.databases() : [];
    await Promise.all(dbs.map((d) => new Promise((done) => {
        const q = indexedDB.deleteDatabase(d.name);
        q.onsuccess = q.onerror = q.onblocked = () => done();
    })));
    return localStorage.length + sessionStorage.length + (indexedDB.databases ? (await indexedDB.databases()).length : 0);
}"""


def console_error(m) -> str | None:
    """A Playwright console message as a test keeps it: an error, with the resource a failed
    load names; None for anything else, and for the 404 of /favicon.ico, which the browser asks
    for on its own when a parked page shows the site's icon (the studio names its icon): it can
    arrive after the next test took the page."""
    if m.type != "error":
        return None
    url = (m.location or {}).get("url", "")
    if m.text.startswith("Failed to load resource"):
        if urlparse(url).path == "/favicon.ico":
            return None
        return f"{m.text}: {url}"
    return m.text


def leave_for_the_icon(context, page) -> int:
    """A Playwright page parked: the tabs a test opened beside it closed, the page at the
    site's icon (same origin, no studio running), the origin's storage emptied there. Returns
    how many stores are left (0 when it is clean)."""
    for other in context.pages:
        if other != page:
            other.close()
    if not page.url.startswith("http"):
        raise RuntimeError(f"the page is at {page.url}")
    page.goto(urljoin(page.url, "icon.svg"))
    return page.evaluate(EMPTY_STORAGE)


TOUR_DONE = "try { localStorage.setItem('articula.studio.tour.done', '1') } catch (e) {}"

CHROMIUM = os.environ.get("ARTICULA_CHROMIUM", "/usr/bin/chromium")
FIREFOX = os.environ.get("ARTICULA_FIREFOX", "/usr/bin/firefox-esr")
MINIBROWSER = os.environ.get("ARTICULA_MINIBROWSER", "/usr/lib/x86_64-linux-gnu/webkit2gtk-4.1/MiniBrowser")
WEBKIT_DRIVER = shutil.which("WebKitWebDriver") or "/usr/bin/WebKitWebDriver"
ENGINES = ("chromium", "firefox", "webkit")


def missing(engine: str) -> str | None:
    """What this machine lacks to run `engine`, or None."""
    need = {"chromium": [CHROMIUM], "firefox": [FIREFOX, shutil.which("Xvfb") or "/usr/bin/Xvfb"],
            "webkit": [MINIBROWSER, WEBKIT_DRIVER, shutil.which("Xvfb") or "/usr/bin/Xvfb"]}[engine]
    gone = [p for p in need if not Path(p).exists()]
    return f"{engine} needs {', '.join(gone)}: run scripts/bootstrap" if gone else None


class VirtualDisplay:
    """An X server in memory (Xvfb) on a display number it picks itself."""

    def __init__(self, size="1920x1200x24"):
        r, w = os.pipe()
        self.proc = subprocess.Popen(["Xvfb", "-displayfd", str(w), "-screen", "0", size, "-nolisten", "tcp"],
                                     pass_fds=(w,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(w)
        with os.fdopen(r) as f:
            number = f.readline().strip()
        if not number:
            self.proc.kill()
            raise RuntimeError("Xvfb did not start")
        self.display = f":{number}"

    def stop(self):
        self.proc.terminate()
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()


# The hook's value of an expression; `a` is window.articula. A function, not a string to
# evaluate: the site's Content-Security-Policy forbids eval.
def _fn(expr: str) -> str:
    return f"() => {{ const a = window.articula; return {expr}; }}"


def driver_made(refusal: str) -> bool:
    """A refusal of code the test's driver evaluated, not the page's: Firefox names such code's
    source "<page> line N > eval" (Playwright's screenshot there adds a <style> of its own).
    The page's own code cannot eval: its policy has no 'unsafe-eval'."""
    return "> eval" in refusal or "%3E%20eval" in refusal


class EnginePage:
    """The studio in one engine: the operations the cross-engine tests need, the same in each."""

    engine = ""

    def hook(self, expr: str):
        raise NotImplementedError

    def wait(self, expr: str, timeout: float = 60.0, what: str = ""):
        """Polls the hook until `expr` is true; `timeout` guards against a hang. A failure says
        what the page was doing: its errors, the engine's unanswered requests, its history, and
        every status line (a refusal in a panel is said there)."""
        end = time.monotonic() + timeout
        while True:
            try:
                if self.hook(f"!!({expr})"):
                    return
            except Exception as e:  # the page is still starting: the hook may not exist yet
                last = e
            else:
                last = None
            if time.monotonic() > end:
                errors = self.page_errors()
                try:  # what the page still waits for from its engine, if anything, and its history
                    waiting = self.hook("a.engineWaiting()")
                    history = self.hook("[a.history, a.project && a.project.dirty, a.blocksPending]")
                    said = self.hook(STATUS_LINES_JS)
                except Exception:
                    waiting = history = said = "?"
                raise AssertionError(f"{self.engine}: {what or expr} did not happen within {timeout:.0f} s"
                                     f"{f' ({last})' if last else ''}; the page's errors: {errors}; "
                                     f"the engine's unanswered requests: {waiting}; [history, dirty, blocks "
                                     f"pending]: {history}; said: {said}")
            time.sleep(0.1)

    def click_answered(self, selector: str, answered: str, within: float = 30.0, tries: int = 3) -> list:
        """Clicks `selector` until the page answers (answered_act). On a busy machine WebKit's
        WebDriver has lost a click on the Draw button (nothing ran; the panel said nothing: the CIs
        of stop 47)."""
        return answered_act(lambda: self.click(selector), self.hook, selector, answered, f"{self.engine}: a click",
                            within, tries)

    def wait_on_nano(self, expr: str, nano_seconds: float, what: str, progress: str = "null", still: float = 60.0,
                     wall: float = 1200.0):
        """Until `expr` holds while the virtual Nano runs a program, its budget counted in the
        Nano's own clock (`a.arm.nano.seconds`, emulated time), not the test's: on a busy machine
        the page's worker emulates slower than real time. The budget is for a stall: it starts
        again whenever `progress` (an expression) changes, since the page's sender, on the busy
        machine's main thread, can also fall behind the Nano, and a Nano running faster than real
        time then waits many of its own seconds for each line. Fails when the Nano has run
        `nano_seconds` without `expr` or progress (a fault), when its clock stands `still` seconds
        (the worker stopped), or after `wall` seconds whatever happens. Returns (Nano s, wall s)."""
        clock = "(a.arm.nano ? a.arm.nano.seconds : null)"
        t0 = time.monotonic()
        n0 = since = None
        last_n, moved, last_p = None, t0, None
        while True:
            done, n, p = self.hook(f"[!!({expr}), {clock}, JSON.stringify({progress})]")
            now = time.monotonic()
            if n0 is None:
                n0 = since = n
            if done:
                return ((n or 0) - (n0 or 0), now - t0)
            if n != last_n:
                last_n, moved = n, now
            if p != last_p:
                last_p, since = p, n
            why = None
            if n is not None and since is not None and n - since > nano_seconds:
                why = (f"the Nano ran {n - since:.1f} s of its own time with no progress ({progress} stayed {p}; "
                       f"budget {nano_seconds:.0f} s, {n - n0:.1f} s in all)")
            elif now - moved > still:
                why = f"the Nano's clock stood still for {now - moved:.0f} s (at {n} s)"
            elif now - t0 > wall:
                why = f"{now - t0:.0f} s went by (the Nano ran {(n or 0) - (n0 or 0):.1f} s)"
            if why:
                arm = self.hook("JSON.stringify(a.arm).slice(0, 3000)")
                raise AssertionError(f"{self.engine}: {what} did not happen: {why}; the page's errors: "
                                     f"{self.page_errors()}; the engine's unanswered requests: "
                                     f"{self.hook('a.engineWaiting()')}; the arm: {arm}")
            time.sleep(0.2)

    def run(self, script: str):
        """Statements in the page (a function's body: `return` gives a value back)."""
        raise NotImplementedError

    def open_file(self, selector: str, name: str, text: str):
        """A file chosen in the file input `selector`, as the page gets one from its dialog:
        its files set, then its change event (no engine's driver opens the dialog itself)."""
        self.run(f"const f = new File([{json.dumps(text)}], {json.dumps(name)}); const d = new DataTransfer(); "
                 f"d.items.add(f); const e = document.querySelector({json.dumps(selector)}); e.files = d.files; "
                 "e.dispatchEvent(new Event('change', { bubbles: true }));")

    def type_boxes(self, typed: list[tuple[str, str]]):
        """Each text into its box, one box after the other with no pause at all: the box given
        the keyboard, all selected, the text typed key by key, then Tab."""
        raise NotImplementedError

    def rect(self, script: str) -> list[float] | None:
        """The viewport rectangle [x, y, width, height] of the element `script` returns (a
        function's body), once it has stopped moving (a dropped block slides as it snaps)."""
        last, same = None, 0
        end = time.monotonic() + 10
        while time.monotonic() < end:
            r = self.run(f"const e = (() => {{ {script} }})(); if (!e) return null; const r = e.getBoundingClientRect(); "
                         "return [r.x, r.y, r.width, r.height];")
            same = same + 1 if r is not None and r == last else 0
            last = r
            if same >= 3:
                return r
            time.sleep(0.05)
        return last

    # A person's mouse and keyboard, in viewport pixels (each engine's own input).
    def drag(self, x0: float, y0: float, x1: float, y1: float):
        raise NotImplementedError

    def mouse_click(self, x: float, y: float):
        raise NotImplementedError

    def keys(self, text: str, select_all=False, enter=False):
        raise NotImplementedError

    def shortcut(self, combo: str):
        """A key with modifiers held, as Playwright writes it: "Control+Shift+Z"."""
        raise NotImplementedError

    def reload(self):
        raise NotImplementedError

    def page_errors(self) -> list[str]:
        try:
            return [e for e in self.hook("a.pageErrors.concat(a.internalErrors)") if not driver_made(e)]
        except Exception as e:
            return [f"(no hook: {e})"]

    def csp_refusals(self) -> list[str]:
        """What the site's Content-Security-Policy refused in this page (the page keeps each
        refusal in hook.pageErrors: WebKit's driver shows no console)."""
        try:
            return [e for e in self.hook("a.pageErrors") if "Content-Security-Policy" in e and not driver_made(e)]
        except Exception:
            return []

    def close(self, keep: Engines | None = None):
        """Closes the page; fails if the Content-Security-Policy refused anything. `keep`: the
        Engines that park it for the next test instead (its test passed), as conftest.PagePool
        does in Chromium; a page that cannot be emptied is closed."""
        refused = self.csp_refusals()
        if not (keep is not None and not refused and self._park()):
            self._close()
        elif keep is not None:
            keep.idle.setdefault(self.engine, []).append(self)
        assert not refused, f"{self.engine}: the page's Content-Security-Policy refused: {refused}"

    def _park(self) -> bool:
        try:
            return self._empty() == 0
        except Exception:
            return False


class PlaywrightPage(EnginePage):
    def __init__(self, browser, engine: str, url: str, width: int, height: int):
        self.engine = engine
        self.context = browser.new_context(viewport={"width": width, "height": height})
        self.context.add_init_script(TOUR_DONE)
        self.page = self.context.new_page()
        self.console: list[str] = []
        self.page.on("console", lambda m: (e := console_error(m)) and self.console.append(e))
        self.page.on("pageerror", lambda e: self.console.append(str(e)))
        self.page.goto(url)

    def reopen(self, url: str, width: int, height: int):
        """A parked page with the studio at `url` (Engines.open)."""
        self.console.clear()
        self.page.set_viewport_size({"width": width, "height": height})
        self.page.goto(url)

    def _url(self) -> str:
        return self.page.url

    def _empty(self) -> int:
        return leave_for_the_icon(self.context, self.page)

    def hook(self, expr):
        return self.page.evaluate(_fn(expr))

    def run(self, script):
        return self.page.evaluate(f"() => {{ {script} }}")

    def type_into(self, selector, text, enter=False):
        # as a person types: Firefox over BiDi sends no input event for fill() on a number
        self.page.click(selector)
        self.page.keyboard.press("Control+a")
        self.page.keyboard.type(text)
        if enter:
            self.page.keyboard.press("Enter")
        else:
            self.page.keyboard.press("Tab")

    def type_boxes(self, typed):
        for selector, text in typed:
            self.page.focus(selector)
            self.page.keyboard.press("Control+a")
            self.page.keyboard.type(text)
            self.page.keyboard.press("Tab")

    def set_text(self, selector, text):
        self.page.fill(selector, text)

    def click(self, selector):
        self.page.click(selector)

    def select(self, selector, value):
        self.page.select_option(selector, value)

    def screenshot(self, path):
        self.page.screenshot(path=str(path))

    def drag(self, x0, y0, x1, y1):
        m = self.page.mouse
        m.move(x0, y0)
        m.down()
        m.move(x0 + 30, y0 + 20, steps=4)
        m.move(x1, y1, steps=8)
        m.up()

    def mouse_click(self, x, y):
        self.page.mouse.click(x, y)

    def keys(self, text, select_all=False, enter=False):
        if select_all:
            self.page.keyboard.press("Control+a")
        self.page.keyboard.type(text)
        if enter:
            self.page.keyboard.press("Enter")

    def shortcut(self, combo):
        self.page.keyboard.press(combo)

    def reload(self):
        self.page.reload()

    def _close(self):
        self.context.close()


class WebKitPage(EnginePage):
    """MiniBrowser under WebKitWebDriver. Selenium gives no console: the hook's pageErrors."""

    def __init__(self, display: str, url: str, width: int, height: int):
        from selenium import webdriver

        self.engine = "webkit"
        opts = webdriver.WebKitGTKOptions()
        opts.binary_location = MINIBROWSER
        opts.add_argument("--automation")
        # WebKitGTK takes navigator.language from LANG: a machine's C.UTF-8 gives "C", which the
        # page survives (test_access.py); here the tests run as an English-speaking user would
        env = dict(os.environ, DISPLAY=display, LANG="en_US.UTF-8", LC_ALL="en_US.UTF-8")
        service = webdriver.WebKitGTKService(executable_path=WEBKIT_DRIVER, env=env)
        self.driver = webdriver.WebKitGTK(options=opts, service=service)
        self.driver.set_script_timeout(60)
        self.driver.set_page_load_timeout(60)
        self.driver.set_window_size(width, height)
        self.driver.get(url.split("#")[0].split("?")[0] + "icon.svg")  # the site's origin, to set the tour aside
        self.driver.execute_script(TOUR_DONE)
        self.driver.get(url)

    def reopen(self, url: str, width: int, height: int):
        """A parked page with the studio at `url` (Engines.open): its origin emptied on the icon
        by _park, the tour set aside there again."""
        self.driver.set_window_size(width, height)
        self.driver.get(url)

    def _url(self) -> str:
        return self.driver.current_url

    def _empty(self) -> int:
        url = self._url()
        if not url.startswith("http"):
            raise RuntimeError(f"the page is at {url}")
        self.driver.get(urljoin(url, "icon.svg"))
        left = self.driver.execute_async_script(f"const done = arguments[arguments.length - 1]; ({EMPTY_STORAGE})().then(done);")
        self.driver.execute_script(TOUR_DONE)  # as __init__ does: WebDriver has no init script
        return left

    def hook(self, expr):
        return self.driver.execute_script(f"const a = window.articula; return {expr};")

    def run(self, script):
        return self.driver.execute_script(script)

    def _el(self, selector):
        return self.driver.find_element("css selector", selector)

    def type_into(self, selector, text, enter=False):
        from selenium.webdriver.common.keys import Keys

        # (clicked as `click` does: again while the layout still settles on a busy machine)
        self._interact(selector, lambda e: e.click())
        self._interact(selector, lambda e: (e.send_keys(Keys.CONTROL, "a"), e.send_keys(text),
                                            e.send_keys(Keys.ENTER if enter else Keys.TAB)))

    def type_boxes(self, typed):
        from selenium.webdriver.common.keys import Keys

        for selector, text in typed:
            self.driver.execute_script("document.querySelector(arguments[0]).focus()", selector)
            chain, _ = self._pointer()
            chain.key_down(Keys.CONTROL).send_keys("a").key_up(Keys.CONTROL).send_keys(text).send_keys(Keys.TAB)
            chain.perform()

    def set_text(self, selector, text):
        # a textarea's whole text at once, with the input event a person's typing gives
        self.driver.execute_script("const e = document.querySelector(arguments[0]); e.value = arguments[1]; "
                                   "e.dispatchEvent(new Event('input', { bubbles: true }));", selector, text)

    def _interact(self, selector, act, within=20.0):
        """`act(element)`, again while WebDriver says the element cannot be interacted with
        yet (a dialog just opened, a layout still settling on a busy machine)."""
        from selenium.common.exceptions import ElementNotInteractableException, StaleElementReferenceException

        end = time.monotonic() + within
        while True:
            try:
                return act(self._el(selector))
            except (ElementNotInteractableException, StaleElementReferenceException) as e:
                if time.monotonic() > end:  # what WebDriver could not reach, and what is there instead
                    raise AssertionError(f"{self.engine}: {selector} cannot be reached: {type(e).__name__}; "
                                         f"the page: {self._where(selector)}") from e
                time.sleep(0.2)
                # a panel that grew or a bar that drew over it since: the element to its scroller's centre
                self.driver.execute_script("const e = document.querySelector(arguments[0]);"
                                           "if (e) e.scrollIntoView({ block: 'center' });", selector)

    def _where(self, selector):
        """The element's box, whether it or a parent is hidden, what is at its centre, the layout."""
        try:
            return self.driver.execute_script(
                "const e = document.querySelector(arguments[0]); if (!e) return 'no such element';"
                "const r = e.getBoundingClientRect(), x = r.left + r.width / 2, y = r.top + r.height / 2;"
                "const top = document.elementFromPoint(x, y); const hid = e.closest('[hidden]');"
                "return { box: [r.left, r.top, r.width, r.height].map(Math.round), view: [innerWidth, innerHeight],"
                " hiddenBy: hid ? (hid.id || hid.tagName) : '', display: getComputedStyle(e).display,"
                " atCentre: top ? (top.id || top.tagName) + (top.className ? '.' + String(top.className).split(' ')[0] : '') : null,"
                " layout: window.articula && window.articula.layout };", selector)
        except Exception as e2:  # the page is gone
            return f"(no page: {e2})"

    def click(self, selector):
        self._interact(selector, lambda e: e.click())

    def select(self, selector, value):
        from selenium.webdriver.support.ui import Select

        self._interact(selector, lambda e: Select(e).select_by_value(value))

    def _pointer(self):
        from selenium.webdriver.common.action_chains import ActionChains
        from selenium.webdriver.common.actions.action_builder import ActionBuilder

        chain = ActionChains(self.driver)
        return chain, ActionBuilder(self.driver)

    def drag(self, x0, y0, x1, y1):
        _, b = self._pointer()
        p = b.pointer_action
        p.move_to_location(int(x0), int(y0)).pointer_down()
        for i in range(1, 9):
            p.move_to_location(int(x0 + (x1 - x0) * i / 8), int(y0 + (y1 - y0) * i / 8 + (10 if i < 8 else 0)))
        p.pointer_up()
        b.perform()

    def mouse_click(self, x, y):
        _, b = self._pointer()
        b.pointer_action.move_to_location(int(x), int(y)).click()
        b.perform()

    def keys(self, text, select_all=False, enter=False):
        from selenium.webdriver.common.keys import Keys

        chain, _ = self._pointer()
        if select_all:
            chain.key_down(Keys.CONTROL).send_keys("a").key_up(Keys.CONTROL)
        chain.send_keys(text)
        if enter:
            chain.send_keys(Keys.ENTER)
        chain.perform()

    def shortcut(self, combo):
        from selenium.webdriver.common.keys import Keys

        *mods, key = combo.split("+")
        held = [{"Control": Keys.CONTROL, "Shift": Keys.SHIFT, "Alt": Keys.ALT, "Meta": Keys.META}[m] for m in mods]
        chain, _ = self._pointer()
        for m in held:
            chain.key_down(m)
        chain.send_keys(key.lower())
        for m in reversed(held):
            chain.key_up(m)
        chain.perform()

    def reload(self):
        self.driver.refresh()

    def screenshot(self, path):
        # two animation frames first, or WebKitGTK shows a stale frame
        self.driver.execute_async_script("const done = arguments[0]; requestAnimationFrame(() => requestAnimationFrame(done));")
        self.driver.save_screenshot(str(path))

    def _close(self):
        self.driver.quit()


class Engines:
    """The browsers of a test session: each started once, on first use."""

    def __init__(self, playwright=None):
        """`playwright`: the session's Playwright (its sync API runs one at a time), else its own."""
        self.display: VirtualDisplay | None = None
        self.pw = playwright
        self.own_pw = playwright is None
        self.browsers = {}
        self.idle: dict[str, list[EnginePage]] = {}  # pages of passed tests, by engine (EnginePage.close)
        self.opened = self.reused = 0

    def _x(self) -> str:
        if self.display is None:
            self.display = VirtualDisplay()
        return self.display.display

    def open(self, engine: str, url: str, width=1600, height=900) -> EnginePage:
        url = as_tested(url)
        if self.idle.get(engine):
            page = self.idle[engine].pop()
            try:
                page.reopen(url, width, height)
                self.reused += 1
                return page
            except Exception:  # the browser went away while parked: a new page
                page._close()
        self.opened += 1
        if engine == "webkit":
            return WebKitPage(self._x(), url, width, height)
        if engine not in self.browsers:
            if self.pw is None:
                from playwright.sync_api import sync_playwright

                self.pw = sync_playwright().start()
                self.own_pw = True
            if engine == "chromium":
                self.browsers[engine] = self.pw.chromium.launch(
                    executable_path=CHROMIUM, headless=True, args=["--no-sandbox", "--disable-background-networking"])
            else:
                # Firefox ESR over WebDriver BiDi (Playwright's "moz-firefox" channel); WebGL
                # needs the X display even headless
                self.browsers[engine] = self.pw.firefox.launch(
                    channel="moz-firefox", executable_path=FIREFOX, headless=True,
                    env=dict(os.environ, DISPLAY=self._x()))
        return PlaywrightPage(self.browsers[engine], engine, url, width, height)

    def stop(self):
        for pages in self.idle.values():
            for page in pages:
                try:
                    page._close()
                except Exception:
                    pass
        for b in self.browsers.values():
            b.close()
        if self.pw is not None and self.own_pw:
            self.pw.stop()
        if self.display is not None:
            self.display.stop()


def versions(engines: Engines) -> dict:
    """Each engine's name and version, for a report."""
    out = {}
    for name, b in engines.browsers.items():
        out[name] = b.version
    try:
        out["webkit"] = subprocess.run([WEBKIT_DRIVER, "--version"], capture_output=True, text=True, timeout=10).stdout.strip()
    except OSError:
        pass
    return json.loads(json.dumps(out))
