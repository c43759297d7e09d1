// The program's time line as plots (uPlot): joint values, tool position and the quantization
// error, a playhead that follows the arm, PNG and CSV export. The values are the engine's
// (the prediction's records); the page only draws them.
import uPlot from "uplot";
import type { TimelineMsg } from "./engine/messages";
import { fill, h } from "./page/dom";

const COLORS = ["#3d5a80", "#ee6c4d", "#2a9d8f", "#e0a458", "#6d597a", "#b56576", "#457b9d", "#8d99ae"];

export class Plots {
  private charts: uPlot[] = [];
  private t = -1;
  onSeek: (t: number) => void = () => {};

  constructor(readonly host: HTMLElement) {
    // the plots follow their panel's size (a window resized, a tablet turned, the plots' tab shown)
    new ResizeObserver(() => this.fit()).observe(host);
    document.body.classList.add("no-plots");
  }

  // Three side by side where they have room, else one above the other (the panel scrolls).
  private size(): { width: number; height: number } {
    const w = this.host.clientWidth, hgt = this.host.clientHeight;
    if (w >= 840) return { width: Math.floor((w - 24) / 3), height: Math.max(110, hgt - 30) };
    return { width: Math.max(200, w - 4), height: 190 };
  }

  private fit(): void {
    if (!this.host.clientWidth) return; // hidden: sized when shown
    const { width, height } = this.size();
    for (const c of this.charts) if (c.width !== width || c.height !== height) c.setSize({ width, height });
  }

  clear(): void {
    this.charts.forEach((c) => c.destroy());
    this.charts = [];
    fill(this.host, h("p", { class: "hint" }, "Run a program to see its joints, tool and quantization error over time."));
    document.body.classList.add("no-plots"); // the plots' row takes only the hint's height
  }

  // The path the arm takes: the time line's samples (the engine's), every action's start and
  // end and evenly between, the tool at each; a move between two points is the curve it is,
  // not the straight line joining its ends.
  private series(m: TimelineMsg) {
    return { t: m.samples.t, joints: m.samples.q, tool: m.samples.tool };
  }

  show(m: TimelineMsg): void {
    this.clear();
    fill(this.host);
    document.body.classList.remove("no-plots");
    const { t, joints, tool } = this.series(m);
    // The quantization error is a property of a pose at rest: one point after each command.
    const ok = m.records.filter((r) => r.reply === "ok");
    const te = [0, ...ok.map((r) => r.end_s)];
    const err = [ok.length ? ok[0].error_mm : 0, ...ok.map((r) => r.error_mm)];
    const { width, height } = this.size();
    const playhead = (u: uPlot) => {
      if (this.t < 0) return;
      const x = u.valToPos(this.t, "x", true);
      const ctx = u.ctx;
      ctx.save();
      ctx.strokeStyle = "#d62828";
      ctx.lineWidth = 2 * devicePixelRatio;
      ctx.beginPath();
      ctx.moveTo(x, u.bbox.top);
      ctx.lineTo(x, u.bbox.top + u.bbox.height);
      ctx.stroke();
      ctx.restore();
    };
    const make = (title: string, unit: string, names: string[], data: number[][], x = t, stepped = false) => {
      const opts: uPlot.Options = {
        title, width, height,
        scales: { x: { time: false, range: [0, Math.max(m.duration, 1e-3)] } },
        axes: [{ label: "time (s)", size: 34, space: 40 }, { label: unit, size: 56, space: 22 }],
        series: [{ label: "t (s)" }, ...names.map((n, i) => ({
          label: n, stroke: COLORS[i % COLORS.length], width: 2,
          ...(stepped ? { paths: uPlot.paths.stepped!({ align: 1 }), points: { show: true, size: 6 } } : { points: { show: false } }),
        }))],
        legend: { show: true, live: false },
        cursor: { drag: { x: false, y: false } },
        hooks: { draw: [playhead] },
      };
      const div = document.createElement("div");
      div.className = "plot";
      this.host.appendChild(div);
      const u = new uPlot(opts, [x, ...data] as uPlot.AlignedData, div);
      u.over.addEventListener("click", (e) => {
        const x = u.posToVal((e as MouseEvent).offsetX, "x");
        if (Number.isFinite(x)) this.onSeek(Math.max(0, Math.min(m.duration, x)));
      });
      this.charts.push(u);
    };
    make("Joint values (whole steps)", m.joints.some(() => true) ? "deg or mm" : "", m.joints, joints);
    make("Tool position", "mm", ["x", "y", "z"], tool);
    make("Quantization error after each command", "mm", ["|whole steps - ideal|"], [err], te, true);
  }

