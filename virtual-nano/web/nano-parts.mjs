// virtual-nano/web/nano-parts.mjs - the virtual Nano's parts for an emulated Nano in JavaScript
// (virtual-nano/web/nano_parts.cpp: nano.mjs and nano.wasm, a few kilobytes, no engine): a motor's coil
// decoder (virtual-nano/coil_decoder.h), STEP/DIR decoder (step_dir_decoder.h) or servo decoder (servo_decoder.h), the board's pins (firmware/src/board.h) and the
// servo's scale (shared/articula/servo.h). The studio's nano worker and node's tests use it.
//
//   const parts = await loadNanoParts(createNanoParts);   // nano.wasm beside nano.mjs
//   parts.wiring.motors[0]                                  // {port: "D", shift: 4}

export class NanoParts {
  constructor(M) {
    this.M = M;
    /** The board's pins: motors [{port, shift}], endstops [{port, bit}], servo and led {port, bit}. */
    this.wiring = JSON.parse(M.boardWiring(false));
    /** A CNC shield's: motors [{port, step, dir}] (STEP/DIR drivers), enable {port, bit}, the rest as above. */
    this.cncWiring = JSON.parse(M.boardWiring(true));
    /** The firmware's step timer, ticks a second (shared/articula/motion.h). */
    this.stepTickHz = M.stepTickHz;
  }
  /** A motor's coil decoder: feed(pattern) -> 0 nothing, 1 step, 2 released, 3 energised, 4 fault. */
  coilDecoder() { return new this.M.CoilDecoder(); }
  /** A STEP/DIR driver's decoder: feed(step, dir, enabled, cycle) -> 0 nothing, 1 step, 4 fault. */
  stepDirDecoder() { return new this.M.StepDirDecoder(); }
  /** A hobby servo's pulse decoder (ticks of cyclesPerTick, position less zeroTicks): feed(level, cycle)
   * -> 0 nothing, 1 the position moved, 2 a pulse within the deadband. */
  servoDecoder(cyclesPerTick, zeroTicks) { return new this.M.ServoDecoder(cyclesPerTick, zeroTicks); }
  /** A header pin by name ("D9"): {port, bit}, or null. */
  headerPin(name) { return JSON.parse(this.M.headerPin(name)); }
  /** The servo angle a pulse width asks for, deg. */
  servoAngleDeg(widthUs) { return this.M.servoAngleDeg(widthUs); }
  /** The gripper's aperture an angle gives, %, between the robot's closed and open angles. */
  servoAperturePercent(angleDeg, closedDeg, openDeg) { return this.M.servoAperturePercent(angleDeg, closedDeg, openDeg); }
}

/** The parts, ready. options go to emscripten's module: wasmBinary or locateFile. */
export async function loadNanoParts(createNanoParts, options = {}) {
  return new NanoParts(await createNanoParts(options));
}
