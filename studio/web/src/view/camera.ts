// The view's camera: framing the arm, the thesis's keyboard orbit and zoom, and the viewpoint a
// project keeps. Z is up; the orbit controls (three.js) turn about their target.
import * as THREE from "three";
import type { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";

/** Frames `arm`: the whole arm and its reach (mm) in view, from where the camera looks now
 * (keepDirection) or from the front-right, a little above. False when there is nothing to frame. */
export function frameArm(camera: THREE.PerspectiveCamera, controls: OrbitControls, arm: THREE.Object3D, reach: number,
                         keepDirection: boolean): boolean {
  arm.updateMatrixWorld(true);
  const box = new THREE.Box3().setFromObject(arm);
  if (box.isEmpty()) return false;
  box.expandByPoint(new THREE.Vector3(0, 0, 0));
  const centre = box.getCenter(new THREE.Vector3());
  const size = Math.max(box.getSize(new THREE.Vector3()).length(), reach * 0.8, 200);
  const dir = keepDirection ? camera.position.clone().sub(controls.target).normalize()
                            : new THREE.Vector3(0.75, -0.95, 0.55).normalize();
  controls.target.copy(centre);
  const fov = (camera.fov * Math.PI) / 180;
  const dist = (size / 2 / Math.tan(fov / 2)) * (camera.aspect < 1 ? 1.2 / camera.aspect : 1.05);
  camera.position.copy(centre.clone().add(dir.multiplyScalar(dist)));
  camera.near = size / 100;
  camera.far = size * 40;
  camera.updateProjectionMatrix();
  return true;
}

/** Arrow keys orbit (left/right about z, up/down in elevation), + and - zoom: the thesis's
 * keyboard camera. False for any other key. */
export function orbitKey(camera: THREE.PerspectiveCamera, controls: OrbitControls, code: string): boolean {
  const offset = camera.position.clone().sub(controls.target);
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
  camera.position.copy(controls.target).add(offset);
  return true;
}

/** Where the camera is and what it looks at (mm, to 0.1), for a project to keep. */
export function viewpointOf(camera: THREE.PerspectiveCamera, controls: OrbitControls): { eye: number[]; target: number[] } {
  const r = (v: THREE.Vector3) => [v.x, v.y, v.z].map((x) => Math.round(x * 10) / 10);
  return { eye: r(camera.position), target: r(controls.target) };
}

export function lookFrom(camera: THREE.PerspectiveCamera, controls: OrbitControls, v: { eye: number[]; target: number[] }): void {
  camera.position.set(v.eye[0], v.eye[1], v.eye[2]);
  controls.target.set(v.target[0], v.target[1], v.target[2]);
  controls.update();
}

/** The camera's distance from its target (mm) and its azimuth (deg). */
export function cameraStateOf(camera: THREE.PerspectiveCamera, controls: OrbitControls): { distance: number; azimuth: number } {
  const d = camera.position.clone().sub(controls.target);
  return { distance: d.length(), azimuth: (Math.atan2(d.y, d.x) * 180) / Math.PI };
}

/** Where a point of the world is on the page, CSS pixels. */
export function onScreen(camera: THREE.PerspectiveCamera, canvas: HTMLCanvasElement, p: THREE.Vector3): number[] {
  const q = p.clone().project(camera);
  const r = canvas.getBoundingClientRect();
  return [r.left + ((q.x + 1) / 2) * r.width, r.top + ((1 - q.y) / 2) * r.height];
}
