// The demo page in a real browser: Debian's Chromium, the page served on
// loopback by scripts/static-server.mjs from web/ (with web/pkg built).
// Nothing here depends on wall-clock speed: waits are bounded by the
// iteration count, and the time-outs only catch a hung page.
import assert from "node:assert/strict";
import { mkdirSync } from "node:fs";
import { join } from "node:path";
import { after, before, test } from "node:test";
import { startServer } from "../../scripts/static-server.mjs";
import { launch, OUT, ROOT } from "./browser.mjs";

let server;
let base;
let browser;
let page;
const problems = [];

before(async () => {
  mkdirSync(OUT, { recursive: true });
  server = await startServer(join(ROOT, "web"), 0);
  base = `http://127.0.0.1:${server.address().port}/`;
  browser = await launch();
  page = browser.context.pages()[0] ?? (await browser.context.newPage());
  page.on("console", (m) => {
    if (m.type() === "error" || m.type() === "warning") problems.push(`console ${m.type()}: ${m.text()}`);
  });
  page.on("pageerror", (e) => problems.push(`page error: ${e.message}`));
  page.on("request", (r) => {
    if (new URL(r.url()).hostname !== "127.0.0.1") problems.push(`request leaving 127.0.0.1: ${r.url()}`);
  });
  page.on("response", (r) => {
    if (r.status() >= 400) problems.push(`HTTP ${r.status()} for ${r.url()}`);
  });
  await page.goto(base);
  await page.waitForSelector("body[data-ready=true]", { timeout: 30_000 });
});

after(async () => {
  await browser?.close();
  server?.close();
});

/** A readout's exact value (its data-value attribute). */
async function readout(id) {
  return Number(await page.getAttribute(`#${id}`, "data-value"));
}

/** Types into a control and commits it, as a person would (Tab away). */
async function setControl(id, value) {
  await page.fill(`#${id}`, String(value));
  await page.press(`#${id}`, "Tab");
}

async function pause() {
  if ((await page.getAttribute("#play", "aria-pressed")) === "true") await page.click("#play");
}

test("the page loads and draws: a landscape and the chains", async () => {
  const colours = await page.evaluate(() => {
    const c = document.getElementById("landscape");
    const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
    const seen = new Set();
    for (let i = 0; i < d.length; i += 4 * 97) seen.add((d[i] << 16) | (d[i + 1] << 8) | d[i + 2]);
    return seen.size;
  });
  assert.ok(colours > 100, `landscape has only ${colours} colours`);
  const drawn = await page.evaluate(() => {
    const c = document.getElementById("particles");
    const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
    let n = 0;
    for (let i = 3; i < d.length; i += 4) if (d[i] > 0) n++;
    return n;
  });
  assert.ok(drawn > 500, `only ${drawn} pixels of chains drawn`);
});

test("the iteration counter advances and HRLA's running best falls below 1", { timeout: 120_000 }, async () => {
  const start = await readout("out-iteration");
  // Bounded by frames, not time: 200 frames of 100 steps.
  await page.waitForFunction(
    () => {
      const it = Number(document.getElementById("out-iteration").dataset.value);
      const best = Number(document.getElementById("out-best").dataset.value);
      return best < 1 || it >= 20_000;
    },
    null,
    { timeout: 110_000 },
  );
  const iteration = await readout("out-iteration");
  assert.ok(iteration > start, `iteration stayed at ${start}`);
  const best = await readout("out-best");
  assert.ok(best < 1, `best U = ${best} after ${iteration} iterations`);
  await page.screenshot({ path: join(OUT, "page.png") });
});

test("changing a control restarts the run from the seed", async () => {
  await pause();
  assert.ok((await readout("out-iteration")) > 0);
  await page.selectOption("#sampler", "ula");
  assert.equal(await readout("out-iteration"), 0);
  assert.match(page.url(), /sampler=ula/);
  await page.click("#step");
  assert.equal(await readout("out-iteration"), 100);
  await setControl("h", 0.02);
  assert.equal(await readout("out-iteration"), 0);
  assert.match(page.url(), /h=0\.02/);
});

test("an invalid h shows the kernel's message and the page recovers", async () => {
  await pause();
  await setControl("h", -1);
  assert.equal(await page.textContent("#error"), "`h` must be finite and > 0, got -1");
  assert.equal(await page.getAttribute("#h", "aria-invalid"), "true");
  assert.equal(await page.textContent("#out-best"), "–");
  await page.click("#step"); // nothing to step: must not throw
  await setControl("h", "");
  assert.equal(await page.textContent("#error"), "`h` must be finite and > 0, got NaN");
  await setControl("h", 0.01);
  assert.equal(await page.textContent("#error"), "");
  assert.equal(await page.getAttribute("#h", "aria-invalid"), null);
  await page.click("#step");
  assert.equal(await readout("out-iteration"), 100);
});

test("the same seed gives the same best value after the same number of steps", async () => {
  await pause();
  await page.selectOption("#sampler", "hrla");
  await setControl("seed", "12345678901234567890");
  const runOnce = async () => {
    for (let i = 0; i < 15; i++) await page.click("#step");
    return [await readout("out-iteration"), await page.getAttribute("#out-best", "data-value")];
  };
  const first = await runOnce();
  await page.click("#reset");
  assert.equal(await readout("out-iteration"), 0);
  const second = await runOnce();
  assert.equal(first[0], 1500);
  assert.deepEqual(second, first);
  // And a reload from the address (which holds every setting) replays it.
  await page.goto(page.url());
  await page.waitForSelector("body[data-ready=true]");
  await pause();
  await page.click("#reset");
  assert.deepEqual(await runOnce(), first);
});

test("the random button draws a new seed and shows it", async () => {
  await page.click("#random-seed");
  const seed = await page.inputValue("#seed");
  assert.match(seed, /^[0-9]+$/);
  assert.notEqual(seed, "12345678901234567890");
  assert.match(page.url(), new RegExp(`seed=${seed}`));
  assert.equal(await page.textContent("#error"), "");
});

test("controls are labelled and reachable by keyboard", async () => {
  const unlabelled = await page.evaluate(() =>
    [...document.querySelectorAll("input, select")]
      .filter((el) => el.labels.length === 0 && !el.getAttribute("aria-label"))
      .map((el) => el.id),
  );
  assert.deepEqual(unlabelled, []);
  await page.focus("#play");
  await page.keyboard.press("Tab");
  assert.equal(await page.evaluate(() => document.activeElement.id), "step");
});

test("a phone-width screen shows the page without horizontal scrolling", async () => {
  await page.setViewportSize({ width: 390, height: 844 });
  await page.waitForTimeout(100);
  const overflow = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  assert.ok(overflow <= 0, `page is ${overflow}px wider than the screen`);
  await page.screenshot({ path: join(OUT, "page-phone.png"), fullPage: true });
  await page.setViewportSize({ width: 1280, height: 800 });
});

test("no console error, failed request or request leaving 127.0.0.1", () => {
  assert.deepEqual(problems, []);
});
