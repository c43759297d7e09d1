// The page's one way to put text on screen: elements built node by node, every string a text
// node or an attribute's value, never markup. No string from a robot file, a scene, a program,
// a link or the arm is ever parsed as HTML (docs/studio.md, "Security"); the page holds Web
// Serial permissions to a real arm, so a script smuggled into it could move a machine.

export const $ = <T extends HTMLElement = HTMLElement>(id: string) => document.getElementById(id) as T;

type Child = Node | string | number | null | undefined | false;
type Props = Record<string, string | number | boolean | null | undefined>;

/** An element: `props` become attributes (`class`, `title`, `data-x`, `min`...), children
 * text nodes or elements. `h("b", null, name)` shows `name` as text whatever it holds. */
export function h<K extends keyof HTMLElementTagNameMap>(tag: K, props?: Props | null, ...children: Child[]): HTMLElementTagNameMap[K] {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(props ?? {})) {
    if (v === null || v === undefined || v === false) continue;
    if (/^on/i.test(k)) throw new Error(`h(): no event handler attributes (${k}): use addEventListener`);
    el.setAttribute(k, v === true ? "" : String(v));
  }
  el.append(...kids(children));
  return el;
}

const SVG_NS = "http://www.w3.org/2000/svg";

/** An SVG element with its attributes, and its text as text (never markup). */
export function svgEl<K extends keyof SVGElementTagNameMap>(tag: K, attrs: Record<string, string | number> = {}, text?: string):
  SVGElementTagNameMap[K] {
  const e = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, String(v));
  if (text !== undefined) e.textContent = text;
  return e;
}

/** Replaces what `el` holds with `children` (text or elements). */
export function fill(el: Element, ...children: Child[]): void {
  el.replaceChildren(...kids(children));
}

function kids(children: Child[]): (Node | string)[] {
  return children.filter((c) => c !== null && c !== undefined && c !== false).map((c) => (typeof c === "number" ? String(c) : c as Node | string));
}

/** A <select>'s options, each label shown as text; keeps the choice when it is still offered. */
export function setOptions(sel: HTMLSelectElement, items: (string | { value: string; label: string })[]): void {
  const keep = sel.value;
  fill(sel, ...items.map((it) => (typeof it === "string" ? h("option", { value: it }, it) : h("option", { value: it.value }, it.label))));
  if ([...sel.options].some((o) => o.value === keep)) sel.value = keep;
}

/** A status line: its text and its kind ("ok", "bad" or plain). */
export function status(el: HTMLElement, text: string, kind: "" | "ok" | "bad" = ""): void {
  el.textContent = text;
  el.className = `status ${kind}`.trim();
}

export function fmt(v: number, d = 2): string {
  return (Math.abs(v) < 0.5 * 10 ** -d ? 0 : v).toFixed(d);
}

/** Saves `data` as a file the browser downloads. */
export function download(name: string, data: string | Blob, type: string): void {
  const blob = typeof data === "string" ? new Blob([data], { type }) : data;
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

/** The banner over the page: an error, or a note. */
export function banner(text: string, kind: "error" | "info" = "error"): void {
  $("banner-text").textContent = text;
  $("banner").className = `banner ${kind}`;
  $("banner").hidden = false;
}
