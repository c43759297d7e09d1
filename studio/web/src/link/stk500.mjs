// Flashing a Nano from the page: the firmware's hex over a serial port (Web Serial, or the
// virtual Nano's port) to the Nano's bootloader, in the STK500 version 1 protocol that
// Optiboot (the Nano's "new bootloader", 115,200 baud) and ATmegaBOOT (the old one, 57,600)
// speak, as avrdude's `-c arduino` does: reset by DTR, sync, check the chip's signature,
// write the pages, read them back, leave. Plain JavaScript, so that node's tests run what
// the page runs (stk500.d.mts gives its types).
//
//   await flashNano(port, hexText, { onProgress: ({ phase, done, total }) => ... });
//
// The bootloader sits in the boot section, which the Nano's lock bits keep from being
// written: a flash that fails anywhere leaves a Nano whose bootloader takes the next one.
import { BOOT_START, PAGE_BYTES, parseHex } from "../virtual-nano/avr-nano.mjs";

// STK500v1 (Atmel's AVR061), what the bootloaders answer
const STK_OK = 0x10, STK_INSYNC = 0x14, CRC_EOP = 0x20;
const GET_SYNC = 0x30, ENTER_PROGMODE = 0x50, LEAVE_PROGMODE = 0x51, LOAD_ADDRESS = 0x55;
const PROG_PAGE = 0x64, READ_PAGE = 0x74, READ_SIGN = 0x75;
/** The ATmega328P's signature bytes. */
export const SIGNATURE = [0x1e, 0x95, 0x0f];
/** The Nano's bootloaders: the new one (Optiboot) first, as the Arduino IDE offers them. */
export const BAUD_RATES = [115200, 57600];

/** Why a flash failed: `kind` says which way, the message what to do. */
export class FlashError extends Error {
  constructor(kind, message) {
    super(message);
    this.kind = kind; // "hex" | "no-bootloader" | "signature" | "verify" | "vanished" | "stalled"
  }
}

const WALL_STALLS = 12;
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const hex2 = (b) => "0x" + b.toString(16).padStart(2, "0");

/** The pages of a firmware hex for the Nano: [address, 128 bytes], the application section only. */
export function firmwarePages(hexText) {
  let image;
  try {
    image = parseHex(hexText);
  } catch (e) {
    throw new FlashError("hex", `the firmware file is not a valid hex: ${e.message}`);
  }
  if (image.used === 0) throw new FlashError("hex", "the firmware file holds no program");
  if (image.used > BOOT_START)
    throw new FlashError("hex", `the firmware is ${image.used} bytes, more than the ${BOOT_START} a Nano holds beside its bootloader`);
  const pages = [];
  for (let at = 0; at < image.used; at += PAGE_BYTES) pages.push([at, image.flash.slice(at, at + PAGE_BYTES)]);
  return { pages, bytes: image.used };
}

// A port's bytes, read with timeouts. A port that ends or fails mid-flash throws "vanished".
class Link {
  constructor(port) {
    this.port = port;
    this.reader = port.readable.getReader();
    this.writer = port.writable.getWriter();
    this.buffer = [];
    this.wake = null;
    this.ended = null;
    // the Nano's time, where the port has its own (the virtual Nano's, slowed by a busy machine)
    this.now = port.clock ? () => port.clock() : () => performance.now();
    this.pump();
  }

  async pump() {
    try {
      for (;;) {
        const { value, done } = await this.reader.read();
        if (done) break;
        for (const b of value) this.buffer.push(b);
        this.wake?.();
      }
      this.ended = "the port closed";
    } catch (e) {
      this.ended = e?.message || String(e);
    }
    this.wake?.();
  }

  async write(bytes) {
    if (this.ended) throw new FlashError("vanished", this.ended);
    try {
      await this.writer.write(Uint8Array.from(bytes));
    } catch (e) {
      throw new FlashError("vanished", e?.message || String(e));
    }
  }

  /** `n` bytes, or null after `ms` in which no byte came (the wait starts again with every
   * byte: a Nano answering slowly, as an emulated one on a busy machine does, is not a stall). */
  async read(n, ms) {
    // (and a device whose own clock stands still, a virtual Nano's stopped worker, stalls after
    // WALL_STALLS times that on the page's clock)
    let end = this.now() + ms, wallEnd = performance.now() + WALL_STALLS * ms, had = this.buffer.length;
    while (this.buffer.length < n) {
      if (this.ended) throw new FlashError("vanished", this.ended);
      if (this.buffer.length > had) {
        had = this.buffer.length;
        end = this.now() + ms;
        wallEnd = performance.now() + WALL_STALLS * ms;
      }
      const left = Math.min(end - this.now(), wallEnd - performance.now());
      if (left <= 0) return null;
      await new Promise((r) => {
        this.wake = r;
        setTimeout(r, Math.min(left, 50));
      });
      this.wake = null;
    }
    return this.buffer.splice(0, n);
  }

