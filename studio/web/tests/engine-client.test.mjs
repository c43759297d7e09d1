// The page's engine client in node (src/page/engine-client.ts), against a stand-in worker that
// records what reaches it: edits reach the engine in the order the student made them, and a
// pose older than an edit is known as such (issue 41: a typed value dropped).
import assert from "node:assert/strict";
import { test } from "node:test";
import { load } from "./page-module.mjs";

/** An EngineClient on a worker that answers nothing until told to. */
async function client() {
  const posted = [];
  globalThis.document = { baseURI: "http://localhost/studio/" };
  globalThis.Worker = class {
    postMessage(m) { posted.push(m); }
  };
  const { EngineClient } = await load("page/engine-client.ts");
  const c = new EngineClient();
  c.ready = true;
  return { c, posted };
}

const edits = (posted) => posted.filter((m) => m.type === "set_joint").map((m) => `${m.joint}=${m.value}`);

test("six values typed with no pause all reach the engine, in order", async () => {
  const { c, posted } = await client();
  // keystroke by keystroke, the engine answering nothing meanwhile: "11" into joint 0, "22" into 1, ...
  for (let j = 0; j < 6; j++) {
    const d = String(j + 1);
    c.request({ type: "set_joint", joint: j, value: Number(d) });
    c.request({ type: "set_joint", joint: j, value: Number(d + d) });
  }
  assert.deepEqual(edits(posted), ["0=1", "0=11"], "two in flight, the rest waiting");
  for (let k = 0; k < 10 && posted.length < 12; k++) c.applied(posted[posted.length - 1].seq);
  assert.deepEqual(edits(posted), ["0=1", "0=11", "1=22", "2=33", "3=44", "4=55", "5=66"],
    "each joint's last value, none lost: only a box's own earlier keystrokes are replaced");
});

test("a drag sends its newest position; other messages never overtake a waiting edit", async () => {
  const { c, posted } = await client();
  for (let v = 1; v <= 5; v++) c.request({ type: "set_joint", joint: 2, value: v });
  c.send({ type: "home" });
  c.request({ type: "set_joint", joint: 2, value: 9 });
  assert.deepEqual(posted.map((m) => m.type === "home" ? "home" : `${m.joint}=${m.value}`), ["2=1", "2=2"]);
  c.applied(posted[0].seq);
  c.applied(posted[1].seq);
  c.applied(posted[posted.length - 1].seq);
  assert.deepEqual(posted.map((m) => m.type === "home" ? "home" : `${m.joint}=${m.value}`), ["2=1", "2=2", "2=5", "home", "2=9"],
    "Home after the edits made before it, the edit after it last");
});

test("a pose older than a box's edit is known as older", async () => {
  const { c, posted } = await client();
  c.request({ type: "set_joint", joint: 0, value: 10 });
  c.request({ type: "set_joint", joint: 1, value: 20 });
  const [a, b] = posted.map((m) => m.seq);
  assert.equal(c.editedSince("set_joint:1", a), true, "the answer to joint 0's edit predates joint 1's");
  assert.equal(c.editedSince("set_joint:0", a), false);
  assert.equal(c.editedSince("set_joint:1", b), false);
  assert.equal(c.editedSince("set_joint:1", null), true, "a pose of its own, before any answer");
  c.applied(b);
  assert.equal(c.editedSince("set_joint:1", null), false, "a pose of its own, after the answer");
});
