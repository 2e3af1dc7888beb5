// The step laid bare where the eye is: Step draws a loupe on the picture
// itself, in the first screen of a 1366 x 768 display, beside the chosen
// chain, building the step in stages (gradient, momentum, mean, Gaussian,
// draw). The stage is state on the overlay (data-stage, data-settled): the
// tests hold a stage or wait for the settled one, never for time to pass.
// In compare mode every sampler's step is drawn at one magnification.
import assert from "node:assert/strict";
import { join } from "node:path";
import { test } from "node:test";
import { SHOTS, h, noProblems, openPaused, setUp, untilIteration } from "./harness.mjs";

const SCREEN = { width: 1366, height: 768 };
setUp(SCREEN);

/** The overlay's RGBA at CSS point [x, y]. */
async function overlayAt([x, y]) {
  return h.page.evaluate(
    ([x, y]) => {
      const dpr = window.hrlaDemo.state.dpr;
      const d = document.getElementById("step-overlay").getContext("2d").getImageData(Math.round(x * dpr), Math.round(y * dpr), 1, 1).data;
      return [...d];
    },
    [x, y],
  );
}

const near = (rgba, [r, g, b]) => Math.hypot(rgba[0] - r, rgba[1] - g, rgba[2] - b) < 40;
const DRAW = [0xff, 0x5a, 0x36];
const MEAN = [0xff, 0xd1, 0x66];

async function step(k) {
  await h.page.click("#step");
  await untilIteration(k);
}

test("Step lays the step bare on the picture, in the first screen, stage by stage", async () => {
  await openPaused();
  assert.equal(await h.page.getAttribute("#step-overlay", "data-stage"), "");
  await step(1);
  // The animation runs to its settled last stage by itself.
  await h.page.waitForSelector("#step-overlay[data-settled=true][data-stage=draw]", { timeout: 30_000 });
  const at = (name) => h.page.evaluate((name) => window.hrlaDemo.holdStage(name), name);
  const first = await at("gradient");
  assert.equal(await h.page.getAttribute("#step-overlay", "data-stage"), "gradient");
  assert.equal(first.loupes.length, 1);
  const loupe = first.loupes[0];
  // The loupe lies in the picture's plot area, and that in the first screen.
  const frame = await h.page.evaluate(() => {
    const f = window.hrlaDemo.state.frame;
    const box = document.getElementById("step-overlay").getBoundingClientRect();
    return { left: f.left, top: f.top, width: f.width, height: f.height, pageTop: box.top + window.scrollY };
  });
  const [bx, by, side] = loupe.box;
  assert.ok(bx >= frame.left && bx + side <= frame.left + frame.width, "loupe outside the plot area");
  assert.ok(by >= frame.top && by + side <= frame.top + frame.height, "loupe outside the plot area");
  assert.ok(side >= 0.4 * frame.width, `loupe ${side} px wide on a ${frame.width} px picture`);
  assert.ok(frame.pageTop + by + side <= SCREEN.height, `loupe ends at ${frame.pageTop + by + side} px, below the first screen`);
  // The stages add their parts: no mean or draw at the first; both at the last.
  assert.ok(!near(await overlayAt(loupe.mean), MEAN), "the mean is drawn at the gradient's stage");
  assert.ok(!near(await overlayAt(loupe.draw), DRAW), "the draw is drawn at the gradient's stage");
  await at("mean");
  assert.ok(near(await overlayAt(loupe.mean), MEAN), "no mean at the mean's stage");
  assert.ok(!near(await overlayAt(loupe.draw), DRAW), "the draw is drawn at the mean's stage");
  const last = await at("draw");
  assert.deepEqual(last.loupes[0].draw, loupe.draw);
  assert.ok(near(await overlayAt(loupe.draw), DRAW), "no draw at the last stage");
  // The loupe's draw is the chain's new position: its offset from the
  // mean, over the loupe's scale, is the kernel's draw minus the mean.
  const { law, draw } = await h.page.evaluate(() => window.hrlaDemo.state.anatomy.parts[0]);
  const scale = loupe.scale;
  assert.ok(Math.abs((loupe.draw[0] - loupe.mean[0]) / scale - (draw[0] - law.mean[0])) < 1e-9);
  assert.ok(Math.abs(-(loupe.draw[1] - loupe.mean[1]) / scale - (draw[1] - law.mean[1])) < 1e-9);
  await h.page.screenshot({ path: join(SHOTS, "step-view-desktop.png") });
  // Moving the run on by other means clears the loupe: it would be stale.
  await h.page.evaluate(() => document.activeElement?.blur());
  await h.page.keyboard.press(".");
  await untilIteration(3);
  await h.page.waitForSelector("#step-overlay[data-stage='']");
});

