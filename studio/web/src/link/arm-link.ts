// The arm in the loop, in the page: a Nano on a Web Serial port or the virtual Nano (both a
// SerialLike, link/ports.ts), spoken to in the arm's protocol (docs/protocol.md): the `I` banner's
// configuration checksum checked against the robot shown (an arm configured for another robot
// is never driven: it can be configured for this one), `?` reports 15 times a second, one line at a time with
// its reply, programs with the harness's flow control, `!` at once. Lines from the arm are
// read by the core's parsers through the engine (`parseArmLine`), and the arm's pose and the
// model's prediction come from the engine too: nothing here computes kinematics.
//
// It speaks to the page in messages (engine/messages.ts: arm, arm_status, arm_reply, arm_program,
// arm_stopped), as the engine's worker does.
//
// Below it, link/arm-lines.ts: the serial line, its lines read and each reply matched to its line.
import type { NanoConfig } from "../engine/messages";
import { ArmLines, type Parsed, REPLY_MS, type ReadLine } from "./arm-lines";
import { type SerialLike, sleepOn } from "./ports";

/** What the arm needs of the engine (the worker): a line from the arm read by the core's
 * parsers, with the arm's pose when it is a status report (one round trip); the model's
 * prediction of a line; what a reply means (the core's status table, held by the page). */
export interface ArmEngine {
  read(line: string): Promise<ReadLine>;
  /** command: the line as the arm acts on it (the core's comment rule), "" for a comment alone. */
  predict(history: string[], line: string): Promise<{ command: string; reply: string; steps: number[] | null; meaning: string; seconds?: number }>;
  meaning(reply: string): string;
  /** The reply a status gives by its name in the core's table ("UnknownCommand" -> "error:2"). */
  reply(name: string): string;
  /** The robot shown as a Nano's configuration, or why a Nano cannot drive it. */
  config(): Promise<NanoConfig | { error: string }>;
}

const POLL_MS = 1000 / 15; // status polls (every 10 ms for a second after a stop)
const SILENT_MS = 1500; // no report for this long: the arm stopped answering
const GRACE_MS = 500; // ... and still none this much later by the page's clock
export class ArmLink {
  label = "";
  connected = false;
  /** The port is open and the Nano configured for another robot: nothing is driven until
   * configure() makes it this one. */
  configurable = false;
  private portLabel = "";
  private lines: ArmLines;
  private queue: Promise<unknown> = Promise.resolve();
  // the arm's time: waits for its answers count in it (the virtual Nano's runs slow on a busy machine)
  private now = () => this.lines.now();
  private pollTimer: ReturnType<typeof setTimeout> | null = null;
  // The arm's time of the oldest `?` no report has answered yet (null: none). Silence is a `?`
  // unanswered: a page too busy to ask for reports (its poll late) does not make the arm silent.
  private askedAt: number | null = null;
  private silentSince: number | null = null; // the page's time silence was first seen
  private lastAsk = -Infinity; // the arm's time of the last `?`
  private lastPoll = 0;
  private fastUntil = 0;
  // A line's predicted end, in the arm's time: `?` at 100 Hz around it, so its end is heard at once
  private fastArm: [number, number] = [0, 0];
  // Status reports read so far; the last that said at rest; the count when the last reply came.
  // A report read after a line's `ok` was written after the line was queued (the arm answers in
  // order): one that says at rest means the line has ended.
  private reportSeq = 0;
  private restSeq = 0;
  private okSeq = 0;
  private history: string[] = []; // the lines the arm accepted, for the prediction
  private stopSentAt = 0;
  private idleWaiters: (() => void)[] = [];
  private statusWaiters: ((line: string) => void)[] = []; // a typed `?`: the next report's text
  private state = "";
  private lastSteps: number[] = []; // the last status report's
  private programRunning = false;
  private programStop = false;

  constructor(private engine: ArmEngine, private emit: (m: Record<string, unknown>) => void) {
    this.lines = new ArmLines((line) => engine.read(line), (p, pose, line) => this.onStatus(p, pose, line), (why) => this.lost(why));
    this.lines.onTraffic = (dir, line, status) => this.emit({ type: "arm_console", dir, line, status });
  }

