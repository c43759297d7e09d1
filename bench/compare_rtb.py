#!/usr/bin/env python3
"""Side-by-side figures: Articula's benchmarks and Robotics Toolbox for Python (PyPI
roboticstoolbox-python) on the same robot and the same targets, in one session.

    .venv/bin/python bench/compare_rtb.py [--build build]

Runs build/bench/bench_ik and build/bench/bench_kinematics (JSON output), has bench_ik write
its 1,000 Panda targets (ARTICULA_BENCH_DUMP), builds the same Panda in the toolbox (modified
DH, the published parameters, the flange as the tool, metres), checks that both give the same
forward kinematics for every target, then times the toolbox's forward kinematics, Jacobian
and its C++ Levenberg-Marquardt IK (ik_LM, with restarts and joint limits) on those targets,
from the same start, with the same success test (< 1 mm, < 1e-3 rad, within the limits).
Prints a Markdown table with the ratios (toolbox time / Articula time).

A benchmark helper, not a test: nothing in ctest needs the toolbox.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np


def run_json(cmd, env=None):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out.json")
        subprocess.run(cmd + [f"--benchmark_out={out}", "--benchmark_out_format=json"], check=True,
                       capture_output=True, text=True, env=env)
        with open(out) as f:
            return {b["name"]: b for b in json.load(f)["benchmarks"]}


def load_targets(path):
    start = None
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("# start (rad):"):
                start = np.array([float(v) for v in line.split(":", 1)[1].split()])
            elif not line.startswith("#"):
                v = [float(x) for x in line.strip().split(",")]
                q, R, p = np.array(v[:7]), np.array(v[7:16]).reshape(3, 3), np.array(v[16:19])
                T = np.eye(4)
                T[:3, :3], T[:3, 3] = R, p / 1000.0
                rows.append((q, T))
    return start, rows


def panda_rtb():
    import roboticstoolbox as rtb
    from spatialmath import SE3

    deg = math.pi / 180
    a = [0, 0, 0, 0.0825, -0.0825, 0, 0.088]
    d = [0.333, 0, 0.316, 0, 0.384, 0, 0]
    alpha = [0, -90, 90, 90, -90, 90, 90]
    lim = [(-2.8973, 2.8973), (-1.7628, 1.7628), (-2.8973, 2.8973), (-3.0718, -0.0698),
           (-2.8973, 2.8973), (-0.0175, 3.7525), (-2.8973, 2.8973)]
    # The limits exactly as robots/panda.json has them (degrees with 4 decimals).
    lim = [(round(lo / deg, 4) * deg, round(hi / deg, 4) * deg) for lo, hi in lim]
    links = [rtb.RevoluteMDH(a=a[i], d=d[i], alpha=alpha[i] * deg, qlim=lim[i]) for i in range(7)]
    return rtb.DHRobot(links, name="panda-articula", tool=SE3(0, 0, 0.107)), np.array(lim)


def rot_err(R1, R2):
    """Angle of R1 R2^T (rad), accurate near 0 too."""
    R = R1 @ R2.T
    s = np.linalg.norm([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]) / 2
    return math.atan2(s, (np.trace(R) - 1) / 2)


def per_call(fn, args_list, repeat=3):
    """Median over `repeat` passes of the mean time per call (s)."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for a in args_list:
            fn(a)
        times.append((time.perf_counter() - t0) / len(args_list))
    return sorted(times)[len(times) // 2]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build")
    args = ap.parse_args()
    bench_ik = os.path.join(args.build, "bench", "bench_ik")
    bench_kin = os.path.join(args.build, "bench", "bench_kinematics")

    try:
        import roboticstoolbox as rtb  # noqa: F401
    except ImportError:
        sys.exit("roboticstoolbox-python is not installed: run scripts/bootstrap --bench")
    import roboticstoolbox

    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, ARTICULA_BENCH_DUMP=tmp)
        ours_ik = run_json([bench_ik, "--benchmark_filter=BM_PandaFullPose1000"], env)
        start, targets = load_targets(os.path.join(tmp, "panda_targets.csv"))
    ours_kin = run_json([bench_kin, "--benchmark_filter=BM_Panda"])

    robot, lim = panda_rtb()
    ets = robot.ets()
    # Same model: the toolbox's FK of every pose against Articula's (dumped) target.
    worst_p = max(np.linalg.norm(robot.fkine(q).A[:3, 3] - T[:3, 3]) for q, T in targets) * 1000
    worst_R = max(rot_err(robot.fkine(q).A[:3, :3], T[:3, :3]) for q, T in targets)

    qs = [q for q, _ in targets]
    fk_py = per_call(lambda q: robot.fkine(q), qs)
    fk_ets = per_call(lambda q: ets.eval(q), qs)
    jac_ets = per_call(lambda q: ets.jacob0(q), qs)

    def solve_all(**kw):
        us, ok = [], 0
        for _, T in targets:
            t0 = time.perf_counter()
            sol = ets.ik_LM(T, q0=start, **kw)
            t1 = time.perf_counter()
            us.append((t1 - t0) * 1e6)
            q = np.asarray(sol.q)
            Tq = ets.eval(q)
            good = (np.linalg.norm(Tq[:3, 3] - T[:3, 3]) < 1e-3 and rot_err(Tq[:3, :3], T[:3, :3]) < 1e-3
                    and np.all(q >= lim[:, 0] - 1e-12) and np.all(q <= lim[:, 1] + 1e-12))
            ok += bool(good)
        us.sort()
        n = len(us)
        return 100.0 * ok / n, us[n // 2], us[int(0.95 * (n - 1))]

    rtb_default = solve_all()
    rtb_tight = solve_all(tol=1e-10)

    pk = ours_ik["BM_PandaFullPose1000/iterations:1"]
    ns = {k: v["real_time"] if v["time_unit"] == "ns" else v["real_time"] * 1000 for k, v in ours_kin.items()}

    print(f"roboticstoolbox-python {roboticstoolbox.__version__}, numpy {np.__version__}; "
          f"same model check: worst FK difference {worst_p:.2e} mm, {worst_R:.2e} rad over {len(targets)} poses\n")
    print("| figure | Articula | Robotics Toolbox | ratio (toolbox / Articula) |")
    print("|---|---|---|---|")
    fk_ours, jac_ours = ns["BM_PandaFk"], ns["BM_PandaJacobian"]
    fkj_ours = ns["BM_PandaFkAndJacobian"]
    print(f"| Panda FK, per call | {fk_ours:.0f} ns (core, C++) | {fk_ets * 1e9:.0f} ns (`ets.eval`, C++ from Python) "
          f"| {fk_ets * 1e9 / fk_ours:.0f} |")
    print(f"| Panda FK, per call | | {fk_py * 1e6:.1f} us (`fkine`, returns SE3) | {fk_py * 1e9 / fk_ours:.0f} |")
    print(f"| Panda Jacobian, per call | {fkj_ours:.0f} ns (FK + Jacobian) | {jac_ets * 1e9:.0f} ns (`ets.jacob0`, "
          f"FK included) | {jac_ets * 1e9 / fkj_ours:.0f} |")
    for label, (succ, med, p95) in (("ik_LM, defaults (tol 1e-6)", rtb_default), ("ik_LM, tol 1e-10", rtb_tight)):
        print(f"| Panda full-pose IK, 1,000 targets, success | {pk['success_pct']:.1f} % | {succ:.1f} % ({label}) | |")
        print(f"| ... median time | {pk['median_us']:.1f} us | {med:.1f} us | {med / pk['median_us']:.1f} |")
        print(f"| ... 95th percentile | {pk['p95_us']:.1f} us | {p95:.1f} us | {p95 / pk['p95_us']:.1f} |")
    print(f"\n(Articula Jacobian alone, frames given: {jac_ours:.0f} ns.)")


if __name__ == "__main__":
    main()
