"""Programs through Python: predict, run and quantize give the CLI's JSON, field for field,
on every shipped robot and program; bad programs raise ProgramError naming the line."""

import numpy as np
import pytest

import articula
from conftest import PLANS, PROGRAMS, REPO, ROBOTS, cli_json


def without_file(doc):
    doc = dict(doc)
    doc.pop("robot_file", None)
    return doc


@pytest.mark.parametrize("name", ROBOTS)
@pytest.mark.parametrize("program", PROGRAMS + PLANS)
def test_predict_and_run_equal_the_clis_json(name, program):
    robot = articula.Robot.load(name)
    try:
        robot.check_program(program)
    except articula.ProgramError:
        with pytest.raises(articula.ProgramError):
            robot.run(program)
        return
    run = robot.run(articula.Program.load(program))
    assert without_file(run.to_dict()) == without_file(cli_json("run", name, program))
    if robot.num_motors == 0:
        with pytest.raises(ValueError, match="has no motors"):
            robot.predict(program)
        return
    pred = robot.predict(program)
    doc = cli_json("predict", name, program)
    assert without_file(pred.to_dict()) == without_file(doc)
    # attribute access reads the same fields
    assert pred.summary.worst_error_mm == doc["summary"]["worst_error_mm"]
    for rec, d in zip(pred.records, doc["records"]):
        assert rec.steps == d["steps"] and rec.tool_quantized_mm == d["tool_quantized_mm"]
        assert rec.end_s == d["end_s"]


def test_settings_as_dict_or_text_match_the_cli():
    mk2 = articula.Robot.load("mk2plus")
    a = mk2.predict("programs/demo.arm", settings={0: 800, 1: 3000})
    b = mk2.predict("programs/demo.arm", settings="0=800,1=3000")
    doc = cli_json("predict", "mk2plus", "programs/demo.arm", "--settings", "0=800,1=3000")
    assert without_file(a.to_dict()) == without_file(b.to_dict()) == without_file(doc)
    with pytest.raises(ValueError, match="9"):
        mk2.predict("programs/demo.arm", settings={9: 1})


def test_columns_for_plots():
    pred = articula.Robot.load("mk2plus").predict("programs/demo.arm")
    steps = pred.column("steps")
    assert steps.shape == (len(pred.records), 3)
    assert np.all(np.diff(pred.column("end_s")) >= 0)


def test_quantize_equals_the_cli():
    lines = ["L 0 10", "L 1 150", "L 0 0.1", "M 1 2 3", "X", "L 2 -12.5"]
    recs = articula.Robot.load("mk2plus").quantize(lines)
    docs = [__import__("json").loads(s) for s in
            __import__("conftest").cli("quantize", "mk2plus", *lines, "--json").stdout.splitlines()]
    for r, d in zip(recs, docs):
        d.pop("where")
        d.pop("note", None)
        assert r.to_dict() == d
    assert recs[1].code == 9 and articula.status_text(recs[1].code) == "target beyond a joint limit"


def test_a_program_from_text_and_its_format():
    p = articula.Program.parse("m\n0\n90\n-90\n", name="p.robosim")
    assert p.format == "robosim"
    q = articula.Program.parse("L 0 10\nL 1 -20\n", name="moves.arm")
    assert q.format == "protocol"
    mk2 = articula.Robot.load("mk2plus")
    assert mk2.check_program(q) == 2
    rec = mk2.predict(q).records
    assert [r.steps for r in rec] == [[32, 0, 0], [32, -27, 0]]


def test_bad_programs_name_the_line(tmp_path):
    mk2 = articula.Robot.load("mk2plus")
    bad = articula.Program.parse("L 0 10\nL 0 1e3\n", name="bad.arm")
    with pytest.raises(articula.ProgramError) as e:
        mk2.predict(bad)
    assert e.value.line == 2 and str(e.value).startswith("bad.arm:2:")
    # every line that cannot be read, at once
    with pytest.raises(articula.ProgramError) as e:
        mk2.predict(articula.Program.parse("L 0 10\nL 7 1\nM 0 90 0\nQ\n", name="two.arm"))
    assert e.value.line == 2 and [line for line, _ in e.value.problems] == [2, 4]
    assert str(e.value).splitlines() == [f"two.arm:{line}: {problem}" for line, problem in e.value.problems]
    with pytest.raises(articula.ProgramError, match=r"short.robosim:1: m \(joint value\): 3 values expected, 2 given"):
        mk2.run(articula.Program.parse("m\n0\n90\n", name="short.robosim"))
    with pytest.raises(articula.ProgramError, match="short.robosim:3: joint shoulder 2 is outside 36 .. 130"):
        mk2.run(articula.Program.parse("m\n0\n2\n-90\n", name="short.robosim"))
    with pytest.raises(articula.ProgramError, match="cannot read"):
        articula.Program.load(tmp_path / "none.arm")
    with pytest.raises(articula.ProgramError, match="none.arm"):
        mk2.run(str(tmp_path / "none.arm"))
    with pytest.raises(TypeError, match="articula.Program or a file path"):
        mk2.run(42)


def test_status_table_is_the_protocol_documents():
    text = (REPO / "docs" / "protocol.md").read_text()
    for code, st in articula.STATUS.items():
        assert f"| {code} |" in text and st.text.split(" (")[0] in text, st
    assert articula.status_text("error:10") == "target out of reach"
    assert articula.status_text(15) == "discarded by stop (!)"
    assert articula.status_text("ok") == "ok"
    with pytest.raises(ValueError):
        articula.status_text("garbage")


def test_a_wait_is_a_pause_in_the_prediction():
    import articula

    mk2 = articula.Robot.load("mk2plus")
    res = mk2.predict(articula.Program("L 0 10\nD 1.5\nL 0 -10\n", "w.arm"))
    move, wait, back = res.records
    assert wait.reply == "ok" and wait.start_tick == move.end_tick
    assert abs(wait.end_s - wait.start_s - 1.5) < 1e-9
    assert back.start_tick == wait.end_tick
    # beyond its range: the program is refused, the line named with the range
    import pytest

    with pytest.raises(articula.ProgramError, match=r"w\.arm:1: 'D 601': error:8 .* 0 to 600"):
        mk2.predict(articula.Program("D 601\n", "w.arm"))


def test_a_straight_line_from_python_on_the_nano_and_on_any_robot():
    """T through Python: the MK2's prediction has the Nano's segments and the tool's worst
    distance from the line at any step; the Panda's run cuts the same line through its IK."""
    line = articula.Program("P 300 -100 150\nT 300 100 150 50\n", "line.arm")
    rec = articula.Robot.load("mk2plus").predict(line).records[1]
    assert rec.reply == "ok" and len(rec.segments) > 3
    assert sum(s.dominant_steps for s in rec.segments) == rec.dominant_steps
    assert 0 < rec.line_error_mm < 2.5
    panda = articula.Robot.load("panda").run(articula.Program("T 500 100 400 50\nT 500 -100 400 50\n", "p.arm"))
    last = panda.records[1]
    assert last.reply == "ok" and len(last.segments) >= 2
    assert abs(last.line_length_mm - 200) < 0.01 and last.segments[-1].along_mm == pytest.approx(200, abs=0.01)
