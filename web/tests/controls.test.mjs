// The picture's controls beyond the mouse: the arrow keys pan it and + and
// − zoom it when it has the focus; on a touch screen one finger drags it
// sideways (an upward swipe scrolls the page) and two pinch it; and the
// colour bar says what its colours mean, with a title and labelled ticks
// in both backgrounds.
import assert from "node:assert/strict";
import { test } from "node:test";
import { h, noProblems, openPaused, readout, setUp } from "./harness.mjs";

setUp();

const view = () => h.page.evaluate(() => window.hrlaDemo.state.view);

test("the colour bar has a title and labelled ticks, for U and for the density", async () => {
  await openPaused();
  const bar = async () => ({
    title: await h.page.getAttribute("#colorbar", "data-title"),
    ticks: (await h.page.getAttribute("#colorbar", "data-ticks")).split(", "),
  });
  const u = await bar();
  assert.equal(u.title, "U − U* (log scale)");
  assert.ok(u.ticks.length >= 4, `U ticks drawn: ${u.ticks}`);
  await h.page.check("#show-density");
  const d = await bar();
  assert.match(d.title, /^density exp\(−aU\) \/ max \(log scale\), a = 4$/);
  // Every decade from the peak down is labelled, not only the peak's 1.
  assert.deepEqual(d.ticks, ["1", "1e−1", "1e−2", "1e−3", "1e−4", "1e−5", "1e−6"]);
});

test("with the picture focused, the arrow keys pan and + and − zoom; the run is untouched", async () => {
  await openPaused();
  await h.page.focus("#particles");
  await h.page.keyboard.press("ArrowRight");
  assert.deepEqual(await view(), { cx: 1, cy: 0, half: 5 });
  await h.page.keyboard.press("ArrowUp");
  assert.deepEqual(await view(), { cx: 1, cy: 1, half: 5 });
  await h.page.keyboard.press("ArrowLeft");
  await h.page.keyboard.press("ArrowDown");
  assert.deepEqual(await view(), { cx: 0, cy: 0, half: 5 });
  await h.page.keyboard.press("+");
  assert.deepEqual(await view(), { cx: 0, cy: 0, half: 5 / 1.5 });
  await h.page.keyboard.press("-");
  assert.ok(Math.abs((await view()).half - 5) < 1e-12);
  await h.page.keyboard.press("ArrowRight");
  await h.page.keyboard.press("0");
  assert.deepEqual(await view(), { cx: 0, cy: 0, half: 5 });
  assert.equal(new URL(h.page.url()).searchParams.get("view"), null);
  assert.equal(await readout("out-iteration"), 0);
});

/** A touch pointer event on the picture at client (x, y). */
function touch(type, id, x, y) {
  return h.page.dispatchEvent("#particles", type, { pointerId: id, pointerType: "touch", isPrimary: id === 1, clientX: x, clientY: y, bubbles: true });
}

test("on a touch screen one finger drags the picture and two pinch it", async () => {
  await openPaused();
  // The browser keeps the upward and downward swipes (it scrolls the page
  // with them) and leaves the others on the picture to the page.
  assert.equal(await h.page.$eval("#particles", (c) => getComputedStyle(c).touchAction), "pan-y");
  const box = await h.page.locator("#particles").boundingBox();
  const perPixel = await h.page.evaluate(() => 10 / window.hrlaDemo.state.frame.width);
  const [x, y] = [box.x + 150, box.y + 150];
  await touch("pointerdown", 1, x, y);
  await touch("pointermove", 1, x + 40, y + 20);
  await touch("pointerup", 1, x + 40, y + 20);
  let v = await view();
  assert.ok(Math.abs(v.cx - -40 * perPixel) < 1e-9 && Math.abs(v.cy - 20 * perPixel) < 1e-9, `after a drag: ${JSON.stringify(v)}`);
  // Two fingers moving apart to twice their distance: twice the zoom, about their midpoint.
  await h.page.click("#zoom-home");
  const mid = [box.x + box.width / 2, box.y + box.height / 2];
  await touch("pointerdown", 1, mid[0] - 50, mid[1]);
  await touch("pointerdown", 2, mid[0] + 50, mid[1]);
  await touch("pointermove", 1, mid[0] - 100, mid[1]);
  await touch("pointermove", 2, mid[0] + 100, mid[1]);
  await touch("pointerup", 1, mid[0] - 100, mid[1]);
  await touch("pointerup", 2, mid[0] + 100, mid[1]);
  v = await view();
  assert.ok(Math.abs(v.half - 2.5) < 1e-9, `after a pinch: ${JSON.stringify(v)}`);
  // A pinch picks no chain, and nothing stepped.
  assert.equal(await readout("out-iteration"), 0);
});

test("a real finger's upward swipe on the picture scrolls the page and leaves the view; a sideways one pans it", async () => {
  await openPaused();
  // Touches through the browser's own input pipeline (not synthetic
  // pointer events), so its gesture handling decides as on a phone.
  const cdp = await h.browser.context.newCDPSession(h.page);
  await cdp.send("Emulation.setTouchEmulationEnabled", { enabled: true, maxTouchPoints: 5 });
  const swipe = async ([x0, y0], [x1, y1]) => {
    await cdp.send("Input.dispatchTouchEvent", { type: "touchStart", touchPoints: [{ x: x0, y: y0 }] });
    for (let i = 1; i <= 10; i++) {
      const at = { x: x0 + ((x1 - x0) * i) / 10, y: y0 + ((y1 - y0) * i) / 10 };
      await cdp.send("Input.dispatchTouchEvent", { type: "touchMove", touchPoints: [at] });
    }
    await cdp.send("Input.dispatchTouchEvent", { type: "touchEnd", touchPoints: [] });
  };
  const centre = async () => {
    const box = await h.page.locator("#particles").boundingBox();
    return [box.x + box.width / 2, box.y + box.height / 2];
  };
  try {
    await h.page.locator("#particles").scrollIntoViewIfNeeded();
    const home = await view();
    const top = await h.page.evaluate(() => scrollY);
    // Sideways first, while the page is still: the picture pans, the page stays.
    const [x, y] = await centre();
    await swipe([x + 80, y], [x - 80, y]);
    // The finger lifted (no gesture left) and the view moved: the pan is whole.
    await h.page.waitForFunction((cx) => {
      const { state } = window.hrlaDemo;
      return state.drag === null && state.view.cx > cx;
    }, home.cx);
    assert.equal(await h.page.evaluate(() => scrollY), top);
    const panned = await view();
    assert.equal(panned.cy, home.cy);
    // Upward: the page scrolls (and may glide on after the finger lifts,
    // so no scroll position is compared after this), and the few pixels
    // the picture moved before the browser took the swipe are undone.
    const [x2, y2] = await centre();
    await swipe([x2, y2 + 100], [x2, y2 - 100]);
    await h.page.waitForFunction(
      ([top, was]) => {
        const v = window.hrlaDemo.state.view;
        return scrollY > top && v.cx === was.cx && v.cy === was.cy && v.half === was.half;
      },
      [top, panned],
    );
    assert.equal(await readout("out-iteration"), 0);
  } finally {
    await cdp.send("Emulation.setTouchEmulationEnabled", { enabled: false });
    await cdp.detach();
  }
});

test("no console error, failed request or request leaving 127.0.0.1", () => noProblems());
