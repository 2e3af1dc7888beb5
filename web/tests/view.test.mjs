// Sharing and moving the view: "Copy link" puts the address that replays
// the run on the clipboard (or, without a clipboard, shows it selected);
// the landscape zooms (buttons, wheel about the cursor) and pans (drag),
// the view is kept in the address, and none of it touches the run.
import assert from "node:assert/strict";
import { test } from "node:test";
import { advance, h, load, noProblems, openPaused, readout, setUp } from "./harness.mjs";

setUp();

/** The view shown, and the frame's box. */
const view = () => h.page.evaluate(() => window.hrlaDemo.state.view);

test("Copy link copies the address that replays the run", async () => {
  await h.browser.context.grantPermissions(["clipboard-read", "clipboard-write"], { origin: h.base.replace(/\/$/, "") });
  await openPaused({ potential: "ackley", seed: 42, spf: 100 });
  await advance(100);
  await h.page.click("#copy-link");
  await h.page.waitForFunction(() => /Link copied/.test(document.getElementById("copy-note").textContent));
  const copied = await h.page.evaluate(() => navigator.clipboard.readText());
  assert.equal(copied, h.page.url());
  const q = new URL(copied).searchParams;
  assert.equal(q.get("potential"), "ackley");
  assert.equal(q.get("seed"), "42");
  // Without the clipboard, the link is shown selected, to copy by hand.
  await h.browser.context.clearPermissions();
  await h.page.evaluate(() => {
    Object.defineProperty(navigator, "clipboard", { value: { writeText: () => Promise.reject(new Error("denied")) }, configurable: true });
  });
  await h.page.click("#copy-link");
  await h.page.waitForSelector("#link-field:not([hidden])");
  assert.equal(await h.page.inputValue("#link-field"), h.page.url());
  assert.equal(await h.page.evaluate(() => document.activeElement.id), "link-field");
});

test("the zoom buttons zoom about the centre, the view is in the address, and home restores it; the run is untouched", async () => {
  await openPaused({ spf: 100 });
  await advance(100);
  assert.deepEqual(await view(), { cx: 0, cy: 0, half: 5 });
  await h.page.click("#zoom-in");
  await h.page.click("#zoom-in");
  const zoomed = await view();
  assert.deepEqual(zoomed, { cx: 0, cy: 0, half: 5 / 1.5 / 1.5 });
  // The picture follows: the frame, and the background computed over the new box.
  const f = await h.page.evaluate(() => {
    const { frame, grid } = window.hrlaDemo.state;
    return { x0: frame.x0, x1: frame.x1, w: grid.w, u: grid.u[Math.floor(grid.h / 2) * grid.w + Math.floor(grid.w / 2)] };
  });
  assert.equal(f.x0, -zoomed.half);
  assert.equal(f.x1, zoomed.half);
  assert.ok(f.u < 0.05, `U at the centre pixel of the zoomed view: ${f.u}`);
  assert.equal(await readout("out-iteration"), 100);
  assert.equal(new URL(h.page.url()).searchParams.get("view"), `0,0,${+(5 / 1.5 / 1.5).toPrecision(12)}`);
  // The address replays the view.
  await load(h.page.url());
  assert.deepEqual(await view(), { cx: 0, cy: 0, half: +(5 / 1.5 / 1.5).toPrecision(12) });
  await h.page.click("#zoom-home");
  assert.deepEqual(await view(), { cx: 0, cy: 0, half: 5 });
  assert.equal(new URL(h.page.url()).searchParams.get("view"), null);
});

test("the wheel zooms about the cursor: the point under it stays", async () => {
  await openPaused();
  const box = await h.page.locator("#particles").boundingBox();
  // Whole pixels: the events carry whole client coordinates.
  const at = { x: Math.round(box.x + box.width * 0.7), y: Math.round(box.y + box.height * 0.3) };
  const under = () =>
    h.page.evaluate(([x, y]) => {
      const { frame } = window.hrlaDemo.state;
      const r = document.getElementById("particles").getBoundingClientRect();
      return [frame.x0 + ((x - r.left - frame.left) / frame.width) * (frame.x1 - frame.x0), frame.y1 - ((y - r.top - frame.top) / frame.height) * (frame.y1 - frame.y0)];
    }, [at.x, at.y]);
  const before = await under();
  await h.page.mouse.move(at.x, at.y);
  await h.page.mouse.wheel(0, -300);
  await h.page.waitForFunction(() => window.hrlaDemo.state.view.half < 5);
  const after = await under();
  const half = (await view()).half;
  assert.ok(half < 5, `half ${half}`);
  for (let i = 0; i < 2; i++) assert.ok(Math.abs(after[i] - before[i]) < 1e-9, `the point under the cursor moved from ${before} to ${after}`);
});

test("a drag pans the view by the distance dragged; a click without a drag still picks a chain", async () => {
  await openPaused({ chains: 16 });
  const box = await h.page.locator("#particles").boundingBox();
  const perPixel = await h.page.evaluate(() => 10 / window.hrlaDemo.state.frame.width);
  await h.page.mouse.move(box.x + 200, box.y + 200);
  await h.page.mouse.down();
  await h.page.mouse.move(box.x + 260, box.y + 170, { steps: 4 });
  await h.page.mouse.up();
  const v = await view();
  assert.ok(Math.abs(v.cx - -60 * perPixel) < 1e-9, `cx ${v.cx}`);
  assert.ok(Math.abs(v.cy - -30 * perPixel) < 1e-9, `cy ${v.cy}`);
  assert.equal(await readout("out-iteration"), 0);
  assert.equal(await h.page.evaluate(() => window.hrlaDemo.state.anatomyChain), 0);
  const target = await h.page.evaluate(() => {
    const { state } = window.hrlaDemo;
    const r = state.runs[0];
    return { px: state.frame.px(r.x[2 * 9]), py: state.frame.py(r.x[2 * 9 + 1]) };
  });
  await h.page.locator("#particles").click({ position: { x: target.px, y: target.py } });
  const picked = await h.page.evaluate(() => window.hrlaDemo.state.anatomyChain);
  // The nearest chain to the click: chain 9, or one drawn on top of it.
  const d = await h.page.evaluate((c) => {
    const { state } = window.hrlaDemo;
    const r = state.runs[0];
    return Math.hypot(r.x[2 * c] - r.x[18], r.x[2 * c + 1] - r.x[19]);
  }, picked);
  assert.ok(d < 0.05, `picked chain ${picked}, ${d} away from chain 9`);
});

test("no console error, failed request or request leaving 127.0.0.1", () => noProblems());
