// Types of avr-nano.mjs for TypeScript.
import type { CPU } from "avr8js";
import type { NanoParts } from "../../../../virtual-nano/web/nano-parts.mjs";
export const CLOCK_HZ: number;
export const PAGE_BYTES: number;
export const BOOT_START: number;
export const RESET_POWER: number, RESET_EXTERNAL: number, RESET_WATCHDOG: number;
export function parseHex(text: string, size?: number): { flash: Uint8Array; used: number };
export class VirtualNano {
  constructor(options: { hex: string; parts: NanoParts; eeprom?: Uint8Array; bootloader?: string; image?: Uint8Array; cnc?: boolean;
    servos?: { pin: string; zeroUs: number }[] | null });
  readonly cpu: CPU;
  readonly flash: Uint8Array;
  readonly flashUsed: number;
  readonly flashWrites: number;
  /** Cycles the CPU spent asleep (the firmware idles with SLEEP): skipped, not run. */
  readonly sleptCycles: number;
  readonly overruns: number;
  hostBaud: number;
  reset(cause: number): void;
  setDtr(on: boolean): void;
  readonly servoPulseUs: number | null;
  onLine: ((line: string) => void) | null;
  onByte: ((byte: number) => void) | null;
  /** After any motor's step (its steps already counted), at the CPU's cycle. */
  onStep: ((cycle: number) => void) | null;
  send(data: string | ArrayLike<number>): void;
  /** Drives header pin `pin` ("A5") from outside at `level` (0 or 1), as W reads it. */
  drive(pin: string, level: number): void;
  /** Header pin `pin`'s level as this Nano drives it: an output's (O), else its pull-up's. */
  level(pin: string): number;
  readonly seconds: number;
  readonly steps: number[];
  readonly coilFaults: number;
  runFor(seconds: number): void;
  runUntil(cycle: number): void;
  eepromBytes(): Uint8Array;
  delete(): void;
}
