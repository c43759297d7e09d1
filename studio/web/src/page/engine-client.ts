// The engine, as the page sees it: the Web Worker (engine/worker.ts: the C++ core, host library and
// ODE in WebAssembly) that computes every pose, solve, prediction and physics step. The page
// posts intents and handles what comes back; a request with an `id` gets its own answer.
import type { EngineMsg } from "../engine/messages";
import { hook } from "./hook";

type Msg = Record<string, unknown>;

// Pose requests (sliders, drags): at most two in flight, so one is computed while the page
// draws the other; the newest intent waits and replaces any older one waiting.
const MAX_IN_FLIGHT = 2;

export class EngineClient {
  ready = false;
  /** The protocol's status table (shared/articula/status.h), from the engine: code -> text. */
  statusTable: Record<string, [string, string]> = {};
  onMessage: (m: EngineMsg) => void = () => undefined;
  onReady: () => void = () => undefined;
  onFatal: (message: string) => void = () => undefined;
  private worker: Worker;
  private seq = 0;
  private sentAt = new Map<number, number>();
  private drawnSeqs: number[] = [];
  private inFlight = 0;
  private queued: Msg | null = null;
  private callId = 0;
  private calls = new Map<number, { resolve: (m: Msg) => void; reject: (e: Error) => void; type: string; at: number }>();

  constructor() {
    this.worker = new Worker(new URL("assets/worker.js", document.baseURI), { type: "module" });
    this.worker.onmessage = (e) => this.receive(e.data as EngineMsg | { type: "ready"; ms: number; status_table: Record<string, [string, string]> } | { type: "fatal"; message: string });
    this.worker.onerror = (e) => this.onFatal(`The engine stopped: ${e.message}`);
  }

  /** Loads the engine and the robot (and scene) shown first. */
  start(start: { robot?: string; scene?: string }): void {
    this.worker.postMessage({ type: "start", ...start });
  }

  /** An intent for the engine (dropped until it is ready). */
  send(msg: Msg, transfer: Transferable[] = []): void {
    if (this.ready) this.worker.postMessage(msg, transfer);
  }

  /** For tests (window.articula.engineSend): a message as the page would post it. */
  post(msg: unknown): void {
    this.worker.postMessage(msg);
  }

  /** A slider or drag intent: tagged, timed to the frame that shows it, one waiting at most. */
  request(msg: Msg): void {
    msg.seq = ++this.seq;
    this.sentAt.set(this.seq, performance.now());
    if (this.inFlight >= MAX_IN_FLIGHT) {
      this.queued = msg;
      return;
    }
    this.inFlight++;
    this.send(msg);
  }

  /** A request's reply came (a pose, a simulated command, an error): the next may go. */
  replyArrived(): void {
    this.inFlight = Math.max(0, this.inFlight - 1);
    if (this.queued) {
      const next = this.queued;
      this.queued = null;
      this.inFlight++;
      this.send(next);
    }
  }

  /** A pose tagged `seq` was applied: its latency counts at the next frame drawn. */
  applied(seq: number): void {
    this.drawnSeqs.push(seq);
    this.replyArrived();
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
      this.worker.postMessage({ ...msg, id });
    });
  }

  /** The requests not answered yet: their type and how long they have waited, ms (for the hook). */
  waiting(): { type: string; ms: number }[] {
    const now = performance.now();
    return [...this.calls.values()].map((c) => ({ type: c.type, ms: Math.round(now - c.at) }));
  }

  /** What a reply ("ok", "error:9") means, from the core's status table. */
  meaning(reply: string): string {
    const code = reply === "ok" ? 0 : parseInt(reply.replace(/^error:/, ""), 10);
    return this.statusTable[String(Number.isFinite(code) ? code : 255)]?.[1] ?? `unknown reply ${reply}`;
  }

  private receive(m: EngineMsg | { type: "ready"; ms: number; status_table: Record<string, [string, string]> } | { type: "fatal"; message: string }): void {
    hook.messages++;
    if (m.type === "ready") {
      this.ready = true;
      this.statusTable = m.status_table;
      hook.engineStartMs = m.ms;
      hook.connected = true;
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
    if (hook.physics?.on) hook.stream.messages++;
    this.onMessage(m);
    if (m.type === "physics") this.worker.postMessage({ type: "physics_ack" }); // taken: the next frame may come
  }
}
