// Flashing the Nano on the chosen port (link/stk500.mjs) with this site's firmware for the robot's
// drivers (one build for every arm on L298N or ULN2003 boards, one for STEP/DIR drivers in a CNC
// shield: the robot is configured after, in the arm panel): its version and size from
// data/firmware/firmware.json, a progress bar, and a sentence for every way it can fail.
import { FlashError, TRIES, flashNano } from "../link/stk500.mjs";
import { $, status } from "../page/dom";
import type { Studio } from "../page/context";

interface FirmwareInfo { file: string; bytes: number; version: string; sha256: string }
let builds: Record<string, FirmwareInfo> = {};
let firmware: FirmwareInfo | null = null; // the build the robot shown needs

let s: Studio;

export function initFlash(studio: Studio): void {
  s = studio;
  $("arm-flash").onclick = () => void flashFirmware();
  s.editor.signals.robotShown.add(() => showFirmware());
  void loadFirmwareInfo();
}

async function loadFirmwareInfo(): Promise<void> {
  try {
    const r = await fetch(new URL("data/firmware/firmware.json", document.baseURI));
    const j = r.ok ? ((await r.json()) as FirmwareInfo & { builds?: Record<string, FirmwareInfo> }) : null;
    builds = j ? j.builds ?? { "articula-nano": j } : {};
  } catch {
    builds = {};
  }
  showFirmware();
}

// The build for the robot shown, and what it is for.
function showFirmware(): void {
  const needs = s.editor.robot?.firmware ?? "articula-nano";
  firmware = builds[needs] ?? null;
  const what = needs === "articula-cnc"
    ? "the build for a CNC shield, for every arm it can drive on STEP/DIR drivers (A4988, DRV8825, TMC2208/2209)"
    : needs === "articula-servo"
    ? "the build for servo arms, for every arm of up to three hobby servos and a gripper"
    : "for every arm it can drive on L298N or ULN2003 boards (up to three steppers and a gripper)";
  $("flash-info").textContent = firmware
    ? `Articula ${firmware.version}, ${firmware.bytes.toLocaleString("en")} bytes: ${what}`
    : "this site carries no firmware for this robot";
  ($("arm-flash") as HTMLButtonElement).disabled = !firmware;
}

/** The flasher's state (window.articula.flash shows it): busy guards against a second flash. */
export const flashStatus = { busy: false, phase: "", done: 0, total: 0, attempt: 0, error: "", errorKind: "",
  result: null as { bytes: number; pages: number; baud: number; seconds: number; attempts: number } | null };

const flashState = (text: string, kind: "" | "ok" | "bad" = "") => status($("flash-state"), text, kind);

async function flashFirmware(): Promise<void> {
  const f = flashStatus;
  if (f.busy || !firmware) return;
  const chosen = await s.editor.arm.choosePort();
  if ("why" in chosen) return chosen.why ? flashState(chosen.why, "bad") : undefined;
  await s.editor.arm.disconnect(); // the bootloader needs the port to itself
  Object.assign(f, { busy: true, phase: "connect", done: 0, total: 0, error: "", errorKind: "", result: null });
  const bar = $("flash-progress") as HTMLProgressElement;
  const button = $("arm-flash") as HTMLButtonElement;
  button.disabled = true;
  bar.hidden = false;
  bar.value = 0;
  flashState("resetting the Nano into its bootloader…");
  try {
    const r = await fetch(new URL(`data/firmware/${firmware.file}`, document.baseURI));
    if (!r.ok) throw new Error(`the firmware's file is missing from this site (${r.status})`);
    const result = await flashNano(chosen.port, await r.text(), {
      onProgress: (p) => {
        Object.assign(f, { phase: p.phase, done: p.done, total: p.total, attempt: p.attempt });
        // writing is two thirds of the bar, reading back the last third
        const part = p.total ? p.done / p.total : 0;
        bar.value = { connect: 0, write: (2 * part) / 3, verify: (2 + part) / 3, done: 1 }[p.phase];
        // a flash that stalled starts again from the reset: said, so that the bar going back is no surprise
        const again = p.attempt > 1 ? `the Nano stopped answering, so the flash started again (try ${p.attempt} of ${TRIES}): ` : "";
        if (p.phase === "connect" && again) flashState(`${again}resetting the Nano into its bootloader…`);
        else if (p.phase === "write") flashState(`${again}writing page ${p.done} of ${p.total} (${p.baud.toLocaleString("en")} baud)`);
        else if (p.phase === "verify") flashState(`${again}reading back page ${p.done} of ${p.total}`);
      },
    });
    f.result = result;
    f.phase = "done";
    flashState(`Flashed and verified: ${result.bytes.toLocaleString("en")} bytes in ${result.seconds.toFixed(1)} s ` +
      `(${result.baud === 115200 ? "Optiboot" : "the old bootloader"}, ${result.baud.toLocaleString("en")} baud). ` +
      "Connect: a Nano keeps the robot it was configured for; if it is not this one, Configure the Nano for this robot.", "ok");
  } catch (e) {
    f.error = (e as Error).message;
    f.errorKind = e instanceof FlashError ? e.kind : "other";
    flashState(`Flashing failed: ${f.error}`, "bad");
  } finally {
    f.busy = false;
    button.disabled = false;
    // after a failure the same button is the retry, and says so
    button.textContent = f.error ? "Flash again" : "Flash firmware";
  }
}