  /** Opens the port, checks the banner names `robot`, starts the reports. */
  async connect(port: SerialLike, portLabel: string, robot: string): Promise<void> {
    this.emit({ type: "arm", connected: false, connecting: true, port: portLabel });
    try {
      await this.lines.openPort(port);
    } catch (e) {
      this.emit({ type: "arm", connected: false, port: portLabel, error: `cannot open ${portLabel}: ${(e as Error).message}` });
      return;
    }
    let info: Parsed & { line: string };
    try {
      info = await this.lines.banner();
    } catch (e) {
      await this.close();
      this.emit({ type: "arm", connected: false, port: portLabel, error: (e as Error).message });
      return;
    }
    this.portLabel = portLabel;
    await this.admit(info, robot);
  }

  // The arm driven when its banner says it is `robot`; else the port kept for configuring (or
  // closed when configuring cannot help), and the panel told why.
  private async admit(info: Parsed, robot: string): Promise<void> {
    const why = await this.mismatch(info, robot);
    if (!why) return this.start(info as Parsed & { kind: "info" }, this.portLabel);
    this.configurable = why.configurable;
    if (!why.configurable) await this.close();
    this.emit({ type: "arm", connected: false, port: this.portLabel, error: why.text, configurable: why.configurable });
  }

  // Why this arm is not the robot shown ("" when it is), and whether configuring would make it
  // so. A firmware before protocol 4 has no checksum: its name must be the robot's.
  private async mismatch(info: Parsed, robot: string): Promise<{ text: string; configurable: boolean } | null> {
    if (info.kind !== "info") return { text: "no banner", configurable: false };
    if (info.checksum === null) {
      return info.robot === robot ? null : { configurable: false,
        text: `the arm is a ${info.robot} (its firmware is older than protocol 4, so it cannot be configured): ` +
          `load that robot, or flash this site's firmware first` };
    }
    const expected = await this.engine.config();
    if ("error" in expected)
      return { configurable: false, text: `a Nano cannot drive the robot shown: ${expected.error}` };
    if (info.checksum === expected.checksum) return null;
    return { configurable: true,
      text: `The Nano is configured for the ${info.robot}; the studio shows the ${robot}. ` +
        "It is not driven until you configure it for this robot (or load its robot)." };
  }

  private start(info: Parsed & { kind: "info" }, portLabel: string): void {
    this.configurable = false;
    this.connected = true;
    this.silentSince = null;
    this.label = `${info.robot} (firmware ${info.version})`;
    this.history = [];
    this.askedAt = null;
    this.emit({ type: "arm", connected: true, port: portLabel, label: this.label,
      info: { version: info.version, protocol: String(info.protocol), robot: info.robot, checksum: info.checksum } });
    this.poll();
  }

  /** The robot shown changed: the arm is driven no more until its banner, asked again, says
   * it is this robot's (or the panel says why not, and offers to configure it). */
  recheck(robot: string): Promise<void> {
    return this.serial(async () => {
      if (!this.lines.open || (!this.connected && !this.configurable)) return;
      if (this.connected) {
        this.connected = false; // no polls and no lines meanwhile: its banner is not this robot's yet
        this.configurable = true;
        if (this.pollTimer !== null) clearTimeout(this.pollTimer);
        this.pollTimer = null;
      }
      let info: Parsed & { line: string };
      try {
        info = await this.lines.banner();
      } catch (e) {
        this.emit({ type: "arm", connected: false, port: this.portLabel, configurable: true, error: (e as Error).message });
        return;
      }
      await this.admit(info, robot);
    });
  }

