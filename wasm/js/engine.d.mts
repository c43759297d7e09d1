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
  jacobian(q: number[]): number[][];
  ik(args: Record<string, unknown>): Record<string, unknown>;
  predict(text: string, name?: string, settings?: string): Record<string, unknown>;
  run(text: string, name?: string): Record<string, unknown>;
  quantize(lines: string[]): Record<string, unknown>[];
  programFormat(text: string, name?: string): "protocol" | "robosim";
  parseProgram(text: string, name?: string): ParsedProgram;
  programFit(text: string, name?: string): { fits: boolean; other_arm: boolean; line: number; problem: string };
  blocksProgram(ops: unknown[]): { text: string; robosim: string; lines: string[]; problems: { block: string; message: string }[] }
    | { error: { block: string; message: string } };
  programActions(text: string, name?: string): { ops: Record<string, unknown>[]; format: "protocol" | "robosim" };
  protocolLine(word: string, values?: number[]): string;
  moveLine(q: number[]): string;
  draw(request: Record<string, unknown>): {
    what: string; bounds: { min_x: number; min_y: number; max_x: number; max_y: number }; strokes: number[][][];
    reach: { fits: boolean; points: number; unreachable: number[][]; movable: boolean; move: number[]; advice: string };
    start: number[]; travel_mm: number; travel_unordered_mm: number; program: string; width_mm: number; height_mm: number;
    ink_lines: number[]; seconds?: number;
    ink?: { strokes: number[][][]; worst_mm: number; worst_at: number[]; worst_line: number; steps: number } };
  reachMap(request: { area: number[]; cell?: number; z?: number; pen?: number }):
    { rows: number; cols: number; cell: number; area: number[]; reached: string };
  ink(request: { steps?: number[]; tool?: number[]; z?: number; pen?: number; lift?: number }): { strokes: number[][][]; points: number };
  drawingCheck(request: { program: string; name?: string; target: Record<string, unknown>; z?: number; pen?: number; tolerance: number }): {
    met: boolean; ink_off_mm: number | null; uncovered_mm: number | null; ink_off_at: number[]; uncovered_at: number[];
    ink_points: number; says: string; what: string; target: number[][][]; ink: number[][][] };
  urdf(): string;
  jointsFromMotors(u: number[]): number[];
  /** The Nano's robot configuration for this robot; throws EngineError with the reason a Nano cannot drive it. */
  nanoConfig(): { name: string; checksum: number; lines: string[]; has_point: boolean };
  motorsFromJoints(q: number[]): number[];
  fkModel(q: ArrayLike<number>): Float64Array;
  ikModel(q: ArrayLike<number>, target: ArrayLike<number>, solver?: number): { status: number; q: Float64Array; error_mm: number };
  delete(): void;
}
export interface ParsedProgram {
  format: "protocol" | "robosim"; source: string;
  statements: ({ line: number; kind: string; values: number[] } | { line: number; kind: "protocol"; text: string; command: string; args: number[] })[];
  comments: { line: number; text: string; whole_line: boolean }[];
}
export class Sim {
  readonly objects: { name: string; type: string; size: number[]; movable: boolean; mass_kg: number }[];
  readonly sceneName: string;
  readonly dt: number;
  step(n?: number): void;
  stepPath(n: number, every?: number): Float64Array;
  runUntil(t: number): void;
  loadProgram(text: string, name?: string): void;
  command(line: string): string;
  events(since?: number): Record<string, unknown>[];
  state(): Record<string, unknown>;
  drag(name: string, xyz: number[]): void;
  release(): void;
  /** Runs a belt of the scene (its object's name) at mm/s along its own x; 0 stops it. */
  setBelt(name: string, mmS: number): void;
  /** From power-up, the objects where the scene file has them. */
  reset(): void;
  /** From power-up, each object a drag let go of where it was let go. */
  restart(): void;
  readonly time: number;
  readonly busy: boolean;
  readonly done: boolean;
  readonly endTime: number;
  delete(): void;
}
export class Cell {
  readonly name: string;
  readonly arms: string[];
  /** The scene's objects as the cell file gives them (name, type, size, movable, ...). */
  readonly objects: Record<string, unknown>[];
  readonly dt: number;
  /** The last deadlock in words, or "". */
  readonly deadlock: string;
  /** The table's mat: an SVG document, 1:1 in mm (host/physics/mat.h). */
  matSvg(): string;
  /** One arm's prediction in the cell, as Robot.predict gives it. */
  predict(name: string): Record<string, unknown>;
  step(n?: number): void;
  runUntil(t: number): void;
  run(): void;
  arm(name: string): Record<string, unknown>;
  state(): { t: number; arms: Record<string, unknown>[]; objects: { name: string; xyz_mm: number[]; pose: number[]; carried_by: string | null; removed: boolean }[] };
  events(since?: number): Record<string, unknown>[];
  reset(): void;
  readonly time: number;
  readonly done: boolean;
  readonly endTime: number;
  delete(): void;
}
export interface TimelineRecord {
  line: number; command: string; reply: string; code: number; error: string; note: string;
  start_s: number; end_s: number; q: number[]; q_ideal: number[]; tool: number[]; tool_ideal: number[];
  error_mm: number; steps: number[] | null; gripper: number | null;
}
/** The path the arm takes (host/lib/timeline.h, timeline_samples_json): column by column. */
export interface TimelineSamples { t: number[]; line: number[]; q: number[][]; tool: number[][] }
export class Timeline {
  readonly doc: { start_q: number[]; start_tool: number[]; duration: number; format: "protocol" | "robosim";
    summary: { commands: number; rejected: number; worst_error_mm?: number }; records: TimelineRecord[];
    samples: TimelineSamples };
  at(t: number): { t: number; line: number; q: number[]; q_ideal: number[]; steps: number[] | null; error_mm: number; gripper: number | null };
  readonly duration: number;
  delete(): void;
}
export interface PlanCommand {
  line: number; text: string; expect: string; timeout_s: number | null;
  single_joint: [number, number] | null; repeat: [number, "out" | "back"] | null;
  kind: "single-joint" | "repeat-out" | "repeat-back" | "target" | "";
}
export class Engine {
  readonly status: Record<string, [string, string]>;
  /** The controller's settings $0, $1, ... (shared/articula/settings.h): [min, max, default]. */
  readonly settings: [number, number, number][];
  /** The pen's settings of a drawing (host/lib/draw.h kPenFields): key, default and range. */
  readonly penFields: { key: string; default: number; min: number; max: number; min_excluded: boolean; unit: string; what: string }[];
  robot(nameOrPath?: string): Robot;
  sim(robot: Robot, sceneText?: string, sceneName?: string, dt?: number): Sim;
  timeline(robot: Robot, text: string, name: string, startQ: number[]): Timeline;
  cell(text: string, name?: string, dir?: string, dt?: number): Cell;
  statusText(code: number): string;
  firstIntervalS(maxRate: number, accel: number): number;
  /** A protocol line as the arm acts on it: before its comment, no blanks around it ("" for none). */
  lineCommand(line: string): string;
  /** The firmware's step timer, ticks a second. */
  readonly stepTickHz: number;
  axisErrors(value: number[], reference: number[]): { mm: number[]; pct: (number | null)[] };
  experimentCsv(experiment: Record<string, unknown>): string;
  repeatChains(commands: { line: number; repeat: [number, string] | null }[]):
    { chain: number; moves: number; back_moves: number; line_before: number | null; line_out: number; line_back: number | null }[];
  jointVerdicts(points: { joint: number; ideal: number[]; quant: number[]; measured: number[] | null }[]):
    { joint: number; measured: boolean; worst_mm: number; quant_mm: number; within: boolean; text: string }[];
  table4(points: { joint: number; value: number[]; reference: number[] }[]):
    { joint: number; poses: number; axes: { max_pct: number | null; max_mm: number; avg_mm: number }[] }[];
  measurementQuestion(measured: number[], predicted: number[], reachMm: number, farMm?: number): string;
  toolPoints(points: Record<string, unknown>[]): { line: number; model_from_target_mm: number; ideal_from_target_mm: number;
    measured_from_target_mm: number | null; measured_from_model_mm: number | null }[];
  table5(chains: Record<string, unknown>[]): { chain: number; moves: number; back_moves: number; dest_error_mm: number;
    return_error_mm: number | null; measured_dest_mm: number | null; measured_return_mm: number | null; return_from_measured_start: boolean }[];
  parsePlan(text: string, name?: string): { name: string; title: string; notes: string[]; commands: PlanCommand[] };
  parseArmLine(line: string):
    | { kind: "reply"; code: number }
    | { kind: "status"; state: string; at_rest: boolean; steps: number[]; angles: number[]; millideg: number[]; gripper: number; free: number; coils: boolean; warning: number }
    | { kind: "info"; version: string; protocol: number; joints: number; robot: string; checksum: number | null; warning: number }
    | { kind: "setting"; number: number; value: number }
    | { kind: "other" };
  writeFile(path: string, data: string | Uint8Array): void;
  exists(path: string): boolean;
  readFile(path: string): Uint8Array;
  removeFile(path: string): void;
  chdir(path: string): void;
}
export function loadEngine(createEngine: (options: object) => Promise<unknown>, options?: object): Promise<Engine>;
