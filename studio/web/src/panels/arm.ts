// The arm panel: the virtual Nano (the firmware's hex in this page) or a Nano on USB (Web
// Serial, opened only when the user asks), its state beside the model's, a line to send with
// the arm's reply and the model's prediction side by side, programs run on the arm, STOP.
// Everything the arm says (its banner's robot name, its replies) is shown as text.
import { cellRunning } from "./cell";
import { ArmLink } from "../link/arm-link";
import type { ArmStatusMsg, EngineMsg, NanoConfig } from "../engine/messages";
import { VirtualNanoPort, webSerial } from "../link/ports";
import type { SerialLike } from "../link/ports";
import type { Studio } from "../page/context";
import { $, banner, fill, h, setOptions } from "../page/dom";
import { noteError } from "../page/errors";
import type { Reports } from "../page/reports";

/** The arm's link as this panel sees it (window.articula.arm shows it; main.ts wires it). */
export const armReport: Reports["arm"] = {
  get connected() { return s?.editor.armConnected ?? false; },
  error: "", label: "", status: null, reply: null, stopMs: null, programLines: [], programDone: false, roundTrips: [], nano: null,
  configurable: false, configured: null, checksum: null, lostTrace: [], console: 0, pausedAt: 0,
};

let armRefusals: { line: number; command: string; reply: string; meaning: string }[] = []; // this run's refused lines
let s: Studio;
let link: ArmLink | null = null; // the arm, while connected (or connecting)
let nanoPort: VirtualNanoPort | null = null;
let wasConnected = false;
const say = (text: string, rejected: string[] = [], bad = false) => s.editor.signals.programSaid.dispatch({ text, rejected, bad });

export function initArm(studio: Studio): void {
  s = studio;
  // the arm while connected (or waiting to be configured), for the other panels
  s.editor.arm = { link: () => link, run: runOnArm, send: sendToArm, choosePort, disconnect: disconnectArm,
    pose: () => armReport.status?.q ?? null,
    restAt: () => (armReport.status?.state === "Idle" ? armReport.status.sent_ms - performance.timeOrigin : -Infinity) };
  s.editor.signals.robotShown.add(armRobotShown);
  $("arm-connect").onclick = () => {
    const port = ($("arm-port") as HTMLSelectElement).value;
    if (port) void connect();
    else showPorts();
  };
  $("arm-disconnect").onclick = () => void disconnectArm();
  $("arm-configure").onclick = () => void link?.configure();
  $("arm-send").onclick = sendLine;
  $("console-clear").onclick = () => {
    traffic.length = 0;
    drawConsole();
  };
  $("console-status").addEventListener("change", drawConsole);
  $("arm-line").addEventListener("keydown", (e) => {
    if ((e as KeyboardEvent).key === "Enter") sendLine();
  });
  showPorts();
  const st = $("arm-state");
  st.className = "status";
  st.textContent = webSerial()
    ? "Connect the virtual Nano (the firmware running in this page), or a Nano on USB: the browser asks which port."
    : "This browser has no Web Serial (Chrome, Edge and Opera have it): the virtual Nano runs the firmware here.";
}

function showPorts(): void {
  setOptions($("arm-port") as HTMLSelectElement, [
    { value: "page:virtual", label: "the virtual Nano (its firmware in this page)" },
    ...(webSerial() ? [{ value: "page:serial", label: "a Nano on USB (Web Serial)…" }] : []),
  ]);
}

/** The port the panel's choice names: the virtual Nano, or a Nano on USB that the browser asks
 * the user to pick (Web Serial, with their permission). `why` when there is none: no Web
 * Serial here, or (empty) the user chose none. */
