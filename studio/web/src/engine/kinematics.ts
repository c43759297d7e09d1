// The worker's kinematic intents: joints, Home and Zero, the gripper, IK and the Jacobian
// transpose animated, Teach, robots loaded from the site or a file, RoboSim's l, URDF out.
import { EngineError } from "../../../../wasm/js/engine.mjs";
import type { Robot } from "../../../../wasm/js/engine.mjs";
import { BadMessage, clamp, num, numbers, text } from "./checks";
import type { Msg, Out } from "./checks";
import { adopt, clampQ, info, moveLine, poseMessage, post, powerUpQ, robotMessage, S, stopTasks, toolForTip } from "./state";
import { shippedRobot, userFiles } from "./site";
import { restartPhysics } from "./physics";

const FRAME_MS = 1000 / 60;

type IkArgs = { target: number[]; solver: string; start: number[]; weights?: number[]; max_iterations?: number };

// `articula ik --json`'s result, and beyond_reach.
interface IkResult {
  status: string; solver: string; q: number[]; position_error_mm: number; orientation_error_deg: number;
  iterations: number; limited_by?: string[]; limited_by_motors?: string[]; beyond_reach: boolean; why?: string;
}

// A target is the pen's tip when a pen is held (the engine solves for the tool point above it).
function ikArgs(m: Msg): IkArgs {
  const target = toolForTip(numbers(m, "target", [3, 6]));
  const solver = m.solver ?? "auto";
  if (typeof solver !== "string") throw new BadMessage("'solver' must be auto, closed, lm or jt");
  const args: IkArgs = { target, solver, start: S.q };
  if (m.weights !== undefined && m.weights !== null) {
    const r = info();
    args.weights = numbers(m, "weights", [r.num_joints, r.num_motors].filter((n) => n > 0));
  }
  return args;
}

function solve(args: IkArgs): IkResult {
  try {
    return S.robot.ik(args) as unknown as IkResult;
  } catch (e) {
    if (e instanceof EngineError) throw new BadMessage(e.message);
    throw e;
  }
}

function ikReply(res: IkResult, seq: unknown): Out {
  return {
    type: "ik", status: res.status, solver: res.solver, position_error_mm: res.position_error_mm,
    orientation_error_deg: res.orientation_error_deg, iterations: res.iterations,
    limited_by: [...(res.limited_by ?? []), ...(res.limited_by_motors ?? [])], beyond_reach: res.beyond_reach,
    why: res.why ?? "", pen_mm: S.pen, seq: seq ?? null,
  };
}

