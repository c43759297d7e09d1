// A cell's arms on Nanos of their own (panels/cell.ts's "on virtual Nanos"): each arm's own
// firmware hex (its build: articula-nano, -cnc or -servo) on a virtual Nano of its own (avr8js,
// each in its own Web Worker, paced to real time), configured for its robot, and its program
// sent line by line as to a real arm (link/arm-link.ts: a line, its reply, then `?` until at
// rest). The wires join the Nanos' header pins: an output's level, as its Nano's worker reports
// it (looked at every 5 ms or less), drives the inputs it is wired to. The view shows each arm
// as its Nano reports itself; the world's objects stand still (its physics is the engine's
// cell's). STOP sends every Nano the realtime `!`.
import type { CellMsg, EngineMsg, NanoConfig } from "../engine/messages";
import { ArmLink } from "../link/arm-link";
import { VirtualNanoPort } from "../link/ports";
import type { Studio } from "../page/context";

type Arm = NonNullable<CellMsg["arms"]>[number];

/** One arm's Nano as the page shows it (cellReport.nanos). */
export interface NanoArm {
  name: string; connected: boolean; line: number; done: boolean; stopped: boolean; error: string;
  rtf: number | null; capacity: number | null; behind: boolean; reports: number; state: string; levels: Record<string, number>;
  said: string; // what its link said last
}

export interface NanoRun {
  arms: NanoArm[];
  running: boolean; // programs still running on some Nano
  startedAt: number; // the first Nano's clock at the start (ms)
  t: number; // s since
  stops: number; // STOPs sent to every Nano
  drives: number; // levels carried by the wires
}

export class CellNanos {
  readonly run: NanoRun = { arms: [], running: false, startedAt: 0, t: 0, stops: 0, drives: 0 };
  private links: ArmLink[] = [];
  private ports: VirtualNanoPort[] = [];
  private closed = false;

  /** `onPose(k, q, frames, fingers)`: arm k where its Nano says it is; `changed()`: the report changed. */
  constructor(private s: Studio, private arms: Arm[], private wires: { from: string; to: string }[],
    private onPose: (k: number, frames: number[][], fingers: number[][] | undefined) => void, private changed: () => void) {
    this.run.arms = arms.map((a) => ({ name: a.name, connected: false, line: 0, done: false, stopped: false, error: "", rtf: null,
      capacity: null, behind: false, reports: 0, state: "", levels: {}, said: "" }));
  }

  /** Powers every arm's Nano up, configures it for its arm (its EEPROM starts empty), joins the
   * wires, then runs each arm's program from the same moment. */
  async start(programs: string[]): Promise<void> {
    this.arms.forEach((a, k) => this.ports.push(this.port(a, k)));
    this.joinWires();
    await Promise.all(this.arms.map((a, k) => this.connect(a, k)));
    if (this.closed) return;
    const bad = this.run.arms.find((a) => !a.connected);
    if (bad) {
      this.changed();
      return;
    }
    this.run.startedAt = this.ports[0].clock();
    this.run.running = true;
    this.links.forEach((l, k) => l.runProgram(programs[k] ?? ""));
    this.changed();
  }

  private port(a: Arm, k: number): VirtualNanoPort {
    const port = new VirtualNanoPort();
    port.eepromKey = null; // (configured for its arm each time)
    const g = a.robot.gripper;
    port.servo = g ? { closed: g.servo_closed_deg, open: g.servo_open_deg } : null;
    port.cnc = a.robot.firmware === "articula-cnc";
    port.servos = a.robot.servos ?? null;
    port.speed = this.s.editor.speed;
    port.onState = (st) => {
      Object.assign(this.run.arms[k], { rtf: st.rtf, capacity: st.capacity, behind: st.behind });
    };
    // avr8js has no pull-ups: an input_pullup pin no wire drives reads 1 as on a Nano
    const wired = new Set(this.ends().filter((e) => e.arm === k).map((e) => e.pin));
    for (const io of a.io) if (io.mode === "input_pullup" && !wired.has(io.pin)) port.drive(io.pin, 1);
    return port;
  }

