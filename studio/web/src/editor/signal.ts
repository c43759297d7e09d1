// A signal: listeners called with a value when something changes (three.js's editor uses
// signals.js for the same: panels listen, they do not call each other).
export class Signal<T = void> {
  private listeners: ((value: T) => void)[] = [];

  /** Calls `f` on every dispatch; returns a function that stops it. */
  add(f: (value: T) => void): () => void {
    this.listeners.push(f);
    return () => (this.listeners = this.listeners.filter((g) => g !== f));
  }

  dispatch(value: T): void {
    for (const f of [...this.listeners]) f(value);
  }
}
