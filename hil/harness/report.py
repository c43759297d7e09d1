"""The report folder: report.md and report.html (the same content), PNG plots (matplotlib,
Agg; none with `--no-plots`, and matplotlib is then not even imported), commands.csv (one row
per command, every figure), and per plan the serial transcript and, on the virtual Nano, its
JSON report.
"""

from __future__ import annotations

import csv
import html
import math
from dataclasses import dataclass
from pathlib import Path

import articula

from .runner import PlanResult, Record

AXES = ("x", "y", "z")
PCT_MIN_MM = 1.0  # a per-axis % needs a coordinate this far from 0 (kPctMinMm, host/lib/experiment.h; for the text)


# ---------------------------------------------------------------- small helpers

def _plt():
    """matplotlib's pyplot on Agg, imported when the first plot is drawn (a second of a run)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def f3(v, nd=3) -> str:
    if v is None:
        return "—"
    if isinstance(v, float) and (math.isnan(v) or math.isinf(v)):
        return "—"
    return f"{v:.{nd}f}"


def vec(v, nd=3) -> str:
    return "—" if v is None else ", ".join(f"{x:.{nd}f}" for x in v)


def ints(v) -> str:
    return "—" if v is None else " ".join(str(x) for x in v)


def dist(a, b) -> float:
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))


def yn(v) -> str:
    return "—" if v is None else ("yes" if v else "**no**")


@dataclass
class Run:
    """Everything the report needs about one harness run."""
    results: list[PlanResult]
    target: str
    robot_name: str
    robot_path: str
    vnano: str | None
    elf: str | None
    started: str
    wall_s: float
    settings_override: dict
    measured_path: str | None
    has_pins: bool
    command_line: str

    @property
    def records(self) -> list[Record]:
        return [r for res in self.results for r in res.records]

    @property
    def faults(self):
        return [f for res in self.results for f in res.faults]


# ---------------------------------------------------------------- figures

def summary_figures(run: Run) -> dict:
    recs = run.records
    sent = [r for r in recs if r.sent]
    matched = sum(1 for r in recs if r.matched)
    worst_q = max((r for r in recs if r.pred is not None and r.reply == r.pred.reply),
                  key=lambda r: r.pred.error_mm, default=None)
    timed = [r for r in recs if r.duration_error_pct is not None]
    worst_d = max(timed, key=lambda r: abs(r.duration_error_pct), default=None)
    mean_d = sum(abs(r.duration_error_pct) for r in timed) / len(timed) if timed else None
    total_pred = sum(r.pred.seconds for r in timed)
    total_meas = sum(r.measured_s for r in timed)
    return {
        "plans": len(run.results), "commands": len(recs), "sent": len(sent), "matched": matched,
        "mismatched": len(recs) - matched,
        "rejected_expected": sum(1 for r in recs if r.command.expect != "ok" and r.reply == r.command.expect),
        "worst_q": worst_q, "timed": len(timed), "worst_d": worst_d, "mean_d": mean_d,
        "total_pred": total_pred, "total_meas": total_meas, "faults": len(run.faults),
        "ok": matched == len(recs) and not run.faults,
    }


def summary_text(run: Run, report_path: Path) -> str:
    s = summary_figures(run)
    lines = [f"articula harness: {s['plans']} plan(s), {s['commands']} commands on the {run.target}"
             f" ({s['rejected_expected']} refused as the plans expect)"]
    what = "prediction = firmware = pins" if run.has_pins else "prediction = firmware"
    lines.append(f"  steps matched: {s['matched']}/{s['commands']} ({what})")
    if s["worst_q"] is not None:
        w = s["worst_q"]
        lines.append(f"  worst predicted quantization error: {w.pred.error_mm:.3f} mm "
                     f"({w.plan}:{w.line} {articula.line_command(w.command.text)})")
    if s["timed"]:
        w = s["worst_d"]
        src = "the pins' cycle stamps" if run.has_pins else "the host clock"
        lines.append(f"  duration: {s['timed']} actions timed by {src}, predicted {s['total_pred']:.3f} s, measured "
                     f"{s['total_meas']:.3f} s; error mean {s['mean_d']:.3f} %, worst {w.duration_error_pct:+.3f} % "
                     f"({w.plan}:{w.line})")
    else:
        lines.append("  duration: no action timed")
    lines.append(f"  faults: {s['faults']}")
    for f in run.faults[:10]:
        lines.append(f"    {f.where()}: {f.command + ': ' if f.command else ''}{f.message}")
    if len(run.faults) > 10:
        lines.append(f"    ... {len(run.faults) - 10} more in the report")
    lines.append(f"  result: {'every command matched' if s['ok'] else 'MISMATCH OR FAULT'}")
    lines.append(f"  report: {report_path}")
    return "\n".join(lines)


# ---------------------------------------------------------------- analyses

def single_joint(run: Run):
    """Rows of the thesis's single-joint test: accepted and refused."""
    acc, refused = [], []
    for r in run.records:
        if not r.command.single_joint or r.pred is None:
            continue
        joint, angle = r.command.single_joint
        if r.reply != "ok" or r.pred.reply != "ok":
            refused.append((joint, angle, r))
            continue
        ideal, quant = r.pred.tool_ideal, r.pred.tool_quantized
        # the numbers are the host library's (host/lib/experiment.h), as the studio's are
        e = articula.axis_errors(quant, ideal)
        row = {"joint": joint, "angle": angle, "rec": r, "ideal": ideal, "quant": quant, "err": e["mm"], "pct": e["pct"]}
        if r.measured_xyz is not None:
            m = r.measured_xyz
            eq, ei = articula.axis_errors(m, quant), articula.axis_errors(m, ideal)
            row["m_err_q"], row["m_pct_q"] = eq["mm"], eq["pct"]
            row["m_err_i"], row["m_pct_i"] = ei["mm"], ei["pct"]
        acc.append(row)
    return acc, refused