  // Each wire's ends: the arm, its header pin, and whether it is the output that drives it.
  private ends(): { arm: number; pin: string; output: boolean; net: number }[] {
    const out: { arm: number; pin: string; output: boolean; net: number }[] = [];
    this.wires.forEach((w, net) => {
      for (const end of [w.from, w.to]) {
        const dot = end.indexOf(".");
        const k = this.arms.findIndex((a) => a.name === end.slice(0, dot));
        const io = this.arms[k]?.io.find((p) => p.name === end.slice(dot + 1));
        if (io) out.push({ arm: k, pin: io.pin, output: io.mode === "output", net });
      }
    });
    return out;
  }

  // Each output's level, as its Nano reports it, drives the inputs on its wire.
  private joinWires(): void {
    const ends = this.ends();
    const outputs = ends.filter((e) => e.output);
    for (const k of new Set(outputs.map((o) => o.arm))) {
      const mine = outputs.filter((o) => o.arm === k);
      this.ports[k].watch(mine.map((o) => o.pin));
      this.ports[k].onLevels = (levels) => {
        this.run.arms[k].levels = levels;
        for (const o of mine) {
          const level = levels[o.pin];
          if (level === undefined) continue;
          for (const e of ends) if (e.net === o.net && !e.output) {
            this.ports[e.arm].drive(e.pin, level);
            this.run.drives++;
          }
        }
      };
    }
  }

  private async connect(a: Arm, k: number): Promise<void> {
    const arm = this.run.arms[k];
    const call = (m: Record<string, unknown>) => this.s.engine.call({ ...m, arm: k });
    const link = new ArmLink({
      read: (line) => call({ type: "cell_arm_read", line }) as never,
      predict: (history, line) => call({ type: "cell_arm_predict", history, line }) as never,
      meaning: (reply) => this.s.engine.meaning(reply),
      reply: (name) => this.s.engine.reply(name),
      config: async () => ((await call({ type: "cell_arm_config" })) as unknown as { config: NanoConfig | { error: string } }).config,
    }, (m) => this.message(k, m as unknown as EngineMsg));
    this.links[k] = link;
    await link.connect(this.ports[k], `${a.name}'s virtual Nano`, a.robot.name);
    if (!link.connected && link.configurable) await link.configure(); // (a Nano's EEPROM starts empty)
    arm.connected = link.connected;
    if (!link.connected && !arm.error) arm.error = "its Nano did not take the arm's configuration";
  }

  private message(k: number, m: EngineMsg): void {
    const arm = this.run.arms[k];
    const x = m as unknown as Record<string, unknown>;
    switch (m.type) {
      case "arm":
        if (typeof x.error === "string" && x.error) arm.said = x.error; // (the last, for whoever reads a failure)
        if (typeof x.error === "string" && x.error && !x.configurable) arm.error = x.error;
        if (x.connected === false && arm.connected) arm.connected = false;
        break;
      case "arm_status": {
        arm.reports++;
        arm.state = String(x.state);
        const q = x.q as number[];
        const g = this.arms[k].robot.gripper;
        const st = this.ports[k].state;
        // (the servo's pulse as an aperture: a pulse past the robot's closed or open angle is held to them)
        const percent = Math.min(100, Math.max(0, st?.gripper ?? 0));
        const opening = g && Number.isFinite(percent) ? (g.max_opening_mm * percent) / 100 : 0;
        this.s.engine.call({ type: "cell_arm_pose", arm: k, q, gripper_mm: opening }).then((p) => {
          const pose = p as unknown as { frames: number[][]; fingers?: number[][] };
          if (!this.closed) this.onPose(k, pose.frames, pose.fingers);
        }, (e: Error) => (arm.said = `its pose: ${e.message}`));
        this.run.t = (this.ports[0].clock() - this.run.startedAt) / 1000;
        break;
      }
      case "arm_program":
        if (typeof x.line === "number") arm.line = x.line;
        if (x.done) {
          arm.done = true;
          arm.stopped = x.stopped === true;
          if (typeof x.error === "string") arm.error = x.error;
          this.run.running = this.run.arms.some((a) => !a.done);
        }
        break;
    }
    this.changed();
  }

  /** STOP: the realtime `!` to every Nano; no further line. */
  async stop(): Promise<void> {
    this.run.stops++;
    await Promise.all(this.links.map((l) => l?.stop()));
    this.changed();
  }

  /** Every Nano off. */
  async close(): Promise<void> {
    this.closed = true;
    await Promise.all(this.links.map((l) => l?.disconnect()));
    await Promise.all(this.ports.map((p) => p.close()));
  }
}