  /** Writes the robot shown into the Nano's configuration (stopping the arm first), then
   * checks the banner: on the same checksum the arm is driven as this robot. */
  configure(): Promise<void> {
    return this.serial(async () => {
      if (!this.lines.open) throw new Error("no arm: Connect first");
      const label = this.portLabel || "the arm";
      const config = await this.engine.config();
      if ("error" in config) {
        this.emit({ type: "arm", connected: this.connected, port: label, error: `a Nano cannot drive the robot shown: ${config.error}` });
        return;
      }
      if (this.connected) {
        await this.lines.write("!"); // whatever it was doing: it becomes another arm
        this.connected = false;
        if (this.pollTimer !== null) clearTimeout(this.pollTimer);
        this.pollTimer = null;
      }
      this.configurable = true;
      for (let k = 0; k < config.lines.length; k++) {
        const line = config.lines[k];
        this.emit({ type: "arm", connected: false, port: label, configuring: { done: k, total: config.lines.length, name: config.name } });
        let reply: string;
        try {
          reply = await this.lines.request(line);
        } catch (e) {
          this.emit({ type: "arm", connected: false, port: label, configurable: true, error: `configuring stopped: ${(e as Error).message}` });
          return;
        }
        if (reply !== "ok") {
          this.emit({ type: "arm", connected: false, port: label, configurable: true, error: `the Nano refused ${line}: ` +
            `${reply} (${this.engine.meaning(reply)})${reply === this.engine.reply("UnknownCommand") ? ": flash this site's firmware first" : ""}` });
          return;
        }
      }
      let info: Parsed & { line: string };
      try {
        info = await this.lines.banner();
      } catch (e) {
        this.emit({ type: "arm", connected: false, port: label, configurable: true, error: (e as Error).message });
        return;
      }
      if (info.kind !== "info" || info.checksum !== config.checksum) {
        this.emit({ type: "arm", connected: false, port: label, configurable: true,
          error: `the Nano's banner says checksum ${info.kind === "info" ? info.checksum : "?"}, not ${config.checksum}: the configuration did not take` });
        return;
      }
      this.emit({ type: "arm_configured", name: config.name, checksum: config.checksum });
      this.start(info, label);
    });
  }

  // A status report: the arm's state and pose, to the page; an arm at rest ends the waits for it.
  private onStatus(p: Parsed & { kind: "status" }, pose: NonNullable<ReadLine["pose"]>, line: string): void {
    this.askedAt = null; // (every `?` before it is answered)
    this.state = p.state;
    this.lastSteps = p.steps;
    this.reportSeq++;
    if (p.at_rest) this.restSeq = this.reportSeq;
    if (p.warning !== 0 && `error:${p.warning}` === this.engine.reply("SettingsReset")) return this.lost("the arm reset (its settings were reset to their defaults)");
    const msg: Record<string, unknown> = { type: "arm_status", state: p.state, steps: p.steps, angles: p.angles,
      q: pose.q, frames: pose.frames, text: line, rtt_ms: performance.now() - this.lastPoll,
      sent_ms: performance.timeOrigin + performance.now() };
    if (this.stopSentAt && p.at_rest) {
      msg.stop_to_idle_ms = performance.now() - this.stopSentAt;
      this.stopSentAt = 0;
      // After a stop the commanded angles are those of the steps reached.
      this.history = [pose.line];
    }
    if (p.at_rest) for (const w of this.idleWaiters.splice(0)) w();
    for (const w of this.statusWaiters.splice(0)) w(line);
    this.emit(msg);
  }

  // `?` at 15 Hz (100 Hz for a second after a stop); a `?` unanswered for 1.5 s is a lost arm.
  private poll(): void {
    if (!this.connected) return;
    const now = performance.now();
    // Silence is judged twice, half a second of the page's time apart: a page stalled by a
    // busy machine has the arm's answers still in its queue when it wakes (a report in the
    // engine's hands is not silence either: the arm answered).
    if (this.askedAt !== null && this.now() - this.askedAt > SILENT_MS && this.lines.reading === 0) {
      if (this.silentSince === null) this.silentSince = now;
      else if (now - this.silentSince > GRACE_MS) return this.lost(`no status report for ${SILENT_MS / 1000} s`);
    } else {
      this.silentSince = null;
    }
    // At 15 Hz of the arm's time: a virtual Nano starved by a busy machine runs slower than the
    // page, and a `?` every 67 ms of the page's time would be hundreds a second of its own.
    // (After a stop, every 10 ms of the page's: the stop's end is timed by the page.)
    const armNow = this.now();
    const fast = now < this.fastUntil || (armNow >= this.fastArm[0] && armNow < this.fastArm[1]);
    if (fast || armNow - this.lastAsk >= POLL_MS / 2) {
      this.lastPoll = now;
      this.lastAsk = armNow;
      this.lines.note("?", String(this.lines.reading));
      if (this.askedAt === null) this.askedAt = this.now();
      this.lines.write("?").catch((e) => this.lost(`cannot write: ${(e as Error).message}`));
    }
    this.pollTimer = setTimeout(() => this.poll(), fast ? 10 : POLL_MS);
  }

