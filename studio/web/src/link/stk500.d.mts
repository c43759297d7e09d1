// Types of stk500.mjs for TypeScript.
import type { SerialLike } from "./ports";
export const SIGNATURE: number[];
export const BAUD_RATES: number[];
export const STALL_MS: number;
export const TRIES: number;
export type FlashErrorKind = "hex" | "no-bootloader" | "signature" | "verify" | "vanished" | "stalled";
export class FlashError extends Error {
  readonly kind: FlashErrorKind;
}
export interface FlashProgress {
  phase: "connect" | "write" | "verify" | "done";
  done: number;
  total: number;
  baud: number;
  /** The try this is, from 1 (a flash that stalls starts again from the reset). */
  attempt: number;
}
export function firmwarePages(hexText: string): { pages: [number, Uint8Array][]; bytes: number };
export function flashNano(port: SerialLike, hexText: string, options?: { onProgress?: (p: FlashProgress) => void; baudRates?: number[]; tries?: number }):
  Promise<{ bytes: number; pages: number; baud: number; seconds: number; attempts: number }>;
