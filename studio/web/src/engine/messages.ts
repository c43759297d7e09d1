// The messages between the page and its engine (engine/worker.ts), and from its arm link (link/arm-link.ts) to
// the arm panel (docs/studio.md, "Messages"). The engine computes every pose; the page sends intents
// and draws what comes back.

export type Flat4x4 = number[]; // a 4x4 homogeneous matrix, row-major, mm

export interface Joint {
  name: string;
  row: number;
  param: "theta" | "d" | "alpha";
  unit: "deg" | "mm";
  min: number;
  max: number;
}

export interface Shape {
  type: "box" | "cylinder" | "capsule" | "sphere" | "mesh";
  size: number[];
  pose: Flat4x4;
  url?: string;
  format?: string;
}

export interface Places {
  tool: number[]; line_to: number[]; pen: number; paper_z: number; draw_at: number[]; draw_width: number; fits: boolean;
}

export interface RobotMsg {
  type: "robot";
  name: string;
  description: string;
  source: string;
  shipped: string; // the shipped robot's name in the site's list ("": opened from a file; engine/state.ts shippedName)
  joints: Joint[];
  dh: Record<string, unknown>[];
  num_rows: number;
  home: number[];
  motors: string[];
  links: { frame: number; shapes: Shape[] }[];
  gripper: null | {
    max_opening_mm: number;
    finger_length_mm: number;
    finger_thickness_mm: number;
    finger_height_mm: number;
    servo_open_deg: number;
    servo_closed_deg: number;
  };
  reach_mm: number;
  // where the toolbox's blocks and a new sheet point for this arm, all within its reach (the
  // engine's example_places_json: host/lib/blocks.h)
  places: Places;
  // the firmware build that drives its motors: "articula-nano" (L298N, ULN2003), "articula-cnc"
  // (STEP/DIR drivers in a CNC shield), "articula-servo" (hobby servos)
  firmware: string;
  // a servo arm's servos in motor order: each one's signal pin and its pulse at step 0 (us)
  servos?: { pin: string; zeroUs: number }[] | null;
  // every wire (host/lib/wiring.h): its board, and each pin and what it feeds; error: none
  wiring?: { board: string; board_title: string; given: boolean; firmware: string; error?: string;
    wires: { pin: string; signal: string; part: string; motor: string | null }[];
    supply?: string[]; // what the wires alone do not say: the supply, its ground, jumpers (host/lib/wiring.h)
    io_pins?: { pin: number; name: string }[]; // the pins the drive leaves for O and W (signals)
    header_pins?: string[] }; // every header pin's name by its index ("D0" .. "A5")
  robots: string[];
  programs: string[];
  import_notes: string[];
  keep_view?: boolean; // the same robot with other link lengths: keep the camera and the program
}

export interface PoseMsg {
  type: "pose";
  q: number[];
  frames: Flat4x4[]; // base, frame 1..n, tool
  tool: { xyz: number[]; rpy: number[] };
  dh_table: number[][]; // a, alpha, d, theta per row
  gripper: number;
  within_limits: boolean;
  fingers?: Flat4x4[];
  tip?: number[]; // the pen's tip (x, y, z mm) when a pen is held: where the page aims
  trail?: number[]; // in the live physics: the tool point's path since the last frame (x, y, z mm, flat), this pose's last
  motors?: number[]; // the motors' angles (deg), for a robot with motors
  ghost?: Flat4x4[];
  ghost_fingers?: Flat4x4[]; // the ghost's fingers, posed by the engine
  seq?: number | null;
  t?: number;
  line?: number;
  steps?: number[] | null;
  error_mm?: number;
}

export interface IkMsg {
  type: "ik" | "jt_frame";
  status: "reached" | "unreachable" | "limited" | "budget";
  solver: string;
  position_error_mm: number;
  orientation_error_deg: number;
  iterations: number;
  limited_by: string[];
  beyond_reach: boolean;
  // not reached: what holds the tool back and how near it comes (the engine's words: ik_miss_words)
  why?: string;
  // a pen held (mm below the tool point; 0: none): the target was its tip
  pen_mm?: number;
  seq?: number | null;
  iteration?: number;
  done?: boolean;
}

