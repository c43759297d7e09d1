"""Sized for the arm shown (issue 55, item 3): a class with meArms found every toolbox block and
the new sheet sized for the MK2 (its "move the tool to 200, 0, 150" is beyond a meArm's reach,
so every new block warned). The toolbox's points and a new sheet are now the engine's places
for the arm shown (host/lib/blocks.h example_places_json)."""

from __future__ import annotations

from class_page import _blocks, _drag_block


def test_a_mearms_toolbox_blocks_are_moves_it_can_make(open_page):
    pg = open_page("mearm", width=1366, height=768)
    _blocks(pg)
    tool = _drag_block(pg, "Move", "arm_tool_to", None)
    line = _drag_block(pg, "Move", "arm_line_to", tool)
    pg.wait("a.blocksCode !== null && !a.blocksPending && a.blocksCode.text.includes('T ')", timeout=20000)
    text = pg.hook("a.blocksCode.text")
    assert "P 150 0 110" in text and "T 170 0 110 30" in text, text
    assert pg.hook("a.blockProblems") == [], pg.hook("a.blockProblems")
    assert line
    # and the pen's blocks draw where its pen reaches
    pen = _drag_block(pg, "Pen", "arm_pen", line)
    _drag_block(pg, "Pen", "arm_shape", pen)
    pg.wait("a.blocksCode !== null && !a.blocksPending && a.blocksCode.text.includes('T 155 15 70 20')", timeout=20000)
    assert pg.hook("a.blockProblems") == [], pg.hook("a.blockProblems")
    assert pg.hook("a.pageErrors") == [] and pg.errors == []


def test_a_new_sheet_lies_where_the_arm_shown_draws(open_page):
    pg = open_page("mearm")
    pg.wait("document.getElementById('draw-pen').value !== ''")
    assert (pg.page.input_value("#paper-x"), pg.page.input_value("#draw-pen")) == ("170", "70")
    # another arm: the untouched sheet follows it
    pg.page.select_option("#robot-select", "mk2plus")
    pg.wait("a.robot && a.robot.source.endsWith('mk2plus.json') && document.getElementById('draw-pen').value === '120'", timeout=20000)
    assert pg.page.input_value("#paper-x") == "250"
    assert pg.errors == []


def test_the_scene_menu_offers_the_arms_own_scenes_first(open_page):
    """Before: every scene was the MK2's (grasp-and-lift's block at 305 mm, a meArm reaches
    about 228). The meArm's own scene comes first; the MK2's are offered as placed for others."""
    pg = open_page("mearm")
    pg.wait("document.querySelectorAll('#scene-select option').length > 2")
    groups = pg.page.eval_on_selector(
        "#scene-select", "s => [[...s.children].filter(c => c.tagName === 'OPTION').map(o => o.value),"
        " [...s.querySelectorAll('optgroup')].map(g => [g.label, [...g.children].map(o => o.value)])]")
    own, others = groups
    assert own == ["", "grasp-and-lift-mearm"], own
    assert others[0][0] == "placed for other arms" and "grasp-and-lift" in others[0][1], others
    # the MK2: the other way round
    pg.page.select_option("#robot-select", "mk2plus")
    pg.wait("a.robot && a.robot.source.endsWith('mk2plus.json')", timeout=20000)
    pg.wait("[...document.querySelectorAll('#scene-select > option')].some(o => o.value === 'grasp-and-lift')")
    assert "grasp-and-lift-mearm" in pg.page.eval_on_selector_all("#scene-select optgroup option", "os => os.map(o => o.value)")
    assert pg.errors == []


def test_the_mearms_wiring_says_its_5_v_supply_and_common_ground(open_page):
    """Before: the wiring view showed the signals only: no 5 V supply, no common ground, no word
    of the servos' stall current (which resets a Nano powering them from its own pin)."""
    pg = open_page("mearm")
    pg.wait("a.wiring.wires > 0", timeout=15000)
    supply = pg.page.eval_on_selector_all("#wiring-supply li", "ls => ls.map(l => l.textContent)")
    assert len(supply) == 2, supply
    assert supply[0].startswith("The servos' + to a 5 V supply that gives 2.6 A"), supply
    assert "not the Nano's 5 V pin" in supply[0] and "one common ground" in supply[1], supply
    assert pg.errors == []
