// The guided path: six links in the header, all on the first screen of a
// 1366 × 768 desktop and of a phone, each an address the page reads, and
// each opening on what its sentence says.
import assert from "node:assert/strict";
import { test } from "node:test";
import { h, load, noProblems, setUp } from "./harness.mjs";

setUp({ width: 1366, height: 768 });

const links = () =>
  h.page.$$eval("#tour a", (as) =>
    as.map((a) => {
      const r = a.getBoundingClientRect();
      return { text: a.textContent, href: a.getAttribute("href"), top: r.top, bottom: r.bottom, visible: r.width > 0 && r.height > 0 };
    }),
  );

/** Follows the guided path's link named `text` from the page as it is. */
async function follow(text) {
  await h.page.click(`#tour a:text-is("${text}")`);
  await h.page.waitForSelector("body[data-ready=true]", { timeout: 30_000 });
}

const value = (id) => h.page.evaluate((id) => Number(document.getElementById(id).dataset.value), id);
const shown = (selector) => h.page.isVisible(selector);

test("the six links are on the first screen, on a desktop and on a phone", async () => {
  for (const [width, height] of [[1366, 768], [390, 844]]) {
    await h.page.setViewportSize({ width, height });
    await load(`${h.base}?play=0`);
    await h.page.evaluate(() => window.scrollTo(0, 0));
    const all = await links();
    assert.deepEqual(
      all.map((l) => l.text),
      ["The basic picture", "Temperature", "The exact step", "Compare in 2-D", "Compare in 10-D", "A failure"],
    );
    for (const l of all) {
      assert.ok(l.visible && l.top >= 0 && l.bottom <= height, `${width}×${height}: ${l.text} at ${l.top}..${l.bottom}`);
    }
  }
  await h.page.setViewportSize({ width: 1366, height: 768 });
});

test("the basic picture: HRLA's chains on Rastrigin, running", async () => {
  await load(`${h.base}?play=0&potential=ackley&compare=1`);
  await follow("The basic picture");
  assert.equal(await h.page.inputValue("#potential"), "rastrigin");
  assert.equal(await h.page.inputValue("#sampler"), "hrla");
  assert.equal(await h.page.isChecked("#compare"), false);
  assert.equal(await h.page.getAttribute("#play", "aria-pressed"), "true");
  await h.page.waitForFunction(() => Number(document.getElementById("out-iteration").dataset.value) > 0);
});

test("temperature: annealing shown on the density, a rising from 0.1", async () => {
  await follow("Temperature");
  assert.equal(await h.page.isChecked("#schedule-linear"), true);
  assert.equal(await h.page.isChecked("#show-density"), true);
  assert.equal(await h.page.inputValue("#aLow"), "0.1");
  assert.equal(await h.page.inputValue("#aHigh"), "4");
  assert.ok(await shown("#schedule-figure"));
  await h.page.waitForFunction(() => Number(document.getElementById("out-a").dataset.value) > 0.2);
});

test("the exact step: one step taken and laid bare", async () => {
  await follow("The exact step");
  await h.page.waitForSelector("#anatomy:not([hidden])");
  assert.equal(await value("out-iteration"), 1);
  assert.equal(await h.page.getAttribute("#play", "aria-pressed"), "false");
  assert.ok((await h.page.$$("#anatomy-runs > *")).length >= 1);
});

test("compare in 2-D: the three samplers side by side", async () => {
  await follow("Compare in 2-D");
  assert.equal(await h.page.isChecked("#compare"), true);
  assert.ok(await shown("#compare-table"));
  assert.equal((await h.page.$$("#compare-table tbody tr")).length, 3);
});

test("compare in 10-D: the d-dimensional view on screen at the paper's setting, running", async () => {
  await follow("Compare in 10-D");
  await h.page.waitForSelector("#ddim[data-ready=true]");
  assert.equal(await h.page.inputValue("#ddim-d"), "10");
  const top = await h.page.evaluate(() => document.getElementById("ddim").getBoundingClientRect().top);
  assert.ok(top >= -1 && top < 100, `the section's top at ${top}`);
  await h.page.waitForFunction(() => Number(document.getElementById("ddim-iteration").dataset.value) > 0, null, { timeout: 60_000 });
});

test("a failure: h = 1.2 is refused by the run, on the field h", async () => {
  await follow("A failure");
  assert.equal(await h.page.inputValue("#h"), "1.2");
  await h.page.waitForFunction(() => /diverged|ran away/.test(document.getElementById("error").textContent), null, { timeout: 60_000 });
  assert.match(await h.page.textContent("#error"), /smaller (step )?h/);
  assert.equal(await h.page.getAttribute("#h", "aria-invalid"), "true");
});

test("no console error, failed request or request off loopback", noProblems);
