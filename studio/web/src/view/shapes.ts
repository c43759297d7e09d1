// The robot file's shapes as three.js objects (boxes, cylinders, capsules, spheres, and meshes
// fetched from the site), placed by the engine's matrices; and the round labels that number
// the frames and an exercise's goals.
import * as THREE from "three";
import { STLLoader } from "three/examples/jsm/loaders/STLLoader.js";
import { OBJLoader } from "three/examples/jsm/loaders/OBJLoader.js";
import type { Flat4x4, Shape } from "../engine/messages";

export const LINK_COLORS = [0x3d5a80, 0xee6c4d, 0x98c1d9, 0xe0a458, 0x6d9f71, 0xb56576, 0x8d99ae];

export function setMatrix(obj: THREE.Object3D, m: Flat4x4): void {
  obj.matrix.set(m[0], m[1], m[2], m[3], m[4], m[5], m[6], m[7], m[8], m[9], m[10], m[11], m[12], m[13], m[14], m[15]);
  obj.matrixWorldNeedsUpdate = true;
}

export function label(text: string, color = "#1d3557"): THREE.Sprite {
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

export async function shapeObject(s: Shape, mat: THREE.Material): Promise<THREE.Object3D | null> {
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
      geo = await meshGeometry(s);
      break;
  }
  if (!geo) return null;
  const m = new THREE.Mesh(geo, mat);
  m.matrixAutoUpdate = false;
  setMatrix(m, s.pose);
  return m;
}

async function meshGeometry(s: Shape): Promise<THREE.BufferGeometry | null> { // s.url carries the token
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
