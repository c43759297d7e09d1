// The virtual Nano's Web Worker: the firmware's own hex (data/firmware/articula-nano.hex, the
// file `make flash` writes) on avr8js (nano.mjs), paced to real time, its serial line as
// bytes to and from the page (serial.ts makes it a port like a real one). Its own copy of the
// web engine decodes the coils (hil/vnano/coil_decoder.h) by the Nano's wiring.
//
// In: {type: "start", eeprom?} (a power-up: the page keeps the EEPROM's bytes), {type: "rx",
// bytes}, {type: "close"}. Out: {type: "ready", flashBytes, ms}, {type: "tx", bytes},
// {type: "state", seconds, steps, faults, servoUs, rtf, capacity, behind}, {type: "eeprom", bytes},
// {type: "fatal", message}.
import { loadEngine } from "../../../wasm/js/engine.mjs";
import type { Engine } from "../../../wasm/js/engine.mjs";
import { CLOCK_HZ, VirtualNano } from "./nano.mjs";

const site = new URL("./", self.location.href.replace(/assets\/[^/]*$/, ""));
const post = (m: Record<string, unknown>, transfer: Transferable[] = []) =>
  (self as unknown as Worker).postMessage(m, transfer);

let engine: Engine | null = null;
let hex = "";
let nano: VirtualNano | null = null;
let timer: ReturnType<typeof setTimeout> | null = null;
let tx: number[] = [];

async function start(eeprom?: Uint8Array): Promise<void> {
  const t0 = performance.now();
  if (!engine) {
    const { default: createEngine } = await import(/* @vite-ignore */ new URL("engine/engine.mjs", site).href);
    engine = await loadEngine(createEngine, { locateFile: (f: string) => new URL(`engine/${f}`, site).href });
  }
  if (!hex) {
    const r = await fetch(new URL("data/firmware/articula-nano.hex", site));
    if (!r.ok) throw new Error(`the firmware's hex is not on this site (data/firmware/articula-nano.hex: ${r.status})`);
    hex = await r.text();
  }
  stop();
  nano = new VirtualNano({ hex, engine, eeprom });
  nano.onByte = (b) => tx.push(b);
  post({ type: "ready", flashBytes: nano.flashUsed, ms: performance.now() - t0 });
  run();
}

function stop(): void {
  if (timer !== null) clearTimeout(timer);
  timer = null;
  nano?.delete();
  nano = null;
}

// Runs the Nano in step with the wall clock, every 5 ms: up to where real time says it should
// be, at most 50 ms a slice, so a short hiccup of the host is caught up on. A backlog of more
// than 200 ms is let go (the host cannot keep up): the state then says it is behind.
function run(): void {
  const n = nano!;
  let clock0 = performance.now();
  let emu0 = n.seconds;
  let eepromSeen = n.eepromBytes();
  let window: [number, number, number][] = []; // (wall s, emulated s, working s) per slice
  let last = clock0;
  let lastState = 0;
  const slice = () => {
    if (nano !== n) return;
    const now = performance.now();
    let due = emu0 + (now - clock0) / 1000;
    if (due - n.seconds > 0.2) {
      clock0 = now;
      emu0 = n.seconds;
      due = n.seconds + 0.05;
    }
    const before = n.seconds;
    n.runUntil(Math.round(Math.min(due, before + 0.05) * CLOCK_HZ));
    const after = performance.now();
    window.push([(after - last) / 1000, n.seconds - before, (after - now) / 1000]);
    last = after;
    if (window.length > 100) window = window.slice(-100);
    if (tx.length) {
      const bytes = new Uint8Array(tx);
      tx = [];
      post({ type: "tx", bytes }, [bytes.buffer]);
    }
    if (now - lastState > 100) {
      lastState = now;
      const sum = (k: number) => window.reduce((a, x) => a + x[k], 0);
      const w = sum(0), e = sum(1), busy = sum(2);
      const rtf = w > 0 ? e / w : 1;
      // capacity: how many times real time the emulator alone could run
      post({ type: "state", seconds: n.seconds, steps: n.steps, faults: n.coilFaults, servoUs: n.servoPulseUs,
        rtf, capacity: busy > 0 ? e / busy : null, behind: window.length >= 50 && rtf < 0.97 }); // judged over 50+ slices
      const ee = n.eepromBytes();
      if (ee.some((b, i) => b !== eepromSeen[i])) {
        eepromSeen = ee;
        post({ type: "eeprom", bytes: ee.slice() });
      }
    }
    timer = setTimeout(slice, 5);
  };
  slice();
}

self.onmessage = (e: MessageEvent) => {
  const m = e.data as { type?: string; bytes?: Uint8Array; eeprom?: Uint8Array };
  if (m?.type === "start") {
    start(m.eeprom instanceof Uint8Array ? m.eeprom : undefined).catch((err) =>
      post({ type: "fatal", message: (err as Error)?.message ?? String(err) }));
  } else if (m?.type === "rx" && m.bytes instanceof Uint8Array) {
    nano?.send(m.bytes);
  } else if (m?.type === "close") {
    stop();
  }
};
