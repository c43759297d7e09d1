// The virtual Nano in the page: the firmware's own hex (the file `make flash` writes to the
// arm) running on avr8js's ATmega328P - CPU, timers 0/1, USART0, ports B/C/D, EEPROM, the
// watchdog - with the Nano's own peripherals beside avr8js's, each in peripherals/: the
// watchdog as a bootloader needs it and the timers' next flag (watchdog.mjs, timer.mjs,
// subclasses of avr8js's), self-programming (spm.mjs: avr8js has none), the host's serial line
// at its baud rate (serial.mjs), and what the pins drive, read as the harness reads it
// (pins.mjs: each motor's four L298N inputs through virtual-nano/coil_decoder.h, the servo's
// pulse). This file puts them together, resets them, and runs the CPU, asleep or awake. Plain
// JavaScript, so that node's tests run it as the page does (avr-nano.d.mts gives its types).
//
//   const nano = new VirtualNano({ hex, parts });  // parts: virtual-nano/web/nano-parts.mjs
//   nano.onLine = (line) => ...;      // what the firmware sends, a line at a time
//   nano.send("L 0 10\n");            // bytes to its serial port, at 115,200 baud
//   nano.runFor(0.5);                 // emulated seconds
//   nano.steps                        // each motor's steps, as its coils moved it
//
// With `bootloader` (a bootloader's hex: Optiboot, or the old ATmegaBOOT) the Nano is one as
// shipped: the Nano's fuses (high 0xDA: BOOTRST, a 2 KB boot section at 0x7800) start every
// reset there, the lock bits keep SPM off the boot section, and the host's DTR (setDtr)
// resets it as the auto-reset capacitor does, so a flasher talks to the bootloader.
import { AVREEPROM, AVRIOPort, AVRUSART, CPU, EEPROMMemoryBackend, avrInstruction, eepromConfig, portBConfig,
  portCConfig, portDConfig, timer0Config, timer1Config, usart0Config } from "avr8js";
import { PinWatch } from "./peripherals/pins.mjs";
import { HostSerial } from "./peripherals/serial.mjs";
import { SelfProgramming } from "./peripherals/spm.mjs";
import { NanoTimer } from "./peripherals/timer.mjs";
import { NanoWatchdog } from "./peripherals/watchdog.mjs";

export const CLOCK_HZ = 16_000_000;
const OP_RETI = 0x9518;
const OP_SEI = 0x9478;
const OP_SPM = 0x95e8;
const OP_SLEEP = 0x9588;
const OP_RJMP_BACK_4 = 0xcffc; // rjmp .-8: the end of `lds rd, A; sbrs/sbrc rd, b` (a poll)
const OP_RJMP_BACK_3 = 0xcffd; // rjmp .-6: the end of `in rd, A; sbrs/sbrc rd, b`
// OUT 0x3F, Rr: a write to SREG (the form 1011 1AAr rrrr AAAA with A = 0x3F)
const isOutSreg = (op) => (op & 0xfe0f) === 0xbe0f;
const FLASH_BYTES = 32 * 1024;
const SRAM_BYTES = 2048;
const EEPROM_BYTES = 1024;
export const PAGE_BYTES = 128; // the ATmega328P's flash page
/** Where the Nano's boot section starts (high fuse 0xDA: BOOTSZ = 1,024 words). */
export const BOOT_START = 0x7800;
// MCUSR's reset causes (datasheet 10.9.1)
export const RESET_POWER = 0x01, RESET_EXTERNAL = 0x02, RESET_WATCHDOG = 0x08;
const SMCR = 0x53, SE = 0x01; // the sleep mode control register, its sleep enable
const MCUSR = 0x54;
// A page erase or write takes 3.7-4.5 ms (datasheet 28.8.10, t_WD_FLASH)
const SPM_BUSY_CYCLES = Math.round(0.004 * CLOCK_HZ);

