// What every browser test file shares: the page served on loopback, one
// Chromium page, the record of everything that must never happen (a console
// error, a failed request, a request leaving 127.0.0.1), and the helpers that
// drive the page by exact step counts.
//
// Nothing here depends on wall-clock speed or on how many animation frames
// run between two reads: a test opens the page paused (?play=0) and moves the
// run only with the step controls, which advance it by known numbers of
// iterations; waits are for conditions, their time-outs only catch a hung
// page.
import assert from "node:assert/strict";
import { mkdirSync } from "node:fs";
import { join } from "node:path";
import { after, before } from "node:test";
import { startServer } from "../../scripts/static-server.mjs";
import { launch, OUT, ROOT, SHOTS } from "./browser.mjs";

export { OUT, ROOT, SHOTS };

/** The shared state of one test file: filled by `setUp`. */
export const h = { server: null, base: "", browser: null, page: null, problems: [] };

/** Registers the before/after hooks of a test file: server, browser (with more flags `args`), page, watchers. */
export function setUp(viewport, args = []) {
  before(async () => {
    mkdirSync(OUT, { recursive: true });
    mkdirSync(SHOTS, { recursive: true });
    h.server = await startServer(join(ROOT, "web"), 0);
    h.base = `http://127.0.0.1:${h.server.address().port}/`;
    h.browser = await launch(viewport, args);
    h.page = h.browser.context.pages()[0] ?? (await h.browser.context.newPage());
    watch(h.page);
  });
  after(async () => {
    await h.browser?.close();
    h.server?.close();
  });
}

/** Records on `h.problems` what a page must never do. */
export function watch(page) {
  page.on("console", (m) => {
    // Chromium's advice on getImageData comes from the tests' own pixel reads.
    if (/willReadFrequently/.test(m.text())) return;
    // Chromium's note that this machine has no WebGPU adapter (the page
    // then says so itself, and runs on the CPU).
    if (m.type() === "warning" && m.text() === "No available adapters.") return;
    if (m.type() === "error" || m.type() === "warning") h.problems.push(`console ${m.type()}: ${m.text()}`);
  });
  page.on("pageerror", (e) => h.problems.push(`page error: ${e.message}`));
  page.on("request", (r) => {
    const url = new URL(r.url());
    // data: and blob: URLs never leave the machine.
    if (url.protocol === "data:" || url.protocol === "blob:") return;
    if (url.hostname !== "127.0.0.1") h.problems.push(`request leaving 127.0.0.1: ${r.url()}`);
  });
  page.on("response", (r) => {
    if (r.status() >= 400) h.problems.push(`HTTP ${r.status()} for ${r.url()}`);
  });
}

/** A readout's exact value (its data-value attribute). */
export async function readout(id) {
  return Number(await h.page.getAttribute(`#${id}`, "data-value"));
}

/** Types into a control and commits it, as a person would (Tab away). */
export async function setControl(id, value) {
  await h.page.fill(`#${id}`, String(value));
  await h.page.press(`#${id}`, "Tab");
}

/** Loads an address and waits until the page has started its run. */
export async function load(url) {
  await h.page.goto(url);
  await h.page.waitForSelector("body[data-ready=true]", { timeout: 30_000 });
}

/**
 * Opens the page paused on `settings` (URL parameters; the rest at their
 * defaults), at iteration 0: until a test steps or plays it, no animation
 * frame moves the run.
 */
export async function openPaused(settings = {}) {
  await load(`${h.base}?${new URLSearchParams({ ...settings, play: "0" })}`);
  assert.equal(await h.page.getAttribute("#play", "aria-pressed"), "false");
}

export async function pause() {
  if ((await h.page.getAttribute("#play", "aria-pressed")) === "true") await h.page.click("#play");
  assert.equal(await h.page.getAttribute("#play", "aria-pressed"), "false");
}

/** Waits until the iteration readout shows `n`. */
export async function untilIteration(n) {
  await h.page.waitForFunction((n) => Number(document.getElementById("out-iteration").dataset.value) === n, n, {
    timeout: 60_000,
  });
}

/**
 * One frame of steps (`steps per frame` of them) with the "." key or the
 * "⏩" button, then waits until the run has done them: a frame steps within
 * a time budget, and the rest is finished on the next frames.
 */
export async function advance(expected, how = "key") {
  if (how === "key") {
    // Keys typed into a field are the field's: the shortcut needs the focus elsewhere.
    await h.page.evaluate(() => document.activeElement?.blur());
    await h.page.keyboard.press(".");
  }
  else await h.page.click("#forward");
  await untilIteration(expected);
}

/** Resolves after `n` more animation frames of the page. */
export async function frames(n) {
  await h.page.evaluate(async (n) => {
    for (let i = 0; i < n; i++) await new Promise((next) => requestAnimationFrame(next));
  }, n);
}

/** The RGB colour of the landscape canvas at the point (x1, x2) of the landscape. */
export async function colourAt(x, y) {
  return h.page.evaluate(
    ([x, y]) => {
      const { state } = window.hrlaDemo;
      const d = document
        .getElementById("landscape")
        .getContext("2d")
        .getImageData(Math.round(state.frame.px(x) * state.dpr), Math.round(state.frame.py(y) * state.dpr), 1, 1).data;
      return [d[0], d[1], d[2]];
    },
    [x, y],
  );
}

/** The RGB colour of the chains' canvas at the point (x1, x2), with its alpha. */
export async function particleAt(x, y) {
  return h.page.evaluate(
    ([x, y]) => {
      const { state } = window.hrlaDemo;
      const d = document
        .getElementById("particles")
        .getContext("2d")
        .getImageData(Math.round(state.frame.px(x) * state.dpr), Math.round(state.frame.py(y) * state.dpr), 1, 1).data;
      return [d[0], d[1], d[2], d[3]];
    },
    [x, y],
  );
}

/** Euclidean distance of two RGB colours. */
export function colourDistance(a, b) {
  return Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

/** The file's last test: nothing the page did was a problem. */
export function noProblems() {
  assert.deepEqual(h.problems, []);
}
