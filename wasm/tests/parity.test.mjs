// The web engine against the CLI, on every shipped robot: the same C++ compiled twice (clang
// to WebAssembly, gcc to x86-64) must give the same answers. node --test runs this file
// (ctest: wasm.parity); ARTICULA_CLI names the CLI, ARTICULA_WASM_DIR the engine's build.
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { mkdtempSync, readFileSync, readdirSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { after, before, describe, test } from "node:test";
import { EngineError } from "../js/engine.mjs";
import { REPO, nodeEngine } from "../js/node.mjs";

const CLI = process.env.ARTICULA_CLI || join(REPO, "build/host/cli/articula");
const ROBOTS = readdirSync(join(REPO, "robots")).filter((f) => f.endsWith(".json") && !f.includes("schema"))
  .map((f) => f.replace(/\.json$/, ""));
const SCENES = readdirSync(join(REPO, "scenes")).filter((f) => f.endsWith(".json") && !f.includes("schema"))
  .map((f) => f.replace(/\.json$/, ""));
const PROGRAMS = readdirSync(join(REPO, "programs")).filter((f) => /\.(arm|robosim)$/.test(f));
const tmp = mkdtempSync(join(tmpdir(), "articula-parity-"));

// The CLI's answer: {json, stderr, status} (exit code 1 is an answer too: unreachable, rejected).
function cli(...args) {
  try {
    const out = execFileSync(CLI, args, { encoding: "utf8", stdio: ["ignore", "pipe", "pipe"] });
    return { json: out.trim() ? JSON.parse(out) : null, status: 0 };
  } catch (e) {
    if (e.status === 1 && e.stdout.trim()) return { json: JSON.parse(e.stdout), status: 1, stderr: e.stderr };
    return { json: null, status: e.status, stderr: String(e.stderr).trim() };
  }
}

// A seeded generator, so a failure can be replayed.
function rng(seed) {
  let s = seed >>> 0;
  return () => ((s = (Math.imul(s, 1664525) + 1013904223) >>> 0) / 2 ** 32);
}

function randomPose(info, next) {
  return info.limits.map(([lo, hi]) => Number((lo + (hi - lo) * next()).toFixed(4)));
}

function close(a, b, tol, what) {
  assert.equal(a.length, b.length, `${what}: lengths`);
  for (let i = 0; i < a.length; i++)
    assert.ok(Math.abs(a[i] - b[i]) <= tol, `${what}[${i}]: ${a[i]} vs ${b[i]} (tolerance ${tol})`);
}

// One protocol move a little off home (the motors' zero for a robot with motors).
function offHome(info) {
  const from = info.num_motors ? info.motors.map((m) => m.zero) : info.home;
  const to = from.map((v, i) => {
    const [lo, hi] = info.num_motors ? [info.motors[i].min, info.motors[i].max] : info.limits[i];
    return Math.min(hi, Math.max(lo, v + (i % 2 ? -8 : 8)));
  });
  return `M ${to.map((v) => v.toFixed(3)).join(" ")}\n`;
}

// Equal, numbers to 1e-9 relative (the last bits of a sine may differ between the two
// compilers' libm), everything else exactly.
function same(a, b, what) {
  if (typeof b === "number") {
    assert.equal(typeof a, "number", `${what}: ${a} vs ${b}`);
    assert.ok(Math.abs(a - b) <= 1e-9 * Math.max(1, Math.abs(b)), `${what}: ${a} vs ${b}`);
  } else if (b && typeof b === "object") {
    assert.equal(Array.isArray(a), Array.isArray(b), `${what}: ${JSON.stringify(a)} vs ${JSON.stringify(b)}`);
    assert.deepEqual(Object.keys(a ?? {}).sort(), Object.keys(b).sort(), `${what}: fields`);
    for (const k of Object.keys(b)) same(a[k], b[k], `${what}.${k}`);
  } else {
    assert.deepEqual(a, b, what);
  }
}

let engine;
before(async () => {
  engine = await nodeEngine();
});

describe("FK and frames on random poses: equal to 1e-9 mm", () => {
  for (const name of ROBOTS)
    test(name, () => {
      const r = engine.robot(name);
      const next = rng(7);
      for (let k = 0; k < 12; k++) {
        const q = randomPose(r.info, next);
        const ref = cli("fk", name, "--q", q.join(","), "--json").json;
        const mine = r.pose(q);
        assert.equal(mine.frames.length, ref.frames.length + 1, "base, every row, the tool");
        ref.frames.forEach((f, i) => {
          const m = mine.frames[i];
          close([m[3], m[7], m[11]], f.position, 1e-9, `${name} q=${q} frame ${i} position`);
          close([m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10]], f.rotation.flat(), 1e-12, `${name} frame ${i} rotation`);
        });
        const tool = mine.frames[mine.frames.length - 1];
        close([tool[3], tool[7], tool[11]], ref.tool.position, 1e-9, `${name} q=${q} tool`);
      }
      r.delete();
    });
});

