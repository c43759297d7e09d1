// For node's tests: a VirtualNano (src/virtual-nano/avr-nano.mjs) behind Web Serial's SerialPort interface -
// open, close, readable, writable, setSignals - as a Nano on a USB cable is: the host's baud
// rate, DTR's auto-reset, and a cable that can be pulled (the port fails, the Nano loses
// power) and plugged in again (it powers up). The emulator runs as fast as node can while
// the port is open, or with `pace` at that many times real time at most (as the page's worker
// runs it: the arm link's polls and waits are timed by the page's clock).
import { RESET_POWER } from "../src/virtual-nano/avr-nano.mjs";

export class NanoPort {
  constructor(nano) {
    this.nano = nano;
    this.readable = this.writable = null;
    this.plugged = true;
    this.out = [];
    this.written = 0; // bytes the host wrote
    this.pullAfter = Infinity; // pull the cable once the host has written this many bytes
    // A Nano gone deaf: its answers are lost once the host has written `muteAfter` bytes since
    // the port opened, until it closes, for the next `muteOpens` openings.
    this.muteAfter = Infinity;
    this.muteOpens = 0;
    this.pace = 0; // 0: as fast as it goes
    // A slow way in (a busy machine's page, worker and emulator): the host's next `lagWrites`
    // writes reach the Nano `lagMs` of its time late, and every byte after them waits its turn
    // (a serial line keeps the order).
    this.lagWrites = 0;
    this.lagMs = 0;
    this.inFlight = []; // [due, bytes]: on their way to the Nano, in order
    nano.onByte = (b) => this.out.push(b);
  }

  async open({ baudRate }) {
    if (!this.plugged) throw new Error("the device has been lost");
    if (this.readable) throw new Error("the port is already open");
    this.nano.hostBaud = baudRate;
    const opened = this.written;
    const mute = this.muteOpens > 0 ? (this.muteOpens--, this.muteAfter) : Infinity;
    this.nano.setDtr(true); // opening asserts DTR: the Nano resets, as on a USB cable
    let controller;
    this.readable = new ReadableStream({ start: (c) => (controller = c) });
    this.controller = controller;
    this.writable = new WritableStream({
      write: (chunk) => {
        if (!this.plugged) throw new Error("the device has been lost");
        const lag = this.lagWrites > 0 ? (this.lagWrites--, this.lagMs) : 0;
        const due = Math.max(this.clock() + lag, this.inFlight.at(-1)?.[0] ?? -Infinity);
        if (due > this.clock()) this.inFlight.push([due, Uint8Array.from(chunk)]);
        else this.nano.send(chunk);
        this.written += chunk.length;
        if (this.written >= this.pullAfter) this.pull();
      },
    });
    const run = (this.running = {});
    const wall0 = performance.now();
    let nano0 = this.nano.seconds;
    const loop = () => {
      if (this.running !== run) return;
      // (ahead of the wall's time by `ahead` s: the Nano waits, the host's side runs)
      let ahead = this.pace ? this.nano.seconds - nano0 - ((performance.now() - wall0) / 1000) * this.pace : -1;
      // (a process the machine left waiting does not make its Nano race to catch up: it falls
      // 50 ms behind the wall at most, so the host's side, which waited as long, answers the
      // Nano's bytes before the Nano is far on: a bootloader's watchdog (1 s) does not end a
      // flash for the machine's load)
      if (this.pace && ahead < -0.05) {
        nano0 += ahead + 0.05;
        ahead = -0.05;
      }
      if (ahead < 0) this.nano.runFor(0.002);
      while (this.inFlight.length && this.inFlight[0][0] <= this.clock()) this.nano.send(this.inFlight.shift()[1]);
      if (this.written - opened >= mute) this.out = [];
      if (this.out.length) {
        controller.enqueue(Uint8Array.from(this.out));
        this.out = [];
      }
      // (waiting by a timer, not spinning: a paced Nano ahead of the wall costs no CPU)
      if (ahead > 0.001) setTimeout(loop, Math.min(4, (ahead / this.pace) * 1000));
      else setImmediate(loop);
    };
    loop();
  }

  async setSignals({ dataTerminalReady }) {
    if (!this.plugged) throw new Error("the device has been lost");
    if (dataTerminalReady !== undefined) this.nano.setDtr(dataTerminalReady);
  }

  async close() {
    this.running = null;
    this.inFlight = [];
    try {
      this.controller?.close();
    } catch {
      /* already errored */
    }
    this.readable = this.writable = null;
    this.nano.setDtr(false);
  }

  /** The Nano's own time, ms (src/link/ports.ts's clock(): the flasher's timeouts count in it, so a
   * busy machine that slows the emulator does not make the Nano look silent). */
  clock() {
    return this.nano.seconds * 1000;
  }

  /** The cable pulled: the port fails, the Nano stops (no power). */
  pull() {
    this.plugged = false;
    this.running = null;
    this.nano.rx.length = 0;
    try {
      this.controller?.error(new Error("the device has been lost"));
    } catch {
      /* already closed */
    }
  }

  /** Plugged in again: the Nano powers up; the port can be opened. */
  plugIn() {
    this.readable = this.writable = null;
    this.plugged = true;
    this.pullAfter = Infinity;
    this.nano.reset(RESET_POWER);
  }
}
