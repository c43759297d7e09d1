// Articula Studio's page: panels around the 3D view. It sends intents to the engine, which
// runs in a Web Worker (worker.ts: the C++ core, host library and ODE in WebAssembly) -
// "set joint 2 to 30 deg", "solve for this target", "run this program" - and draws the poses
// that come back; it never computes kinematics itself (docs/studio.md). The arm in the loop
// is the page's too (arm.ts): the virtual Nano (nano-worker.ts) or a Nano over Web Serial,
// which the page can flash (stk500.mjs). No server takes part.
import { View } from "./view";
import { Plots } from "./plots";
import { startTour } from "./tour";
import { ArmLink } from "./arm";
import { VirtualNanoPort, webSerial } from "./serial";
import type { SerialLike } from "./serial";
import { FlashError, flashNano } from "./stk500.mjs";
import type { ArmStatusMsg, IkMsg, PhysicsMsg, PoseMsg, RobotMsg, SceneMsg, ServerMsg, SimEvent, TimelineMsg } from "./protocol";

const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;
const params = new URLSearchParams(location.search);

// ---- the test hook: state to read, never to write (tests read it instead of pixels)
interface Hook {
  ready: boolean;
  connected: boolean;
  robot: RobotMsg | null;
  pose: PoseMsg | null;
  ik: IkMsg | null;
  timeline: TimelineMsg | null;
  playing: boolean;
  programError: string;
  robotError: string;
  lastError: string;
  teach: string;
  fps: number;
  framesDrawn: number;
  firstFrameAt: number; // performance.now() of the first frame with the arm drawn
  latency: number[]; // ms from a slider's input to the frame that shows its pose
  ikUpdates: number[]; // performance.now() of each IK pose drawn while dragging
  messages: number;
  targetScreen: number[]; // where the IK target's centre is on screen (CSS px), to drag it
  scene: SceneMsg | null;
  physics: PhysicsMsg | null;
  events: SimEvent[]; // the physics events since the simulation started or was reset
  simCommand: string; // the last line a pose became for the simulated controller
  objectScreen: (name: string) => number[] | null;
  arm: { connected: boolean; error: string; label: string; status: ArmStatusMsg | null; reply: unknown; stopMs: number | null;
         programLines: unknown[]; programDone: boolean; roundTrips: number[]; nano: unknown };
  stream: { messages: number }; // physics and pose messages while the physics runs
  armPixels: () => number; // share of the view's pixels that are the arm's colours (0..1)
  errors: number; // error replies from the engine or the arm's server
  internalErrors: string[]; // replies that say the engine itself went wrong (never expected)
  engineStartMs: number; // the worker's time from its first message to the robot loaded
  engineSend: (msg: unknown) => void; // for tests: a message to the engine as the page would post it
  flash: { busy: boolean; phase: string; done: number; total: number; error: string; errorKind: string;
           result: { bytes: number; pages: number; baud: number; seconds: number } | null };
}
const hook: Hook = {
  ready: false, connected: false, robot: null, pose: null, ik: null, timeline: null, playing: false,
  programError: "", robotError: "", lastError: "", teach: "", fps: 0, framesDrawn: 0, firstFrameAt: 0,
  latency: [], ikUpdates: [], messages: 0, targetScreen: [0, 0], armPixels: () => view.armPixels(),
  scene: null, physics: null, events: [], simCommand: "", objectScreen: (n) => view.objectScreen(n),
  arm: { connected: false, error: "", label: "", status: null, reply: null, stopMs: null, programLines: [], programDone: false, roundTrips: [], nano: null },
  stream: { messages: 0 }, errors: 0, internalErrors: [], engineStartMs: 0,
  engineSend: (msg) => worker.postMessage(msg),
  flash: { busy: false, phase: "", done: 0, total: 0, error: "", errorKind: "", result: null },
};
const readOnly = new Proxy(hook, { set: () => false, deleteProperty: () => false });
Object.defineProperty(window, "articula", { value: readOnly, writable: false });

// The engine starts first: it compiles and loads the robot in its worker while the page
// builds its 3D view (its messages are handled once this script has run).
let worker: Worker;
let engineReady = false;
startEngine();

const view = new View($("view"));
const plots = new Plots($("plots"));
let robot: RobotMsg | null = null;
let seq = 0;
const sentAt = new Map<number, number>();
let pendingDrawn: number[] = []; // seqs applied, waiting for the frame that shows them
let armDrawn: ArmStatusMsg[] = []; // arm reports applied, waiting for the frame that shows them
// Pose requests (sliders, drags): at most two in flight, so one is computed while the page
// draws the other; the newest intent waits and replaces any older one waiting.
const MAX_IN_FLIGHT = 2;
let inFlight = 0;
let queued: Record<string, unknown> | null = null;
let dragging = false;
// The robot shown, as the arm's server loads it: a shipped robot's name, or the file's text.
let robotSpec: Record<string, unknown> = (params.get("robot") ?? "").endsWith(".json")
  ? { file: params.get("robot") } : { name: params.get("robot") ?? "mk2plus" };
const MAX_FILE = 20_000_000; // bytes of a robot file or mesh the page opens
let needFit: Promise<void> | null = null; // a new robot: frame it once its first pose is drawn

// The arm's messages go to the arm in the page (arm.ts: the virtual Nano here, or a Nano over
// Web Serial); everything else to the engine in the worker.
function send(msg: Record<string, unknown>, transfer: Transferable[] = []): void {
  if (typeof msg.type === "string" && msg.type.startsWith("arm_")) {
    armInPage(msg);
    return;
  }
  if (engineReady) worker.postMessage(msg, transfer);
}

// ---- the arm in the page: ports, and the engine's help (line parsing, poses, predictions)

let armLink: ArmLink | null = null; // the arm in the page, while connected (or connecting)
let nanoPort: VirtualNanoPort | null = null;
let callId = 0;
const calls = new Map<number, { resolve: (m: Record<string, unknown>) => void; reject: (e: Error) => void }>();