  private lost(why: string): void {
    if (!this.connected && !this.configurable) return;
    this.connected = false;
    this.configurable = false;
    this.programStop = true;
    this.resume(); // (a program paused at a breakpoint ends)
    this.lines.note("lost", why);
    const trace = this.lines.takeTrace();
    this.emit({ type: "arm", connected: false, error: why, lost: true, trace });
    this.close();
  }

  /** One protocol line, its reply; the model's prediction beside it. */
  send(line: string): Promise<void> {
    return this.serial(async () => {
      if (line.trim() === "?") return this.sendQuestion();
      const predicted = await this.engine.predict(this.history, line);
      const got = await this.command(line, predicted.seconds ?? 0, true).catch((e) => {
        this.emit({ type: "arm_reply", line, reply: null, error: (e as Error).message, predicted });
        return null;
      });
      if (got === null) return;
      const { reply, output } = got;
      this.emit({ type: "arm_reply", line, reply, meaning: this.engine.meaning(reply), predicted, output });
    });
  }

  // A `?` typed: the realtime byte alone (a `?` with a line's end would be a second, empty line:
  // error:1), answered by the next status report, which the page shows as the arm's answer.
  private async sendQuestion(): Promise<void> {
    const predicted = { reply: "status", steps: null, meaning: "a status report, not a reply", seconds: 0 };
    if (!this.connected) {
      this.emit({ type: "arm_reply", line: "?", reply: null, error: "no arm connected: Connect first", predicted });
      return;
    }
    let waiter: (line: string) => void = () => undefined;
    const report = new Promise<string | null>((resolve) => {
      waiter = resolve;
      this.statusWaiters.push(waiter);
      void sleepOn(this.lines.replyClock, REPLY_MS, () => !this.statusWaiters.includes(waiter) || !this.connected).then(() => resolve(null));
    });
    this.lines.write("?").catch((e) => this.lost(`cannot write: ${(e as Error).message}`));
    const text = await report;
    this.statusWaiters = this.statusWaiters.filter((w) => w !== waiter);
    if (text === null) this.emit({ type: "arm_reply", line: "?", reply: null, error: `no status report within ${REPLY_MS / 1000} s`, predicted });
    else this.emit({ type: "arm_reply", line: "?", reply: "status", meaning: "the arm's status report", predicted, output: [text] });
  }

  private serial<T>(f: () => Promise<T>): Promise<T> {
    const next = this.queue.then(f, f);
    this.queue = next.catch(() => undefined);
    return next;
  }

  // `seconds`: the line's predicted duration. A queued line is answered once it has a place,
  // and a straight line (T) once its last segment has one: a line answered late waits that
  // much longer for its reply.
  private async command(line: string, seconds?: number): Promise<string>;
  private async command(line: string, seconds: number, withOutput: true): Promise<{ reply: string; output: string[] }>;
  private async command(line: string, seconds = 0, withOutput = false): Promise<string | { reply: string; output: string[] }> {
    if (!this.connected) throw new Error("no arm connected: Connect first");
    if (line.trim() === "!") {
      // A program's stop: the byte alone, no LF, and no reply to wait for (docs/protocol.md);
      // the next line is held by the arm until it is at rest.
      await this.lines.write("!");
      return withOutput ? { reply: "ok", output: [] } : "ok";
    }
    const got = await this.lines.exchange(line, REPLY_MS + seconds * 1000);
    this.okSeq = this.reportSeq;
    if (got.reply === "ok") {
      this.history.push(line);
      // heard at once when it ends: `?` at 100 Hz from 50 ms before its predicted end to 400 ms after
      const end = this.now() + seconds * 1000;
      this.fastArm = [end - 50, end + 400];
      if (this.pollTimer !== null && this.connected) { // (the poll's next look: in 10 ms, not 67)
        clearTimeout(this.pollTimer);
        this.pollTimer = setTimeout(() => this.poll(), 10);
      }
    }
    return withOutput ? got : got.reply;
  }

