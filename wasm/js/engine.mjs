// wasm/js/engine.mjs - the web engine for JavaScript: wasm/src's classes and functions with the
// JSON parsed and errors thrown as EngineError (what the CLI would print: the file, the JSON
// path or the line, and the problem). No logic of its own, as python/articula holds none.
//
//   import { loadEngine } from "./engine.mjs";
//   const engine = await loadEngine();            // in a page or worker: engine.wasm beside engine.mjs
//   engine.writeFile("/robots/mk2plus.json", text);
//   const mk2 = engine.robot("mk2plus");           // a shipped robot's name, or a path in the engine's files
//   mk2.pose([0, 90, -90]).tool.xyz                // [235, 0, 213]
//
// The engine's file system is in memory: robots, scenes and meshes are written into it by
// the caller (the studio's worker fetches them from the site), as a file on disk is read by
// the CLI.

/** An error the engine reported: message as the CLI words it, with file, json_path, line. */
export class EngineError extends Error {
  constructor(info) {
    super(info.error);
    this.name = "EngineError";
    Object.assign(this, info);
    delete this.error;
  }
}

function checked(text) {
  const value = JSON.parse(text);
  if (value && typeof value === "object" && !Array.isArray(value) && typeof value.error === "string")
    throw new EngineError(value);
  return value;
}

function loaded(text) {
  if (text) throw new EngineError(JSON.parse(text));
}

export class Robot {
  constructor(engine) {
    this.engine = engine;
    this.h = new engine.M.Robot();
    this.scratch = null;
  }
  /** A shipped robot's name ("mk2plus": /robots/mk2plus.json) or a robot file's path. */
  load(nameOrPath) { loaded(this.h.load(nameOrPath)); this._info = null; return this; }
  /** A robot file's JSON text; `name` stands for the file in messages and mesh paths. */
  parse(text, name = "robot.json") { loaded(this.h.parse(text, name)); this._info = null; return this; }
  /** A robot file of the thesis's system (appendix C) at `scale` mm per unit. */
  fromLegacy(text, name, scale) { loaded(this.h.fromLegacy(text, name, scale)); this._info = null; return this; }
  /** RoboSim's l: the adjustable rows' lengths a(i-1), mm, in row order. */
  setLinkLengths(values) { loaded(this.h.setLinkLengths(JSON.stringify(values))); this._info = null; return this; }

