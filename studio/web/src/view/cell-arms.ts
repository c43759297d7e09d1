// A cell's arms in the view (cells/README.md): each arm's links and fingers where its base
// stands on the table, posed by the frames the engine sends (each in its own base frame), all
// of one colour per arm so that a student tells them apart (the single arm's colours are per
// link). The single arm is hidden while a cell is shown (view.ts's showCell).
import * as THREE from "three";
import type { CellFrameMsg, CellMsg } from "../engine/messages";
import { setMatrix, shapeObject } from "./shapes";

/** One colour per arm, in the cell file's order. */
export const ARM_COLORS = [0x3d5a80, 0xee6c4d, 0x6d9f71, 0xb56576, 0xe0a458, 0x5c6f91, 0x8a5a44, 0x2a9d8f];

interface Arm {
  frames: THREE.Group[];
  fingers: THREE.Mesh[];
}

export class CellArms {
  readonly group = new THREE.Group();
  private arms: Arm[] = [];

  constructor(private readonly changed: () => void) {}

  /** The cell's arms built (null: none); resolves once every shape (a mesh loads) is in. */
  build(arms: NonNullable<CellMsg["arms"]> | null): Promise<void> {
    this.group.clear();
    this.arms = [];
    const loading: Promise<void>[] = [];
    (arms ?? []).forEach((a, k) => {
      const color = ARM_COLORS[k % ARM_COLORS.length];
      const base = new THREE.Group();
      base.name = `arm ${a.name}`;
      base.position.set(a.base.xyz[0], a.base.xyz[1], a.base.xyz[2]);
      base.rotation.z = (a.base.yaw * Math.PI) / 180;
      this.group.add(base);
      const mat = new THREE.MeshStandardMaterial({ color, roughness: 0.45, metalness: 0.15 });
      const dark = new THREE.MeshStandardMaterial({ color: new THREE.Color(color).multiplyScalar(0.55), roughness: 0.5 });
      const arm: Arm = { frames: [], fingers: [] };
      for (let i = 0; i < a.robot.num_rows + 2; i++) {
        const g = new THREE.Group();
        g.matrixAutoUpdate = false;
        arm.frames.push(g);
        base.add(g);
      }
      for (const link of a.robot.links)
        for (const s of link.shapes)
          loading.push(shapeObject(s, link.frame === 0 ? dark : mat).then((m) => {
            if (!m) return;
            m.name = `${a.name}: ${link.frame === 0 ? "base" : `link ${link.frame}`}`; // as the engine's events name it
            arm.frames[link.frame]?.add(m);
            this.changed();
          }));
      const g = a.robot.gripper;
      if (g) {
        const geo = new THREE.BoxGeometry(g.finger_length_mm, g.finger_thickness_mm, g.finger_height_mm);
        for (let f = 0; f < 2; f++) {
          const m = new THREE.Mesh(geo, dark);
          m.name = `${a.name}: finger ${f === 0 ? "left" : "right"}`;
          m.matrixAutoUpdate = false;
          arm.fingers.push(m);
          base.add(m);
        }
      }
      this.arms.push(arm);
    });
    this.changed();
    return Promise.all(loading).then(() => undefined);
  }

  /** Each arm at the frames the engine sent. */
  pose(f: CellFrameMsg): void {
    f.arms.forEach((a, k) => {
      const arm = this.arms[k];
      if (!arm) return;
      a.frames.forEach((m, i) => arm.frames[i] && setMatrix(arm.frames[i], m));
      a.fingers?.forEach((m, i) => arm.fingers[i] && setMatrix(arm.fingers[i], m));
    });
    this.changed();
  }

  /** Arm k at the frames (and fingers) given, in its base frame (as its Nano reports it). */
  poseArm(k: number, frames: number[][], fingers?: number[][]): void {
    const arm = this.arms[k];
    if (!arm) return;
    frames.forEach((m, i) => arm.frames[i] && setMatrix(arm.frames[i], m));
    fingers?.forEach((m, i) => arm.fingers[i] && setMatrix(arm.fingers[i], m));
    this.changed();
  }

  /** The meshes of a part as an event names it ("taker: link 3", "giver: finger left"). */
  named(name: string): THREE.Mesh[] {
    const found: THREE.Mesh[] = [];
    this.group.traverse((o) => {
      if (o.name === name && (o as THREE.Mesh).isMesh) found.push(o as THREE.Mesh);
    });
    return found;
  }

  get count(): number {
    return this.arms.length;
  }
}
