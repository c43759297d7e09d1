// avr8js's AVRTimer, able to say when it next sets a flag: what lets the Nano's sleep skip
// ahead to the next compare match or overflow instead of counting every tick. And it counts
// only then: avr8js's count event comes at every tick of the prescaler (every 8 cycles for the
// stepper's Timer1, a sixth of the emulator's time), this one at the next flag, counting all
// the ticks since at once, as avr8js's count() does after the Nano slept. A write that moves
// the next flag (a compare value, the count, the mode, the top) first counts the ticks up to
// it, as avr8js had, then the event moves: every flag, so every interrupt, comes at the cycle
// it did.
import { AVRTimer } from "avr8js";

export class NanoTimer extends AVRTimer {
  constructor(cpu, config) {
    super(cpu, config);
    const tick = this.count;
    this.count = (reschedule = true, external = false) => {
      const divided = this.updateDivider; // (then avr8js's count sets the new prescaler and its event)
      tick(false, external);
      if (reschedule && !divided && this.divider) this.schedule();
    };
    if (cpu.clearClockEvent(tick)) cpu.addClockEvent(this.count, 0);
    const writes = [config.OCRA, config.OCRB, config.TCNT, config.TCCRA, config.TCCRB];
    if (config.bits === 16) writes.push(config.ICR);
    for (const addr of writes) {
      const hook = cpu.writeHooks[addr];
      cpu.writeHooks[addr] = (value, old, a, mask) => {
        this.count(false); // the ticks so far, against the compare values they met
        const r = hook(value, old, a, mask);
        // (a new prescaler or a written count: avr8js's own event applies it at once)
        if (this.divider && !this.updateDivider && !this.tcntUpdated) {
          cpu.clearClockEvent(this.count);
          this.schedule();
        }
        return r;
      };
    }
  }

  /** The count event at the next flag (or the next tick while a written count waits). */
  schedule() {
    const next = this.nextFlagCycle();
    const at = next === null ? this.lastCycle + this.divider : next;
    this.cpu.addClockEvent(this.count, Math.max(0, at - this.cpu.cycles));
  }

  /**
   * The first cycle at which it sets a flag: its next compare match (A or B) or its wrap at
   * TOP, from its count and prescaler; Infinity when stopped. null when a change is pending
   * that only its own count event applies (a new prescaler or a written count), or in a
   * phase-correct mode.
   */
  nextFlagCycle() {
    if (!this.divider) return Infinity;
    if (this.updateDivider || this.tcntUpdated || this.timerMode === 1 || this.timerMode === 4) return null; // (PWMPhaseCorrect, PWMPhaseFrequencyCorrect)
    const top = this.TOP, val = this.tcnt;
    const ticksTo = (x) => (x > val ? x - val : x + top + 1 - val);
    let ticks = top + 1 - val; // the wrap
    for (const ocr of [this.ocrA, this.ocrB]) if (ocr <= top) ticks = Math.min(ticks, ticksTo(ocr));
    return this.lastCycle + ticks * this.divider;
  }
}
