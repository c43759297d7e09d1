// The virtual Nano in the page: the firmware's own hex (the file `make flash` writes to the
// arm) running on avr8js's ATmega328P - CPU, timers 0/1, USART0, ports B/C/D, EEPROM -
// with what its pins drive read as the harness reads them: each motor's four L298N inputs
// through the engine's coil decoder (hil/vnano/coil_decoder.h, compiled into the web engine),
// by the wiring of hil/vnano/wiring.h. Plain JavaScript, so that node's tests run it as the
// page does (nano.d.mts gives its types).
//
//   const nano = new VirtualNano({ hex, engine });
//   nano.onLine = (line) => ...;      // what the firmware sends, a line at a time
//   nano.send("L 0 10\n");            // bytes to its serial port, at 115,200 baud
//   nano.runFor(0.5);                 // emulated seconds
//   nano.steps                        // each motor's steps, as its coils moved it
import { AVREEPROM, AVRIOPort, AVRTimer, AVRUSART, CPU, EEPROMMemoryBackend, avrInstruction, eepromConfig,
  portBConfig, portCConfig, portDConfig, timer0Config, timer1Config, usart0Config } from "avr8js";

export const CLOCK_HZ = 16_000_000;
const OP_RETI = 0x9518;
const OP_SEI = 0x9478;
const FLASH_BYTES = 32 * 1024;
const SRAM_BYTES = 2048;
const EEPROM_BYTES = 1024;

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
   * hex: the firmware's Intel HEX text; engine: the web engine (its coil decoders and the
   * wiring); eeprom: the EEPROM's bytes to start from (kept by the caller across sessions).
   */
  constructor({ hex, engine, eeprom }) {
    const { flash, used } = parseHex(hex);
    this.flashUsed = used;
    this.cpu = new CPU(new Uint16Array(flash.buffer), SRAM_BYTES);
    // Timer0 (millis) and Timer1 (the stepper and servo interrupts). The firmware leaves Timer2
    // unused (firmware/src/pins.h), so it is not emulated: a fifth of the emulator's time.
    this.timers = [timer0Config, timer1Config].map((c) => new AVRTimer(this.cpu, c, CLOCK_HZ));
    this.usart = new AVRUSART(this.cpu, usart0Config, CLOCK_HZ);
    // On the chip UDRE is level state: an empty-buffer interrupt that writes nothing leaves it
    // set. avr8js clears it when the interrupt is taken; marked constant it stays, as on silicon
    // (otherwise, after one such call, the firmware never transmits again).
    this.usart.UDRE.constant = true;
    this.eepromBackend = new EEPROMMemoryBackend(EEPROM_BYTES);
    if (eeprom) this.eepromBackend.memory.set(eeprom.subarray(0, EEPROM_BYTES));
    this.eeprom = new AVREEPROM(this.cpu, this.eepromBackend, eepromConfig);
    this.ports = { B: new AVRIOPort(this.cpu, portBConfig), C: new AVRIOPort(this.cpu, portCConfig),
      D: new AVRIOPort(this.cpu, portDConfig) };

    // The motors' coils and the servo's pulses, as the pins change.
    const wiring = engine.nanoWiring;
    this.decoders = wiring.motors.map(() => engine.coilDecoder());
    this.firstStepCycle = -1; // the first and last step of any motor since markSteps()
    this.lastStepCycle = -1;
    this.servoPulseUs = null; // the last pulse's width
    let servoRise = -1;
    const last = { B: 0, C: 0, D: 0 };
    for (const name of ["B", "C", "D"]) {
      this.ports[name].addListener((value) => {
        const changed = value ^ last[name];
        last[name] = value;
        wiring.motors.forEach((m, i) => {
          if (m.port === name && (changed >> m.shift) & 0xf && this.decoders[i].feed((value >> m.shift) & 0xf) === 1) {
            if (this.firstStepCycle < 0) this.firstStepCycle = this.cpu.cycles;
            this.lastStepCycle = this.cpu.cycles;
          }
        });
        const s = wiring.servo;
        if (s.port === name && (changed >> s.bit) & 1) {
          if ((value >> s.bit) & 1) servoRise = this.cpu.cycles;
          else if (servoRise >= 0) this.servoPulseUs = ((this.cpu.cycles - servoRise) * 1e6) / CLOCK_HZ;
        }
      });
    }

    // The serial line: bytes out a line at a time, bytes in at the baud rate.
    this.onLine = null;
    this.onByte = null;
    this.lineBuffer = "";
    this.usart.onByteTransmit = (b) => {
      this.onByte?.(b);
      if (b === 10) {
        const line = this.lineBuffer.replace(/\r$/, "");
        this.lineBuffer = "";
        this.onLine?.(line);
      } else {
        this.lineBuffer += String.fromCharCode(b);
      }
    };
    this.rx = [];
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
      // the next byte in, once the last has arrived (and the firmware has enabled its receiver)
      if (this.rx.length && this.usart.writeByte(this.rx[0])) this.rx.shift();
      // a slice between two looks at the serial input: shorter than a byte at 115,200 baud
      const end = Math.min(cycle, cpu.cycles + 1000);
      const prog = cpu.progMem;
      while (cpu.cycles < end) {
        const op = prog[cpu.pc];
        avrInstruction(cpu);
        // The ATmega328P's datasheet (7.7, "Reset and Interrupt Handling"): after RETI, and
        // after SEI, the next instruction runs before any pending interrupt is served. avr8js
        // serves it at once: a level interrupt that stays pending (UDRE while the firmware
        // has nothing to send) would then starve the main program for ever.
        if (op === OP_RETI || op === OP_SEI) avrInstruction(cpu);
        cpu.tick();
      }
    }
  }

  /** The EEPROM's bytes now (settings the firmware saved), to keep across sessions. */
  eepromBytes() {
    return this.eepromBackend.memory.slice();
  }

  delete() {
    for (const d of this.decoders) d.delete();
  }
}