  /** name, description, source, joints, dh, home, limits, motors, links, gripper, reach_mm, ... */
  get info() { return (this._info ??= checked(this.h.info())); }
  /** The Nano's robot configuration for this robot: {name, checksum (the banner's K), lines
   * ($100 ... N name, $199 last), has_point}. Throws EngineError with the reason a Nano cannot
   * drive it. */
  nanoConfig() { return checked(this.h.nanoConfig()); }
  /** Frames (base, rows, tool: 16 numbers each, row-major), tool {xyz, rpy}, dh_table,
   * within_limits, and fingers at the gripper's opening (mm). */
  pose(q, openingMm = NaN) { return checked(this.h.pose(JSON.stringify(q), openingMm)); }
  /** The Jacobian of the tool point at q: 6 rows (velocity mm, rotation deg) per deg or mm of q. */
  jacobian(q) { return checked(this.h.jacobian(JSON.stringify(q))); }
  /** `articula ik --json`'s result for {target, solver, start, weights, max_iterations}. */
  ik(args) { return checked(this.h.ik(JSON.stringify(args))); }
  predict(text, name = "program.arm", settings = "") { return checked(this.engine.M.predict(this.h, text, name, settings)); }
  run(text, name = "program.arm") { return checked(this.engine.M.run(this.h, text, name)); }
  quantize(lines) { return checked(this.engine.M.quantize(this.h, JSON.stringify(lines))); }
  /** The program as its parser reads it: {format, statements, comments} (host/lib/records_json.h). */
  parseProgram(text, name = "program.arm") { return checked(this.engine.M.parseProgram(this.h, text, name)); }
  programFormat(text, name = "") { return this.engine.M.programFormat(text, name); }
  /** Whether a program fits this robot: {fits, other_arm (written for an arm of another shape), line, problem}. */
  programFit(text, name = "program.arm") { return checked(this.engine.M.programFit(this.h, text, name)); }
  /** The program of the studio's block actions: {text, robosim, lines, problems}, or
   * {error: {block, message}} (host/lib/blocks.h). */
  blocksProgram(ops) { return checked(this.engine.M.blocksProgram(this.h, JSON.stringify(ops))); }
  /** A program's text as block actions: {ops, format}. */
  programActions(text, name = "program.arm") { return checked(this.engine.M.programActions(this.h, text, name)); }
  /** One protocol line, as every tool here writes it: protocolLine("P", [200, 0, 50]). */
  protocolLine(word, values = []) { return checked(this.engine.M.protocolLine(this.h, word, JSON.stringify(values))); }
  /** The line that moves the arm to joint values q (deg or mm): M with the motors' angles. */
  moveLine(q) { return checked(this.engine.M.moveLine(this.h, JSON.stringify(q))); }
  /** A drawing for a pen in the gripper (`articula draw`): {text | shape, width, at, z, pen, ...}
   * -> {what, bounds, strokes, reach, start, travel_mm, travel_unordered_mm, program}. */
  draw(request) { return checked(this.engine.M.drawing(this.h, JSON.stringify(request))); }
  /** Where on an area of the table the pen reaches the paper: {area [min_x, min_y, max_x,
   * max_y], cell, z, pen} -> {rows, cols, cell, area, reached: "0110..." row after row}. */
  reachMap(request) { return checked(this.engine.M.reachMap(this.h, JSON.stringify(request))); }
  /** The ink the pen leaves (on the paper below half its lift): {steps: [flat rows of motor
   * counts] | tool: [x, y, z, ...], z, pen, lift} -> {strokes, points}. */
  ink(request) { return checked(this.engine.M.ink(this.h, JSON.stringify(request))); }
  /** A program's ink against a target drawing, both ways: {program, target (a draw request), z,
   * pen, tolerance} -> {met, ink_off_mm, uncovered_mm, says, target, ink, ...}. */
  drawingCheck(request) { return checked(this.engine.M.drawingCheck(this.h, JSON.stringify(request))); }
  urdf() { return checked(this.h.urdf()).xml; }
  jointsFromMotors(u) { return checked(this.h.jointsFromMotors(JSON.stringify(u))); }
  motorsFromJoints(q) { return checked(this.h.motorsFromJoints(JSON.stringify(q))); }

  /** The hot path: the tool pose of q (model units: rad or mm) as a Float64Array(16) view
   * into the engine's memory, valid until the next call. */
  fkModel(q) {
    const s = this._scratch();
    s.set(q);
    this.h.fkScratch();
    return this._scratch().subarray(64, 80);
  }
  /** The hot path of IK (the benchmark's): start q (model units), target [x, y, z] mm or
   * [x, y, z, roll, pitch, yaw] mm and rad; solver 0 auto, 1 closed, 2 lm, 3 jt. Returns
   * {status (0 reached .. 3 budget), q (a view), error_mm}. */
  ikModel(q, target, solver = 0) {
    const s = this._scratch();
    s.set(q);
    s.set(target, 32);
    const status = this.h.ikScratch(target.length, solver);
    const v = this._scratch();
    return { status, q: v.subarray(64, 64 + q.length), error_mm: v[63] };
  }
  _scratch() {
    // The memory may have grown (a new buffer): the view is made anew when it did.
    const heap = this.engine.M.HEAPF64;
    if (!this.scratch || this.scratch.buffer !== heap.buffer) {
      const at = this.h.scratch() / 8;
      this.scratch = heap.subarray(at, at + 1024);
    }
    return this.scratch;
  }
  delete() { this.h.delete(); }
}