/** An Intel HEX file into the flash's bytes; throws naming the line of a malformed record. */
export function parseHex(text, size = FLASH_BYTES) {
  const flash = new Uint8Array(size).fill(0xff);
  let base = 0, used = 0, lineNo = 0;
  for (const raw of text.split(/\r?\n/)) {
    lineNo++;
    const line = raw.trim();
    if (!line) continue;
    if (line[0] !== ":" || line.length < 11 || !/^:[0-9A-Fa-f]+$/.test(line))
      throw new Error(`hex line ${lineNo}: not an Intel HEX record`);
    const bytes = line.slice(1).match(/../g).map((h) => parseInt(h, 16));
    const [n, hi, lo, type] = bytes;
    if (bytes.length !== n + 5) throw new Error(`hex line ${lineNo}: its length says ${n} data bytes`);
    if (bytes.reduce((a, b) => a + b, 0) & 0xff) throw new Error(`hex line ${lineNo}: bad checksum`);
    if (type === 0) {
      const at = base + ((hi << 8) | lo);
      if (at + n > size) throw new Error(`hex line ${lineNo}: data at 0x${at.toString(16)} is beyond the flash`);
      flash.set(bytes.slice(4, 4 + n), at);
      used = Math.max(used, at + n);
    } else if (type === 1) {
      break;
    } else if (type === 2) {
      base = ((bytes[4] << 8) | bytes[5]) << 4;
    } else if (type === 4) {
      base = ((bytes[4] << 8) | bytes[5]) << 16;
    }
  }
  return { flash, used };
}

export class VirtualNano {
  /**
   * hex: the firmware's Intel HEX text; parts: the virtual Nano's parts (virtual-nano/web/nano-parts.mjs:
   * the coil decoders and the board's pins); eeprom: the EEPROM's bytes to start from (kept by the caller across sessions);
   * cnc: the hex is the build for a CNC shield (articula-cnc.hex): its motors on STEP/DIR drivers, the shield's pins;
   * servos: the hex is the servo build (articula-servo.hex): [{pin, zeroUs}] per motor (PinWatch).
   */
  constructor({ hex, parts, eeprom, bootloader, image, cnc = false, servos = null }) {
    const { flash, used } = parseHex(hex);
    if (image) {
      flash.set(image.subarray(0, FLASH_BYTES)); // a flash image kept from before (bootloader and all)
    } else if (bootloader) {
      if (used > BOOT_START) throw new Error(`the firmware (${used} bytes) reaches into the boot section at 0x${BOOT_START.toString(16)}`);
      const boot = parseHex(bootloader).flash;
      flash.set(boot.subarray(BOOT_START), BOOT_START);
    }
    this.flash = flash; // the flash's bytes: SPM writes them, the CPU runs them
    this.flashUsed = used;
    this.sleptCycles = 0; // cycles the CPU spent asleep (SLEEP), skipped rather than run
    this.asleep = false; // between SLEEP and the interrupt that wakes it
    this.bootWord = bootloader ? BOOT_START / 2 : 0; // where a reset starts (BOOTRST)
    this.resetPending = 0; // a reset's cause, done after the instruction that caused it
    this.dtr = true; // the host holds DTR asserted while the port is open
    const cpu = this.cpu = new CPU(new Uint16Array(flash.buffer), SRAM_BYTES);
    // Timer0 (millis) and Timer1 (the stepper and servo interrupts). The firmware leaves Timer2
    // unused (firmware/src/board.h), so it is not emulated: a fifth of the emulator's time.
    this.timers = [timer0Config, timer1Config].map((c) => new NanoTimer(cpu, c));
    this.usart = new AVRUSART(cpu, usart0Config, CLOCK_HZ);
    this.eepromBackend = new EEPROMMemoryBackend(EEPROM_BYTES);
    if (eeprom) this.eepromBackend.memory.set(eeprom.subarray(0, EEPROM_BYTES));
    this.eeprom = new AVREEPROM(cpu, this.eepromBackend, eepromConfig);
    this.watchdog = new NanoWatchdog(cpu, CLOCK_HZ, () => (this.resetPending = RESET_WATCHDOG));
    this.ports = { B: new AVRIOPort(cpu, portBConfig), C: new AVRIOPort(cpu, portCConfig), D: new AVRIOPort(cpu, portDConfig) };
    this.serial = new HostSerial(cpu, this.usart, CLOCK_HZ);
    this.spm = new SelfProgramming(cpu, flash, { pageBytes: PAGE_BYTES, bootStart: BOOT_START, busyCycles: SPM_BUSY_CYCLES });
    this.pins = new PinWatch(cpu, this.ports, parts, CLOCK_HZ, cnc, servos);
    this.parts = parts;
    this.reset(RESET_POWER);
  }

