// What the Nano's pins drive, read as the arm would see it (and as simavr's virtual Nano reads
// it): each motor's four L298N inputs through its coil decoder (or, on a CNC shield, its STEP/DIR
// driver's pins through a STEP/DIR decoder, virtual-nano/step_dir_decoder.h; or a servo's signal
// through a servo decoder, servo_decoder.h) (virtual-nano/coil_decoder.h, by
// the board's pins of firmware/src/board.h, both in the parts module: virtual-nano/web), and the
// servo's pulse width, the gripper's command.
export class PinWatch {
  /**
   * ports: avr8js's AVRIOPorts by name (B, C, D); parts: the virtual Nano's (virtual-nano/web/nano-parts.mjs);
   * cnc: the firmware is the build for a CNC shield, its motors on STEP/DIR drivers (the shield's pins);
   * servos: the firmware is the servo build, its motors hobby servos: [{pin: "D9", zeroUs}] in motor
   * order (each one's signal pin and its pulse at step 0), read by servo decoders (servo_decoder.h).
   */
  constructor(cpu, ports, parts, clockHz, cnc = false, servos = null) {
    this.cpu = cpu;
    const wiring = cnc ? parts.cncWiring : parts.wiring;
    const servoPins = servos ? servos.map((sv) => parts.headerPin(sv.pin)) : null;
    if (servoPins && servoPins.some((p) => !p)) throw new Error(`no such pin among ${servos.map((sv) => sv.pin).join(", ")}`);
    this.decoders = servos
      ? servos.map((sv) => parts.servoDecoder(clockHz / parts.stepTickHz, Math.round(sv.zeroUs * 2)))
      : wiring.motors.map(() => (cnc ? parts.stepDirDecoder() : parts.coilDecoder()));
    this.firstStepCycle = -1; // the first and last step of any motor since markSteps()
    this.lastStepCycle = -1;
    this.firstStepCycles = this.decoders.map(() => -1); // and of each motor
    this.lastStepCycles = this.decoders.map(() => -1);
    this.servoPulseUs = null; // the last pulse's width
    this.onStep = null; // (cycle) after any motor's step, its steps already counted
    let servoRise = -1;
    const last = {};
    this.listeners = {};
    for (const name of Object.keys(ports)) {
      last[name] = 0;
      ports[name].addListener(this.listeners[name] = (value) => {
        const changed = value ^ last[name];
        last[name] = value;
        const stepped = (i) => {
          if (this.firstStepCycle < 0) this.firstStepCycle = cpu.cycles;
          this.lastStepCycle = cpu.cycles;
          if (this.firstStepCycles[i] < 0) this.firstStepCycles[i] = cpu.cycles;
          this.lastStepCycles[i] = cpu.cycles;
          this.onStep?.(cpu.cycles);
        };
        if (servoPins) {
          // Each servo's signal: a pulse that moves its position is a step (of many ticks).
          servoPins.forEach((p, i) => {
            if (p.port === name && (changed >> p.bit) & 1 && this.decoders[i].feed(!!((value >> p.bit) & 1), cpu.cycles) === 1) stepped(i);
          });
        } else if (cnc) {
          // STEP, DIR and the drivers' EN (low: enabled), as the driver module reads them.
          const en = wiring.enable;
          const enabled = !((name === en.port ? value : last[en.port]) >> en.bit & 1);
          wiring.motors.forEach((m, i) => {
            if (m.port !== name && en.port !== name) return;
            const v = m.port === name ? value : last[m.port];
            if (this.decoders[i].feed(!!((v >> m.step) & 1), !!((v >> m.dir) & 1), enabled, cpu.cycles) === 1) stepped(i);
          });
        } else {
          wiring.motors.forEach((m, i) => {
            if (m.port === name && (changed >> m.shift) & 0xf && this.decoders[i].feed((value >> m.shift) & 0xf) === 1) stepped(i);
          });
        }
        const s = wiring.servo;
        if (s.port === name && (changed >> s.bit) & 1) {
          if ((value >> s.bit) & 1) servoRise = cpu.cycles;
          else if (servoRise >= 0) this.servoPulseUs = ((cpu.cycles - servoRise) * 1e6) / clockHz;
        }
      });
    }
    this.forgetPulse = () => (servoRise = -1);
  }

  /** A reset makes every pin an input: the coils and the servo go off. */
  reset() {
    for (const listener of Object.values(this.listeners)) listener(0);
    this.forgetPulse();
  }

  /** Each motor's steps as its coils moved it. */
  get steps() {
    return this.decoders.map((d) => d.steps());
  }

  get coilFaults() {
    return this.decoders.reduce((n, d) => n + d.faults(), 0);
  }

  /** Starts a new span of steps: firstStepCycle and lastStepCycle are -1 until the next step. */
  markSteps() {
    this.firstStepCycle = this.lastStepCycle = -1;
    this.firstStepCycles.fill(-1);
    this.lastStepCycles.fill(-1);
  }

  /** The first and last step since markSteps() of the motors given (indices): [-1, -1] if none. */
  stepSpan(motors) {
    const firsts = motors.map((i) => this.firstStepCycles[i]).filter((c) => c >= 0);
    return firsts.length ? [Math.min(...firsts), Math.max(...motors.map((i) => this.lastStepCycles[i]))] : [-1, -1];
  }

  delete() {
    for (const d of this.decoders) d.delete();
  }
}