export const kinematicHandlers: Record<string, (m: Msg) => Out[] | Promise<Out[]>> = {
  set_joint(m) {
    const j = num(m, "joint", 0, info().num_joints - 1);
    if (!Number.isInteger(j)) throw new BadMessage("'joint' must be a whole number");
    const [lo, hi] = info().limits[j];
    S.q = [...S.q];
    S.q[j] = clamp(num(m, "value"), lo, hi);
    return [poseMessage(S.q, { seq: m.seq ?? null })];
  },
  set_joints(m) {
    S.q = clampQ(numbers(m, "q", [info().num_joints]));
    return [poseMessage(S.q, { seq: m.seq ?? null })];
  },
  home: () => {
    S.q = [...info().home];
    return [poseMessage()];
  },
  // The motors' zero angles (where the real arm powers up), or all joint variables 0 (clamped
  // into the limits) for a robot without motors.
  zero: () => {
    S.q = info().num_motors ? powerUpQ() : clampQ(S.q.map(() => 0));
    return [poseMessage()];
  },
  // The pen's length below the tool point (0: none): the page aims its tip.
  pen(m) {
    S.pen = num(m, "mm", 0, S.engine.penFields[0].max); // (kPenFields: the pen first)
    return [poseMessage()];
  },
  gripper(m) {
    if (!info().gripper) throw new BadMessage(`${info().name} has no gripper`);
    S.gripper = num(m, "percent", 0, 100);
    return [poseMessage()];
  },

  // Solve for a target and move there (to the best pose found when not reached).
  ik(m) {
    const res = solve(ikArgs(m));
    S.q = res.q;
    return [ikReply(res, m.seq), poseMessage(S.q, { seq: m.seq ?? null })];
  },
  jt_animate(m) {
    const args = ikArgs(m);
    args.solver = "jt";
    let i = 0;
    const frame = () => {
      const res = solve({ ...args, start: S.q, max_iterations: 1 });
      const moved = Math.max(...res.q.map((v: number, k: number) => Math.abs(v - S.q[k])));
      S.q = res.q;
      const done = res.status !== "budget" || moved < 1e-9 || i + 1 >= 400;
      let last = res;
      if (done && res.status === "budget" && i + 1 < 400) {
        // It stopped moving short of the target: the solver's own verdict from here.
        last = solve({ ...args, start: S.q });
        S.q = last.q;
      }
      post([{ ...ikReply(last, m.seq), type: "jt_frame", iteration: i + 1, done }, poseMessage(S.q, { seq: m.seq ?? null })]);
      i++;
      S.task = done ? null : setTimeout(frame, FRAME_MS);
    };
    stopTasks();
    frame();
    return [];
  },
  stop_animation: () => {
    stopTasks();
    return [poseMessage()];
  },
  // Record: a pose as a program line (RoboSim's Teach): `M` with the motor angles (joint
  // variables for a robot without motors), or RoboSim's `m` and one value a line; or the tool
  // point as `P`, a straight line to it as `T` (the pen's tip's point when a pen is held: the
  // line takes the tool point above it), the gripper as `G`. The pose is the one shown, or `q`
  // (a connected arm's, from its steps: its `M` line replays to the same steps).
  teach(m) {
    const q = m.q === undefined || m.q === null ? S.q : numbers(m, "q", [info().num_joints]);
    const kind = m.kind === undefined ? "M" : text(m, "kind", 1);
    if (kind === "M")
      return [{ type: "teach", kind, line: m.format === "robosim" ? "m\n" + q.map((v) => v.toFixed(3)).join("\n") : moveLine(q), q }];
    if (kind === "G") {
      if (!info().gripper) throw new BadMessage(`${info().name} has no gripper to record`);
      return [{ type: "teach", kind, line: S.robot.protocolLine("G", [Math.round(S.gripper)]), q }];
    }
    if (kind !== "P" && kind !== "T") throw new BadMessage("'kind' must be M, P, T or G");
    const xyz = (S.robot.pose(q) as { tool: { xyz: number[] } }).tool.xyz.map((v) => Math.round(v * 1000) / 1000);
    const values = kind === "T" ? [...xyz, num(m, "speed", 0.1, 1000)] : xyz;
    return [{ type: "teach", kind, line: S.robot.protocolLine(kind, values), q, xyz }];
  },

  // A shipped robot by name, or a robot file's text (JSON, or a thesis appendix C file with
  // its scale), with the mesh files the user opened beside it. A file that cannot be used
  // keeps the robot that was there.
  async load_robot(m) {
    let r: Robot;
    try {
      r = "name" in m ? await shippedRobot(text(m, "name", 200)) : robotFromFile(m);
    } catch (e) {
      if (e instanceof EngineError) return [{ type: "robot_error", message: e.message }];
      throw e;
    }
    stopTasks();
    adopt(r, restartPhysics);
    return [robotMessage(), poseMessage()];
  },
  // RoboSim's l: the lengths a(i-1) of the rows the robot file lets change, in row order.
  set_lengths(m) {
    const rows = info().dh.filter((row) => typeof (row as { a: unknown }).a === "object");
    const values = numbers(m, "values", [rows.length]);
    const keepQ = S.q, keepGrip = S.gripper;
    try {
      S.robot.setLinkLengths(values);
    } catch (e) {
      if (e instanceof EngineError) throw new BadMessage(e.message);
      throw e;
    }
    adopt(S.robot, restartPhysics);
    S.q = keepQ;
    S.gripper = keepGrip;
    return [{ ...robotMessage(), keep_view: true }, poseMessage(S.q, { seq: m.seq ?? null })];
  },
  export_urdf: () => [{ type: "urdf", name: info().name, xml: S.robot.urdf() }],
};

function robotFromFile(m: Msg): Robot {
  const body = text(m, "text");
  const filename = ("filename" in m ? text(m, "filename", 200) : "robot.json").replace(/[\\/]/g, "_");
  const r = S.engine.robot();
  try {
    userFiles(m);
    if (m.legacy) r.fromLegacy(body, filename, num(m, "scale", 1e-6, 1e6));
    else r.parse(body, filename);
    for (const l of (r.info as unknown as ReturnType<typeof info>).links)
      for (const s of l.shapes)
        if (s.mesh && !S.engine.exists(s.mesh))
          throw new EngineError({ error: `${filename}: the mesh file ${s.mesh.replace(/^\/user\//, "")} was not ` +
            "opened: open it together with the robot file (select both)" });
  } catch (e) {
    r.delete();
    throw e;
  }
  return r;
}