  /** Waits `ms` of the Nano's time. */
  async sleep(ms) {
    const end = this.now() + ms;
    for (let left = ms; left > 0; left = end - this.now()) await sleep(Math.min(left, 20));
  }

  drain() {
    this.buffer.length = 0;
  }

  async close() {
    try {
      this.reader.releaseLock();
      this.writer.releaseLock();
    } catch {
      /* a vanished port's locks go with it */
    }
  }
}

// How long a command's answer may keep the page waiting with no byte at all (avrdude's
// serial timeout): a stall, after which the flash starts again from the reset.
export const STALL_MS = 5000;
// Flashes that stall are tried this many times in all before the flasher gives up.
export const TRIES = 2;

// `n` bytes of the answer to `what`, or a stall naming it.
async function answer(link, n, what, ms = STALL_MS) {
  const r = await link.read(n, ms);
  if (!r) throw new FlashError("stalled", `the bootloader stopped answering (${what}): nothing for ${ms / 1000} s`);
  return r;
}

// One command: `INSYNC <n bytes> OK` back, or an error naming it.
async function command(link, bytes, n, what, ms = STALL_MS) {
  await link.write([...bytes, CRC_EOP]);
  const r = await answer(link, n + 2, what, ms);
  if (r[0] !== STK_INSYNC || r[n + 1] !== STK_OK)
    throw new FlashError("no-bootloader", `the bootloader answered ${r.map(hex2).join(" ")} to ${what}`);
  return r.slice(1, n + 1);
}

// Resets the Nano into its bootloader (DTR and RTS low, then high: the auto-reset capacitor
// pulls RESET low) and gets in sync; false when nothing answers at this baud rate.
async function sync(link, port) {
  if (port.setSignals) {
    await port.setSignals({ dataTerminalReady: false, requestToSend: false });
    await link.sleep(100);
    await port.setSignals({ dataTerminalReady: true, requestToSend: true });
    await link.sleep(50);
  }
  link.drain();
  for (let attempt = 0; attempt < 10; attempt++) {
    await link.write([GET_SYNC, CRC_EOP]);
    const r = await link.read(2, 250);
    if (r && r[0] === STK_INSYNC && r[1] === STK_OK) {
      // answers to earlier attempts, still on their way: 100 ms of the Nano's time (which the
      // page learns in steps: a shorter wait could end at once)
      await link.sleep(100);
      link.drain();
      return true;
    }
    link.drain();
  }
  return false;
}

// The signature request, the first command after the sync. Answers to the sync's earlier
// attempts can still be on their way: a busy machine delays the page's bytes to a virtual Nano
// (and a USB adapter's buffer a real one's) by more than the sync's waits. They all come before
// this one's answer (a serial line keeps the order), so they are passed over here: INSYNC OK
// pairs, or an OK whose INSYNC the sync drained. A signature begins 0x1e (Atmel's), never OK.
async function signature(link) {
  const what = "the signature request";
  await link.write([READ_SIGN, CRC_EOP]);
  const next = (n) => answer(link, n, what);
  const skipped = [];
  for (;;) {
    const [b] = await next(1);
    if (b === STK_INSYNC) {
      const [first] = await next(1);
      if (first !== STK_OK) {
        const rest = await next(3);
        if (rest[2] !== STK_OK)
          throw new FlashError("no-bootloader", `the bootloader answered ${[b, first, ...rest].map(hex2).join(" ")} to ${what}`);
        return [first, rest[0], rest[1]];
      }
      skipped.push(b, first);
    } else if (b === STK_OK) skipped.push(b);
    else throw new FlashError("no-bootloader", `the bootloader answered ${[...skipped, b].map(hex2).join(" ")} to ${what}`);
    if (skipped.length > 40) // more than ten syncs' answers: something else talks on this port
      throw new FlashError("no-bootloader", `the bootloader answered ${skipped.map(hex2).join(" ")}… to ${what}`);
  }
}

// The page's address (`what`: the step it is part of, as a stall names it).
async function loadAddress(link, at, what) {
  const word = at >> 1;
  await command(link, [LOAD_ADDRESS, word & 0xff, word >> 8], 0, `${what}, at ${hex2(at)}`);
}

