// The page's arm link (src/link/arm-link.ts, bundled as the page has it) driving the page's
// virtual Nano (avr8js, the firmware's own hex) in node, with the web engine reading the arm's
// lines: what the Run on the arm does at the protocol's edges, without a browser.
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { test } from "node:test";
import { REPO, nodeEngine, nodeNanoParts } from "../../../wasm/js/node.mjs";
import { VirtualNano } from "../src/virtual-nano/avr-nano.mjs";
import { NanoPort } from "./nano-port.mjs";
import { load } from "./page-module.mjs";

const HEX = process.env.ARTICULA_NANO_HEX || join(REPO, "build/avr/firmware/articula-nano.hex");

// (node before 21 has no navigator: the page's environment module reads its language)
globalThis.navigator ??= { language: "en" };

// The page's link on a virtual Nano running the MK2's firmware; `messages` is what it told the page.
async function linked() {
  const engine = await nodeEngine();
  const robot = engine.robot("mk2plus");
  const { ArmLink } = await load("link/arm-link.ts");
  const parts = await nodeNanoParts();
  const nano = new VirtualNano({ hex: readFileSync(HEX, "utf8"), parts });
  const messages = [];
  const armEngine = {
    // the worker's arm_read (engine/arm.ts): the core's reading, the pose from the reported angles
    read: async (line) => {
      const parsed = engine.parseArmLine(line);
      return { parsed, pose: parsed.kind === "status" ? { q: parsed.angles, frames: [], line: "" } : null };
    },
    // the Run's waits are what is under test: a line predicted to take no time at all gets
    // the link's least time to come to rest (5 s of the arm's)
    predict: async (history, line) => ({ command: engine.lineCommand(line), reply: "ok", steps: null, meaning: "", seconds: 0 }),
    meaning: (reply) => reply,
    reply: (name) => { const c = Object.entries(engine.status).find(([, [n]]) => n === name)[0]; return c === "0" ? "ok" : `error:${c}`; },
    config: async () => robot.nanoConfig(),
  };
  const link = new ArmLink(armEngine, (m) => messages.push(m));
  const port = new NanoPort(nano);
  port.pace = 1; // in real time, as the page's worker runs it (the link polls by the page's clock)
  await link.connect(port, "the virtual Nano", "MK2 Plus");
  assert.equal(link.connected, true, JSON.stringify(messages.at(-1)));
  return { link, messages, nano, parts };
}

// Until a message that `f` picks, for at most `seconds` of the wall's time (a hang's guard).
async function until(messages, f, seconds = 120) {
  const end = performance.now() + seconds * 1000;
  for (;;) {
    const m = messages.find(f);
    if (m) return m;
    assert.ok(performance.now() < end, `no such message in ${seconds} s; the last: ${JSON.stringify(messages.slice(-3))}`);
    await new Promise((r) => setTimeout(r, 20));
  }
}

test("after a failed homing the Run goes on at Alarm, as the harness does", async (t) => {
  const { link, messages, nano, parts } = await linked();
  // an endstop switch on the base (the board's pin, open: its input high) that is never pressed:
  // the search runs out of steps and the arm is in Alarm, at rest; G still works there
  const { port, bit } = parts.wiring.endstops[0];
  nano.ports[port].setPin(bit, true);
  link.runProgram("$4=4000\n$3=1\nH\nG 50\n");
  const end = await until(messages, (m) => m.type === "arm_program" && m.done);
  const lines = messages.filter((m) => m.type === "arm_program" && !m.done);
  assert.equal(end.error, undefined, `the Run ended with: ${end.error}`);
  assert.deepEqual(lines.map((m) => [m.command, m.reply]), [["$4=4000", "ok"], ["$3=1", "ok"], ["H", "ok"], ["G 50", "ok"]]);
  const states = messages.filter((m) => m.type === "arm_status").map((m) => m.state);
  assert.ok(states.includes("Alarm"), `no Alarm reported: ${[...new Set(states)]}`);
  t.diagnostic(`states seen: ${[...new Set(states)].join(", ")}; ${nano.seconds.toFixed(2)} s of the Nano's time`);
  await link.disconnect();
  nano.delete();
});

