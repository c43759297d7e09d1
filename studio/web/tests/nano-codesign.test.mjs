// Co-design: one firmware, configured at run time for each arm of hil/robots (the thesis's
// example, the 3-link arm with made-up motors, a half-step MK2, an MK2 with other gears and a
// reversed motor, an MK2 on 28BYJ-48s and ULN2003 boards, an MK2 on STEP/DIR drivers in a CNC
// shield's sockets, which runs the shield's build, an MK2 on servos, which runs the servo build), on the page's virtual Nano (avr8js): its configuration's lines (the web
// engine's nanoConfig, as the studio sends them) then the plans of hil/plans and random
// lines, each against `articula predict` for that arm: the same reply, the same steps (the
// status report's and the coils'), and every move's duration. hil/tests/test_harness.py runs
// the same arms on simavr.
import assert from "node:assert/strict";
import { readFileSync, readdirSync } from "node:fs";
import { join } from "node:path";
import { test } from "node:test";
import { REPO, nodeEngine, nodeNanoParts } from "../../../wasm/js/node.mjs";
import { VirtualNano } from "../src/virtual-nano/avr-nano.mjs";
import { command, runRecords } from "./run-records.mjs";

const HEX = process.env.ARTICULA_NANO_HEX || join(REPO, "build/avr/firmware/articula-nano.hex");
// An arm on STEP/DIR drivers runs the build for a CNC shield, beside it.
const CNC_HEX = join(HEX, "..", "articula-cnc.hex");
// An arm on servos runs the servo build.
const SERVO_HEX = join(HEX, "..", "articula-servo.hex");
// The co-design arms, and the shipped robots of each new drive (as hil/tests/test_harness.py).
const ARMS = readdirSync(join(REPO, "hil/robots")).filter((f) => f.endsWith(".json")).sort().map((f) => `hil/robots/${f}`)
  .concat(["robots/mk2plus-cnc.json", "robots/mearm.json", "robots/eezybot-mk2.json", "robots/micro-arm-28byj48.json"]);
const PLANS = readdirSync(join(REPO, "hil/plans")).filter((f) => f.endsWith(".arm")).sort();
const RANDOM_LINES = 130; // with the plans' 73 lines, at least 200 an arm

// A small seeded generator (mulberry32): the same lines every run.
function rng(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

// Random protocol lines for an arm: absolute moves (some beyond a limit), relative turns,
// points (some out of reach), the gripper and short waits.
function randomLines(info, hasPoint, seed, count) {
  const r = rng(seed);
  const motors = info.motors;
  const out = [];
  const deg = (x) => (Math.round(x * 1000) / 1000).toString();
  for (let k = 0; k < count; k++) {
    const pick = r();
    if (pick < 0.45) {
      out.push("M " + motors.map((m) => deg(m.min - 5 + r() * (m.max - m.min + 10))).join(" "));
    } else if (pick < 0.7) {
      out.push(`L ${Math.floor(r() * motors.length)} ${deg((r() - 0.5) * 40)}`);
    } else if (pick < 0.85) {
      const reach = info.reach_mm * 1.1;
      out.push(`P ${deg((r() - 0.5) * 2 * reach)} ${deg((r() - 0.5) * 2 * reach)} ${deg(r() * reach)}`);
    } else if (pick < 0.95) {
      out.push(`G ${Math.floor(r() * 101)}`);
    } else {
      out.push("D 0.05");
    }
  }
  if (!hasPoint) out.push("P 100 0 100");
  return out.join("\n") + "\n";
}

test("one firmware, every arm of hil/robots configured at run time, on avr8js: replies, steps and durations as predicted", async (t) => {
  const engine = await nodeEngine();
  const parts = await nodeNanoParts();
  const hex = readFileSync(HEX, "utf8"), cncHex = readFileSync(CNC_HEX, "utf8"), servoHex = readFileSync(SERVO_HEX, "utf8");
  for (const file of ARMS) {
    engine.writeFile(`/hil-robots/${file.split("/").pop()}`, readFileSync(join(REPO, file)));
    const robot = engine.robot(`/hil-robots/${file.split("/").pop()}`);
    const cfg = robot.nanoConfig();
    const cnc = robot.info.motors.every((m) => m.driver.kind === "step-dir");
    const servo = robot.info.motors.every((m) => m.driver.kind === "servo");
    const servos = servo ? robot.info.motors.map((m) => ({ pin: m.driver.pin, zeroUs: m.driver.at[0][0] })) : null;
    const n = new VirtualNano({ hex: cnc ? cncHex : servo ? servoHex : hex, parts, cnc, servos });
    const lines = [];
    n.onLine = (l) => lines.push(l);
    n.runFor(0.3);
    // A fresh Nano runs the MK2 (on a CNC shield, the MK2 on A4988s); the lines make it this arm, at once.
    let [reply, before] = command(n, lines, "I");
    assert.equal(engine.parseArmLine(before[0]).checksum, cnc ? 65000 : servo ? 45618 : 21232, `${file}: a fresh Nano's banner`);
    for (const l of cfg.lines) assert.equal(command(n, lines, l)[0], "ok", `${file}: ${l}`);
    [reply, before] = command(n, lines, "I");
    const banner = engine.parseArmLine(before[0]);
    assert.equal(banner.checksum, cfg.checksum, `${file}: the banner after configuring`);
    assert.equal(banner.robot, cfg.name);
    assert.equal(banner.joints, robot.info.motors.length);
    robot.info.motors.forEach((m, i) => {
      if (cnc || servo) return; // STEP/DIR drivers and servos: a pulse is a step (or ticks), whatever the microsteps
      if (m.microsteps === 2) n.decoders[i].forceHalfStep();
      if (m.driver.kind === "uln2003") n.decoders[i].setUnipolar(true); // the motors the arm is wired with
    });
    let commands = 0, refused = 0, timed = 0, worst = 0, worstUs = 0;
    const texts = PLANS.map((p) => [p, readFileSync(join(REPO, "hil/plans", p), "utf8")]);
    texts.push(["random.arm", randomLines(robot.info, cfg.has_point, 7, RANDOM_LINES)]);
    for (const [name, text] of texts) {
      const records = robot.predict(text, name).records;
      // Each plan from step 0, as predict assumes: the power-up pose, by M to the zero angles.
      const zero = "M " + robot.info.motors.map((m) => m.zero).join(" ");
      assert.equal(command(n, lines, zero)[0], "ok", `${file}: ${zero}`);
      while (!n.steps.every((s) => Math.abs(s) <= (servo ? 1 : 0))) n.runFor(0.05);
      n.runFor(0.1);
      const r = runRecords(n, lines, engine, records, `${file} ${name}`, undefined, servo);
      commands += r.commands;
      refused += r.refused;
      timed += r.timed;
      if (Math.abs(r.worst) > Math.abs(worst)) worst = r.worst;
      worstUs = Math.max(worstUs, r.worstUs);
    }
    assert.equal(n.coilFaults, 0, `${file}: coil faults`);
    assert.equal(n.overruns, 0, `${file}: received bytes lost`);
    t.diagnostic(`${cfg.name} (K:${cfg.checksum}${cfg.has_point ? "" : ", no P"}): ${commands} commands ` +
      `(${refused} refused as predicted), steps matched ${commands}/${commands}; ${timed} moves timed, worst duration ` +
      `error ${worst >= 0 ? "+" : ""}${worst.toFixed(5)} % (${worstUs.toFixed(1)} us)`);
    n.delete();
    robot.delete();
  }
});