export interface TimelineRecord {
  line: number;
  command: string;
  reply: string;
  code: number;
  error: string;
  note: string;
  start_s: number;
  end_s: number;
  q: number[];
  q_ideal: number[];
  tool: number[];
  tool_ideal: number[];
  error_mm: number;
  steps: number[] | null;
  gripper: number | null;
  path: number[]; // predicted: the tool after every step, x y z after x y z (mm)
  straight: { from: number[]; to: number[]; error_mm: number } | null; // a straight line (T)
}

export interface TimelineMsg {
  type: "timeline";
  name: string;
  format: "protocol" | "robosim";
  records: TimelineRecord[];
  duration: number;
  start_tool?: number[]; // the tool where the program starts (mm)
  joints: string[];
  // the path the arm takes, for the plots and the CSV: the time line sampled at every action's
  // start and end and evenly between, the tool at each (a move is the curve it is)
  samples: { t: number[]; line: number[]; q: number[][]; tool: number[][] };
  summary: Record<string, number>;
}

export interface SceneObjectInfo {
  name: string;
  type: "box" | "cylinder" | "sphere";
  size: number[];
  movable: boolean;
  mass_kg: number;
  belt?: number; // mm/s: a conveyor belt's top face (0: not a belt)
}

export interface SceneMsg {
  type: "scene";
  name: string | null; // null: no physics
  title: string;
  world?: Record<string, unknown> | null; // a scene of the student's own (the scene editor's), as its file
  objects: SceneObjectInfo[];
  scenes: string[];
  sized_for?: Record<string, string[]>; // each scene's arms (none: any): the menu offers a scene to them first
  cells?: string[]; // the shipped cells (several arms), for the Cell menu
}

/** A cell opened (several arms, cells/README.md), or closed (name null). */
/** A cell's device (cells/README.md): a belt and a feeder the wires run, a light barrier and a switch on a wire. */
export interface CellDevice {
  name: string; kind: "belt" | "barrier" | "switch" | "feeder"; pin: string; level: boolean;
  object?: string; running?: boolean; // a belt
  from_mm?: number[]; to_mm?: number[]; broken_by?: string | null; // a barrier
  at_mm?: number[]; size_mm?: number[]; pressed_by?: string | null; // a switch (at_mm: a feeder's outlet too)
  objects?: string[]; every_s?: number; left?: number; // a feeder
}

export interface CellMsg {
  type: "cell";
  name: string | null;
  title?: string;
  objects?: SceneObjectInfo[];
  arms?: { name: string; robot: RobotMsg; base: { xyz: number[]; yaw: number }; io: { name: string; pin: string; number: number; mode: string;
    driven_by: string | null; by_device: boolean }[];
    program: string; shipped: string; timeline: CellTimeline }[];
  wires?: { from: string; to: string }[];
  devices?: CellDevice[];
}

/** One arm's lines in time, as its own firmware runs them in the cell (engine Cell.predict), or
 * why there are none (an arm without motors). */
export interface CellTimeline {
  end_s?: number;
  why?: string;
  lines: { line: number; command: string; ok: boolean; start_s: number; end_s: number }[];
}

/** Run all refused a program: the arm (null: not one arm's), its line (1-based; 0: the program
 * as a whole) and why. The cell runs on as it was. */
export interface CellRefusedMsg {
  type: "cell_refused";
  arm: string | null;
  line: number;
  text: string;
  programs: string[]; // the programs refused, as the tabs hold them
}

