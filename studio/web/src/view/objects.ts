// The physics scene's objects in the view: drawn where the engine's world has them, flashing
// when an event names them, and dragged by the pointer (a press on a movable one grabs it; the
// pointer pulls it in the plane facing the camera through where it was grabbed).
import * as THREE from "three";
import type { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import type { PhysicsMsg, SceneObjectInfo } from "../engine/messages";
import { onScreen } from "./camera";
import { setMatrix } from "./shapes";

export class SceneObjects {
  readonly group = new THREE.Group();
  private objects = new Map<string, THREE.Mesh>();
  private flashes = new Map<THREE.Mesh, number>();
  private raycaster = new THREE.Raycaster();
  private dragPlane = new THREE.Plane();
  private dragging: { name: string; offset: THREE.Vector3 } | null = null;
  /** The scene editor's drop: the next press on the view gives the point of the surface under
   * the pointer (mm: an object's face or the ground) and whether Shift was held; null: none. */
  placing: ((point: number[], free: boolean) => void) | null = null;

  /** changed(): the view draws its next frame; onDrag(object, target): an object pulled to
   * target (mm), or let go (null). */
  constructor(private readonly camera: THREE.PerspectiveCamera, private readonly canvas: HTMLCanvasElement,
              private readonly controls: OrbitControls, private readonly changed: () => void,
              private readonly onDrag: (object: string, target: number[] | null) => void) {
    canvas.addEventListener("pointerdown", (e) => this.grab(e), { capture: true });
    canvas.addEventListener("pointermove", (e) => this.pull(e));
    window.addEventListener("pointerup", () => this.letGo());
  }

  setObjects(objects: SceneObjectInfo[]): void {
    this.group.clear();
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
      this.group.add(m);
    });
    this.changed();
  }

  physics(p: PhysicsMsg): void {
    for (const o of p.objects ?? []) {
      const m = this.objects.get(o.name);
      if (!m) continue;
      setMatrix(m, o.pose);
      m.visible = !o.removed;
    }
    this.changed();
  }

  /** The object named so, if the scene has one. */
  named(name: string): THREE.Mesh | undefined {
    return this.objects.get(name);
  }

  /** A part an event names flashes red for 0.7 s (its own material meanwhile). */
  flash(mesh: THREE.Mesh): void {
    if (!this.flashes.has(mesh)) mesh.material = (mesh.material as THREE.Material).clone();
    this.flashes.set(mesh, performance.now() + 700);
  }

  /** The flashing parts at `now`: true while any flashes (the view draws the frame). */
  tick(now: number): boolean {
    for (const [m, until] of this.flashes) {
      const mat = m.material as THREE.MeshStandardMaterial;
      if (now > until) {
        mat.emissive.setHex(0x000000);
        this.flashes.delete(m);
      } else {
        mat.emissive.setHex(Math.floor(now / 120) % 2 ? 0xff3b30 : 0x551100);
      }
    }
    return this.flashes.size > 0;
  }

  private pointer(e: PointerEvent): THREE.Vector2 {
    const r = this.canvas.getBoundingClientRect();
    return new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
  }

  // The surface under the pointer: the nearest visible object's face that looks up, else the
  // ground (z = 0); null where the pointer points at the sky.
  private surface(e: PointerEvent): number[] | null {
    this.raycaster.setFromCamera(this.pointer(e), this.camera);
    this.group.updateMatrixWorld(true); // (the view brings it up to date only as it draws)
    const hit = this.raycaster.intersectObjects([...this.objects.values()].filter((m) => m.visible))[0];
    if (hit && hit.face && hit.face.normal.clone().transformDirection(hit.object.matrixWorld).z > 0.7) return hit.point.toArray();
    const p = new THREE.Vector3();
    return this.raycaster.ray.intersectPlane(new THREE.Plane(new THREE.Vector3(0, 0, 1), 0), p) ? p.toArray() : null;
  }

  private grab(e: PointerEvent): void {
    if (e.button === 0 && this.placing) {
      const at = this.surface(e);
      if (!at) return;
      e.stopImmediatePropagation();
      const place = this.placing;
      this.placing = null;
      place(at, e.shiftKey);
      return;
    }
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

  // Where a point (mm) is on the page (tests drop objects there).
  pointScreen(p: number[]): number[] {
    return onScreen(this.camera, this.canvas, new THREE.Vector3(p[0], p[1], p[2]));
  }

  // Where an object's centre is on the page (tests drag it).
  objectScreen(name: string): number[] | null {
    const m = this.objects.get(name);
    if (!m || !m.visible) return null; // (none, or out of the world: a feeder's, one fallen off)
    return onScreen(this.camera, this.canvas, new THREE.Vector3().setFromMatrixPosition(m.matrixWorld));
  }
}
