// The virtual Nano's Web Worker: the firmware's own hex (data/firmware/articula-nano.hex, the
// file `make flash` writes) on avr8js (avr-nano.mjs), paced to real time, its serial line as
// bytes to and from the page (link/ports.ts makes it a port like a real one). The virtual Nano's
// parts (engine/nano.mjs: the coil decoder, the board's pins, the servo's scale; a few
// kilobytes, not the engine) read its pins as simavr's virtual Nano does.
//
// The Nano is one as shipped: Optiboot (data/firmware/optiboot_atmega328.hex, built from
// Debian's source) in its boot section, so the page's flasher (link/stk500.mjs) can write it; the
// host's DTR resets it, and bytes at another baud rate than the USART's arrive garbled.
//
// In: {type: "start", eeprom?, image?, baud, servo?, speed?, cnc?} (a power-up: the page keeps the EEPROM's
// bytes, and the flash's after a flash; servo: the robot's servo angles {closed, open}; speed:
// the Nano's seconds a second of real time, 1 unless the page runs its world faster or slower; cnc:
// the Nano sits on a CNC shield, its motors on STEP/DIR drivers, and runs the shield's build,
// data/firmware/articula-cnc.hex, until it is flashed; servos: the robot's servos [{pin, zeroUs}], the
// Nano runs the servo build, data/firmware/articula-servo.hex, its pins read by servo decoders),
// {type: "rx", bytes}, {type: "signals", dtr}, {type: "speed", speed}, {type: "close"},
// {type: "drive", pin, level} (a header pin driven from outside, as a wire from another arm's
// output does: "A0", 0 or 1), {type: "watch", pins} (header pins whose levels the page wants).
// A wire's level is held across a power-up.
// Out: {type: "ready", flashBytes, ms}, {type: "tx", bytes}, {type: "state", seconds, steps,
// faults, servoUs, gripper (the aperture its pulse asks for, %), flashWrites, rtf, capacity, behind, speed,
// trail (Int32Array: each motor's steps after every step interrupt since the last state, row
// after row: where the pen went, step by step)}, {type: "eeprom", bytes}, {type: "flash", bytes} (after
// pages were written), {type: "closed"}, {type: "fatal", message}, {type: "levels", levels: {pin:
// level}} (the watched pins' levels: once as the Nano starts, then whenever one changes, looked
// at every slice of 5 ms or less).
import { loadNanoParts } from "../../../../virtual-nano/web/nano-parts.mjs";
import type { NanoParts } from "../../../../virtual-nano/web/nano-parts.mjs";
import { CLOCK_HZ, VirtualNano } from "./avr-nano.mjs";
import { RealTimeMeter, every } from "../pacer";

const site = new URL("./", self.location.href.replace(/assets\/[^/]*$/, ""));
const post = (m: Record<string, unknown>, transfer: Transferable[] = []) =>
  (self as unknown as Worker).postMessage(m, transfer);

let parts: NanoParts | null = null;
let hexes: Record<string, string> = {};
let bootloader = "";
let cnc = false;
let servos: { pin: string; zeroUs: number }[] | null = null; // a servo arm's servos, in motor order
let nano: VirtualNano | null = null;
let loop: { stop(): void } | null = null;
let tx: number[] = [];
let servo: { closed: number; open: number } | null = null; // the robot's servo angles, deg
// the Nano's seconds a second of real time (the page's speed); `rebase`: it changed, the pace
// starts again from now
let speed = 1;
let rebase = false;
const SPEED_RANGE = [0.05, 20];
const driven = new Map<string, number>(); // header pins driven from outside, and their levels
let watched: string[] = []; // header pins whose levels go to the page
let levelsSent = ""; // (as last sent)
// The motors' steps after each step interrupt: the firmware steps every motor of a tick in one
// interrupt, microseconds apart; ticks are at least 250 us apart ($0 at most 4000 steps/s).
// Steps closer than 100 us are one row. At most a million counts wait for the page.
const TICK_CYCLES = Math.round(CLOCK_HZ * 100e-6);
const TRAIL_MAX = 1_000_000;
let trail: number[] = [];
let tickAt = -Infinity;