describe("IK: the same status, within the same tolerance", () => {
  for (const name of ROBOTS)
    test(name, () => {
      const r = engine.robot(name);
      const next = rng(11);
      const targets = [];
      for (let k = 0; k < 6; k++) targets.push(r.pose(randomPose(r.info, next)).tool.xyz.map((v) => Number(v.toFixed(3))));
      targets.push([5 * r.info.reach_mm, 0, 0]); // beyond its reach
      for (const target of targets) {
        const ref = cli("ik", name, "--target", target.join(","), "--json").json;
        const mine = r.ik({ target });
        assert.equal(mine.status, ref.status, `${name} target ${target}: status`);
        assert.equal(mine.solver, ref.solver, `${name} target ${target}: solver`);
        if (ref.status === "reached") assert.ok(mine.position_error_mm <= 0.01, `${name} ${target}: ${mine.position_error_mm} mm`);
        else assert.ok(Math.abs(mine.position_error_mm - ref.position_error_mm) < 1e-6 * Math.max(1, ref.position_error_mm),
          `${name} ${target}: ${mine.position_error_mm} vs ${ref.position_error_mm} mm`);
        close(mine.q, ref.q, 1e-6, `${name} ${target}: q`);
      }
      r.delete();
    });
});

describe("programs: predict (robots with motors) and run records as the CLI's --json", () => {
  for (const name of ROBOTS)
    test(name, () => {
      const r = engine.robot(name);
      const command = r.info.num_motors ? "predict" : "run";
      let compared = 0;
      // The shipped programs (written for the MK2), and one move of this robot's own.
      const own = join(tmp, `${name}-move.arm`);
      writeFileSync(own, offHome(r.info));
      for (const path of [...PROGRAMS.map((p) => join(REPO, "programs", p)), own]) {
        const prog = path.split("/").pop();
        const text = readFileSync(path, "utf8");
        const ref = cli(command, name, path, "--json");
        let mine;
        try {
          mine = command === "predict" ? r.predict(text, prog) : r.run(text, prog);
        } catch (e) {
          assert.ok(e instanceof EngineError, String(e));
          // The CLI refused it too, with the same words (it names the file by its path).
          assert.equal(ref.json, null, `${name} ${prog}: the engine refused what the CLI took: ${e.message}`);
          // (a line for each line of the program that cannot be read)
          for (const said of e.message.split("\n"))
            assert.ok(ref.stderr.includes(said.replace(/^[^:]*:/, "")), `${name} ${prog}: '${ref.stderr}' vs '${e.message}'`);
          continue;
        }
        assert.ok(ref.json, `${name} ${prog}: the CLI refused what the engine took: ${ref.stderr}`);
        assert.equal(mine.records.length, ref.json.records.length, `${name} ${prog}: records`);
        mine.records.forEach((rec, i) => {
          const want = ref.json.records[i];
          assert.deepEqual(Object.keys(rec).sort(), Object.keys(want).sort(), `${name} ${prog} record ${i}: fields`);
          same(rec, want, `${name} ${prog} record ${i}`);
          if (command === "predict") {
            // Times are whole controller ticks: equal to the tick, not merely close.
            assert.equal(rec.start_tick, want.start_tick, `${name} ${prog} record ${i}: start tick`);
            assert.equal(rec.end_tick, want.end_tick, `${name} ${prog} record ${i}: end tick`);
          }
        });
        same(mine.summary, ref.json.summary, `${name} ${prog}: summary`);
        compared++;
      }
      assert.ok(compared > 0, `${name}: no program compared`);
      r.delete();
    });
});