// A request to the engine's worker and its answer (matched by id).
function engineCall(msg: Record<string, unknown>): Promise<Record<string, unknown>> {
  const id = ++callId;
  return new Promise((resolve, reject) => {
    calls.set(id, { resolve, reject });
    worker.postMessage({ ...msg, id });
  });
}

const armEngine = {
  parse: (line: string) => engineCall({ type: "arm_parse", line }).then((r) => r.parsed as never),
  pose: (angles: number[]) => engineCall({ type: "arm_pose", angles }) as Promise<never>,
  predict: (history: string[], line: string) => engineCall({ type: "arm_predict", history, line }) as Promise<never>,
  meaning: (reply: string) => {
    const code = reply === "ok" ? 0 : parseInt(reply.replace(/^error:/, ""), 10);
    return engineCall({ type: "status_text", code: Number.isFinite(code) ? code : 255 }).then((r) => r.text as string);
  },
};

const PAGE_PORTS = [{ id: "page:virtual", label: "the virtual Nano (its firmware in this page)" }];

function showPorts(): void {
  const sel = $("arm-port") as HTMLSelectElement;
  const keep = sel.value;
  const page = [...PAGE_PORTS, ...(webSerial() ? [{ id: "page:serial", label: "a Nano on USB (Web Serial)…" }] : [])];
  sel.innerHTML = page.map((p) => `<option value="${p.id}">${esc(p.label)}</option>`).join("");
  if ([...sel.options].some((o) => o.value === keep)) sel.value = keep;
}

// An arm message, for the arm in the page.
function armInPage(msg: Record<string, unknown>): void {
  const t = msg.type;
  if (t === "arm_ports") return showPorts();
  if (t === "arm_connect" && typeof msg.port === "string" && msg.port.startsWith("page:")) {
    void connectInPage(msg.port);
    return;
  }
  if (!armLink) return;
  if (t === "arm_send") armLink.send(String(msg.line ?? ""));
  else if (t === "arm_stop") armLink.stop();
  else if (t === "arm_run") armLink.runProgram(String(msg.text ?? ""));
  else if (t === "arm_disconnect") armLink.disconnect().then(() => (armLink = null));
}

// The port the arm panel's choice names: the virtual Nano, or a Nano on USB that the browser
// asks the user to pick (Web Serial, with their permission). `why` when there is none: no Web
// Serial here, or (empty) the user chose none.
async function choosePort(which: string): Promise<{ port: SerialLike; label: string } | { why: string }> {
  if (which === "page:virtual") {
    const port = virtualNano();
    const g = robot?.gripper;
    port.servo = g ? { closed: g.servo_closed_deg, open: g.servo_open_deg } : null;
    return { port, label: "the virtual Nano" };
  }
  if (which !== "page:serial") return { why: "Choose the virtual Nano or a Nano on USB first." };
  const api = webSerial();
  if (!api) return { why: "This browser has no Web Serial (Chrome, Edge and Opera have it): use the virtual Nano." };
  try {
    const port = await api.requestPort();
    const info = port.getInfo?.() ?? {};
    return { port, label: info.usbVendorId
      ? `USB ${info.usbVendorId.toString(16)}:${(info.usbProductId ?? 0).toString(16)}` : "a serial port" };
  } catch {
    return { why: "" }; // the user chose none
  }
}

async function connectInPage(which: string): Promise<void> {
  if (armLink) await armLink.disconnect();
  const chosen = await choosePort(which);
  if ("why" in chosen) {
    if (chosen.why) banner(chosen.why);
    return;
  }
  armLink = new ArmLink(armEngine, (m) => handle(m as unknown as ServerMsg));
  await armLink.connect(chosen.port, chosen.label, robot?.name ?? "");
  if (!armLink.connected) armLink = null;
}

// One virtual Nano for the page's life: what is flashed to it stays until the page closes.
function virtualNano(): VirtualNanoPort {
  if (nanoPort) return nanoPort;
  const port = (nanoPort = new VirtualNanoPort());
  port.onState = (st) => {
    hook.arm.nano = st;
    const servo = st.gripper === null ? "" : `; its servo pulse ${Math.round(st.servoUs ?? 0)} us: gripper ${st.gripper.toFixed(0)} %`;
    $("arm-speed").textContent = (st.behind ? `the virtual Nano is behind real time: ${st.rtf.toFixed(2)}x`
      : `the virtual Nano keeps real time (it could run ${(st.capacity ?? 0).toFixed(1)}x; ${port.flashBytes.toLocaleString("en")} B of firmware)`) + servo;
    $("arm-speed").className = `rtf ${st.behind ? "behind" : ""}`;
  };
  return port;
}

// ---- flashing the Nano on the chosen port (stk500.mjs) with this site's firmware

interface FirmwareInfo { file: string; bytes: number; version: string; robot: string; sha256: string }
let firmware: FirmwareInfo | null = null;

async function loadFirmwareInfo(): Promise<void> {
  try {
    const r = await fetch(new URL("data/firmware/firmware.json", document.baseURI));
    firmware = r.ok ? ((await r.json()) as FirmwareInfo) : null;
  } catch {
    firmware = null;
  }
  $("flash-info").textContent = firmware
    ? `Articula ${firmware.version} for the ${firmware.robot}, ${firmware.bytes.toLocaleString("en")} bytes`
    : "this site carries no firmware";
  ($("arm-flash") as HTMLButtonElement).disabled = !firmware;
}

function flashState(text: string, kind: "" | "ok" | "bad" = ""): void {
  const st = $("flash-state");
  st.textContent = text;
  st.className = `status ${kind}`;
}

