// Real time for the two loops that run a model against the wall clock: the live physics (the
// engine's worker, engine/physics.ts) and the virtual Nano (virtual-nano/worker.ts). One meter of
// simulated time against wall time, and one timer that keeps a period without drifting.

/** Simulated (or emulated) seconds against wall seconds over the last `size` slices: `rtf`
 * (1.0 keeps real time) and `capacity` (how many times real time the work alone could run). */
export class RealTimeMeter {
  private window: [number, number, number][] = []; // (wall s, simulated s, working s) per slice
  private last = performance.now();

  constructor(private readonly size: number) {}

  /** One slice ended now: it simulated `simulated` s in `busy` s of work. Returns the wall
   * seconds since the slice before. */
  slice(simulated: number, busy: number): number {
    const now = performance.now();
    const wall = (now - this.last) / 1000;
    this.last = now;
    this.window.push([wall, simulated, busy]);
    if (this.window.length > this.size) this.window.shift();
    return wall;
  }

  get slices(): number { return this.window.length; }
  get rtf(): number {
    const w = this.sum(0);
    return w > 0 ? this.sum(1) / w : 1;
  }
  get capacity(): number | null {
    const b = this.sum(2);
    return b > 0 ? this.sum(1) / b : null;
  }

  private sum(k: number): number {
    return this.window.reduce((a, x) => a + x[k], 0);
  }
}

/** Calls `tick` every `periodMs` on the wall clock's schedule (a late tick shortens the next
 * wait, never by more than a period) until it returns false or `stop()`. */
export function every(periodMs: number, tick: () => boolean | void): { stop(): void } {
  let timer: ReturnType<typeof setTimeout> | null = null;
  let due = performance.now();
  let stopped = false;
  const run = () => {
    timer = null;
    if (stopped || tick() === false) return;
    due = Math.max(due + periodMs, performance.now() - periodMs);
    timer = setTimeout(run, Math.max(0, due - performance.now()));
  };
  timer = setTimeout(run, 0);
  return {
    stop() {
      stopped = true;
      if (timer !== null) clearTimeout(timer);
      timer = null;
    },
  };
}
