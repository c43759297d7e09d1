"""The thesis's sim-vs-real experiment in the page (panels/experiment.ts), end to end on the
static site: the one firmware on the virtual Nano, configured for a student's own arm (the
thesis example arm of hil/robots, opened as a file), the single-joint plan run on it, the
tool's positions typed at every pose (positions that reproduce appendix K's errors on joint 0),
the questions a mistyped measurement raises, the report exported as CSV and HTML, kept with
the project over a reload - and its numbers equal to the harness's report on the same
measurements (hil/harness on simavr)."""

from __future__ import annotations

import csv
import io
import json
import os
import re
import subprocess
import sys

import pytest

from conftest import FAST, REPO, SHOTS, cli_json

ARM = REPO / "hil" / "robots" / "thesis-example-arm.json"
PLAN = "thesis-single-joint.arm"

# Appendix K, "Changing Joint 0": the absolute errors per axis (cm) at the thesis's angles 0,
# 10, 30, 90 (its first four poses; 120 and 180 follow).
K_JOINT0_CM = {0: (0.0095, 0.0479, 0.04975), 10: (0.017874615, 0.0479, 0.04835335),
               30: (0.005534722, 0.0479, 0.027489348), 90: (0.26575, 0.1525, 0.04975)}
OTHER_MM = (0.8, -0.6, 1.1)  # a ruler's error elsewhere


def measured_for(waiting):
    """What the student types for a pose: the model's position plus appendix K's errors (joint
    0, where the thesis gives them) or a ruler's error, to 0.01 mm."""
    model = waiting["model"]
    err = [c * 10 for c in K_JOINT0_CM[waiting["angle"]]] if waiting["joint"] == 0 and waiting["angle"] in K_JOINT0_CM \
        else OTHER_MM
    return [round(m + e, 2) for m, e in zip(model, err)]


def type_xyz(pg, xyz):
    for axis, v in zip("xyz", xyz):
        pg.page.fill(f"#exp-{axis}", str(v))
    pg.page.click("#exp-record")


def configured_page(open_page, arm=ARM):
    """The static site with the thesis example arm (or `arm`), the virtual Nano configured for it."""
    pg = open_page("mk2plus", query=FAST)
    pg.page.set_input_files("#robot-file", str(arm))
    name = json.loads(arm.read_text())["name"]
    pg.wait(f"a.robot.name === {json.dumps(name)}")
    pg.page.select_option("#arm-port", "page:virtual")
    pg.page.click("#arm-connect")
    pg.wait("a.arm.configurable", timeout=30000)
    pg.page.click("#arm-configure")
    pg.wait("a.arm.connected && a.arm.status !== null", timeout=60000)
    return pg


