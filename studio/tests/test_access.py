"""Every control reachable from the keyboard with a name a screen reader reads (axe-core, from
npm, in the page: no serious or critical violation on the main screens), and a page that
survives its environment: a locale that is no language tag, no WebGL, no storage."""

from __future__ import annotations

import pytest

from conftest import REPO, Page

AXE = REPO / "studio" / "web" / "node_modules" / "axe-core" / "axe.min.js"


def _axe(pg) -> list[dict]:
    """axe-core's serious and critical violations on the page as it is now."""
    if not pg.page.evaluate("() => typeof window.axe === 'object'"):
        pg.page.add_script_tag(path=str(AXE))
    found = pg.page.evaluate("""async () => {
      const r = await axe.run(document, { resultTypes: ['violations'] });
      return r.violations.filter(v => v.impact === 'serious' || v.impact === 'critical')
        .map(v => ({ id: v.id, impact: v.impact, help: v.help, nodes: v.nodes.slice(0, 4).map(n => n.target.join(' ')) }));
    }""")
    return found


@pytest.fixture
def axe_page(browser, site):
    pages = []

    def open_(width, height, touch=False, query=""):
        # axe-core goes into the page as a script of the test's: the site's CSP would refuse it
        pg = Page(browser, f"{site.url}?robot=mk2plus{query}", width=width, height=height, touch=touch, bypass_csp=True)
        pages.append(pg)
        return pg

    yield open_
    for p in pages:
        p.close()


@pytest.mark.parametrize("width,height,touch", [(1600, 900, False), (1024, 768, True), (390, 844, True)])
def test_no_serious_accessibility_violation_on_the_main_screens(axe_page, width, height, touch):
    pg = axe_page(width, height, touch, "&scene=push")
    pg.wait("a.physics !== null")
    problems = _axe(pg)
    if pg.hook("a.layout.mode") != "wide":
        for tab in ["ik", "program", "arm", "robot"] + (["plots"] if pg.hook("a.layout.plotsInTab") else []):
            pg.page.click(f"#tab-{tab}")
            problems += [dict(p, tab=tab) for p in _axe(pg)]
    assert problems == [], "\n".join(f"{p.get('tab', 'page')}: {p['id']} ({p['help']}) at {p['nodes']}" for p in problems)


def test_every_control_is_reached_from_the_keyboard(open_page):
    pg = open_page("mk2plus", width=1024, height=768)
    # Tab from the top of the page: STOP comes early, the view's canvas and the tabs are stops
    seen = []
    for _ in range(40):
        pg.page.keyboard.press("Tab")
        seen.append(pg.page.evaluate("() => document.activeElement.id || document.activeElement.tagName"))
    assert "stop" in seen[:6], seen
    assert "tab-joints" in seen, seen
    # the tab list: arrows move between tabs and show each
    pg.page.focus("#tab-joints")
    pg.page.keyboard.press("ArrowRight")
    assert pg.page.evaluate("() => document.activeElement.id") == "tab-ik"
    assert pg.hook("a.layout.tab") == "ik" and pg.page.is_visible("#solve")
    pg.page.keyboard.press("End")  # the last tab: the plots where they are a tab (under 800 px), else the robot
    last = pg.page.evaluate("() => document.activeElement.id")
    if pg.hook("a.layout.plotsInTab"):
        assert last == "tab-plots" and pg.page.is_visible("#plots")
        pg.page.keyboard.press("ArrowLeft")
        last = pg.page.evaluate("() => document.activeElement.id")
    assert last == "tab-robot" and pg.page.is_visible("#robot-select")
    # a slider typed from the keyboard moves the arm
    pg.page.keyboard.press("Home")
    q0 = pg.hook("a.pose.q[0]")
    pg.page.focus("#joints input[type=range]")
    for _ in range(5):
        pg.page.keyboard.press("ArrowRight")
    pg.wait(f"a.pose.q[0] > {q0}")
    # Escape is STOP wherever the focus is
    assert pg.page.get_attribute("#stop", "title").endswith("Escape does the same.")
    assert pg.errors == []


def test_a_locale_that_is_no_language_tag_does_not_stop_the_page(open_page):
    """WebKitGTK with LANG=C.UTF-8 says navigator.language is "C"; Intl throws on it."""
    pg = open_page("mk2plus", init_script="Object.defineProperty(Navigator.prototype, 'language', "
                                          "{ get: () => 'C', configurable: true })")
    assert pg.hook("a.language") == "en"
    pg.page.select_option("#program-select", "demo.arm")
    pg.page.wait_for_function("() => document.querySelector('#editor').value.length > 0")
    pg.page.click("#run")
    pg.page.wait_for_selector("#plots .uplot")  # uPlot, which formats with the language, draws
    assert pg.errors == []


def test_without_webgl_the_panels_still_work(open_page):
    no_webgl = ("const real = HTMLCanvasElement.prototype.getContext; HTMLCanvasElement.prototype.getContext = "
                "function (kind, ...rest) { return /webgl/.test(kind) ? null : real.call(this, kind, ...rest); };")
    pg = open_page("mk2plus", init_script=no_webgl, ready="window.articula.pose !== null")
    assert pg.hook("a.webgl") is False
    assert "no WebGL" in pg.page.text_content("#view-wrap")
    pg.page.fill("#tx", "250")
    pg.page.fill("#ty", "50")
    pg.page.fill("#tz", "150")
    pg.page.click("#solve")
    pg.wait("a.ik && a.ik.status === 'reached'")
    pg.page.fill("#editor", "L 0 30\nM 0 60 -60")
    pg.page.click("#run")
    pg.wait("a.timeline !== null && a.playing === false && a.pose.t > 0")
    assert pg.page.is_visible("#stop")
    assert [e for e in pg.errors if "WebGL" not in e] == []


def test_without_storage_the_page_works_and_forgets(open_page):
    """Private browsing, or storage turned off: localStorage throws on every use."""
    no_storage = ("Object.defineProperty(window, 'localStorage', { get() { throw new DOMException('denied', "
                  "'SecurityError'); } });")
    pg = open_page("mk2plus", init_script=no_storage, tour=True)
    assert pg.hook("a.storage") is False
    assert pg.page.is_visible("#tour")  # it cannot remember the tour was seen: it shows it
    pg.page.click("#tour-skip")
    pg.page.fill("#editor", "L 0 30")
    pg.page.click("#run")
    pg.wait("a.timeline !== null && a.playing === false && a.pose.t > 0")
    assert pg.errors == []
