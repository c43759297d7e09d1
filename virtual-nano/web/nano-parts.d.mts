export interface CoilDecoder {
  feed(pattern: number): number; // 0 no change, 1 step, 2 released, 3 energised, 4 fault
  forceHalfStep(): void;
  setUnipolar(unipolar: boolean): void;
  steps(): number;
  halfSteps(): number;
  faults(): number;
  pattern(): number;
  delete(): void;
}
export interface StepDirDecoder {
  feed(step: boolean, dir: boolean, enabled: boolean, cycle: number): number; // 0 nothing, 1 step, 4 fault
  steps(): number;
  faults(): number;
  minPulseCycles(): number; // -1: none yet
  minDirSetupCycles(): number;
  delete(): void;
}
export interface ServoDecoder {
  feed(level: boolean, cycle: number): number; // 0 nothing, 1 the position moved, 2 a pulse within the deadband
  steps(): number;
  pulses(): number;
  lastWidthCycles(): number;
  maxOffCycles(): number;
  faults(): number;
  delete(): void;
}
type Pin = { port: "B" | "C" | "D"; bit: number };
export class NanoParts {
  readonly wiring: {
    motors: { port: "B" | "C" | "D"; shift: number }[];
    endstops: { port: "B" | "C" | "D"; bit: number }[];
    servo: { port: "B" | "C" | "D"; bit: number };
    led: { port: "B" | "C" | "D"; bit: number };
  };
  readonly cncWiring: {
    motors: { port: "B" | "C" | "D"; step: number; dir: number }[];
    enable: Pin;
    endstops: Pin[];
    servo: Pin;
    led: Pin;
  };
  coilDecoder(): CoilDecoder;
  stepDirDecoder(): StepDirDecoder;
  servoDecoder(cyclesPerTick: number, zeroTicks: number): ServoDecoder;
  headerPin(name: string): Pin | null;
  servoAngleDeg(widthUs: number): number;
  servoAperturePercent(angleDeg: number, closedDeg: number, openDeg: number): number;
}
export function loadNanoParts(createNanoParts: (options: object) => Promise<unknown>, options?: object): Promise<NanoParts>;
