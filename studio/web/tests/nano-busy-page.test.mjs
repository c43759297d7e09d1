// The page's virtual Nano in a busy page: the worker runs the Nano in slices, and the host's
// bytes reach it only between two (virtual-nano/worker.ts); on a busy machine a slice is up to
// 50 ms of the Nano's time, so lines and `?`s land at any instruction. Here the slices are of
// seeded random length, and the host is the arm link's program loop (link/arm-link.ts): a
// line, its reply, then `?` until an Idle report. Every line is answered and every `?` is
// reported: the Nano never hangs, whatever instruction a byte interrupts.
//
// (Before avr-nano.mjs let the instruction after a write to SREG run before an interrupt, as
// the chip does, an interrupt could come between avr-gcc's `out SREG` and `out SPL` when a
// function made its frame: pushed 256 bytes off, it overwrote the main program's frames, and
// the Nano hung, its line never answered. Seed 5 hung at its fifth line.)
import assert from "node:assert/strict";
import { existsSync, readFileSync } from "node:fs";
import { join } from "node:path";
import { test } from "node:test";
import { REPO, nodeEngine, nodeNanoParts } from "../../../wasm/js/node.mjs";
import { VirtualNano } from "../src/virtual-nano/avr-nano.mjs";
import { rng } from "./seeded.mjs";

const HEX = process.env.ARTICULA_NANO_HEX || join(REPO, "build/avr/firmware/articula-nano.hex");
const SEEDS = [1, 2, 3, 4, 5, 6];
const LINES = 16; // of the drawing's
const MAX_SLICE_MS = 20;

// The arm link's loop on `n`, the host's bytes between slices of random length. Returns what
// went wrong ("" when nothing did) and the last events, for the message.
function drive(n, program, seed) {
  const r = rng(seed);
  const heard = [];
  n.onLine = (l) => heard.push(l);
  const ms = () => n.seconds * 1000;
  const events = [];
  const note = (e) => {
    events.push(`${ms().toFixed(1)} ms ${e}`);
    if (events.length > 12) events.shift();
  };
  let pending = "";
  const write = (s) => {
    pending += s;
    if (s !== "?") note(`sent ${JSON.stringify(s)}`);
  };
  n.runFor(0.3);
  let index = 0, sentAt = 0, askedAt = null, lastAsk = -Infinity, seen = 0;
  let waiting = "reply";
  write(program[0] + "\n");
  sentAt = ms();
  while (index < program.length) {
    n.send(pending);
    pending = "";
    n.runFor((1 + r() * MAX_SLICE_MS) / 1000);
    for (; seen < heard.length; seen++) {
      const l = heard[seen];
      if (!l.startsWith("<")) note(`heard ${JSON.stringify(l)}`);
      if (l.startsWith("<")) {
        askedAt = null;
        if (waiting === "idle" && l.startsWith("<Idle") && ms() - sentAt > 150 && ++index < program.length) {
          write(program[index] + "\n");
          waiting = "reply";
          sentAt = ms();
        }
      } else if (waiting === "reply" && (l === "ok" || l.startsWith("error:"))) {
        if (l !== "ok") return { error: `line ${index + 1} '${program[index]}' refused: ${l}`, events };
        waiting = "idle";
        sentAt = ms();
      }
    }
    if (askedAt !== null && ms() - askedAt > 1500) return { error: "no status report for 1.5 s", events };
    if (waiting === "reply" && ms() - sentAt > 5000) return { error: `line ${index + 1} '${program[index]}' not answered in 5 s`, events };
    if (waiting === "idle" && ms() - sentAt > 30000) return { error: `line ${index + 1} not at rest in 30 s`, events };
    // `?` at 30 Hz and more, at random
    if (ms() - lastAsk >= 33 || r() < 0.3) {
      lastAsk = ms();
      askedAt ??= ms();
      write("?");
    }
  }
  return { error: "", events };
}

