// The paper seen from above, as a student at +x facing the arm sees it: the table's +y to the
// right, +x down (the base is up the page; host/lib/draw.h's drawing_svg looks the same way).
// One SVG user unit is a millimetre. It draws the sheet, the part of it the pen reaches (the
// engine's reach map), and layers of strokes: the drawing, the line the arm will draw, the ink
// the arm left, a hand's strokes, an exercise's target. The sheet can be dragged; in freehand
// mode a finger or the mouse draws. Built with createElementNS: nothing is parsed as markup.
import { svgEl as el } from "../page/dom";

const NS = "http://www.w3.org/2000/svg";
const MARGIN_MM = 12;

export type Layer = "target" | "ideal" | "predicted" | "ink" | "hand";
const STYLE: Record<Layer, { stroke: string; width: number; dash?: string; opacity?: number }> = {
  target: { stroke: "#7c3aed", width: 2.4, opacity: 0.25 },
  ideal: { stroke: "#1d4ed8", width: 0.6 },
  predicted: { stroke: "#c2410c", width: 0.45 },
  ink: { stroke: "#111827", width: 0.8 },
  hand: { stroke: "#0f766e", width: 0.6, dash: "1.5 1" },
};

// A table point [x, y] as the view's "right,down".
const at = (p: number[]) => `${p[1].toFixed(2)},${p[0].toFixed(2)}`;

export class PaperView {
  readonly svg: SVGSVGElement;
  /** A drag of the sheet ended: it moved by dx, dy on the table, mm. */
  onMoveSheet: (dx: number, dy: number) => void = () => undefined;
  /** A stroke drawn by hand ended: its points on the table, mm. */
  onStroke: (points: number[][]) => void = () => undefined;
  freehand = false;
  private area: number[] | null = null;
  private sheet: SVGGElement;
  private reach = el("g", { id: "reach" });
  private layers = new Map<Layer, SVGGElement>();
  private marks = el("g", { id: "marks" });
  private live: SVGPolylineElement | null = null;

  constructor(svg: SVGSVGElement) {
    this.svg = svg;
    svg.setAttribute("xmlns", NS);
    this.sheet = el("g", { id: "sheet" });
    this.sheet.append(el("rect", { id: "sheet-paper", fill: "#fdfdf8", stroke: "#94a3b8", "stroke-width": 0.4 }), this.reach);
    for (const name of Object.keys(STYLE) as Layer[]) {
      const st = STYLE[name];
      const g = el("g", { id: name, fill: "none", stroke: st.stroke, "stroke-width": st.width, "stroke-linecap": "round",
        "stroke-linejoin": "round", ...(st.dash ? { "stroke-dasharray": st.dash } : {}), ...(st.opacity ? { opacity: st.opacity } : {}) });
      this.layers.set(name, g);
      this.sheet.append(g);
    }
    this.sheet.append(this.marks);
    svg.append(el("rect", { id: "table", x: -1e4, y: -1e4, width: 2e4, height: 2e4, fill: "#e7ecf1" }), this.sheet);
    this.pointers();
  }

  /** The sheet's corners [min_x, min_y, max_x, max_y] on the table, mm; the view frames it. */
  setSheet(area: number[]): void {
    this.area = area;
    const [x0, y0, x1, y1] = area;
    const paper = this.sheet.querySelector("#sheet-paper")!;
    for (const [k, v] of Object.entries({ x: y0, y: x0, width: y1 - y0, height: x1 - x0 })) paper.setAttribute(k, String(v));
    this.svg.setAttribute("viewBox", `${y0 - MARGIN_MM} ${x0 - MARGIN_MM} ${y1 - y0 + 2 * MARGIN_MM} ${x1 - x0 + 2 * MARGIN_MM}`);
    this.sheet.removeAttribute("transform");
  }

  /** The engine's reach map of the sheet: the cells the pen reaches shaded, a run per row. */
  setReach(map: { rows: number; cols: number; cell: number; area: number[]; reached: string } | null): void {
    this.reach.replaceChildren();
    if (!map) return;
    const [x0, y0] = map.area;
    for (let r = 0; r < map.rows; r++) {
      for (let c = 0; c < map.cols;) {
        if (map.reached[r * map.cols + c] !== "1") { c++; continue; }
        let e = c;
        while (e < map.cols && map.reached[r * map.cols + e] === "1") e++;
        this.reach.append(el("rect", { x: y0 + c * map.cell, y: x0 + r * map.cell, width: (e - c) * map.cell, height: map.cell,
          fill: "#99f6e4", "fill-opacity": 0.35 }));
        c = e;
      }
    }
  }