async function flashFirmware(): Promise<void> {
  const f = hook.flash;
  if (f.busy || !firmware) return;
  if (robot && robot.name !== firmware.robot)
    return flashState(`This site's firmware is built for the ${firmware.robot}; the studio shows the ${robot.name}. ` +
      "Load that robot, or build the firmware for this one (make ARTICULA_ROBOT=...).", "bad");
  const chosen = await choosePort(($("arm-port") as HTMLSelectElement).value);
  if ("why" in chosen) return chosen.why ? flashState(chosen.why, "bad") : undefined;
  const port = chosen.port;
  if (armLink) {
    await armLink.disconnect(); // the bootloader needs the port to itself
    armLink = null;
  }
  Object.assign(f, { busy: true, phase: "connect", done: 0, total: 0, error: "", errorKind: "", result: null });
  const bar = $("flash-progress") as HTMLProgressElement;
  const button = $("arm-flash") as HTMLButtonElement;
  button.disabled = true;
  bar.hidden = false;
  bar.value = 0;
  flashState("resetting the Nano into its bootloader…");
  try {
    const r = await fetch(new URL(`data/firmware/${firmware.file}`, document.baseURI));
    if (!r.ok) throw new Error(`the firmware's file is missing from this site (${r.status})`);
    const hex = await r.text();
    const result = await flashNano(port, hex, {
      onProgress: (p) => {
        Object.assign(f, { phase: p.phase, done: p.done, total: p.total });
        // writing is two thirds of the bar, reading back the last third
        const part = p.total ? p.done / p.total : 0;
        bar.value = { connect: 0, write: (2 * part) / 3, verify: (2 + part) / 3, done: 1 }[p.phase];
        if (p.phase === "write") flashState(`writing page ${p.done} of ${p.total} (${p.baud.toLocaleString("en")} baud)`);
        else if (p.phase === "verify") flashState(`reading back page ${p.done} of ${p.total}`);
      },
    });
    f.result = result;
    f.phase = "done";
    flashState(`Flashed and verified: ${result.bytes.toLocaleString("en")} bytes in ${result.seconds.toFixed(1)} s ` +
      `(${result.baud === 115200 ? "Optiboot" : "the old bootloader"}, ${result.baud.toLocaleString("en")} baud). Connect to drive it.`, "ok");
  } catch (e) {
    f.error = (e as Error).message;
    f.errorKind = e instanceof FlashError ? e.kind : "other";
    flashState(`Flashing failed: ${f.error}`, "bad");
  } finally {
    f.busy = false;
    button.disabled = false;
  }
}

// Slider and drag intents: one in flight, the newest replaces any waiting one.
function request(msg: Record<string, unknown>): void {
  msg.seq = ++seq;
  sentAt.set(seq, performance.now());
  if (inFlight >= MAX_IN_FLIGHT) {
    queued = msg;
    return;
  }
  inFlight++;
  send(msg);
}

function replyArrived(): void {
  inFlight = Math.max(0, inFlight - 1);
  if (queued) {
    const next = queued;
    queued = null;
    inFlight++;
    send(next);
  }
}

view.onFrame = (now) => {
  hook.fps = view.fps;
  if (view.continuous) $("fps").textContent = `${view.fps} frames/s`;
  hook.framesDrawn = view.framesDrawn;
  hook.targetScreen = view.targetScreen();
  if (!hook.firstFrameAt && hook.pose && robot) hook.firstFrameAt = now;
  for (const s of pendingDrawn) {
    const t0 = sentAt.get(s);
    if (t0 !== undefined) {
      hook.latency.push(now - t0);
      sentAt.delete(s);
    }
  }
  pendingDrawn = [];
  // `?` to the drawn pose: the server's round trip to the arm, then its message to this frame
  for (const m of armDrawn) {
    if (m.rtt_ms !== null) hook.arm.roundTrips.push(m.rtt_ms + (performance.timeOrigin + now - m.sent_ms));
  }
  armDrawn = [];
};

// ---- the engine (a Web Worker)

function startEngine(): void {
  setConn("starting the engine…", "ok");
  worker = new Worker(new URL("assets/worker.js", document.baseURI), { type: "module" });
  worker.onmessage = (e) => {
    const m = e.data as ServerMsg | { type: "ready"; ms: number } | { type: "fatal"; message: string };
    hook.messages++;
    if (m.type === "ready") {
      engineReady = true;
      hook.engineStartMs = m.ms;
      hook.connected = true;
      setConn("engine ready", "ok");
      send({ type: "hello" });
      return;
    }
    if (m.type === "fatal") {
      setConn("the engine did not start", "bad");
      banner(`${m.message}. The studio needs a browser with WebAssembly and module workers (Chrome, Edge, Firefox, Safari of the last three years).`);
      return;
    }
    if (hook.physics?.on) hook.stream.messages++;
    handle(m);
  };
  worker.onerror = (e) => {
    setConn("the engine stopped", "bad");
    banner(`The engine stopped: ${e.message}`);
  };
  worker.postMessage({ type: "start", robot: params.get("robot") ?? undefined, scene: params.get("scene") ?? undefined });
}

// What the arm panel offers, in one sentence, before an arm is connected.
function armHelp(): void {
  const st = $("arm-state");
  st.className = "status";
  st.textContent = webSerial()
    ? "Connect the virtual Nano (the firmware running in this page), or a Nano on USB: the browser asks which port."
    : "This browser has no Web Serial (Chrome, Edge and Opera have it): the virtual Nano runs the firmware here.";
}

function setConn(text: string, kind: "ok" | "bad"): void {
  const c = $("conn");
  c.textContent = text;
  c.className = `conn ${kind}`;
}

function banner(text: string, kind: "error" | "info" = "error"): void {
  $("banner-text").textContent = text;
  $("banner").className = `banner ${kind}`;
  $("banner").hidden = false;
}
$("banner-close").onclick = () => ($("banner").hidden = true);

// ---- messages from the server

