// Serial ports for the arm panel: a real Nano through Web Serial (navigator.serial: Chrome,
// Edge, Opera, in a secure context), and the virtual Nano in the page (virtual-nano/worker.ts) behind
// the same interface, so that arm-link.ts has one code path for both.

import { store, stored } from "../page/environment";

/** What arm-link.ts needs of a port: the part of Web Serial's SerialPort it uses. */
export interface SerialLike {
  open(options: { baudRate: number }): Promise<void>;
  close(): Promise<void>;
  readonly readable: ReadableStream<Uint8Array> | null;
  readonly writable: WritableStream<Uint8Array> | null;
  getInfo?(): { usbVendorId?: number; usbProductId?: number };
  /** DTR and RTS: a Nano resets when DTR goes high (the flasher resets it into its bootloader). */
  setSignals?(signals: { dataTerminalReady?: boolean; requestToSend?: boolean }): Promise<void>;
  /** The device's own time (ms), where it is not the page's: the virtual Nano's emulated time,
   * which a busy machine slows. Waits for the device's answers count in it (deviceClock). */
  clock?(): number;
}

/** The clock that waits for `port`'s answers count in: its own, else the page's. */
export function deviceClock(port: SerialLike): () => number {
  return port.clock ? () => port.clock!() : () => performance.now();
}

/** Waits `ms` of `clock`'s time (looking at it every 20 ms of the page's), or until `over()`:
 * a wait that lost its race to an answer, on a device whose clock stopped with its port, must
 * not look at that clock for ever. */
export async function sleepOn(clock: () => number, ms: number, over: () => boolean = () => false): Promise<void> {
  const end = clock() + ms;
  for (let left = ms; left > 0 && !over(); left = end - clock()) await new Promise((r) => setTimeout(r, Math.min(left, 20)));
}

interface SerialApi {
  requestPort(options?: unknown): Promise<SerialLike>;
  getPorts(): Promise<SerialLike[]>;
}

/** Web Serial, where the browser has it (and the page is a secure context). */
export function webSerial(): SerialApi | null {
  const s = (navigator as unknown as { serial?: SerialApi }).serial;
  return s && typeof s.requestPort === "function" ? s : null;
}

const EEPROM_KEY = "articula.virtualNano.eeprom";

/** The virtual Nano as a serial port: opening it powers it up (as a real Nano resets when
 * its port opens), with the EEPROM it had when the page last closed it (localStorage), and
 * the flash it had when this port last closed (the site's firmware until it is flashed). */
export class VirtualNanoPort implements SerialLike {
  readable: ReadableStream<Uint8Array> | null = null;
  writable: WritableStream<Uint8Array> | null = null;
  /** The emulator's speed against real time, its steps as the coils moved them. */
  state: { seconds: number; steps: number[]; faults: number; servoUs: number | null; gripper: number | null; flashWrites: number;
    rtf: number; capacity: number | null; behind: boolean; speed: number; trail: Int32Array } | null = null;
  /** The robot's servo angles (deg), for the aperture its pulses ask for. */
  servo: { closed: number; open: number } | null = null;
  /** The board the robot's motors are wired to: a CNC shield (STEP/DIR drivers) or the Nano's own pins. */
  get cnc(): boolean { return this.onShield; }
  set cnc(on: boolean) {
    if (on !== this.onShield) this.image = null; // another board: it starts with the site's build for it
    this.onShield = on;
  }
  private onShield = false;
  /** A servo arm's servos in motor order (their pins and pulses at step 0): the Nano runs the servo build. */
  get servos(): { pin: string; zeroUs: number }[] | null { return this.servoArm; }
  set servos(v: { pin: string; zeroUs: number }[] | null) {
    if (JSON.stringify(v) !== JSON.stringify(this.servoArm)) this.image = null; // other servos: the site's build for them
    this.servoArm = v;
  }
  private servoArm: { pin: string; zeroUs: number }[] | null = null;
  flashBytes = 0;
  /** The Nano's seconds a second of real time (the page's speed, editor.speed). */
  speed = 1;
  /** The flash's bytes after a flash (the bootloader wrote pages), for the next power-up. */
  image: Uint8Array | null = null;
  onState: ((s: NonNullable<VirtualNanoPort["state"]>) => void) | null = null;
  /** The watched header pins' levels (watch()), as the Nano starts and whenever one changes. */
  onLevels: ((levels: Record<string, number>) => void) | null = null;
  /** Where its EEPROM is kept between pages (localStorage), null: nowhere (a cell's arm's Nano,
   * configured for its arm each time it starts). */
  eepromKey: string | null = EEPROM_KEY;
  private driven = new Map<string, number>();
  private watched: string[] = [];
  private worker: Worker | null = null;
  // clock(): the page's time while closed, the Nano's emulated time while open, never backwards.
  // The Nano's time comes with each thing it sends and with its state (10 a second); in between
  // it runs on at the page's speed for up to 100 ms (a Nano behind is waited for, not outrun).
  private clockBase = 0;
  private wallBase = performance.now();
  private nanoMs = 0; // the Nano's time at its last word
  private nanoAt = 0; // ... and the page's then
  private lastClock = 0;