/** A cell's world now: each arm's frames (in its base frame) and line, the objects, new events. */
export interface CellFrameMsg {
  type: "cell_frame";
  t: number;
  running: boolean;
  done: boolean;
  fresh?: boolean;
  deadlock: string;
  events: SimEvent[];
  arms: { name: string; line: number; joints?: number[]; frames: Flat4x4[]; fingers?: Flat4x4[]; program_end_s: number;
    signals: { kind: string; line: number; pin: string; name: string; level: number; t: number; end_t?: number | null; met?: boolean | null }[] }[];
  objects: { name: string; pose: Flat4x4; removed: boolean; carried: boolean }[];
  devices?: CellDevice[];
}

export interface SimEvent {
  t: number;
  kind: string;
  arm?: string; // a cell's: the arm whose action it is
  line: number;
  a: string;
  b: string;
  point_mm?: number[];
  detail?: string;
}

export interface PhysicsMsg {
  type: "physics";
  on: boolean;
  fresh?: boolean; // a new or reset simulation: its events start here
  line?: number; // the program's line the simulated controller carries out (0: none)
  t?: number;
  busy?: boolean;
  objects?: { name: string; pose: Flat4x4; carried: boolean; removed: boolean; movable: boolean }[];
  contacts?: string[][];
  events?: SimEvent[];
  steps?: number[];
  lost?: number[];
  rtf?: number | null;
  capacity?: number | null;
  behind?: boolean;
  running?: boolean;
}

export interface ArmStatusMsg {
  type: "arm_status";
  state: string;
  steps: number[];
  angles: number[];
  q: number[];
  frames: Flat4x4[];
  text: string;
  stop_to_idle_ms?: number;
  rtt_ms: number | null; // the page's `?` to this report
  sent_ms: number; // when the page read it (epoch ms)
}

export type EngineMsg =
  | ArmStatusMsg
  | { type: "arm"; connected: boolean; connecting?: boolean; port?: string; label?: string; info?: Record<string, unknown>; error?: string; lost?: boolean;
      configurable?: boolean; configuring?: { done: number; total: number; name: string } }
  | { type: "arm_configured"; name: string; checksum: number }
  | { type: "arm_reply"; line: string; reply: string | null; meaning?: string; error?: string;
      // output: what the arm printed for the line before its reply (`$`'s settings, `I`'s
      // banner; a typed `?`: its status report, with reply "status")
      predicted: { reply: string; steps: number[] | null; meaning: string; seconds?: number }; output?: string[] }
  | { type: "arm_stopped" }
  | { type: "arm_program"; line?: number; command?: string; reply?: string; meaning?: string; done?: boolean;
      sent?: number; error?: string; stopped?: boolean; predicted?: { reply: string }; paused?: boolean; resumed?: boolean;
      seconds?: number } // seconds: how long the program took on the arm's clock (less its pauses)
  | SceneMsg
  | PhysicsMsg
  | CellMsg
  | CellFrameMsg
  | CellRefusedMsg
  | { type: "sim_command"; line: string; seq?: number | null }
  | RobotMsg
  | PoseMsg
  | IkMsg
  | TimelineMsg
  | { type: "robot_error"; message: string }
  // a program that cannot be read: every line that cannot be read (problems), the first as line
  | { type: "program_error"; message: string; line: number; problems?: { line: number; problem: string }[] }
  | { type: "program_text"; name: string; text: string }
  | { type: "playing"; t: number; playing: boolean; ended?: boolean; paused_at?: number } // paused_at: after a breakpoint's line
  | { type: "teach"; kind: string; line: string; q: number[]; xyz?: number[] }
  | { type: "urdf"; name: string; xml: string }
  | { type: "error"; message: string; request?: string | null; id?: number }
  | { type: "arm_read"; id: number; parsed: unknown; pose: { q: number[]; frames: Flat4x4[] } | null }
  | { type: "arm_predicted"; id: number; command: string; reply: string; steps: number[] | null; meaning: string; seconds?: number }
  | { type: "arm_config"; id: number; config: NanoConfig | { error: string } };

/** The robot shown as a Nano's configuration (the engine's nanoConfig, host/lib/nano_config.h). */
export interface NanoConfig { name: string; checksum: number; lines: string[]; has_point: boolean }