function handle(m: ServerMsg): void {
  switch (m.type) {
    case "robot":
      buildRobot(m);
      break;
    case "pose":
      showPose(m);
      break;
    case "ik":
    case "jt_frame":
      showIk(m);
      break;
    case "timeline":
      hook.timeline = m;
      hook.programError = "";
      plots.show(m);
      programStatus(`${m.records.length} commands, ${m.summary.rejected ?? 0} rejected` +
        (m.summary.worst_error_mm !== undefined ? `, worst quantization error ${m.summary.worst_error_mm.toFixed(3)} mm` : "") +
        `, ${m.duration.toFixed(2)} s`, rejectedLines(m));
      if (autoplay) {
        autoplay = false;
        send({ type: "play" });
      }
      break;
    case "playing":
      hook.playing = m.playing;
      $("run").classList.toggle("active", m.playing);
      break;
    case "program_error":
      hook.programError = m.message;
      programStatus(m.message, [], true);
      highlightLine(m.line, true);
      break;
    case "program_text":
      ($("editor") as HTMLTextAreaElement).value = m.text;
      currentProgram = m.name;
      editorChanged();
      break;
    case "robot_error":
      pendingSpec = null;
      hook.robotError = m.message;
      banner(`This robot file cannot be used, the robot stays ${robot?.name ?? ""}: ${m.message}`);
      break;
    case "scene":
      showScene(m);
      break;
    case "physics":
      showPhysics(m);
      break;
    case "arm_parsed":
    case "arm_posed":
    case "arm_predicted":
    case "status_text": {
      const c = calls.get((m as { id?: number }).id ?? -1);
      if (c) {
        calls.delete((m as { id: number }).id);
        c.resolve(m as unknown as Record<string, unknown>);
      }
      break;
    }
    case "arm":
      showArm(m);
      break;
    case "arm_status":
      hook.arm.status = m;
      if (m.stop_to_idle_ms !== undefined) hook.arm.stopMs = m.stop_to_idle_ms;
      view.liveFrames(m.frames);
      armDrawn.push(m);
      $("arm-state").className = "status ok";
      $("arm-state").innerHTML = `<div class="reply-grid"><b>${hook.arm.label}</b><span>${m.state}, steps ${m.steps.join(" ")}</span>
        <b>angles</b><span>${m.angles.map((a) => a.toFixed(2)).join(" ")} deg</span>
        <b>from the model</b><span>${armDiff(m).toFixed(2)} mm (tool to tool)</span></div>`;
      break;
    case "arm_reply": {
      hook.arm.reply = m;
      const p = m.predicted;
      const arm = m.reply === null ? `no answer: ${m.error}` : m.reply === "ok" ? "ok" : `${m.reply} (${m.meaning})`;
      const model = p.reply === "ok" ? `ok${p.steps ? `, steps ${p.steps.join(" ")}` : ""}` : `${p.reply} (${p.meaning})`;
      $("arm-reply").className = `status ${m.reply === p.reply ? "" : "bad"}`;
      $("arm-reply").innerHTML = `<div class="reply-grid"><b>sent</b><span>${esc(m.line)}</span><b>the arm</b><span>${esc(arm)}</span>
        <b>the model</b><span>${esc(model)}</span></div>`;
      break;
    }
    case "arm_program":
      if (m.done) {
        hook.arm.programDone = true;
        programStatus(m.error ? `The arm stopped: ${m.error}` : m.stopped ? "Stopped: no further line is sent."
          : `The arm ran the program: ${m.sent} lines.`, [], !!m.error);
      } else {
        highlightLine(m.line ?? 0, m.reply !== "ok");
        hook.arm.programLines.push([m.line, m.reply]);
        programStatus(`on the arm, line ${m.line}: ${m.command} -> ${m.reply}${m.reply !== "ok" ? ` (${m.meaning})` : ""}` +
          (m.predicted && m.predicted.reply !== m.reply ? `; the model said ${m.predicted.reply}` : ""));
      }
      break;
    case "arm_stopped":
      programStatus("stop sent: the arm decelerates to rest and empties its queue");
      break;
    case "sim_command":
      hook.simCommand = m.line;
      if (m.seq !== undefined && m.seq !== null) replyArrived();
      break;
    case "teach": {
      hook.teach = m.line;
      const ed = $("editor") as HTMLTextAreaElement;
      ed.value = ed.value.replace(/\s*$/, "") + (ed.value.trim() ? "\n" : "") + m.line + "\n";
      editorChanged();
      programStatus(`taught: ${m.line.replace(/\n/g, " ")}`);
      break;
    }
    case "urdf":
      download(`${m.name.replace(/\W+/g, "_")}.urdf`, m.xml, "application/xml");
      break;
    case "error":
      if (m.id !== undefined && calls.has(m.id)) {
        calls.get(m.id)!.reject(new Error(m.message));
        calls.delete(m.id);
        break;
      }
      hook.errors++;
      if (m.message.startsWith("internal error")) hook.internalErrors.push(m.message);
      hook.lastError = m.message;
      replyArrived();
      banner(m.message);
      break;
  }
}

// The arm's tool from the model's (both drawn from the engine's frames), mm.
function armDiff(m: ArmStatusMsg): number {
  const f = m.frames[m.frames.length - 1], tool = hook.pose?.tool.xyz;
  if (!f || !tool) return NaN;
  return Math.hypot(f[3] - tool[0], f[7] - tool[1], f[11] - tool[2]);
}

let pendingSpec: Record<string, unknown> | null = null; // a robot asked for, until it is shown

function buildRobot(r: RobotMsg): void {
  robot = r;
  if (pendingSpec && !r.keep_view) robotSpec = pendingSpec;
  pendingSpec = null;
  hook.robot = r;
  hook.robotError = "";
  const built = view.build(r);
  view.showAxes(($("show-axes") as HTMLInputElement).checked);
  $("robot-name").textContent = r.description ? `${r.name}: ${r.description}` : r.name;
  $("robot-name").title = r.source;
  const sel = $("robot-select") as HTMLSelectElement;
  sel.innerHTML = r.robots.map((n) => `<option>${n}</option>`).join("");
  const stem = r.source.split("/").pop()?.replace(/\.json$/, "") ?? "";
  sel.value = r.robots.includes(stem) ? stem : "";
  const ps = $("program-select") as HTMLSelectElement;
  ps.innerHTML = `<option value="">examples&hellip;</option>` + r.programs.map((n) => `<option>${n}</option>`).join("");
  buildJoints(r);
  $("gripper-row").hidden = !r.gripper;
  if (r.keep_view) return; // the same robot, other link lengths
  hook.timeline = null;
  plots.clear();
  if (r.import_notes.length) banner(`Imported. ${r.import_notes.length} things had no place in a robot file; the first: ${r.import_notes[0]}`, "info");
  needFit = built;
}

