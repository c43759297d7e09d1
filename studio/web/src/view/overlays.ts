// What the view lays over the world: a drawing's paper, its strokes, the line the arm will
// draw and the ink it left; a program's predicted tool path and the straight lines it asks for;
// an exercise's goal. Each is a group of the scene that the view adds once.
import * as THREE from "three";
import { label } from "./shapes";

export class Overlays {
  readonly drawing = new THREE.Group();
  readonly paths = new THREE.Group();
  readonly goal = new THREE.Group();

  /** changed(): something drawn changed (the view draws its next frame); reach(): the robot's
   * reach, mm (dashes are sized to it). */
  constructor(private readonly changed: () => void, private readonly reach: () => number) {}

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
    this.changed();
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
    this.changed();
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
    this.changed();
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
      const ideal = new THREE.LineSegments(g, new THREE.LineDashedMaterial({ color: 0x1d4ed8, dashSize: this.reach() * 0.012, gapSize: this.reach() * 0.008 }));
      ideal.computeLineDistances();
      ideal.name = "ideal lines";
      this.paths.add(ideal);
    }
    this.changed();
  }

  // ---- an exercise's goal: where the tool must go (a ball of the tolerance, numbered) and where
  // an object must end (a see-through box), drawn faintly in every view

  showGoal(parts: ({ kind: "reach"; xyz: number[]; tolerance_mm: number } | { kind: "object"; min: number[]; max: number[] })[]): void {
    for (const o of [...this.goal.children]) o.removeFromParent();
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
      this.goal.add(g);
    }
    this.changed();
  }

  /** The goal's parts drawn (for the hook): reach balls and places. */
  goalParts(): number {
    return this.goal.children.length;
  }
}
