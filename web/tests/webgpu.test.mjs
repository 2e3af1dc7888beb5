// The page's WebGPU section on a real adapter: Chromium with
// --enable-unsafe-webgpu (on this project's machines, SwiftShader's
// "google swiftshader", a CPU implementation of WebGPU). Where Chromium
// offers no adapter, every test here says so loudly and is skipped; the
// fallback itself is tested in webgpu-fallback.test.mjs.
//
// No test depends on timing: each run is started, stepped by an explicit
// number of steps ("+ steps"), and read once the iteration readout shows
// that number. The law tests take the kernel's own coefficients (the wasm
// export `coefficients`) and compare the chains' moments with the closed
// form of the linear Gaussian recursion on the quadratic bowl.
import assert from "node:assert/strict";
import { join } from "node:path";
import { test } from "node:test";
import { VIRIDIS } from "../js/colormap.js";
import { h, noProblems, openPaused, setControl, setUp, SHOTS } from "./harness.mjs";

setUp({ width: 1280, height: 800 }, ["--enable-unsafe-webgpu"]);

/** Whether the page found an adapter; if not, says so loudly and skips `t`. */
async function adapterOr(t) {
  await h.page.waitForFunction(() => document.getElementById("gpu-status").dataset.state !== "probing", null, { timeout: 30_000 });
  if ((await h.page.getAttribute("#gpu-status", "data-state")) !== "unavailable") return true;
  const why = await h.page.textContent("#gpu-status");
  console.warn(`WARNING: WebGPU test SKIPPED: headless Chromium offers no WebGPU adapter here (${why})`);
  t.skip("no WebGPU adapter in headless Chromium");
  return false;
}

/** Starts a device run of `chains` chains on the page's settings and waits for iteration 0. */
async function startRun(chains) {
  await h.page.fill("#gpu-chains", String(chains));
  await h.page.click("#gpu-start");
  await h.page.waitForFunction(
    () => document.getElementById("gpu-iteration").dataset.value === "0" || document.getElementById("gpu-status").dataset.state === "error",
    null,
    { timeout: 60_000 },
  );
  assert.equal(await h.page.textContent("#gpu-error"), "");
  assert.equal(await h.page.getAttribute("#gpu-iteration", "data-value"), "0");
}

/** `k` more steps with "+ steps"; waits until the readout shows `until`. */
async function stepRun(k, until) {
  await h.page.fill("#gpu-steps", String(k));
  await h.page.click("#gpu-forward");
  await h.page.waitForFunction(
    (n) => document.getElementById("gpu-iteration").dataset.value === String(n) || document.getElementById("gpu-status").dataset.state === "error",
    until,
    { timeout: 120_000 },
  );
  assert.equal(await h.page.textContent("#gpu-error"), "");
  // The picture and readouts are drawn before the state returns to ready.
  await h.page.waitForFunction(() => document.getElementById("gpu-status").dataset.state === "ready", null, { timeout: 60_000 });
}

const positions = () => h.page.evaluate(async () => Array.from(await window.hrlaGpu.run.positions()));

/**
 * Mean and variance of one coordinate after `k` steps on U = |x|²/2 from
 * x ~ N(m0, s0²), y = 0: the step is linear in (x, y) with Gaussian noise,
 * so its law is Gaussian with moments given by the recursion
 * m' = A m, S' = A S Aᵀ + Q, with the device's (f32-rounded) coefficients.
 */
function exactLaw(sampler, c, m0, s0, k) {
  const f = c.map(Math.fround);
  let A, Q;
  if (sampler === "ola") {
    const [drift, noise] = f;
    A = [1 - drift, 0, 0, 0];
    Q = [noise * noise, 0, 0];
  } else {
    const [cxy, e, cxg, cyg, lxy, lxx, lyy] = f;
    A = [1 - cxg, cxy, -cyg, e];
    Q = [lxy * lxy + lxx * lxx, lxy * lyy, lyy * lyy];
  }
  let [mx, my] = [m0, 0];
  let [sxx, sxy, syy] = [s0 * s0, 0, 0];
  for (let i = 0; i < k; i++) {
    [mx, my] = [A[0] * mx + A[1] * my, A[2] * mx + A[3] * my];
    const nxx = A[0] * A[0] * sxx + 2 * A[0] * A[1] * sxy + A[1] * A[1] * syy + Q[0];
    const nxy = A[0] * A[2] * sxx + (A[0] * A[3] + A[1] * A[2]) * sxy + A[1] * A[3] * syy + Q[1];
    const nyy = A[2] * A[2] * sxx + 2 * A[2] * A[3] * sxy + A[3] * A[3] * syy + Q[2];
    [sxx, sxy, syy] = [nxx, nxy, nyy];
  }
  return { mean: mx, variance: sxx };
}