function buildJoints(r: RobotMsg): void {
  const box = $("joints");
  box.innerHTML = "";
  r.joints.forEach((j, i) => {
    const row = document.createElement("div");
    row.className = "joint";
    const step = j.unit === "deg" ? 0.1 : 0.5;
    row.innerHTML = `<label title="${j.param === "theta" ? "An angle about z" : j.param === "alpha" ? "A twist about x" : "A slide along z"} of DH row ${j.row}: ${j.min} .. ${j.max} ${j.unit}">${j.name} <span class="unit">${j.param}<sub>${j.param === "alpha" ? j.row - 1 : j.row}</sub>, ${j.unit}</span></label>
      <input type="range" min="${j.min}" max="${j.max}" step="${step}" data-joint="${i}">
      <input type="number" min="${j.min}" max="${j.max}" step="${step}" data-joint="${i}">`;
    box.appendChild(row);
  });
  // RoboSim's l: a slider for each row whose length a(i-1) the robot file lets change.
  const lengths = r.dh.map((row, i) => ({ a: row.a as unknown, row: i + 1 }))
    .filter((x) => typeof x.a === "object" && x.a !== null) as { a: { value: number; min: number; max: number }; row: number }[];
  for (const { a, row } of lengths) {
    const div = document.createElement("div");
    div.className = "joint length";
    div.innerHTML = `<label title="The length a(${row - 1}) of DH row ${row}: ${a.min} .. ${a.max} mm (RoboSim's l)">a<sub>${row - 1}</sub> <span class="unit">row ${row} length, mm</span></label>
      <input type="range" min="${a.min}" max="${a.max}" step="0.5" value="${a.value}" data-length="${row}">
      <input type="number" min="${a.min}" max="${a.max}" step="0.5" value="${a.value}" data-length="${row}">`;
    box.appendChild(div);
  }
  box.querySelectorAll<HTMLInputElement>("input[data-joint]").forEach((inp) => {
    inp.addEventListener("input", () => {
      const v = parseFloat(inp.value);
      if (!Number.isFinite(v)) return;
      request({ type: "set_joint", joint: Number(inp.dataset.joint), value: v });
    });
  });
  box.querySelectorAll<HTMLInputElement>("input[data-length]").forEach((inp) => {
    inp.addEventListener("change", () => {
      const values = lengths.map(({ row, a }) => {
        const el = box.querySelector<HTMLInputElement>(`input[data-length="${row}"]${inp.dataset.length === String(row) ? `[type=${inp.type}]` : ""}`);
        const v = el ? parseFloat(el.value) : a.value;
        return Number.isFinite(v) ? v : a.value;
      });
      request({ type: "set_lengths", values });
    });
  });
  const w = $("weights");
  w.innerHTML = (r.motors.length ? r.motors : r.joints.map((j) => j.name))
    .map((n, i) => `<label>${n} <input type="number" min="0" step="0.1" value="1" data-weight="${i}"></label>`)
    .join("");
}

function fmt(v: number, d = 2): string {
  return (Math.abs(v) < 0.5 * 10 ** -d ? 0 : v).toFixed(d);
}

function showPose(p: PoseMsg): void {
  hook.pose = p;
  if (p.seq !== undefined && p.seq !== null) {
    pendingDrawn.push(p.seq);
    replyArrived();
  }
  if (!showGhost) delete p.ghost;
  view.pose(p);
  if (needFit) {
    needFit.then(() => requestAnimationFrame(() => view.fit(false)));
    needFit = null;
  }
  if (!robot) return;
  // sliders and numbers follow the pose (not the one being dragged)
  $("joints").querySelectorAll<HTMLInputElement>("input[data-joint]").forEach((inp) => {
    const v = p.q[Number(inp.dataset.joint)];
    if (document.activeElement !== inp) inp.value = inp.type === "number" ? fmt(v, 2) : String(v);
  });
  const g = $("gripper") as HTMLInputElement;
  if (document.activeElement !== g) g.value = String(p.gripper);
  ($("gripper-num") as HTMLInputElement).value = fmt(p.gripper, 0);
  const linkedParams = new Set<string>();
  robot.dh.forEach((row, i) => {
    for (const k of ["a", "alpha", "d", "theta"]) {
      const v = row[k] as Record<string, unknown> | number;
      if (typeof v === "object" && v && "linked" in v) linkedParams.add(`${i}.${k}`);
    }
  });
  const varParams = new Set(robot.joints.map((j) => `${j.row - 1}.${j.param}`));
  $("dh").querySelector("tbody")!.innerHTML = p.dh_table
    .map((r, i) => {
      const cells = ["a", "alpha", "d", "theta"].map((k, c) => {
        const cls = varParams.has(`${i}.${k}`) ? "var" : linkedParams.has(`${i}.${k}`) ? "linked" : "";
        return `<td class="${cls}">${fmt(r[c], c % 2 ? 2 : 1)}</td>`;
      });
      return `<tr><td>${i + 1}</td>${cells.join("")}</tr>`;
    })
    .join("");
  const [x, y, z] = p.tool.xyz;
  const [ro, pi, ya] = p.tool.rpy;
  $("tool").innerHTML = `<div><b>x</b> ${fmt(x)}</div><div><b>y</b> ${fmt(y)}</div><div><b>z</b> ${fmt(z)} <span class="unit">mm</span></div>
    <div><b>roll</b> ${fmt(ro, 1)}</div><div><b>pitch</b> ${fmt(pi, 1)}</div><div><b>yaw</b> ${fmt(ya, 1)} <span class="unit">deg</span></div>`;
  if (p.t !== undefined) {
    plots.playhead(p.t);
    highlightLine(p.line ?? 0, false);
    const err = p.error_mm !== undefined ? `, quantization error ${p.error_mm.toFixed(3)} mm` : "";
    $("view-status").textContent = `t = ${p.t.toFixed(2)} s, line ${p.line ?? 0}${err}${p.steps ? `, steps ${p.steps.join(" ")}` : ""}`;
  }
  if (!$("show-target").matches(":checked") || !dragging) {
    syncTargetInputs(p.tool.xyz, p.tool.rpy, false);
  }
  if (!hook.ready) {
    hook.ready = true;
    syncTargetInputs(p.tool.xyz, p.tool.rpy, true);
  }
}

