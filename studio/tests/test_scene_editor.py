"""The scene editor (panels/scene-edit.ts): a scene of the student's own, built by dropping a class's
objects where the pointer presses on the view, typed in millimetres, undone, kept in the project
(a reload brings it back) and in its share link (opened in a new profile: the same world, to
0.1 mm), refused by the engine's scene loader when it cannot be (nothing changes), saved as a scene
file the CLI runs."""

from __future__ import annotations

import json
import subprocess

from conftest import SHOTS, Page, cli_path


def _world(pg) -> dict:
    return pg.hook("a.scene && a.scene.world")


def _objects(world: dict) -> dict:
    return {o["name"]: o for o in world["objects"]}


def _drop(pg, key: str, at: list[float], count: int) -> None:
    """Chooses `key` from the palette and presses the view where the world point `at` (mm) is."""
    pg.page.click(f"#scene-palette [data-add={key}]")
    x, y = pg.hook(f"a.pointScreen({json.dumps(at)})")
    pg.page.mouse.click(x, y)
    pg.wait(f"a.scene && a.scene.world && a.scene.world.objects.length === {count}", timeout=30000)


def _same_world(a: dict, b: dict) -> None:
    oa, ob = _objects(a), _objects(b)
    assert sorted(oa) == sorted(ob)
    for name, o in oa.items():
        for k in ("xyz", "size"):
            assert all(abs(p - q) <= 0.1 for p, q in zip(o[k], ob[name][k])), (name, k, o[k], ob[name][k])
        assert o["type"] == ob[name]["type"] and o.get("movable") == ob[name].get("movable")