  // ---- the header's pins for O and W (docs/protocol.md): a wire's level in, the firmware's out

  /** The port and bit of header pin `pin` ("A5", "D12"); throws for a pin the Nano has not. */
  headerPin(pin) {
    const p = this.parts.headerPin(pin);
    if (!p || !this.ports[p.port]) throw new Error(`the Nano has no header pin "${pin}"`);
    return p;
  }

  /**
   * Drives header pin `pin` from outside at `level` (0 or 1): another arm's wire, a device,
   * as the firmware's W reads it. (avr8js models no pull-up: a pin nothing drives reads 0,
   * where a Nano's pull-up reads 1; a wire gives its source's level from the start.)
   */
  drive(pin, level) {
    const p = this.headerPin(pin);
    this.ports[p.port].setPin(p.bit, !!level);
  }

  /** Header pin `pin`'s level as this Nano drives it: an output's (O), else its pull-up's (1 once set). */
  level(pin) {
    const p = this.headerPin(pin);
    const port = { B: portBConfig, C: portCConfig, D: portDConfig }[p.port].PORT;
    return (this.cpu.data[port] >> p.bit) & 1;
  }

  // ---- what its peripherals say, and hooks on them

  /** Pages written by SPM. */
  get flashWrites() { return this.spm.writes; }
  /** Bytes lost to a full receive buffer. */
  get overruns() { return this.serial.overruns; }
  /** The host's bytes not yet on the wire. */
  get rx() { return this.serial.rx; }
  get hostBaud() { return this.serial.hostBaud; }
  set hostBaud(baud) { this.serial.hostBaud = baud; }
  get onLine() { return this.serial.onLine; }
  set onLine(f) { this.serial.onLine = f; }
  get onByte() { return this.serial.onByte; }
  set onByte(f) { this.serial.onByte = f; }
  /** After any motor's step (its steps already counted), at the CPU's cycle. */
  get onStep() { return this.pins.onStep; }
  set onStep(f) { this.pins.onStep = f; }
  get decoders() { return this.pins.decoders; }
  get servoPulseUs() { return this.pins.servoPulseUs; }
  get firstStepCycle() { return this.pins.firstStepCycle; }
  get lastStepCycle() { return this.pins.lastStepCycle; }
  /** The first and last step cycles since markSteps() of some motors (indices): [-1, -1] if none. */
  stepSpan(motors) { return this.pins.stepSpan(motors); }
  /** Each motor's steps as its coils moved it. */
  get steps() { return this.pins.steps; }
  get coilFaults() { return this.pins.coilFaults; }
  /** Starts a new span of steps: firstStepCycle and lastStepCycle are -1 until the next step. */
  markSteps() { this.pins.markSteps(); }

  // ---- resets

  /**
   * A reset (datasheet 10, "System Control and Reset"): registers and I/O to their initial
   * values, the pins inputs, MCUSR the cause, and the program from the reset vector - the boot
   * section's start with a bootloader. SRAM, EEPROM and flash keep their bytes. After a
   * watchdog reset the watchdog stays on (WDE with WDRF set) at its shortest time.
   */
  reset(cause) {
    const cpu = this.cpu;
    this.resetPending = 0;
    this.asleep = false;
    cpu.data.fill(0, 0, 0x100);
    cpu.reset(); // pc 0, the stack at the top, no interrupt or clock event pending
    for (const t of this.timers) t.reset();
    this.usart.reset();
    this.watchdog.reset(!!(cause & RESET_WATCHDOG));
    this.serial.reset();
    this.spm.reset();
    this.pins.reset();
    cpu.data[MCUSR] = cause;
    cpu.pc = this.bootWord;
  }

