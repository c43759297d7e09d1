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
export class NanoParts {
  readonly wiring: {
    motors: { port: "B" | "C" | "D"; shift: number }[];
    endstops: { port: "B" | "C" | "D"; bit: number }[];
    servo: { port: "B" | "C" | "D"; bit: number };
    led: { port: "B" | "C" | "D"; bit: number };
  };
  coilDecoder(): CoilDecoder;
  servoAngleDeg(widthUs: number): number;
  servoAperturePercent(angleDeg: number, closedDeg: number, openDeg: number): number;
}
export function loadNanoParts(createNanoParts: (options: object) => Promise<unknown>, options?: object): Promise<NanoParts>;
