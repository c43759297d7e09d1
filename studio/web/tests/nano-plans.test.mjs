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
import { CLOCK_HZ, VirtualNano } from "../src/nano.mjs";

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
    const until = (pred, s) => {
      const end = n.seconds + s;
      while (!pred() && n.seconds < end) n.runFor(0.0005);
      return pred();
    };
    n.runFor(0.3);
    const settings = { 0: 600, 1: 2000 };
    for (const rec of records) {
      commands++;
      lines.length = 0;
      n.markSteps();
      n.send(rec.command + "\n");
      const isReply = (l) => l === "ok" || l.startsWith("error:");
      assert.ok(until(() => lines.some(isReply), 1), `${plan}:${rec.line} ${rec.command}: no reply`);
      const reply = lines.find(isReply);
      assert.equal(reply, rec.code === 0 ? "ok" : `error:${rec.code}`, `${plan}:${rec.line} ${rec.command}`);
      if (rec.code !== 0) refused++;
      const set = /^\$(\d+)=([\d.]+)$/.exec(rec.command.trim());
      if (set && rec.code === 0) settings[set[1]] = Number(set[2]);
      // to rest: the status report's steps, and the coils'
      let st;
      for (let k = 0; k < 2000; k++) {
        lines.length = 0;
        n.send("?");
        assert.ok(until(() => lines.some((l) => l.startsWith("<")), 0.5),
          `${plan}:${rec.line} ${rec.command}: no status report (${JSON.stringify(lines)}); ${matched} commands matched before it`);
        st = engine.parseArmLine(lines.find((l) => l.startsWith("<")));
        if (st.state === "Idle") break;
        n.runFor(0.01);
      }
      assert.equal(st.state, "Idle", `${plan}:${rec.line}: never at rest`);
      assert.deepEqual(st.steps, rec.steps, `${plan}:${rec.line} ${rec.command}: status steps`);
      assert.deepEqual(n.steps, rec.steps, `${plan}:${rec.line} ${rec.command}: the coils' steps`);
      matched++;
      if (rec.code === 0 && rec.seconds > 0 && n.firstStepCycle >= 0 && !/^[GS]\b/.test(rec.command)) {
        const measured = engine.firstIntervalS(settings[0], settings[1]) + (n.lastStepCycle - n.firstStepCycle) / CLOCK_HZ;
        const err = ((measured - rec.seconds) / rec.seconds) * 100;
        assert.ok(Math.abs(err) <= 0.1, `${plan}:${rec.line} ${rec.command}: ${measured} s measured, ${rec.seconds} s predicted (${err.toFixed(4)} %)`);
        worst = Math.abs(err) > Math.abs(worst) ? err : worst;
        timed++;
      }
    }
    assert.equal(n.coilFaults, 0, `${plan}: coil faults`);
    assert.equal(n.overruns, 0, `${plan}: received bytes lost`);
    n.delete();
  }
  t.diagnostic(`${PLANS.length} plans, ${commands} commands on avr8js (${refused} refused as the plans expect): ` +
    `steps matched ${matched}/${commands} (prediction = status = coils); ${timed} moves timed, worst duration error ` +
    `${worst >= 0 ? "+" : ""}${worst.toFixed(4)} %`);
  mk2.delete();
});