def test_a_scene_of_ones_own_is_built_by_pointer_and_typing_undone_kept_and_shared(open_page, browser, tmp_path):
    pg = open_page("mk2plus")
    pg.wait("a.project.name !== '' && a.scene !== null", timeout=20000)
    assert pg.hook("a.scene.name") is None  # physics off: the first object turns it on with a scene of one's own
    # five objects, dropped onto the surface under the pointer: the table, then the pallet's top
    _drop(pg, "pallet", [-200, 0, 0], 1)
    _drop(pg, "cube", [200, 0, 0], 2)
    _drop(pg, "cylinder", [200, 100, 0], 3)
    _drop(pg, "ball", [150, -120, 0], 4)
    _drop(pg, "cube", [-200, 10, 20], 5)  # on the pallet (20 mm high)
    objs = _objects(_world(pg))
    assert objs["cube 1"]["xyz"] == [200, 0, 12.5]  # snapped to 5 mm, standing on the table
    assert objs["pallet 1"]["xyz"] == [-200, 0, 10]
    assert objs["cube 2"]["xyz"][2] == 32.5, objs["cube 2"]  # on top of the pallet
    assert objs["cylinder 1"]["xyz"] == [200, 100, 12.5] and objs["ball 1"]["xyz"] == [150, -120, 12.5]
    assert pg.hook("a.physics && a.physics.on") is True
    assert pg.page.eval_on_selector("#scene-select", "s => s.value") == "@yours"
    assert pg.page.locator("#scene-objects .scene-obj").count() == 5  # a row each
    # in the engine: its objects where the world has them
    assert sorted(o["name"] for o in pg.hook("a.scene.objects")) == sorted(objs)
    # one typed: the first cube 10.5 mm further out
    pg.page.fill("[data-object='cube 1'][data-field='x']", "210.5")
    pg.page.press("[data-object='cube 1'][data-field='x']", "Enter")
    pg.wait("a.scene.world.objects.find(o => o.name === 'cube 1').xyz[0] === 210.5", timeout=15000)
    # one more object, undone: the History takes it back
    _drop(pg, "wall", [0, -250, 0], 6)
    pg.wait("document.querySelector('#undo').title.includes('your scene')", timeout=10000)
    pg.page.click("#undo")
    pg.wait("a.scene.world.objects.length === 5", timeout=15000)
    assert "wall 1" not in _objects(_world(pg))
    before = _world(pg)
    assert _objects(before)["cube 1"]["xyz"][0] == 210.5  # (the typed edit stays)
    # a refused edit changes nothing: a cube sunk into the table is the loader's to refuse
    pg.page.fill("[data-object='ball 1'][data-field='z']", "-30")
    pg.page.press("[data-object='ball 1'][data-field='z']", "Enter")
    pg.page.wait_for_selector("#banner:not([hidden])", timeout=15000)
    assert "ball 1" in pg.page.text_content("#banner-text")
    pg.page.wait_for_timeout(300)
    _same_world(_world(pg), before)
    assert pg.page.input_value("[data-object='ball 1'][data-field='z']") == "12.5"  # (the field says so too)
    pg.page.click("#banner-close")
    pg.page.eval_on_selector("#scene-edit-section", "e => e.scrollIntoView()")
    pg.page.screenshot(path=str(SHOTS / "studio-scene-editor.png"))
    # kept: a reload brings the world back
    pg.wait("a.project.dirty === false && a.project.saves > 0", timeout=10000)
    pg.page.reload()
    pg.page.wait_for_function("() => window.articula && window.articula.ready && window.articula.project.name !== ''", timeout=30000)
    pg.wait("a.scene && a.scene.world && a.scene.world.objects.length === 5", timeout=30000)
    _same_world(_world(pg), before)
    # shared: the link opens the same world in a new profile
    pg.page.click("#share-button")
    pg.wait("a.shareLink !== ''")
    other = Page(browser, pg.hook("a.shareLink"), ready="window.articula.project.name.includes('from a link')")
    try:
        other.wait("a.scene && a.scene.world && a.scene.world.objects.length === 5", timeout=30000)
        _same_world(other.hook("a.scene.world"), before)
        assert sorted(o["name"] for o in other.hook("a.scene.objects")) == sorted(_objects(before))
        assert other.errors == []
    finally:
        other.close()
    # saved as a scene file: the CLI runs a program in it
    with pg.page.expect_download() as dl:
        pg.page.click("#scene-save")
    path = tmp_path / dl.value.suggested_filename
    dl.value.save_as(path)
    saved = json.loads(path.read_text())
    _same_world(saved, before)
    program = tmp_path / "p.arm"
    program.write_text("M 0 90 0\n")
    r = subprocess.run([str(cli_path()), "sim", "mk2plus", str(program), "--scene", str(path), "--json"],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    last = json.loads([line for line in r.stdout.splitlines() if line.startswith("{")][-1])  # (a JSON line a sample)
    assert sorted(last["objects"]) == sorted(o["name"] for o in before["objects"] if o.get("movable"))
    assert pg.errors == []


def test_a_links_scene_with_markup_names_is_shown_as_text_and_a_bad_one_refused_by_name(open_page, browser, site):
    from class_page import _fragment, _project

    script = "<img src=x onerror=window.__pwned=1>"
    world = {"name": "Mine", "objects": [{"name": script, "type": "box", "size": [25, 25, 25], "xyz": [200, 0, 12.5], "movable": True}]}
    p = Page(browser, f"{site.url}#{_fragment(_project('World', mode='text', world=world))}",
             ready="window.articula.project.name.includes('from a link')")
    try:
        p.wait("a.scene && a.scene.world && a.scene.objects.length === 1", timeout=30000)
        assert script in p.page.text_content("#scene-objects")  # as text
        assert p.page.locator("#scene-objects img").count() == 0
        assert p.page.evaluate("() => window.__pwned") is None
    finally:
        p.close()
    bad = {"name": "Bad", "objects": [{"name": "nan", "type": "box", "size": [25, -1, 25], "xyz": [200, 0, 12.5]}]}
    p = Page(browser, f"{site.url}#{_fragment(_project('World', mode='text', world=bad))}",
             ready="window.articula.project.name.includes('from a link')")
    try:
        p.page.wait_for_selector("#banner:not([hidden])", timeout=30000)
        assert "/objects/0/size/1" in p.page.text_content("#banner-text")
        assert p.hook("a.scene.world") is None
    finally:
        p.close()


def test_on_a_tablet_a_finger_drops_an_object_and_types_its_place(open_page):
    """An upright tablet with touch: the Robot tab holds the scene editor; a tap on the palette
    and a tap on the view drop a cube there, and its typed y moves it."""
    pg = open_page("mk2plus", width=768, height=1024, touch=True)
    pg.wait("a.project.name !== '' && a.scene !== null", timeout=20000)
    pg.page.tap("#tab-robot")
    pg.page.locator("#scene-palette [data-add=cube]").scroll_into_view_if_needed()
    pg.page.tap("#scene-palette [data-add=cube]")
    x, y = pg.hook("a.pointScreen([150, 50, 0])")
    assert 0 < x < 768 and 0 < y < 1024, (x, y)
    pg.page.touchscreen.tap(x, y)
    pg.wait("a.scene && a.scene.world && a.scene.world.objects.length === 1", timeout=30000)
    assert _world(pg)["objects"][0]["xyz"] == [150, 50, 12.5]
    field = "[data-object='cube 1'][data-field='y']"
    pg.page.tap(field)
    pg.page.fill(field, "-40")
    pg.page.press(field, "Enter")
    pg.wait("a.scene.world.objects[0].xyz[1] === -40", timeout=15000)
    assert pg.hook("a.scene.objects.map(o => o.name)") == ["cube 1"]
    pg.page.screenshot(path=str(SHOTS / "studio-scene-editor-tablet.png"))
    assert pg.errors == []


def test_a_shipped_scene_becomes_ones_own_and_its_file_stays(open_page):
    """An object added to the shipped scene on screen: its objects and the new one are yours
    ("... (yours)"); the shipped scene is still offered as it was."""
    pg = open_page("mk2plus")
    pg.page.select_option("#scene-select", "push")
    pg.wait("a.scene && a.scene.name === 'push' && a.scene.objects.length > 0", timeout=30000)
    shipped = sorted(o["name"] for o in pg.hook("a.scene.objects"))
    _drop(pg, "cube", [0, -250, 0], len(shipped) + 1)
    w = _world(pg)
    assert w["name"].endswith("(yours)") and sorted(_objects(w)) == sorted(shipped + ["cube 1"])
    assert pg.page.eval_on_selector("#scene-select", "s => s.value") == "@yours"
    pg.page.select_option("#scene-select", "push")
    pg.wait("a.scene.world === null && a.scene.name === 'push'", timeout=30000)
    assert sorted(o["name"] for o in pg.hook("a.scene.objects")) == shipped
    assert pg.errors == []