function syncTargetInputs(xyz: number[], rpy: number[], moveGizmo: boolean): void {
  if (document.activeElement?.closest("#ik-section")) return;
  ["tx", "ty", "tz"].forEach((id, i) => (($(id) as HTMLInputElement).value = fmt(xyz[i], 1)));
  ["troll", "tpitch", "tyaw"].forEach((id, i) => (($(id) as HTMLInputElement).value = fmt(rpy[i], 1)));
  if (moveGizmo || !view.target.visible) view.setTarget(xyz, rpy);
}

function showIk(m: IkMsg): void {
  hook.ik = m;
  if (dragging) hook.ikUpdates.push(performance.now());
  const el = $("ik-status");
  const err = `${m.position_error_mm.toFixed(3)} mm` + (m.orientation_error_deg ? `, ${m.orientation_error_deg.toFixed(3)} deg` : "");
  let text = "";
  if (m.status === "reached") text = `Reached (${m.solver}, ${m.iterations} iterations): ${err} from the target.`;
  else if (m.status === "unreachable") text = `Unreachable: the arm stretches toward it and stays ${err} away` + (m.beyond_reach ? " (farther than the arm is long)." : ".");
  else if (m.status === "limited") text = `Not reached: held back by the limit of ${m.limited_by.join(", ") || "a joint"}; ${err} away.`;
  else text = `Not reached yet after ${m.iterations} iterations: ${err} away.`;
  if (m.type === "jt_frame") {
    text = `Jacobian transpose, iteration ${m.iteration}: ${err} away.`;
    if (m.done) {
      if (m.status === "reached") text += " Converged.";
      else if (m.status === "limited") text += ` Stopped: held back by the limit of ${m.limited_by.join(", ") || "a joint"}.`;
      else if (m.status === "unreachable") text += " Stopped: the target is out of reach; the arm stretches toward it.";
      else text += " Stopped: it stopped improving (stuck in a local minimum, or the arm 'fell in line').";
    }
    else if ((m.iteration ?? 0) >= 400) text += " Stopped after 400 iterations.";
  }
  el.textContent = text;
  el.className = `status ${m.status === "reached" ? "ok" : m.status === "budget" && m.type === "jt_frame" && !m.done ? "" : "bad"}`;
}

// ---- the arm in the loop

function esc(s: string): string {
  return s.replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]!);
}

function showArm(m: { connected: boolean; connecting?: boolean; label?: string; error?: string; lost?: boolean }): void {
  hook.arm.connected = m.connected;
  hook.arm.error = m.error ?? "";
  if (m.label) hook.arm.label = m.label;
  $("arm-connect").hidden = m.connected;
  $("arm-disconnect").hidden = !m.connected;
  $("arm-send-row").hidden = !m.connected;
  $("drive-arm-row").hidden = !m.connected;
  const st = $("arm-state");
  if (m.connecting) {
    st.className = "status";
    st.textContent = "connecting...";
  } else if (m.error) {
    st.className = "status bad";
    st.textContent = m.lost ? `Lost the arm: ${m.error}. The studio goes on with the model.` : m.error;
    if (m.lost) banner(`Lost the arm: ${m.error}`);
    view.liveFrames(null);
  } else if (!m.connected) {
    st.textContent = "";
    view.liveFrames(null);
  }
}

function sendArmLine(): void {
  const inp = $("arm-line") as HTMLInputElement;
  if (inp.value.trim()) send({ type: "arm_send", line: inp.value.trim() });
}

function stopEverything(): void {
  if (hook.arm.connected) {
    hook.arm.stopMs = null; // until the arm reports itself at rest
    send({ type: "arm_stop" });
  }
  if (hook.playing || hook.physics?.running) send({ type: "pause" });
}

$("arm-connect").onclick = () => {
  const port = ($("arm-port") as HTMLSelectElement).value;
  if (port) send({ type: "arm_connect", port, robot: robotSpec });
  else send({ type: "arm_ports" });
};
$("arm-disconnect").onclick = () => send({ type: "arm_disconnect" });
$("arm-flash").onclick = () => void flashFirmware();
$("arm-send").onclick = sendArmLine;
$("arm-line").addEventListener("keydown", (e) => {
  if ((e as KeyboardEvent).key === "Enter") sendArmLine();
});
$("stop").onclick = stopEverything;
window.addEventListener("keydown", (e) => {
  if (e.key === "Escape") stopEverything();
});

// ---- live physics

const TROUBLE = new Set(["collision", "self_collision", "squeeze", "steps_lost", "blocked", "rejected", "object_removed",
  "gripper_blocked", "stall"]);

function showScene(m: SceneMsg): void {
  hook.scene = m;
  const sel = $("scene-select") as HTMLSelectElement;
  sel.innerHTML = `<option value="">off</option>` + m.scenes.map((n) => `<option>${n}</option>`).join("");
  sel.value = m.name ?? "";
  view.setObjects(m.objects);
  $("physics-bar").hidden = m.name === null;
  $("events").hidden = m.name === null;
  $("events").innerHTML = "";
}

