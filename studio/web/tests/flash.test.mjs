// Flashing from the page, end to end in node: the page's flasher (src/link/stk500.mjs) writes the
// firmware's hex through Debian's own Optiboot (and the old ATmegaBOOT) running on the
// page's virtual Nano (src/virtual-nano/avr-nano.mjs, SPM emulated as the chip does it), reads it back, and
// the Nano resets into it and answers `I` with the robot's banner. And every way it fails.
import assert from "node:assert/strict";
import { existsSync, readFileSync } from "node:fs";
import { join } from "node:path";
import { before, describe, test } from "node:test";
import { REPO, nodeNanoParts } from "../../../wasm/js/node.mjs";
import { RESET_POWER, VirtualNano, parseHex } from "../src/virtual-nano/avr-nano.mjs";
import { FlashError, flashNano } from "../src/link/stk500.mjs";
import { NanoPort } from "./nano-port.mjs";

const HEX = process.env.ARTICULA_NANO_HEX || join(REPO, "build/avr/firmware/articula-nano.hex");
const BOOTLOADERS = "/usr/share/arduino/hardware/arduino/avr/bootloaders";
const OPTIBOOT = process.env.ARTICULA_OPTIBOOT_HEX || join(REPO, "build/avr/firmware/optiboot_atmega328.hex");
const OLD_BOOT = join(BOOTLOADERS, "atmega/ATmegaBOOT_168_atmega328.hex");
// Debian's own build of Optiboot: 532 bytes for a 512-byte slot (see bootloader/CMakeLists.txt)
const DEBIAN_OPTIBOOT = join(BOOTLOADERS, "optiboot/optiboot_atmega328.hex");
const EMPTY = ":00000001FF\n"; // a Nano with its bootloader and no program

let parts, firmware, image;
before(async () => {
  parts = await nodeNanoParts();
  firmware = readFileSync(HEX, "utf8");
  image = parseHex(firmware);
});