  clock(): number {
    const t = this.worker ? this.clockBase + this.nanoMs + Math.min(performance.now() - this.nanoAt, 100) * this.speed
      : this.clockBase + performance.now() - this.wallBase;
    this.lastClock = Math.max(this.lastClock, t);
    return this.lastClock;
  }
  private heard(seconds: unknown): void {
    if (typeof seconds !== "number") return;
    this.nanoMs = seconds * 1000;
    this.nanoAt = performance.now();
  }

  async open(options: { baudRate: number }): Promise<void> {
    if (this.worker) throw new Error("the virtual Nano is already open");
    this.clockBase = this.clock();
    this.nanoMs = 0;
    this.nanoAt = performance.now();
    this.state = null;
    const worker = new Worker(new URL("assets/nano-worker.js", document.baseURI), { type: "module" });
    this.worker = worker;
    let push: ((b: Uint8Array) => void) | null = null;
    let end: ((e?: Error) => void) | null = null;
    this.readable = new ReadableStream<Uint8Array>({
      start(controller) {
        push = (b) => {
          try {
            controller.enqueue(b);
          } catch {
            /* the port was closed: bytes still on their way from the worker have no reader */
          }
        };
        end = (e) => {
          try {
            if (e) controller.error(e);
            else controller.close();
          } catch {
            /* already closed (a STOP, a flash or a run ending at once): nothing is left to end */
          }
        };
      },
    });
    this.writable = new WritableStream<Uint8Array>({
      write: (chunk) => {
        if (this.worker !== worker) throw new Error("the virtual Nano is closed");
        worker.postMessage({ type: "rx", bytes: new Uint8Array(chunk) });
      },
    });
    await new Promise<void>((resolve, reject) => {
      worker.onmessage = (e: MessageEvent) => {
        const m = e.data;
        if (m.type === "ready") {
          this.flashBytes = m.flashBytes;
          resolve();
        } else if (m.type === "tx") {
          this.heard(m.seconds);
          push?.(m.bytes);
        } else if (m.type === "flash") {
          this.image = m.bytes;
        } else if (m.type === "closed") {
          this.closed?.();
        } else if (m.type === "state") {
          this.state = m;
          this.heard(m.seconds);
          this.onState?.(m);
        } else if (m.type === "levels") {
          this.onLevels?.(m.levels);
        } else if (m.type === "eeprom") {
          // (storage full or off: the settings last as long as the page)
          if (this.eepromKey) store(this.eepromKey, JSON.stringify(Array.from(m.bytes as Uint8Array)));
        } else if (m.type === "fatal") {
          end?.(new Error(m.message));
          reject(new Error(m.message));
        }
      };
      worker.onerror = (e) => {
        end?.(new Error(e.message));
        reject(new Error(e.message));
      };
      let eeprom: Uint8Array | undefined;
      try {
        const saved = this.eepromKey ? stored(this.eepromKey) : null;
        if (saved) eeprom = new Uint8Array(JSON.parse(saved));
      } catch {
        eeprom = undefined;
      }
      worker.postMessage({ type: "start", eeprom, image: this.image ?? undefined, baud: options.baudRate,
        servo: this.servo ?? undefined, speed: this.speed, cnc: this.onShield, servos: this.servoArm ?? undefined });
      for (const [pin, level] of this.driven) worker.postMessage({ type: "drive", pin, level });
      if (this.watched.length) worker.postMessage({ type: "watch", pins: this.watched });
    });
    this.closeStream = () => end?.();
  }

  /** Header pin `pin` ("A0") driven from outside at `level` (0 or 1), as a wire from another arm's
   * output drives it, from now on (and from power-up, when it is not open yet). */
  drive(pin: string, level: number): void {
    this.driven.set(pin, level);
    this.worker?.postMessage({ type: "drive", pin, level });
  }

  /** The header pins whose levels onLevels is told. */
  watch(pins: string[]): void {
    this.watched = [...pins];
    this.worker?.postMessage({ type: "watch", pins: this.watched });
  }

  /** The page's speed changed: the Nano runs at it from now on. */
  setSpeed(speed: number): void {
    this.speed = speed;
    this.worker?.postMessage({ type: "speed", speed });
  }

  private closeStream: () => void = () => undefined;
  private closed: (() => void) | null = null;

  async setSignals(signals: { dataTerminalReady?: boolean; requestToSend?: boolean }): Promise<void> {
    if (!this.worker) throw new Error("the virtual Nano is closed");
    if (signals.dataTerminalReady !== undefined) this.worker.postMessage({ type: "signals", dtr: signals.dataTerminalReady });
  }

  async close(): Promise<void> {
    const worker = this.worker;
    if (worker) {
      // the worker hands back the flash as it is before it stops (at most 0.5 s)
      await new Promise<void>((resolve) => {
        this.closed = resolve;
        worker.postMessage({ type: "close" });
        setTimeout(resolve, 500);
      });
      this.closed = null;
    }
    this.worker?.terminate();
    if (this.worker) {
      this.clockBase = this.clock();
      this.wallBase = performance.now();
    }
    this.worker = null;
    this.closeStream();
    this.readable = this.writable = null;
  }

  getInfo() {
    return {};
  }
}
