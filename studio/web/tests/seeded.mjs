// A seeded random source for the node tests (a linear congruential generator): the same seed,
// the same numbers, so a failing case can be run again. Shared by nano-fuzz.test.mjs and
// nano-busy-page.test.mjs.

/** Numbers in [0, 1) from `seed`. */
export function rng(seed) {
  let s = seed >>> 0;
  return () => ((s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 2 ** 32);
}
