// The drawing's budget: the trails' segments per frame adapt to the frame
// rate on an injected clock (so these checks do not depend on this
// machine's speed), and the positions are drawn in full whatever the
// budget. In Node for the rule, in the page for its use at 1024 chains.
import assert from "node:assert/strict";
import { test } from "node:test";
import { DrawBudget, trailAges } from "../js/pace.js";
import { h, noProblems, openPaused, setControl, setUp, untilIteration } from "./harness.mjs";

/** A clock that moves `ms` per frame (DrawBudget reads it once a frame). */
const clock = (ms) => {
  let t = 0;
  return () => (t += ms);
};

test("slow frames shrink the trails' budget to its floor; fast ones grow it back to full trails", () => {
  const budget = new DrawBudget(clock(50));
  for (let f = 0; f < 20; f++) budget.frame();
  assert.equal(budget.cap, budget.min);
  // At 1024 chains and 39 ages kept, the frame draws at most the cap.
  const ages = trailAges(39, 1024, budget.cap);
  assert.ok(ages >= 1 && ages * 1024 <= budget.cap, `${ages} ages`);
  // Frames at 60 per second: the cap grows until the whole trails fit.
  budget.now = clock(1000 / 60);
  for (let f = 0; f < 200; f++) budget.frame();
  assert.equal(trailAges(39, 1024, budget.cap), 39);
  // Between the two thresholds the cap holds.
  const held = budget.cap;
  budget.now = clock(19.5);
  for (let f = 0; f < 10; f++) budget.frame();
  assert.equal(budget.cap, held);
});

test("a trail is at least one segment long when any is kept, and none when none is", () => {
  assert.equal(trailAges(39, 100_000, 2048), 1);
  assert.equal(trailAges(0, 1024, 1e9), 0);
  assert.equal(trailAges(39, 256, 1e9), 39);
});

setUp();

/** The positions after 20 steps (ten frames of 2), on a slow clock or the page's own. */
async function positionsAfter20(slow) {
  await openPaused({ chains: 1024 });
  if (slow) {
    // Every reading of the clock 50 ms after the last: each frame is slow.
    await h.page.evaluate(() => {
      let t = 0;
      window.hrlaDemo.setClock(() => (t += 50));
    });
  }
  for (let k = 1; k <= 10; k++) {
    await h.page.evaluate(() => document.activeElement?.blur());
    await h.page.keyboard.press(".");
    await untilIteration(2 * k);
  }
  return h.page.evaluate(() => [...window.hrlaDemo.state.runs[0].x]);
}

test("at 1024 chains on a slow clock the moving trails are cut to the budget, every chain's dot is drawn where it is, and the still picture is whole", async () => {
  const fast = await positionsAfter20(false);
  const slow = await positionsAfter20(true);
  // The budget touches the picture only: the positions are the same.
  assert.deepEqual(slow, fast);
  // Many steps asked: on the slow clock each frame does one, so the run
  // keeps moving for many frames, at the budget's floor.
  await setControl("spf", 100000);
  await h.page.evaluate(() => document.activeElement?.blur());
  await h.page.keyboard.press(".");
  await h.page.waitForFunction(() => {
    const { state } = window.hrlaDemo;
    return state.pending > 0 && state.lastDraw.cap === state.drawBudget.min;
  });
  // One task: the state and the canvas read from the same frame.
  const seen = await h.page.evaluate(async () => {
    const { Summary } = await import("/js/sim.js");
    const { state } = window.hrlaDemo;
    const r = state.runs[0];
    const f = state.frame;
    const canvas = document.getElementById("particles");
    const data = canvas.getContext("2d").getImageData(0, 0, canvas.width, canvas.height).data;
    const best = [f.px(r.s[Summary.BestX0]), f.py(r.s[Summary.BestX1])];
    const missing = [];
    let checked = 0;
    for (let c = 0; c < r.n; c++) {
      const px = f.px(r.x[2 * c]);
      const py = f.py(r.x[2 * c + 1]);
      if (px < f.left + 3 || px > f.left + f.width - 3 || py < f.top + 3 || py > f.top + f.height - 3) continue;
      // Away from the running best's ring, each dot, drawn over the trails, is white at its centre.
      if (Math.hypot(px - best[0], py - best[1]) < 11) continue;
      checked++;
      const k = 4 * (Math.round(py * state.dpr) * canvas.width + Math.round(px * state.dpr));
      if (!(data[k] > 230 && data[k + 1] > 230 && data[k + 2] > 230 && data[k + 3] > 230)) missing.push(c);
    }
    return { lastDraw: state.lastDraw, kept: r.trails.count - 1, missing, checked };
  });
  const { ages, segments, cap } = seen.lastDraw;
  assert.ok(segments <= cap, `${segments} segments over a cap of ${cap}`);
  assert.ok(ages >= 1 && ages < seen.kept, `${ages} of ${seen.kept} ages drawn`);
  assert.ok(seen.checked > 900, `only ${seen.checked} chains checked`);
  assert.deepEqual(seen.missing, []);
  // Still (Step drops the steps still asked and pauses), the picture is
  // drawn whole: every trail point kept.
  await h.page.click("#step");
  await h.page.waitForFunction(() => {
    const { state } = window.hrlaDemo;
    return state.pending === 0 && !state.playing && state.lastDraw.ages === state.runs[0].trails.count - 1;
  });
});

test("no console error, failed request or request leaving 127.0.0.1", () => noProblems());
