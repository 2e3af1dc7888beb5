// The page without WebGPU: the WebGPU section says why it cannot run, and
// the page's own runs (on the CPU, in WebAssembly) step as ever. Forced
// here by hiding the browser's WebGPU, so that the fallback is tested on
// every machine, whatever Chromium offers there.
import assert from "node:assert/strict";
import { test } from "node:test";
import { advance, h, noProblems, openPaused, readout, setUp, watch } from "./harness.mjs";

setUp();

const settled = (page) =>
  page.waitForFunction(() => document.getElementById("gpu-status").dataset.state !== "probing", null, { timeout: 30_000 });

test("without navigator.gpu the section says so, and the CPU run steps", async () => {
  await h.page.addInitScript(() => {
    Object.defineProperty(Navigator.prototype, "gpu", { get: () => undefined, configurable: true });
  });
  await openPaused({ potential: "quadratic", spf: 50 });
  await settled(h.page);
  assert.equal(await h.page.getAttribute("#gpu-status", "data-state"), "unavailable");
  const max = await h.page.evaluate(async () => (await import("/pkg/hrla_wasm.js")).max_chains());
  assert.equal(
    await h.page.textContent("#gpu-status"),
    `No WebGPU here: this browser has no WebGPU. The chains run on the CPU, in WebAssembly, in the picture above (up to ${max} of them).`,
  );
  assert.equal(await h.page.isVisible("#gpu-panel"), false);
  assert.equal(await h.page.isVisible("#gpu-start"), false);
  await advance(50);
  assert.equal(await readout("out-iteration"), 50);
  assert.ok(Number.isFinite(await readout("out-best")));
});

test("an adapter refused (requestAdapter gives null): the section says so", async () => {
  const page = await h.browser.context.newPage();
  watch(page);
  await page.addInitScript(() => {
    if (navigator.gpu) navigator.gpu.requestAdapter = async () => null;
    else Object.defineProperty(Navigator.prototype, "gpu", { get: () => ({ requestAdapter: async () => null }), configurable: true });
  });
  await page.goto(`${h.base}?play=0`);
  await page.waitForSelector("body[data-ready=true]", { timeout: 30_000 });
  await settled(page);
  assert.equal(await page.getAttribute("#gpu-status", "data-state"), "unavailable");
  assert.match(await page.textContent("#gpu-status"), /this browser offers no WebGPU adapter/);
  await page.close();
});

test("no console errors, failed requests or requests leaving 127.0.0.1", noProblems);