export class Sim {
  /** robot: a Robot; scene: its file's text ("" or null: the ground only). */
  constructor(engine, robot, sceneText = "", sceneName = "scene.json", dt = engine.M.defaultDt) {
    this.h = new engine.M.Sim();
    try {
      loaded(this.h.create(robot.h, sceneText ?? "", sceneName, dt));
    } catch (e) {
      this.h.delete();
      throw e;
    }
    this.objects = checked(this.h.objects());
    this.sceneName = this.h.sceneName();
    this.dt = dt;
  }
  step(n = 1) { this.h.step(n); }
  /** `n` world steps; the tool point (x, y, z mm, flat) after every `every`-th and the last. */
  stepPath(n, every = 1) { return Float64Array.from(this.h.stepPath(n, every)); }
  runUntil(t) { this.h.runUntil(t); }
  loadProgram(text, name = "program.arm") { loaded(this.h.loadProgram(text, name)); }
  /** One protocol line for the simulated controller: "ok" or "error:N". */
  command(line) { return this.h.command(line); }
  events(since = 0) { return checked(this.h.events(since)); }
  state() { return checked(this.h.state()); }
  drag(name, xyz) { loaded(this.h.drag(String(name), xyz[0], xyz[1], xyz[2])); }
  release() { this.h.release(); }
  /** Runs a belt of the scene (its object's name) at mm/s along its own x; 0 stops it. */
  setBelt(name, mmS) { loaded(this.h.setBelt(String(name), Number(mmS))); }
  /** From power-up, the objects where the scene file has them. */
  reset() { this.h.reset(); }
  /** From power-up, each object a drag let go of where it was let go. */
  restart() { this.h.restart(); }
  get time() { return this.h.time(); }
  get busy() { return this.h.busy(); }
  get done() { return this.h.done(); }
  get endTime() { return this.h.endTime(); }
  delete() { this.h.delete(); }
}

export class Cell {
  /** A cell (cells/README.md) from its file's text; the robots, scenes and programs it names are
   * read from the engine's files (writeFile: /robots/NAME.json, paths from `dir`). */
  constructor(engine, text, name = "cell.json", dir = "/cells", dt = engine.M.defaultDt) {
    this.h = new engine.M.Cell();
    try {
      loaded(this.h.create(text, name, dir, dt));
    } catch (e) {
      this.h.delete();
      throw e;
    }
    this.name = this.h.name();
    this.arms = checked(this.h.arms());
    this.objects = checked(this.h.objects());
    this.dt = dt;
  }
  step(n = 1) { this.h.step(n); }
  runUntil(t) { this.h.runUntil(t); }
  run() { this.h.run(); }
  /** One arm now, by name: {name, robot, robot_ref, base, io: [{name, pin, mode}], program, program_end_s, line, joints, tool_mm,
   * gripper_mm, counted_steps, lost_steps, signals}. */
  arm(name) { return checked(this.h.arm(String(name))); }
  /** {t, arms, objects: [{name, xyz_mm, pose, carried_by, removed}]}. */
  state() { return checked(this.h.state()); }
  events(since = 0) { return checked(this.h.events(since)); }
  /** The last deadlock in words, or "". */
  get deadlock() { return this.h.deadlock(); }
  /** The table's mat: an SVG document, 1:1 in mm (host/physics/mat.h). */
  matSvg() { return this.h.matSvg(); }
  /** One arm's prediction in the cell, as Robot.predict gives it. */
  predict(name) { return checked(this.h.predict(String(name))); }
  reset() { this.h.reset(); }
  get time() { return this.h.time(); }
  get done() { return this.h.done(); }
  get endTime() { return this.h.endTime(); }
  delete() { this.h.delete(); }
}

export class Timeline {
  /** A program's time line on `robot` (host/lib/timeline.h): predicted (a robot with motors,
   * from power-up) or run from startQ (deg or mm). {start_q, duration, summary, format,
   * records} in `doc`; `at(t)` the arm at time t. */
  constructor(engine, robot, text, name, startQ) {
    this.h = new engine.M.Timeline();
    try {
      this.doc = checked(this.h.make(robot.h, text, name, JSON.stringify(startQ)));
    } catch (e) {
      this.h.delete();
      throw e;
    }
  }
  /** {t, line, q, q_ideal, steps, error_mm, gripper}. */
  at(t) { return checked(this.h.at(t)); }
  get duration() { return this.h.duration(); }
  delete() { this.h.delete(); }
}

