// The engine, as the page sees it: the Web Worker (engine/worker.ts: the C++ core, host library and
// ODE in WebAssembly) that computes every pose, solve, prediction and physics step. The page
// posts intents and handles what comes back; a request with an `id` gets its own answer.
import type { EngineMsg } from "../engine/messages";

type Msg = Record<string, unknown>;

/** A pen setting of a drawing (host/lib/draw.h kPenFields): its key, default and range. */
export interface PenField { key: string; default: number; min: number; max: number; min_excluded: boolean; unit: string; what: string }

// Pose requests (sliders, drags): at most two in flight, so one is computed while the page
// draws the other. What waits goes in the order the student made it: a new intent replaces
// only the one waiting last, and only when it is of the same thing (the same joint's box or
// slider, the IK target), so that a drag sends its newest position and no other edit is lost.
// Every other message waits behind them, so nothing overtakes an edit made before it.
const MAX_IN_FLIGHT = 2;

/** What an intent edits: intents with the same key replace one another while they wait. */
function keyOf(msg: Msg): string {
  return msg.joint === undefined ? String(msg.type) : `${String(msg.type)}:${String(msg.joint)}`;
}

export class EngineClient {
  ready = false;
  /** The protocol's status table (shared/articula/status.h), from the engine: code -> text. */
  statusTable: Record<string, [string, string]> = {};
  /** What it has said: messages in all, and while `streaming()` (the physics runs); the
   * worker's time from its first message to the robot loaded, ms. Read by the hook. */
  messages = 0;
  streamMessages = 0;
  startMs = 0;
  streaming: () => boolean = () => false;
  /** The pen's settings (host/lib/draw.h), from the engine. */
  penFields: PenField[] = [];
  onMessage: (m: EngineMsg) => void = () => undefined;
  onReady: () => void = () => undefined;
  onFatal: (message: string) => void = () => undefined;
  private worker: Worker;
  private seq = 0;
  private sentAt = new Map<number, number>();
  private drawnSeqs: number[] = [];
  private inFlight = 0;
  /** Waiting to go, in order: `counted` ones are requests (their reply frees a place in flight). */
  private waitingToGo: { msg: Msg; counted: boolean; at: number }[] = [];
  /** Per key (keyOf), the seq of the newest request; and the newest seq the engine answered. */
  private lastSeq = new Map<string, number>();
  private answeredSeq = 0;
  private callId = 0;
  private calls = new Map<number, { resolve: (m: Msg) => void; reject: (e: Error) => void; type: string; at: number }>();

  constructor() {
    this.worker = new Worker(new URL("assets/worker.js", document.baseURI), { type: "module" });
    this.worker.onmessage = (e) => this.receive(e.data as EngineMsg | { type: "ready"; ms: number; status_table: Record<string, [string, string]>; pen_fields: PenField[] } | { type: "fatal"; message: string });
    this.worker.onerror = (e) => this.onFatal(`The engine stopped: ${e.message}`);
  }

  /** Loads the engine and the robot (and scene) shown first. */
  start(start: { robot?: string; scene?: string }, frameMs = 0): void {
    this.worker.postMessage({ type: "start", ...start, frame_ms: frameMs });
  }

  /** An intent for the engine (dropped until it is ready), after every request still waiting. */
  send(msg: Msg, transfer: Transferable[] = []): void {
    if (!this.ready) return;
    if (this.waitingToGo.length === 0) this.worker.postMessage(msg, transfer);
    else this.waitingToGo.push({ msg, counted: false, at: performance.now() });
  }

  /** For tests (window.articula.engineSend): a message as the page would post it. */
  post(msg: unknown): void {
    this.worker.postMessage(msg);
  }

  /** A slider or drag intent: tagged, timed to the frame that shows it; while two are in
   * flight it waits, replacing the one waiting last if that edits the same thing. */
  request(msg: Msg): void {
    if (!this.ready) return; // (as send: nothing to act on yet)
    msg.seq = ++this.seq;
    this.sentAt.set(this.seq, performance.now());
    const key = keyOf(msg);
    this.lastSeq.set(key, this.seq);
    const last = this.waitingToGo[this.waitingToGo.length - 1];
    if (last && last.counted && keyOf(last.msg) === key) {
      this.sentAt.delete(last.msg.seq as number);
      last.msg = msg;
    } else {
      this.waitingToGo.push({ msg, counted: true, at: performance.now() });
    }
    this.pump();
  }

  /** Whether `key`'s box was edited after the state a pose with `seq` shows (a pose without
   * one shows what the engine has answered so far): that pose is older than the box. */
  editedSince(key: string, seq: number | null | undefined): boolean {
    return (this.lastSeq.get(key) ?? 0) > (seq ?? this.answeredSeq);
  }