test("with reduced motion, Step shows the finished step at once", async () => {
  await h.page.emulateMedia({ reducedMotion: "reduce" });
  try {
    await openPaused();
    await step(1);
    assert.equal(await h.page.getAttribute("#step-overlay", "data-stage"), "draw");
    assert.equal(await h.page.getAttribute("#step-overlay", "data-settled"), "true");
  } finally {
    await h.page.emulateMedia({ reducedMotion: null });
  }
});

test("compare mode draws the three samplers' steps at one magnification, said on the picture", async () => {
  await openPaused({ compare: 1 });
  await step(1);
  const view = await h.page.evaluate(() => window.hrlaDemo.holdStage("draw"));
  assert.equal(view.loupes.length, 3);
  assert.equal(new Set(view.loupes.map((l) => l.scale)).size, 1, "the loupes' scales differ");
  assert.equal(Number(await h.page.getAttribute("#step-overlay", "data-magnification")), view.magnification);
  // The panel's insets too: one magnification, the same words.
  const spans = await h.page.evaluate(() => window.hrlaDemo.anatomySpans());
  assert.equal(spans.length, 3);
  assert.equal(new Set(spans.map((s) => s.scale)).size, 1, `the insets' scales differ: ${spans.map((s) => s.zoom)}`);
  const zooms = await h.page.$$eval("#anatomy-runs .zoom", (els) => els.map((e) => e.textContent));
  assert.equal(new Set(zooms).size, 1, zooms.join(" / "));
  // At one magnification, sizes compare: ULA's Gaussian, all of it
  // through the velocity, is drawn far smaller than HRLA's.
  const parts = await h.page.evaluate(() => window.hrlaDemo.state.anatomy.parts);
  const sigma = (p) => Math.sqrt(p.law.moments[0].varX);
  assert.ok(spans[1].sigmaPx < spans[0].sigmaPx / 10);
  assert.ok(Math.abs(spans[1].sigmaPx / spans[0].sigmaPx - sigma(parts[1]) / sigma(parts[0])) < 1e-9);
  await h.page.screenshot({ path: join(SHOTS, "step-view-compare.png") });
});

test("the words claim a position-velocity correlation only where the picture shows one", async () => {
  await openPaused({ compare: 1 });
  await step(1);
  const parts = await h.page.evaluate(() => window.hrlaDemo.state.anatomy.parts);
  const words = await h.page.$$eval("#anatomy-runs .anatomy-run", (els) => els.map((e) => e.textContent));
  for (const [k, part] of parts.entries()) {
    const m = part.law.moments[0];
    if (!(m.varY > 0)) continue;
    const rho = m.cov / Math.sqrt(m.varX * m.varY);
    if (Math.abs(rho) < 0.1) {
      assert.match(words[k], /nearly uncorrelated/, part.sampler);
      assert.doesNotMatch(words[k], /which no Euler scheme has/, part.sampler);
    } else assert.match(words[k], /correlated, ρ = .*tilts/, part.sampler);
  }
});

test("no console error, failed request or request leaving 127.0.0.1", () => noProblems());
