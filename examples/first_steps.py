"""First steps with `import articula`: load the MK2 Plus, move it by forward kinematics, find
joint values for a point by inverse kinematics, predict what the real arm does with a program
step for step, and plot it.

    .venv/bin/python examples/first_steps.py            # writes first_steps.png here
    .venv/bin/python examples/first_steps.py -o out.png

docs/python.md walks through it.
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # write a file; no window needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import articula  # noqa: E402

REPO = Path(__file__).resolve().parents[1]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--output", default="first_steps.png", help="the plot (PNG)")
    args = ap.parse_args()

    # 1. A robot: the MK2 Plus of the thesis, from robots/mk2plus.json.
    mk2 = articula.Robot.load("mk2plus")
    print(mk2)
    for j in mk2.joints:
        print(f"  {j['name']:8s} theta of row {j['row']}, {j['min']:g} .. {j['max']:g} {j['unit']}")

    # 2. Forward kinematics: where is the tool at base 30, shoulder 60, elbow -80 degrees?
    T = mk2.fk([30, 60, -80])
    print("tool at", np.round(T[:3, 3], 3), "mm")

    # 3. Inverse kinematics: which joint values put the tool at (200, -150, 150) mm?
    res = mk2.ik([200, -150, 150])
    print(f"ik: {res.status} by {res.solver}, q = {np.round(res.q, 3)} deg, "
          f"{res.position_error_mm:.4f} mm from the target")
    far = mk2.ik([600, 0, 100])
    print(f"ik of a point out of reach: {far.status}, {far.position_error_mm:.1f} mm short")

    # 4. A program, predicted step for step as the Nano will run it.
    pred = mk2.predict(articula.Program.load(REPO / "programs" / "demo.arm"))
    s = pred.summary
    print(f"demo.arm: {s.commands} commands, {s.rejected} rejected, worst quantization error "
          f"{s.worst_error_mm:.3f} mm, {s.total_s:.3f} s")

    # 5. Plot: each action moves from its start to its end time (the controller runs them back
    # to back); the joint values are those the motors' whole steps give. Below, after each
    # command, the distance between the tool there and where the exact angles would put it.
    start, end = pred.column("start_s"), pred.column("end_s")
    joints, err = pred.column("joints"), pred.column("error_mm")
    t = np.r_[0.0, np.column_stack([start, end]).ravel()]
    def ramps(v):  # value before each action, then after it
        before = np.r_[v[:1], v[:-1]]
        return np.r_[v[:1], np.column_stack([before, v]).ravel()]

    fig, (a, b) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True, constrained_layout=True)
    for k, name in enumerate(pred.joints):
        a.plot(t, ramps(joints[:, k]), label=name, lw=2)
    a.set_ylabel("joint value (deg)")
    a.set_title(f"{pred.robot}: programs/demo.arm as the Nano runs it")
    a.legend(loc="lower left", ncols=3, frameon=False)
    a.grid(alpha=0.3)
    b.vlines(end, 0, err, color="tab:red", lw=2)
    b.plot(end, err, "o", color="tab:red")
    b.set_ylabel("tool error after the\ncommand, from whole\nsteps (mm)")
    b.set_xlabel("time (s)")
    b.grid(alpha=0.3)
    shift, last_end = 0, None
    for r in pred.records:  # commands that end together (a zero-time one) side by side
        shift = shift + 11 if r.end_s == last_end else 0
        last_end = r.end_s
        b.annotate(r.command, (r.end_s, r.error_mm), fontsize=8, rotation=90, ha="center", va="bottom",
                   xytext=(shift, 7), textcoords="offset points")
    b.set_ylim(0, err.max() * 1.9)
    fig.savefig(args.output, dpi=110)
    print("plot:", args.output)


if __name__ == "__main__":
    main()