async function choosePort(): Promise<{ port: SerialLike; label: string } | { why: string }> {
  const which = ($("arm-port") as HTMLSelectElement).value;
  if (which === "page:virtual") {
    const port = virtualNano();
    const g = s.editor.robot?.gripper;
    port.servo = g ? { closed: g.servo_closed_deg, open: g.servo_open_deg } : null;
    port.cnc = s.editor.robot?.firmware === "articula-cnc"; // the robot's motors on a CNC shield's STEP/DIR drivers
    // a servo arm: the servo build, each servo's pin and its pulse at step 0
    port.servos = s.editor.robot?.servos ?? null;
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

async function connect(): Promise<void> {
  await disconnectArm();
  const chosen = await choosePort();
  if ("why" in chosen) {
    if (chosen.why) banner(chosen.why);
    return;
  }
  link = new ArmLink({
    read: (line) => s.engine.call({ type: "arm_read", line }) as never,
    predict: (history, line) => s.engine.call({ type: "arm_predict", history, line }) as never,
    meaning: (reply) => s.engine.meaning(reply),
    reply: (name) => s.engine.reply(name),
    config: async () => ((await s.engine.call({ type: "arm_config" })) as unknown as { config: NanoConfig | { error: string } }).config,
  }, (m) => (m.type === "arm_console" ? consoleLine(m as unknown as Traffic) : armMessage(m as unknown as EngineMsg)));
  await link.connect(chosen.port, chosen.label, s.editor.robot?.name ?? "");
  if (!link.connected && !link.configurable) link = null;
}

/** Another robot is shown: the Nano is driven only if it is configured for that one. */
function armRobotShown(): void {
  if (link && (link.connected || link.configurable)) void link.recheck(s.editor.robot?.name ?? "");
}


/** Closes the arm's port (flashing needs it to itself). */
async function disconnectArm(): Promise<void> {
  const l = link;
  link = null;
  await l?.disconnect();
}

// One virtual Nano for the page's life: what is flashed to it stays until the page closes.
function virtualNano(): VirtualNanoPort {
  if (nanoPort) return nanoPort;
  const port = (nanoPort = new VirtualNanoPort());
  port.speed = s.editor.speed;
  s.editor.signals.speedChanged.add((speed) => port.setSpeed(speed));
  port.onState = (st) => {
    const { trail, ...rest } = st;
    armReport.nano = rest;
    if (trail?.length) s.editor.signals.nanoSteps.dispatch({ rows: trail, motors: st.steps.length });
    const servo = st.gripper === null ? "" : `; its servo pulse ${Math.round(st.servoUs ?? 0)} us: gripper ${st.gripper.toFixed(0)} %`;
    const pace = st.speed === 1 ? "real time" : `${st.speed}x real time`;
    $("arm-speed").textContent = (st.behind ? `the virtual Nano is behind ${st.speed === 1 ? pace : `its speed (${pace})`}: ${st.rtf.toFixed(2)}x`
      : `the virtual Nano ${st.speed === 1 ? "keeps" : "runs at"} ${pace} (it could run ${(st.capacity ?? 0).toFixed(1)}x; ${port.flashBytes.toLocaleString("en")} B of firmware)`) + servo;
    $("arm-speed").className = `rtf ${st.behind ? "behind" : ""}`;
  };
  return port;
}

// The console: every line sent to the arm and heard from it (the last CONSOLE_LINES), drawn at
// most once a frame; status reports only when asked for (15 a second would bury the rest).
type Traffic = { dir: "sent" | "heard"; line: string; status: boolean };
const CONSOLE_LINES = 400;
const traffic: (Traffic & { t: number })[] = [];
let consoleQueued = false;
function consoleLine(m: Traffic): void {
  traffic.push({ ...m, t: performance.now() });
  if (traffic.length > CONSOLE_LINES * 2) traffic.splice(0, traffic.length - CONSOLE_LINES * 2);
  armReport.console = traffic.length;
  if (!consoleQueued) {
    consoleQueued = true;
    requestAnimationFrame(drawConsole);
  }
}
function drawConsole(): void {
  consoleQueued = false;
  const box = $("arm-console");
  const statuses = ($("console-status") as HTMLInputElement).checked;
  const atEnd = box.scrollTop + box.clientHeight >= box.scrollHeight - 4;
  const shown = traffic.filter((m) => statuses || !m.status).slice(-CONSOLE_LINES);
  fill(box, ...shown.map((m) => h("div", { class: m.dir === "sent" ? "sent" : m.status ? "status-line" : /^(error|ALARM)/.test(m.line) ? "err" : null },
    `${m.dir === "sent" ? "→" : "←"} ${m.line}`)));
  if (atEnd) box.scrollTop = box.scrollHeight;
}

function sendLine(): void {
  const line = ($("arm-line") as HTMLInputElement).value.trim();
  if (line && link) void link.send(line);
}

/** One line to the arm, as the Send box sends it; false when no arm is connected. */
function sendToArm(line: string): boolean {
  if (!link) return false;
  void link.send(line);
  return true;
}

/** A program on the arm, line by line (the program panel's Run with "on the arm"). */
function runOnArm(text: string, breaks: Iterable<number> = []): void {
  armReport.programLines = [];
  armReport.programDone = false;
  armReport.pausedAt = 0;
  armRefusals = [];
  link?.runProgram(text, breaks);
}

/** STOP: the arm's realtime `!` at once, and the model's program or physics paused. */
export function stopEverything(): void {
  const arm = s.editor.armConnected && link;
  if (arm) {
    armReport.stopMs = null; // until the arm reports itself at rest
    void link!.stop();
  }
  const moving = s.editor.playing || !!s.editor.physics?.running || cellRunning();
  if (moving) s.engine.send({ type: "pause" });
  s.editor.stops++;
  s.editor.signals.stopped.dispatch();
  banner(arm ? "STOP: the arm slows to rest and forgets the lines it was given. Nothing more is sent."
    : moving ? "STOP: the program is paused where it was." : "STOP: nothing was moving.", "info");
}

interface ArmMsg {
  connected: boolean; connecting?: boolean; label?: string; error?: string; lost?: boolean; configurable?: boolean;
  configuring?: { done: number; total: number; name: string }; info?: { checksum: number | null };
  trace?: unknown[];
}

function showArm(m: ArmMsg): void {
  s.editor.armConnected = m.connected;
  armReport.error = m.error ?? "";
  if (m.trace) armReport.lostTrace = m.trace;
  armReport.configurable = !!m.configurable || !!m.configuring;
  if (m.info) armReport.checksum = m.info.checksum;
  if (m.label) armReport.label = m.label;
  const open = m.connected || armReport.configurable; // the port is ours
  $("arm-connect").hidden = open;
  $("arm-disconnect").hidden = !open;
  $("arm-configure-row").hidden = !m.configurable; // only when the Nano is another robot's
  $("arm-send-row").hidden = !m.connected;
  $("arm-console-box").hidden = !open;
  $("view-legend").hidden = !m.connected; // the teal arm beside the model: which is which
  if (m.connected !== wasConnected) {
    wasConnected = m.connected;
    s.editor.signals.armConnected.dispatch(m.connected);
  }
  const st = $("arm-state");
  if (m.configuring) {
    st.className = "status";
    st.textContent = `configuring the Nano for the ${m.configuring.name}: line ${m.configuring.done + 1} of ${m.configuring.total}`;
  } else if (m.connecting) {
    armReport.status = null; // the last connection's report and reply are no news of this one
    armReport.reply = null;
    $("arm-reply").textContent = "";
    st.className = "status";
    st.textContent = "connecting...";
  } else if (m.error) {
    st.className = m.configurable && !m.lost ? "status ask" : "status bad";
    st.textContent = m.lost ? `Lost the arm: ${m.error}. The studio goes on with the model.` : m.error;

    if (m.lost) banner(`Lost the arm: ${m.error}`);
    s.view.liveFrames(null);
  } else if (!m.connected) {
    st.textContent = "";
    st.className = "status";
    s.view.liveFrames(null);
  } else if (/^Lost the arm/.test($("banner-text").textContent ?? "")) {
    $("banner").hidden = true; // connected again: the old loss is no news
  }
  if (!m.connected) armReport.status = null;
}

// The arm's tool from the model's (both drawn from the engine's frames), mm.
function armDiff(m: ArmStatusMsg): number {
  const f = m.frames[m.frames.length - 1], tool = s.editor.pose?.tool.xyz;
  if (!f || !tool) return NaN;
  return Math.hypot(f[3] - tool[0], f[7] - tool[1], f[11] - tool[2]);
}

const grid = (...pairs: [string, string][]) =>
  h("div", { class: "reply-grid" }, ...pairs.flatMap(([k, v]) => [h("b", null, k), h("span", null, v)]));

/** Arm reports applied, waiting for the frame that shows them (for `?` to drawn pose). */
let drawnReports: ArmStatusMsg[] = [];

/** The frame at `now` shows them: `?` to pixels, ms, into the hook. */
export function armFrameDrawn(now: number): void {
  for (const m of drawnReports)
    if (m.rtt_ms !== null) armReport.roundTrips.push(m.rtt_ms + (performance.timeOrigin + now - m.sent_ms));
  drawnReports = [];
}

function armMessage(m: EngineMsg): void {
  switch (m.type) {
    case "arm":
      return showArm(m as unknown as ArmMsg);
    case "arm_configured": {
      const c = m as unknown as { name: string; checksum: number };
      armReport.configured = { name: c.name, checksum: c.checksum };
      return banner(`The Nano is now configured for the ${c.name} (checksum ${c.checksum}), kept in its EEPROM: ` +
        "it drives this robot from now on, after a power cycle too.", "info");
    }
    case "arm_status": {
      if (!s.editor.armConnected) return; // a report still in flight when the link was lost: not news of an arm
      armReport.status = m;
      if (m.stop_to_idle_ms !== undefined) armReport.stopMs = m.stop_to_idle_ms;
      s.view.liveFrames(m.frames);
      drawnReports.push(m);
      s.editor.signals.armReported.dispatch(m.q);
      $("arm-state").className = "status ok";
      fill($("arm-state"), grid([armReport.label, `${m.state}, steps ${m.steps.join(" ")}`],
        ["angles", `${m.angles.map((a) => a.toFixed(2)).join(" ")} deg`], ["from the model", `${armDiff(m).toFixed(2)} mm (tool to tool)`]));
      return;
    }
    case "arm_reply": {
      armReport.reply = m;
      const p = m.predicted;
      const output = m.output ?? [];
      // What the arm printed for the line (a `?`'s report, `$`'s settings, `I`'s banner) is its
      // answer as much as its ok: every line of it, as text.
      const arm = m.reply === null ? `no answer: ${m.error}` : m.reply === "status" ? output.join("\n")
        : [...output, m.reply === "ok" ? "ok" : `${m.reply} (${m.meaning})`].join("\n");
      const model = p.reply === "status" ? "(a status report: the arm's state now, nothing to predict)"
        : p.reply === "ok" ? `ok${p.steps ? `, steps ${p.steps.join(" ")}` : ""}${p.seconds ? `, ${p.seconds.toFixed(2)} s` : ""}`
        : `${p.reply} (${p.meaning})`;
      $("arm-reply").className = `status ${m.reply === p.reply ? "" : "bad"}`;
      fill($("arm-reply"), grid(["sent", m.line], ["the arm", arm], ["the model", model]));
      return;
    }
    case "arm_program":
      if (m.paused || m.resumed) {
        armReport.pausedAt = m.paused ? m.line ?? 0 : 0;
        s.editor.signals.lineRunning.dispatch({ line: m.line ?? 0, refused: false });
        if (m.paused) say(`Paused on the arm, at rest after line ${m.line}: Run goes on, Step runs one line, STOP ends the program.`);
        s.editor.signals.armPaused.dispatch(m.paused ? m.line ?? 0 : 0);
        return;
      }
      if (m.done) {
        if (armReport.pausedAt) s.editor.signals.armPaused.dispatch(0);
        armReport.pausedAt = 0;
        armReport.programDone = true;
        // every refusal stays in sight, under the summary
        const refused = armRefusals.map((r) => `line ${r.line}: ${r.command} → ${r.reply} (${r.meaning}): nothing moved`);
        // how long it took, beside the model's prediction: its moves, each line sent once the last
        // is at rest (as the page sends them); what the arm takes beyond it is each line's way
        // there and back, which the model leaves out
        const predicted = s.editor.timeline?.duration;
        const more = m.seconds !== undefined && predicted ? m.seconds - predicted : 0;
        const took = m.seconds === undefined ? "" : ` in ${m.seconds.toFixed(1)} s of the arm's time` + (!predicted ? ""
          : more < 0.05 ? ` (the model: ${predicted.toFixed(1)} s)`
          : ` (the model: ${predicted.toFixed(1)} s of moves; the ${more.toFixed(1)} s more, ${Math.round((more * 1000) / Math.max(1, m.sent ?? 1))} ms a line, ` +
            "is the Nano working each line out and the page hearing it come to rest)");
        say(m.error ? `The arm stopped: ${m.error}` : m.stopped ? "Stopped: no further line is sent."
          : refused.length ? `The arm ran the program: ${m.sent} lines, ${refused.length} refused${took}.`
          : `The arm ran the program: ${m.sent} lines, all accepted${took}.`, refused, !!m.error || refused.length > 0);
        armRefusals = [];
      } else {
        s.editor.signals.lineRunning.dispatch({ line: m.line ?? 0, refused: m.reply !== "ok" });
        if (m.reply !== "ok") {
          armRefusals.push({ line: m.line ?? 0, command: m.command ?? "", reply: m.reply ?? "", meaning: m.meaning ?? "" });
          s.editor.signals.lineRefused.dispatch({ line: m.line ?? 0, message: `the arm refused this: ${m.reply}, ${m.meaning}` });
        }
        armReport.programLines.push([m.line, m.reply]);
        say(`on the arm, line ${m.line}: ${m.command} -> ${m.reply}${m.reply !== "ok" ? ` (${m.meaning})` : ""}` +
          (m.predicted && m.predicted.reply !== m.reply ? `; the model said ${m.predicted.reply}` : ""));
      }
      return;
    case "arm_stopped":
      return say("stop sent: the arm decelerates to rest and empties its queue");
    case "error":
      noteError(m.message);
      return banner(m.message);
  }
}
