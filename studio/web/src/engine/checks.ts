// Checks of what the page sends the engine's worker: a bad message gets an error reply that
// names the field, never a crash.
export type Msg = Record<string, unknown>;
export type Out = Record<string, unknown>;

export class BadMessage extends Error {}

export const MAX_TEXT = 1_000_000; // characters of a robot file or program from the page

export function num(m: Msg, key: string, lo = -Infinity, hi = Infinity): number {
  const v = m[key];
  if (typeof v !== "number" || !Number.isFinite(v)) throw new BadMessage(`'${key}' must be a finite number`);
  if (v < lo || v > hi) throw new BadMessage(`'${key}' must be within ${lo} .. ${hi}`);
  return v;
}

export function numbers(m: Msg, key: string, counts: number[]): number[] {
  const v = m[key];
  if (!Array.isArray(v) || !counts.includes(v.length))
    throw new BadMessage(`'${key}' must be a list of ${counts.join(" or ")} numbers`);
  return v.map((x, i) => {
    if (typeof x !== "number" || !Number.isFinite(x)) throw new BadMessage(`'${key}[${i}]' must be a finite number`);
    return x;
  });
}

export function text(m: Msg, key: string, limit = MAX_TEXT): string {
  const v = m[key];
  if (typeof v !== "string") throw new BadMessage(`'${key}' must be text`);
  if (v.length > limit) throw new BadMessage(`'${key}' is larger than ${limit.toLocaleString("en")} characters`);
  return v;
}

export const round6 = (x: number) => Math.round(x * 1e6) / 1e6;
export const clamp = (v: number, lo: number, hi: number) => Math.min(Math.max(v, lo), hi);