// One robot in one scene with one program, the engine against `articula sim`.
function simParity(t, name, scene, text, progName) {
  const r = engine.robot(name);
  const prog = join(tmp, progName), traj = join(tmp, `${progName}.jsonl`), ev = join(tmp, `${progName}.events`);
  writeFileSync(prog, text);
  const ref = cli("sim", name, prog, "--scene", scene, "--json", "-o", traj, "--events", ev);
  assert.ok(ref.status === 0 || ref.status === 1, `${name} ${scene}: articula sim failed: ${ref.stderr}`);
  const rows = readFileSync(traj, "utf8").trim().split("\n").map((l) => JSON.parse(l));
  const events = readFileSync(ev, "utf8").trim().split("\n").filter(Boolean).map((l) => JSON.parse(l));
  const last = rows[rows.length - 1];
  const sim = engine.sim(r, readFileSync(join(REPO, "scenes", `${scene}.json`), "utf8"), `scenes/${scene}.json`);
  sim.loadProgram(text, progName);
  sim.runUntil(last.t);
  const mineEvents = sim.events();
  assert.deepEqual(mineEvents.map((e) => [Math.round(e.t * 1000), e.kind, e.a, e.b]),
    events.filter((e) => e.t <= last.t + 1e-9).map((e) => [Math.round(e.t * 1000), e.kind, e.a, e.b]),
    `${name} ${scene}: events (step, kind, parts)`);
  const st = sim.state();
  let worst = 0;
  for (const o of st.objects.filter((x) => x.movable)) { // the trajectory holds the movable ones
    const want = last.objects[o.name];
    assert.ok(want, `${name} ${scene}: ${o.name} is not in the CLI's trajectory`);
    close([o.pose[3], o.pose[7], o.pose[11]], want.xyz_mm, 0.1, `${name} ${scene} ${o.name} at ${last.t} s`);
    worst = Math.max(worst, Math.hypot(o.pose[3] - want.xyz_mm[0], o.pose[7] - want.xyz_mm[1], o.pose[11] - want.xyz_mm[2]));
  }
  close(st.joints, last.joints, 1e-9, `${name} ${scene}: joints at ${last.t} s`);
  t.diagnostic(`${(last.t * 1000).toFixed(0)} steps, ${mineEvents.length} events alike, ${Object.keys(last.objects).length} movable objects, ` +
    `largest difference ${worst.toExponential(2)} mm`);
  sim.delete();
  r.delete();
  return mineEvents.length;
}

describe("physics: every shipped scene, the same events at the same steps, objects within 0.1 mm", () => {
  for (const name of ROBOTS)
    for (const scene of SCENES)
      test(`${name} in ${scene}`, (t) => {
        const r = engine.robot(name);
        const text = offHome(r.info); // then the 1 s the CLI adds
        r.delete();
        simParity(t, name, scene, text, `${name}-${scene}.arm`);
      });
  test("mk2plus runs programs/grasp-and-lift.arm in its scene", (t) => {
    const text = readFileSync(join(REPO, "programs/grasp-and-lift.arm"), "utf8");
    const n = simParity(t, "mk2plus", "grasp-and-lift", text, "grasp-and-lift.arm");
    assert.ok(n >= 5, `grasp and lift makes events (contacts, a grasp): ${n}`);
  });
});

test("the physics' tool path: stepPath's points are the tool point after those world steps", () => {
  const r = engine.robot("mk2plus");
  const a = engine.sim(r, "", "ground"), b = engine.sim(r, "", "ground");
  a.loadProgram(offHome(r.info), "m.arm");
  b.loadProgram(offHome(r.info), "m.arm");
  const path = a.stepPath(2500, 100); // 2.5 s of world: a point after the 100th step, the 200th, ... the 2500th
  assert.equal(path.length, 25 * 3);
  for (let k = 0; k < 25; k++) {
    b.step(100);
    const T = b.state().tool; // the same world stepped alike: its tool point (row-major 4x4)
    const xyz = Array.isArray(T[0]) ? [T[0][3], T[1][3], T[2][3]] : [T[3], T[7], T[11]];
    for (let i = 0; i < 3; i++) assert.ok(Math.abs(path[3 * k + i] - xyz[i]) < 1e-9, `point ${k}: ${path.slice(3 * k, 3 * k + 3)} vs ${xyz}`);
  }
  assert.ok(Math.hypot(path[72] - path[0], path[73] - path[1], path[74] - path[2]) > 1, "the tool moved along the path");
  assert.equal(a.stepPath(7, 10).length, 3, "the last step's point, always");
  a.delete();
  b.delete();
  r.delete();
});

test("setBelt runs a scene's belt (a cube rides it at its speed) and refuses an object that is none", () => {
  const r = engine.robot("mk2plus");
  const scene = JSON.stringify({ objects: [
    { name: "belt", type: "box", size: [1200, 80, 10], xyz: [0, -500, 5], belt: 1 },
    { name: "cube", type: "box", size: [25, 25, 25], xyz: [-500, -500, 22.5], movable: true, mass: 0.02 }] });
  const sim = engine.sim(r, scene, "belt.json");
  sim.setBelt("belt", 100);
  sim.runUntil(1);
  const x = () => sim.state().objects[1].pose[3];
  const x0 = x();
  sim.runUntil(3);
  assert.ok(Math.abs((x() - x0) / 2 - 100) < 5, `${(x() - x0) / 2} mm/s`);
  assert.throws(() => sim.setBelt("cube", 10), (e) => e instanceof EngineError && /"cube" is not a belt/.test(e.message));
  sim.delete();
  r.delete();
});

