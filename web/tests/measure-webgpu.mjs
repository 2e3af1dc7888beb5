// Measures the page's WebGPU section in headless Chromium with
// --enable-unsafe-webgpu: chain-steps per second of HRLA on Rastrigin (the
// page's defaults) at 10^4, 10^5 and 10^6 chains, timed around the device's
// steps alone (the "+ steps" click's work, before the picture), and the
// time of a start and of one picture (binning plus read-back). On this
// project's machines the adapter is SwiftShader, a CPU implementation of
// WebGPU: its figures say nothing of a real GPU's. A measurement for the
// docs, not a test.
//
//   node web/tests/measure-webgpu.mjs     (after scripts/serve.sh or test-web.sh built web/pkg)
import { join } from "node:path";
import { startServer } from "../../scripts/static-server.mjs";
import { launch, ROOT } from "./browser.mjs";

const server = await startServer(join(ROOT, "web"), 0);
const base = `http://127.0.0.1:${server.address().port}/`;
const browser = await launch(undefined, ["--enable-unsafe-webgpu"]);
const page = browser.context.pages()[0] ?? (await browser.context.newPage());
await page.goto(`${base}?play=0`);
await page.waitForFunction(() => document.getElementById("gpu-status")?.dataset.state !== "probing" && window.hrlaGpu, null, { timeout: 30_000 });
const label = await page.evaluate(() => window.hrlaGpu.label);
if (!label) {
  console.log(`no WebGPU adapter: ${await page.textContent("#gpu-status")}`);
  process.exit(1);
}
console.log(`adapter: ${label}; ${await page.evaluate(() => navigator.userAgent)}`);
console.log("chains | steps | start ms | steps ms | chain-steps/s | picture ms");
for (const [chains, steps] of [
  [10_000, 640],
  [100_000, 128],
  [1_000_000, 20],
]) {
  const r = await page.evaluate(
    async ([chains, steps]) => {
      const g = window.hrlaGpu;
      document.getElementById("gpu-chains").value = String(chains);
      await g.start();
      const run = g.run;
      // One step first: compiled pipelines warm.
      await run.step(1);
      let t0 = performance.now();
      await run.step(steps);
      const stepMs = performance.now() - t0;
      t0 = performance.now();
      await run.density([-5, 5, -5, 5], 256, 256);
      const pictureMs = performance.now() - t0;
      return { stepMs, pictureMs };
    },
    [chains, steps],
  );
  const t0 = Date.now();
  await page.evaluate(() => window.hrlaGpu.start());
  const startMs = Date.now() - t0;
  console.log(`${chains} | ${steps} | ${startMs} | ${r.stepMs.toFixed(0)} | ${((chains * steps) / (r.stepMs / 1000)).toExponential(2)} | ${r.pictureMs.toFixed(0)}`);
}
await browser.close();
server.close();
