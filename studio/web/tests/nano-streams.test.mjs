// The look-ahead planner on the page's virtual Nano (avr8js): the streamed programs of
// hil/streams sent as `articula predict --sender stream` models the host (each line as soon
// as the reply to the one before is out), every move blended as the firmware plans it. The
// same steps as the prediction, and the span from the first step to the last within 0.01 %
// of the prediction's (simavr: hil/tests/test_planner_streams.py). Then the same streams
// stopped by '!' at set times.
import assert from "node:assert/strict";
import { execFileSync, spawnSync } from "node:child_process";
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { test } from "node:test";
import { REPO, nodeEngine, nodeNanoParts } from "../../../wasm/js/node.mjs";
import { CLOCK_HZ, VirtualNano } from "../src/virtual-nano/avr-nano.mjs";
import { until } from "./run-records.mjs";

const HEX = process.env.ARTICULA_NANO_HEX || join(REPO, "build/avr/firmware/articula-nano.hex");
const CLI = process.env.ARTICULA_CLI || join(REPO, "build/host/cli/articula");
const STREAMS = ["collinear-split", "circle", "zigzag", "square", "lines"];

test("streams on avr8js: blended to the predicted steps and span", async (t) => {
  const engine = await nodeEngine();
  const parts = await nodeNanoParts();
  const hex = readFileSync(HEX, "utf8");
  for (const name of STREAMS) {
    const file = join(REPO, "hil/streams", `${name}.arm`);
    const pred = JSON.parse(execFileSync(CLI, ["predict", "mk2plus", file, "--sender", "stream", "--json"], { encoding: "utf8" }));
    const moves = pred.records.filter((r) => (r.dominant_steps ?? 0) > 0);
    const lines = readFileSync(file, "utf8").split("\n").map((l) => l.split("#")[0].trim()).filter((l) => l);
    const n = new VirtualNano({ hex, parts });
    let next = 0, replies = 0;
    n.onLine = (l) => {
      if (l !== "ok" && !l.startsWith("error:")) return;
      replies++;
      if (next < lines.length) n.send(lines[next++] + "\n"); // the next line as the reply is out
    };
    n.runFor(0.3);
    n.markSteps();
    n.send(lines[next++] + "\n");
    assert.ok(until(n, () => replies === lines.length, 60), `${name}: ${replies} of ${lines.length} replies`);
    const last = moves[moves.length - 1];
    assert.ok(until(n, () => n.steps.every((s, i) => s === last.steps[i]), 30), `${name}: steps ${n.steps} not ${last.steps}`);
    n.runFor(0.1);
    assert.equal(n.coilFaults, 0, `${name}: coil faults`);
    assert.equal(n.overruns, 0, `${name}: received bytes lost`);
    // (a T line's first segment may cruise slower than the first step from rest: its cruise)
    const c0 = engine.firstIntervalS(600, 2000);
    const first = moves[0].segments ? Math.max(c0, (4 * moves[0].segments[0].cruise4) / 2e6) : c0;
    const predicted = (last.end_tick - moves[0].start_tick) / 2e6 - first;
    const measured = (n.lastStepCycle - n.firstStepCycle) / CLOCK_HZ;
    const err = ((measured - predicted) / predicted) * 100;
    t.diagnostic(`${name}: measured ${(measured * 1e3).toFixed(3)} ms, predicted ${(predicted * 1e3).toFixed(3)} ms ` +
      `(${err >= 0 ? "+" : ""}${err.toFixed(5)} %)`);
    assert.ok(Math.abs(err) <= 0.01, `${name}: ${err.toFixed(5)} % from the prediction`);
    n.delete();
  }
});

// '!' at set times after the first step (a student pressing STOP), as in
// hil/tests/test_planner_streams.py: the arm at rest on the predicted steps after each stop,
// the same replies (the line waiting then answered error:15).
const STOPS = { "stream-mixed": [0.15, 1.2, 2.5], "collinear-split": [0.1, 0.6], square: [0.4, 1.5] };

test("stops on avr8js: at rest on the predicted steps", async (t) => {
  const parts = await nodeNanoParts();
  const hex = readFileSync(HEX, "utf8");
  for (const [name, stopAt] of Object.entries(STOPS)) {
    const file = join(REPO, "hil/streams", `${name}.arm`);
    // (exit 1: a line the '!' answered error:15)
    const run = spawnSync(CLI, ["predict", "mk2plus", file, "--sender", "stream", "--json", "--stop-at", stopAt.join(",")],
      { encoding: "utf8" });
    assert.ok(run.status === 0 || run.status === 1, run.stderr);
    const pred = JSON.parse(run.stdout);
    const first = pred.summary.first_step_tick;
    const stops = pred.records.filter((r) => r.stop);
    const lines = readFileSync(file, "utf8").split("\n").map((l) => l.split("#")[0].trim()).filter((l) => l);
    const n = new VirtualNano({ hex, parts });
    let next = 0;
    const replies = [];
    n.onLine = (l) => {
      if (l !== "ok" && !l.startsWith("error:")) return;
      replies.push(l);
      if (next < lines.length) n.send(lines[next++] + "\n");
    };
    n.runFor(0.3);
    n.markSteps();
    n.send(lines[next++] + "\n");
    assert.ok(until(n, () => n.firstStepCycle >= 0, 2), `${name}: no step`);
    const at = (tick) => n.firstStepCycle + ((tick - first) * CLOCK_HZ) / 2e6; // a prediction's tick, in cycles
    const frame = 1360; // a byte on the wire: 10 bits of 136 cycles
    for (const s of stops) {
      // the '!' on the wire one frame before its tick (in slices, so that the lines keep coming)
      const send = Math.round(at(s.stop_at_tick)) - frame;
      while (n.cpu.cycles < send - 8000) n.runUntil(Math.min(send - 8000, n.cpu.cycles + 8000));
      n.runUntil(send);
      n.send("!");
      // at rest: 10 ms after the predicted rest, before a line taken up after it can step
      const look = Math.round(at(s.end_tick) + 0.01 * CLOCK_HZ);
      while (n.cpu.cycles < look) n.runUntil(Math.min(look, n.cpu.cycles + 8000));
      assert.deepEqual(n.steps, s.steps, `${name}: '!' at ${s.stop_at_tick}: at rest on ${n.steps}, predicted ${s.steps}`);
    }
    const expect = pred.records.filter((r) => !r.stop).map((r) => (r.reply === "ok" ? "ok" : `error:${r.code}`));
    assert.ok(until(n, () => replies.length === expect.length, 60), `${name}: ${replies.length} of ${expect.length} replies`);
    assert.deepEqual(replies, expect);
    const last = pred.records[pred.records.length - 1];
    assert.ok(until(n, () => n.steps.every((v, i) => v === last.steps[i]), 30), `${name}: steps ${n.steps} not ${last.steps}`);
    assert.equal(n.coilFaults, 0, `${name}: coil faults`);
    t.diagnostic(`${name}: '!' at ${stopAt.join(", ")} s, at rest on ${stops.map((s) => s.steps.join(" ")).join("; ")} as predicted`);
    n.delete();
  }
});