  /** A request's reply came (a pose, a simulated command, an error): the next may go. */
  replyArrived(seq?: number | null): void {
    if (seq !== undefined && seq !== null) this.answeredSeq = Math.max(this.answeredSeq, seq);
    this.inFlight = Math.max(0, this.inFlight - 1);
    this.pump();
  }

  /** Posts what waits, in order, while requests have room in flight. */
  private pump(): void {
    while (this.waitingToGo.length > 0) {
      const next = this.waitingToGo[0];
      if (next.counted && this.inFlight >= MAX_IN_FLIGHT) return;
      this.waitingToGo.shift();
      if (next.counted) this.inFlight++;
      this.worker.postMessage(next.msg);
    }
  }

  /** A pose tagged `seq` was applied: its latency counts at the next frame drawn. */
  applied(seq: number): void {
    this.drawnSeqs.push(seq);
    this.replyArrived(seq);
  }

  /** The frame at `now` shows what was applied: slider-to-pixels latencies, ms. */
  drawn(now: number): number[] {
    const out: number[] = [];
    for (const s of this.drawnSeqs) {
      const t0 = this.sentAt.get(s);
      if (t0 !== undefined) {
        out.push(now - t0);
        this.sentAt.delete(s);
      }
    }
    this.drawnSeqs = [];
    return out;
  }

  /** A request with its own answer (matched by id); an error reply rejects it. */
  call(msg: Msg): Promise<Msg> {
    const id = ++this.callId;
    return new Promise((resolve, reject) => {
      this.calls.set(id, { resolve, reject, type: String(msg.type), at: performance.now() });
      // (behind the edits still waiting, as send)
      if (this.waitingToGo.length === 0) this.worker.postMessage({ ...msg, id });
      else this.waitingToGo.push({ msg: { ...msg, id }, counted: false, at: performance.now() });
    });
  }

  /** The requests not answered yet, and the messages not sent yet (behind `inFlight` pose
   * requests): their type and how long they have waited, ms (for the hook: what a stuck page
   * waits for). */
  waiting(): { type: string; ms: number }[] {
    const now = performance.now();
    const unsent = this.waitingToGo.filter((w) => w.msg.id === undefined)
      .map((w) => ({ type: `${String(w.msg.type)} (not sent: ${this.inFlight} in flight)`, ms: Math.round(now - w.at) }));
    return [...[...this.calls.values()].map((c) => ({ type: c.type, ms: Math.round(now - c.at) })), ...unsent];
  }

  /** A status's code by its name in the core's table ("SettingsReset" -> 14); -1 for none. */
  code(name: string): number {
    const hit = Object.entries(this.statusTable).find(([, [n]]) => n === name);
    return hit ? Number(hit[0]) : -1;
  }

  /** The reply a status gives by its name in the core's table ("Ok" -> "ok", "JointLimit" -> "error:9"). */
  reply(name: string): string {
    const c = this.code(name);
    return c === 0 ? "ok" : `error:${c}`;
  }

  /** What a reply ("ok", "error:9") means, from the core's status table. */
  meaning(reply: string): string {
    const code = reply === "ok" ? 0 : parseInt(reply.replace(/^error:/, ""), 10);
    return this.statusTable[String(Number.isFinite(code) ? code : 255)]?.[1] ?? `unknown reply ${reply}`;
  }

  private receive(m: EngineMsg | { type: "ready"; ms: number; status_table: Record<string, [string, string]>; pen_fields: PenField[] } | { type: "fatal"; message: string }): void {
    this.messages++;
    if (m.type === "ready") {
      this.ready = true;
      this.statusTable = m.status_table;
      this.penFields = m.pen_fields;
      this.startMs = m.ms;
      this.onReady();
      return;
    }
    if (m.type === "fatal") {
      this.onFatal(`${m.message}. The studio needs a browser with WebAssembly and module workers (Chrome, Edge, Firefox, Safari of the last three years).`);
      return;
    }
    const id = (m as { id?: number }).id;
    if (id !== undefined && this.calls.has(id)) {
      const c = this.calls.get(id)!;
      this.calls.delete(id);
      if (m.type === "error") c.reject(new Error(m.message));
      else c.resolve(m as unknown as Msg);
      return;
    }
    if (this.streaming()) this.streamMessages++;
    this.onMessage(m);
    if (m.type === "physics" || m.type === "cell_frame") this.worker.postMessage({ type: "physics_ack" }); // taken: the next frame may come
  }
}
