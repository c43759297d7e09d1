// The program as blocks (Blockly, bundled with the site): the workspace, the mode switch
// between blocks and text, Show code. Blocks unroll into actions (blocks/unroll.ts), the
// engine turns the actions into the program text it runs (engine/blocks.ts), and that text
// is the program: the editor holds it, Run plays it wherever a program plays (the model, the
// physics, the virtual Nano, the arm). The running line's block is highlighted; a block the
// arm would refuse, or the engine did, says why on itself.
import * as Blockly from "blockly/core";
import type { Editor } from "../editor/editor";
import type { Studio } from "../page/context";
import { $ } from "../page/dom";
import type { Reports } from "../page/reports";
import { defineBlocks, setJoints, setPins, toolbox } from "../blocks/define";
import { BlockError, opsToWorkspace, unroll } from "../blocks/unroll";
import type { RobotMsg } from "../engine/messages";

/** The blocks' reports (window.articula shows it; main.ts wires it). */
export const blocksReport: { blockProblems: Reports["blockProblems"]; blockStacks: number; blocksCode: Reports["blocksCode"]; blocksFirstPaintMs: number; programMode: string; runningBlock: string } = {
  blockProblems: [], blockStacks: 0, blocksCode: null, blocksFirstPaintMs: 0, programMode: "text", runningBlock: "",
};

let editor: Editor | null = null;
let s: Studio;
let ws: Blockly.WorkspaceSvg | null = null;
let mode: "text" | "blocks" = "text";
let lineBlocks: string[] = []; // block id of each program line (index: line - 1)
const warned = new Map<string, string[]>(); // a block's problems, each in its bubble
let compiling = 0;
let compiles = 0; // the compiles asked for: only the newest one's answer counts
let pendingLoad: unknown = null; // a workspace to load once Blockly is up
let blocksPending = false; // the blocks changed and their program is not made yet (editor.blocks.pending)
let lastHighlight = "";
let saidFatal = false; // the status says why the blocks make no program
let code = { text: "", robosim: "", python: "" };
const changed = () => s.editor.signals.changed.dispatch("blocks");


export function initBlocks(studio: Studio): void {
  s = studio;
  editor = s.editor;
  editor.blocks = { mode: () => mode, setMode, json: workspaceJson, load: loadBlocks, fromText, record: recordBlock,
    dragging: () => !!ws?.isDragging(), pending: () => blocksPending };
  const sig = editor.signals;
  sig.robotShown.add(blocksRobot);
  sig.lineRunning.add(({ line }) => highlightBlockOfLine(line));
  sig.lineRefused.add(({ line, message }) => refusedLine(line, message));
  $("mode-blocks").onclick = () => setMode("blocks");
  $("mode-text").onclick = () => setMode("text");
  $("show-code").onclick = showCode;
  $("code-close").onclick = () => ($("code-dialog") as HTMLDialogElement).close();
  for (const b of document.querySelectorAll<HTMLButtonElement>("#code-tabs button"))
    b.onclick = () => codeTab(b.dataset.code as "text" | "robosim" | "python");
}

/** Shows the blocks or the text editor. */
function setMode(m: "text" | "blocks", fromProject = false): void {
  mode = m;
  $("blockly").hidden = m !== "blocks";
  $("text-editor").hidden = m !== "text";
  $("mode-blocks").setAttribute("aria-pressed", String(m === "blocks"));
  $("mode-text").setAttribute("aria-pressed", String(m === "text"));
  blocksReport.programMode = m;
  document.body.classList.toggle("blocks-mode", m === "blocks");
  if (m === "blocks") {
    ensureWorkspace();
    Blockly.svgResize(ws!);
    if (!fromProject && ws!.getAllBlocks(false).length === 0) fromText();
  }
  if (!fromProject) changed();
}

// Blockly's zelos renderer, but its CSS from the site's own file (the build writes it into
// app.css): a <style> Blockly would add is refused by the page's Content-Security-Policy.
// On a touch screen every target is 44 px or more (docs/studio.md): zelos sizes its blocks in
// grid units (a number's box is 8), so there a unit is 5.5 px, not 4 (which gave 23 px at the
// desktop's scale 0.7), and the workspace starts at scale 1; the text keeps its size.
const TOUCH = typeof matchMedia === "function" && matchMedia("(pointer: coarse)").matches;
class Constants extends Blockly.zelos.ConstantProvider {
  constructor() {
    super(TOUCH ? 5.5 : undefined);
  }
  protected override injectCSS_(): void {}
}
class Renderer extends Blockly.zelos.Renderer {
  protected override makeConstants_(): Blockly.zelos.ConstantProvider {
    return new Constants();
  }
}