def harness_report(tmp_path, plan, typed, arm=ARM, page_csv=None):
    """The harness's report.md on simavr for the same arm, plan and measurements: those typed,
    or the page's exported CSV as it is (its first section is the harness's --measured format)."""
    measured = tmp_path / "measured.csv"
    measured.write_text(page_csv if page_csv is not None else
                        "plan,plan_line,x_mm,y_mm,z_mm\n" + "".join(f"{plan},{n},{x},{y},{z}\n" for n, x, y, z in typed))
    out = tmp_path / "report"
    env = dict(os.environ, PYTHONPATH=f"{REPO}:{REPO / 'python'}")
    p = subprocess.run([sys.executable, "-m", "hil.harness", "run", str(REPO / "hil" / "plans" / plan), "--robot", str(arm),
                        "--expect-predicted", "--measured", str(measured), "--out", str(out), "--no-progress",
                        "--vnano", str(REPO / "build" / "virtual-nano" / "articula-vnano"),
                        "--elf", str(REPO / "build" / "avr" / "firmware" / "articula-nano.elf")],
                       cwd=REPO, env=env, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout + p.stderr
    return (out / "report.md").read_text()


def run_plan(pg, plan, xyz_for, first_pose=None):
    """Runs a plan in the Experiment panel, typing xyz_for(pose asked about) at every pose
    (first_pose(pose, xyz) runs once before the first is typed); returns what was typed as
    (plan line, x, y, z), as the harness's --measured CSV has it."""
    pg.page.select_option("#exp-plan", plan)
    pg.page.click("#exp-run")
    typed = []
    while True:
        pg.wait("a.experiment.waiting !== null || !a.experiment.running", timeout=120000)
        w = pg.hook("a.experiment.waiting")
        if w is None:
            break
        xyz = xyz_for(w)
        if first_pose and not typed:
            first_pose(w, xyz)
        type_xyz(pg, xyz)
        pg.wait(f"a.experiment.waiting === null || a.experiment.waiting.line !== {w['line']}", timeout=30000)
        typed.append((w["line"], *xyz))
    assert pg.hook("a.experiment.mismatches") == []  # every reply and every step as the model predicts
    # (the tables come when the plan's last move has ended and its analysis ran: on half a core
    # that took more than a minute, the 15 s default's four times)
    pg.wait("a.experiment.tables !== null", timeout=60000)
    return typed


def test_the_experiment_in_the_page_equals_the_harness(open_page, tmp_path):
    pg = configured_page(open_page)

    assert pg.page.eval_on_selector_all("#exp-plan option", "os => os.map(o => o.value)") == \
        ["straight-lines.arm", "thesis-repeatability.arm", "thesis-single-joint.arm", "tool-points.arm"]

    def mistyped_first(w, xyz):
        # a measurement typed in cm, then one that is not a number: questions, not plots
        type_xyz(pg, [round(v / 10, 2) for v in xyz])
        pg.wait("a.experiment.question !== ''")
        assert "centimetres" in pg.hook("a.experiment.question")
        assert pg.page.is_visible("#exp-anyway")
        pg.page.screenshot(path=str(SHOTS / "studio-experiment-measure.png"))
        type_xyz(pg, ["abc", xyz[1], xyz[2]])
        pg.wait("a.experiment.question !== '' && !a.experiment.question.includes('centimetres')")
        assert "not a number" in pg.hook("a.experiment.question")
        assert not pg.page.is_visible("#exp-anyway")  # a value that is not a number is never used
        assert pg.hook("a.experiment.waiting.line") == w["line"]  # still this pose

    typed = run_plan(pg, PLAN, measured_for, mistyped_first)
    assert "every reply and every step as the model predicts" in pg.page.text_content("#exp-state")
    assert len(typed) >= 8
    pg.page.locator("#experiment-section").scroll_into_view_if_needed()
    pg.page.screenshot(path=str(SHOTS / "studio-experiment-report.png"), full_page=False)

    # The exports.
    with pg.page.expect_download() as dl:
        pg.page.click("#exp-csv")
    page_csv = open(dl.value.path()).read()
    with pg.page.expect_download() as dl:
        pg.page.click("#exp-html")
    html = open(dl.value.path()).read()
    assert dl.value.suggested_filename == "articula-experiment-thesis-single-joint.html"
    assert html.startswith("<!doctype html>") and "<table>" in html and html.count('<img src="data:image/png;base64,') >= 2
    assert "<script" not in html and "Thesis example arm" in html
    assert "Table 4: measured against the model" in html

    # The page's CSV opens with every measurement in the harness's --measured format
    first = page_csv.split("\n\n", 1)[0].splitlines()
    assert first[0].startswith("# ") and first[1] == "plan,plan_line,x_mm,y_mm,z_mm"
    assert [(int(r["plan_line"]), float(r["x_mm"]), float(r["y_mm"]), float(r["z_mm"]))
            for r in csv.DictReader(first[1:])] == [(n, float(x), float(y), float(z)) for n, x, y, z in typed]
    # and fed to the harness as it is, makes its report: the page's Table 4 (measured against the
    # model) and verdicts are the harness's on the same measurements.
    body = "table," + page_csv.split("\ntable,", 1)[1]
    page_t4 = {(r["joint"], r["axis"]): r for r in csv.DictReader(io.StringIO(body.split("\n\n", 1)[0])) if r["table"] == "measured_vs_model"}
    md = harness_report(tmp_path, PLAN, typed, page_csv=page_csv)
    page_verdicts = pg.page.eval_on_selector_all("#exp-report .verdicts li", "ls => ls.map(l => l.textContent)")
    assert page_verdicts and " ".join(page_verdicts) in md.split("**Verdict per joint**: ", 1)[1]
    section = md.split("**Measured vs predicted (quantized)**", 1)[1].split("**", 1)[0]
    rows = [ln for ln in section.splitlines() if re.match(r"^\| [XYZ] \|", ln)]
    head = next(ln for ln in section.splitlines() if ln.startswith("| axis"))
    joints = [int(j) for j in re.findall(r"joint (\d+) max %", head)]
    assert joints and len(rows) == 3
    compared = 0
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        axis = cells[0].lower()
        for k, j in enumerate(joints):
            max_pct, max_mm, avg_mm = cells[1 + 3 * k: 4 + 3 * k]
            mine = page_t4[(str(j), axis)]
            assert max_mm == f"{float(mine['max_mm']):.3f}" and avg_mm == f"{float(mine['avg_mm']):.3f}", (j, axis, row)
            assert max_pct == ("—" if mine["max_pct"] == "" else f"{float(mine['max_pct']):.2f}"), (j, axis, row)
            compared += 1
    assert compared == 3 * len(joints)
    # appendix K's joint 0 errors come back: max |dx| 2.6575 mm (the 90 deg pose)
    assert abs(float(page_t4[("0", "x")]["max_mm"]) - 2.6575) < 0.006

    # Kept with the project: after a reload the report is there again, the same numbers.
    pg.wait("!a.project.dirty", timeout=10000)
    pg.page.reload()
    pg.wait("a.experiment.tables !== null", timeout=60000)
    assert pg.hook("a.experiment.csv") == page_csv
    assert pg.errors == []


def test_repeatability_in_the_page_equals_the_harness(open_page, tmp_path):
    """Table 5 (thesis 5.3): the repeatability chains run on the arm, the tool measured before
    each chain, at its destination and back; every chain's steps back where they started, and
    the page's distances the harness's on the same measurements."""
    pg = configured_page(open_page)

    def ruler(w):
        assert w["joint"] == -1  # a repeatability pose
        return [round(m + e, 2) for m, e in zip(w["model"], OTHER_MM)]

    typed = run_plan(pg, "thesis-repeatability.arm", ruler)
    csv_text = pg.hook("a.experiment.csv")
    body = csv_text.split("\nchain,", 1)[1]
    chains = list(csv.DictReader(io.StringIO("chain," + body)))
    assert len(chains) == 5 and all(c["steps_back"] == "true" for c in chains)
    assert "Table 5: repeatability, out and back" in pg.page.text_content("#exp-report")
    md = harness_report(tmp_path, "thesis-repeatability.arm", typed)
    rows = [ln for ln in md.split("## Repeatability", 1)[1].splitlines() if re.match(r"^\| [1-5] \| \d+ \|", ln)]
    assert len(rows) == 5, md
    for row, c in zip(rows, chains):
        cells = [x.strip() for x in row.strip("|").split("|")]
        assert cells[2] == f"{float(c['dest_error_mm']):.3f}", (row, c)
        assert cells[4] == f"{float(c['return_error_mm']):.3f}", (row, c)
        assert cells[-2] == f"{float(c['measured_dest_mm']):.3f}", (row, c)
        assert cells[-1].split(" ")[0] == f"{float(c['measured_return_mm']):.3f}", (row, c)
    assert pg.errors == []


def test_tool_points_in_the_page_equal_the_harness(open_page, tmp_path):
    """The tool sent to points (P) on the MK2 (a fresh virtual Nano is one): measured 2 mm above
    each target; the model's distance to each target is the harness's, the measured one 2 mm."""
    pg = open_page("mk2plus", query=FAST)
    pg.page.select_option("#arm-port", "page:virtual")
    pg.page.click("#arm-connect")
    pg.wait("a.arm.connected && a.arm.status !== null", timeout=60000)

    def two_mm_above_the_target(w):
        target = [float(v) for v in w["command"].split("#")[0].split()[1:4]]
        return [target[0], target[1], target[2] + 2]

    typed = run_plan(pg, "tool-points.arm", two_mm_above_the_target)
    body = pg.hook("a.experiment.csv").split("\ntarget_line,", 1)[1]
    rows = list(csv.DictReader(io.StringIO("target_line," + body)))
    assert len(rows) == len(typed) >= 8
    assert "Tool to points (P)" in pg.page.text_content("#exp-report")
    md = harness_report(tmp_path, "tool-points.arm", typed, arm=REPO / "robots" / "mk2plus.json")
    harness = {}
    for ln in md.split("\n## Tool to points (P)\n", 1)[1].split("\n## ", 1)[0].splitlines():
        cells = [c.strip() for c in ln.strip("|").split("|")]
        if len(cells) >= 8 and cells[1].isdigit() and cells[3] == "ok":
            harness[cells[1]] = cells
    for r in rows:
        assert abs(float(r["measured_from_target_mm"]) - 2.0) < 1e-9, r
        h = harness[r["target_line"]]
        assert h[5] == f"{float(r['model_from_target_mm']):.3f}" and h[6] == f"{float(r['ideal_from_target_mm']):.4f}", (h, r)
    assert pg.errors == []


@pytest.mark.parametrize("arm", ["mk2-cnc", "mk2-servos"])
def test_the_experiment_runs_on_every_drive(open_page, arm, tmp_path):
    """Issue 40: the Experiment panel and Run on the arm on an arm of each new drive kind
    (STEP/DIR drivers on a CNC shield, hobby servos), on the page's virtual Nano running the
    build for it, configured for the arm: the tool-points plan, every reply and every step as
    the model predicts, its table made from what was typed (2 mm above each target); then a
    program run on the arm ends on the predicted steps."""
    pg = configured_page(open_page, REPO / "hil" / "robots" / f"{arm}.json")
    assert pg.hook("a.arm.label").startswith(json.loads((REPO / "hil" / "robots" / f"{arm}.json").read_text())["name"])

    def two_mm_above_the_target(w):
        target = [float(v) for v in w["command"].split("#")[0].split()[1:4]]
        return [target[0], target[1], target[2] + 2]

    typed = run_plan(pg, "tool-points.arm", two_mm_above_the_target)
    assert len(typed) >= 8
    body = pg.hook("a.experiment.csv").split("\ntarget_line,", 1)[1]
    rows = list(csv.DictReader(io.StringIO("target_line," + body)))
    assert len(rows) == len(typed)
    for r in rows:
        assert abs(float(r["measured_from_target_mm"]) - 2.0) < 1e-9, r
    assert "every reply and every step as the model predicts" in pg.page.text_content("#exp-state")
    # And Run on the arm: a program line by line, the arm on the steps the model predicts.
    text = "M 10 80 -10\nL 0 -5\nP 200 30 150\n"
    pg.page.fill("#editor", text)
    pg.page.check("#drive-arm")
    pg.page.click("#run")
    pg.wait("a.arm.programDone === true", timeout=60000)
    program = tmp_path / "drive.arm"
    program.write_text(text)
    records = cli_json("predict", str(REPO / "hil" / "robots" / f"{arm}.json"), str(program))["records"]
    assert pg.hook("a.arm.programLines") == [[r["line"], "ok" if r["code"] == 0 else f"error:{r['code']}"] for r in records]
    want = json.dumps(records[-1]["steps"], separators=(",", ":"))
    pg.wait(f"a.arm.status.state === 'Idle' && JSON.stringify(a.arm.status.steps) === '{want}'", timeout=20000)
    assert pg.errors == []
