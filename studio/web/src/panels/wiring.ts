// The Wiring view (in The arm): every wire of the robot shown, drawn from the engine's wiring
// (host/lib/wiring.h, from firmware/src/board.h, the one pin table): the board and its pins on
// the left, each driver, switch and servo on the right, a line from each pin to the input it
// feeds, coloured by motor. Saved as SVG for printing: a student wires the arm from the paper.
// Every name is text (textContent), never markup: a robot file is untrusted.
import { $, download, fill, h, svgEl as el } from "../page/dom";
import type { Studio } from "../page/context";
import type { RobotMsg } from "../engine/messages";

type Wiring = NonNullable<RobotMsg["wiring"]>;

const ROW = 22; // px a wire
const PART_GAP = 10; // between two parts' boxes
const HEAD = 16; // the name line of a part with several inputs
const BOARD_W = 64, GAP = 56, PART_W = 200, PAD = 8;
// one colour a motor (the board's own wires grey), distinct in print and for most colour vision
const COLOURS = ["#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#8a6d00", "#6a3d9a"];

let s: Studio;

/** The view's state (window.articula.wiring): the wires drawn, for the tests. */
export const wiringStatus = { board: "", firmware: "", wires: 0, error: "" };

export function initWiring(studio: Studio): void {
  s = studio;
  s.editor.signals.robotShown.add((r) => draw(r.wiring, r.name));
  $("wiring-save").onclick = () => {
    const svg = $("wiring") as unknown as SVGSVGElement;
    const copy = svg.cloneNode(true) as SVGSVGElement;
    const t = el("title", {}, `${s.editor.robot?.name ?? "arm"}: wiring`); // text, escaped by the serializer
    copy.prepend(t);
    download("wiring.svg", new XMLSerializer().serializeToString(copy), "image/svg+xml");
  };
}

function draw(w: Wiring | undefined, robotName: string): void {
  const svg = $("wiring") as unknown as SVGSVGElement;
  svg.replaceChildren();
  const title = $("wiring-title");
  Object.assign(wiringStatus, { board: w?.board ?? "", firmware: w?.firmware ?? "", wires: 0, error: w?.error ?? "" });
  ($("wiring-save") as HTMLButtonElement).disabled = true;
  // the supply, the common ground and a CNC shield's jumpers: a line each, as text
  fill($("wiring-supply"), ...(w && !w.error ? w.supply ?? [] : []).map((t) => h("li", null, t)));
  if (!w || w.error) {
    title.textContent = w?.error ? `No wiring: ${w.error}.` : "No wiring.";
    svg.setAttribute("viewBox", "0 0 10 10");
    svg.setAttribute("height", "0");
    return;
  }
  title.textContent = `${robotName} on an ${w.board_title}` +
    (w.given ? "" : " (its file names no drive: the thesis's wiring)") +
    (w.firmware ? `. Firmware: ${w.firmware}.hex.` : ". No firmware for its servos yet.");
  // The wires grouped by what they go to (a part of one motor, or the board's own), in order.
  const groups: { part: string; motor: string | null; wires: Wiring["wires"] }[] = [];
  for (const x of w.wires) {
    const g = groups[groups.length - 1];
    if (g && g.part === x.part && g.motor === x.motor) g.wires.push(x);
    else groups.push({ part: x.part, motor: x.motor, wires: [x] });
  }
  const motors = [...new Set(w.wires.map((x) => x.motor).filter((m): m is string => m !== null))];
  const colour = (m: string | null) => (m === null ? "#6b7280" : COLOURS[motors.indexOf(m) % COLOURS.length]);
  const height = PAD * 2 + 26 + ROW / 2 + w.wires.length * ROW + groups.length * PART_GAP +
    groups.filter((g) => g.wires.length > 1).length * HEAD;
  const width = PAD * 2 + BOARD_W + GAP + PART_W;
  svg.setAttribute("viewBox", `0 0 ${width} ${height}`);
  // its own size at most (a wide panel does not blow it up), less in a narrow one (CSS max-width)
  svg.setAttribute("width", String(width));
  svg.setAttribute("height", String(height));
  svg.append(el("rect", { x: 0, y: 0, width, height, fill: "#ffffff" }));
  const top = PAD + 26 + ROW / 2;
  svg.append(el("text", { x: PAD, y: PAD + 12, fill: "#111827", "font-size": 13, "font-weight": 600 }, w.board_title));
  svg.append(el("rect", { x: PAD, y: PAD + 20, width: BOARD_W, height: height - 2 * PAD - 20, rx: 6, fill: "#1f5f8b",
    class: "board" }));
  let y = top;
  for (const g of groups) {
    const c = colour(g.motor);
    const head = g.wires.length > 1 ? HEAD : 0; // a part with several inputs: its name on a line of its own
    y += head;
    const boxTop = y - ROW / 2 + 2 - head;
    const x0 = PAD + BOARD_W + GAP;
    svg.append(el("rect", { x: x0, y: boxTop, width: PART_W, height: g.wires.length * ROW - 4 + head, rx: 4, fill: "#f8fafc",
      stroke: c, "stroke-width": 1.5 }));
    const label = g.motor === null ? g.part : `${g.part}, ${g.motor}`;
    svg.append(el("text", { x: x0 + PART_W - 6, y: boxTop + 13, "text-anchor": "end", "font-size": 12,
      "font-weight": head ? 600 : 400, fill: "#111827" }, label));
    for (const x of g.wires) {
      const px = PAD + BOARD_W;
      svg.append(el("circle", { cx: px - 8, cy: y, r: 3.5, fill: "#f1c40f" }));
      svg.append(el("text", { x: px - 16, y: y + 4, "text-anchor": "end", "font-size": 13, fill: "#ffffff",
        "font-family": "monospace" }, x.pin));
      svg.append(el("line", { x1: px - 8, y1: y, x2: x0, y2: y, stroke: c, "stroke-width": 2.5, class: "wire" }));
      svg.append(el("circle", { cx: x0, cy: y, r: 3, fill: c }));
      svg.append(el("text", { x: x0 + 8, y: y + 4, "font-size": 13, "font-family": "monospace", fill: "#111827" }, x.signal));
      y += ROW;
    }
    y += PART_GAP;
  }
  wiringStatus.wires = w.wires.length;
  ($("wiring-save") as HTMLButtonElement).disabled = false;
}
