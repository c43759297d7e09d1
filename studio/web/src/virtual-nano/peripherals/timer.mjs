// avr8js's AVRTimer, able to say when it next sets a flag: what lets the Nano's sleep skip
// ahead to the next compare match or overflow instead of counting every tick.
import { AVRTimer } from "avr8js";

export class NanoTimer extends AVRTimer {
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
