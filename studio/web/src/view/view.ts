// The 3D view: one three.js scene graph where each DH frame is a Group whose children are
// that frame's shapes and axes, so a pose from the engine is one matrix per frame (the page
// computes no kinematics). Z is up, lengths are millimetres, as in the robot files. Beside it
// in view/: the shapes (shapes.ts), the physics scene's objects (objects.ts), what is laid over
// the world (overlays.ts: paper, ink, paths, a goal) and the camera (camera.ts).
import * as THREE from "three";
import { CellArms } from "./cell-arms";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import { TransformControls } from "three/examples/jsm/controls/TransformControls.js";
import type { CellFrameMsg, CellMsg, Flat4x4, PhysicsMsg, PoseMsg, RobotMsg, SceneObjectInfo } from "../engine/messages";
import { cameraStateOf, frameArm, lookFrom, onScreen, orbitKey, viewpointOf } from "./camera";
import { SceneObjects } from "./objects";
import { Overlays } from "./overlays";
import { LINK_COLORS, label, setMatrix, shapeObject } from "./shapes";


export interface TargetChange {
  xyz: number[];
  rpy: number[]; // fixed X-Y-Z, deg
}

export class View {
  /** null where the browser gives the page no WebGL: the view is then a message, and the
   * scene is kept (poses, targets) without being drawn; every panel still works. */
  readonly renderer: THREE.WebGLRenderer | null;
  readonly canvas: HTMLCanvasElement;
  readonly scene = new THREE.Scene();
  readonly camera: THREE.PerspectiveCamera;
  readonly controls: OrbitControls;
  readonly gizmo: TransformControls;
  readonly target = new THREE.Group();
  frames: THREE.Group[] = [];
  ghost: THREE.Group[] = [];
  live: THREE.Group[] = []; // the arm itself, from its status reports
  private liveArm = new THREE.Group();
  fingers: THREE.Mesh[] = [];
  ghostFingers: THREE.Mesh[] = [];
  axes: THREE.Object3D[] = [];
  reach = 500;
  onTarget: (t: TargetChange, final: boolean) => void = () => {};
  onFrame: (now: number) => void = () => {};
  private arm = new THREE.Group();
  // The physics scene's objects (view/objects.ts) and what is laid over the world: the paper,
  // the ink, the paths, a goal (view/overlays.ts).
  private objects: SceneObjects;
  private overlays = new Overlays(() => (this.dirty = true), () => this.reach);
  onDrag: (object: string, target: number[] | null) => void = () => {};
  /** The user moved the camera (an orbit, a zoom, a pan ended). */
  onViewChange: () => void = () => {};
  private ghostArm = new THREE.Group();
  // A cell's arms (view/cell-arms.ts), shown instead of the single arm while a cell is open.
  readonly cellArms = new CellArms(() => (this.dirty = true));
  private cellReach = 0;
  private cellFit = false;
  private grid: THREE.GridHelper | null = null;
  // From the last frame's origin to the tool point: the tool offset, drawn for every robot.
  private toolLine = new THREE.Line(new THREE.BufferGeometry(), new THREE.LineBasicMaterial({ color: 0x9a3412 }));
  // a pen held in the gripper, hanging straight down from the tool point (setPen)
  private pen = new THREE.Mesh(new THREE.CylinderGeometry(1, 0.35, 1, 16).rotateX(Math.PI / 2),
    new THREE.MeshStandardMaterial({ color: 0x2563eb, roughness: 0.5 }));
  private penMm = 0;
  private toolDot = new THREE.Mesh(new THREE.SphereGeometry(1, 16, 12), new THREE.MeshStandardMaterial({ color: 0x9a3412 }));
  private ground: THREE.Mesh;
  private frameTimes: number[] = [];
  fps = 0;
  framesDrawn = 0;
  // Draw only when something changed (a pose, the camera, a toggle): a software renderer then
  // leaves the CPU to the rest. ?fps=continuous in the URL draws every display frame (to
  // measure the frame rate). Half a second with nothing to draw, and the loop stops asking for
  // display frames (each costs the browser work even when nothing is drawn: an idle page took
  // 1 CPU s in 10, and takes 0.2 asleep): it looks at the camera's controls and the flashing
  // objects ten times a second, and wakes at once when anything marks the view dirty.
  private needsDraw = true;
  get dirty(): boolean { return this.needsDraw; }
  set dirty(v: boolean) {
    this.needsDraw = v;
    if (v && this.sleeping) this.wake(); // (a timer id is never 0)
  }
  private sleeping: number | null = null; // the timer of the sleeping loop
  private idleFrames = 0;
  readonly continuous = new URLSearchParams(location.search).get("fps") === "continuous";
  // ?quality=low (a slow computer) also draws at most 20 frames a second while the arm moves:
  // a software renderer's frame is the page's largest cost then, and 20 still reads as motion.
  // ?fps=N draws at most N a second (the last pose is always drawn): a very slow computer, or
  // a test that looks at where the arm ends, not at the motion (studio/tests: 5).
  private minFrameMs = 0;
  /** The least time between two drawn frames, ms (0: every display frame). */
  get frameMs(): number { return this.minFrameMs; }
  private lastDrawn = -Infinity;

