// The studio's engine in a Web Worker: the web engine (wasm/, the same C++ as the CLI and
// the Python package) and one page's session - the robot shown, its pose, the program's time
// line, the Jacobian transpose animated, the live physics, the arm's lines. The page posts
// intents (the messages of engine/messages.ts) and draws what comes back; nothing here blocks its
// drawing.
//
// Every pose, solve, prediction and physics step is the engine's: this file only dispatches
// intents to the session's parts (engine/: kinematics, program, physics, arm), which keep the
// state of the page and turn intents into engine calls (docs/studio.md, "What runs where").
import { EngineError, loadEngine } from "../../../../wasm/js/engine.mjs";
import { BadMessage } from "./checks";
import type { Msg, Out } from "./checks";
import { armHandlers } from "./arm";
import { CELL_INTENTS, cellArmHandlers, cellControl, cellIntent, cellOpen, cellRunIntent, closeCell } from "./cell";
import { blockHandlers } from "./blocks";
import { drawHandlers } from "./draw";
import { exerciseHandlers } from "./exercise";
import { experimentHandlers } from "./experiment";
import { kinematicHandlers } from "./kinematics";
import { jogHandlers } from "./jog";
import { PHYSICS_INTENTS, PHYSICS_ONLY, ensurePhysics, physicsIntent, physicsMessage, sceneIntent, sceneMessage,
  startPhysics } from "./physics";
import { programHandlers } from "./program";
import { loadIndex, sceneFile, shippedRobot, site, urlRobot } from "./site";
import { info, poseMessage, post, robotMessage, S, stopTasks } from "./state";

type Handler = (m: Msg) => Out[] | Promise<Out[]>;

const handlers: Record<string, Handler> = {
  // An answer after every intent sent before it (intents are handled in order).
  sync: () => [{ type: "sync" }],
  hello: () => {
    S.greeted = true;
    if (S.sim) setTimeout(ensurePhysics, 0); // after these replies: the page has its robot first
    return [robotMessage(), sceneMessage(), physicsMessage(), poseMessage()];
  },
  scene: (m) => {
    closeCell(); // (a scene is the single arm's physics again)
    return sceneIntent(m);
  },
  cell: cellIntent,
  cell_run: cellRunIntent,
  ...cellArmHandlers,
  ...kinematicHandlers,
  ...jogHandlers,
  ...programHandlers,
  ...armHandlers,
  ...blockHandlers,
  ...exerciseHandlers,
  ...experimentHandlers,
  ...drawHandlers,
};

// Intents that end a playing program or an animation.
const STOPS_TASKS = new Set(["set_joint", "set_joints", "jog", "ik", "home", "zero", "program_load", "set_lengths"]);

function kinematic(kind: string, m: Msg): Out[] {
  return handlers[kind](m) as Out[];
}

async function dispatch(m: unknown): Promise<Out[]> {
  if (typeof m !== "object" || m === null || Array.isArray(m)) throw new BadMessage("a message is an object with a 'type'");
  const msg = m as Msg;
  const kind = msg.type;
  if (typeof kind !== "string") throw new BadMessage(`unknown message type ${JSON.stringify(kind) ?? "undefined"}`);
  if (cellOpen() && CELL_INTENTS.has(kind)) return cellControl(kind);
  if (S.sim && PHYSICS_INTENTS.has(kind)) return physicsIntent(kind, msg, kinematic);
  if (PHYSICS_ONLY.has(kind)) throw new BadMessage("no physics: choose a scene first");
  const handler = Object.prototype.hasOwnProperty.call(handlers, kind) ? handlers[kind] : undefined;
  if (!handler) throw new BadMessage(`unknown message type '${kind}'`);
  if (STOPS_TASKS.has(kind)) stopTasks();
  return handler(msg);
}

// Messages are handled one at a time, in order (a robot that is still being fetched answers
// before the slider moved after it).
let queue: Promise<void> = Promise.resolve();

function receive(m: unknown): void {
  // A request with an `id` (the page's engine.call) gets it back on its answers.
  const id = typeof m === "object" && m !== null && typeof (m as Msg).id === "number" ? (m as Msg).id : undefined;
  const tagged = (msgs: Out[]) => (id === undefined ? msgs : msgs.map((x) => ({ ...x, id })));
  queue = queue.then(async () => {
    try {
      post(tagged(await dispatch(m)));
    } catch (e) {
      const request = typeof m === "object" && m !== null ? (m as Msg).type : null;
      if (e instanceof BadMessage || e instanceof EngineError) post(tagged([{ type: "error", message: e.message, request: request ?? null }]));
      else post(tagged([{ type: "error", message: `internal error: ${(e as Error)?.message ?? String(e)}`, request: request ?? null }]));
    }
  });
}

// The first message is {type: "start", robot, scene, frame_ms}: the engine loads, the site's index is
// read, the robot shown first is loaded; then "ready" with the core's status table.
async function start(first: Msg): Promise<void> {
  const t0 = performance.now();
  const engineUrl = new URL("engine/engine.mjs", site).href;
  const { default: createEngine } = await import(/* @vite-ignore */ engineUrl);
  S.engine = await loadEngine(createEngine, { locateFile: (f: string) => new URL(`engine/${f}`, site).href });
  await loadIndex();
  const wanted = typeof first.robot === "string" ? first.robot : "mk2plus";
  try {
    S.robot = wanted.endsWith(".json") ? await urlRobot(wanted) : await shippedRobot(S.index.robots.includes(wanted) ? wanted : "mk2plus");
  } catch (e) {
    // A robot the address names but that cannot be used: the MK2, and the page says why.
    S.robot = await shippedRobot("mk2plus");
    post([{ type: "robot_error", message: (e as Error).message }]);
  }
  S.q = [...info().home];
  const frameMs = Number(first.frame_ms);
  S.postMs = Number.isFinite(frameMs) ? Math.min(500, Math.max(0, frameMs / 2)) : 0;
  const scene = typeof first.scene === "string" && S.index.scenes.includes(first.scene) ? first.scene : null;
  if (scene) {
    await sceneFile(scene);
    startPhysics(scene);
  }
  post([{ type: "ready", ms: performance.now() - t0, status_table: S.engine.status, pen_fields: S.engine.penFields }]);
}

let started: Promise<void> | null = null;
self.onmessage = (e: MessageEvent) => {
  const m = e.data;
  if (typeof m === "object" && m !== null && m.type === "physics_ack") {  // not queued: it frees the stream
    S.unacked = Math.max(0, S.unacked - 1);
    return;
  }
  if (!started) {
    started = start(typeof m === "object" && m !== null ? m : {}).catch((err) => {
      post([{ type: "fatal", message: `the engine did not start: ${(err as Error)?.message ?? err}` }]);
    });
    queue = started;
    return;
  }
  receive(m);
};