// A warning's bubble (Blockly's TextBubble) sets its text's direction with a style attribute,
// which the Content-Security-Policy refuses (style-src 'self'; Firefox says so in its console):
// the same paragraph, its direction set through the CSSOM, which the policy allows.
function paragraphWithoutStyleAttribute(): void {
  const proto = Blockly.bubbles.TextBubble.prototype as unknown as { createParagraph(container: SVGGElement): SVGGElement;
    workspace: Blockly.WorkspaceSvg };
  proto.createParagraph = function (this: typeof proto, container: SVGGElement): SVGGElement {
    const p = Blockly.utils.dom.createSvgElement(Blockly.utils.Svg.G, {
      class: "blocklyText blocklyBubbleText blocklyNoPointerEvents",
      transform: `translate(0,${Blockly.bubbles.Bubble.BORDER_WIDTH})`,
    }, container);
    p.style.direction = this.workspace.RTL ? "rtl" : "ltr";
    return p;
  };
}

// A finger drags one block, not the stack under it: on a tablet, a block dragged to the bin
// took the four below it with it. A mouse drags the stack (Ctrl or Cmd: one block), as Blockly
// does everywhere; a drag made by mistake is one tap on Undo away.
function touchDragsOneBlock(): void {
  const proto = Blockly.dragging.BlockDragStrategy.prototype as unknown as {
    shouldHealStack(e?: PointerEvent | KeyboardEvent): boolean };
  const asBlockly = proto.shouldHealStack;
  proto.shouldHealStack = function (this: unknown, e?: PointerEvent | KeyboardEvent): boolean {
    return (e instanceof PointerEvent && (e.pointerType === "touch" || e.pointerType === "pen")) || asBlockly.call(this, e);
  };
}

/** A warning's text in lines of about `width` characters: Blockly's bubble does not wrap, and a
 *  long one-line bubble reached past the workspace's left edge and over the blocks beside. */
function wrapWords(text: string, width = 38): string {
  const out: string[] = [];
  for (const para of text.split("\n")) {
    let line = "";
    for (const word of para.split(" ")) {
      if (line && line.length + 1 + word.length > width) {
        out.push(line);
        line = word;
      } else line = line ? `${line} ${word}` : word;
    }
    out.push(line);
  }
  return out.join("\n");
}

// Blockly's Undo and Redo (its workspace menu, a long press on a tablet) are the Editor's: one
// History for the blocks and everything else (its Ctrl+Z the page takes before Blockly sees it).
function historyMenu(): void {
  const reg = Blockly.ContextMenuRegistry.registry;
  for (const [id, label, act, can] of [
    ["undoWorkspace", "Undo", () => editor?.undo(), () => editor?.history.canUndo],
    ["redoWorkspace", "Redo", () => editor?.redo(), () => editor?.history.canRedo],
  ] as const) {
    const weight = reg.getItem(id)?.weight ?? 1;
    if (reg.getItem(id)) reg.unregister(id);
    reg.register({ id, weight, displayText: label, scopeType: Blockly.ContextMenuRegistry.ScopeType.WORKSPACE,
      preconditionFn: () => (can() ? "enabled" : "disabled"), callback: () => void act() });
  }
}

function ensureWorkspace(): void {
  if (ws) return;
  const t0 = performance.now();
  defineBlocks();
  historyMenu();
  paragraphWithoutStyleAttribute();
  touchDragsOneBlock();
  Blockly.blockRendering.unregister("zelos");
  Blockly.blockRendering.register("zelos", Renderer);
  if (s.editor.robot) robotMenus(s.editor.robot);
  ws = Blockly.inject($("blockly"), {
    toolbox: toolbox(s.editor.robot?.places ?? null), css: false, sounds: false, media: "assets/blockly-media/", trashcan: true, renderer: "zelos", theme: Blockly.Themes.Classic,
    zoom: { controls: true, startScale: TOUCH ? 1 : 0.7, wheel: false }, move: { scrollbars: true, drag: true, wheel: true },
    grid: { spacing: 24, length: 2, colour: "#dde4ec", snap: true },
  });
  ws.addChangeListener(onChange);
  ws.addChangeListener(tapToAdd);
  // a press in the toolbox's flyout arms tapToAdd; a press anywhere else disarms it
  $("blockly").addEventListener("pointerdown", (e) => {
    flyoutPress = !!(e.target as Element).closest?.(".blocklyFlyout");
  }, true);
  new ResizeObserver(() => ws && Blockly.svgResize(ws)).observe($("blockly"));
  if (pendingLoad) {
    load(pendingLoad);
    pendingLoad = null;
  }
  requestAnimationFrame(() => (blocksReport.blocksFirstPaintMs = performance.now() - t0));
}

