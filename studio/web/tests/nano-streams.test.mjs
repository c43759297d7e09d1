// The look-ahead planner on the page's virtual Nano (avr8js): the streamed programs of
// hil/streams sent as `articula predict --sender stream` models the host (each line as soon
// as the reply to the one before is out), every move blended as the firmware plans it. The
// same steps as the prediction, and the span from the first step to the last within 0.01 %
// of the prediction's (simavr: hil/tests/test_planner_streams.py).
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { test } from "node:test";
import { REPO, nodeEngine, nodeNanoParts } from "../../../wasm/js/node.mjs";
import { CLOCK_HZ, VirtualNano } from "../src/nano.mjs";
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
