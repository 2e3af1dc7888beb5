// h and a on the running chains: a slider (or the exact field beside it)
// changes them without a restart, every chain going on from where it is;
// the change is recorded in the address with its iteration, and the
// address replays the run, change included, bit for bit.
import assert from "node:assert/strict";
import { test } from "node:test";
import { advance, h, load, noProblems, openPaused, readout, setControl, setUp } from "./harness.mjs";

setUp();

/** Every chain's position and value, and the running best, as exact numbers. */
const snapshot = () =>
  h.page.evaluate(() => {
    const r = window.hrlaDemo.state.runs[0];
    return { x: [...r.x], u: [...r.u], best: document.getElementById("out-best").dataset.value };
  });

/** Moves a slider by keys (each press is a change, as a person's). */
async function slide(id, key, presses) {
  await h.page.focus(`#${id}`);
  for (let i = 0; i < presses; i++) await h.page.keyboard.press(key);
}

test("a change of h acts on the running chains, and the address replays it bit for bit", async () => {
  await openPaused({ spf: 50, seed: 5 });
  await advance(50);
  await advance(100);
  const before = await snapshot();
  await setControl("h", 0.03);
  // No restart: the same iteration, every chain where it was.
  assert.equal(await readout("out-iteration"), 100);
  assert.deepEqual(await snapshot(), before);
  assert.equal(await h.page.textContent("#error"), "");
  // The slider shows the value typed (to its step of 0.01 in log10 h).
  assert.ok(Math.abs(Number(await h.page.inputValue("#h-slider")) - Math.log10(0.03)) <= 0.005);
  const url = new URL(h.page.url());
  assert.equal(url.searchParams.get("h"), "0.01");
  assert.equal(url.searchParams.get("tune"), "100:0.03:4");
  await advance(150);
  await advance(200);
  const after = await snapshot();
  // The step took the new h: the run differs from one left at 0.01.
  await openPaused({ spf: 50, seed: 5 });
  for (const k of [50, 100, 150, 200]) await advance(k);
  assert.notDeepEqual((await snapshot()).x, after.x);
  // The address replays the change at iteration 100, whatever the frames: 200 steps in frames of 40.
  url.searchParams.set("spf", "40");
  await load(url.href);
  assert.equal(await h.page.inputValue("#h"), "0.01");
  for (const k of [40, 80, 120, 160, 200]) await advance(k);
  assert.deepEqual(await snapshot(), after);
  assert.equal(await h.page.inputValue("#h"), "0.03");
  // Reset replays the same run again, change included.
  await h.page.click("#reset");
  assert.equal(await h.page.inputValue("#h"), "0.01");
  for (const k of [40, 80, 120, 160, 200]) await advance(k);
  assert.deepEqual(await snapshot(), after);
});

test("the a slider changes a on the running chains; two changes replay from the address", async () => {
  await openPaused({ spf: 20, seed: 9 });
  await advance(20);
  await slide("a-slider", "ArrowLeft", 1);
  // One slider step: log10 a from 0.6 to 0.59.
  assert.equal(await h.page.inputValue("#a"), String(+(10 ** 0.59).toPrecision(3)));
  assert.equal(await readout("out-iteration"), 20);
  assert.equal(await readout("out-a"), +(10 ** 0.59).toPrecision(3));
  await advance(40);
  await setControl("h", 0.02);
  await advance(60);
  const after = await snapshot();
  const url = new URL(h.page.url());
  assert.equal(url.searchParams.get("a"), "4");
  assert.equal(url.searchParams.get("tune"), `20:0.01:${+(10 ** 0.59).toPrecision(3)},40:0.02:${+(10 ** 0.59).toPrecision(3)}`);
  await load(url.href);
  assert.equal(await readout("out-a"), 4);
  for (const k of [20, 40, 60]) await advance(k);
  assert.deepEqual(await snapshot(), after);
});

test("in compare mode every sampler takes the change at the same iteration, and the address replays all three", async () => {
  await openPaused({ spf: 30, seed: 2, compare: "1" });
  await advance(30);
  await setControl("a", 2);
  for (const k of [60, 90]) await advance(k);
  const all = () => h.page.evaluate(() => window.hrlaDemo.state.runs.map((r) => ({ a: r.s[5], x: [...r.x] })));
  const after = await all();
  assert.deepEqual(after.map((r) => r.a), [2, 2, 2]);
  await load(h.page.url());
  for (const k of [30, 60, 90]) await advance(k);
  assert.deepEqual(await all(), after);
});

test("a refused h leaves the run going as it was, the field saying why", async () => {
  await openPaused({ spf: 20 });
  await advance(20);
  await setControl("h", -1);
  assert.match(await h.page.textContent("#err-h"), /step h/);
  assert.equal(await h.page.getAttribute("#h", "aria-invalid"), "true");
  assert.equal(await h.page.isDisabled("#step"), false);
  assert.equal(new URL(h.page.url()).searchParams.get("tune"), null);
  await advance(40);
});

test("under annealing the a slider is off, with a title saying why; h still changes mid-run", async () => {
  await openPaused({ spf: 20, schedule: "linear" });
  assert.equal(await h.page.isDisabled("#a-slider"), true);
  assert.match(await h.page.getAttribute("#a-slider", "title"), /Annealing sets a at every step/);
  await advance(20);
  await setControl("h", 0.02);
  assert.equal(await readout("out-iteration"), 20);
  assert.equal(new URL(h.page.url()).searchParams.get("tune"), "20:0.02:");
  await advance(40);
});

test("an address with changes that are not changes is said so, and the run starts without them", async () => {
  await openPaused({ tune: "30:0.02:4,10:0.01:4" });
  assert.match(await h.page.textContent("#err-general"), /changes of h and a during the run “30:0\.02:4,10:0\.01:4”, which must be changes k:h:a at increasing iterations/);
});

test("no console error, failed request or request leaving 127.0.0.1", () => noProblems());
