"""Tool positions measured on a real arm (the thesis's tape-measure method, section 5.2).

A CSV with a header and the columns `plan_line,x_mm,y_mm,z_mm` (any order; more columns are
ignored), one row per measured plan step: the tool's position in the base frame after the
command on that line of the plan. An optional `plan` column names the plan (its file name,
as `thesis-single-joint.arm`); without it the CSV belongs to the only plan of the run. A line
measured several times is averaged (the report says how many).

The studio's Experiment panel exports its CSV in this format too: `#` lines are comments, and
the measurements are the file's first section (the tables after the first blank line are
not read), so measurements typed in the page make the harness's report.
"""

from __future__ import annotations

import csv
from pathlib import Path


class MeasuredError(Exception):
    pass


def load_measured(path: str | Path, plan_names: list[str]) -> dict[tuple[str, int], tuple[list[float], int]]:
    """{(plan name, plan line): ([x, y, z] mean, count)}."""
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as e:
        raise MeasuredError(f"{path}: cannot read: {e.strerror}") from None
    # the first section, without comments, each line with its number in the file
    numbered = [(n, ln) for n, ln in enumerate(text.splitlines(), start=1) if not ln.startswith("#")]
    while numbered and not numbered[0][1].strip():
        numbered.pop(0)
    end = next((i for i, (_, ln) in enumerate(numbered) if not ln.strip()), len(numbered))
    first = numbered[:end]
    rows = list(csv.DictReader([ln for _, ln in first]))
    line_of = [n for n, _ in first[1:]]
    if not rows:
        raise MeasuredError(f"{path}: no rows (a header plan_line,x_mm,y_mm,z_mm and one row per measurement)")
    header = set(rows[0].keys())
    missing = {"plan_line", "x_mm", "y_mm", "z_mm"} - header
    if missing:
        raise MeasuredError(f"{path}: missing column(s) {', '.join(sorted(missing))}")
    has_plan = "plan" in header
    if not has_plan and len(plan_names) != 1:
        raise MeasuredError(f"{path}: {len(plan_names)} plans in this run: add a 'plan' column naming each row's plan")
    sums: dict[tuple[str, int], list[float]] = {}
    for k, row in enumerate(rows):
        i = line_of[k] if k < len(line_of) else k + 2
        plan = (row.get("plan") or "").strip() if has_plan else plan_names[0]
        if plan not in plan_names:
            matches = [p for p in plan_names if Path(p).stem == plan]
            if len(matches) != 1:
                raise MeasuredError(f"{path}:{i}: no plan '{plan}' in this run ({', '.join(plan_names)})")
            plan = matches[0]
        try:
            line = int(row["plan_line"])
            xyz = [float(row["x_mm"]), float(row["y_mm"]), float(row["z_mm"])]
        except (TypeError, ValueError):
            raise MeasuredError(f"{path}:{i}: plan_line must be a whole number and x_mm, y_mm, z_mm numbers") from None
        s = sums.setdefault((plan, line), [0.0, 0.0, 0.0, 0])
        for k in range(3):
            s[k] += xyz[k]
        s[3] += 1
    return {k: ([v[0] / v[3], v[1] / v[3], v[2] / v[3]], int(v[3])) for k, v in sums.items()}