function moments(xs) {
  const n = xs.length;
  const mean = xs.reduce((s, v) => s + v, 0) / n;
  const variance = xs.reduce((s, v) => s + (v - mean) ** 2, 0) / (n - 1);
  return { mean, variance };
}

for (const sampler of ["hrla", "ula", "ola"]) {
  test(`${sampler.toUpperCase()} on the device: the chains' law after 20 steps is the closed form on the bowl`, async (t) => {
    const [a, step, cx, cy, spread, k, n] = [1, 0.1, 4, -2, 0.5, 20, 100_000];
    await openPaused({ potential: "quadratic", sampler, a, h: step, cx, cy, spread, seed: 11 });
    if (!(await adapterOr(t))) return;
    await startRun(n);
    await stepRun(k, k);
    const xs = await positions();
    assert.equal(xs.length, 2 * n);
    const c = await h.page.evaluate(
      async ([s, hh, aa]) => Array.from((await import("/pkg/hrla_wasm.js")).coefficients(s, hh, aa)),
      [sampler, step, a],
    );
    for (const [i, m0] of [
      [0, cx],
      [1, cy],
    ]) {
      const law = exactLaw(sampler, c, m0, spread, k);
      const got = moments(xs.slice(i * n, (i + 1) * n));
      // Five standard errors: sqrt(v/n) for the mean, v sqrt(2/(n-1)) for
      // the variance of a Gaussian sample.
      const seMean = Math.sqrt(law.variance / n);
      const seVar = law.variance * Math.sqrt(2 / (n - 1));
      assert.ok(Math.abs(got.mean - law.mean) < 5 * seMean, `x${i + 1}: mean ${got.mean}, law ${law.mean} (se ${seMean})`);
      assert.ok(Math.abs(got.variance - law.variance) < 5 * seVar, `x${i + 1}: variance ${got.variance}, law ${law.variance} (se ${seVar})`);
    }
  });
}

test("the device's starts are the kernel's f32 Gaussian draws from chain_seed's xoshiro128++, bit for bit", async (t) => {
  const [seed, cx, cy, spread, n] = [9, 2.5, -1.25, 0.7, 4096];
  await openPaused({ potential: "rastrigin", sampler: "hrla", seed, cx, cy, spread });
  if (!(await adapterOr(t))) return;
  await startRun(n);
  const device = await positions();
  const kernel = await h.page.evaluate(
    async (args) => Array.from((await import("/pkg/hrla_wasm.js")).gpu_kernel_starts(...args)),
    [BigInt(seed), 0, n, cx, cy, spread],
  );
  const first = device.findIndex((v, i) => !Object.is(v, kernel[i]));
  assert.equal(first, -1, `first difference at ${first}: device ${device[first]}, kernel ${kernel[first]}`);
});

test("the same seed gives the same chains, bit for bit; another seed others", async (t) => {
  await openPaused({ potential: "rastrigin", sampler: "hrla", seed: 3 });
  if (!(await adapterOr(t))) return;
  const run = async () => {
    await startRun(4096);
    await stepRun(30, 30);
    return positions();
  };
  const first = await run();
  const again = await run();
  assert.deepEqual(again, first);
  await setControl("seed", 4);
  const other = await run();
  const same = other.filter((v, i) => v === first[i]).length;
  assert.ok(same < first.length / 100, `${same} of ${first.length} coordinates equal under another seed`);
});

