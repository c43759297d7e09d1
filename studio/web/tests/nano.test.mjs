// The page's virtual Nano (src/virtual-nano/avr-nano.mjs: avr8js) running the firmware's own hex, in node:
// it answers as the firmware does, and its coils turn the motors by the steps the prediction
// gives. ARTICULA_NANO_HEX names the hex (default build/avr/firmware/articula-nano.hex).
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { before, describe, test } from "node:test";
import { REPO, nodeEngine, nodeNanoParts } from "../../../wasm/js/node.mjs";
import { VirtualNano, parseHex } from "../src/virtual-nano/avr-nano.mjs";

const HEX = process.env.ARTICULA_NANO_HEX || join(REPO, "build/avr/firmware/articula-nano.hex");

let engine, parts, hex;
before(async () => {
  engine = await nodeEngine();
  parts = await nodeNanoParts();
  hex = readFileSync(HEX, "utf8");
});

// The Nano with a line-by-line conversation: ask() sends a line and runs until a reply line.
function nano(eeprom) {
  const n = new VirtualNano({ hex, parts, eeprom });
  n.lines = [];
  n.onLine = (l) => n.lines.push(l);
  n.ask = (line, seconds = 1) => {
    const from = n.lines.length;
    n.send(line === "?" ? line : line + "\n"); // `?` is a realtime byte, no line
    const end = n.cpu.cycles + seconds * 16e6;
    while (n.lines.length === from && n.cpu.cycles < end) n.runFor(0.002);
    return n.lines.slice(from);
  };
  n.idle = (limit = 10) => {
    const end = n.seconds + limit;
    for (;;) {
      const st = n.ask("?")[0] ?? "";
      if (st.startsWith("<Idle")) return st;
      if (n.seconds > end) throw new Error(`not Idle after ${limit} s: ${st}`);
      n.runFor(0.05);
    }
  };
  return n;
}

describe("the virtual Nano in the page (avr8js)", () => {
  test("a malformed hex is refused, naming the line", () => {
    assert.throws(() => parseHex(":10000000\n"), /hex line 1/);
    assert.throws(() => parseHex(":0100000000FF\nnonsense\n"), /hex line 2: not an Intel HEX record/);
    assert.throws(() => parseHex(":0100000001FF\n"), /hex line 1: bad checksum/);
  });

  test("the firmware answers I with the robot's banner, and moves by the predicted steps", (t) => {
    const n = nano();
    n.runFor(0.3); // boot
    const banner = n.ask("I");
    // (W:14 on a first boot: the blank EEPROM's settings reset to their defaults)
    assert.match(banner[0], /^\[Articula\|V:[\d.]+\|P:\d+\|J:3\|R:MK2 Plus\|K:21232(\|W:14)?\]$/);
    assert.deepEqual(n.ask("L 0 10"), ["ok"]);
    const st = n.idle();
    assert.match(st, /\|S:32,0,0\|/);
    const mk2 = engine.robot("mk2plus");
    assert.deepEqual(mk2.quantize(["L 0 10"])[0].all_steps, [32, 0, 0]);
    assert.deepEqual(n.steps, [32, 0, 0], "the coils moved the base 32 steps");
    assert.deepEqual(n.ask("L 1 150"), ["error:9"]);
    n.runFor(0.2);
    assert.deepEqual(n.steps, [32, 0, 0], "a refused line moves nothing");
    assert.equal(n.coilFaults, 0);
    t.diagnostic(`emulated ${n.seconds.toFixed(2)} s, flash ${n.flashUsed} B`);
    mk2.delete();
    n.delete();
  });

  test("O and W on the header's pins: a W holds the move until the pin another drives goes low; O sets a pin", (t) => {
    const n = nano();
    n.runFor(0.3);
    assert.equal(n.level("A5"), 1, "a free pin's pull-up, at power-up");
    n.drive("A5", 1); // a wire from another arm's output, high
    assert.deepEqual(n.ask("W 19 0 5"), ["ok"]);
    assert.deepEqual(n.ask("L 0 10"), ["ok"]);
    n.runFor(0.5);
    assert.deepEqual(n.steps, [0, 0, 0], "the W holds the move behind it");
    n.markSteps();
    const low = n.cpu.cycles;
    n.drive("A5", 0);
    n.idle();
    assert.deepEqual(n.steps, [32, 0, 0]);
    // its first step: within the W's millisecond look and the move's first interval (31.6 ms)
    const lagMs = ((n.firstStepCycle - low) / 16e6) * 1000;
    assert.ok(lagMs > 0 && lagMs < 1 + 31.7 + 1, `the first step ${lagMs.toFixed(2)} ms after the pin went low`);
    assert.deepEqual(n.ask("O 19 0"), ["ok"]);
    n.idle();
    assert.equal(n.level("A5"), 0, "O 19 0 set it low");
    assert.match(n.ask("?")[0], /\|I:/);
    assert.throws(() => n.level("D14"), /no header pin "D14"/);
    t.diagnostic(`the move's first step ${lagMs.toFixed(2)} ms after the input went low`);
    n.delete();
  });

  test("a program's final steps are articula predict's, and settings survive a new Nano", () => {
    const n = nano();
    n.runFor(0.3);
    const program = ["$0=2000", "$1=40000", "L 0 10", "M -20 80 -10", "L 2 5"];
    for (const line of program) {
      assert.deepEqual(n.ask(line), ["ok"], line);
      n.idle();
    }
    const mk2 = engine.robot("mk2plus");
    const want = mk2.predict(program.join("\n") + "\n", "p.arm").records.at(-1).steps;
    assert.match(n.idle(), new RegExp(`\\|S:${want.join(",")}\\|`));
    assert.deepEqual(n.steps, want);
    // the EEPROM keeps $0: a new Nano with the same bytes reports it
    const again = nano(n.eepromBytes());
    again.runFor(0.3);
    const listed = again.ask("$", 1);
    again.runFor(0.05);
    assert.ok(again.lines.some((l) => l.startsWith("$0=2000")), `settings kept in EEPROM: ${listed}`);
    mk2.delete();
    n.delete();
    again.delete();
  });
});
