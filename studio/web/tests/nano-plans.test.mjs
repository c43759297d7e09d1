// Two emulators, one prediction: the thesis's plans (hil/plans/*.arm, what `make demo` runs on
// simavr) on the page's virtual Nano (avr8js), every command against `articula predict`: the
// same reply, the same steps (the status report's and the coils'), and every move's duration,
// measured as the harness measures it on simavr (the first step interval, which no pin shows,
// plus the span from the first step to the last), within 0.1 % of the prediction's.
//
//
// Bytes reach the firmware at the line's rate into the chip's two-byte receive buffer, so a
// byte the firmware were too slow to read would be lost as on a Nano: none is (overruns 0).
import assert from "node:assert/strict";
import { readFileSync, readdirSync } from "node:fs";
import { join } from "node:path";
import { test } from "node:test";
import { REPO, nodeEngine, nodeNanoParts } from "../../../wasm/js/node.mjs";
import { VirtualNano } from "../src/virtual-nano/avr-nano.mjs";
import { runRecords } from "./run-records.mjs";

const HEX = process.env.ARTICULA_NANO_HEX || join(REPO, "build/avr/firmware/articula-nano.hex");
const PLANS = readdirSync(join(REPO, "hil/plans")).filter((f) => f.endsWith(".arm")).sort();

test("the thesis's plans on avr8js: replies, steps and durations as predicted", async (t) => {
  const engine = await nodeEngine();
  const mk2 = engine.robot("mk2plus");
  const parts = await nodeNanoParts();
  const hex = readFileSync(HEX, "utf8");
  let commands = 0, matched = 0, timed = 0, worst = 0, refused = 0;
  for (const plan of PLANS) {
    const text = readFileSync(join(REPO, "hil/plans", plan), "utf8");
    const records = mk2.predict(text, plan).records;
    const n = new VirtualNano({ hex, parts });
    const lines = [];
    n.onLine = (l) => lines.push(l);
    n.runFor(0.3);
    const r = runRecords(n, lines, engine, records, plan);
    commands += r.commands;
    matched += r.commands;
    refused += r.refused;
    timed += r.timed;
    if (Math.abs(r.worst) > Math.abs(worst)) worst = r.worst;
    assert.equal(n.coilFaults, 0, `${plan}: coil faults`);
    assert.equal(n.overruns, 0, `${plan}: received bytes lost`);
    n.delete();
  }
  t.diagnostic(`${PLANS.length} plans, ${commands} commands on avr8js (${refused} refused as the plans expect): ` +
    `steps matched ${matched}/${commands} (prediction = status = coils); ${timed} moves timed, worst duration error ` +
    `${worst >= 0 ? "+" : ""}${worst.toFixed(4)} %`);
  mk2.delete();
});
