// The virtual Nano in the page: the firmware's own hex (the file `make flash` writes to the
// arm) running on avr8js's ATmega328P - CPU, timers 0/1, USART0, ports B/C/D, EEPROM, the
// watchdog, and (emulated here, avr8js has none) SPM, the resets and the Nano's bootloader -
// with what its pins drive read as the harness reads them: each motor's four L298N inputs
// through the coil decoder of virtual-nano/coil_decoder.h, by the board's pins of
// firmware/src/board.h (both in the nano parts module, virtual-nano/web/nano_parts.cpp, the code simavr's
// virtual Nano runs too). Plain JavaScript, so that node's tests run it as the
// page does (nano.d.mts gives its types).
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
import { AVREEPROM, AVRIOPort, AVRTimer, AVRUSART, AVRWatchdog, CPU, EEPROMMemoryBackend, avrInstruction,
  eepromConfig, portBConfig, portCConfig, portDConfig, timer0Config, timer1Config, usart0Config,
  watchdogConfig } from "avr8js";

export const CLOCK_HZ = 16_000_000;
const OP_RETI = 0x9518;
const OP_SEI = 0x9478;
const OP_SPM = 0x95e8;
const OP_SLEEP = 0x9588;
const FLASH_BYTES = 32 * 1024;
const SRAM_BYTES = 2048;
const EEPROM_BYTES = 1024;
export const PAGE_BYTES = 128; // the ATmega328P's flash page
/** Where the Nano's boot section starts (high fuse 0xDA: BOOTSZ = 1,024 words). */
export const BOOT_START = 0x7800;
// MCUSR's reset causes (datasheet 10.9.1)
export const RESET_POWER = 0x01, RESET_EXTERNAL = 0x02, RESET_WATCHDOG = 0x08;
// Registers (data addresses) and bits
const SMCR = 0x53, SE = 0x01; // the sleep mode control register, its sleep enable
const MCUSR = 0x54, SPMCSR = 0x57, WDTCSR = 0x60, UCSR0A = usart0Config.UCSRA, UDR0 = usart0Config.UDR;
const SPMEN = 0x01, PGERS = 0x02, PGWRT = 0x04, BLBSET = 0x08, RWWSRE = 0x10, SIGRD = 0x20, RWWSB = 0x40;
const RXC = 0x80, FE = 0x10, RXEN = 0x10, WDE = 0x08;
// A page erase or write takes 3.7-4.5 ms (datasheet 28.8.10, t_WD_FLASH)
const SPM_BUSY_CYCLES = Math.round(0.004 * CLOCK_HZ);

// The first cycle at which an avr8js timer (`t`) sets a flag: its next compare match (A or B)
// or its wrap at TOP, from its count and prescaler. null when a change is pending that only
// its own count event applies (a new prescaler or a written count), or a phase-correct mode.
function timerWake(t) {
  if (!t.divider) return Infinity; // stopped
  if (t.updateDivider || t.tcntUpdated || t.timerMode === 1 || t.timerMode === 4) return null; // (PWMPhaseCorrect, PWMPhaseFrequencyCorrect)
  const top = t.TOP, val = t.tcnt;
  const ticksTo = (x) => (x > val ? x - val : x + top + 1 - val);
  let ticks = top + 1 - val; // the wrap
  for (const ocr of [t.ocrA, t.ocrB]) if (ocr <= top) ticks = Math.min(ticks, ticksTo(ocr));
  return t.lastCycle + ticks * t.divider;
}