// The banner, asked of whatever runs on the Nano now (at 115,200 baud, as the firmware talks),
// `I` every 300 ms, for at most `seconds` of the wall's time: it comes within about 1.5 s on a
// quiet machine, and the wait ends when it does; the emulator runs slower on a busy machine,
// so the default leaves it ten times that.
async function banner(port, seconds = 15) {
  await port.open({ baudRate: 115200 });
  const reader = port.readable.getReader();
  const writer = port.writable.getWriter();
  let text = "";
  const end = performance.now() + seconds * 1000;
  let asked = 0;
  let pending = null; // one read at a time: a read left behind would take bytes with it
  try {
    while (performance.now() < end && !/\[Articula[^\n]*\n/.test(text)) {
      if (performance.now() > asked + 300) {
        asked = performance.now();
        await writer.write(new TextEncoder().encode("I\n"));
      }
      pending ??= reader.read();
      const r = await Promise.race([pending, new Promise((res) => setTimeout(() => res(null), 100))]);
      if (r) {
        pending = null;
        if (r.value) text += new TextDecoder("latin1").decode(r.value);
      }
    }
  } finally {
    reader.releaseLock();
    writer.releaseLock();
    await port.close();
  }
  return /\[Articula[^\n]*/.exec(text)?.[0] ?? null;
}

function nanoWith(bootloader, app = EMPTY) {
  return new VirtualNano({ hex: app, parts, bootloader: bootloader && readFileSync(bootloader, "utf8") });
}

// The Nano at most PACE times real time, as the page's worker runs it at most in real time: a
// bootloader's waits for the host cost nothing to emulate (VirtualNano.skipPoll), so unpaced
// its clock would run far ahead of the flasher's, and its watchdog (1 s) end the bootloader
// between two of the flasher's commands.
const PACE = 4;
const pacedPort = (n) => Object.assign(new NanoPort(n), { pace: PACE });

const written = (n) => n.flash.subarray(0, image.used).every((b, i) => b === image.flash[i]);

describe("flashing the Nano from the page", { skip: !existsSync(OPTIBOOT) && "arduino-core-avr's bootloaders are not installed" }, () => {
  test("through Optiboot: written, verified, and the Nano answers I with the robot's banner", async (t) => {
    const n = nanoWith(OPTIBOOT);
    const port = pacedPort(n);
    assert.equal(await banner(port, 1), null, "a Nano with no program has no banner");
    const phases = new Set();
    let last = null;
    const r = await flashNano(port, firmware, { onProgress: (p) => (phases.add(p.phase), (last = p)) });
    assert.equal(r.baud, 115200);
    assert.equal(r.bytes, image.used);
    assert.equal(r.pages, Math.ceil(image.used / 128));
    assert.deepEqual([...phases], ["connect", "write", "verify", "done"]);
    assert.equal(last.done, last.total);
    assert.ok(written(n), "the flash holds the firmware");
    assert.equal(n.flashWrites, r.pages, "one page write per page");
    const b = await banner(port);
    assert.match(b ?? "", /^\[Articula\|V:[^|]+\|P:\d+\|J:3\|R:MK2 Plus\|K:21232(\|W:\d+)?\]$/);
    t.diagnostic(`${r.bytes} bytes, ${r.pages} pages through Optiboot at ${r.baud} baud, verified; banner ${b}; ` +
      `${n.seconds.toFixed(2)} s emulated`);
    n.delete();
  });

  test("each drive's build through Optiboot: the CNC shield's and the servo arms', each with its built-in arm", async (t) => {
    for (const [file, options, robot] of [
      ["articula-cnc.hex", { cnc: true }, "MK2 Plus CNC\\|K:65000"],
      ["articula-servo.hex", { servos: [{ pin: "D9", zeroUs: 1544 }, { pin: "D10", zeroUs: 1265 }, { pin: "D11", zeroUs: 1472 }] },
        "meArm\\|K:45618"],
    ]) {
      const hex = readFileSync(join(HEX, "..", file), "utf8");
      const n = new VirtualNano({ hex: EMPTY, parts, bootloader: readFileSync(OPTIBOOT, "utf8"), ...options });
      const port = pacedPort(n);
      const r = await flashNano(port, hex);
      assert.equal(r.bytes, parseHex(hex).used, file);
      const b = await banner(port);
      assert.match(b ?? "", new RegExp(`^\\[Articula\\|V:[^|]+\\|P:\\d+\\|J:3\\|R:${robot}(\\|W:\\d+)?\\]$`), file);
      t.diagnostic(`${file}: ${r.bytes} bytes, ${r.pages} pages through Optiboot, verified; banner ${b}`);
      n.delete();
    }
  });

  test("through the old bootloader (ATmegaBOOT, 57,600 baud) after Optiboot's rate finds nothing", { skip: !existsSync(OLD_BOOT) }, async (t) => {
    const n = nanoWith(OLD_BOOT);
    const port = pacedPort(n);
    const r = await flashNano(port, firmware);
    assert.equal(r.baud, 57600);
    assert.ok(written(n));
    assert.match((await banner(port)) ?? "", /R:MK2 Plus/);
    t.diagnostic(`${r.bytes} bytes through ATmegaBOOT at ${r.baud} baud in ${r.seconds.toFixed(1)} s (wall, the emulator at most ${PACE}x real time)`);
    n.delete();
  });

  test("a flash cut off halfway, then flashed again, ends with a working firmware", async (t) => {
    const n = nanoWith(OPTIBOOT, firmware); // a firmware in place, as on a Nano in use
    const port = pacedPort(n);
    port.pullAfter = Math.floor(image.used / 2); // bytes: the cable goes about halfway
    await assert.rejects(flashNano(port, firmware), (e) => {
      assert.ok(e instanceof FlashError);
      assert.equal(e.kind, "vanished");
      assert.match(e.message, /after \d+ of \d+ pages.*keeps its bootloader: plug it in again and flash again/);
      t.diagnostic(e.message);
      return true;
    });
    assert.ok(!written(n) || n.flashWrites < Math.ceil(image.used / 128), "the flash is half written");
    port.plugIn();
    const r = await flashNano(port, firmware);
    assert.ok(written(n));
    assert.match((await banner(port)) ?? "", /R:MK2 Plus/);
    t.diagnostic(`flashed again: ${r.pages} pages, verified, banner back`);
    n.delete();
  });

  test("a Nano that stops answering mid-flash: the flash starts again from the reset and ends verified", async (t) => {
    const n = nanoWith(OPTIBOOT, firmware);
    const port = pacedPort(n);
    port.muteAfter = Math.floor(image.used / 3); // a third of the way, its answers lost, this once
    port.muteOpens = 1;
    const attempts = [];
    const r = await flashNano(port, firmware, { onProgress: (p) => attempts.includes(p.attempt) || attempts.push(p.attempt) });
    assert.deepEqual(attempts, [1, 2]);
    assert.equal(r.attempts, 2);
    assert.ok(written(n));
    assert.match((await banner(port)) ?? "", /R:MK2 Plus/);
    t.diagnostic(`stalled once, flashed on the second try: ${r.pages} pages in ${r.seconds.toFixed(1)} s of the wall's time`);
    n.delete();
  });

  test("a sync missed at every rate (a busy page, a lost reset): the flash starts again from the reset and ends verified", async (t) => {
    const n = nanoWith(OPTIBOOT, firmware);
    const port = pacedPort(n);
    port.muteAfter = 0; // every answer lost, at 115,200 and then at 57,600, on the first try only
    port.muteOpens = 2;
    const attempts = [];
    const r = await flashNano(port, firmware, { onProgress: (p) => attempts.includes(p.attempt) || attempts.push(p.attempt) });
    assert.deepEqual(attempts, [1, 2]);
    assert.equal(r.attempts, 2);
    assert.equal(r.baud, 115200);
    assert.ok(written(n));
    assert.match((await banner(port)) ?? "", /R:MK2 Plus/);
    t.diagnostic(`no sync on the first try, flashed on the second: ${r.pages} pages in ${r.seconds.toFixed(1)} s of the wall's time`);
    n.delete();
  });

  test("answers to the sync that come late (a busy machine) are passed over: the flash ends verified", async (t) => {
    // The first two GET_SYNCs reach the bootloader 300 ms late: the first one's answer comes in
    // the second's wait, and the second's after the sync has ended, before the signature's.
    const n = nanoWith(OPTIBOOT, firmware);
    const port = pacedPort(n);
    port.lagWrites = 2;
    port.lagMs = 300;
    const r = await flashNano(port, firmware);
    assert.equal(r.attempts, 1);
    assert.ok(written(n));
    assert.match((await banner(port)) ?? "", /R:MK2 Plus/);
    t.diagnostic(`a late sync answer passed over: ${r.pages} pages, verified`);
    n.delete();
  });

  test("a Nano that never answers again: the stall is told in words, with what to do", async (t) => {
    const n = nanoWith(OPTIBOOT, firmware);
    const port = pacedPort(n);
    port.muteAfter = Math.floor(image.used / 3);
    port.muteOpens = Infinity;
    await assert.rejects(flashNano(port, firmware), (e) => {
      assert.equal(e.kind, "stalled");
      // (whichever of the page's two commands its answers stopped at: the page's address or its bytes)
      assert.match(e.message, /^the bootloader stopped answering \(writing page \d+ of \d+(, at 0x[0-9a-f]+)?\): nothing for 5 s, 2 times\. .*Flash again/);
      t.diagnostic(e.message);
      return true;
    });
    n.delete();
  });

  test("a verify that reads back another byte names the address", async () => {
    const n = nanoWith(OPTIBOOT);
    // a worn cell: one bit at an address the firmware sets stays 0 after a write
    const at = image.flash.findIndex((b, i) => i >= 0x200 && b & 1);
    const execute = n.spm.execute.bind(n.spm);
    n.spm.execute = () => {
      execute();
      n.flash[at] &= 0xfe;
    };
    await assert.rejects(flashNano(pacedPort(n), firmware), (e) => {
      assert.equal(e.kind, "verify");
      assert.match(e.message, new RegExp(`^verify failed at 0x${at.toString(16).padStart(2, "0")}: wrote 0x[0-9a-f]{2}, read 0x[0-9a-f]{2}`));
      return true;
    });
    n.delete();
  });

  test("no bootloader answers: a Nano without one, or a port at the wrong end", async () => {
    const n = new VirtualNano({ hex: firmware, parts }); // the firmware alone, no bootloader
    const port = pacedPort(n);
    await assert.rejects(flashNano(port, firmware), (e) => {
      assert.equal(e.kind, "no-bootloader");
      assert.match(e.message, /no answer from a bootloader at 115200 or 57600 baud: is it a Nano/);
      return true;
    });
    assert.match((await banner(port)) ?? "", /R:MK2 Plus/, "the firmware is untouched");
    n.delete();
  });

  test("Debian's prebuilt optiboot_atmega328.hex overflows its slot: the virtual Nano refuses it and says where", { skip: !existsSync(DEBIAN_OPTIBOOT) }, () => {
    assert.throws(() => nanoWith(DEBIAN_OPTIBOOT), /hex line \d+: data at 0x8000 is beyond the flash/);
  });

  test("a hex that is not one, or too big for a Nano, is refused before the port is opened", async () => {
    const port = { open: () => assert.fail("opened the port") };
    await assert.rejects(flashNano(port, ":10000000zz\n"), (e) => e.kind === "hex" && /hex line 1/.test(e.message));
    await assert.rejects(flashNano(port, ""), (e) => e.kind === "hex" && /no program/.test(e.message));
    const big = [];
    for (let a = 0; a < 0x7900; a += 16) {
      const rec = [16, a >> 8, a & 0xff, 0, ...Array(16).fill(0)];
      const sum = (256 - (rec.reduce((x, y) => x + y, 0) & 0xff)) & 0xff;
      big.push(":" + [...rec, sum].map((b) => b.toString(16).padStart(2, "0")).join("").toUpperCase());
    }
    await assert.rejects(flashNano(port, big.join("\n") + "\n:00000001FF\n"), (e) => e.kind === "hex" && /more than the 30720/.test(e.message));
  });
});