  /** One line for the Experiment panel: its reply beside the model's, then (accepted) the arm
   * at rest; the steps it reports there. Throws when the arm is gone or does not come to rest. */
  runLine(line: string): Promise<{ reply: string; predicted: { reply: string; steps: number[] | null }; steps: number[] }> {
    return this.serial(async () => {
      this.programStop = false; // a STOP from now on ends the wait (and the caller's run)
      const predicted = await this.engine.predict(this.history, line);
      const reply = await this.command(line, predicted.seconds ?? 0);
      this.emit({ type: "arm_reply", line, reply, meaning: this.engine.meaning(reply), predicted });
      if (reply === "ok") await this.idle((3 * (predicted.seconds ?? 0) + 5) * 1000, 0);
      return { reply, predicted, steps: [...this.lastSteps] };
    });
  }

  /** A protocol program, line by line: a line, its reply, then `?` until at rest (Idle or Alarm). */
  // A program's debugging on the arm: the line numbers it pauses after (at rest), and the
  // pause itself (resume() or step() ends it; a STOP too).
  private breaks = new Set<number>();
  private stepping = false;
  private resumeWaiter: (() => void) | null = null;
  /** Where the program waits (0: it does not). */
  pausedAt = 0;

  /** The breakpoints, changed while a program runs too. */
  setBreaks(lines: Iterable<number>): void {
    this.breaks = new Set(lines);
  }
  /** Pause after the line that is running (at rest), as a breakpoint would. */
  pauseAfterLine(): void {
    if (this.programRunning) this.stepping = true;
  }
  /** Go on from a pause: to the next breakpoint (step: one line). */
  resume(step = false): void {
    this.stepping = step;
    const w = this.resumeWaiter;
    this.resumeWaiter = null;
    w?.();
  }

  runProgram(text: string, breaks: Iterable<number> = []): void {
    this.setBreaks(breaks);
    this.stepping = false;
    if (this.programRunning) {
      this.emit({ type: "error", message: "the arm is already running a program: stop it first" });
      return;
    }
    this.programRunning = true;
    this.programStop = false;
    this.serial(async () => {
      let sent = 0;
      const t0 = this.now(); // the arm's clock (the virtual Nano's own): how long the program took on it
      let paused = 0; // ... less the time it waited at breakpoints
      try {
        const lines = text.split("\n");
        // The next line's prediction is worked out while this one runs (the engine replays every
        // line the arm accepted: on a long drawing that is tens of ms a line the arm would wait),
        // after the lines the arm had accepted then: used if the arm has accepted none since.
        type Predicted = Awaited<ReturnType<ArmEngine["predict"]>>;
        let ahead: { n: number; accepted: number; p: Promise<Predicted> } | null = null;
        // each line's number, and the next line with something on it (0: none)
        const next: number[] = new Array(lines.length + 1).fill(0);
        for (let n = lines.length - 1; n >= 1; n--) next[n] = lines[n].trim() ? n + 1 : next[n + 1];
        for (let n = 1; n <= lines.length; n++) {
          if (!lines[n - 1].trim()) continue;
          if (this.programStop) {
            this.emit({ type: "arm_program", done: true, stopped: true, sent });
            return;
          }
          const predicted = ahead && ahead.n === n && ahead.accepted === this.history.length ? await ahead.p
            : await this.engine.predict(this.history, lines[n - 1]);
          ahead = null;
          const line = predicted.command; // (a comment alone is none)
          if (!line) continue;
          const reply = await this.command(line, predicted.seconds ?? 0);
          sent++;
          const after = next[n];
          if (after) {
            const p = this.engine.predict([...this.history], lines[after - 1]);
            p.catch(() => undefined); // (not used after a STOP: its failure is nobody's)
            ahead = { n: after, accepted: this.history.length, p };
          }
          this.emit({ type: "arm_program", line: n, command: line, reply, meaning: this.engine.meaning(reply), predicted });
          if (reply === "ok") {
            const limit = 3 * (predicted.seconds ?? 0) + 5;
            await this.idle(limit * 1000, n);
          }
          // a breakpoint, or a step or a pause asked for: here, at rest after the line, until told
          if ((this.breaks.has(n) || this.stepping) && !this.programStop && next[n]) {
            this.pausedAt = n;
            this.emit({ type: "arm_program", paused: true, line: n });
            const p0 = this.now();
            await new Promise<void>((resolve) => (this.resumeWaiter = resolve));
            paused += this.now() - p0;
            this.pausedAt = 0;
            this.emit({ type: "arm_program", resumed: true, line: n });
          }
        }
        this.emit({ type: "arm_program", done: true, sent, seconds: (this.now() - t0 - paused) / 1000 });
      } catch (e) {
        this.emit({ type: "arm_program", done: true, sent, error: (e as Error).message });
      } finally {
        this.programRunning = false;
      }
    });
  }