# Which positions a Table 4 compares: (value, reference) of a single-joint row.
TABLE4_PAIRS = {"err": ("quant", "ideal"), "m_err_q": ("measured", "quant"), "m_err_i": ("measured", "ideal")}


def table4(rows, err_key="err", pct_key="pct"):
    """Per joint and axis: max %, max mm, average mm (thesis Table 4), from the host library
    (articula.table4: host/lib/experiment.h, the studio's Experiment panel's too)."""
    value_key, ref_key = TABLE4_PAIRS[err_key]
    points = [(r["joint"], r["rec"].measured_xyz if value_key == "measured" else r[value_key], r[ref_key])
              for r in rows if err_key in r]
    out = {}
    for t in articula.table4(points):
        for k, a in enumerate(t["axes"]):
            out[(t["joint"], k)] = (a["max_pct"], a["max_mm"], a["avg_mm"])
    return sorted({j for j, _ in out}), out


def repeatability(res: PlanResult, robot_zero_tool):
    """Per chain: start, destination and return (thesis Table 5)."""
    # the chains as the host library groups them (articula.repeat_chains), the studio's too
    by_line = {r.line: r for r in res.records}
    grouped = articula.repeat_chains([{"line": r.line, "repeat": list(r.command.repeat)
                                       if r.command.repeat and r.pred is not None else None} for r in res.records])
    out = []
    for g in grouped:
        n = g["chain"]
        c = {"out": [by_line[g["line_out"]]] * g["moves"],
             "back": [by_line[g["line_back"]]] * g["back_moves"] if g["line_back"] is not None else []}
        before = by_line.get(g["line_before"]) if g["line_before"] is not None else None
        start_q = before.pred.tool_quantized if before is not None and before.pred else robot_zero_tool
        start_steps = before.pred.steps if before is not None and before.pred else None
        zeros = [0] * len(c["out"][0].pred.steps)
        start_fw = before.fw_steps if before is not None else zeros
        start_pins = before.pins if before is not None else (zeros if run_has_pins(res) else None)
        dest = c["out"][-1]
        back = c["back"][-1] if c["back"] else None
        start_m = before.measured_xyz if before is not None else None
        # the distances are the host library's Table 5 (articula.table5: host/lib/experiment.h),
        # as the studio's Experiment panel's are
        t5 = articula.table5([{"chain": n, "moves": len(c["out"]), "back_moves": len(c["back"]), "start": list(start_q),
                               "dest_quant": list(dest.pred.tool_quantized), "dest_ideal": list(dest.pred.tool_ideal),
                               "back_quant": list(back.pred.tool_quantized) if back else None,
                               "start_measured": list(start_m) if start_m is not None else None,
                               "dest_measured": list(dest.measured_xyz) if dest.measured_xyz is not None else None,
                               "back_measured": list(back.measured_xyz) if back and back.measured_xyz is not None
                               else None}])[0]
        row = {"n": n, "moves": len(c["out"]), "back_moves": len(c["back"]), "dest": dest, "back": back,
               "start_q": start_q,
               "dest_err": t5["dest_error_mm"],
               "ret_err": t5["return_error_mm"],
               "fw_back": (back.fw_steps == start_fw) if back and back.fw_steps is not None else None,
               "pins_back": (back.pins == start_pins) if back and back.pins is not None and start_pins is not None
               else None,
               "start_steps": start_steps}
        if t5["measured_dest_mm"] is not None:
            row["m_dest_q"] = t5["measured_dest_mm"]
            row["m_dest_i"] = t5["measured_dest_ideal_mm"]
        if t5["measured_return_mm"] is not None:
            row["m_ret"] = t5["measured_return_mm"]
            row["m_ret_ref"] = "measured start" if t5["return_from_measured_start"] else "predicted start"
        out.append(row)
    return out


def run_has_pins(res: PlanResult) -> bool:
    return any(r.pins is not None for r in res.records)


# ---------------------------------------------------------------- plots

def _plan_bounds(ax, results, offsets):
    for res, off in zip(results, offsets):
        ax.axvline(off - 0.5, color="0.8", lw=0.8, zorder=0)


