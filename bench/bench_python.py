#!/usr/bin/env python3
"""The Python package's speed (bench/README.md, "Through Python"), each figure against a peer
measured in the same run:

  - FK, Panda, one pose through Python: articula `Robot.fk(q)` against Pinocchio's
    `forwardKinematics` (PyPI `pin`, the same Panda from `robot.to_urdf()`) and Robotics
    Toolbox's `ets.eval` (PyPI `roboticstoolbox-python`), each given a numpy q;
  - batch FK: `Robot.fk_batch` over (N, 7) poses, poses/s, against bench_kinematics's C++
    BM_PandaFk (the same FK, one pose per call, no Python);
  - IK through Python: `Robot.ik` on bench_ik's own targets (it writes them with
    ARTICULA_BENCH_DUMP) from the same start, median and p95 per call, against bench_ik's C++
    figures of the same run;
  - `Sim.step(1000)`: the scene and program of bench_physics (the MK2 and a 3 cm cube, 10 s
    of moves) through Python, world steps/s, against bench_physics's BM_SimMk2Cube.

    .venv/bin/python bench/bench_python.py [--build build] [--quick]

Peers missing (scripts/bootstrap --bench installs them) are reported as such. A benchmark,
not a test: figures on a shared machine vary; the ratios, measured in one run, less so.
"""
import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "python"))
sys.path.insert(0, str(REPO / "bench"))

import articula  # noqa: E402
from compare_rtb import load_targets, panda_rtb, run_json  # noqa: E402