  /** A layer's strokes ([x, y] polylines on the table, mm); none: cleared. */
  setLayer(name: Layer, strokes: number[][][]): void {
    const g = this.layers.get(name)!;
    g.replaceChildren();
    for (const s of strokes) {
      if (!s.length) continue;
      if (s.length === 1) g.append(el("circle", { cx: s[0][1], cy: s[0][0], r: 0.5, fill: STYLE[name].stroke, stroke: "none" }));
      else g.append(el("polyline", { points: s.map(at).join(" ") }));
    }
  }

  /** The points the pen cannot reach (red) and the worst distance of the line the arm will
   * draw from the drawing (a ring); empty: none. */
  setMarks(unreachable: number[][], worst: number[] | null): void {
    this.marks.replaceChildren();
    for (const p of unreachable) this.marks.append(el("circle", { cx: p[1], cy: p[0], r: 1.2, fill: "#dc2626" }));
    if (worst) this.marks.append(el("circle", { cx: worst[1], cy: worst[0], r: 2.5, fill: "none", stroke: "#c2410c", "stroke-width": 0.5 }));
  }

  /** The view as an SVG file's text: the sheet, the shading and every layer, each a group. */
  svgText(title: string): string {
    const copy = this.svg.cloneNode(true) as SVGSVGElement;
    copy.querySelector("#table")?.remove();
    const t = el("title");
    t.textContent = title; // text, escaped by the serializer
    copy.prepend(t);
    const [, , w, h] = (copy.getAttribute("viewBox") ?? "0 0 100 100").split(" ").map(Number);
    copy.setAttribute("width", `${w}mm`);
    copy.setAttribute("height", `${h}mm`);
    return new XMLSerializer().serializeToString(copy);
  }

  // Table mm of a pointer event.
  private table(e: PointerEvent): number[] {
    const m = this.svg.getScreenCTM();
    if (!m) return [0, 0];
    const p = new DOMPoint(e.clientX, e.clientY).matrixTransform(m.inverse());
    return [p.y, p.x];
  }

  private pointers(): void {
    let drag: { from: number[]; id: number } | null = null;
    let stroke: number[][] = [];
    this.svg.addEventListener("pointerdown", (e) => {
      if (!this.area || e.button > 0) return;
      const p = this.table(e);
      if (this.freehand) {
        stroke = [p];
        this.live = el("polyline", { points: at(p) });
        this.layers.get("hand")!.append(this.live);
      } else {
        const [x0, y0, x1, y1] = this.area;
        if (p[0] < x0 || p[0] > x1 || p[1] < y0 || p[1] > y1) return;
        drag = { from: p, id: e.pointerId };
        this.svg.classList.add("dragging");
      }
      this.svg.setPointerCapture(e.pointerId);
      e.preventDefault();
    });
    this.svg.addEventListener("pointermove", (e) => {
      if (this.live) {
        for (const c of e.getCoalescedEvents?.() ?? [e]) stroke.push(this.table(c));
        this.live.setAttribute("points", stroke.map(at).join(" "));
      } else if (drag && e.pointerId === drag.id) {
        const p = this.table(e);
        this.sheet.setAttribute("transform", `translate(${p[1] - drag.from[1]} ${p[0] - drag.from[0]})`);
      }
    });
    const end = (e: PointerEvent) => {
      if (this.live) {
        this.live = null;
        if (stroke.length) this.onStroke(stroke);
        stroke = [];
      } else if (drag && e.pointerId === drag.id) {
        const p = this.table(e);
        const dx = Math.round(p[0] - drag.from[0]), dy = Math.round(p[1] - drag.from[1]);
        drag = null;
        this.svg.classList.remove("dragging");
        this.sheet.removeAttribute("transform");
        if (dx || dy) this.onMoveSheet(dx, dy);
      }
    };
    this.svg.addEventListener("pointerup", end);
    this.svg.addEventListener("pointercancel", end);
  }
}
