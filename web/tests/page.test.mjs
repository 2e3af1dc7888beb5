// The demo page in a real browser: Debian's Chromium, the page served on
// loopback by scripts/static-server.mjs from web/ (with web/pkg built).
//
// Nothing here depends on wall-clock speed or on how many animation frames
// run between two reads: every test that reads the run opens the page paused
// (?play=0) and moves the run only with the step control (button or "."),
// which advances it by exactly `steps per frame` iterations, so every count is
// exact. The one test of playing waits for a condition that only progress can
// make true, and pauses before comparing counts. Time-outs only catch a hung
// page.
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

/** Loads an address and waits until the page has started its run. */
async function load(url) {
  await page.goto(url);
  await page.waitForSelector("body[data-ready=true]", { timeout: 30_000 });
}

/**
 * Opens the page paused on `settings` (URL parameters; the rest at their
 * defaults), at iteration 0: until a test steps or plays it, no animation
 * frame moves the run.
 */
async function openPaused(settings = {}) {
  await load(`${base}?${new URLSearchParams({ ...settings, play: "0" })}`);
  assert.equal(await page.getAttribute("#play", "aria-pressed"), "false");
  assert.equal(await readout("out-iteration"), 0);
}

async function pause() {
  if ((await page.getAttribute("#play", "aria-pressed")) === "true") await page.click("#play");
  assert.equal(await page.getAttribute("#play", "aria-pressed"), "false");
}

/** Resolves after `n` more animation frames of the page. */
async function frames(n) {
  await page.evaluate(async (n) => {
    for (let i = 0; i < n; i++) await new Promise((next) => requestAnimationFrame(next));
  }, n);
}