/**
 * Writes `hexText` to the Nano on `port` (closed on entry and on return) and reads it back.
 * onProgress({ phase: "connect" | "write" | "verify" | "done", done, total, baud, attempt }).
 * A flash that stalls (no byte for STALL_MS), or that no bootloader answered at any rate, starts
 * again from the reset, up to `tries` times in all (attempt counts them); the bootloader takes every try, whatever the last one wrote.
 * Resolves to { bytes, pages, baud, seconds, attempts }; throws a FlashError.
 */
export async function flashNano(port, hexText, { onProgress = () => {}, baudRates = BAUD_RATES, tries = TRIES } = {}) {
  const image = firmwarePages(hexText);
  const t0 = performance.now();
  for (let attempt = 1; ; attempt++) {
    try {
      const r = await flashOnce(port, image, baudRates, (p) => onProgress({ ...p, attempt }));
      return { ...r, seconds: (performance.now() - t0) / 1000, attempts: attempt };
    } catch (e) {
      // a stall, or no sync at any rate (a bootloader's window missed by a busy page, or a
      // reset the adapter lost): from the reset again
      const again = e instanceof FlashError && (e.kind === "stalled" || (e.kind === "no-bootloader" && e.unsynced));
      if (!again || (attempt >= tries && e.kind !== "stalled")) throw e;
      if (attempt >= tries)
        throw new FlashError("stalled", `${e.message}, ${attempt === 1 ? "once" : `${attempt} times`}. ` +
          "Is the machine very busy, or the cable loose? Flash again: the Nano keeps its bootloader");
    }
  }
}

// One try: reset, sync, signature, write, read back, leave.
async function flashOnce(port, { pages, bytes }, baudRates, onProgress) {
  const total = pages.length;
  let link = null, baud = 0, phase = "connect", done = 0;
  const progress = () => onProgress({ phase, done, total, baud });
  try {
    for (const rate of baudRates) {
      progress();
      await port.open({ baudRate: rate });
      link = new Link(port);
      if (await sync(link, port)) {
        baud = rate;
        break;
      }
      await link.close();
      link = null;
      await port.close();
    }
    if (!link) {
      const e = new FlashError("no-bootloader", `no answer from a bootloader at ${baudRates.join(" or ")} baud: is it a Nano ` +
        "(new or old bootloader), and is no other program (a serial monitor, the arm panel) using the port?");
      e.unsynced = true; // (tried again from the reset while tries are left)
      throw e;
    }
    const sig = await signature(link);
    if (sig.some((b, i) => b !== SIGNATURE[i]))
      throw new FlashError("signature", `the chip's signature is ${sig.map(hex2).join(" ")}, not an ATmega328P's ` +
        `(${SIGNATURE.map(hex2).join(" ")}): this is not a Nano`);
    await command(link, [ENTER_PROGMODE], 0, "entering programming mode");
    phase = "write";
    for (const [at, data] of pages) {
      await loadAddress(link, at, `writing page ${done + 1} of ${total}`);
      await command(link, [PROG_PAGE, 0, PAGE_BYTES, 0x46, ...data], 0, `writing page ${done + 1} of ${total}`);
      done++;
      progress();
    }
    phase = "verify";
    done = 0;
    for (const [at, data] of pages) {
      await loadAddress(link, at, `reading back page ${done + 1} of ${total}`);
      const back = await command(link, [READ_PAGE, 0, PAGE_BYTES, 0x46], PAGE_BYTES, `reading back page ${done + 1} of ${total}`);
      const i = back.findIndex((b, k) => b !== data[k]);
      if (i >= 0)
        throw new FlashError("verify", `verify failed at ${hex2(at + i)}: wrote ${hex2(data[i])}, read ${hex2(back[i])}. ` +
          "Flash again; if it fails again, the Nano's flash may be worn out");
      done++;
      progress();
    }
    await command(link, [LEAVE_PROGMODE], 0, "leaving programming mode");
    phase = "done";
    progress();
    return { bytes, pages: total, baud };
  } catch (e) {
    if (e instanceof FlashError && e.kind === "vanished") {
      const where = phase === "write" ? `after ${done} of ${total} pages` : phase === "verify" ? "while verifying" : "";
      throw new FlashError("vanished", `the port went away ${where} (${e.message}). The Nano keeps its bootloader: ` +
        "plug it in again and flash again");
    }
    throw e;
  } finally {
    if (link) {
      await link.close();
      await port.close().catch(() => {});
    }
  }
}
