// A cell's arms in the view (cells/README.md): each arm's links and fingers where its base
// stands on the table, posed by the frames the engine sends (each in its own base frame), all
// of one colour per arm so that a student tells them apart (the single arm's colours are per
// link). The single arm is hidden while a cell is shown (view.ts's showCell).
import * as THREE from "three";
import type { CellDevice, CellFrameMsg, CellMsg } from "../engine/messages";
import { setMatrix, shapeObject } from "./shapes";

/** One colour per arm, in the cell file's order. */
export const ARM_COLORS = [0x3d5a80, 0xee6c4d, 0x6d9f71, 0xb56576, 0xe0a458, 0x5c6f91, 0x8a5a44, 0x2a9d8f];

interface Arm {
  frames: THREE.Group[];
  fingers: THREE.Mesh[];
}

// A light barrier's beam: red while clear, amber while an object breaks it (a module's LED).
const BEAM_CLEAR = 0xd62828, BEAM_BROKEN = 0xf4a261;
// A switch's actuator: teal, brighter while pressed.
const SWITCH_FREE = 0x2a9d8f, SWITCH_PRESSED = 0x52e0c4;

export class CellArms {
  readonly group = new THREE.Group();
  private arms: Arm[] = [];
  private beams = new Map<string, THREE.Mesh>(); // each barrier's beam and switch's box, by the device's name

  constructor(private readonly changed: () => void) {}

  /** The cell's arms built (null: none); resolves once every shape (a mesh loads) is in. */
  build(arms: NonNullable<CellMsg["arms"]> | null): Promise<void> {
    this.group.clear();
    this.arms = [];
    this.beams.clear();
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

  /** The cell's light barriers: a thin beam between its ends, with a post at each (none: none). */
  devices(devices: CellDevice[] | undefined): void {
    for (const m of this.beams.values()) this.group.remove(m.parent && m.parent !== this.group ? m.parent : m);
    this.beams.clear();
    for (const d of devices ?? []) {
      if (d.kind === "switch" && d.at_mm && d.size_mm) { // a switch's actuator: a translucent box
        const box = new THREE.Mesh(new THREE.BoxGeometry(d.size_mm[0], d.size_mm[1], d.size_mm[2]),
          new THREE.MeshBasicMaterial({ color: SWITCH_FREE, transparent: true, opacity: 0.35, depthWrite: false }));
        box.position.set(d.at_mm[0], d.at_mm[1], d.at_mm[2]);
        box.name = `switch ${d.name}`;
        this.group.add(box);
        this.beams.set(d.name, box);
        continue;
      }
      if (d.kind !== "barrier" || !d.from_mm || !d.to_mm) continue;
      const a = new THREE.Vector3(...d.from_mm), b = new THREE.Vector3(...d.to_mm);
      const holder = new THREE.Group();
      holder.name = `barrier ${d.name}`;
      const beam = new THREE.Mesh(new THREE.CylinderGeometry(1.2, 1.2, a.distanceTo(b), 8),
        new THREE.MeshBasicMaterial({ color: BEAM_CLEAR, transparent: true, opacity: 0.85 }));
      beam.position.copy(a).add(b).multiplyScalar(0.5);
      beam.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), b.clone().sub(a).normalize());
      holder.add(beam);
      // the sender and the receiver: a small dark post under each end, down to the table
      const post = new THREE.MeshStandardMaterial({ color: 0x2b2d42, roughness: 0.6 });
      for (const p of [a, b]) {
        const h = Math.max(8, p.z + 6);
        const m = new THREE.Mesh(new THREE.BoxGeometry(10, 10, h), post);
        m.position.set(p.x, p.y, p.z + 6 - h / 2);
        holder.add(m);
      }
      this.group.add(holder);
      this.beams.set(d.name, beam);
    }
    this.changed();
  }

  /** Each barrier's beam as the frame has it: red while clear, amber while broken. */
  showBeams(devices: CellDevice[] | undefined): void {
    for (const d of devices ?? []) {
      const beam = this.beams.get(d.name);
      if (!beam) continue;
      const colour = d.kind === "switch" ? (d.pressed_by ? SWITCH_PRESSED : SWITCH_FREE) : d.broken_by ? BEAM_BROKEN : BEAM_CLEAR;
      (beam.material as THREE.MeshBasicMaterial).color.setHex(colour);
    }
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