  /** The host's DTR line: asserting it resets the Nano (its auto-reset capacitor), as avrdude does. */
  setDtr(on) {
    if (on && !this.dtr) this.reset(RESET_EXTERNAL);
    this.dtr = on;
  }

  /** Bytes (a string or numbers) to the Nano's serial port, in order. */
  send(data) {
    this.serial.send(data);
  }

  /** Emulated time so far, s. */
  get seconds() {
    return this.cpu.cycles / CLOCK_HZ;
  }

  /** Runs the Nano for `seconds` of its time (as fast as the host can). */
  runFor(seconds) {
    this.runUntil(this.cpu.cycles + Math.round(seconds * CLOCK_HZ));
  }

  runUntil(cycle) {
    const cpu = this.cpu, serial = this.serial;
    while (cpu.cycles < cycle) {
      serial.pump();
      // a slice between two looks at the host's bytes, shorter than a byte at 115,200 baud,
      // while any wait (they only come between two runUntil() calls)
      const end = serial.waiting ? Math.min(cycle, cpu.cycles + 1000) : cycle;
      const prog = cpu.progMem;
      const boot = this.bootWord;
      while (cpu.cycles < end) {
        if (this.asleep) {
          if (!this.sleep(end)) break; // still asleep at the slice's end
          this.asleep = false;
          cpu.tick(); // serves the interrupt that woke it
          continue;
        }
        let op = prog[cpu.pc];
        if (op === OP_SPM && boot !== 0 && cpu.pc >= boot) this.spm.execute(); // (from the application section: ignored)
        avrInstruction(cpu);
        // The ATmega328P's datasheet (7.7, "Reset and Interrupt Handling"): after RETI, and
        // after SEI, the next instruction runs before any pending interrupt is served. avr8js
        // serves it at once: a level interrupt that stays pending (UDRE while the firmware
        // has nothing to send) would then starve the main program for ever. The same holds for
        // a write to SREG that sets I, and avr-gcc relies on it: a function's frame is made
        // with `cli; out SPH; out SREG; out SPL`, and an interrupt served between the last
        // two would push onto a stack pointer half old, half new (256 bytes off when the
        // frame crosses a page), overwriting the main program's frames: the virtual Nano then
        // hung now and then in a busy page, its line never answered.
        if (op === OP_RETI || op === OP_SEI || isOutSreg(op)) {
          op = prog[cpu.pc];
          avrInstruction(cpu);
        }
        // a bootloader's poll of a status register: over at once to the next clock event
        if ((op === OP_RJMP_BACK_4 || op === OP_RJMP_BACK_3) && cpu.cycles < end) this.skipPoll(op, end);
        // SLEEP (avr8js runs it as a NOP; the firmware's idle is SEI, SLEEP): nothing runs
        // until an interrupt, unless tick() serves one now (the CPU then wakes at once)
        const pc = cpu.pc;
        cpu.tick();
        if (op === OP_SLEEP && cpu.data[SMCR] & SE && cpu.pc === pc) this.asleep = true;
        if (this.resetPending) this.reset(this.resetPending);
      }
    }
  }