export class Engine {
  constructor(M) {
    this.M = M;
    this.status = checked(M.statusTable());
    // The controller's settings (shared/articula/settings.h): [min, max, default] by number.
    this.settings = JSON.parse(M.settingsTable());
    // The pen's settings (host/lib/draw.h kPenFields): [{key, default, min, max, min_excluded, unit, what}].
    this.penFields = JSON.parse(M.penFields());
  }
  robot(nameOrPath) {
    const r = new Robot(this);
    if (nameOrPath !== undefined) {
      try {
        r.load(nameOrPath);
      } catch (e) {
        r.delete();
        throw e;
      }
    }
    return r;
  }
  sim(robot, sceneText, sceneName, dt) { return new Sim(this, robot, sceneText, sceneName, dt); }
  timeline(robot, text, name, startQ) { return new Timeline(this, robot, text, name, startQ); }
  cell(text, name, dir, dt) { return new Cell(this, text, name, dir, dt); }
  statusText(code) { return this.M.statusText(code); }
  /** A line from the arm read by the core's parsers (host/lib/protocol_view.h): {kind: "reply" |
   * "status" | "info" | "setting" | "other", ...}. */
  parseArmLine(line) { return JSON.parse(this.M.parseArmLine(line)); }
  /** A protocol line as the arm acts on it: before its comment, no blanks around it; "" for a
   * blank line or a comment alone (host/lib/program.h line_command). */
  lineCommand(line) { return this.M.lineCommand(line); }
  /** The firmware's step timer, ticks a second (shared/articula/motion.h). */
  get stepTickHz() { return this.M.stepTickHz; }
  /** The first step interval of a move from rest at $0 = maxRate, $1 = accel (motion.h), s. */
  firstIntervalS(maxRate, accel) { return this.M.firstIntervalS(maxRate, accel); }
  /** The sim-vs-real experiment's numbers (host/lib/experiment.h), as Python's articula has them:
   * per-axis errors {mm, pct (null: none)} of a position against a reference, both [x, y, z] mm. */
  axisErrors(value, reference) { return checked(this.M.axisErrors(JSON.stringify(value), JSON.stringify(reference))); }
  /** The thesis's Table 4 from points [{joint, value, reference}]: [{joint, poses, axes: [{max_pct, max_mm, avg_mm}]}]. */
  table4(points) { return checked(this.M.table4(JSON.stringify(points))); }
  /** A verdict per joint from single-joint poses [{joint, ideal, quant, measured|null}]. */
  /** A plan's repeatability chains from its commands [{line, repeat}]. */
  repeatChains(commands) { return checked(this.M.repeatChains(JSON.stringify(commands))); }
  /** The experiment as CSV: the measurements first (the harness's --measured format), then the tables. */
  experimentCsv(experiment) { return checked(this.M.experimentCsv(JSON.stringify(experiment))); }
  jointVerdicts(points) { return checked(this.M.jointVerdicts(JSON.stringify(points))); }
  /** The thesis's Table 5 from repeatability chains (host/lib/experiment.h): [{chain, moves,
   * back_moves, dest_error_mm, return_error_mm, measured_dest_mm, measured_return_mm,
   * return_from_measured_start}]. */
  table5(chains) { return checked(this.M.table5(JSON.stringify(chains))); }
  /** The tool sent to points (P), from [{line, target, quant, ideal, measured}]: [{line,
   * model_from_target_mm, ideal_from_target_mm, measured_from_target_mm, measured_from_model_mm}]. */
  toolPoints(points) { return checked(this.M.toolPoints(JSON.stringify(points))); }
  /** A test plan (hil/plans/README.md): {name, title, notes, commands: [{line, text, expect,
   * timeout_s, single_joint, repeat, kind}]}; EngineError naming name:line. */
  parsePlan(text, name = "plan.arm") { return checked(this.M.parsePlan(text, name)); }
  /** The question a typed tool position raises ("" when it looks right). */
  measurementQuestion(measured, predicted, reachMm, farMm = this.M.measurementFarMm) {
    return checked(this.M.measurementQuestion(JSON.stringify(measured), JSON.stringify(predicted), reachMm, farMm));
  }
  /** Files of the engine's in-memory file system (folders are made on the way). */
  writeFile(path, data) {
    const parts = path.split("/").filter(Boolean);
    let dir = "";
    for (const p of parts.slice(0, -1)) {
      dir += "/" + p;
      if (!this.exists(dir)) this.M.FS.mkdir(dir);
    }
    this.M.FS.writeFile(path, data);
  }
  exists(path) { return this.M.FS.analyzePath(path).exists; }
  readFile(path) { return this.M.FS.readFile(path); }
  removeFile(path) { if (this.exists(path)) this.M.FS.unlink(path); }
  chdir(path) { this.M.FS.chdir(path); }
}

/** The engine, ready. options go to emscripten's module: wasmBinary (bytes, for node) or
 * locateFile (where engine.wasm is). */
export async function loadEngine(createEngine, options = {}) {
  return new Engine(await createEngine(options));
}
