// Types of stk500.mjs for TypeScript.
import type { SerialLike } from "./ports";
export const SIGNATURE: number[];
export const BAUD_RATES: number[];
export type FlashErrorKind = "hex" | "no-bootloader" | "signature" | "verify" | "vanished";
export class FlashError extends Error {
  readonly kind: FlashErrorKind;
}
export interface FlashProgress {
  phase: "connect" | "write" | "verify" | "done";
  done: number;
  total: number;
  baud: number;
}
export function firmwarePages(hexText: string): { pages: [number, Uint8Array][]; bytes: number };
export function flashNano(port: SerialLike, hexText: string, options?: { onProgress?: (p: FlashProgress) => void; baudRates?: number[] }):
  Promise<{ bytes: number; pages: number; baud: number; seconds: number }>;