test("the page loads and draws: a landscape and the chains", async () => {
  await openPaused();
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

test("opened without settings, the page plays whole frames of steps until paused", async () => {
  await load(base);
  assert.equal(await page.getAttribute("#play", "aria-pressed"), "true");
  // Waits for progress, however slow the frames are: three frames of 100 steps.
  await page.waitForFunction(() => Number(document.getElementById("out-iteration").dataset.value) >= 300, null, {
    timeout: 60_000,
  });
  await pause();
  const paused = await readout("out-iteration");
  assert.ok(paused >= 300, `iteration ${paused}`);
  assert.equal(paused % 100, 0, `iteration ${paused} is not a whole number of frames of 100 steps`);
  // Paused, frames still run (and draw) but the run stays where it is.
  await frames(5);
  assert.equal(await readout("out-iteration"), paused);
});

// 10 chains started at (3, 3) with spread 1: every start's best U is above 1
// for seeds 0..1999 (the lowest, 1.14), 15.0 for seed 1. With seed 1 (one
// stream per chain, hrla::chain_seed) the best falls below 1 within 500 steps
// and to 2e-3 by 1000; the 3000 stepped here leave a margin (the slowest of
// seeds 0..1999 took 1450, the median 300).
const DESCENT = { sampler: "hrla", a: 4, h: 0.01, chains: 10, cx: 3, cy: 3, spread: 1, seed: 1, spf: 100 };

test("the iteration counter advances and HRLA's running best falls below 1", async () => {
  await openPaused(DESCENT);
  let best = await readout("out-best");
  assert.ok(best > 1, `the start's best U = ${best} is already below 1`);
  assert.equal(await readout("out-best-at"), 0);
  // 30 frames of 100 steps, one per press: 15 with the Step button, 15 with
  // the "." key (with nothing focused, as the key is ignored in controls).
  for (let i = 1; i <= 30; i++) {
    if (i <= 15) {
      await page.click("#step");
    } else {
      await page.evaluate(() => document.activeElement?.blur());
      await page.keyboard.press(".");
    }
    assert.equal(await readout("out-iteration"), 100 * i);
    const now = await readout("out-best");
    assert.ok(now <= best, `the running best rose from ${best} to ${now} at step ${i}`);
    best = now;
  }
  assert.equal(await page.getAttribute("#play", "aria-pressed"), "false");
  assert.ok(best < 1, `best U = ${best} after 3000 iterations`);
  const at = await readout("out-best-at");
  assert.ok(at > 0 && at <= 3000, `best found at iteration ${at}`);
  await page.screenshot({ path: join(OUT, "page.png") });
});

test("changing a control restarts the run from the seed", async () => {
  await openPaused();
  await page.click("#step");
  assert.equal(await readout("out-iteration"), 100);
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
  await openPaused();
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

// h = 5 is far too long a step for Rastrigin at a = 4: the drift alone
// (not the noise) makes every chain's position overflow, at iteration 142
// to 144 for each of seeds 0..499, so one press of 1000 steps ends the run.
test("a run whose chains all diverge shows the kernel's message, and the page recovers", async () => {
  const message = "all 10 chains diverged (non-finite position, potential or gradient): try a smaller step h";
  await openPaused({ h: 5, chains: 10, spf: 1000 });
  assert.equal(await readout("out-diverged"), 0);
  await page.click("#step");
  assert.equal(await page.textContent("#error"), message);
  assert.equal(await page.getAttribute("#h", "aria-invalid"), "true");
  assert.equal(await page.getAttribute("#play", "aria-pressed"), "false");
  assert.equal(await readout("out-diverged"), 10);
  const stopped = await readout("out-iteration");
  assert.ok(stopped > 0 && stopped < 1000, `stopped at iteration ${stopped}`);
  assert.ok(Number.isFinite(await readout("out-best")), "the running best of the live iterates stays shown");
  // Stepping again: the same message, and the run stays where it stopped.
  await page.click("#step");
  assert.equal(await page.textContent("#error"), message);
  assert.equal(await readout("out-iteration"), stopped);
  // Playing: the first frame meets the error and pauses again.
  await page.click("#play");
  await page.waitForFunction(() => document.getElementById("play").getAttribute("aria-pressed") === "false", null, {
    timeout: 30_000,
  });
  assert.equal(await page.textContent("#error"), message);
  assert.equal(await readout("out-iteration"), stopped);
  // A good h restarts the run from the seed, without the error.
  await setControl("h", 0.01);
  assert.equal(await page.textContent("#error"), "");
  assert.equal(await page.getAttribute("#h", "aria-invalid"), null);
  assert.equal(await readout("out-iteration"), 0);
  await page.click("#step");
  assert.equal(await readout("out-iteration"), 1000);
  assert.equal(await readout("out-diverged"), 0);
  assert.equal(await page.textContent("#error"), "");
});

test("the same seed gives the same best value after the same number of steps", async () => {
  await openPaused({ sampler: "ula" });
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
  const url = new URL(page.url());
  assert.equal(url.searchParams.get("seed"), "12345678901234567890");
  url.searchParams.set("play", "0");
  await load(url.href);
  assert.equal(await readout("out-iteration"), 0);
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
  // Layout is synchronous; the canvases follow through ResizeObserver:
  // wait for that (not for some time) so that the screenshot shows them.
  await page.waitForFunction(() => {
    const dpr = window.devicePixelRatio || 1;
    const wrap = document.getElementById("canvas-wrap");
    const fits = (id, w) => document.getElementById(id).width === Math.round(w * dpr);
    return (
      window.innerWidth === 390 &&
      fits("landscape", Math.floor(wrap.clientWidth)) &&
      ["plot-best", "plot-prob"].every((id) => fits(id, document.getElementById(id).clientWidth))
    );
  });
  const overflow = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  assert.ok(overflow <= 0, `page is ${overflow}px wider than the screen`);
  await page.screenshot({ path: join(OUT, "page-phone.png"), fullPage: true });
  await page.setViewportSize({ width: 1280, height: 800 });
});

test("no console error, failed request or request leaving 127.0.0.1", () => {
  assert.deepEqual(problems, []);
});
