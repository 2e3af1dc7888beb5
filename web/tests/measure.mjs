// Measures the demo page's speed in headless Chromium: frames per second
// and steps per second, as the page's own meters show them, at the
// defaults, at 1024 chains (also with 100 000 steps asked per frame, which
// the frame's time budget cuts), in compare mode (also with descent beside)
// and on a typed formula; and the time between frames at 256 and 1024
// chains. A measurement for the README, not a test.
//
//   node web/tests/measure.mjs        (on the committed web/pkg/)
import { join } from "node:path";
import { startServer } from "../../scripts/static-server.mjs";
import { launch, ROOT } from "./browser.mjs";

const server = await startServer(join(ROOT, "web"), 0);
const base = `http://127.0.0.1:${server.address().port}/`;
const browser = await launch();
const page = browser.context.pages()[0] ?? (await browser.context.newPage());
const read = async (id) => Number(await page.getAttribute(`#${id}`, "data-value"));

const CASES = [
  ["defaults (HRLA, 256 chains, 2 steps/frame)", ""],
  ["256 chains, 100 steps/frame", "?spf=100"],
  ["1024 chains, 2 steps/frame", "?chains=1024"],
  ["1024 chains, 100 steps/frame", "?chains=1024&spf=100"],
  ["1024 chains, 100000 steps/frame (time budget)", "?chains=1024&spf=100000"],
  ["compare mode, 256 chains x 3, 100 steps/frame", "?compare=1&spf=100"],
  ["density shown, annealing 0.1 -> 4 over 10000", "?show=density&schedule=linear&spf=100"],
  ["compare mode and gradient descent, 256 chains x 4, 100 steps/frame", "?compare=1&descent=1&spf=100"],
  ["a typed formula (Himmelblau's), 256 chains, 100 steps/frame", "?potential=formula&spf=100"],
];
console.log("case | frames/s | steps/s | chain-steps/s");
for (const [name, query] of CASES) {
  await page.goto(base + query);
  await page.waitForSelector("body[data-ready=true]");
  // Warm up, then average the page's one-second meters over 5 seconds.
  await page.waitForTimeout(2000);
  let fps = 0;
  let rate = 0;
  for (let i = 0; i < 5; i++) {
    await page.waitForTimeout(1000);
    fps += (await read("out-fps")) / 5;
    rate += (await read("out-rate")) / 5;
  }
  const chains = await page.evaluate(() => window.hrlaDemo.state.runs.reduce((s, r) => s + r.n, 0));
  console.log(`${name} | ${fps.toFixed(1)} | ${Math.round(rate)} | ${((rate * chains) / 1e6).toFixed(2)}M`);
}
// Frame times while playing at the defaults' 2 steps per frame: the time
// between animation frames (rendering included, which the page's own
// meters do not separate), mean, median and 95th percentile over 180
// frames, with the trails' length the drawing budget allowed.
for (const chains of [256, 1024]) {
  await page.goto(`${base}?chains=${chains}`);
  await page.waitForSelector("body[data-ready=true]");
  await page.waitForTimeout(3000);
  const stamps = await page.evaluate(
    () =>
      new Promise((done) => {
        const t = [];
        const next = (ts) => {
          t.push(ts);
          if (t.length < 181) requestAnimationFrame(next);
          else done(t);
        };
        requestAnimationFrame(next);
      }),
  );
  const dt = stamps
    .slice(1)
    .map((v, i) => v - stamps[i])
    .sort((a, b) => a - b);
  const mean = dt.reduce((s, v) => s + v, 0) / dt.length;
  const drawn = await page.evaluate(() => window.hrlaDemo.state.lastDraw);
  const trails = drawn ? `, trails ${drawn.ages} segments long` : "";
  console.log(
    `${chains} chains, frame time: mean ${mean.toFixed(1)} ms, median ${dt[dt.length >> 1].toFixed(1)}, ` +
      `95th percentile ${dt[Math.floor(0.95 * dt.length)].toFixed(1)}${trails}`,
  );
}
// How long a click on Pause waits at the heaviest setting: the time from
// the click until the next frame has been drawn.
await page.goto(`${base}?chains=1024&spf=100000`);
await page.waitForSelector("body[data-ready=true]");
await page.waitForTimeout(2000);
const pauseMs = await page.evaluate(
  () =>
    new Promise((done) => {
      const t0 = performance.now();
      document.getElementById("play").click();
      requestAnimationFrame(() => done(performance.now() - t0));
    }),
);
console.log(`pause at 1024 chains, 100000 steps/frame: next frame ${pauseMs.toFixed(1)} ms after the click`);
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
  console.log(`${sampler} kernel alone, Rastrigin, 256 chains x 20000 steps: ${(rate / 1e6).toFixed(2)}M chain-steps/s`);
}
await browser.close();
server.close();
