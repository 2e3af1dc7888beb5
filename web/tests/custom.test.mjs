// A visitor's own function: typed for U(x, y), parsed and differentiated
// exactly in the wasm, run by the kernel like a built-in landscape, a
// syntax error shown at its column, the formula and its box kept in the
// address so that a link replays the run.
import assert from "node:assert/strict";
import { join } from "node:path";
import { test } from "node:test";
import { SHOTS, advance, h, load, noProblems, openPaused, readout, setControl, setUp } from "./harness.mjs";

setUp();

/** Opens the page on a formula, paused. */
async function openFormula(formula, extra = {}) {
  await openPaused({ potential: "formula", formula, ...extra });
}

test("a typed formula is the potential the chains run on, its gradient exact", async () => {
  await openFormula("x^2 + 3 y^2 + sin(x y)", { spf: 50 });
  assert.equal(await h.page.textContent("#error"), "");
  assert.equal(await h.page.isVisible("#formula"), true);
  // Every chain's value is the formula at its position, and the law of its
  // next step uses the exact gradient (2x + y cos(xy), 6y + x cos(xy)).
  const worst = await h.page.evaluate(() => {
    const r = window.hrlaDemo.state.runs[0];
    let worstU = 0;
    let worstG = 0;
    for (let c = 0; c < r.n; c++) {
      const x = r.x[2 * c];
      const y = r.x[2 * c + 1];
      const u = x * x + 3 * y * y + Math.sin(x * y);
      worstU = Math.max(worstU, Math.abs(r.u[c] - u) / (1 + Math.abs(u)));
      const law = r.nextStep(c);
      const g = [2 * x + y * Math.cos(x * y), 6 * y + x * Math.cos(x * y)];
      worstG = Math.max(worstG, Math.abs(law[5] - g[0]) / (1 + Math.abs(g[0])), Math.abs(law[6] - g[1]) / (1 + Math.abs(g[1])));
    }
    return { worstU, worstG };
  });
  // libm against the browser's Math: both within an ulp or two.
  assert.ok(worst.worstU < 1e-14, `values off by ${worst.worstU}`);
  assert.ok(worst.worstG < 1e-14, `gradients off by ${worst.worstG}`);
  // The run searches it: U* = 0 at the origin, found.
  for (let k = 1; k <= 20; k++) await advance(50 * k);
  assert.ok((await readout("out-best")) < 1e-2, `best ${await readout("out-best")}`);
  assert.equal(await readout("out-lost"), 0);
});

test("a syntax error is shown at its column, with a caret, and nothing runs", async () => {
  await openFormula("x^2 + y^2", { spf: 10 });
  await setControl("formula", "x^2 + * y");
  assert.match(await h.page.textContent("#err-formula"), /^formula, column 7: “\*” where a number, x, y, a function or “\(” is needed$/);
  assert.equal(await h.page.getAttribute("#formula", "aria-invalid"), "true");
  const caret = (await h.page.textContent("#formula-caret")).split("\n");
  assert.equal(caret[0], "x^2 + * y");
  assert.equal(caret[1].indexOf("^"), 6, `caret line “${caret[1]}”`);
  assert.equal(caret[0][caret[1].indexOf("^")], "*");
  assert.match(await h.page.textContent("#error"), /No run/);
  assert.equal(await h.page.isDisabled("#play"), true);
  // Other mistakes, other columns.
  for (const [typed, column, words] of [
    ["x + z", 5, /“z” is not known/],
    ["sin(x", 6, /ends where “\)” or “,” is needed/],
    ["max(x)", 1, /max takes 2 arguments, given 1/],
    ["2 $ x", 3, /“\$” is not part of a formula/],
  ]) {
    await setControl("formula", typed);
    assert.match(await h.page.textContent("#err-formula"), new RegExp(`column ${column}: `), typed);
    assert.match(await h.page.textContent("#err-formula"), words, typed);
    assert.equal(Number(await h.page.getAttribute("#formula-caret", "data-column")), column);
  }
  await setControl("formula", "x^2 + y^2");
  assert.equal(await h.page.textContent("#err-formula"), "");
  assert.equal(await h.page.isHidden("#formula-caret"), true);
  assert.equal(await h.page.textContent("#error"), "");
});

test("a formula that is not finite over its box is refused at the box, and a smaller box fixes it", async () => {
  await openFormula("log(x) + y^2");
  assert.match(await h.page.textContent("#err-fhalf"), /U = NaN at \(-5, -5\).*choose a smaller box/);
  assert.match(await h.page.textContent("#error"), /No run/);
  await setControl("fcx", 3);
  await setControl("fhalf", 2);
  assert.equal(await h.page.textContent("#err-fhalf"), "");
  assert.equal(await h.page.textContent("#error"), "");
  const view = await h.page.evaluate(() => window.hrlaDemo.state.view);
  assert.deepEqual(view, { cx: 3, cy: 0, half: 2 });
  // The start follows the box, as a landscape's suggestion.
  assert.equal(await h.page.inputValue("#cx"), "3");
});

test("the formula and its box are in the address: the link replays the run", async () => {
  await openFormula("(x^2 - 1)^2 + (y - x)^2 / 2 + 0.3 x", { spf: 100, fcx: 0.5, fcy: -0.5, fhalf: 3, seed: 7 });
  for (let k = 1; k <= 5; k++) await advance(100 * k);
  const first = await h.page.getAttribute("#out-best", "data-value");
  const url = new URL(h.page.url());
  assert.equal(url.searchParams.get("formula"), "(x^2 - 1)^2 + (y - x)^2 / 2 + 0.3 x");
  assert.equal(url.searchParams.get("fhalf"), "3");
  await load(url.href);
  assert.equal(await h.page.inputValue("#formula"), "(x^2 - 1)^2 + (y - x)^2 / 2 + 0.3 x");
  assert.deepEqual(await h.page.evaluate(() => window.hrlaDemo.state.view), { cx: 0.5, cy: -0.5, half: 3 });
  for (let k = 1; k <= 5; k++) await advance(100 * k);
  assert.equal(await h.page.getAttribute("#out-best", "data-value"), first);
  await h.page.screenshot({ path: join(SHOTS, "formula.png") });
});

test("a formula unbounded below: the chains run away and the run says so", async () => {
  // Downhill at speed |∇U| h = 0.7 per step: beyond the escape radius
  // (5000) after about 7000 steps.
  await openFormula("x + y", { spf: 20000, h: 0.5 });
  await h.page.keyboard.press(".");
  await h.page.waitForFunction(() => document.getElementById("error").textContent !== "", null, { timeout: 60_000 });
  assert.match(await h.page.textContent("#error"), /ran away.*U does not hold the chains/);
});

test("no console error, failed request or request leaving 127.0.0.1", () => noProblems());
