// Measures the demo page's speed in headless Chromium: frames per second and
// chain-steps per second, as the page's own meters show them, for 256 chains
// at several steps per frame. A measurement for the README, not a test.
//
//   node web/tests/measure.mjs        (after scripts/serve.sh or test-web.sh built web/pkg)
import { join } from "node:path";
import { startServer } from "../../scripts/static-server.mjs";
import { launch, ROOT } from "./browser.mjs";

const server = await startServer(join(ROOT, "web"), 0);
const base = `http://127.0.0.1:${server.address().port}/`;
const browser = await launch();
const page = browser.context.pages()[0] ?? (await browser.context.newPage());
const read = async (id) => Number(await page.getAttribute(`#${id}`, "data-value"));

console.log("sampler  chains  steps/frame  frames/s  chain-steps/s");
for (const sampler of ["hrla", "ola"]) {
  for (const spf of [100, 200, 400]) {
    await page.goto(`${base}?sampler=${sampler}&chains=256&spf=${spf}`);
    await page.waitForSelector("body[data-ready=true]");
    // Warm up, then average the page's one-second meters over 5 seconds.
    await page.waitForTimeout(2000);
    let fps = 0;
    let rate = 0;
    for (let i = 0; i < 5; i++) {
      await page.waitForTimeout(1000);
      fps += (await read("out-fps")) / 5;
      rate += (await read("out-chain-rate")) / 5;
    }
    console.log(
      `${sampler.padEnd(8)} ${"256".padStart(6)}  ${String(spf).padStart(11)}  ${fps.toFixed(1).padStart(8)}  ${(rate / 1e6).toFixed(2).padStart(11)}M`,
    );
  }
}
// The wasm kernel alone, without drawing: one long advance() per sampler.
for (const sampler of ["hrla", "ula", "ola"]) {
  const rate = await page.evaluate(async (sampler) => {
    const m = await import("/pkg/hrla_wasm.js");
    const settings = { sampler, a: 4, h: 0.01, chains: 256, centre: [3, 3], spread: Math.sqrt(10), seed: 1 };
    const opt = new m.Optimizer(settings);
    const t0 = performance.now();
    opt.advance(20_000);
    const dt = (performance.now() - t0) / 1000;
    opt.free();
    return (256 * 20_000) / dt;
  }, sampler);
  console.log(`${sampler} kernel alone, 256 chains x 20000 steps: ${(rate / 1e6).toFixed(2)}M chain-steps/s`);
}
await browser.close();
server.close();