function showPhysics(p: PhysicsMsg): void {
  hook.physics = p;
  if (!p.on) return;
  view.physics(p);
  if (p.t !== undefined && hook.timeline) plots.playhead(p.t);
  if (p.fresh) {
    hook.events = [];
    $("events").innerHTML = "";
  }
  const rtf = $("phys-rtf");
  if (p.running === false) {
    rtf.textContent = `paused at ${p.t?.toFixed(2)} s`;
    rtf.className = "rtf";
  } else if (p.rtf !== undefined && p.rtf !== null) {
    const cap = p.capacity ? `, could run ${Math.round(p.capacity)}x` : "";
    rtf.textContent = p.behind ? `behind real time: ${p.rtf.toFixed(2)}x` : `${p.rtf.toFixed(2)}x real time${cap}`;
    rtf.className = `rtf ${p.behind ? "behind" : ""}`;
  }
  const log = $("events");
  for (const e of p.events ?? []) {
    hook.events.push(e);
    const d = document.createElement("div");
    d.className = TROUBLE.has(e.kind) ? "trouble" : e.kind === "grasp" || e.kind === "release" ? "grasp" : "";
    d.textContent = `${e.t.toFixed(2)} s ${e.kind}: ${e.a}${e.b ? ` / ${e.b}` : ""}${e.detail ? ` - ${e.detail}` : ""}`;
    d.title = d.textContent;
    log.appendChild(d);
    if (e.kind !== "contact_ended") {
      if (e.a) view.flash(e.a);
      if (e.b && e.b !== "ground") view.flash(e.b);
    }
  }
  while (log.childElementCount > 200) log.firstElementChild!.remove();
  if (p.events?.length) log.scrollTop = log.scrollHeight;
  if (p.steps && robot?.motors.length) $("view-status").textContent = `t = ${p.t?.toFixed(2)} s, steps ${p.steps.join(" ")}` +
    (p.lost?.some((v) => v) ? `, lost ${p.lost.join(" ")}` : "");
}

$("scene-select").addEventListener("change", (e) => {
  const v = (e.target as HTMLSelectElement).value;
  send({ type: "scene", name: v || null });
});
$("phys-run").onclick = () => send({ type: "physics_run" });
$("phys-pause").onclick = () => send({ type: "physics_pause" });
$("phys-step").onclick = () => send({ type: "physics_step" });
$("phys-reset").onclick = () => send({ type: "physics_reset" });
let dragSent = 0;
view.onDrag = (object, target) => {
  if (target === null) return send({ type: "release" });
  const now = performance.now();
  if (now - dragSent < 15) return; // one pull a display frame is plenty
  dragSent = now;
  send({ type: "drag", object, target });
};

// ---- controls: robot, joints, IK

$("robot-select").addEventListener("change", (e) => {
  pendingSpec = { name: (e.target as HTMLSelectElement).value };
  send({ type: "load_robot", name: (e.target as HTMLSelectElement).value });
});
$("open-robot").onclick = () => $("robot-file").click();
$("robot-file").addEventListener("change", async (e) => {
  const all = [...((e.target as HTMLInputElement).files ?? [])];
  (e.target as HTMLInputElement).value = "";
  // The robot file, and any mesh files (STL, OBJ) its shapes name, opened together.
  const f = all.find((x) => /\.(json|txt)$/i.test(x.name)) ?? all[0];
  if (!f) return;
  const meshes = all.filter((x) => x !== f);
  if (f.size > MAX_FILE || meshes.some((x) => x.size > MAX_FILE))
    return banner(`That file is larger than ${MAX_FILE / 1e6} MB: the studio opens robot files and meshes up to that size.`);
  const text = await f.text();
  const files = await Promise.all(meshes.map(async (x) => ({ name: x.name, data: await x.arrayBuffer() })));
  const transfer = files.map((x) => x.data);
  if (f.name.toLowerCase().endsWith(".json")) {
    pendingSpec = { text, filename: f.name };
    send({ type: "load_robot", text, filename: f.name, files }, transfer);
  } else {
    const s = prompt(`${f.name} is a robot file of the thesis's original system: how many millimetres is one of its units? (the thesis's MK2 model: 25.75)`, "10");
    if (s === null) return;
    const scale = parseFloat(s);
    if (!(scale > 0)) return banner("The scale must be a number above 0");
    pendingSpec = { text, filename: f.name, legacy: true, scale };
    send({ type: "load_robot", text, filename: f.name, legacy: true, scale }, transfer);
  }
});
$("export-urdf").onclick = () => send({ type: "export_urdf" });
$("home").onclick = () => send({ type: "home" });
$("zero").onclick = () => send({ type: "zero" });
for (const id of ["gripper", "gripper-num"]) {
  $(id).addEventListener("input", (e) => {
    const v = parseFloat((e.target as HTMLInputElement).value);
    if (Number.isFinite(v)) send({ type: "gripper", percent: Math.min(100, Math.max(0, v)) });
  });
}
$("fit").onclick = () => view.fit();
$("show-axes").addEventListener("change", (e) => view.showAxes((e.target as HTMLInputElement).checked));
$("show-target").addEventListener("change", (e) => {
  const on = (e.target as HTMLInputElement).checked;
  if (on && hook.pose) view.setTarget(hook.pose.tool.xyz, hook.pose.tool.rpy);
  view.showTarget(on);
});
$("gizmo-mode").addEventListener("change", (e) => view.gizmoMode((e.target as HTMLSelectElement).value as "translate" | "rotate"));
$("use-rpy").addEventListener("change", (e) => ($("rpy-row").hidden = !(e.target as HTMLInputElement).checked));

function ikMessage(type: string, xyz?: number[], rpy?: number[]): Record<string, unknown> {
  const num = (id: string) => parseFloat(($(id) as HTMLInputElement).value);
  const pos = xyz ?? [num("tx"), num("ty"), num("tz")];
  const useRpy = ($("use-rpy") as HTMLInputElement).checked;
  const ang = rpy ?? [num("troll"), num("tpitch"), num("tyaw")];
  const msg: Record<string, unknown> = { type, target: useRpy ? [...pos, ...ang] : pos, solver: ($("solver") as HTMLSelectElement).value };
  const w = [...$("weights").querySelectorAll<HTMLInputElement>("input")].map((i) => parseFloat(i.value));
  if (w.some((v) => v !== 1)) msg.weights = w;
  return msg;
}

