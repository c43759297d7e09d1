// The 3D view: one three.js scene graph where each DH frame is a Group whose children are
// that frame's shapes and axes, so a pose from the engine is one matrix per frame (the page
// computes no kinematics). Z is up, lengths are millimetres, as in the robot files.
import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import { TransformControls } from "three/examples/jsm/controls/TransformControls.js";
import { STLLoader } from "three/examples/jsm/loaders/STLLoader.js";
import { OBJLoader } from "three/examples/jsm/loaders/OBJLoader.js";
import type { Flat4x4, PhysicsMsg, PoseMsg, RobotMsg, SceneObjectInfo, Shape } from "./engine/messages";

const LINK_COLORS = [0x3d5a80, 0xee6c4d, 0x98c1d9, 0xe0a458, 0x6d9f71, 0xb56576, 0x8d99ae];

export function setMatrix(obj: THREE.Object3D, m: Flat4x4): void {
  obj.matrix.set(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11], m[12], m[13], m[14], m[15]);
  obj.matrixWorldNeedsUpdate = true;
}

function label(text: string, color = "#1d3557"): THREE.Sprite {
  const c = document.createElement("canvas");
  c.width = c.height = 64;
  const g = c.getContext("2d")!;
  g.fillStyle = "rgba(255,255,255,0.92)";
  g.beginPath();
  g.arc(32, 32, 26, 0, Math.PI * 2);
  g.fill();
  g.strokeStyle = color;
  g.lineWidth = 4;
  g.stroke();
  g.fillStyle = color;
  g.font = "bold 30px system-ui, sans-serif";
  g.textAlign = "center";
  g.textBaseline = "middle";
  g.fillText(text, 32, 34);
  const s = new THREE.Sprite(new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(c), depthTest: false }));
  s.renderOrder = 10;
  return s;
}

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
  // The physics scene's objects by name, and what flashes (an event names it) until when.
  private objects = new Map<string, THREE.Mesh>();
  private objectGroup = new THREE.Group();
  private goalGroup = new THREE.Group();
  private flashes = new Map<THREE.Mesh, number>();
  private raycaster = new THREE.Raycaster();
  private dragPlane = new THREE.Plane();
  private dragging: { name: string; offset: THREE.Vector3 } | null = null;
  onDrag: (object: string, target: number[] | null) => void = () => {};
  /** The user moved the camera (an orbit, a zoom, a pan ended). */
  onViewChange: () => void = () => {};
  private ghostArm = new THREE.Group();
  // A program's predicted tool path (every step) and the straight lines it asks for.
  private paths = new THREE.Group();
  private drawing = new THREE.Group();
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
  // measure the frame rate).
  dirty = true;
  readonly continuous = new URLSearchParams(location.search).get("fps") === "continuous";

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
    this.software = View.softwareRenderer();
    const q = new URLSearchParams(location.search).get("quality");
    this.canvas = document.createElement("canvas");
    this.canvas.setAttribute("aria-label", "The arm in 3D: drag to orbit, arrow keys orbit, + and - zoom");
    this.canvas.tabIndex = 0;
    let renderer: THREE.WebGLRenderer | null = null;
    try {
      renderer = new THREE.WebGLRenderer({ canvas: this.canvas, antialias: q ? q === "high" : !this.software, preserveDrawingBuffer: true });
      renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2) * (this.software && q !== "high" ? 0.6 : 1));
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
    this.scene.add(this.arm, this.ghostArm, this.objectGroup, this.goalGroup, this.liveArm, this.paths, this.drawing);

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
    // Dragging an object of the physics scene: a press on a movable one grabs it, the pointer
    // pulls it in the plane facing the camera through where it was grabbed.
    const el = this.canvas;
    el.addEventListener("pointerdown", (e) => this.grab(e), { capture: true });
    el.addEventListener("pointermove", (e) => this.pull(e));
    window.addEventListener("pointerup", () => this.letGo());
    this.controls.addEventListener("change", () => (this.dirty = true));
    this.controls.addEventListener("end", () => this.onViewChange());
    this.gizmo.addEventListener("change", () => (this.dirty = true));
    this.resize();
    if (this.renderer) this.renderer.setAnimationLoop((now) => this.draw(now));
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

  private draw(now: number): void {
    const moved = this.controls.update();
    for (const [m, until] of this.flashes) {
      const mat = m.material as THREE.MeshStandardMaterial;
      if (now > until) {
        mat.emissive.setHex(0x000000);
        this.flashes.delete(m);
      } else {
        mat.emissive.setHex(Math.floor(now / 120) % 2 ? 0xff3b30 : 0x551100);
      }
      this.dirty = true;
    }
    if (!(this.dirty || moved || this.continuous)) return;
    this.dirty = false;
    this.renderer!.render(this.scene, this.camera);
    this.framesDrawn++;
    this.frameTimes.push(now);
    while (this.frameTimes.length && now - this.frameTimes[0] > 1000) this.frameTimes.shift();
    this.fps = this.frameTimes.length;
    this.onFrame(now);
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
        loading.push(this.shape(s, mat).then((m) => {
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

  private async shape(s: Shape, mat: THREE.Material): Promise<THREE.Object3D | null> {
    let geo: THREE.BufferGeometry | null = null;
    const [a, b, c] = s.size;
    switch (s.type) {
      case "box":
        geo = new THREE.BoxGeometry(a, b, c);
        break;
      case "cylinder":
        geo = new THREE.CylinderGeometry(a, a, b, 40).rotateX(Math.PI / 2);
        break;
      case "capsule":
        geo = new THREE.CapsuleGeometry(a, b, 8, 24).rotateX(Math.PI / 2);
        break;
      case "sphere":
        geo = new THREE.SphereGeometry(a, 32, 20);
        break;
      case "mesh":
        geo = await this.mesh(s);
        break;
    }
    if (!geo) return null;
    const m = new THREE.Mesh(geo, mat);
    m.matrixAutoUpdate = false;
    setMatrix(m, s.pose);
    return m;
  }

  private async mesh(s: Shape): Promise<THREE.BufferGeometry | null> {  // s.url carries the token
    try {
      const res = await fetch(s.url!);
      if (!res.ok) return null;
      if (s.format === "stl") {
        const g = new STLLoader().parse(await res.arrayBuffer());
        g.computeVertexNormals();
        return g;
      }
      const obj = new OBJLoader().parse(await res.text());
      let g: THREE.BufferGeometry | null = null;
      obj.traverse((o) => {
        if (!g && (o as THREE.Mesh).isMesh) g = (o as THREE.Mesh).geometry as THREE.BufferGeometry;
      });
      (g as THREE.BufferGeometry | null)?.computeVertexNormals();
      return g;
    } catch {
      return null;
    }
  }

  /** A drawing on the paper at height z (mm): its strokes (blue) and the line the arm will
   * draw, the pen's tip at every step (orange), each a list of [x, y] polylines; nothing:
   * cleared. */
  showDrawing(ideal: number[][][], ink: number[][][], z: number): void {
    for (const o of [...this.drawing.children]) {
      if (o.name === "sheet" || o.name === "ink") continue;
      o.removeFromParent();
      ((o as THREE.LineSegments).geometry as THREE.BufferGeometry).dispose();
    }
    const segments = (strokes: number[][][], dz: number) => {
      const v: number[] = [];
      for (const s of strokes) for (let i = 1; i < s.length; i++) v.push(s[i - 1][0], s[i - 1][1], z + dz, s[i][0], s[i][1], z + dz);
      return v;
    };
    for (const [strokes, color, name, dz] of [[ideal, 0x1d4ed8, "drawing", 1.2], [ink, 0xc2410c, "drawing as the arm draws it", 1.6]] as
      [number[][][], number, string, number][]) {
      const v = segments(strokes, dz);
      if (!v.length) continue;
      const g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.Float32BufferAttribute(v, 3));
      const lines = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color }));
      lines.name = name;
      this.drawing.add(lines);
    }
    this.dirty = true;
  }

  /** A pen in the gripper, its tip `mm` below the tool point; 0: none. */
  setPen(mm: number): void {
    const at = this.toolDot.position;
    this.penMm = mm > 0 ? mm : 0;
    this.pen.visible = this.penMm > 0;
    this.pen.scale.set(4, 4, Math.max(this.penMm, 1));
    this.pen.position.set(at.x, at.y, at.z - this.penMm / 2);
    // the program's paths are then the pen tip's: the tool point's, the pen's length lower
    this.paths.position.z = -this.penMm;
    this.dirty = true;
  }

  /** A sheet of paper on the table, its corners [min_x, min_y, max_x, max_y] mm, at height z;
   * null: none. */
  showSheet(area: number[] | null, z: number): void {
    const old = this.drawing.getObjectByName("sheet") as THREE.Mesh | undefined;
    if (old) {
      old.removeFromParent();
      old.geometry.dispose();
      (old.material as THREE.Material).dispose();
    }
    if (area) {
      const [x0, y0, x1, y1] = area;
      const sheet = new THREE.Mesh(new THREE.PlaneGeometry(x1 - x0, y1 - y0),
        new THREE.MeshStandardMaterial({ color: 0xfdfdf8, roughness: 1, metalness: 0, polygonOffset: true, polygonOffsetFactor: -1,
          polygonOffsetUnits: -1 }));
      sheet.position.set((x0 + x1) / 2, (y0 + y1) / 2, z + 0.2); // above the table, below the lines
      sheet.name = "sheet";
      sheet.receiveShadow = true;
      this.drawing.add(sheet);
    }
    this.dirty = true;
  }

  /** Ink on the paper at height z: what the pen left as the arm moved (the virtual Nano's steps,
   * the physics), a list of [x, y] polylines; nothing: cleared. */
  showInk(strokes: number[][][], z: number): void {
    const old = this.drawing.getObjectByName("ink") as THREE.LineSegments | undefined;
    if (old) {
      old.removeFromParent();
      old.geometry.dispose();
    }
    const v: number[] = [];
    for (const st of strokes) {
      if (st.length === 1) v.push(st[0][0], st[0][1], z + 2, st[0][0] + 0.3, st[0][1], z + 2);
      for (let i = 1; i < st.length; i++) v.push(st[i - 1][0], st[i - 1][1], z + 2, st[i][0], st[i][1], z + 2);
    }
    if (v.length) {
      const g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.Float32BufferAttribute(v, 3));
      const ink = new THREE.LineSegments(g, new THREE.LineBasicMaterial({ color: 0x111827 }));
      ink.name = "ink";
      this.drawing.add(ink);
    }
    this.dirty = true;
  }

  /** The tool's predicted path, every step (x y z after x y z, mm; the stairs the steps make),
   * and the straight lines a program asks for (each [x0, y0, z0, x1, y1, z1]), drawn over
   * each other; nothing: both cleared. With a pen held (setPen) they are drawn where its tip
   * goes. */
  showPaths(predicted: number[], lines: number[][]): void {
    for (const o of [...this.paths.children]) {
      o.removeFromParent();
      ((o as THREE.Line).geometry as THREE.BufferGeometry).dispose();
    }
    if (predicted.length >= 6) {
      const g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.Float32BufferAttribute(predicted, 3));
      const path = new THREE.Line(g, new THREE.LineBasicMaterial({ color: 0xc2410c }));
      path.name = "predicted path";
      this.paths.add(path);
    }
    if (lines.length) {
      const g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.Float32BufferAttribute(lines.flat(), 3));
      const ideal = new THREE.LineSegments(g, new THREE.LineDashedMaterial({ color: 0x1d4ed8, dashSize: this.reach * 0.012, gapSize: this.reach * 0.008 }));
      ideal.computeLineDistances();
      ideal.name = "ideal lines";
      this.paths.add(ideal);
    }
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

  // ---- an exercise's goal: where the tool must go (a ball of the tolerance, numbered) and where
  // an object must end (a see-through box), drawn faintly in every view

  showGoal(parts: ({ kind: "reach"; xyz: number[]; tolerance_mm: number } | { kind: "object"; min: number[]; max: number[] })[]): void {
    for (const o of [...this.goalGroup.children]) o.removeFromParent();
    const color = 0x16a34a;
    let n = 0;
    for (const p of parts) {
      const g = new THREE.Group();
      g.name = "goal";
      if (p.kind === "reach") {
        const ball = new THREE.Mesh(new THREE.SphereGeometry(Math.max(p.tolerance_mm, 4), 24, 16),
          new THREE.MeshBasicMaterial({ color, transparent: true, opacity: 0.35, depthWrite: false }));
        g.position.set(p.xyz[0], p.xyz[1], p.xyz[2]);
        g.add(ball);
        const tag = label(String(++n), "#15803d");
        tag.scale.setScalar(22);
        tag.position.set(0, 0, Math.max(p.tolerance_mm, 4) + 14);
        g.add(tag);
      } else {
        const size = [0, 1, 2].map((i) => Math.max(p.max[i] - p.min[i], 1));
        const geo = new THREE.BoxGeometry(size[0], size[1], size[2]);
        g.position.set((p.min[0] + p.max[0]) / 2, (p.min[1] + p.max[1]) / 2, (p.min[2] + p.max[2]) / 2);
        g.add(new THREE.Mesh(geo, new THREE.MeshBasicMaterial({ color, transparent: true, opacity: 0.18, depthWrite: false })));
        g.add(new THREE.LineSegments(new THREE.EdgesGeometry(geo), new THREE.LineBasicMaterial({ color })));
        const tag = label("✓", "#15803d");
        tag.scale.setScalar(22);
        tag.position.set(0, 0, size[2] / 2 + 16);
        g.add(tag);
      }
      this.goalGroup.add(g);
    }
    this.dirty = true;
  }

  /** The goal's parts drawn (for the hook): reach balls and places. */
  goalShown(): number {
    return this.goalGroup.children.length;
  }

  // ---- the physics scene

  setObjects(objects: SceneObjectInfo[]): void {
    this.objectGroup.clear();
    this.objects.clear();
    const colors = [0xe63946, 0x2a9d8f, 0xf4a261, 0x457b9d, 0x8ab17d, 0xe9c46a, 0x9d4edd];
    objects.forEach((o, i) => {
      const [a, b, c] = o.size;
      const geo = o.type === "box" ? new THREE.BoxGeometry(a, b, c)
        : o.type === "sphere" ? new THREE.SphereGeometry(a, 32, 20)
        : new THREE.CylinderGeometry(a, a, b, 40).rotateX(Math.PI / 2);
      const mat = new THREE.MeshStandardMaterial({
        color: o.movable ? colors[i % colors.length] : 0x8d99ae, roughness: o.movable ? 0.5 : 0.8,
      });
      const m = new THREE.Mesh(geo, mat);
      m.matrixAutoUpdate = false;
      m.name = o.name;
      m.userData.movable = o.movable;
      this.objects.set(o.name, m);
      this.objectGroup.add(m);
    });
    this.dirty = true;
  }

  physics(p: PhysicsMsg): void {
    for (const o of p.objects ?? []) {
      const m = this.objects.get(o.name);
      if (!m) continue;
      setMatrix(m, o.pose);
      m.visible = !o.removed;
    }
    this.dirty = true;
  }

  // An event names parts ("link 2", "finger left", an object, "ground"): they flash.
  flash(name: string): void {
    let m: THREE.Object3D | undefined = this.objects.get(name);
    if (!m) {
      const frame = /^link (\d+)$/.exec(name);
      if (frame) m = this.frames[Number(frame[1])]?.children.find((c) => (c as THREE.Mesh).isMesh);
      else if (name.startsWith("finger")) m = this.fingers[name.endsWith("right") ? 1 : 0];
    }
    if (m && (m as THREE.Mesh).isMesh) {
      const mesh = m as THREE.Mesh;
      if (!this.flashes.has(mesh)) mesh.material = (mesh.material as THREE.Material).clone();
      this.flashes.set(mesh, performance.now() + 700);
    }
  }

  private pointer(e: PointerEvent): THREE.Vector2 {
    const r = this.canvas.getBoundingClientRect();
    return new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
  }

  private grab(e: PointerEvent): void {
    if (e.button !== 0 || !this.objects.size) return;
    this.raycaster.setFromCamera(this.pointer(e), this.camera);
    const hit = this.raycaster.intersectObjects([...this.objects.values()].filter((m) => m.userData.movable && m.visible))[0];
    if (!hit) return;
    e.stopImmediatePropagation();
    this.controls.enabled = false;
    const normal = this.camera.getWorldDirection(new THREE.Vector3()).negate();
    this.dragPlane.setFromNormalAndCoplanarPoint(normal, hit.point);
    const centre = new THREE.Vector3().setFromMatrixPosition(hit.object.matrixWorld);
    this.dragging = { name: hit.object.name, offset: centre.sub(hit.point) };
    this.onDrag(hit.object.name, [...hit.point.clone().add(this.dragging.offset).toArray()]);
  }

  private pull(e: PointerEvent): void {
    if (!this.dragging) return;
    this.raycaster.setFromCamera(this.pointer(e), this.camera);
    const p = new THREE.Vector3();
    if (this.raycaster.ray.intersectPlane(this.dragPlane, p)) {
      p.add(this.dragging.offset);
      this.onDrag(this.dragging.name, [p.x, p.y, p.z]);
    }
  }

  private letGo(): void {
    if (!this.dragging) return;
    this.onDrag(this.dragging.name, null);
    this.dragging = null;
    this.controls.enabled = true;
  }

  // Where an object's centre is on the page (tests drag it).
  objectScreen(name: string): number[] | null {
    const m = this.objects.get(name);
    if (!m) return null;
    const p = new THREE.Vector3().setFromMatrixPosition(m.matrixWorld).project(this.camera);
    const r = this.canvas.getBoundingClientRect();
    return [r.left + ((p.x + 1) / 2) * r.width, r.top + ((1 - p.y) / 2) * r.height];
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

  // ---- the camera

  // Frames the arm: from the front-right, a little above, the whole arm and its reach in view.
  fit(keepDirection = true): void {
    this.arm.updateMatrixWorld(true);
    const box = new THREE.Box3().setFromObject(this.arm);
    if (box.isEmpty()) return;
    box.expandByPoint(new THREE.Vector3(0, 0, 0));
    const centre = box.getCenter(new THREE.Vector3());
    const size = Math.max(box.getSize(new THREE.Vector3()).length(), this.reach * 0.8, 200);
    const dir = keepDirection ? this.camera.position.clone().sub(this.controls.target).normalize()
                              : new THREE.Vector3(0.75, -0.95, 0.55).normalize();
    this.controls.target.copy(centre);
    const fov = (this.camera.fov * Math.PI) / 180;
    const dist = (size / 2 / Math.tan(fov / 2)) * (this.camera.aspect < 1 ? 1.2 / this.camera.aspect : 1.05);
    this.camera.position.copy(centre.clone().add(dir.multiplyScalar(dist)));
    this.camera.near = size / 100;
    this.camera.far = size * 40;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  }

  // Arrow keys orbit (left/right about z, up/down in elevation), + and - zoom: the thesis's
  // keyboard camera.
  key(code: string): boolean {
    const offset = this.camera.position.clone().sub(this.controls.target);
    const sph = new THREE.Spherical();
    // Spherical works about y: turn z-up into y-up and back.
    const toY = new THREE.Quaternion().setFromUnitVectors(new THREE.Vector3(0, 0, 1), new THREE.Vector3(0, 1, 0));
    offset.applyQuaternion(toY);
    sph.setFromVector3(offset);
    const step = Math.PI / 36;
    if (code === "ArrowLeft") sph.theta -= step;
    else if (code === "ArrowRight") sph.theta += step;
    else if (code === "ArrowUp") sph.phi = Math.max(0.05, sph.phi - step);
    else if (code === "ArrowDown") sph.phi = Math.min(Math.PI - 0.05, sph.phi + step);
    else if (code === "Equal" || code === "NumpadAdd") sph.radius *= 0.9;
    else if (code === "Minus" || code === "NumpadSubtract") sph.radius *= 1.1;
    else return false;
    offset.setFromSpherical(sph).applyQuaternion(toY.invert());
    this.camera.position.copy(this.controls.target).add(offset);
    this.dirty = true;
    this.onViewChange();
    return true;
  }

  /** Where the camera is and what it looks at (mm), for a project to keep. */
  viewpoint(): { eye: number[]; target: number[] } {
    const r = (v: THREE.Vector3) => [v.x, v.y, v.z].map((x) => Math.round(x * 10) / 10);
    return { eye: r(this.camera.position), target: r(this.controls.target) };
  }

  setViewpoint(v: { eye: number[]; target: number[] }): void {
    this.camera.position.set(v.eye[0], v.eye[1], v.eye[2]);
    this.controls.target.set(v.target[0], v.target[1], v.target[2]);
    this.controls.update();
    this.dirty = true;
  }

  cameraState(): { distance: number; azimuth: number } {
    const d = this.camera.position.clone().sub(this.controls.target);
    return { distance: d.length(), azimuth: (Math.atan2(d.y, d.x) * 180) / Math.PI };
  }

  // Where the IK target is on the page, CSS pixels (for tests that drag it).
  targetScreen(): number[] {
    const p = this.target.position.clone().project(this.camera);
    const r = this.canvas.getBoundingClientRect();
    return [r.left + ((p.x + 1) / 2) * r.width, r.top + ((1 - p.y) / 2) * r.height];
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