test("a cell's mat is the CLI's (articula mat)", () => {
  const c = engine.cell(readFileSync(join(REPO, "cells", "station.json"), "utf8"), "station.json", "/cells");
  assert.equal(c.matSvg(), execFileSync(CLI, ["mat", "station"], { encoding: "utf8" }));
  c.delete();
});

const CELLS = readdirSync(join(REPO, "cells")).filter((f) => f.endsWith(".json") && !f.includes("schema"))
  .map((f) => f.replace(/\.json$/, ""));

describe("cells: every shipped cell, the same events and the same arms at the end as `articula sim CELL`", () => {
  for (const name of CELLS)
    test(name, (t) => {
      const ref = cli("sim", name, "--json");
      assert.ok(ref.status === 0 || ref.status === 1, `${name}: articula sim failed: ${ref.stderr}`);
      const cell = engine.cell(readFileSync(join(REPO, "cells", `${name}.json`), "utf8"), `cells/${name}.json`, "/cells");
      assert.deepEqual(cell.arms, ref.json.arms.map((a) => a.name));
      cell.run();
      assert.equal(cell.done, true);
      const mine = cell.events();
      assert.deepEqual(mine.map((e) => [Math.round(e.t * 1000), e.kind, e.arm, e.a, e.b]),
        ref.json.events.map((e) => [Math.round(e.t * 1000), e.kind, e.arm, e.a, e.b]), `${name}: events`);
      const st = cell.state();
      st.arms.forEach((a, i) => {
        const want = ref.json.arms[i];
        close(a.joints, want.joints, 1e-9, `${name} ${a.name}: joints`);
        assert.deepEqual(a.counted_steps, want.counted_steps, `${name} ${a.name}: steps`);
        assert.deepEqual(a.lost_steps, want.lost_steps, `${name} ${a.name}: lost`);
      });
      st.objects.forEach((o, i) => close(o.xyz_mm, ref.json.objects[i].xyz_mm, 0.1, `${name} ${o.name}`));
      t.diagnostic(`${cell.arms.length} arms, ${mine.length} events alike`);
      assert.throws(() => engine.cell(JSON.stringify({ name: "x", arms: [{ name: "a", robot: "mk2plus" },
        { name: "b", robot: "mk2plus", base: { xyz: [10, 0, 0] } }] }), "cells/x.json"), (e) => {
        assert.ok(e instanceof EngineError);
        assert.equal(e.json_path, "/arms/1/base");
        assert.match(e.message, /cells\/x\.json: \/arms\/1\/base: the bases of "b" and "a" overlap/);
        return true;
      });
      assert.throws(() => cell.arm("nobody"), /no arm 'nobody'/);
      cell.delete();
    });
});

describe("bad input gets the CLI's words, and the robot that was there stays", () => {
  test("a malformed robot file names the file, the JSON path and the problem", () => {
    const r = engine.robot("mk2plus");
    const bad = JSON.parse(readFileSync(join(REPO, "robots/mk2plus.json"), "utf8"));
    bad.dh[1].a = -5;
    bad.dh[1].alpha = "ninety";
    const path = join(tmp, "bad.json");
    writeFileSync(path, JSON.stringify(bad));
    const ref = cli("info", path);
    assert.throws(() => r.parse(JSON.stringify(bad), path), (e) => {
      assert.ok(e instanceof EngineError);
      assert.ok(ref.stderr.includes(e.message), `'${ref.stderr}' vs '${e.message}'`);
      assert.match(e.json_path, /^\/dh\/1/);
      return true;
    });
    assert.equal(r.info.name, "MK2 Plus", "the robot that was there stays");
    assert.throws(() => r.parse("{", "x.json"), /x\.json: JSON syntax error/);
    assert.throws(() => r.pose([0, NaN, 0]), /q\[1\] \(shoulder\) is NaN: joint values must be finite numbers/);
    assert.throws(() => r.pose([0, 0]), /q has 2 values; MK2 Plus has 3 joint variables/);
    assert.throws(() => r.ik({ target: [1, 2] }), /target must be/);
    assert.throws(() => r.ik({ target: [100, 0, 100], solver: "magic" }), /unknown solver 'magic'/);
    assert.throws(() => engine.sim(r, "{\"objects\": 5}", "scenes/x.json"), /scenes\/x\.json: \/objects/);
    assert.equal(r.ik({ target: [200, 0, 150] }).status, "reached", "and it still works");
    r.delete();
  });
});

after(() => rmSync(tmp, { recursive: true, force: true })); // the CLI's files, the trajectories
