// The arm's serial line, below the session (link/arm-link.ts): bytes to lines, each line read by
// the core's parsers through the engine, and each reply matched to the line it answers. The arm
// answers every line once, in order, so a reply belongs to the oldest line unanswered; an `I`'s
// banner comes right before its reply. Waits count in the arm's own time (the virtual Nano's
// runs slow on a busy machine, or fast at the page's speed).
import { type SerialLike, deviceClock, sleepOn } from "./ports";

export type Parsed =
  | { kind: "reply"; code: number }
  // at_rest: nothing runs and nothing will until another line (Idle, or Alarm after a failed
  // homing): the core's state_at_rest, the rule the harness waits by too
  | { kind: "status"; state: string; at_rest: boolean; steps: number[]; angles: number[]; gripper: number; free: number; coils: boolean; warning: number }
  | { kind: "info"; version: string; protocol: number; joints: number; robot: string; checksum: number | null; warning: number }
  | { kind: "other" };

/** A line the arm sent, as the core read it, with the arm's pose when it is a status report. */
export type ReadLine = { parsed: Parsed; pose: { q: number[]; frames: number[][]; line: string } | null };

export const BAUD = 115200;
const BANNER_MS = 6000; // a Nano resets when its port opens: its bootloader waits first
export const REPLY_MS = 5000;

/** A line written to the arm, waiting for its reply (and an `I` for its banner first). */
interface Outstanding {
  line: string;
  banner: boolean; // an `I` whose banner has not come yet
  output: string[]; // what the arm printed for it before its reply (`$`'s settings, `I`'s banner)
  onBanner?: (p: Parsed & { line: string }) => void;
  onReply?: (p: Parsed & { line: string }) => void;
}

export class ArmLines {
  /** Lines in the engine's hands: while it reads one, the arm is not silent (it answered). */
  reading = 0;
  private port: SerialLike | null = null;
  private writer: WritableStreamDefaultWriter<Uint8Array> | null = null;
  private reader: ReadableStreamDefaultReader<Uint8Array> | null = null;
  // The lines written and not yet answered, oldest first. A waiter gone (timed out) leaves its
  // line here, so a late reply is still its own.
  private unanswered: Outstanding[] = [];
  // The last events of the line (kind: "sent", "line" (heard), "?", "lost"; the arm's clock, the
  // page's clock, a word), told with a lost link: what the page sent and heard and when, for
  // whoever finds out why. (The `?`s apart: a few hundred of them would hide the last lines heard.)
  private trace: [string, number, number, string][] = [];
  private polls: [string, number, number, string][] = [];

  /** read(line): the engine's reading; onStatus: a status report came; onGone: the port closed
   * or failed under the reader. */
  constructor(private readonly read: (line: string) => Promise<ReadLine>,
              private readonly onStatus: (p: Parsed & { kind: "status" }, pose: NonNullable<ReadLine["pose"]>, line: string) => void,
              private readonly onGone: (why: string) => void) {}

  /** Every line written to the arm and heard from it, as it goes (the arm panel's console);
   * `status`: a status report (the console's filter hides them). */
  onTraffic: ((dir: "sent" | "heard", line: string, status: boolean) => void) | null = null;

  /** The arm's time, ms: the virtual Nano's own clock, or the page's for a real port. */
  now: () => number = () => performance.now();

  // A reply's deadline counts the arm's time less the time the page spent reading what the arm
  // had sent: each line waits for the engine's worker, which a busy page keeps waiting, and a
  // reply behind a status report is the arm's answer the page has not yet heard. (On half a
  // core the virtual Nano's replies were given up 5 s of its time after the line while they
  // waited in the page: "no reply to 'P 500 0 100' within 5 s".) A silent arm times out as ever.
  private pausedMs = 0;
  private pausedFrom: number | null = null;
  /** The arm's time for waiting on an answer (the time the page spent reading left out). */
  readonly replyClock = (): number => (this.pausedFrom ?? this.now()) - this.pausedMs;

  get open(): boolean {
    return this.port !== null;
  }

  /** Opens the port (throws what the port says when it cannot) and starts reading it. */
  async openPort(port: SerialLike): Promise<void> {
    await port.open({ baudRate: BAUD });
    this.port = port;
    this.now = deviceClock(port);
    this.writer = port.writable!.getWriter();
    this.reader = port.readable!.getReader();
    void this.readLoop();
  }

  note(kind: string, what = ""): void {
    const events = kind === "?" ? this.polls : this.trace;
    events.push([kind, Math.round(this.now()), Math.round(performance.now()), what]);
    if (events.length > 32) events.shift();
  }

  /** The last events, in the page's order, taken (for a lost link's message). */
  takeTrace(): [string, number, number, string][] {
    return [...this.trace.splice(0), ...this.polls.splice(0)].sort((a, b) => a[2] - b[2]);
  }

  async write(text: string): Promise<void> {
    if (!this.writer) throw new Error("not connected");
    await this.writer.write(new TextEncoder().encode(text));
  }

