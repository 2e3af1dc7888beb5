// One step laid bare: what the panel shows is the kernel's law of the
// chosen chain's next step (the wrapper's nextStep, read before the step)
// and the step the run then took; for the three samplers side by side in
// compare mode. That the law is the one the step draws from is checked
// statistically by the wrapper's own tests (next_step_is_the_law_the_step_draws_from).
import assert from "node:assert/strict";
import { join } from "node:path";
import { test } from "node:test";
import { SHOTS, h, noProblems, openPaused, setUp, untilIteration } from "./harness.mjs";

setUp();

/** The same settings run independently: the law of chain c's step at iteration k and the position after it. */
async function independent(settings, c, k) {
  return h.page.evaluate(
    async ([settings, c, k]) => {
      const sim = await import("/js/sim.js");
      const { readNextStep } = await import("/js/anatomy.js");
      const r = new sim.Run({ ...settings, seed: BigInt(settings.seed) }, 10);
      r.opt.advance(k);
      const law = readNextStep(r.nextStep(c));
      r.opt.advance(1);
      r.rebind();
      const out = { law, draw: [r.x[2 * c], r.x[2 * c + 1]] };
      r.free();
      return out;
    },
    [settings, c, k],
  );
}

const RASTRIGIN = { potential: "rastrigin", a: 4, annealing: null, h: 0.01, chains: 256, centre: [3, 3], spread: 0.5, seed: 1, stopSteps: null, stopTarget: null, escape: 5000 };

test("Step shows the kernel's law of chain 0's next step and the draw the run took", async () => {
  await openPaused();
  for (let k = 1; k <= 3; k++) {
    await h.page.click("#step");
    await untilIteration(k);
  }
  const shown = await h.page.evaluate(() => window.hrlaDemo.state.anatomy);
  assert.equal(shown.iteration, 3);
  assert.equal(shown.chain, 0);
  assert.equal(shown.parts.length, 1);
  const want = await independent({ ...RASTRIGIN, sampler: "hrla" }, 0, 2);
  assert.deepEqual(shown.parts[0].law, want.law);
  assert.deepEqual(shown.parts[0].draw, want.draw);
  // The words carry the same numbers.
  const words = await h.page.textContent("#anatomy-runs");
  assert.match(words, /gradient, frozen/);
  assert.match(words, /noise of its own on the position/);
  assert.ok(words.includes(String(+want.law.a.toPrecision(3))) || words.includes("a = 4"));
  assert.match(await h.page.textContent("#anatomy-intro"), /Step 2 → 3 of chain 0/);
  // Moving the run on by other means hides the panel: it would be stale.
  await h.page.evaluate(() => document.activeElement?.blur());
  await h.page.keyboard.press(".");
  await untilIteration(5);
  await h.page.waitForFunction(() => document.getElementById("anatomy").hidden);
});

test("compare mode lays the three samplers' steps side by side, each the kernel's", async () => {
  await openPaused({ compare: 1, chains: 64 });
  await h.page.click("#step");
  await untilIteration(1);
  const columns = await h.page.$$eval("#anatomy-runs .anatomy-run", (els) =>
    els.map((e) => ({ title: e.querySelector("h3").textContent, top: e.getBoundingClientRect().top, text: e.textContent })),
  );
  assert.deepEqual(
    columns.map((c) => c.title.split(" ")[0]),
    ["HRLA", "ULA", "OLA"],
  );
  assert.equal(new Set(columns.map((c) => Math.round(c.top))).size, 1, "the three are not side by side");
  assert.match(columns[2].text, /OLA has no velocity/);
  assert.match(columns[1].text, /no noise of its own on the position/);
  const shown = await h.page.evaluate(() => window.hrlaDemo.state.anatomy.parts);
  for (const [k, sampler] of ["hrla", "ula", "ola"].entries()) {
    const want = await independent({ ...RASTRIGIN, chains: 64, sampler }, 0, 0);
    assert.deepEqual(shown[k].law, want.law, sampler);
    assert.deepEqual(shown[k].draw, want.draw, sampler);
  }
  // OLA's law has no velocity part; HRLA's and ULA's do.
  assert.equal(shown[2].law.moments[0].varY, 0);
  assert.ok(shown[0].law.moments[0].varY > 0 && shown[1].law.moments[0].varY > 0);
  await h.page.locator("#anatomy").screenshot({ path: join(SHOTS, "anatomy-compare.png") });
});

test("a click on a chain chooses whose step is laid bare", async () => {
  await openPaused({ chains: 64 });
  const target = await h.page.evaluate(() => {
    const { state } = window.hrlaDemo;
    const r = state.runs[0];
    // The chain farthest from chain 0, so that the click is unambiguous.
    let best = 1;
    let far = 0;
    for (let c = 1; c < r.n; c++) {
      const d = Math.hypot(r.x[2 * c] - r.x[0], r.x[2 * c + 1] - r.x[1]);
      if (d > far) {
        far = d;
        best = c;
      }
    }
    return { c: best, px: state.frame.px(r.x[2 * best]), py: state.frame.py(r.x[2 * best + 1]) };
  });
  await h.page.locator("#particles").click({ position: { x: target.px, y: target.py } });
  await h.page.click("#step");
  await untilIteration(1);
  assert.equal(await h.page.evaluate(() => window.hrlaDemo.state.anatomy.chain), target.c);
  const want = await independent({ ...RASTRIGIN, chains: 64, sampler: "hrla" }, target.c, 0);
  assert.deepEqual(await h.page.evaluate(() => window.hrlaDemo.state.anatomy.parts[0].law), want.law);
});

test("no console error, failed request or request leaving 127.0.0.1", () => noProblems());