test("the density is the chains binned over the view, drawn on a log scale", async (t) => {
  await openPaused({ potential: "quadratic", sampler: "hrla", a: 1, h: 0.05, cx: 3, cy: 3, spread: 0.5, seed: 5 });
  if (!(await adapterOr(t))) return;
  const n = 50_000;
  await startRun(n);
  await stepRun(200, 200);
  const xs = await positions();
  const got = await h.page.evaluate(() => {
    const d = window.hrlaGpu.density;
    const canvas = document.getElementById("gpu-density");
    const px = canvas.getContext("2d").getImageData(0, 0, d.w, d.h).data;
    const box = window.hrlaDemo.state.frame;
    return { counts: Array.from(d.counts), w: d.w, h: d.h, outside: d.outside, diverged: d.diverged, px: Array.from(px), box: [box.x0, box.x1, box.y0, box.y1] };
  });
  // The bins recomputed here in f32, as the device computes them.
  const f = Math.fround;
  const [x0, x1, y0, y1] = got.box;
  const sx = f(got.w / (x1 - x0));
  const sy = f(got.h / (y1 - y0));
  const expected = new Array(got.w * got.h).fill(0);
  let outside = 0;
  for (let c = 0; c < n; c++) {
    const i = Math.floor(f(f(xs[c] - f(x0)) * sx));
    const j = Math.floor(f(f(f(y1) - xs[n + c]) * sy));
    if (i >= 0 && j >= 0 && i < got.w && j < got.h) expected[j * got.w + i]++;
    else outside++;
  }
  assert.equal(got.diverged, 0);
  assert.equal(got.outside, outside);
  assert.deepEqual(got.counts, expected);
  assert.equal(got.counts.reduce((s, v) => s + v, 0) + got.outside, n);
  // After a time of 10 the chains are about N(0, I): the densest cell
  // within 1 of the origin, drawn in the colour map's top colour
  // (viridis yellow); an empty cell black.
  const yellow = [...VIRIDIS.slice(765, 768), 255];
  const top = got.counts.indexOf(Math.max(...got.counts));
  const [ti, tj] = [top % got.w, Math.floor(top / got.w)];
  const centre = [x0 + ((ti + 0.5) * (x1 - x0)) / got.w, y1 - ((tj + 0.5) * (y1 - y0)) / got.h];
  assert.ok(Math.hypot(...centre) < 1, `densest cell at ${centre}`);
  assert.deepEqual(got.px.slice(4 * top, 4 * top + 4), yellow);
  const empty = got.counts.indexOf(0);
  assert.deepEqual(got.px.slice(4 * empty, 4 * empty + 4), [0, 0, 0, 255]);
  await h.page.locator("#gpu").screenshot({ path: join(SHOTS, "webgpu-density.png") });
});

test("refused settings: N beyond 10^6, a step the kernel refuses; no run is left", async (t) => {
  await openPaused({ potential: "rastrigin" });
  if (!(await adapterOr(t))) return;
  await h.page.fill("#gpu-chains", "1000001");
  await h.page.click("#gpu-start");
  await h.page.waitForFunction(() => document.getElementById("gpu-status").dataset.state === "error");
  assert.equal(await h.page.textContent("#err-gpu-chains"), "N must be a whole number from 1 to 1000000");
  assert.equal(await h.page.evaluate(() => window.hrlaGpu.run), null);
  assert.equal(await h.page.isDisabled("#gpu-forward"), true);
  await setControl("h", -1);
  await h.page.fill("#gpu-chains", "100");
  await h.page.click("#gpu-start");
  await h.page.waitForFunction(() => document.getElementById("gpu-status").dataset.state === "error" && document.getElementById("gpu-error").textContent !== "");
  assert.match(await h.page.textContent("#gpu-error"), /h/);
  assert.equal(await h.page.evaluate(() => window.hrlaGpu.run), null);
});

test("a run whose every chain diverges says so and stops; it never reads as a result", async (t) => {
  // OLA on the bowl at h = 2.5: x' = -1.5 x + noise, past f32's range
  // within 300 steps from |x| about 3.
  await openPaused({ potential: "quadratic", sampler: "ola", a: 1, h: 2.5, cx: 3, cy: 3, spread: 0.5, seed: 2 });
  if (!(await adapterOr(t))) return;
  await startRun(1000);
  await h.page.fill("#gpu-steps", "300");
  await h.page.click("#gpu-forward");
  await h.page.waitForFunction(() => document.getElementById("gpu-status").dataset.state === "error", null, { timeout: 60_000 });
  assert.equal(await h.page.textContent("#gpu-error"), "Every chain diverged: the step h is too long for this landscape.");
  assert.equal(await h.page.getAttribute("#gpu-diverged", "data-value"), "1000");
  assert.equal(await h.page.getAttribute("#gpu-lowest", "data-value"), "NaN");
  assert.equal(await h.page.getAttribute("#gpu-play", "aria-pressed"), "false");
});

test("no console errors, failed requests or requests leaving 127.0.0.1", noProblems);