async function fetchText(path: string): Promise<string> {
  const r = await fetch(new URL(path, site));
  if (!r.ok) throw new Error(`the firmware is not on this site (${path}: ${r.status})`);
  return r.text();
}

async function start(eeprom: Uint8Array | undefined, image: Uint8Array | undefined, baud: number): Promise<void> {
  const t0 = performance.now();
  if (!parts) {
    const { default: createNanoParts } = await import(/* @vite-ignore */ new URL("engine/nano.mjs", site).href);
    parts = await loadNanoParts(createNanoParts, { locateFile: (f: string) => new URL(`engine/${f}`, site).href });
  }
  const build = cnc ? "articula-cnc" : servos ? "articula-servo" : "articula-nano";
  if (!hexes[build]) hexes[build] = await fetchText(`data/firmware/${build}.hex`);
  if (!bootloader) bootloader = await fetchText("data/firmware/optiboot_atmega328.hex");
  stop();
  nano = new VirtualNano({ hex: hexes[build], parts, eeprom, bootloader, image, cnc, servos });
  nano.hostBaud = baud;
  for (const [pin, level] of driven) nano.drive(pin, level);
  levelsSent = "";
  nano.onByte = (b) => tx.push(b);
  trail = [];
  tickAt = -Infinity;
  nano.onStep = (cycle) => {
    const steps = nano!.steps;
    if (cycle - tickAt > TICK_CYCLES) {
      tickAt = cycle;
      if (trail.length + steps.length <= TRAIL_MAX) trail.push(...steps);
    } else {
      trail.splice(trail.length - steps.length, steps.length, ...steps); // the same tick's next motor
    }
  };
  post({ type: "ready", flashBytes: nano.flashUsed, ms: performance.now() - t0 });
  run();
}

function stop(): void {
  loop?.stop();
  loop = null;
  nano?.delete();
  nano = null;
}

// Runs the Nano in step with the wall clock (times the speed), every 5 ms: up to where real time
// says it should be, at most 50 ms of real time a slice, so a short hiccup of the host is caught
// up on. A backlog of more than 200 ms is let go (the host cannot keep up): the state then says
// it is behind.
function run(): void {
  const n = nano!;
  let clock0 = performance.now();
  let emu0 = n.seconds;
  let eepromSeen = n.eepromBytes();
  let flashWrites = n.flashWrites;
  const meter = new RealTimeMeter(100);
  let lastState = 0;
  loop = every(5, () => {
    if (nano !== n) return false;
    const now = performance.now();
    if (rebase) {
      rebase = false;
      clock0 = now;
      emu0 = n.seconds;
    }
    let due = emu0 + (speed * (now - clock0)) / 1000;
    if (due - n.seconds > 0.2 * speed) {
      clock0 = now;
      emu0 = n.seconds;
      due = n.seconds + 0.05 * speed;
    }
    const before = n.seconds;
    n.runUntil(Math.round(Math.min(due, before + 0.05 * speed) * CLOCK_HZ));
    meter.slice(n.seconds - before, (performance.now() - now) / 1000);
    postLevels(n);
    if (tx.length) {
      const bytes = new Uint8Array(tx);
      tx = [];
      post({ type: "tx", bytes, seconds: n.seconds }, [bytes.buffer]); // (the Nano's time: the page's clock of it)
    }
    if (now - lastState > 100) {
      lastState = now;
      // the gripper as simavr's virtual Nano reads it from the servo's pulse (articula/servo.h)
      const us = n.servoPulseUs;
      const gripper = us !== null && servo && parts && servo.open !== servo.closed
        ? parts.servoAperturePercent(parts.servoAngleDeg(us), servo.closed, servo.open) : null;
      const rtf = meter.rtf;
      const rows = new Int32Array(trail);
      trail = [];
      post({ type: "state", seconds: n.seconds, steps: n.steps, faults: n.coilFaults, servoUs: us, gripper, flashWrites: n.flashWrites,
        rtf, capacity: meter.capacity, behind: meter.slices >= 50 && rtf < 0.97 * speed, speed, trail: rows }, [rows.buffer]); // judged over 50+ slices
      if (n.flashWrites !== flashWrites) {
        flashWrites = n.flashWrites;
        post({ type: "flash", bytes: n.flash.slice() });
      }
      const ee = n.eepromBytes();
      if (ee.some((b, i) => b !== eepromSeen[i])) {
        eepromSeen = ee;
        post({ type: "eeprom", bytes: ee.slice() });
      }
    }
  });
}

