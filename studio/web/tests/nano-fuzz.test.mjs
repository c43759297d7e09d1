// A protocol fuzz on the page's virtual Nano (avr8js running the firmware's hex), as hil.fuzz
// does on simavr's: 800 seeded random lines, valid and malformed (every command both
// accepted and refused at least once, checked below). Each gets exactly one reply, the reply
// the controller model (the engine's predict) gives for it after the lines the Nano accepted,
// the Nano never hangs, and a refused line moves nothing.
//
// Run alone: node --no-experimental-fetch --test studio/web/tests/nano-fuzz.test.mjs
// (ARTICULA_FUZZ_LINES=2000 for the long run).
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { test } from "node:test";
import { REPO, nodeEngine, nodeNanoParts } from "../../../wasm/js/node.mjs";
import { VirtualNano } from "../src/virtual-nano/avr-nano.mjs";
import { rng } from "./seeded.mjs";

const HEX = process.env.ARTICULA_NANO_HEX || join(REPO, "build/avr/firmware/articula-nano.hex");
const LINES = Number(process.env.ARTICULA_FUZZ_LINES || 800);

test(`${LINES} random lines: one reply each, the model's, and no motion on a refused one`, async (t) => {
  const engine = await nodeEngine();
  const mk2 = engine.robot("mk2plus");
  const n = new VirtualNano({ hex: readFileSync(HEX, "utf8"), parts: await nodeNanoParts() });
  const lines = [];
  n.onLine = (l) => lines.push(l);
  const until = (pred, seconds) => {
    const end = n.seconds + seconds;
    while (!pred()) {
      if (n.seconds > end) return false;
      n.runFor(0.001);
    }
    return true;
  };
  const status = () => {
    const from = lines.length;
    n.send("?");
    assert.ok(until(() => lines.slice(from).some((l) => l.startsWith("<")), 0.5), "no status report: the Nano hangs");
    return engine.parseArmLine(lines.slice(from).find((l) => l.startsWith("<")));
  };
  const history = ["$0=3000", "$1=20000"]; // brisk moves, so that 2,000 lines take little emulated time
  let index = 0;
  // At rest once the model's duration for the line has passed (and a little more).
  const idle = (line, seconds) => {
    const end = n.seconds + seconds + 0.5;
    let s;
    for (;;) {
      s = status();
      if (s.state === "Idle") return s;
      if (n.seconds > end) break;
      n.runFor(0.02);
    }
    assert.fail(`line ${index}, after '${line}': not Idle ${seconds.toFixed(2)} s (the model's time) + 0.5 s later: ` +
      `${JSON.stringify(s)}; before it: ${history.slice(-6).join(" / ")}`);
  };
  n.runFor(0.3);
  const r = rng(20261124);
  const pick = (a) => a[Math.floor(r() * a.length)];
  const num = () => (r() < 0.7 ? (r() * 300 - 150).toFixed(pick([0, 1, 2, 3])) : pick(["1e3", "NaN", "--5", "4.", ".5", "99999999", "-0", "+7", ""]));
  const garbage = () => String.fromCharCode(...Array.from({ length: 1 + Math.floor(r() * 30) }, () => 32 + Math.floor(r() * 95)))
    .replace(/[?!~]/g, "x");
  const gen = () => {
    const k = r();
    if (k < 0.25) return `L ${Math.floor(r() * 4)} ${num()}`;
    if (k < 0.4) return `M ${num()} ${num()} ${num()}`;
    if (k < 0.5) return `G ${Math.floor(r() * 130) - 10}`;
    if (k < 0.58) return `P ${num()} ${num()} ${num()}`;
    if (k < 0.65) return pick(["$0=3000", "$1=60000", "$0=200", "$9=5", "$1=-4", "$5=100"]);
    if (k < 0.7) return "x".repeat(60 + Math.floor(r() * 40)); // overlong
    // (not H: homing seeks an endstop switch, and the emulated Nano has none wired)
    if (k < 0.8) return pick(["I", "L", "M 1 2", "L 0 10 20", "S 1", "S 2", "Z", ""]);
    return garbage();
  };
  for (const line of history) {
    n.send(line + "\n");
    until(() => lines.includes("ok"), 1);
    lines.length = 0;
  }
  let before = idle("the settings", 0);
  let refused = 0, accepted = 0;
  const seen = {}; // command word -> [accepted, refused]
  for (let i = 0; i < LINES; i++) {
    const line = gen();
    index = i + 1;
    const doc = (() => {
      try {
        return mk2.predict([...history, line].join("\n") + "\n", "fuzz.arm");
      } catch {
        return null; // the program reader refuses it: the firmware answers with an error
      }
    })();
    const want = doc ? doc.records.at(-1) : null;
    lines.length = 0;
    n.send(line + "\n");
    const isReply = (l) => l === "ok" || l.startsWith("error:");
    assert.ok(until(() => lines.some(isReply), 2), `line ${i + 1} '${line}': no reply (a hang)`);
    n.runFor(0.005); // a second reply would be here by now
    const replies = lines.filter(isReply);
    const info = lines.filter((l) => l.startsWith("["));
    assert.equal(replies.length, 1, `line ${i + 1} '${line}': ${replies.length} replies: ${replies}`);
    const reply = replies[0];
    if (line.trim() === "I") assert.equal(info.length, 1, "I answers its banner, then ok");
    if (want && line.trim() !== "") {
      const model = want.code === 0 ? "ok" : `error:${want.code}`;
      assert.equal(reply, model, `line ${i + 1} '${line}': the Nano says ${reply}, the model ${model}`);
    } else {
      assert.notEqual(reply, "ok", `line ${i + 1} '${line}': the program reader refuses it, the Nano took it`);
    }
    const word = /^[A-Z$]/.test(line) ? line[0] : "other";
    seen[word] ??= [0, 0];
    seen[word][reply === "ok" ? 0 : 1]++;
    if (reply === "ok") {
      accepted++;
      history.push(line);
      before = idle(line, want ? want.seconds : 0);
    } else {
      refused++;
      n.runFor(0.02);
      const after = status();
      assert.deepEqual(after.steps, before.steps, `line ${i + 1} '${line}' (${reply}) moved the arm`);
    }
  }
  t.diagnostic(`${LINES} lines: ${accepted} accepted, ${refused} refused, one reply each, the model's; ` +
    `${n.seconds.toFixed(1)} s emulated, coil faults ${n.coilFaults}, bytes lost ${n.overruns}`);
  // every command was taken and refused: the fuzz reaches each one's checks both ways
  for (const w of ["L", "M", "G", "P", "$", "S", "I"])
    assert.ok(seen[w] && seen[w][0] > 0 && (w === "I" || seen[w][1] > 0), `'${w}' not both accepted and refused: ${JSON.stringify(seen)}`);
  assert.ok(seen.Z && seen.other && seen.other[1] > 0, `Z and garbage lines sent: ${JSON.stringify(seen)}`);
  t.diagnostic(`by command (accepted, refused): ${JSON.stringify(seen)}`);
  assert.equal(n.coilFaults, 0);
  assert.equal(n.overruns, 0, "received bytes lost");
  n.delete();
  mk2.delete();
});