def per_call_us(fn, arg, calls, repeat=7):
    """Median over `repeat` passes of the mean time per call (us)."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for _ in range(calls):
            fn(arg)
        times.append((time.perf_counter() - t0) / calls * 1e6)
    return statistics.median(times)


def each_call_us(fn, args_list):
    """Median and p95 of single calls (us)."""
    us = []
    for a in args_list:
        t0 = time.perf_counter_ns()
        fn(a)
        us.append((time.perf_counter_ns() - t0) / 1000)
    us.sort()
    return us[len(us) // 2], us[int(0.95 * (len(us) - 1))]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=str(REPO / "build"))
    ap.add_argument("--quick", action="store_true", help="fewer repetitions (a smoke run)")
    args = ap.parse_args()
    reps = 3 if args.quick else 7
    bench = Path(args.build) / "bench"
    rows = []  # (what, ours, peer, peer name, ratio text)

    panda = articula.Robot.load("panda")
    rng = np.random.default_rng(1)
    lo, hi = panda.limits[:, 0], panda.limits[:, 1]
    q_deg = lo + (hi - lo) * rng.random(7)

    # ---- FK, one pose: ours and each peer measured in turn, round after round (the machine's
    # speed drifts; a ratio within a round is steadier than figures minutes apart).
    calls = 100_000 if not args.quick else 20_000
    peers = {}
    try:
        import pinocchio as pin
        model = pin.buildModelFromXML(panda.to_urdf())
        data = model.createData()
        q_rad = np.radians(q_deg)
        pin.framesForwardKinematics(model, data, q_rad)  # same model: its tool frame against ours
        tool = model.getFrameId("tool")
        diff = np.abs(data.oMf[tool].homogeneous[:3, 3] * 1000 - panda.fk(q_deg)[:3, 3]).max()
        assert diff < 1e-6, f"Pinocchio's Panda differs from ours by {diff} mm"
        peers["Pinocchio forwardKinematics (joint placements only)"] = (
            lambda q: pin.forwardKinematics(model, data, q), q_rad)
        peers["Pinocchio framesForwardKinematics + the tool pose as an array"] = (
            lambda q: (pin.framesForwardKinematics(model, data, q), data.oMf[tool].homogeneous), q_rad)
    except ImportError:
        rows.append(("  peer: Pinocchio", "not installed (scripts/bootstrap --bench)", None, None, None))
    try:
        robot, _ = panda_rtb()
        peers["Robotics Toolbox ets.eval"] = (robot.ets().eval, np.radians(q_deg))
    except ImportError:
        rows.append(("  peer: Robotics Toolbox", "not installed (scripts/bootstrap --bench)", None, None, None))
    ours, theirs = [], {k: [] for k in peers}
    for _ in range(reps):
        ours.append(per_call_us(panda.fk, q_deg, calls, 1))
        for k, (fn, arg) in peers.items():
            theirs[k].append(per_call_us(fn, arg, calls if "Toolbox" not in k else calls // 5, 1))
    fk_us = statistics.median(ours)
    rows.append(("Panda FK, one pose, Python: articula Robot.fk", f"{fk_us:.3f} us", None, None, None))
    for k in peers:
        ratio = statistics.median(o / t for o, t in zip(ours, theirs[k]))
        rows.append((f"  peer: {k}", f"{statistics.median(theirs[k]):.3f} us", None, None,
                     f"ours takes {ratio:.2f}x its time"))

    # ---- batch FK
    N = 200_000 if not args.quick else 50_000
    Q = lo + (hi - lo) * rng.random((N, 7))
    times = []
    for _ in range(reps):
        t0 = time.perf_counter()
        panda.fk_batch(Q)
        times.append(time.perf_counter() - t0)
    batch_rate = N / statistics.median(times)
    kin = run_json([str(bench / "bench_kinematics"), "--benchmark_filter=BM_PandaFk$",
                    f"--benchmark_repetitions={reps}", "--benchmark_report_aggregates_only=true"])
    cpp_fk_ns = kin["BM_PandaFk_median"]["real_time"]
    rows.append((f"Panda batch FK, Python: Robot.fk_batch of {N:,} poses", f"{batch_rate / 1e6:.2f} M poses/s",
                 None, None, None))
    rows.append(("  peer: C++ BM_PandaFk (one pose a call, no Python)", f"{1e3 / cpp_fk_ns:.2f} M poses/s",
                 None, "C++", f"{batch_rate / (1e9 / cpp_fk_ns):.2f}x the C++ rate"))

    # ---- IK on bench_ik's targets, and Sim.step against bench_physics: Python and C++ in turn,
    # round after round; each ratio is of one round, the figures medians over the rounds.
    rounds = 3 if args.quick else 5
    mk2 = articula.Robot.load("mk2plus")
    scene = {"name": "bench: MK2 and a cube", "objects": [
        {"name": "cube", "type": "box", "size": [30, 30, 30], "xyz": [250, -60, 15], "movable": True,
         "mass": 0.027}]}
    moves = ("G 100\nM 40 60 -30\nM -40 100 10\nG 0\nM 0 45 -40\nM 60 80 -20\nG 60\nM -60 50 0\nM 0 120 -40\n"
             "M 30 36 -43\nM -30 90 15\nG 100\nM 0 90 0\n")
    fig = {k: [] for k in ("py_med", "py_p95", "c_med", "c_p95", "m_py", "m_c", "m_batch", "sim_py", "sim_c",
                           "ok")}
    with tempfile.TemporaryDirectory() as tmp:
        scene_path = Path(tmp) / "cube.json"
        scene_path.write_text(json.dumps(scene))
        env = dict(os.environ, ARTICULA_BENCH_DUMP=tmp)
        for r in range(rounds):
            ik = run_json([str(bench / "bench_ik"), "--benchmark_filter=BM_PandaFullPose1000|BM_Mk2Position1000/"],
                          env)
            if r == 0:
                start, targets = load_targets(os.path.join(tmp, "panda_targets.csv"))
                mk2_targets = list(np.loadtxt(os.path.join(tmp, "mk2_targets.csv"), delimiter=","))
                poses = []
                for _, T in targets:
                    T = T.copy()
                    T[:3, 3] *= 1000  # load_targets gives metres (for the toolbox)
                    poses.append(T)
                np.testing.assert_allclose(np.radians(panda.home), start, atol=1e-12)
                res = [panda.ik(T) for T in poses]
                fig["ok"].append(sum(x.position_error_mm < 1 and x.orientation_error_deg < np.degrees(1e-3)
                                     and panda.within_limits(x.q) for x in res) / len(res) * 100)
            c, m = ik["BM_PandaFullPose1000/iterations:1"], ik["BM_Mk2Position1000/iterations:1"]
            med, p95 = each_call_us(panda.ik, poses)
            fig["py_med"].append(med), fig["py_p95"].append(p95)
            fig["c_med"].append(c["median_us"]), fig["c_p95"].append(c["p95_us"])
            # The MK2's closed form takes 0.4 us: reading a clock around each Python call would add a
            # quarter of that, so here the mean of a loop, against the C++ mean.
            t0 = time.perf_counter()
            for t in mk2_targets:
                mk2.ik(t)
            fig["m_py"].append((time.perf_counter() - t0) / len(mk2_targets) * 1e6)
            fig["m_c"].append(m["mean_us"])
            t0 = time.perf_counter()
            mk2.ik_batch(np.array(mk2_targets))
            fig["m_batch"].append((time.perf_counter() - t0) / len(mk2_targets) * 1e6)
            phys = run_json([str(bench / "bench_physics"), "--benchmark_filter=BM_SimMk2Cube$",
                             "--benchmark_repetitions=3", "--benchmark_report_aggregates_only=true"])
            fig["sim_c"].append(phys["BM_SimMk2Cube_median"]["items_per_second"])
            rates = []
            for _ in range(3):
                sim = articula.Sim(mk2, str(scene_path))
                sim.load_program(articula.Program.parse(moves, "bench.arm"))
                t0 = time.perf_counter()
                for _ in range(10):
                    sim.step(1000)
                rates.append(10_000 / (time.perf_counter() - t0))
            fig["sim_py"].append(statistics.median(rates))

    def med(k):
        return statistics.median(fig[k])

    def ratio(a, b):
        vals = sorted(x / y for x, y in zip(fig[a], fig[b]))
        return f"{statistics.median(vals):.2f}x (rounds {vals[0]:.2f} .. {vals[-1]:.2f})"

    rows.append((f"IK Panda full pose, Python: Robot.ik, bench_ik's 1,000 targets ({rounds} rounds)",
                 f"median {med('py_med'):.2f} us, p95 {med('py_p95'):.1f} us, success {fig['ok'][0]:.1f} %",
                 None, None, None))
    rows.append(("  peer: C++ bench_ik, same targets, in turn", f"median {med('c_med'):.2f} us, p95 "
                 f"{med('c_p95'):.1f} us", None, "C++", f"median: {ratio('py_med', 'c_med')}; p95: "
                 f"{ratio('py_p95', 'c_p95')}"))
    rows.append(("IK MK2 position (closed form), Python: Robot.ik in a loop over bench_ik's 1,000 points",
                 f"mean {med('m_py'):.2f} us", None, None, None))
    rows.append(("  peer: C++ bench_ik, same points, in turn", f"mean {med('m_c'):.2f} us", None, "C++",
                 f"{ratio('m_py', 'm_c')}"))
    rows.append(("IK MK2 position, Python: Robot.ik_batch of the 1,000 points, per point", f"mean {med('m_batch'):.2f} us",
                 None, None, None))
    rows.append(("  peer: C++ bench_ik, same points, in turn", f"mean {med('m_c'):.2f} us", None, "C++",
                 f"{ratio('m_batch', 'm_c')}"))
    rows.append(("Physics, Python: Sim.step(1000) x 10, MK2 + cube, 10 s of moves", f"{med('sim_py'):,.0f} steps/s",
                 None, None, None))
    rows.append(("  peer: C++ bench_physics BM_SimMk2Cube, in turn", f"{med('sim_c'):,.0f} steps/s", None, "C++",
                 f"Python takes {ratio('sim_c', 'sim_py')} the C++ time"))

    print(f"articula {articula.__version__}, numpy {np.__version__}, Python {sys.version.split()[0]}; "
          f"{'quick run' if args.quick else f'{reps} repetitions'}")
    print()
    print("| what | figure | against the peer |")
    print("|---|---|---|")
    for what, fig, _, _, ratio in rows:
        print(f"| {what} | {fig} | {ratio or ''} |")


if __name__ == "__main__":
    main()