test("a busy page: lines and `?`s at any instruction, every one answered", { skip: !existsSync("/usr/share/hershey-fonts/futural.jhf") && "no Hershey font" }, async (t) => {
  const engine = await nodeEngine();
  const drawing = engine.robot("mk2plus").draw({ text: "Hello", width: 60, at: [250, 0], z: 0, pen: 120 });
  const program = drawing.program.split("\n").map((l) => l.split("#")[0].trim()).filter((l) => l).slice(0, LINES);
  assert.ok(program.some((l) => l.startsWith("T ")), "the drawing has straight lines");
  const hex = readFileSync(HEX, "utf8");
  const parts = await nodeNanoParts();
  for (const seed of SEEDS) {
    const n = new VirtualNano({ hex, parts });
    const { error, events } = drive(n, program, seed);
    n.delete();
    assert.equal(error, "", `seed ${seed}: ${error}; the last events:\n  ${events.join("\n  ")}`);
    t.diagnostic(`seed ${seed}: ${program.length} lines answered and drawn`);
  }
});

// The rule itself, on a program of a few instructions: a received byte's interrupt waits
// while interrupts are off; then the stack pointer is moved as avr-gcc makes a frame (`out SPH`,
// `out SREG` setting I, `out SPL`). The interrupt is served after `out SPL`, so it pushes its
// return address below the new stack pointer, not below one half old, half new.
const ldi = (d, k) => 0xe000 | ((k & 0xf0) << 4) | ((d - 16) << 4) | (k & 0x0f);
const out = (a, r) => 0xb800 | ((a & 0x30) << 5) | (r << 4) | (a & 0x0f);
const inn = (d, a) => 0xb000 | ((a & 0x30) << 5) | (d << 4) | (a & 0x0f);
const sts = (k, r) => [0x9200 | (r << 4), k];
const lds = (d, k) => [0x9000 | (d << 4), k];
const jmp = (k) => [0x940c, k];
const SPL = 0x3d, SPH = 0x3e, SREG = 0x3f, UCSR0A = 0xc0, UCSR0B = 0xc1, UDR0 = 0xc6;
const CLI = 0x94f8, RETI = 0x9518, SBRS_R17_7 = 0xfe00 | (17 << 4) | 7;
const rjmp = (from, to) => 0xc000 | ((to - from - 1) & 0xfff);

function intelHex(words) {
  const bytes = words.flatMap((w) => [w & 0xff, w >> 8]);
  const lines = [];
  for (let at = 0; at < bytes.length; at += 16) {
    const rec = [Math.min(16, bytes.length - at), at >> 8, at & 0xff, 0, ...bytes.slice(at, at + 16)];
    const sum = (0x100 - (rec.reduce((a, b) => a + b, 0) & 0xff)) & 0xff;
    lines.push(":" + [...rec, sum].map((b) => b.toString(16).padStart(2, "0")).join(""));
  }
  return lines.join("\n") + "\n:00000001FF\n";
}

test("an interrupt waits for the instruction after a write to SREG, as avr-gcc's frames need", async () => {
  const flash = new Array(0x60).fill(0);
  const put = (at, ...ws) => ws.flat().forEach((w, i) => (flash[at + i] = w));
  put(0, jmp(0x30)); // reset
  const main = [ldi(16, 0x08), out(SPH, 16), ldi(16, 0xff), out(SPL, 16), // SP = 0x8ff
    ldi(16, 0x90), sts(UCSR0B, 16), CLI]; // the receiver and its interrupt on, interrupts off
  put(0x30, ...main);
  const wait = 0x30 + main.flat().length; // until a byte has come (RXC0): its interrupt pending
  put(wait, lds(17, UCSR0A), SBRS_R17_7, rjmp(wait + 3, wait));
  const frame = wait + 4; // the frame: SP = 0x700
  put(frame, ldi(28, 0x00), ldi(29, 0x07), ldi(18, 0x80), out(SPH, 29), out(SREG, 18), out(SPL, 28), rjmp(frame + 6, frame + 6));
  put(0x24, jmp(0x50)); // USART_RX: the stack pointer as the interrupt found it, into 0x100
  put(0x50, inn(20, SPL), inn(21, SPH), sts(0x100, 20), sts(0x101, 21), lds(22, UDR0), RETI);
  const n = new VirtualNano({ hex: intelHex(flash), parts: await nodeNanoParts() });
  n.runFor(0.001);
  n.send([0x55]);
  n.runFor(0.001);
  const sp = n.cpu.data[0x100] | (n.cpu.data[0x101] << 8);
  n.delete();
  assert.equal(sp.toString(16), "6fe", "the interrupt pushed its return address (2 bytes) below 0x700");
});