  // Until the arm reports it is at rest (a report read after the line's `ok`: one read before it may
  // say Idle from before the line was queued), a STOP, the link lost, or `ms` of the arm's time.
  // Looked at every 100 ms of the page's time as well as at each report: a link lost or an arm
  // that stopped reporting ends the wait (and the program) instead of leaving it waiting.
  private idle(ms: number, line: number): Promise<void> {
    return new Promise((resolve, reject) => {
      const start = this.now();
      let over = false;
      const end = (f: () => void) => {
        if (over) return;
        over = true;
        clearInterval(tick);
        f();
      };
      const check = () => {
        if (!this.connected) return end(() => reject(new Error(`line ${line}: the arm is gone`)));
        if (this.programStop) return end(resolve);
        if (this.now() - start > ms) end(() => reject(new Error(`line ${line}: the arm did not come to rest within ${Math.round(ms / 1000)} s`)));
      };
      const tick = setInterval(check, 100);
      check();
      if (over) return;
      if (this.restSeq > this.okSeq) return end(resolve); // (already heard, since the reply)
      this.idleWaiters.push(() => end(resolve));
    });
  }

  /** A program is being sent to the arm. */
  get running(): boolean {
    return this.programRunning;
  }

  /** The arm at rest (its last report said so). */
  get atRest(): boolean {
    return this.state === "Idle";
  }

  /** A held jog let go: the realtime `!` (the arm decelerates along its path to rest and its
   * queue is emptied), without a STOP's messages. */
  async halt(): Promise<void> {
    if (!this.connected) return;
    this.stopSentAt = performance.now();
    this.fastUntil = this.stopSentAt + 1000;
    this.lines.onTraffic?.("sent", "! (the jog let go)", false);
    await this.lines.write("!").catch((e) => this.lost(`cannot write: ${(e as Error).message}`));
  }

  /** STOP: the realtime `!` now, ahead of anything queued; no further program line. */
  async stop(): Promise<void> {
    if (!this.connected) return;
    if (this.programRunning) {
      this.programStop = true;
      this.resume(); // (a program paused at a breakpoint ends)
      this.emit({ type: "arm_program", done: true, stopped: true });
    }
    this.stopSentAt = performance.now();
    this.fastUntil = this.stopSentAt + 1000;
    this.lines.onTraffic?.("sent", "! (stop)", false);
    await this.lines.write("!").catch((e) => this.lost(`cannot write: ${(e as Error).message}`));
    this.emit({ type: "arm_stopped" });
  }

  async disconnect(): Promise<void> {
    const was = this.connected || this.configurable;
    this.connected = false;
    this.configurable = false;
    this.programStop = true;
    this.resume(); // (a program paused at a breakpoint ends)
    await this.close();
    if (was) this.emit({ type: "arm", connected: false });
  }

  private async close(): Promise<void> {
    if (this.pollTimer !== null) clearTimeout(this.pollTimer);
    this.pollTimer = null;
    await this.lines.close();
  }
}

