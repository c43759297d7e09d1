"""Every screen a class has: a desktop, a Chromebook, a tablet either way up and a phone. On each,
STOP is on screen and nothing covers it, the 3D view is the largest thing, nothing scrolls
sideways, and the panels that do not fit are tabs. The pictures are docs/studio.md's."""

from __future__ import annotations

import pytest

from conftest import SHOTS

# name: (width, height, touch, the least share of the screen the 3D view gets)
SCREENS = {
    "desktop": (1920, 1080, False, 0.40),
    "chromebook": (1366, 768, False, 0.40),
    "laptop": (1280, 800, False, 0.40),
    "tablet-landscape": (1024, 768, True, 0.40),
    "tablet-portrait": (768, 1024, True, 0.40),
    "phone": (390, 844, True, 0.30),
}

# The page's layout, measured in it: where STOP is and what is on top of its centre, the view's
# share of the screen, and anything wider than its box (sideways scrolling).
MEASURE = """() => {
  const box = (el) => { const r = el.getBoundingClientRect(); return [r.left, r.top, r.width, r.height]; };
  const stop = document.getElementById('stop');
  const [x, y, w, h] = box(stop);
  const top = document.elementFromPoint(x + w / 2, y + h / 2);
  const view = box(document.getElementById('view-wrap'));
  const wide = [...document.querySelectorAll('body, main, header, .panel, .dock-body, .dock-tabs, footer')]
    .filter((el) => el.offsetParent !== null || el === document.body)
    .filter((el) => el.scrollWidth > el.clientWidth + 1 && getComputedStyle(el).overflowX !== 'auto')
    .map((el) => el.id || el.className || el.tagName);
  const conn = document.getElementById('conn');
  return { stop: [x, y, w, h], stopOnTop: top === stop || stop.contains(top), view,
           conn: box(conn), connOk: conn.classList.contains('ok'),
           pageWidth: document.documentElement.scrollWidth, wide, layout: window.articula.layout };
}"""

# Every control a finger can reach now (visible, in the header or the tab shown): its size.
TARGETS = """() => [...document.querySelectorAll('header button, header select, .dock-tabs .tab, #dock-body button, #dock-body select, #dock-body input:not([type=file]), .view-tools button, .view-tools select')]
  .filter((el) => el.offsetParent !== null && el.getBoundingClientRect().width > 0)
  .map((el) => { const r = el.getBoundingClientRect(); return [el.id || el.textContent.trim() || el.type, r.width, r.height]; })"""


def _check_stop(pg, width, height, touch):
    m = pg.page.evaluate(MEASURE)
    x, y, w, h = m["stop"]
    assert 0 <= x and x + w <= width and 0 <= y and y + h <= height, f"STOP is off the screen: {m['stop']}"
    assert m["stopOnTop"], "something covers STOP"
    if touch:
        assert h >= 44 and w >= 44, f"STOP is {w:.0f}x{h:.0f} px: too small for a finger"
    return m


