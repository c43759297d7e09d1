// Types of wasm/js/engine.mjs for TypeScript (the studio's worker).
export class EngineError extends Error {
  constructor(info: { error: string; [k: string]: unknown });
  file?: string;
  json_path?: string;
  line?: number;
}
export class Robot {
  load(nameOrPath: string): Robot;
  parse(text: string, name?: string): Robot;
  fromLegacy(text: string, name: string, scale: number): Robot;
  setLinkLengths(values: number[]): Robot;
  readonly info: Record<string, unknown>;
  pose(q: number[], openingMm?: number): Record<string, unknown>;
  ik(args: Record<string, unknown>): Record<string, unknown>;
  predict(text: string, name?: string, settings?: string): Record<string, unknown>;
  run(text: string, name?: string): Record<string, unknown>;
  quantize(lines: string[]): Record<string, unknown>[];
  programFormat(text: string, name?: string): "protocol" | "robosim";
  urdf(): string;
  jointsFromMotors(u: number[]): number[];
  motorsFromJoints(q: number[]): number[];
  fkModel(q: ArrayLike<number>): Float64Array;
  ikModel(q: ArrayLike<number>, target: ArrayLike<number>, solver?: number): { status: number; q: Float64Array; error_mm: number };
  delete(): void;
}
export class Sim {
  readonly objects: { name: string; type: string; size: number[]; movable: boolean; mass_kg: number }[];
  readonly sceneName: string;
  readonly dt: number;
  step(n?: number): void;
  runUntil(t: number): void;
  loadProgram(text: string, name?: string): void;
  command(line: string): string;
  events(since?: number): Record<string, unknown>[];
  state(): Record<string, unknown>;
  drag(name: string, xyz: number[]): void;
  release(): void;
  reset(): void;
  readonly time: number;
  readonly busy: boolean;
  readonly done: boolean;
  readonly endTime: number;
  delete(): void;
}
export interface CoilDecoder {
  feed(pattern: number): number; // 0 no change, 1 step, 2 released, 3 energised, 4 fault
  forceHalfStep(): void;
  steps(): number;
  halfSteps(): number;
  faults(): number;
  pattern(): number;
  delete(): void;
}
export class Engine {
  readonly status: Record<string, [string, string]>;
  robot(nameOrPath?: string): Robot;
  sim(robot: Robot, sceneText?: string, sceneName?: string, dt?: number): Sim;
  statusText(code: number): string;
  coilDecoder(): CoilDecoder;
  firstIntervalS(maxRate: number, accel: number): number;
  /** The servo angle a pulse width asks for, and the gripper's aperture at that angle (hil/vnano/servo.h). */
  servoAngleDeg(widthUs: number): number;
  servoAperturePercent(angleDeg: number, closedDeg: number, openDeg: number): number;
  parseArmLine(line: string):
    | { kind: "reply"; code: number }
    | { kind: "status"; state: string; steps: number[]; angles: number[]; gripper: number; free: number; coils: boolean; warning: number }
    | { kind: "info"; version: string; protocol: number; joints: number; robot: string; warning: number }
    | { kind: "other" };
  readonly nanoWiring: {
    motors: { port: "B" | "C" | "D"; shift: number }[];
    endstops: { port: "B" | "C" | "D"; bit: number }[];
    servo: { port: "B" | "C" | "D"; bit: number };
    led: { port: "B" | "C" | "D"; bit: number };
  };
  writeFile(path: string, data: string | Uint8Array): void;
  exists(path: string): boolean;
  readFile(path: string): Uint8Array;
  removeFile(path: string): void;
  chdir(path: string): void;
}
export function loadEngine(createEngine: (options: object) => Promise<unknown>, options?: object): Promise<Engine>;