// A block tapped (not dragged) in the toolbox joins the end of the program: on a tablet or a
// phone, and for anyone, it builds a program without a drag. (Blockly makes the tapped block
// where the toolbox showed it; a dragged one is made while the workspace drags.)
let flyoutPress = false;
function tapToAdd(e: Blockly.Events.Abstract): void {
  if (e.type !== Blockly.Events.BLOCK_CREATE || !flyoutPress || !ws) return;
  flyoutPress = false;
  if (ws.isDragging()) return;
  const block = ws.getBlockById((e as Blockly.Events.BlockCreate).blockId ?? "");
  if (!block || !block.previousConnection || block.getParent()) return;
  // the program: the topmost stack of statements (procedure definitions aside)
  const main = ws.getTopBlocks(true).find((b) => b !== block && b.nextConnection !== null && !b.type.startsWith("procedures_def"));
  const end = main?.lastConnectionInStack(false);
  if (!main) block.moveTo(new Blockly.utils.Coordinate(24, 24));
  else if (end && ws.connectionChecker.canConnect(end, block.previousConnection, false)) end.connect(block.previousConnection);
  ws.scrollBoundsIntoView?.((block as Blockly.BlockSvg).getBoundingRectangleWithoutChildren());
}

function onChange(e: Blockly.Events.Abstract): void {
  if (e.isUiEvent) return;
  clearTimeout(compiling);
  blocksPending = true;
  compiling = window.setTimeout(compile, 150);
}

/** The workspace as Blockly's JSON (what a project keeps). */
function workspaceJson(): object | null {
  return ws ? Blockly.serialization.workspaces.save(ws) : (pendingLoad as object | null);
}

/** A project's blocks (null: none). */
function loadBlocks(json: unknown): void {
  lineBlocks = [];
  if (!ws) {
    pendingLoad = json;
    return;
  }
  load(json);
}

function load(json: unknown): void {
  Blockly.Events.disable();
  try {
    ws!.clear();
    if (json) Blockly.serialization.workspaces.load(json as object, ws!);
  } finally {
    Blockly.Events.enable();
  }
  if (json) compile();
}

// The menus that are the robot's: its joints, and the pins its drive leaves for signals.
function robotMenus(r: { joints: RobotMsg["joints"]; wiring?: RobotMsg["wiring"] }): void {
  setJoints(r.joints);
  setPins(r.wiring?.io_pins ?? [], r.wiring?.header_pins ?? []);
}

/** The robot changed: the joint and pin menus follow it, and the toolbox's points are where it reaches. */
function blocksRobot(r: RobotMsg): void {
  robotMenus(r);
  if (!ws) return;
  ws.updateToolbox(toolbox(r.places));
  compile();
}

/** Unrolls the blocks and asks the engine for their program. */
function compile(): void {
  if (!ws) return;
  const mine = ++compiles;
  blocksPending = true;
  const settled = () => {
    if (mine === compiles) blocksPending = false;
  };
  clearWarnings();
  let ops;
  blocksReport.blockStacks = ws.getTopBlocks(false).filter((b) => b.type !== "procedures_defnoreturn" && !b.isShadow()).length;
  try {
    ops = unroll(Blockly.serialization.workspaces.save(ws));
  } catch (e) {
    settled();
    if (e instanceof BlockError) return blockProblem(e.block, e.message, true);
    throw e;
  }
  s.engine.call({ type: "blocks_compile", ops }).then((m) => {
    if (mine !== compiles) return; // a newer compile is under way
    settled();
    const r = m as { text?: string; robosim?: string; python?: string; lines?: string[]; problems?: { block: string; message: string }[];
      error?: { block: string; message: string } };
    if (r.error) return blockProblem(r.error.block, r.error.message, true);
    fatalMended();
    lineBlocks = r.lines ?? [];
    code = { text: r.text ?? "", robosim: r.robosim ?? "", python: r.python ?? "" };
    blocksReport.blocksCode = code;
    if (mode === "blocks") s.editor.program.set(code.text, "blocks.arm"); // (in text mode the text is the student's)
    for (const p of r.problems ?? []) blockProblem(p.block, p.message, false);
    changed();
  }, (err: Error) => {
    settled();
    blockProblem("", err.message, true);
  });
}

function clearWarnings(): void {
  for (const id of warned.keys()) ws?.getBlockById(id)?.setWarningText(null);
  warned.clear();
  blocksReport.blockProblems = [];
}

/** The blocks make a program again: the status that said why they did not goes (typing "-95"
 * passes through "-", whose problem must not outlive it). */
function fatalMended(): void {
  if (!saidFatal) return;
  saidFatal = false;
  s.editor.signals.programSaid.dispatch({ text: "" });
}