@pytest.mark.parametrize("name", list(SCREENS))
def test_every_screen_has_stop_the_view_and_every_panel(open_page, name):
    width, height, touch, share = SCREENS[name]
    pg = open_page("mk2plus", width=width, height=height, touch=touch)
    m = _check_stop(pg, width, height, touch)
    vx, vy, vw, vh = m["view"]
    assert vw * vh / (width * height) >= share, f"the 3D view gets {vw * vh / (width * height):.0%} of the screen"
    assert m["pageWidth"] <= width and m["wide"] == [], f"sideways scrolling: {m}"
    pg.wait("a.armPixels() > 0.002")  # the arm is drawn in the view
    # the engine's chip whole in the header (a phone shows its green dot alone)
    pg.wait("document.getElementById('conn').classList.contains('ok')")
    cx, cy, cw, ch = pg.page.evaluate(MEASURE)["conn"]
    assert cx >= 0 and cx + cw <= width and cw >= 16, f"the engine's chip is cut: {[cx, cy, cw, ch]}"
    pg.page.screenshot(path=str(SHOTS / f"studio-{name}.png"))

    if m["layout"]["mode"] == "wide":
        sections = ["joints-section", "ik-section", "program-section", "arm-section"]
        assert all(pg.page.is_visible(f"#{s}") for s in sections)
    else:
        # every panel is a tab away: the tab shows it, the view keeps its size, STOP stays
        tabs = pg.page.eval_on_selector_all(".dock-tabs .tab", "els => els.filter(e => !e.hidden).map(e => e.id)")
        assert {"tab-joints", "tab-ik", "tab-program", "tab-arm", "tab-robot"} <= set(tabs)
        for tab, shown in [("tab-program", "#editor"), ("tab-ik", "#solve"), ("tab-arm", "#arm-connect"),
                           ("tab-robot", "#robot-select"), ("tab-joints", "#joints input[type=range]")]:
            if touch:
                pg.page.tap(f"#{tab}")
            else:
                pg.page.click(f"#{tab}")
            assert pg.page.get_attribute(f"#{tab}", "aria-selected") == "true"
            assert pg.page.is_visible(shown), f"{tab} does not show {shown}"
            again = _check_stop(pg, width, height, touch)
            assert again["view"] == m["view"] and again["wide"] == [], again
        if m["layout"]["plotsInTab"]:
            assert "tab-plots" in tabs
    if touch:
        small = [t for t in pg.page.evaluate(TARGETS) if t[2] < 44]
        assert small == [], f"touch targets under 44 px high: {small}"
    assert pg.errors == []


def test_stop_stays_on_top_of_the_tour_and_a_banner(open_page):
    pg = open_page("mk2plus", width=768, height=1024, touch=True, tour=True)
    assert pg.page.is_visible("#tour")
    assert "finger" in pg.page.text_content("#tour-text")  # a tablet's words: no mouse to drag
    _check_stop(pg, 768, 1024, True)
    pg.page.tap("#tour-next")  # the joints: the tour shows the tab that holds them
    assert pg.hook("a.layout.tab") == "joints" and pg.page.is_visible("#joints-section")
    pg.page.tap("#tour-next")
    assert pg.hook("a.layout.tab") == "ik" and pg.page.is_visible("#ik-section")
    _check_stop(pg, 768, 1024, True)
    pg.page.tap("#tour-skip")
    pg.page.set_input_files("#robot-file", files=[{"name": "broken.json", "mimeType": "application/json",
                                                    "buffer": b'{"name": "broken",'}])
    pg.page.wait_for_selector("#banner", state="visible")  # "This robot file cannot be used..."
    _check_stop(pg, 768, 1024, True)


def test_the_layout_follows_the_window_and_a_turned_tablet(open_page):
    pg = open_page("mk2plus", width=1920, height=1080)
    assert pg.hook("a.layout.mode") == "wide"
    pg.page.fill("#editor", "L 0 30")
    for (w, h), mode in [((1024, 768), "dock"), ((768, 1024), "stacked"), ((390, 844), "stacked"), ((1920, 1080), "wide")]:
        pg.page.set_viewport_size({"width": w, "height": h})
        pg.wait(f"a.layout.mode === '{mode}'")
        _check_stop(pg, w, h, False)
        # the panels moved, with what was typed in them
        assert pg.page.input_value("#editor") == "L 0 30"
    # the view followed: its canvas fills its box again
    pg.wait("(() => { const c = document.querySelector('#view canvas'), v = document.getElementById('view-wrap'); "
            "return Math.abs(c.clientWidth - v.clientWidth) < 2 && Math.abs(c.clientHeight - v.clientHeight) < 2; })()")
    assert pg.errors == []


