// The Nano's USB serial line as its USART0 sees it, beside avr8js's AVRUSART: the host's bytes
// go over the wire at the host's baud rate (ten bit times each) into the chip's two-byte
// receive buffer, and what the firmware transmits comes out a byte and a line at a time. A
// baud rate other than the USART's (within the 5 % a receiver tolerates) garbles both ways.
import { usart0Config } from "avr8js";

const UCSR0A = usart0Config.UCSRA, UCSR0B = usart0Config.UCSRB, UDR0 = usart0Config.UDR;
const FE = 0x10, RXEN = 0x10;

/** A byte as a receiver set to another baud rate reads it: not the byte, and a framing error. */
const garble = (b) => (b * 0x9d + 0x5a) & 0xff;

export class HostSerial {
  constructor(cpu, usart, clockHz) {
    this.cpu = cpu;
    this.usart = usart;
    this.clockHz = clockHz;
    this.hostBaud = 115200; // the host's side of the line
    this.rx = []; // the host's bytes not yet on the wire
    this.rxBuffer = []; // received, unread: [0] is in UDR0 (RXC0 set); the chip holds two
    this.shifting = false; // a byte on the wire
    this.overruns = 0; // bytes lost to a full receive buffer (the chip's DOR0)
    this.onLine = null; // what the firmware sends, a line at a time
    this.onByte = null; // ... and a byte at a time
    this.lineBuffer = "";

    // On the chip UDRE is level state: an empty-buffer interrupt that writes nothing leaves it
    // set. avr8js clears it when the interrupt is taken; marked constant it stays, as on silicon
    // (otherwise, after one such call, the firmware never transmits again).
    usart.UDRE.constant = true;
    usart.onByteTransmit = (sent) => {
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
    const writeUcsrb = cpu.writeHooks[UCSR0B];
    cpu.writeHooks[UCSR0B] = (value, oldValue, addr, mask) => {
      const result = writeUcsrb(value, oldValue, addr, mask);
      if (!(value & RXEN)) this.rxBuffer = [];
      else if (this.rxBuffer.length) cpu.setInterruptFlag(usart.RXC);
      return result;
    };
  }

  /** Bytes (a string or numbers) from the host, in order. */
  send(data) {
    for (const b of typeof data === "string" ? new TextEncoder().encode(data) : data) this.rx.push(b);
  }

  /** Whether host bytes wait to go over the wire (they go between two runs of the CPU). */
  get waiting() {
    return this.rx.length > 0;
  }

  /** Starts the next waiting byte over the wire, unless one is on it. */
  pump() {
    if (this.rx.length && !this.shifting) this.shiftIn();
  }

  // A byte is on the wire for ten bit times of the host's baud rate; then it joins the buffer
  // if there is room (else it is lost, as on the chip) and the next one starts.
  shiftIn() {
    const cpu = this.cpu;
    const b = this.rx.shift();
    this.shifting = true;
    cpu.addClockEvent(() => {
      this.shifting = false;
      if (cpu.data[UCSR0B] & RXEN) {
        if (this.rxBuffer.length < 2) {
          this.rxBuffer.push(this.baudMatches() ? [b, 0] : [garble(b), FE]);
          if (this.rxBuffer.length === 1) this.toUdr();
        } else {
          this.overruns++;
        }
      }
      if (this.rx.length) this.shiftIn();
    }, Math.round((10 * this.clockHz) / this.hostBaud));
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

  /** A reset: the receive buffer empties, a byte on the wire is lost. */
  reset() {
    this.rxBuffer = [];
    this.shifting = false;
  }
}