  // `I` until the banner comes (the firmware may still be starting). An `I` asked again
  // while the first is unanswered is answered too: its banner and reply are its own.
  async banner(): Promise<Parsed & { line: string }> {
    const end = this.replyClock() + BANNER_MS;
    let resolve: (p: Parsed & { line: string }) => void = () => undefined;
    const got = new Promise<Parsed & { line: string }>((r) => (resolve = r));
    while (this.replyClock() < end) {
      await this.writeLine("I", { onBanner: resolve });
      let answered = false;
      const r = await Promise.race([got.then((p) => ((answered = true), p)), sleepOn(this.replyClock, 600, () => answered || !this.open).then(() => null)]);
      if (r) return r;
    }
    throw new Error(`no answer to I within ${BANNER_MS / 1000} s: is it a Nano with Articula's firmware, at ${BAUD} baud?`);
  }

  /** A line and its reply (ok or error:N), within `ms` of the arm's time. */
  async request(line: string, ms = REPLY_MS): Promise<string> {
    return (await this.exchange(line, ms)).reply;
  }

  /** A line, its reply, and every line the arm printed for it before the reply (the settings
   * `$` lists, the banner `I` sends), within `ms` of the arm's time. */
  async exchange(line: string, ms = REPLY_MS): Promise<{ reply: string; output: string[] }> {
    let resolve: (p: Parsed & { line: string }) => void = () => undefined;
    const got = new Promise<Parsed & { line: string }>((r) => (resolve = r));
    const entry = await this.writeLine(line, { onReply: resolve });
    let answered = false;
    const r = await Promise.race([got.then((p) => ((answered = true), p)), sleepOn(this.replyClock, ms, () => answered || !this.open).then(() => null)]);
    if (!r) {
      entry.onReply = undefined; // a late reply is still this line's
      if (!this.open) throw new Error(`the port closed before '${line}' was answered`);
      throw new Error(`no reply to '${line}' within ${(ms / 1000).toFixed(ms % 1000 ? 1 : 0)} s`);
    }
    return { reply: r.line, output: entry.output };
  }

  // A line to the arm, remembered until its reply comes.
  private async writeLine(line: string, waiter: Pick<Outstanding, "onBanner" | "onReply">): Promise<Outstanding> {
    const entry: Outstanding = { line, banner: /^I\s*(#.*)?$/.test(line), output: [], ...waiter };
    this.unanswered.push(entry);
    this.note("sent", line.slice(0, 24));
    this.onTraffic?.("sent", line, false);
    await this.write(line + "\n");
    return entry;
  }

  private async readLoop(): Promise<void> {
    let buf = "";
    const reader = this.reader!;
    try {
      for (;;) {
        const { value, done } = await reader.read();
        if (done) break;
        buf += new TextDecoder().decode(value);
        let nl: number;
        while ((nl = buf.indexOf("\n")) >= 0) {
          const line = buf.slice(0, nl).replace(/\r$/, "");
          buf = buf.slice(nl + 1);
          if (line) await this.onLine(line);
        }
      }
      this.onGone("the port closed");
    } catch (e) {
      this.onGone(`the port failed: ${(e as Error).message}`);
    }
  }

  private async onLine(line: string): Promise<void> {
    // The engine reads it in its worker, which a busy page can keep waiting: while it does, the
    // arm is not silent (it answered).
    this.note("line", line.slice(0, 24));
    if (this.reading++ === 0) this.pausedFrom = this.now();
    let got: ReadLine;
    try {
      got = await this.read(line);
    } finally {
      if (--this.reading === 0 && this.pausedFrom !== null) {
        this.pausedMs += Math.max(0, this.now() - this.pausedFrom);
        this.pausedFrom = null;
      }
    }
    const { parsed: p, pose } = got;
    this.onTraffic?.("heard", line, p.kind === "status");
    if (p.kind === "status" && pose) {
      this.onStatus(p, pose, line);
    } else if (p.kind === "info") {
      // The answer to the oldest `I` still waiting for its banner (the firmware sends a
      // banner only when asked: a banner is never a reset).
      const asked = this.unanswered.find((o) => o.banner);
      if (!asked) return;
      asked.banner = false;
      asked.output.push(line);
      const w = asked.onBanner;
      asked.onBanner = undefined;
      w?.({ ...p, line });
    } else if (p.kind === "reply") {
      // An `I` is answered by its banner first: one still waiting for its banner was lost
      // (sent while the Nano was starting), and this reply is a later line's.
      while (this.unanswered.length && this.unanswered[0].banner) this.unanswered.shift();
      const answered = this.unanswered.shift();
      answered?.onReply?.({ ...p, line });
    } else {
      // Anything else the arm prints (a setting of `$`'s list) belongs to the oldest line
      // unanswered that is not an `I` waiting for its banner (one that was lost while the Nano
      // started stays at the head until a reply clears it).
      this.unanswered.find((o) => !o.banner)?.output.push(line);
    }
  }

  /** Closes the port (a vanished one too); nothing is waited for any more. */
  async close(): Promise<void> {
    this.unanswered = [];
    const port = this.port;
    this.port = null;
    try {
      await this.reader?.cancel();
    } catch {
      /* already gone */
    }
    try {
      this.reader?.releaseLock();
      this.writer?.releaseLock();
    } catch {
      /* already gone */
    }
    this.reader = null;
    this.writer = null;
    try {
      await port?.close();
    } catch {
      /* a vanished port cannot be closed */
    }
  }
}