class Fingers:
    """Touches on the page through Chromium's DevTools protocol (Playwright has taps, not drags
    or pinches): each touch point a finger, moved in steps as a hand moves."""

    def __init__(self, pg):
        self.pg = pg
        self.cdp = pg.context.new_cdp_session(pg.page)

    def _send(self, kind, points):
        self.cdp.send("Input.dispatchTouchEvent", {
            "type": kind, "touchPoints": [{"x": x, "y": y, "id": i, "radiusX": 4, "radiusY": 4, "force": 1}
                                          for i, (x, y) in enumerate(points)]})

    def gesture(self, starts, ends, steps=20):
        """Fingers down at `starts`, moved to `ends` in `steps`, lifted."""
        self._send("touchStart", starts)
        for k in range(1, steps + 1):
            self._send("touchMove", [(x0 + (x1 - x0) * k / steps, y0 + (y1 - y0) * k / steps)
                                     for (x0, y0), (x1, y1) in zip(starts, ends)])
            self.pg.page.wait_for_timeout(16)
        self._send("touchEnd", [])


def test_touch_a_finger_orbits_drags_the_ik_target_and_two_pinch_to_zoom(open_page):
    pg = open_page("mk2plus", width=768, height=1024, touch=True)
    assert pg.page.evaluate("() => matchMedia('(pointer: coarse)').matches && navigator.maxTouchPoints > 0")
    fingers = Fingers(pg)
    vx, vy, vw, vh = pg.page.evaluate(MEASURE)["view"]
    cx, cy = vx + vw / 2, vy + vh * 0.75  # the ground in front of the arm

    # one finger orbits the camera about the arm
    before = pg.hook("a.camera()")
    fingers.gesture([(cx - 100, cy)], [(cx + 100, cy)])
    pg.wait(f"Math.abs(a.camera().azimuth - {before['azimuth']}) > 20")
    assert pg.hook("a.camera().distance") == pytest.approx(before["distance"], rel=0.02)

    # two fingers apart: a pinch that zooms in (the camera comes closer)
    before = pg.hook("a.camera()")
    fingers.gesture([(cx - 30, cy), (cx + 30, cy)], [(cx - 150, cy), (cx + 150, cy)])
    pg.wait(f"a.camera().distance < {before['distance'] * 0.8}")

    # a finger drags the IK target: the arm follows it
    pg.page.tap("#tab-ik")
    pg.page.tap("#show-target")
    assert pg.page.is_checked("#show-target")
    pg.page.tap("#fit")
    pg.page.wait_for_timeout(500)  # the fitted camera has settled (its damping)
    x, y = pg.hook("a.targetScreen")
    tool = pg.hook("a.pose.tool.xyz")
    fingers.gesture([(x, y)], [(x - 40, y + 30)])
    pg.wait("a.ik && a.ik.status === 'reached'")
    pg.wait(f"Math.hypot(...a.pose.tool.xyz.map((v, i) => v - {tool}[i])) > 15")
    assert pg.hook("a.ikUpdates.length") >= 3
    assert pg.errors == []


@pytest.mark.parametrize("width", [1600, 1920])
def test_the_robots_name_in_the_header_is_readable_or_not_there(open_page, width):
    """Beside a long project name the robot's name has little room: cut to a letter ("M") it
    says nothing, so it is not shown; else it shows at least a few words."""
    pg = open_page("mk2plus", width=width, height=900)
    shown = "(() => { const e = document.getElementById('robot-name'); return e.offsetParent !== null && " \
            "getComputedStyle(e).visibility === 'visible' ? e.clientWidth : 0; })()"
    assert pg.hook(shown) >= 90  # a short project's name: the robot's shows
    pg.page.click("#projects-button")
    pg.page.select_option("#exercise-select", "pick-and-place.articula")
    pg.wait("a.project.name.startsWith('Exercise: pick and place')")
    pg.page.keyboard.press("Escape")
    pg.wait(f"(w => w === 0 || w >= 90)({shown})")
    assert pg.page.evaluate(MEASURE)["wide"] == []
    assert pg.errors == []