// What a student types in the Send box gets the arm's own answer, not only its ok: `$` its
// settings, `I` its banner, and a `?` (the realtime byte, no line's end) its status report.
test("typed $, I and ? show what the arm prints", async (t) => {
  const { link, messages, nano } = await linked();
  const replyTo = (line) => until(messages, (m) => m.type === "arm_reply" && m.line === line);
  // an `I` the connection sent while the Nano was starting, lost: it stays at the head of the
  // lines waiting for a reply until the next reply clears it (as a slow page's connect leaves it)
  link.lines.unanswered.unshift({ line: "I", banner: true, output: [] });
  await link.send("$");
  const settings = await replyTo("$");
  assert.equal(settings.reply, "ok");
  assert.ok(settings.output.some((l) => /^\$0=\d+/.test(l)), `no $0 among: ${JSON.stringify(settings.output)}`);
  assert.ok(settings.output.length >= 8, `${settings.output.length} settings`);
  await link.send("I");
  const info = await replyTo("I");
  assert.equal(info.reply, "ok");
  assert.equal(info.output.length, 1);
  assert.match(info.output[0], /MK2 Plus/);
  await link.send("?");
  const status = await replyTo("?");
  assert.equal(status.reply, "status", JSON.stringify(status));
  assert.match(status.output[0], /^<(Idle|Run|Alarm)/);
  assert.equal(messages.filter((m) => m.type === "arm_reply" && m.reply && m.reply.startsWith("error")).length, 0,
    "nothing typed was refused");
  await link.send("L 0 5");
  const moved = await replyTo("L 0 5");
  assert.equal(moved.reply, "ok");
  assert.deepEqual(moved.output, []);
  t.diagnostic(`$: ${settings.output.length} lines; I: ${info.output[0]}; ?: ${status.output[0]}`);
  await link.disconnect();
  nano.delete();
});

// A Run sends each line once the arm reports the last at rest. The rest is heard from the first
// report read after the line's `ok` (the arm answers in order: a report read before the `ok` may
// say Idle from before the line was queued), so no line starts while the one before still moves,
// and none waits the 150 ms the link used to wait for every line.
test("a Run sends each line once the arm has come to rest after the last", async (t) => {
  const { link, messages, nano } = await linked();
  t.after(async () => {
    await link.disconnect();
    nano.delete();
  });
  link.runProgram("L 0 10\nL 0 -10\nL 0 5\nG 20\nL 0 0\n");
  const end = await until(messages, (m) => m.type === "arm_program" && m.done);
  assert.equal(end.error, undefined, `the Run ended with: ${end.error}`);
  assert.equal(end.sent, 5);
  // each line's message comes at its `ok`; before the next one's, a report at rest at the line's angle
  const at = (m) => messages.indexOf(m);
  const lines = messages.filter((m) => m.type === "arm_program" && !m.done);
  const want = [10, 0, 5, 5, 5]; // (L turns a joint by its angle)
  for (let i = 0; i + 1 < lines.length; i++) {
    const between = messages.slice(at(lines[i]) + 1, at(lines[i + 1])).filter((m) => m.type === "arm_status");
    const rest = between.filter((m) => m.state === "Idle");
    assert.ok(rest.length > 0, `line ${i + 2} was sent with no report at rest after line ${i + 1}`);
    assert.ok(Math.abs(rest.at(-1).angles[0] - want[i]) < 0.5, `after line ${i + 1} the base was at ${rest.at(-1).angles[0]}, not ${want[i]}`);
    // ... and the line moved before it: the base's angle was not yet there at the first report
    if (i < 3) assert.ok(between.some((m) => m.state === "Run"), `line ${i + 1} was never seen running`);
  }
  t.diagnostic(`5 lines in ${end.seconds.toFixed(2)} s of the arm's time`);
});

test("a reply the page was slow to read is the arm's answer, not a timeout (a busy page's engine)", async () => {
  // On half a core the page's engine read each line seconds late; a reply behind a status
  // report waited in the page while the virtual Nano's clock ran past its 5 s deadline.
  const { ArmLines } = await load("link/arm-lines.ts");
  let clock = 0;
  let push = null;
  const port = {
    readable: new ReadableStream({ start(c) { push = (t) => c.enqueue(new TextEncoder().encode(t)); } }),
    writable: new WritableStream({
      write(chunk) {
        const line = new TextDecoder().decode(chunk).trim();
        if (line === "M 0 90 0") push("<Run|S:0,0,0|A:0.000,90.000,0.000|G:0>\nok\n"); // answered at once
      },
    }),
    async open() {}, async close() {},
    clock: () => clock,
  };
  // the engine's reading of a status report takes 8 s of the arm's time (the page was busy)
  const read = async (line) => {
    if (line.startsWith("<")) {
      for (let i = 0; i < 80; i++) {
        clock += 100;
        await new Promise((r) => setTimeout(r, 1));
      }
      return { parsed: { kind: "status" }, pose: null };
    }
    return { parsed: { kind: line === "ok" ? "reply" : "other" }, pose: null };
  };
  const lines = new ArmLines(read, () => undefined, () => undefined);
  await lines.openPort(port);
  assert.equal(await lines.request("M 0 90 0"), "ok");
  // and an arm that never answers still times out, in its own time
  const silent = lines.request("G 50", 1000);
  const tick = setInterval(() => (clock += 50), 1);
  await assert.rejects(silent, /no reply to 'G 50' within 1 s/);
  clearInterval(tick);
});