$("solve").onclick = () => {
  const m = ikMessage("ik");
  view.setTarget((m.target as number[]).slice(0, 3), (m.target as number[]).slice(3));
  send(m);
};
$("animate-jt").onclick = () => {
  const m = ikMessage("jt_animate");
  view.setTarget((m.target as number[]).slice(0, 3), (m.target as number[]).slice(3));
  send(m);
};
for (const id of ["tx", "ty", "tz", "troll", "tpitch", "tyaw"]) {
  $(id).addEventListener("keydown", (e) => {
    if ((e as KeyboardEvent).key === "Enter") $("solve").click();
  });
}
view.onTarget = (t, final) => {
  dragging = !final;
  ["tx", "ty", "tz"].forEach((id, i) => (($(id) as HTMLInputElement).value = fmt(t.xyz[i], 1)));
  ["troll", "tpitch", "tyaw"].forEach((id, i) => (($(id) as HTMLInputElement).value = fmt(t.rpy[i], 1)));
  request(ikMessage("ik", t.xyz, t.rpy));
};

document.addEventListener("keydown", (e) => {
  const t = e.target as HTMLElement;
  if (t.closest("input, textarea, select")) return;
  if (view.key(e.code)) e.preventDefault();
});

// ---- programs

let currentProgram = "program.arm";
let autoplay = false;
let showGhost = true;
const editor = $("editor") as HTMLTextAreaElement;

function editorChanged(): void {
  const n = editor.value.split("\n").length;
  $("gutter").innerHTML = Array.from({ length: n }, (_, i) => `<div>${i + 1}</div>`).join("");
  $("gutter").scrollTop = editor.scrollTop;
  hook.timeline = null;
}
editor.addEventListener("input", editorChanged);
editor.addEventListener("scroll", () => {
  $("gutter").scrollTop = editor.scrollTop;
  positionLine();
});
let lineShown = 0;
function highlightLine(line: number, error: boolean): void {
  if (line > 0 && line !== lineShown) {
    // keep the line in sight: scroll the editor when it leaves the visible part
    const lh = parseFloat(getComputedStyle(editor).lineHeight) || 18;
    const top = (line - 1) * lh, view = editor.clientHeight;
    if (top < editor.scrollTop || top + lh > editor.scrollTop + view) editor.scrollTop = Math.max(0, top - view / 3);
    $("gutter").scrollTop = editor.scrollTop;
  }
  lineShown = line;
  const bar = $("current-line");
  bar.hidden = line <= 0;
  bar.classList.toggle("error", error);
  positionLine();
}
function positionLine(): void {
  const lh = parseFloat(getComputedStyle(editor).lineHeight) || 18;
  const pad = parseFloat(getComputedStyle(editor).paddingTop) || 0;
  $("current-line").style.top = `${pad + (lineShown - 1) * lh - editor.scrollTop}px`;
  $("current-line").style.height = `${lh}px`;
}

function programStatus(text: string, rejected: string[] = [], bad = false): void {
  const el = $("program-status");
  el.innerHTML = "";
  const head = document.createElement("div");
  head.textContent = text;
  el.appendChild(head);
  for (const r of rejected) {
    const d = document.createElement("div");
    d.className = "rejected";
    d.textContent = r;
    el.appendChild(d);
  }
  el.className = `status ${bad ? "bad" : ""}`;
}

function rejectedLines(m: TimelineMsg): string[] {
  return m.records
    .filter((r) => r.reply !== "ok")
    .map((r) => `line ${r.line}: ${r.command} → error:${r.code}, ${r.error}: nothing moves`);
}

function loadProgram(): void {
  send({ type: "program_load", text: editor.value, name: currentProgram });
}

$("program-select").addEventListener("change", (e) => {
  const name = (e.target as HTMLSelectElement).value;
  if (name) send({ type: "program_open", name });
  (e.target as HTMLSelectElement).value = "";
});
$("open-program").onclick = () => $("program-file").click();
$("program-file").addEventListener("change", async (e) => {
  const f = (e.target as HTMLInputElement).files?.[0];
  if (!f) return;
  editor.value = await f.text();
  currentProgram = f.name;
  (e.target as HTMLInputElement).value = "";
  editorChanged();
});
$("save-program").onclick = () => download(currentProgram, editor.value, "text/plain");
$("run").onclick = () => {
  if (hook.arm.connected && ($("drive-arm") as HTMLInputElement).checked) {
    hook.arm.programLines = [];
    hook.arm.programDone = false;
    send({ type: "arm_run", text: editor.value, name: currentProgram });
    return;
  }
  if (hook.timeline) send({ type: "play" });
  else {
    autoplay = true;
    loadProgram();
  }
};
$("pause").onclick = () => send({ type: "pause" });
$("step").onclick = () => {
  if (hook.timeline) send({ type: "step" });
  else loadProgram();
};
$("reset").onclick = () => {
  if (hook.timeline) send({ type: "rewind" });
  else loadProgram();
};
$("teach").onclick = () => {
  const robosim = currentProgram.endsWith(".robosim") || /^\s*[a-z]\s*$/m.test(editor.value.split("\n").find((l) => l.trim() && !l.trim().startsWith("#")) ?? "");
  send({ type: "teach", format: robosim ? "robosim" : "protocol" });
};
$("show-ghost").addEventListener("change", (e) => {
  showGhost = (e.target as HTMLInputElement).checked;
  if (!showGhost) view.pose({ ...hook.pose!, ghost: undefined });
});
plots.onSeek = (t) => send({ type: "seek", t });

$("export-png").onclick = () => plots.png().then((blob) => blob && download("articula-plots.png", blob, "image/png"));
$("export-csv").onclick = () => hook.timeline && download("articula-timeline.csv", plots.csv(hook.timeline), "text/csv");

function download(name: string, data: string | Blob, type: string): void {
  const blob = typeof data === "string" ? new Blob([data], { type }) : data;
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

// ---- start

$("tour-button").onclick = () => startTour(true);
editorChanged();
// Offline use and installing as an app (sw.js keeps the whole site).
if ("serviceWorker" in navigator && !params.has("nosw")) navigator.serviceWorker.register("sw.js").catch(() => undefined);
showPorts();
armHelp();
loadFirmwareInfo();
startTour(false);
