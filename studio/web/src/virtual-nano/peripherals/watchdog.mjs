// The ATmega328P's watchdog as the Nano's bootloader needs it: avr8js's AVRWatchdog, with a
// new timeout counting at once (avr8js looks at it only when the old one's check comes round:
// Optiboot, which shortens it to 16 ms to reset into the application, waited up to the old
// second), and its system reset handed to the Nano (onReset) instead of avr8js's cpu.reset(),
// which leaves the I/O registers as they were and starts at 0.
import { AVRWatchdog, watchdogConfig } from "avr8js";

const WDTCSR = watchdogConfig.WDTCSR;
const WDE = 0x08, WDIE = 0x40;

export class NanoWatchdog extends AVRWatchdog {
  /** onReset(): the watchdog's system reset is due (the Nano resets after the instruction). */
  constructor(cpu, clockHz, onReset) {
    super(cpu, watchdogConfig, { frequency: clockHz });
    const write = cpu.writeHooks[WDTCSR];
    cpu.writeHooks[WDTCSR] = (value, oldValue, addr, mask) => {
      const result = write(value, oldValue, addr, mask);
      if (this.enabled) this.reschedule();
      return result;
    };
    // avr8js's check, but for the reset: the Nano's (onReset), with MCUSR's cause set there
    this.checkWatchdog = () => {
      if (this.enabled && cpu.cycles >= this.watchdogTimeout) {
        const wdtcsr = cpu.data[WDTCSR];
        if (wdtcsr & WDIE) cpu.setInterruptFlag(this.Watchdog);
        if (wdtcsr & WDE) {
          if (wdtcsr & WDIE) {
            cpu.data[WDTCSR] &= ~WDIE; // interrupt first, the reset at the next time-out
          } else {
            this.scheduled = false;
            onReset();
            return;
          }
        }
        this.resetWatchdog();
      }
      this.scheduled = this.enabled;
      if (this.enabled) cpu.addClockEvent(this.checkWatchdog, this.watchdogTimeout - cpu.cycles);
    };
  }

  // The check at the timeout as it is now.
  reschedule() {
    this.cpu.clearClockEvent(this.checkWatchdog);
    this.cpu.addClockEvent(this.checkWatchdog, Math.max(0, this.watchdogTimeout - this.cpu.cycles));
    this.scheduled = true;
  }

  /** A reset's watchdog: off, or after a watchdog reset on (WDE with WDRF set) at its shortest time. */
  reset(byWatchdog) {
    this.scheduled = false;
    this.enabledValue = false;
    this.changeEnabledCycles = 0;
    if (byWatchdog) {
      this.cpu.data[WDTCSR] = WDE;
      this.enabledValue = true;
      this.resetWatchdog();
      this.reschedule();
    }
  }
}