/** A byte as a receiver set to another baud rate reads it: not the byte, and a framing error. */
const garble = (b) => (b * 0x9d + 0x5a) & 0xff;

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
   * the coil decoders and the board's pins); eeprom: the EEPROM's bytes to start from (kept by the caller across sessions).
   */
  constructor({ hex, parts, eeprom, bootloader, image }) {
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
    this.flashWrites = 0; // pages written by SPM
    this.sleptCycles = 0; // cycles the CPU spent asleep (SLEEP), skipped rather than run
    this.asleep = false; // between SLEEP and the interrupt that wakes it
    this.sleptFrom = 0;
    this.bootWord = bootloader ? BOOT_START / 2 : 0; // where a reset starts (BOOTRST)
    this.cpu = new CPU(new Uint16Array(flash.buffer), SRAM_BYTES);
    // Timer0 (millis) and Timer1 (the stepper and servo interrupts). The firmware leaves Timer2
    // unused (firmware/src/board.h), so it is not emulated: a fifth of the emulator's time.
    this.timers = [timer0Config, timer1Config].map((c) => new AVRTimer(this.cpu, c, CLOCK_HZ));
    this.usart = new AVRUSART(this.cpu, usart0Config, CLOCK_HZ);
    // On the chip UDRE is level state: an empty-buffer interrupt that writes nothing leaves it
    // set. avr8js clears it when the interrupt is taken; marked constant it stays, as on silicon
    // (otherwise, after one such call, the firmware never transmits again).
    this.usart.UDRE.constant = true;
    this.eepromBackend = new EEPROMMemoryBackend(EEPROM_BYTES);
    if (eeprom) this.eepromBackend.memory.set(eeprom.subarray(0, EEPROM_BYTES));
    this.eeprom = new AVREEPROM(this.cpu, this.eepromBackend, eepromConfig);
    this.watchdog = new AVRWatchdog(this.cpu, watchdogConfig, { frequency: CLOCK_HZ });
    // avr8js looks at a new timeout only when the old one's check comes round: a bootloader
    // that shortens it to 16 ms (Optiboot's way to reset into the application) waited up to
    // the old second. On the chip the new timeout counts at once.
    const writeWdtcsr = this.cpu.writeHooks[WDTCSR];
    this.cpu.writeHooks[WDTCSR] = (value, oldValue, addr, mask) => {
      const result = writeWdtcsr(value, oldValue, addr, mask);
      const w = this.watchdog;
      if (w.enabled) {
        this.cpu.clearClockEvent(w.checkWatchdog);
        this.cpu.addClockEvent(w.checkWatchdog, Math.max(0, w.watchdogTimeout - this.cpu.cycles));
        w.scheduled = true;
      }
      return result;
    };
    this.ports = { B: new AVRIOPort(this.cpu, portBConfig), C: new AVRIOPort(this.cpu, portCConfig),
      D: new AVRIOPort(this.cpu, portDConfig) };
    this.setUpReceiver();
    this.setUpSpm();
    // avr8js's watchdog resets by cpu.reset(), which leaves the I/O registers as they were and
    // starts at 0: noted here, done by reset() after the instruction.
    this.resetPending = 0;
    this.cpuReset = this.cpu.reset.bind(this.cpu);
    this.cpu.reset = () => {
      this.resetPending = RESET_WATCHDOG;
    };
    this.dtr = true; // the host holds DTR asserted while the port is open
    this.hostBaud = 115200; // the host's side of the line

    // The motors' coils and the servo's pulses, as the pins change.
    const wiring = parts.wiring;
    this.decoders = wiring.motors.map(() => parts.coilDecoder());
    this.firstStepCycle = -1; // the first and last step of any motor since markSteps()
    this.lastStepCycle = -1;
    this.servoPulseUs = null; // the last pulse's width
    this.onStep = null; // (cycle) after any motor's step, its steps already counted
    let servoRise = -1;
    const last = { B: 0, C: 0, D: 0 };
    const listeners = {};
    for (const name of ["B", "C", "D"]) {
      this.ports[name].addListener(listeners[name] = (value) => {
        const changed = value ^ last[name];
        last[name] = value;
        wiring.motors.forEach((m, i) => {
          if (m.port === name && (changed >> m.shift) & 0xf && this.decoders[i].feed((value >> m.shift) & 0xf) === 1) {
            if (this.firstStepCycle < 0) this.firstStepCycle = this.cpu.cycles;
            this.lastStepCycle = this.cpu.cycles;
            this.onStep?.(this.cpu.cycles);
          }
        });
        const s = wiring.servo;
        if (s.port === name && (changed >> s.bit) & 1) {
          if ((value >> s.bit) & 1) servoRise = this.cpu.cycles;
          else if (servoRise >= 0) this.servoPulseUs = ((this.cpu.cycles - servoRise) * 1e6) / CLOCK_HZ;
        }
      });
    }
    // A reset makes every pin an input: the coils and the servo go off.
    this.pinsOff = () => {
      for (const name of ["B", "C", "D"]) listeners[name](0);
      servoRise = -1;
    };

    // The serial line: bytes out a line at a time, bytes in at the baud rate.
    this.onLine = null;
    this.onByte = null;
    this.lineBuffer = "";
    this.usart.onByteTransmit = (sent) => {
      const b = this.baudMatches() ? sent : garble(sent);
      this.onByte?.(b);
      if (b === 10) {
        const line = this.lineBuffer.replace(/\r$/, "");
        this.lineBuffer = "";
        this.onLine?.(line);
      } else {
        this.lineBuffer += String.fromCharCode(b);
      }
    };
    this.reset(RESET_POWER);
  }

  // ---- the serial line in: the host's bytes at its baud rate into a two-byte receive buffer

  setUpReceiver() {
    const cpu = this.cpu, usart = this.usart;
    this.rx = []; // the host's bytes not yet on the wire
    this.rxBuffer = []; // received, unread: [0] is in UDR0 (RXC0 set); the chip holds two
    this.rxShifting = false; // a byte on the wire
    this.overruns = 0; // bytes lost to a full receive buffer (the chip's DOR0)
    // A byte is on the wire for ten bit times of the host's baud rate; then it joins the
    // buffer if there is room (else it is lost, as on the chip) and the next one starts.
    this.shiftIn = () => {
      const b = this.rx.shift();
      this.rxShifting = true;
      cpu.addClockEvent(() => {
        this.rxShifting = false;
        if (cpu.data[usart0Config.UCSRB] & RXEN) {
          if (this.rxBuffer.length < 2) {
            this.rxBuffer.push(this.baudMatches() ? [b, 0] : [garble(b), FE]);
            if (this.rxBuffer.length === 1) this.toUdr();
          } else {
            this.overruns++;
          }
        }
        if (this.rx.length) this.shiftIn();
      }, Math.round((10 * CLOCK_HZ) / this.hostBaud));
    };
    // Reading UDR0 takes the oldest byte; the next, if any, takes its place.
    const readUdr = cpu.readHooks[UDR0];
    cpu.readHooks[UDR0] = (addr) => {
      const value = readUdr(addr);
      cpu.data[UCSR0A] &= ~FE;
      this.rxBuffer.shift();
      if (this.rxBuffer.length) this.toUdr();
      return value;
    };
    // On the chip an unread byte waits (RXC0 set) until it is read, or the receiver is
    // switched off (datasheet 20.11.2, "RXCn"). avr8js clears RXC on every write to UCSR0B
    // that leaves the receiver on, and the firmware writes UCSR0B whenever it masks or unmasks
    // its transmit interrupts: a byte that arrived while interrupts were off was lost (a `?`
    // that never got its report, a command line missing a character). Kept, as on silicon.
    const writeUcsrb = cpu.writeHooks[usart0Config.UCSRB];
    cpu.writeHooks[usart0Config.UCSRB] = (value, oldValue, addr, mask) => {
      const result = writeUcsrb(value, oldValue, addr, mask);
      if (!(value & RXEN)) this.rxBuffer = [];
      else if (this.rxBuffer.length) cpu.setInterruptFlag(usart.RXC);
      return result;
    };
  }

  toUdr() {
    const [b, fe] = this.rxBuffer[0];
    this.usart.rxByte = b;
    this.cpu.data[UCSR0A] = (this.cpu.data[UCSR0A] & ~FE) | fe;
    this.cpu.setInterruptFlag(this.usart.RXC);
  }

  /** Whether the host's baud rate is the USART's, within the 5 % a receiver tolerates. */
  baudMatches() {
    return Math.abs(this.usart.baudRate - this.hostBaud) <= 0.05 * this.hostBaud;
  }

  // ---- self-programming (SPM), as the chip does it (datasheet 26, "Boot Loader Support")

  setUpSpm() {
    const cpu = this.cpu;
    this.pageBuffer = new Uint8Array(PAGE_BYTES).fill(0xff);
    this.spmBusyUntil = 0;
    // SPMCSR: RWWSB is the hardware's; SPMEN reads 1 while an erase or write runs.
    cpu.writeHooks[SPMCSR] = (value) => {
      cpu.data[SPMCSR] = (value & ~RWWSB) | (cpu.data[SPMCSR] & RWWSB);
      return true;
    };
    cpu.readHooks[SPMCSR] = () => cpu.data[SPMCSR] | (cpu.cycles < this.spmBusyUntil ? SPMEN : 0);
  }

  /** One SPM: the operation SPMCSR selects, on the page Z points at (R1:R0 the word to fill). */
  spm() {
    const cpu = this.cpu, d = cpu.data;
    const op = d[SPMCSR] & (SPMEN | PGERS | PGWRT | BLBSET | RWWSRE | SIGRD);
    if (!(op & SPMEN) || cpu.cycles < this.spmBusyUntil) return;
    const z = d[30] | (d[31] << 8);
    const page = z & ~(PAGE_BYTES - 1) & (FLASH_BYTES - 1);
    // The lock bits a Nano ships with (0x0F: BLB1 mode 3) keep SPM off the boot section.
    const writable = page < BOOT_START;
    let busy = false;
    if (op === SPMEN) {
      this.pageBuffer[z & (PAGE_BYTES - 2)] = d[0];
      this.pageBuffer[(z & (PAGE_BYTES - 2)) + 1] = d[1];
    } else if (op === (SPMEN | PGERS)) {
      if (writable) this.flash.fill(0xff, page, page + PAGE_BYTES);
      busy = true;
    } else if (op === (SPMEN | PGWRT)) {
      if (writable) {
        // programming only clears bits: a page not erased first keeps its zeros
        for (let i = 0; i < PAGE_BYTES; i++) this.flash[page + i] &= this.pageBuffer[i];
        this.flashWrites++;
      }
      this.pageBuffer.fill(0xff);
      busy = true;
    } else if (op === (SPMEN | RWWSRE)) {
      d[SPMCSR] &= ~RWWSB;
      this.pageBuffer.fill(0xff);
    }
    // (BLBSET and SIGRD, the lock bits and the signature row, are left alone.) The CPU goes
    // on (a bootloader polls SPMEN); the application section reads as it will be after.
    d[SPMCSR] &= ~(SPMEN | PGERS | PGWRT | BLBSET | RWWSRE | SIGRD);
    if (busy) {
      this.spmBusyUntil = cpu.cycles + SPM_BUSY_CYCLES;
      d[SPMCSR] |= RWWSB; // the application section is busy until RWWSRE
    }
  }

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
    this.cpuReset(); // pc 0, the stack at the top, no interrupt or clock event pending
    for (const t of this.timers) t.reset();
    this.usart.reset();
    const w = this.watchdog;
    w.scheduled = false;
    w.enabledValue = false;
    w.changeEnabledCycles = 0;
    if (cause & RESET_WATCHDOG) {
      cpu.data[WDTCSR] = WDE;
      w.enabledValue = true;
      w.resetWatchdog();
      w.scheduled = true;
      cpu.addClockEvent(w.checkWatchdog, w.watchdogTimeout - cpu.cycles);
    }
    this.rxBuffer = [];
    this.rxShifting = false; // a byte on the wire is lost
    this.spmBusyUntil = 0;
    this.pageBuffer.fill(0xff);
    this.pinsOff();
    cpu.data[MCUSR] = cause;
    cpu.pc = this.bootWord;
  }

  /** The host's DTR line: asserting it resets the Nano (its auto-reset capacitor), as avrdude does. */
  setDtr(on) {
    if (on && !this.dtr) this.reset(RESET_EXTERNAL);
    this.dtr = on;
  }

  /** Starts a new span of steps: firstStepCycle and lastStepCycle are -1 until the next step. */
  markSteps() {
    this.firstStepCycle = this.lastStepCycle = -1;
  }

  /** Bytes (a string or numbers) to the Nano's serial port, in order. */
  send(data) {
    for (const b of typeof data === "string" ? new TextEncoder().encode(data) : data) this.rx.push(b);
  }

  /** Emulated time so far, s. */
  get seconds() {
    return this.cpu.cycles / CLOCK_HZ;
  }

  /** Each motor's steps as its coils moved it. */
  get steps() {
    return this.decoders.map((d) => d.steps());
  }

  get coilFaults() {
    return this.decoders.reduce((n, d) => n + d.faults(), 0);
  }

  /** Runs the Nano for `seconds` of its time (as fast as the host can). */
  runFor(seconds) {
    this.runUntil(this.cpu.cycles + Math.round(seconds * CLOCK_HZ));
  }

  runUntil(cycle) {
    const cpu = this.cpu;
    while (cpu.cycles < cycle) {
      if (this.rx.length && !this.rxShifting) this.shiftIn();
      // a slice between two looks at the host's bytes, shorter than a byte at 115,200 baud,
      // while any wait (they only come between two runUntil() calls)
      const end = this.rx.length ? Math.min(cycle, cpu.cycles + 1000) : cycle;
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
        if (op === OP_SPM && boot !== 0 && cpu.pc >= boot) this.spm(); // (from the application section: ignored)
        avrInstruction(cpu);
        // The ATmega328P's datasheet (7.7, "Reset and Interrupt Handling"): after RETI, and
        // after SEI, the next instruction runs before any pending interrupt is served. avr8js
        // serves it at once: a level interrupt that stays pending (UDRE while the firmware
        // has nothing to send) would then starve the main program for ever.
        if (op === OP_RETI || op === OP_SEI) {
          op = prog[cpu.pc];
          avrInstruction(cpu);
        }
        // SLEEP (avr8js runs it as a NOP; the firmware's idle is SEI, SLEEP): nothing runs
        // until an interrupt, unless tick() serves one now (the CPU then wakes at once)
        const pc = cpu.pc;
        cpu.tick();
        if (op === OP_SLEEP && cpu.data[SMCR] & SE && cpu.pc === pc) this.asleep = true;
        if (this.resetPending) this.reset(this.resetPending);
      }
    }
  }

  // The CPU asleep (the firmware's idle, hal::idle): nothing runs until an interrupt. The
  // clock jumps to the first cycle one can come: a timer's next compare match or overflow
  // (worked out from its count, not counted tick by tick), or the next other clock event (the
  // USART, a byte from the host), up to `end`. True when an interrupt woke it (the caller's
  // tick() serves it), false when it still sleeps at `end` (it sleeps on in the next slice).
  // Bytes from the host only come between runUntil() calls; shiftIn() makes each an event.
  sleep(end) {
    const cpu = this.cpu;
    const from = cpu.cycles;
    while (cpu.cycles < end && !(cpu.interruptsEnabled && cpu.nextInterrupt >= 0)) {
      let until = end;
      let exact = true;
      for (const t of this.timers) {
        const wake = timerWake(t);
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
    for (const d of this.decoders) d.delete();
  }
}
