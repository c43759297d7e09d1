// One prediction, run on the page's virtual Nano (avr8js): each record of `articula predict`
// (robot.predict(...).records) sent as its line, its reply compared, the arm let come to
// rest, the status report's steps and the coils' compared, and every move's duration
// measured as the harness measures it on simavr (the first step interval, which no pin
// shows, plus the span from the first step to the last). Shared by nano-plans.test.mjs and
// nano-codesign.test.mjs.
import assert from "node:assert/strict";
import { CLOCK_HZ } from "../src/virtual-nano/avr-nano.mjs";

/** Runs the emulated Nano `n` until pred() or s more seconds. */
export function until(n, pred, s) {
  const end = n.seconds + s;
  while (!pred() && n.seconds < end) n.runFor(0.0005);
  return pred();
}

/** Sends a line and waits for its reply (`s` seconds more for a line answered late: a T is
 * answered once its last segment is in the queue); returns [reply, the lines before it]. */
export function command(n, lines, text, s = 0) {
  lines.length = 0;
  n.send(text + "\n");
  const isReply = (l) => l === "ok" || l.startsWith("error:");
  assert.ok(until(n, () => lines.some(isReply), 2 + s), `${text}: no reply`);
  return [lines.find(isReply), lines.filter((l) => !isReply(l))];
}

/** The records on `n` (whose onLine pushes into `lines`). `settings`: $0 and $1 at the start.
 * Returns {commands, refused, timed, worst (duration error %, signed), worstUs}. */
export function runRecords(n, lines, engine, records, where, settings = { 0: 600, 1: 2000 }, servo = false) {
  let refused = 0, timed = 0, worst = 0, worstUs = 0;
  let before = n.steps.map(() => 0); // the steps before each record: the prediction starts at step 0
  for (const rec of records) {
    const at = `${where}:${rec.line} ${rec.command}`;
    n.markSteps();
    const settled = n.seconds;
    const [reply] = command(n, lines, rec.command, rec.seconds);
    assert.equal(reply, rec.code === 0 ? "ok" : `error:${rec.code}`, at);
    if (rec.code !== 0) refused++;
    const set = /^\$(\d+)=([\d.]+)$/.exec(rec.command.trim());
    if (set && rec.code === 0) settings[set[1]] = Number(set[2]);
    // The line's predicted time runs first, and only then is the arm asked, every 10 ms, whether
    // it is at rest: a `?` every 10 ms from the start cost the emulated firmware a status line
    // each, more than half of its awake cycles (the co-design run took 200 CPU s, 80 after). A
    // move that ends early is still told by its step stamps below, one that ends late by the
    // status reports that say it moves.
    const sent = n.seconds - settled;
    if (rec.code === 0 && rec.seconds > sent) n.runFor(rec.seconds - sent);
    let st;
    for (let k = 0; k < 4000; k++) {
      lines.length = 0;
      n.send("?");
      assert.ok(until(n, () => lines.some((l) => l.startsWith("<")), 0.5), `${at}: no status report`);
      st = engine.parseArmLine(lines.find((l) => l.startsWith("<")));
      if (st.state === "Idle") break;
      n.runFor(0.01);
    }
    assert.equal(st.state, "Idle", `${at}: never at rest`);
    // A servo's pin shows its width once a period (20 ms): its pins are at rest a period after
    // the firmware is, and until then a change of this move may still come.
    if (servo) until(n, () => n.steps.every((p, i) => p === rec.steps[i]), 0.1);
    assert.deepEqual(st.steps, rec.steps, `${at}: status steps`);
    if (servo) // a servo's pin holds its width within one tick (servo_decoder.h's deadband)
      n.steps.forEach((p, i) => assert.ok(Math.abs(p - rec.steps[i]) <= 1, `${at}: servo ${i} on ${p}, predicted ${rec.steps[i]}`));
    else assert.deepEqual(n.steps, rec.steps, `${at}: the coils' steps`);
    // A servo the record does not move may show a one-tick change (two pulses on a tick's edge
    // decoding alike): its span is the moving servos' only.
    const moving = rec.steps.map((s, i) => i).filter((i) => rec.steps[i] !== before[i]);
    const [firstCycle, lastCycle] = servo ? n.stepSpan(moving) : [n.firstStepCycle, n.lastStepCycle];
    before = rec.steps.slice();
    if (rec.code === 0 && rec.seconds > 0 && firstCycle >= 0 && !/^[GSD]\b/i.test(rec.command)) {
      // (a T whose first segment cruises slower than the first step from rest: its cruise)
      const c0 = engine.firstIntervalS(settings[0], settings[1]);
      const first = rec.segments ? Math.max(c0, (4 * rec.segments[0].cruise4) / 2e6) : c0;
      const measured = first + (lastCycle - firstCycle) / CLOCK_HZ;
      const err = ((measured - rec.seconds) / rec.seconds) * 100;
      // A servo's pin shows its width once a period (20 ms), a change once it is two ticks (or
      // one two pulses agree on): its moves are timed to 170 ms (hil/tests/test_harness.py says why).
      if (servo) assert.ok(Math.abs(measured - rec.seconds) <= 0.17, `${at}: ${measured} s measured, ${rec.seconds} s predicted`);
      else assert.ok(Math.abs(err) <= 0.1, `${at}: ${measured} s measured, ${rec.seconds} s predicted (${err.toFixed(4)} %)`);
      if (Math.abs(err) > Math.abs(worst)) worst = err;
      worstUs = Math.max(worstUs, Math.abs(measured - rec.seconds) * 1e6);
      timed++;
    }
  }
  return { commands: records.length, refused, timed, worst, worstUs };
}