// The watched pins' levels, when they changed.
function postLevels(n: VirtualNano): void {
  if (!watched.length) return;
  const levels: Record<string, number> = {};
  for (const pin of watched) levels[pin] = n.level(pin);
  const now = JSON.stringify(levels);
  if (now === levelsSent) return;
  levelsSent = now;
  post({ type: "levels", levels });
}

const HEADER_PIN = /^(D([0-9]|1[0-3])|A[0-7])$/;

/** The page's speed, when it is one (a number in SPEED_RANGE); 1 otherwise. */
function setSpeed(x: unknown): void {
  const v = typeof x === "number" && x >= SPEED_RANGE[0] && x <= SPEED_RANGE[1] ? x : 1;
  if (v !== speed) rebase = true;
  speed = v;
}

self.onmessage = (e: MessageEvent) => {
  const m = e.data as { type?: string; bytes?: Uint8Array; eeprom?: Uint8Array; image?: Uint8Array; baud?: number; dtr?: boolean;
    servo?: { closed: number; open: number }; speed?: number; cnc?: boolean; servos?: { pin: string; zeroUs: number }[];
    pin?: unknown; level?: unknown; pins?: unknown[] };
  if (m?.type === "start") {
    cnc = m.cnc === true;
    servos = Array.isArray(m.servos) && m.servos.length > 0
      ? m.servos.map((sv) => ({ pin: String(sv.pin), zeroUs: Number(sv.zeroUs) })) : null;
    servo = m.servo && Number.isFinite(m.servo.closed) && Number.isFinite(m.servo.open) ? m.servo : null;
    setSpeed(m.speed);
    const bytes = (x: unknown) => (x instanceof Uint8Array ? x : undefined);
    start(bytes(m.eeprom), bytes(m.image), Number(m.baud) || 115200).catch((err) =>
      post({ type: "fatal", message: (err as Error)?.message ?? String(err) }));
  } else if (m?.type === "rx" && m.bytes instanceof Uint8Array) {
    nano?.send(m.bytes);
  } else if (m?.type === "signals" && typeof m.dtr === "boolean") {
    nano?.setDtr(m.dtr);
  } else if (m?.type === "drive" && typeof m.pin === "string" && HEADER_PIN.test(m.pin) && (m.level === 0 || m.level === 1)) {
    driven.set(m.pin, m.level);
    nano?.drive(m.pin, m.level);
  } else if (m?.type === "watch" && Array.isArray(m.pins)) {
    watched = m.pins.filter((p): p is string => typeof p === "string" && HEADER_PIN.test(p)).slice(0, 20);
    levelsSent = "";
    if (nano) postLevels(nano);
  } else if (m?.type === "speed") {
    setSpeed(m.speed);
  } else if (m?.type === "close") {
    // the flash as it is now (pages written since the last state), then nothing more
    if (nano && nano.flashWrites > 0) post({ type: "flash", bytes: nano.flash.slice() });
    stop();
    post({ type: "closed" });
  }
};