  readonly software: boolean;

  static softwareRenderer(): boolean {
    try {
      const gl = document.createElement("canvas").getContext("webgl2");
      const ext = gl?.getExtension("WEBGL_debug_renderer_info");
      const name = ext ? String(gl!.getParameter(ext.UNMASKED_RENDERER_WEBGL)) : "";
      gl?.getExtension("WEBGL_lose_context")?.loseContext();
      return /swiftshader|llvmpipe|software/i.test(name);
    } catch {
      return false;
    }
  }

  constructor(readonly host: HTMLElement) {
    // A software renderer (SwiftShader, llvmpipe: no GPU) draws with MSAA several times
    // slower: it gets no antialiasing, and a smaller drawing buffer when it still lags.
    // ?quality=high: full resolution and antialiasing whatever draws; ?quality=low: a third of
    // the screen's resolution, no antialiasing (a slow computer; a software renderer's frame then
    // costs a quarter of its CPU time).
    this.software = View.softwareRenderer();
    const q = new URLSearchParams(location.search).get("quality");
    if (q === "low") this.minFrameMs = 50;
    const cap = Number(new URLSearchParams(location.search).get("fps"));
    if (cap > 0 && Number.isFinite(cap)) this.minFrameMs = Math.max(this.minFrameMs, 1000 / cap);
    this.canvas = document.createElement("canvas");
    this.canvas.setAttribute("aria-label", "The arm in 3D: drag to orbit, arrow keys orbit, + and - zoom");
    this.canvas.tabIndex = 0;
    let renderer: THREE.WebGLRenderer | null = null;
    try {
      renderer = new THREE.WebGLRenderer({ canvas: this.canvas, antialias: q ? q === "high" : !this.software, preserveDrawingBuffer: true });
      renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2) * (q === "low" ? 0.35 : this.software && q !== "high" ? 0.6 : 1));
      renderer.outputColorSpace = THREE.SRGBColorSpace;
    } catch {
      const note = document.createElement("div");
      note.className = "no-webgl";
      note.setAttribute("role", "status");
      note.textContent = "This browser gives the page no WebGL, so the 3D view is off. Everything else works: " +
        "the joints, IK, programs, plots and the arm. (Turn on hardware acceleration, or try another browser.)";
      host.appendChild(note);
    }
    this.renderer = renderer;
    host.appendChild(this.canvas);
    this.scene.background = new THREE.Color(0xeef2f6);
    this.scene.fog = new THREE.Fog(0xeef2f6, 4000, 9000);

    this.camera = new THREE.PerspectiveCamera(40, 1, 1, 20000);
    this.camera.up.set(0, 0, 1);
    this.camera.position.set(900, -700, 600);
    this.controls = new OrbitControls(this.camera, this.canvas);
    this.controls.enableDamping = true;
    this.controls.dampingFactor = 0.15;
    this.controls.target.set(0, 0, 150);

    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8a94a6, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(600, -900, 1400);
    this.scene.add(sun);
    const fill = new THREE.DirectionalLight(0xdfe8ff, 0.6);
    fill.position.set(-800, 600, 400);
    this.scene.add(fill);

    this.ground = new THREE.Mesh(
      new THREE.CircleGeometry(1, 96),
      new THREE.MeshStandardMaterial({ color: 0xdde3ea, roughness: 0.95, metalness: 0 }),
    );
    this.ground.position.z = -0.5;
    this.scene.add(this.ground);
    this.objects = new SceneObjects(this.camera, this.canvas, this.controls, () => (this.dirty = true),
      (object, target) => this.onDrag(object, target));
    const o = this.overlays;
    this.scene.add(this.arm, this.ghostArm, this.objects.group, o.goal, this.liveArm, o.paths, o.drawing, this.cellArms.group);

    // The IK target: a ball with its own axes, moved by the gizmo.
    const ball = new THREE.Mesh(
      new THREE.SphereGeometry(1, 24, 16),
      // drawn over the arm: inside the gripper it would be hidden
      new THREE.MeshStandardMaterial({ color: 0xf4a259, emissive: 0x6b3a0c, roughness: 0.4, depthTest: false, transparent: true, opacity: 0.9 }),
    );
    ball.name = "target-ball";
    ball.renderOrder = 10;
    this.target.add(ball, new THREE.AxesHelper(1));
    this.target.visible = false;
    this.scene.add(this.target);
    this.gizmo = new TransformControls(this.camera, this.canvas);
    this.gizmo.setSize(0.8);
    this.gizmo.attach(this.target);
    this.gizmo.enabled = false;
    this.gizmo.getHelper().visible = false;
    this.scene.add(this.gizmo.getHelper());
    this.gizmo.addEventListener("dragging-changed", (e) => {
      this.controls.enabled = !(e as unknown as { value: boolean }).value;
      if (!(e as unknown as { value: boolean }).value) this.onTarget(this.targetValue(), true);
    });
    this.gizmo.addEventListener("objectChange", () => this.onTarget(this.targetValue(), false));

    // the view follows its box: a window resized, a tablet turned, the layout changed (layout.ts)
    new ResizeObserver(() => this.resize()).observe(host);
    this.controls.addEventListener("change", () => (this.dirty = true));
    this.controls.addEventListener("end", () => this.onViewChange());
    this.gizmo.addEventListener("change", () => (this.dirty = true));
    this.resize();
    if (this.renderer) requestAnimationFrame(this.frame);
  }

  resize(): void {
    const w = this.host.clientWidth || 800;
    const h = this.host.clientHeight || 600;
    this.renderer?.setSize(w, h, false);
    this.canvas.style.width = "100%";
    this.canvas.style.height = "100%";
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  }

  private frame = (now: number): void => {
    if (this.draw(now) || this.continuous) this.idleFrames = 0;
    else this.idleFrames++;
    if (this.idleFrames < 30) requestAnimationFrame(this.frame);
    else this.sleep();
  };

  private sleep(): void {
    this.sleeping = window.setTimeout(() => {
      this.sleeping = null;
      if (this.controls.update() || this.objects.tick(performance.now()) || this.needsDraw) this.dirty = true;
      if (this.needsDraw) this.wake();
      else this.sleep();
    }, 100);
  }

  private wake(): void {
    if (this.sleeping) window.clearTimeout(this.sleeping);
    this.sleeping = null;
    this.idleFrames = 0;
    requestAnimationFrame(this.frame);
  }

  // True when it drew, or has a frame to draw that the frame-rate limit put off.
  private draw(now: number): boolean {
    const moved = this.controls.update();
    if (this.objects.tick(now)) this.dirty = true;
    if (!(this.dirty || moved || this.continuous)) return false;
    if (now - this.lastDrawn < this.minFrameMs) {
      this.dirty = true;  // drawn at the next frame the limit allows
      return true;
    }
    this.lastDrawn = now;
    this.dirty = false;
    this.renderer!.render(this.scene, this.camera);
    this.framesDrawn++;
    this.frameTimes.push(now);
    while (this.frameTimes.length && now - this.frameTimes[0] > 1000) this.frameTimes.shift();
    this.fps = this.frameTimes.length;
    this.onFrame(now);
    return true;
  }

  // ---- the robot

  // Builds the robot's frames and shapes; resolves when every shape (meshes load from the
  // engine) is in the scene.
  build(robot: RobotMsg): Promise<void> {
    for (const g of [this.arm, this.ghostArm, this.liveArm]) {
      g.clear();
    }
    this.frames = [];
    this.ghost = [];
    this.live = [];
    this.axes = [];
    this.fingers = [];
    this.ghostFingers = [];
    this.reach = Math.max(200, robot.reach_mm);
    const n = robot.num_rows + 2; // base, frames 1..n, tool
    const axisSize = this.reach * 0.12;
    const ghostMat = new THREE.MeshStandardMaterial({
      color: 0x7fb7e6, transparent: true, opacity: 0.28, depthWrite: false, roughness: 0.6,
    });
    for (let i = 0; i < n; i++) {
      const g = new THREE.Group();
      g.matrixAutoUpdate = false;
      g.name = i === n - 1 ? "tool" : `frame ${i}`;
      this.frames.push(g);
      this.arm.add(g);
      const gg = new THREE.Group();
      gg.matrixAutoUpdate = false;
      this.ghost.push(gg);
      this.ghostArm.add(gg);
      const lg = new THREE.Group();
      lg.matrixAutoUpdate = false;
      this.live.push(lg);
      this.liveArm.add(lg);
      // Each frame's axes (x red, y green, z blue) and its number; hidden until asked for.
      const ax = new THREE.Group();
      const helper = new THREE.AxesHelper(i === n - 1 ? axisSize * 0.8 : axisSize);
      (helper.material as THREE.LineBasicMaterial).depthTest = false;
      helper.renderOrder = 5;
      ax.add(helper);
      const tag = label(i === n - 1 ? "T" : String(i), i === n - 1 ? "#9a3412" : "#1d3557");
      tag.scale.setScalar(axisSize * 0.38);
      tag.position.set(axisSize * 0.18, axisSize * 0.18, axisSize * 0.18);
      ax.add(tag);
      ax.visible = false;
      g.add(ax);
      this.axes.push(ax);
    }
    const liveMat = new THREE.MeshStandardMaterial({
      color: 0x2a9d8f, transparent: true, opacity: 0.45, depthWrite: false, roughness: 0.5,
    });
    this.liveArm.visible = false;
    const loading: Promise<void>[] = [];
    robot.links.forEach((link, li) => {
      const color = LINK_COLORS[li % LINK_COLORS.length];
      const mat = new THREE.MeshStandardMaterial({ color, roughness: 0.45, metalness: 0.15 });
      for (const s of link.shapes) {
        loading.push(shapeObject(s, mat).then((m) => {
          if (!m) return;
          m.name = `link ${link.frame}`;
          this.frames[link.frame].add(m);
          const gm = m.clone();
          gm.traverse((o) => {
            if ((o as THREE.Mesh).isMesh) (o as THREE.Mesh).material = ghostMat;
          });
          this.ghost[link.frame].add(gm);
          const lm = m.clone();
          lm.traverse((o) => {
            if ((o as THREE.Mesh).isMesh) (o as THREE.Mesh).material = liveMat;
          });
          this.live[link.frame].add(lm);
          this.dirty = true;
        }));
      }
    });
    if (robot.gripper) {
      const g = robot.gripper;
      const geo = new THREE.BoxGeometry(g.finger_length_mm, g.finger_thickness_mm, g.finger_height_mm);
      const mat = new THREE.MeshStandardMaterial({ color: 0x2b2d42, roughness: 0.5, metalness: 0.3 });
      for (let k = 0; k < 2; k++) {
        const f = new THREE.Mesh(geo, mat);
        f.matrixAutoUpdate = false;
        f.name = k ? "finger right" : "finger left";
        this.fingers.push(f);
        this.arm.add(f);
        const gf = new THREE.Mesh(geo, ghostMat);
        gf.matrixAutoUpdate = false;
        this.ghostFingers.push(gf);
        this.ghostArm.add(gf);
      }
    }
    this.ghostArm.visible = false;
    this.toolLine.geometry.setAttribute("position", new THREE.Float32BufferAttribute(new Float32Array(6), 3));
    this.toolDot.scale.setScalar(Math.max(3, this.reach * 0.012));
    this.arm.add(this.toolLine, this.toolDot, this.pen);
    this.pen.visible = false;
    this.penMm = 0;
    // Ground and grid to the robot's size.
    const size = Math.ceil((this.reach * 3) / 100) * 100;
    if (this.grid) this.scene.remove(this.grid);
    const cell = size > 2000 ? 100 : 50;
    this.grid = new THREE.GridHelper(size, size / cell, 0x9aa5b1, 0xc8d0d9);
    this.grid.rotation.x = Math.PI / 2;
    this.scene.add(this.grid);
    this.ground.scale.setScalar(size * 0.75);
    const ball = this.target.getObjectByName("target-ball")!;
    ball.scale.setScalar(this.reach * 0.025);
    this.target.children[1].scale.setScalar(this.reach * 0.1);
    return Promise.all(loading).then(() => undefined);
  }

  // ---- what is laid over the world (view/overlays.ts)

  showDrawing(ideal: number[][][], ink: number[][][], z: number): void {
    this.overlays.showDrawing(ideal, ink, z);
  }

  showSheet(area: number[] | null, z: number): void {
    this.overlays.showSheet(area, z);
  }

  showInk(strokes: number[][][], z: number): void {
    this.overlays.showInk(strokes, z);
  }

  showPaths(predicted: number[], lines: number[][]): void {
    this.overlays.showPaths(predicted, lines);
  }

  showGoal(parts: Parameters<Overlays["showGoal"]>[0]): void {
    this.overlays.showGoal(parts);
  }

  /** The goal's parts drawn (for the hook): reach balls and places. */
  goalShown(): number {
    return this.overlays.goalParts();
  }

  /** A pen in the gripper, its tip `mm` below the tool point; 0: none. */
  setPen(mm: number): void {
    const at = this.toolDot.position;
    this.penMm = mm > 0 ? mm : 0;
    this.pen.visible = this.penMm > 0;
    this.pen.scale.set(4, 4, Math.max(this.penMm, 1));
    this.pen.position.set(at.x, at.y, at.z - this.penMm / 2);
    // the program's paths are then the pen tip's: the tool point's, the pen's length lower
    this.overlays.paths.position.z = -this.penMm;
    this.dirty = true;
  }

  pose(p: PoseMsg): void {
    this.dirty = true;
    p.frames.forEach((m, i) => this.frames[i] && setMatrix(this.frames[i], m));
    p.fingers?.forEach((m, i) => this.fingers[i] && setMatrix(this.fingers[i], m));
    const last = p.frames[p.frames.length - 2], tool = p.frames[p.frames.length - 1];
    const pos = this.toolLine.geometry.getAttribute("position") as THREE.BufferAttribute;
    pos.setXYZ(0, last[3], last[7], last[11]);
    pos.setXYZ(1, tool[3], tool[7], tool[11]);
    pos.needsUpdate = true;
    this.toolLine.geometry.computeBoundingSphere();
    this.toolDot.position.set(tool[3], tool[7], tool[11]);
    this.pen.position.set(tool[3], tool[7], tool[11] - this.penMm / 2);
    if (p.ghost) {
      this.ghostArm.visible = true;
      p.ghost.forEach((m, i) => this.ghost[i] && setMatrix(this.ghost[i], m));
      p.ghost_fingers?.forEach((m, i) => this.ghostFingers[i] && setMatrix(this.ghostFingers[i], m));
    } else {
      this.ghostArm.visible = false;
    }
  }

  // The arm itself (its status reports' angles, frames from the engine), beside the model.
  liveFrames(frames: Flat4x4[] | null): void {
    this.liveArm.visible = frames !== null;
    frames?.forEach((m, i) => this.live[i] && setMatrix(this.live[i], m));
    this.dirty = true;
  }

  showAxes(on: boolean): void {
    this.dirty = true;
    this.axes.forEach((a) => (a.visible = on));
  }

  // ---- a cell of arms (view/cell-arms.ts)

  /** A cell's arms shown (the single arm hidden), or the single arm again (null). */
  showCell(m: CellMsg): Promise<void> {
    const on = m.name !== null && !!m.arms;
    this.arm.visible = !on;
    if (on) this.ghostArm.visible = this.liveArm.visible = false;
    this.target.visible = this.target.visible && !on;
    // the camera takes in every arm where it stands, once its shapes are in
    this.cellReach = on ? Math.max(...m.arms!.map((a) => Math.max(200, a.robot.reach_mm) + Math.hypot(a.base.xyz[0], a.base.xyz[1]))) : 0;
    return this.cellArms.build(on ? m.arms! : null).then(() => {
      this.cellArms.devices(on ? m.devices : undefined);
      this.cellFit = on;
    });
  }

  /** A cell's frame: its arms (unless `arms` is false: they are posed otherwise, as their Nanos
   * report them) and its objects. */
  cellFrame(f: CellFrameMsg, arms = true): void {
    if (arms) this.cellArms.pose(f);
    this.cellArms.showBeams(f.devices);
    if (this.cellFit) {  // the first frame with every arm posed and its shapes in: all of them in view
      this.cellFit = false;
      this.fit(false);
    }
    this.objects.physics({ type: "physics", on: true, objects: f.objects.map((o) => ({ ...o, movable: true })) });
  }

  // ---- the physics scene (view/objects.ts)

  setObjects(objects: SceneObjectInfo[]): void {
    this.objects.setObjects(objects);
  }

  physics(p: PhysicsMsg): void {
    this.objects.physics(p);
  }

  // An event names parts ("link 2", "finger left", an object, "ground"; in a cell, an arm's
  // "taker: link 3"): they flash.
  flash(name: string): number {
    const parts = this.cellArms.named(name);
    for (const p of parts) this.objects.flash(p);
    if (parts.length) return parts.length;
    let m: THREE.Object3D | undefined = this.objects.named(name);
    if (!m) {
      const frame = /^link (\d+)$/.exec(name);
      if (frame) m = this.frames[Number(frame[1])]?.children.find((c) => (c as THREE.Mesh).isMesh);
      else if (name.startsWith("finger")) m = this.fingers[name.endsWith("right") ? 1 : 0];
    }
    if (!m || !(m as THREE.Mesh).isMesh) return 0;
    this.objects.flash(m as THREE.Mesh);
    return 1;
  }

  // Where an object's centre is on the page (tests drag it).
  pointScreen(p: number[]): number[] {
    return this.objects.pointScreen(p);
  }
  /** The scene editor's drop (SceneObjects.placing); null: none. The pointer shows a cross meanwhile. */
  set placing(f: ((point: number[], free: boolean) => void) | null) {
    this.objects.placing = f && ((p, free) => {
      this.canvas.style.cursor = "";
      f(p, free);
    });
    this.canvas.style.cursor = f ? "crosshair" : "";
  }
  get placing(): ((point: number[], free: boolean) => void) | null {
    return this.objects.placing;
  }
  objectScreen(name: string): number[] | null {
    return this.objects.objectScreen(name);
  }

  // ---- the IK target

  showTarget(on: boolean): void {
    this.dirty = true;
    this.target.visible = on;
    this.gizmo.getHelper().visible = on;
    this.gizmo.enabled = on;
  }

  setTarget(xyz: number[], rpy: number[] = [0, 0, 0]): void {
    this.dirty = true;
    this.target.position.set(xyz[0], xyz[1], xyz[2]);
    const d = Math.PI / 180;
    this.target.rotation.set(rpy[0] * d, rpy[1] * d, rpy[2] * d, "ZYX");
  }

  targetValue(): TargetChange {
    const p = this.target.position;
    const e = new THREE.Euler().setFromQuaternion(this.target.quaternion, "ZYX");
    const d = 180 / Math.PI;
    return { xyz: [p.x, p.y, p.z], rpy: [e.x * d, e.y * d, e.z * d] };
  }

  gizmoMode(mode: "translate" | "rotate"): void {
    this.gizmo.setMode(mode);
  }

  // ---- the camera (view/camera.ts)

  // Frames the arm: from the front-right, a little above, the whole arm and its reach in view.
  fit(keepDirection = true): void {
    const cell = this.cellArms.count > 0;
    if (frameArm(this.camera, this.controls, cell ? this.cellArms.group : this.arm, cell ? this.cellReach : this.reach, keepDirection))
      this.dirty = true;
  }

  // Arrow keys orbit, + and - zoom (the thesis's keyboard camera).
  key(code: string): boolean {
    if (!orbitKey(this.camera, this.controls, code)) return false;
    this.dirty = true;
    this.onViewChange();
    return true;
  }

  /** Where the camera is and what it looks at (mm), for a project to keep. */
  viewpoint(): { eye: number[]; target: number[] } {
    return viewpointOf(this.camera, this.controls);
  }

  setViewpoint(v: { eye: number[]; target: number[] }): void {
    lookFrom(this.camera, this.controls, v);
    this.dirty = true;
  }

  cameraState(): { distance: number; azimuth: number } {
    return cameraStateOf(this.camera, this.controls);
  }

  // Where the IK target is on the page, CSS pixels (for tests that drag it).
  targetScreen(): number[] {
    return onScreen(this.camera, this.canvas, this.target.position);
  }

  // The share of the drawn pixels that are coloured like the arm (saturated): the scene
  // without the arm is greys only. Tests check that the arm is on screen with it.
  armPixels(): number {
    if (!this.renderer) return 0;
    const gl = this.renderer.getContext();
    const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let n = 0;
    for (let i = 0; i < px.length; i += 16) {
      const r = px[i], g = px[i + 1], b = px[i + 2];
      if (Math.max(r, g, b) - Math.min(r, g, b) > 40) n++;
    }
    return n / (px.length / 16);
  }
}