  // A bootloader waits for the host's next byte in a loop that reads a status register until a
  // bit changes (Optiboot's getch: `lds r24, UCSR0A; sbrs r24, RXC0; rjmp .-8`; its wait for
  // SPM: `in r0, SPMCSR; sbrc r0, SELFPRGEN; rjmp .-6`), with interrupts off: the whole flash is
  // such waits, each iteration the same. Such a register (no read hook: plain data) changes only
  // when a clock event fires (a byte arrives, SPM ends, a timer counts) or an interrupt is
  // served, so the clock jumps over the whole iterations before the next event (or `end`), as
  // running them would leave the CPU: the same cycle count, registers and flags (lds, in, sbrs
  // and rjmp change none). Called just after the loop's rjmp ran: the pc is at its read.
  skipPoll(op, end) {
    const cpu = this.cpu, prog = cpu.progMem, pc = cpu.pc;
    const read = prog[pc];
    let addr, words, cycles;
    if (op === OP_RJMP_BACK_4 && (read & 0xfe0f) === 0x9000) {
      addr = prog[pc + 1]; words = 2; cycles = 5; // lds (2) + sbrs not skipping (1) + rjmp (2)
    } else if (op === OP_RJMP_BACK_3 && (read & 0xf800) === 0xb000) {
      addr = 0x20 + ((read & 0x0f) | ((read >> 5) & 0x30)); words = 1; cycles = 4; // in (1) + 1 + 2
    } else return;
    const test = prog[pc + words];
    const reg = (read >> 4) & 0x1f;
    if ((test & 0xfc08) !== 0xfc00 || ((test >> 4) & 0x1f) !== reg || cpu.readHooks[addr]) return;
    const set = (cpu.data[addr] >> (test & 7)) & 1;
    const skipsIfSet = (test & 0x0200) !== 0; // sbrs; sbrc skips if clear
    if (set === (skipsIfSet ? 1 : 0)) return; // the next read ends the loop
    if (cpu.interruptsEnabled && cpu.nextInterrupt >= 0) return;
    const next = cpu.nextClockEvent ? Math.min(cpu.nextClockEvent.cycles, end) : end;
    const n = Math.floor((next - 1 - cpu.cycles) / cycles);
    if (n <= 0) return;
    cpu.cycles += n * cycles;
    cpu.data[reg] = cpu.data[addr]; // (as the last read left it)
  }

  // The CPU asleep (the firmware's idle, hal::idle): nothing runs until an interrupt. The
  // clock jumps to the first cycle one can come: a timer's next compare match or overflow
  // (NanoTimer.nextFlagCycle(), not counted tick by tick), or the next other clock event (the
  // USART, a byte from the host), up to `end`. True when an interrupt woke it (the caller's
  // tick() serves it), false when it still sleeps at `end` (it sleeps on in the next slice).
  // Bytes from the host only come between runUntil() calls; the serial line makes each an event.
  sleep(end) {
    const cpu = this.cpu;
    const from = cpu.cycles;
    while (cpu.cycles < end && !(cpu.interruptsEnabled && cpu.nextInterrupt >= 0)) {
      let until = end;
      let exact = true;
      for (const t of this.timers) {
        const wake = t.nextFlagCycle();
        if (wake === null) exact = false;
        else if (wake < until) until = wake;
      }
      for (let e = cpu.nextClockEvent; e; e = e.next) {
        if (exact && this.timers.some((t) => t.count === e.callback)) continue; // counted below
        if (e.cycles < until) until = e.cycles;
        break;
      }
      if (until > cpu.cycles) {
        cpu.cycles = until;
        if (exact) for (const t of this.timers) t.count(false); // up to now: a match sets its flag
      }
      // the events due now, as tick() fires them, without serving an interrupt (the caller does)
      for (let e = cpu.nextClockEvent; e && e.cycles <= cpu.cycles; e = cpu.nextClockEvent) {
        cpu.nextClockEvent = e.next;
        e.callback();
        if (cpu.clockEventPool.length < 10) cpu.clockEventPool.push(e);
      }
    }
    this.sleptCycles += cpu.cycles - from;
    return cpu.interruptsEnabled && cpu.nextInterrupt >= 0;
  }

  /** The EEPROM's bytes now (settings the firmware saved), to keep across sessions. */
  eepromBytes() {
    return this.eepromBackend.memory.slice();
  }

  delete() {
    this.pins.delete();
  }
}
