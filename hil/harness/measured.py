"""Tool positions measured on a real arm (the thesis's tape-measure method, section 5.2).

A CSV with a header and the columns `plan_line,x_mm,y_mm,z_mm` (any order; more columns are
ignored), one row per measured plan step: the tool's position in the base frame after the
command on that line of the plan. An optional `plan` column names the plan (its file name,
as `thesis-single-joint.arm`); without it the CSV belongs to the only plan of the run. A line
measured several times is averaged (the report says how many).
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
    rows = list(csv.DictReader(text.splitlines()))
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
    for i, row in enumerate(rows, start=2):
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
