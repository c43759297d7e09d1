// The virtual Nano's Web Worker: the firmware's own hex (data/firmware/articula-nano.hex, the
// file `make flash` writes) on avr8js (nano.mjs), paced to real time, its serial line as
// bytes to and from the page (serial.ts makes it a port like a real one). Its own copy of the
// web engine decodes the coils (hil/vnano/coil_decoder.h) by the Nano's wiring.
//
// In: {type: "start", eeprom?} (a power-up: the page keeps the EEPROM's bytes), {type: "rx",
// bytes}, {type: "close"}. Out: {type: "ready", flashBytes, ms}, {type: "tx", bytes},
// {type: "state", seconds, steps, faults, servoUs, rtf, behind}, {type: "eeprom", bytes},
// {type: "fatal", message}.
import { loadEngine } from "../../../wasm/js/engine.mjs";
import type { Engine } from "../../../wasm/js/engine.mjs";
import { VirtualNano } from "./nano.mjs";

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

// Runs the Nano as much of its time as passed on the wall clock (at most 50 ms a slice: a
// slower host falls behind and says so rather than freezing), every 5 ms.
function run(): void {
  const n = nano!;
  let last = performance.now();
  let eepromSeen = n.eepromBytes();
  let window: [number, number][] = []; // (wall s, emulated s) per slice
  let lastState = 0;
  const slice = () => {
    if (nano !== n) return;
    const now = performance.now();
    const wall = Math.min((now - last) / 1000, 0.05);
    last = now;
    const before = n.seconds;
    n.runFor(wall);
    const spent = (performance.now() - now) / 1000;
    window.push([Math.max(spent, wall), n.seconds - before]);
    if (window.length > 100) window = window.slice(-100);
    if (tx.length) {
      const bytes = new Uint8Array(tx);
      tx = [];
      post({ type: "tx", bytes }, [bytes.buffer]);
    }
    if (now - lastState > 100) {
      lastState = now;
      const w = window.reduce((a, x) => a + x[0], 0), e = window.reduce((a, x) => a + x[1], 0);
      const rtf = w > 0 ? e / w : 1;
      post({ type: "state", seconds: n.seconds, steps: n.steps, faults: n.coilFaults, servoUs: n.servoPulseUs,
        rtf, behind: rtf < 0.97 });
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
