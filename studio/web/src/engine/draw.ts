// Drawing and writing, in the engine's worker: the page's request (text, a shape or an SVG
// file's text; its width, place, the paper's height, the pen) goes to the engine as it is
// (host/lib/draw.h, which checks every key and value), and back comes the drawing: its strokes,
// the reach check, the program, and the line the arm will draw, step by step.
import { EngineError } from "../../../../wasm/js/engine.mjs";
import { BadMessage } from "./checks";
import type { Msg, Out } from "./checks";
import { fetchBytes } from "./site";
import { S } from "./state";

// Where the engine reads the font (host/lib/draw.h, default_font_path): the site ships it.
const FONT = "/usr/share/hershey-fonts/futural.jhf";

/** The font where the engine reads it, fetched from the site once. */
export async function ensureFont(): Promise<void> {
  if (!S.engine.exists(FONT)) S.engine.writeFile(FONT, await fetchBytes("data/fonts/futural.jhf"));
}

// The page's request as it is to the engine, which checks every key and value: its answer, or
// its refusal in words, as a message of `type`.
function answer(type: string, m: Msg, ask: (req: Record<string, unknown>) => object): Out[] {
  const req = m.request;
  if (typeof req !== "object" || req === null || Array.isArray(req)) throw new BadMessage("'request' must be an object");
  try {
    return [{ type, ...ask(req as Record<string, unknown>) }];
  } catch (e) {
    if (!(e instanceof EngineError)) throw e;
    return [{ type, error: e.message }];
  }
}

export const drawHandlers: Record<string, (m: Msg) => Promise<Out[]>> = {
  async draw(m) {
    await ensureFont();
    return answer("drawing", m, (req) => S.robot.draw(req));
  },
  // Where on the sheet the pen reaches the paper: the paper view shades it.
  async reach_map(m) {
    return answer("reach_map", m, (req) => S.robot.reachMap(req as { area: number[] }));
  },
  // The ink the virtual Nano's steps (its step counts, row after row) or the physics' tool
  // leave, by the engine's rule for where the pen touches the paper (the prediction's too).
  async ink(m) {
    return answer("ink", m, (req) => S.robot.ink(req as { steps?: number[]; tool?: number[] }));
  },
};
