// Baselines a visitor understands: plain gradient descent with random
// restarts beside the samplers, from the same starts; and, under
// annealing, the inverse temperature a(t) drawn with the run's place on it.
import assert from "node:assert/strict";
import { test } from "node:test";
import { advance, h, noProblems, openPaused, readout, setUp } from "./harness.mjs";

setUp();

test("gradient descent with restarts runs beside the sampler, from the same starts, and is explained", async () => {
  await openPaused({ descent: 1, chains: 64, spf: 100 });
  assert.equal(await h.page.isVisible("#descent-about"), true);
  const start = await h.page.evaluate(() => window.hrlaDemo.state.runs.map((r) => ({ sampler: r.sampler, x: [...r.x] })));
  assert.deepEqual(start.map((r) => r.sampler), ["hrla", "gd"]);
  assert.deepEqual(start[1].x, start[0].x);
  assert.match(await h.page.textContent("#compare-table"), /GD \+ restarts/);
  let before = await h.page.evaluate(() => [...window.hrlaDemo.state.runs[1].u]);
  for (let k = 1; k <= 5; k++) {
    await advance(100 * k);
    const now = await h.page.evaluate(() => {
      const r = window.hrlaDemo.state.runs[1];
      return { u: [...r.u], x: [...r.x], restarts: r.opt.restarts(), iteration: r.iteration };
    });
    assert.equal(now.iteration, 100 * k);
    // Each chain's published value is its best so far: it never rises.
    now.u.forEach((u, c) => assert.ok(u <= before[c], `chain ${c}: ${before[c]} -> ${u}`));
    // Every chain is in the view's box, where it restarts.
    assert.ok(now.x.every((v) => v >= -5 && v <= 5), "a descent chain outside the box");
    before = now.u;
    if (k === 5) assert.ok(now.restarts > 64, `${now.restarts} restarts`);
  }
  // The page's descent is the wrapper's, replayed independently.
  const replay = await h.page.evaluate(async () => {
    const sim = await import("/js/sim.js");
    const r = new sim.Run({ potential: "rastrigin", sampler: "hrla", a: 4, annealing: null, h: 0.01, chains: 64, centre: [3, 3], spread: 0.5, seed: 1n, stopSteps: null, stopTarget: null }, 10, [-5, 5, -5, 5]);
    r.opt.advance(500);
    r.rebind();
    const out = [...r.u];
    r.free();
    return out;
  });
  assert.deepEqual(replay, before);
  assert.equal(await readout("cmp-prob-gd"), await h.page.evaluate(() => window.hrlaDemo.state.runs[1].fractionWithin(0.5)));
  // Descent draws nothing: Step lays bare the sampler's step only.
  await h.page.click("#step");
  await h.page.waitForFunction(() => Number(document.getElementById("out-iteration").dataset.value) === 501);
  assert.deepEqual(await h.page.evaluate(() => window.hrlaDemo.state.anatomy.parts.map((p) => p.sampler)), ["hrla"]);
});

test("under annealing, a(t) is drawn with the run's place on it; not under a constant a", async () => {
  await openPaused({ schedule: "linear", aLow: 0.5, aHigh: 4, K: 2000, spf: 500 });
  assert.equal(await h.page.isVisible("#plot-a"), true);
  for (let k = 1; k <= 3; k++) {
    await advance(500 * k);
    const plot = await h.page.evaluate(() => window.hrlaDemo.state.schedulePlot);
    assert.deepEqual(plot.points.slice(0, 2), [
      [0, 0.5],
      [2000, 4],
    ]);
    const a = await readout("out-a");
    assert.deepEqual(plot.marker, [500 * k, a]);
    // The kernel's a of the last step, on the line drawn (a_k at k - 1).
    assert.ok(Math.abs(a - (0.5 + (3.5 * (500 * k - 1)) / 2000)) < 1e-12, `a = ${a} at ${500 * k}`);
    // The dot is drawn where the plot says.
    const [r, g] = await h.page.evaluate(([x, y]) => {
      const c = document.getElementById("plot-a");
      const dpr = window.devicePixelRatio || 1;
      const d = c.getContext("2d").getImageData(Math.round(x * dpr), Math.round(y * dpr), 1, 1).data;
      return [d[0], d[1]];
    }, plot.px);
    assert.ok(r > 200 && g < 150, `the dot's colour (${r}, ${g})`);
  }
  await h.page.check("#schedule-constant");
  assert.equal(await h.page.isVisible("#plot-a"), false);
});

test("no console error, failed request or request leaving 127.0.0.1", () => noProblems());