def plot_steps(run: Run, path: Path, motors: list[str]) -> None:
    plt = _plt()
    recs = run.records
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(10, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1.2]})
    xs = list(range(len(recs)))
    colors = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown"]
    for m, name in enumerate(motors):
        c = colors[m % len(colors)]
        ax1.plot(xs, [r.pred.steps[m] if r.pred else math.nan for r in recs], "-", color=c, lw=1.2,
                 label=f"{name}: predicted")
        ax1.plot(xs, [r.fw_steps[m] if r.fw_steps else math.nan for r in recs], "o", color=c, ms=3.5, mfc="none",
                 label=f"{name}: firmware status")
        if run.has_pins:
            ax1.plot(xs, [r.pins[m] if r.pins else math.nan for r in recs], "x", color=c, ms=3,
                     label=f"{name}: decoded pins")
    ax1.set_ylabel("motor position (steps)")
    ax1.legend(fontsize=7, ncol=len(motors), loc="upper left", frameon=False)
    ax1.set_title("Step agreement after every command")
    dfw = [sum(abs(a - b) for a, b in zip(r.fw_steps, r.pred.steps)) if r.fw_steps and r.pred else math.nan
           for r in recs]
    ax2.bar([x - 0.2 for x in xs], dfw, width=0.4, color="tab:red", label="|firmware - prediction|")
    if run.has_pins:
        dp = [sum(abs(a - b) for a, b in zip(r.pins, r.pred.steps)) if r.pins and r.pred else math.nan for r in recs]
        ax2.bar([x + 0.2 for x in xs], dp, width=0.4, color="tab:purple", label="|pins - prediction|")
    bad = [x for x, r in zip(xs, recs) if not r.matched]
    if bad:
        ax2.plot(bad, [0] * len(bad), "v", color="k", ms=5, label="not matched")
    offs = [v for v in dfw if not math.isnan(v)]
    if run.has_pins:
        offs += [v for v in dp if not math.isnan(v)]
    if not any(offs):
        ax2.text(0.5, 0.5, "0 steps off after every command", transform=ax2.transAxes, ha="center", va="center",
                 fontsize=9, color="0.3")
    ymax = max(offs + [1])
    ax2.set_ylim(-0.1 * ymax, ymax * 1.3)
    ax2.set_ylabel("steps off")
    ax2.set_xlabel("command (plans in order)")
    ax2.xaxis.get_major_locator().set_params(integer=True)
    ax2.legend(fontsize=7, loc="lower right", frameon=False, ncol=3)
    offsets, off = [], 0
    for res in run.results:
        offsets.append(off)
        off += len(res.records)
    for ax in (ax1, ax2):
        _plan_bounds(ax, run.results, offsets)
    for res, o in zip(run.results, offsets):
        ax2.annotate(res.plan.name, (o, 0.97), xycoords=("data", "axes fraction"), fontsize=7, va="top",
                     color="0.4")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def plot_quantization(run: Run, path: Path) -> None:
    plt = _plt()
    recs = [r for r in run.records if r.pred is not None]
    xs = list(range(len(recs)))
    fig, ax = plt.subplots(figsize=(10, 3.8))
    for k, (axis, c) in enumerate(zip(AXES, ("tab:blue", "tab:orange", "tab:green"))):
        ax.plot(xs, [r.pred.tool_quantized[k] - r.pred.tool_ideal[k] for r in recs], ".", color=c, ms=5,
                label=f"{axis}: quantized - ideal")
    ax.plot(xs, [r.pred.error_mm for r in recs], "_", color="k", ms=7, label="distance")
    ax.axhline(0, color="0.7", lw=0.8)
    ax.set_xlabel("command (plans in order)")
    ax.set_ylabel("mm")
    ax.set_title("Predicted quantization error of the tool position (whole steps vs commanded angles)")
    ax.legend(fontsize=7, ncol=4, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def plot_durations(run: Run, path: Path) -> None:
    plt = _plt()
    timed = [r for r in run.records if r.duration_error_pct is not None]
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 3.8))
    if timed:
        p = [r.pred.seconds for r in timed]
        m = [r.measured_s for r in timed]
        ax1.plot(p, m, "o", ms=4, mfc="none")
        hi = max(p + m) * 1.05
        ax1.plot([0, hi], [0, hi], "-", color="0.6", lw=0.8, label="measured = predicted")
        ax1.set_xlim(0, hi)
        ax1.set_ylim(0, hi)
        ax1.legend(fontsize=7, frameon=False)
        ax2.plot(range(len(timed)), [r.duration_error_pct for r in timed], ".", ms=5)
        ax2.axhline(0, color="0.7", lw=0.8)
    ax1.set_xlabel("predicted duration (s)")
    ax1.set_ylabel("measured duration (s)")
    ax1.set_title("Duration of each timed action")
    ax2.set_xlabel("timed action")
    ax2.set_ylabel("(measured - predicted) / predicted, %")
    ax2.set_title("Duration error")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def plot_single_joint(rows, joint: int, motor: str, path: Path) -> None:
    plt = _plt()
    jr = sorted((r for r in rows if r["joint"] == joint), key=lambda r: r["angle"])
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(10, 3.6))
    xs = [r["angle"] for r in jr]
    for k, (axis, c) in enumerate(zip(AXES, ("tab:blue", "tab:orange", "tab:green"))):
        ax1.plot(xs, [r["err"][k] for r in jr], "o-", color=c, ms=4, label=f"{axis}: quantized vs ideal")
        ax2.plot(xs, [r["pct"][k] if r["pct"][k] is not None else math.nan for r in jr], "o-", color=c, ms=4,
                 label=f"{axis}")
        if any("m_err_q" in r for r in jr):
            ax1.plot(xs, [r["m_err_q"][k] if "m_err_q" in r else math.nan for r in jr], "s--", color=c, ms=4,
                     mfc="none", label=f"{axis}: measured vs quantized")
            ax2.plot(xs, [r["m_pct_q"][k] if "m_pct_q" in r and r["m_pct_q"][k] is not None else math.nan
                          for r in jr], "s--", color=c, ms=4, mfc="none", label=f"{axis}: measured")
    ax1.set_xlabel(f"joint {joint} angle, thesis convention (deg)")
    ax2.set_xlabel(f"joint {joint} angle, thesis convention (deg)")
    ax1.set_ylabel("absolute error (mm)")
    ax2.set_ylabel("error (% of the coordinate)")
    ax1.set_title(f"Tool error vs joint {joint} ({motor}) angle")
    ax2.set_title(f"Percentage error vs joint {joint} angle")
    ax1.legend(fontsize=7, frameon=False)
    ax2.legend(fontsize=7, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def plot_repeatability(rows, path: Path) -> None:
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7, 3.4))
    ns = [r["n"] for r in rows]
    ax.bar([n - 0.2 for n in ns], [r["dest_err"] for r in rows], width=0.4, label="at the destination (quantized vs ideal)")
    ax.bar([n + 0.2 for n in ns], [r["ret_err"] or 0.0 for r in rows], width=0.4,
           label="on return to the start (quantized)")
    for r in rows:
        if r["ret_err"] is not None:
            ax.annotate(f"{r['ret_err']:.3f}", (r["n"] + 0.2, r["ret_err"]), ha="center", va="bottom", fontsize=7)
    if any("m_dest_q" in r for r in rows):
        ax.plot(ns, [r.get("m_dest_q", math.nan) for r in rows], "k^", label="measured vs predicted, destination")
    ax.set_xlabel("number of movements")
    ax.set_ylabel("tool position error (mm)")
    ax.set_xticks(ns)
    ax.set_title("Repeatability chains")
    ax.legend(fontsize=7, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


# ---------------------------------------------------------------- document

class Doc:
    """Blocks rendered to Markdown and to HTML."""

    def __init__(self):
        self.blocks: list[tuple] = []

    def h(self, level: int, text: str):
        self.blocks.append(("h", level, text))

    def p(self, text: str):
        self.blocks.append(("p", text))

    def ul(self, items: list[str]):
        self.blocks.append(("ul", items))

    def table(self, head: list[str], rows: list[list], right: set[int] | None = None):
        self.blocks.append(("table", head, [[str(c) for c in row] for row in rows], right or set()))

    def img(self, src: str, alt: str):
        self.blocks.append(("img", src, alt))

    def code(self, text: str):
        self.blocks.append(("code", text))

    def markdown(self) -> str:
        out = []
        for b in self.blocks:
            if b[0] == "h":
                out.append("#" * b[1] + " " + b[2])
            elif b[0] == "p":
                out.append(b[1])
            elif b[0] == "ul":
                out.append("\n".join("- " + i for i in b[1]))
            elif b[0] == "table":
                head, rows, right = b[1], b[2], b[3]
                esc = lambda s: s.replace("|", "\\|")  # noqa: E731
                t = ["| " + " | ".join(esc(h) for h in head) + " |",
                     "|" + "|".join("---:" if i in right else "---" for i in range(len(head))) + "|"]
                t += ["| " + " | ".join(esc(c) for c in row) + " |" for row in rows]
                out.append("\n".join(t))
            elif b[0] == "img":
                out.append(f"![{b[2]}]({b[1]})")
            elif b[0] == "code":
                out.append("```\n" + b[1] + "\n```")
        return "\n\n".join(out) + "\n"

    @staticmethod
    def _inline(text: str) -> str:
        """`code` and **bold** of the Markdown, escaped."""
        parts = text.split("`")
        out = []
        for i, part in enumerate(parts):
            if i % 2:
                out.append("<code>" + html.escape(part) + "</code>")
            else:
                segs = html.escape(part).split("**")
                out.append("".join(("<b>" + s + "</b>") if j % 2 else s for j, s in enumerate(segs)))
        return "".join(out)

    def html(self, title: str) -> str:
        out = ["<!DOCTYPE html>", "<html><head><meta charset='utf-8'>", f"<title>{html.escape(title)}</title>",
               "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;line-height:1.4}"
               "table{border-collapse:collapse;margin:0.8em 0;font-size:0.85em}"
               "td,th{border:1px solid #ccc;padding:2px 6px}th{background:#f0f0f0}td.r{text-align:right}"
               "code,pre{background:#f6f6f6}pre{padding:0.6em;overflow-x:auto}img{max-width:100%}</style>",
               "</head><body>"]
        for b in self.blocks:
            if b[0] == "h":
                out.append(f"<h{b[1]}>{self._inline(b[2])}</h{b[1]}>")
            elif b[0] == "p":
                out.append(f"<p>{self._inline(b[1])}</p>")
            elif b[0] == "ul":
                out.append("<ul>" + "".join(f"<li>{self._inline(i)}</li>" for i in b[1]) + "</ul>")
            elif b[0] == "table":
                head, rows, right = b[1], b[2], b[3]
                t = ["<table><tr>" + "".join(f"<th>{self._inline(h)}</th>" for h in head) + "</tr>"]
                for row in rows:
                    t.append("<tr>" + "".join(
                        f"<td class='r'>{self._inline(c)}</td>" if i in right else f"<td>{self._inline(c)}</td>"
                        for i, c in enumerate(row)) + "</tr>")
                t.append("</table>")
                out.append("".join(t))
            elif b[0] == "img":
                out.append(f"<p><img src='{html.escape(b[1])}' alt='{html.escape(b[2])}'></p>")
            elif b[0] == "code":
                out.append("<pre>" + html.escape(b[1]) + "</pre>")
        out.append("</body></html>")
        return "\n".join(out) + "\n"


# ---------------------------------------------------------------- the report

def _cmd(r: Record) -> str:
    return "`" + articula.line_command(r.command.text) + "`"


def write_csv(run: Run, path: Path, motors: int, joints: int) -> None:
    """commands.csv: angles in degrees (actuator angles of the motors; `pred_joint_*` the DH
    joint values the steps give), positions in mm, durations in s."""
    head = ["plan", "plan_line", "command", "kind", "expect", "joint", "thesis_deg", "chain", "leg",
            "predicted_reply", "firmware_reply"]
    head += [f"pred_steps_{m}" for m in range(motors)] + [f"fw_steps_{m}" for m in range(motors)]
    head += [f"pin_steps_{m}" for m in range(motors)] + [f"pin_made_{m}" for m in range(motors)]
    head += ["firmware_match", "pins_match", "matched", "fw_state"]
    head += [f"pred_angle_{m}" for m in range(motors)] + [f"fw_angle_{m}" for m in range(motors)]
    head += [f"pred_joint_{j}" for j in range(joints)]
    head += ["ideal_x", "ideal_y", "ideal_z", "quant_x", "quant_y", "quant_z", "quant_err_x", "quant_err_y",
             "quant_err_z", "quant_err_mm", "target_x", "target_y", "target_z", "target_err_mm",
             "pred_duration_s", "measured_duration_s", "duration_source", "duration_err_pct", "duration_diff_us",
             "first_interval_s",
             "step_events", "coil_faults", "measured_x", "measured_y", "measured_z", "measured_n",
             "measured_err_quant_mm", "measured_err_ideal_mm", "faults"]

    def cols(v, n, fmt="{}"):
        return [fmt.format(x) for x in v] if v is not None else [""] * n

    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(head)
        for r in run.records:
            p = r.pred
            sj = r.command.single_joint
            rp = r.command.repeat
            row = [r.plan, r.line, articula.line_command(r.command.text), r.command.kind, r.command.expect,
                   sj[0] if sj else "", f"{sj[1]:g}" if sj else "", rp[0] if rp else "", rp[1] if rp else "",
                   p.reply if p else "", r.reply or ""]
            row += cols(p.steps if p else None, motors) + cols(r.fw_steps, motors)
            row += cols(r.pins, motors) + cols(r.pin_delta, motors)
            row += [r.firmware_match if r.firmware_match is not None else "",
                    r.pins_match if r.pins_match is not None else "", r.matched,
                    r.status.state if r.status else ""]
            row += cols(p.actuator_deg if p else None, motors, "{:.4f}")
            row += cols(r.status.angles if r.status else None, motors, "{:.3f}")
            row += cols(p.joints if p else None, joints, "{:.4f}")
            if p:
                row += [f"{v:.4f}" for v in p.tool_ideal] + [f"{v:.4f}" for v in p.tool_quantized]
                row += [f"{q - i:.4f}" for q, i in zip(p.tool_quantized, p.tool_ideal)] + [f"{p.error_mm:.4f}"]
                row += cols(p.target_mm, 3, "{:.3f}") + [f"{p.target_error_mm:.4f}" if p.target_error_mm is not None
                                                         else ""]
                row += [f"{p.seconds:.6f}"]
            else:
                row += [""] * 15
            row += [f"{r.measured_s:.9f}" if r.measured_s is not None else "", r.measured_source,
                    f"{r.duration_error_pct:.5f}" if r.duration_error_pct is not None else "",
                    f"{(r.measured_s - p.seconds) * 1e6:.3f}" if r.duration_error_pct is not None else "",
                    f"{r.first_interval_s:.6f}" if r.first_interval_s is not None else "",
                    r.step_events if r.pins is not None else "", len(r.coil_faults) if r.pins is not None else ""]
            if r.measured_xyz is not None and p:
                row += [f"{v:.3f}" for v in r.measured_xyz] + [r.measured_count,
                                                               f"{dist(r.measured_xyz, p.tool_quantized):.3f}",
                                                               f"{dist(r.measured_xyz, p.tool_ideal):.3f}"]
            else:
                row += [""] * 6
            row += ["; ".join(f"{x.kind}: {x.message}" for x in r.faults)]
            w.writerow(row)


def build(run: Run, out: Path, robot, plots: bool = True) -> Path:
    """The report folder `out`; without `plots`, no PNG (the report says so once)."""
    out.mkdir(parents=True, exist_ok=True)
    motors = [m.name for m in robot.motors]
    s = summary_figures(run)
    d = Doc()

    def picture(name: str, alt: str, draw) -> None:
        if plots:
            draw(out / name)
            d.img(name, alt)
    d.h(1, "Articula hardware-in-the-loop report")
    meta = [["run", f"{run.started}, {run.wall_s:.1f} s"], ["target", run.target]]
    if run.vnano:
        meta.append(["virtual Nano", f"`{run.vnano}`"])
    if run.elf:
        meta.append(["firmware ELF", f"`{run.elf}`"])
    infos = sorted({res.info_line for res in run.results if res.info_line})
    if infos:
        meta.append(["firmware says", ", ".join(f"`{i}`" for i in infos)])
    meta.append(["robot file", f"{run.robot_name} (`{run.robot_path}`)"])
    meta.append(["prediction", "`articula.Robot.predict(PLAN, settings=...)` (the `articula` package; = `articula predict ROBOT PLAN --json`)"])
    meta.append(["plans", ", ".join(f"`{res.plan.path}`" for res in run.results)])
    if run.settings_override:
        meta.append(["settings", "--settings " + ",".join(f"{k}={v:g}" for k, v in sorted(run.settings_override.items()))
                     + " (sent before each plan)"])
    if run.measured_path:
        meta.append(["measured positions", f"`{run.measured_path}`"])
    meta.append(["command", f"`{run.command_line}`"])
    if not plots:
        meta.append(["plots", "not drawn (--no-plots): the tables below have every figure"])
    d.table(["", ""], meta)

    # ---- summary
    d.h(2, "Summary")
    if s["ok"]:
        d.p(f"**Every command matched**: {s['commands']} commands, prediction = firmware"
            + (" = pins" if run.has_pins else "") + ", no fault.")
    else:
        d.p(f"**{s['mismatched']} of {s['commands']} commands did not match, {s['faults']} fault(s).**")
    rows = []
    for res in run.results:
        recs = res.records
        timed = [r for r in recs if r.duration_error_pct is not None]
        wq = max((r.pred.error_mm for r in recs if r.pred and r.reply == r.pred.reply), default=None)
        wd = max(timed, key=lambda r: abs(r.duration_error_pct), default=None)
        rows.append([f"`{res.plan.name}`", res.plan.title, len(recs),
                     sum(1 for r in recs if r.command.expect != "ok" and r.reply == r.command.expect),
                     f"{sum(1 for r in recs if r.matched)}/{len(recs)}", f3(wq), len(timed),
                     f"{wd.duration_error_pct:+.3f}" if wd else "—", len(res.faults)])
    d.table(["plan", "title", "commands", "refused as expected", "steps matched", "worst quantization error mm",
             "actions timed", "worst duration error %", "faults"], rows, right={2, 3, 5, 6, 7, 8})
    d.code(summary_text(run, out / "report.md"))

    # ---- faults
    d.h(2, "Faults")
    if run.faults:
        d.table(["where", "command", "kind", "what"],
                [[f.where(), f"`{f.command}`" if f.command else "", f.kind, f.message] for f in run.faults])
    else:
        d.p("None: no error reply the plan did not expect, no timeout, no vanished port, no reset, no coil fault.")
    for res in run.results:
        if res.aborted:
            d.p(f"`{res.plan.name}` stopped early: {res.aborted}")

    # ---- steps
    d.h(2, "Step agreement")
    d.p("After each command the harness polls `?` until the arm reports `Idle`, then compares the status "
        "report's motor steps (`S`) and angles (`A`) with `articula predict`'s steps for that line"
        + (", and with the positions the virtual Nano decoded from the motor driver pins at that moment "
           "(read from its step trace as it runs: the cumulative position of every motor when the "
           "firmware reports `Idle`; the coil events since the previous `Idle` are the command's own, "
           "`pins made`)." if run.has_pins else ". On a real port there are no pins to decode.")
        + " A command matches when the reply, the steps, the angles and (once set) the gripper agree.")
    picture("steps.png", "steps per motor after every command: prediction, firmware, pins",
            lambda path: plot_steps(run, path, motors))
    for res in run.results:
        d.h(3, f"{res.plan.title} (`{res.plan.name}`)")
        for note in res.plan.notes:
            d.p(note)
        head = ["line", "command", "expect", "predicted", "firmware", "predicted steps", "firmware steps"]
        if run.has_pins:
            head += ["pins", "pins made"]
        head += ["match"]
        trows = []
        for r in res.records:
            row = [r.line, _cmd(r), r.command.expect, r.pred.reply if r.pred else "—", r.reply or "not run",
                   ints(r.pred.steps if r.pred else None), ints(r.fw_steps)]
            if run.has_pins:
                row += [ints(r.pins), ints(r.pin_delta)]
            row += ["yes" if r.matched else "**no**"]
            trows.append(row)
        d.table(head, trows, right={0})

    # ---- quantization
    d.h(2, "Predicted quantization error")
    d.p("How far the tool is from where the commanded angles would put it, because every motor stops on a "
        "whole step: `articula predict`'s quantized tool position minus its ideal one, per axis, in the robot's "
        "base frame (x forward, z up, mm).")
    picture("quantization.png", "predicted quantization error per axis", lambda path: plot_quantization(run, path))
    qrows = []
    for res in run.results:
        recs = [r for r in res.records if r.pred]
        if not recs:
            continue
        per_axis = []
        for k in range(3):
            w = max(recs, key=lambda r: abs(r.pred.tool_quantized[k] - r.pred.tool_ideal[k]))
            per_axis.append(f"{abs(w.pred.tool_quantized[k] - w.pred.tool_ideal[k]):.3f} (line {w.line})")
        w = max(recs, key=lambda r: r.pred.error_mm)
        qrows.append([f"`{res.plan.name}`"] + per_axis + [f"{w.pred.error_mm:.3f} (line {w.line})"])
    d.table(["plan", "worst x mm", "worst y mm", "worst z mm", "worst distance mm"], qrows)

    # ---- durations
    d.h(2, "Durations")
    if run.has_pins:
        d.p("Predicted: `articula predict`'s duration of each action (`motion.h`'s step profile on the 2 MHz "
            "tick). Measured on the virtual Nano from the cycle stamps of the decoded steps: the span from the "
            "move's first step to its last, plus the profile's first interval (from rest to the first step: no "
            "pin shows when a move starts, so that interval is computed from `$0` and `$1` as `motion.h` does). "
            "Gripper actions (`G`, `S`) leave no step on the pins and are not timed here.")
    else:
        d.p("Predicted: `articula predict`'s duration of each action. Measured with the host's clock, from "
            "sending the line to the first `Idle` status report: it includes the line's transmission and up to "
            "one polling interval, so it errs by some milliseconds.")
    picture("durations.png", "predicted vs measured durations", lambda path: plot_durations(run, path))
    drows = []
    for res in run.results:
        timed = [r for r in res.records if r.duration_error_pct is not None]
        if not timed:
            drows.append([f"`{res.plan.name}`", 0, "—", "—", "—", "—", "—"])
            continue
        wd = max(timed, key=lambda r: abs(r.duration_error_pct))
        wu = max(abs(r.measured_s - r.pred.seconds) for r in timed) * 1e6
        drows.append([f"`{res.plan.name}`", len(timed), f"{sum(r.pred.seconds for r in timed):.6f}",
                      f"{sum(r.measured_s for r in timed):.6f}",
                      f"{sum(abs(r.duration_error_pct) for r in timed) / len(timed):.4f}",
                      f"{wd.duration_error_pct:+.4f} (line {wd.line})", f"{wu:.1f}"])
    d.table(["plan", "actions timed", "predicted s", "measured s", "mean abs error %", "worst error %",
             "worst difference us"], drows, right={1, 2, 3, 4, 6})

    # ---- single joint
    sj_rows, refused = single_joint(run)
    if sj_rows or refused:
        d.h(2, "Single-joint movements (thesis 5.2, Table 4, Figs. 30-32)")
        d.p("From the start pose one joint moves to an angle of the thesis's appendix K, the tool position is "
            "recorded, and the joint moves back. Angles are in the thesis's convention (the plan's notes give the "
            "mapping to the arm's actuator angles). Here the error is the predicted **quantization error**: the "
            "tool position of the whole steps against that of the exact angles, per axis (x forward, y left, "
            "z up, mm); % is that error as a share of the coordinate's size, as the thesis gives it (left out "
            f"where the coordinate is within {PCT_MIN_MM:g} mm of 0)."
            + (" With measured positions, the tables after it compare them with the prediction." if
               run.measured_path else ""))
        joints, t4 = table4(sj_rows)
        head = ["axis"]
        for j in joints:
            head += [f"joint {j} max %", f"joint {j} max mm", f"joint {j} avg mm"]
        rows = []
        for k, axis in enumerate(AXES):
            row = [axis.upper()]
            for j in joints:
                mp, mx, avg = t4[(j, k)]
                row += [f3(mp, 2), f3(mx), f3(avg)]
            rows.append(row)
        d.p("**Quantized vs ideal tool position, per joint and axis** (the thesis's Table 4 compared its "
            "physical arm with its simulation; this is what whole steps alone leave):")
        d.table(head, rows, right=set(range(1, len(head))))
        if any("m_err_q" in r for r in sj_rows):
            for key, pkey, what in (("m_err_q", "m_pct_q", "Measured vs predicted (quantized)"),
                                    ("m_err_i", "m_pct_i", "Measured vs ideal")):
                joints_m, tm = table4(sj_rows, key, pkey)
                rows = []
                for k, axis in enumerate(AXES):
                    row = [axis.upper()]
                    for j in joints_m:
                        mp, mx, avg = tm[(j, k)]
                        row += [f3(mp, 2), f3(mx), f3(avg)]
                    rows.append(row)
                hm = ["axis"] + [f"joint {j} {c}" for j in joints_m for c in ("max %", "max mm", "avg mm")]
                d.p(f"**{what}**, per joint and axis:")
                d.table(hm, rows, right=set(range(1, len(hm))))
            # the verdict per joint: the host library's (articula.joint_verdicts), the studio's too
            verdicts = articula.joint_verdicts([{"joint": r["joint"], "ideal": list(r["ideal"]), "quant": list(r["quant"]),
                                                 "measured": list(r["rec"].measured_xyz) if r["rec"].measured_xyz else None}
                                                for r in sj_rows])
            d.p("**Verdict per joint**: " + " ".join(f"joint {v['joint']}: {v['text']}" for v in verdicts))
        rows = []
        for r in sorted(sj_rows, key=lambda r: (r["joint"], r["rec"].line)):
            rec = r["rec"]
            row = [r["joint"], f"{r['angle']:g}", rec.line, _cmd(rec), vec(rec.pred.actuator_deg, 3),
                   vec(r["ideal"], 2), vec(r["quant"], 2)] + [f3(e) for e in r["err"]] + [f3(p, 2) for p in r["pct"]]
            if run.measured_path:
                row += [vec(rec.measured_xyz, 1) if rec.measured_xyz else "—"]
            rows.append(row)
        head = ["joint", "thesis deg", "line", "command", "actuator deg (steps)", "ideal tool mm",
                "quantized tool mm", "|dx| mm", "|dy| mm", "|dz| mm", "x %", "y %", "z %"]
        if run.measured_path:
            head += ["measured mm"]
        d.table(head, rows, right={0, 1, 2, 7, 8, 9, 10, 11, 12})
        if refused:
            d.p("Refused by the arm (beyond its limits), as the plan expects: " + "; ".join(
                f"joint {j} at {a:g} (line {r.line}, {_cmd(r)}: {r.reply or 'not run'})" for j, a, r in refused) + ".")
        for j in sorted({r["joint"] for r in sj_rows}):
            name = f"single-joint-{j}.png"
            picture(name, f"error vs joint {j} angle",
                    lambda path, j=j: plot_single_joint(sj_rows, j, motors[j] if j < len(motors) else str(j), path))

    # ---- repeatability
    zero_tool = list(robot.tool_from_actuators(robot.zero_angles))
    for res in run.results:
        rows_r = repeatability(res, zero_tool)
        if not rows_r:
            continue
        d.h(2, f"Repeatability (thesis 5.3, Table 5): `{res.plan.name}`")
        d.p("Chains of 1 to 5 moves out and the same moves reversed back. At the destination: the tool "
            "position of the whole steps against that of the exact commanded angles (the quantization error). "
            "On return: the tool position of the whole steps against the start's. Relative moves are held "
            "exactly in thousandths of a degree and rounded to a step once, so the motors come back to the very "
            "steps they started from" + (", which the firmware's status and the pins confirm." if run.has_pins
                                        else ", which the firmware's status confirms."))
        head = ["movements", "line out", "destination error mm", "line back", "error on return to start mm",
                "firmware steps back at start"]
        if run.has_pins:
            head.append("pins back at start")
        if any("m_dest_q" in r or "m_ret" in r for r in rows_r):
            head += ["measured vs predicted at destination mm", "measured return vs start mm"]
        trows = []
        for r in rows_r:
            row = [r["moves"], r["dest"].line, f3(r["dest_err"]), r["back"].line if r["back"] else "—",
                   f3(r["ret_err"]), yn(r["fw_back"])]
            if run.has_pins:
                row.append(yn(r["pins_back"]))
            if "measured vs predicted at destination mm" in head:
                row += [f3(r.get("m_dest_q")), f3(r.get("m_ret")) + (f" ({r['m_ret_ref']})" if "m_ret" in r else "")]
            trows.append(row)
        d.table(head, trows, right={0, 1, 2, 3, 4})
        name = f"repeatability-{Path(res.plan.name).stem}.png"
        picture(name, "repeatability", lambda path, rows_r=rows_r: plot_repeatability(rows_r, path))

    # ---- P targets
    prow = []
    for r in run.records:
        if r.command.word == "P" and r.pred is not None:
            t = r.pred.target_mm
            # the distances are the host library's (articula.tool_points), as the studio's are
            tp = articula.tool_points([{"line": r.line, "target": list(t), "quant": list(r.pred.tool_quantized),
                                        "ideal": list(r.pred.tool_ideal), "measured": None}])[0] if t else None
            ok = tp is not None and r.reply == "ok"
            prow.append([f"`{r.plan}`", r.line, _cmd(r), r.reply or "not run",
                         vec(r.pred.tool_quantized, 2) if r.reply == "ok" else "—",
                         f3(tp["model_from_target_mm"]) if ok else "—",
                         f3(tp["ideal_from_target_mm"], 4) if ok else "—", ints(r.fw_steps)])
    if prow:
        d.h(2, "Tool to points (P)")
        d.p("The firmware solves each target in closed form (in float), keeps the angles to 0.001 degree and "
            "moves to whole steps. `quantized tool` is where those steps put the tool and `from target` its "
            "distance to the target; `ideal from target` is that of the solved angles before the steps (the "
            "closed form's own error).")
        d.table(["plan", "line", "command", "reply", "quantized tool mm", "from target mm", "ideal from target mm",
                 "firmware steps"], prow, right={1, 5, 6})

    # ---- measured
    mrows = [r for r in run.records if r.measured_xyz is not None and r.pred is not None]
    if mrows:
        d.h(2, "Measured tool positions")
        d.p(f"From `{run.measured_path}` (tape measure, base frame, mm); a line measured several times is "
            "averaged (n).")
        d.table(["plan", "line", "command", "n", "measured mm", "predicted (quantized) mm", "ideal mm",
                 "measured - quantized mm", "measured - ideal mm"],
                [[f"`{r.plan}`", r.line, _cmd(r), r.measured_count, vec(r.measured_xyz, 2),
                  vec(r.pred.tool_quantized, 2), vec(r.pred.tool_ideal, 2),
                  f3(dist(r.measured_xyz, r.pred.tool_quantized)), f3(dist(r.measured_xyz, r.pred.tool_ideal))]
                 for r in mrows], right={1, 3, 7, 8})

    # ---- vnano
    vrows = []
    for res in run.results:
        rep = res.vnano_report
        if rep is None:
            continue
        jit = rep.get("jitter_us")
        vrows.append([f"`{res.plan.name}`", f3(rep.get("simulated_s")), f3(rep.get("wall_s")),
                      f3(rep.get("speed_x_realtime"), 2), rep.get("exit_reason", ""), rep.get("_exit", ""),
                      rep.get("faults", ""), f3(jit, 2) if jit is not None else "—",
                      rep.get("uart", {}).get("rx_overrun_risk", ""), f"`vnano/{Path(res.plan.name).stem}.json`"])
    if vrows:
        d.h(2, "Virtual Nano")
        d.p("One run of `articula-vnano` per plan (the firmware powers up at step 0 with blank EEPROM, as "
            "the prediction assumes), ended by SIGTERM; its report is kept in `vnano/`. Coil faults are "
            "transitions no rotor can follow; jitter is the largest step interval error; rx overrun risk counts "
            "bytes that waited at the receiver for more than two frame times (hil/README.md, \"The report\").")
        d.table(["plan", "simulated s", "wall s", "x real time", "ended by", "process", "coil faults",
                 "step jitter us", "rx overrun risk", "report"], vrows, right={1, 2, 3, 6, 7, 8})

    d.h(2, "Files")
    d.ul(["`commands.csv`: one row per command with every figure above (steps, angles, tool positions, "
          "durations, faults, measurements)",
          "`transcripts/`: every line to and from the arm, per plan (status polls included)",
          "`*.png`: the plots" + ("; `vnano/`: the virtual Nano's reports (and step traces with --keep-traces)"
                                  if run.has_pins else "")])

    write_csv(run, out / "commands.csv", len(motors), len(robot.joints))
    tdir = out / "transcripts"
    tdir.mkdir(exist_ok=True)
    for res in run.results:
        (tdir / f"{Path(res.plan.name).stem}.txt").write_text("\n".join(res.transcript) + "\n")
    md = out / "report.md"
    md.write_text(d.markdown())
    (out / "report.html").write_text(d.html("Articula hardware-in-the-loop report"))
    return md
