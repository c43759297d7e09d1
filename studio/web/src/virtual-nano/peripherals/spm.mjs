// Self-programming (SPM), as the ATmega328P does it (datasheet 26, "Boot Loader Support"):
// avr8js has none. A bootloader fills a page buffer a word at a time, erases and writes
// pages of the flash; SPMEN reads 1 while an erase or a write runs, and the application
// section is busy (RWWSB) until RWWSRE. The lock bits a Nano ships with keep SPM off the boot
// section.
const SPMCSR = 0x57;
const SPMEN = 0x01, PGERS = 0x02, PGWRT = 0x04, BLBSET = 0x08, RWWSRE = 0x10, SIGRD = 0x20, RWWSB = 0x40;
const OPS = SPMEN | PGERS | PGWRT | BLBSET | RWWSRE | SIGRD;

export class SelfProgramming {
  /**
   * flash: the flash's bytes (the CPU runs them); pageBytes: a page; bootStart: the boot
   * section's first byte; busyCycles: how long an erase or a write takes (3.7-4.5 ms).
   */
  constructor(cpu, flash, { pageBytes, bootStart, busyCycles }) {
    this.cpu = cpu;
    this.flash = flash;
    this.pageBytes = pageBytes;
    this.bootStart = bootStart;
    this.busyCycles = busyCycles;
    this.pageBuffer = new Uint8Array(pageBytes).fill(0xff);
    this.busyUntil = 0;
    this.writes = 0; // pages written
    cpu.writeHooks[SPMCSR] = (value) => {
      cpu.data[SPMCSR] = (value & ~RWWSB) | (cpu.data[SPMCSR] & RWWSB); // RWWSB is the hardware's
      return true;
    };
    cpu.readHooks[SPMCSR] = () => cpu.data[SPMCSR] | (cpu.cycles < this.busyUntil ? SPMEN : 0);
  }

  /** One SPM instruction: the operation SPMCSR selects, on the page Z points at (R1:R0 the word to fill). */
  execute() {
    const cpu = this.cpu, d = cpu.data, P = this.pageBytes;
    const op = d[SPMCSR] & OPS;
    if (!(op & SPMEN) || cpu.cycles < this.busyUntil) return;
    const z = d[30] | (d[31] << 8);
    const page = z & ~(P - 1) & (this.flash.length - 1);
    const writable = page < this.bootStart;
    let busy = false;
    if (op === SPMEN) {
      this.pageBuffer[z & (P - 2)] = d[0];
      this.pageBuffer[(z & (P - 2)) + 1] = d[1];
    } else if (op === (SPMEN | PGERS)) {
      if (writable) this.flash.fill(0xff, page, page + P);
      busy = true;
    } else if (op === (SPMEN | PGWRT)) {
      if (writable) {
        // programming only clears bits: a page not erased first keeps its zeros
        for (let i = 0; i < P; i++) this.flash[page + i] &= this.pageBuffer[i];
        this.writes++;
      }
      this.pageBuffer.fill(0xff);
      busy = true;
    } else if (op === (SPMEN | RWWSRE)) {
      d[SPMCSR] &= ~RWWSB;
      this.pageBuffer.fill(0xff);
    }
    // (BLBSET and SIGRD, the lock bits and the signature row, are left alone.) The CPU goes
    // on (a bootloader polls SPMEN); the application section reads as it will be after.
    d[SPMCSR] &= ~OPS;
    if (busy) {
      this.busyUntil = cpu.cycles + this.busyCycles;
      d[SPMCSR] |= RWWSB; // the application section is busy until RWWSRE
    }
  }

  /** A reset: nothing being written, the page buffer empty. */
  reset() {
    this.busyUntil = 0;
    this.pageBuffer.fill(0xff);
  }
}