  playhead(t: number): void {
    this.t = t;
    this.charts.forEach((c) => c.redraw(false, false));
  }

  /** The plots as one picture: what they show (robot, program, when), each plot's title and
   * its legend (a series' colour and name). */
  async png(caption = ""): Promise<Blob | null> {
    if (!this.charts.length) return null;
    const canvases = this.charts.map((c) => c.ctx.canvas);
    const out = document.createElement("canvas");
    const px = devicePixelRatio;
    const head = 58 * px, legend = 26 * px;
    out.width = canvases.reduce((s, c) => s + c.width, 0);
    out.height = Math.max(...canvases.map((c) => c.height)) + head + legend;
    const g = out.getContext("2d")!;
    g.fillStyle = "#fff";
    g.fillRect(0, 0, out.width, out.height);
    g.fillStyle = "#1d3557";
    g.font = `600 ${14 * px}px system-ui, sans-serif`;
    g.fillText(caption, 12 * px, 20 * px);
    g.font = `${13 * px}px system-ui, sans-serif`;
    let x = 0;
    this.charts.forEach((c, i) => {
      g.fillStyle = "#1d3557";
      g.fillText(c.root.querySelector(".u-title")?.textContent ?? `plot ${i + 1}`, x + 12 * px, 46 * px);
      g.drawImage(c.ctx.canvas, x, head);
      // the legend under it
      let lx = x + 12 * px;
      const ly = head + c.ctx.canvas.height + 17 * px;
      c.series.slice(1).forEach((s, k) => {
        const stroke = typeof s.stroke === "function" ? s.stroke(c, k + 1) : s.stroke;
        g.fillStyle = typeof stroke === "string" ? stroke : "#1d3557";
        g.fillRect(lx, ly - 9 * px, 14 * px, 4 * px);
        g.fillStyle = "#1d3557";
        const label = String(s.label ?? "");
        g.fillText(label, lx + 18 * px, ly);
        lx += 28 * px + g.measureText(label).width;
      });
      x += c.ctx.canvas.width;
    });
    return new Promise((resolve) => out.toBlob(resolve, "image/png"));
  }

  /** The path the arm takes, as the plots show it: one row a sample of the time line (t, the
   *  line running, each joint, the tool), and each line's command and reply on its first row. */
  csv(m: TimelineMsg): string {
    const head = ["t_s", "line", "command", "reply", ...m.joints.map((j) => `joint_${j}`), "tool_x", "tool_y", "tool_z"];
    const q = (s: string) => (/[",\n\r]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s);
    const byLine = new Map(m.records.map((r) => [r.line, r]));
    const said = new Set<number>();
    const S = m.samples;
    const rows = S.t.map((t, i) => {
      const line = S.line[i];
      const r = line > 0 && !said.has(line) ? byLine.get(line) : undefined;
      if (r) said.add(line);
      return [t, line, r ? q(r.command) : "", r ? (r.reply === "ok" ? "ok" : `error:${r.code}`) : "",
        ...S.q.map((c) => c[i]), S.tool[0][i], S.tool[1][i], S.tool[2][i]].join(",");
    });
    return [head.join(","), ...rows].join("\n") + "\n";
  }
}