/** A problem on a block: its warning, the panel's status (`fatal`: no program made). */
export function blockProblem(id: string, message: string, fatal: boolean): void {
  const b = id ? ws?.getBlockById(id) : null;
  if (b) {
    const all = [...(warned.get(id) ?? []), message];
    warned.set(id, all);
    b.setWarningText(all.map((m) => wrapWords(m)).join("\n\n"));
  }
  blocksReport.blockProblems = [...blocksReport.blockProblems, { block: id, message }];
  if (fatal) {
    saidFatal = true;
    s.editor.signals.programSaid.dispatch({ text: message, bad: true });
  }
}

/** The program's line `line` is running: its block lights up. */
function highlightBlockOfLine(line: number): void {
  if (!ws || mode !== "blocks") return;
  const id = line > 0 ? lineBlocks[line - 1] ?? "" : "";
  if (id === lastHighlight) return;
  lastHighlight = id;
  ws.highlightBlock(id || null);
  blocksReport.runningBlock = id;
}

/** The arm (or the model) refused line `line`: the refusal goes on its block. */
function refusedLine(line: number, message: string): void {
  if (mode !== "blocks") return; // the text's line: no block made it
  const id = lineBlocks[line - 1];
  if (id) blockProblem(id, message, false);
}

/** The editor's text as blocks (the engine reads it; its comments kept). */
function fromText(): void {
  const ed = $("editor") as HTMLTextAreaElement;
  if (!ed.value.trim()) return;
  s.engine.call({ type: "program_ops", text: ed.value, name: s.editor.program.name() || "program.arm" }).then((m) => {
    const r = m as { ops?: []; error?: string };
    if (r.error) {
      blockProblem("", `The text cannot be read as blocks: ${r.error}`, true);
      return;
    }
    loadBlocks(opsToWorkspace(r.ops ?? []));
  }, (err: Error) => blockProblem("", err.message, true));
}

/** Record: a pose as a block at the end of the program: the joints (to 0.001, so it replays to
 * the same steps), the tool point, a straight line to it, or the gripper. Named, it is a
 * function of that name (Blockly's own) holding the block, called there: a waypoint to call
 * again from the Functions category. */
function recordBlock(m: { kind: string; q: number[]; xyz?: number[]; line: string }, name: string): void {
  if (!ws) return;
  const num = (v: number) => ({ shadow: { type: "math_number", fields: { NUM: Math.round(v * 1000) / 1000 } } });
  const words = m.line.trim().split(/\s+/).map(Number);
  const xyz = m.xyz ?? [0, 0, 0];
  const block: Blockly.serialization.blocks.State =
    m.kind === "P" ? { type: "arm_tool_to", inputs: { X: num(xyz[0]), Y: num(xyz[1]), Z: num(xyz[2]) } }
    : m.kind === "T" ? { type: "arm_line_to", inputs: { X: num(xyz[0]), Y: num(xyz[1]), Z: num(xyz[2]), SPEED: num(words[4] ?? 30) } }
    : m.kind === "G" ? { type: "arm_gripper_to", inputs: { PERCENT: num(words[1] ?? 0) } }
    : { type: "arm_joints", fields: { VALUES: m.q.map((v) => String(Math.round(v * 1000) / 1000)).join(", ") } };
  const tops = ws.getTopBlocks(true).filter((t) => t.type !== "procedures_defnoreturn");
  let last: Blockly.BlockSvg | null = tops[0] ?? null;
  while (last?.getNextBlock()) last = last.getNextBlock() as Blockly.BlockSvg | null;
  let added: Blockly.BlockSvg;
  if (name) {
    // the function beside the program, then its call at the program's end
    const right = Math.max(0, ...ws.getTopBlocks(false).map((t) => t.getBoundingRectangle().right)) + 30;
    const def = Blockly.serialization.blocks.append({ type: "procedures_defnoreturn", x: right, y: 20, fields: { NAME: name },
      inputs: { STACK: { block } } }, ws) as Blockly.BlockSvg;
    added = Blockly.serialization.blocks.append({ type: "procedures_callnoreturn", extraState: { name: def.getFieldValue("NAME") } }, ws) as Blockly.BlockSvg;
  } else {
    added = Blockly.serialization.blocks.append(block, ws) as Blockly.BlockSvg;
  }
  if (last?.nextConnection && added.previousConnection) last.nextConnection.connect(added.previousConnection);
  else added.moveBy(20, 20);
  s.editor.taught = m.kind === "M" ? (block.fields as { VALUES: string }).VALUES : m.line;
}

function showCode(): void {
  const d = $("code-dialog") as HTMLDialogElement;
  if (mode === "text") code.text = ($("editor") as HTMLTextAreaElement).value;
  codeTab("text");
  d.show();
}

function codeTab(which: "text" | "robosim" | "python"): void {
  for (const b of document.querySelectorAll<HTMLButtonElement>("#code-tabs button"))
    b.setAttribute("aria-pressed", String(b.dataset.code === which));
  $("code-text").textContent = code[which] || (which === "text" ? "" : "(make the program from blocks to see it this way)");
}
