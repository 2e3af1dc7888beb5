// A visitor's own function: typed for U(x, y), parsed and differentiated
// exactly in the wasm, run by the kernel like a built-in landscape, a
// syntax error shown at its column, the formula and its box kept in the
// address so that a link replays the run.
import assert from "node:assert/strict";
import { join } from "node:path";
import { test } from "node:test";
import { SHOTS, advance, colourAt, h, load, noProblems, openPaused, readout, setControl, setUp } from "./harness.mjs";

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

/** Whether the landscape canvas shows a colour at (x, y) (a cleared canvas reads black). */
async function drawnAt(x, y) {
  const c = await colourAt(x, y);
  return c[0] + c[1] + c[2] > 60;
}

test("a formula undefined on part of its box: the refusal says where, moving the box fixes it, the picture stays", async () => {
  await openFormula("log(x) + y^2");
  const said = await h.page.textContent("#err-fhalf");
  // U is NaN for x < 0 and -inf at x = 0: only moving the box helps.
  assert.match(said, /^U = NaN at \(-5, -5\), and U must be finite over the whole box: move the box so that it leaves out the part with x from -5 to 0 and y from -5 to 5 /);
  assert.doesNotMatch(said, /choose a smaller box/);
  assert.match(await h.page.textContent("#error"), /No run/);
  // The formula is drawn where it is defined, the rest hatched grey.
  assert.equal(await drawnAt(3, 1), true);
  const grey = await colourAt(-3, 1);
  assert.ok(grey[0] === grey[1] && grey[1] === grey[2] && grey[0] > 60, `at (-3, 1): ${grey}`);
  assert.equal(await h.page.isVisible("#potential-undefined"), true);
  await setControl("fcx", 3);
  await setControl("fhalf", 2);
  assert.equal(await h.page.textContent("#err-fhalf"), "");
  assert.equal(await h.page.textContent("#error"), "");
  assert.equal(await h.page.isVisible("#potential-undefined"), false);
  const view = await h.page.evaluate(() => window.hrlaDemo.state.view);
  assert.deepEqual(view, { cx: 3, cy: 0, half: 2 });
  // The start follows the box, as a landscape's suggestion.
  assert.equal(await h.page.inputValue("#cx"), "3");
});

test("a formula infinite at one point: the refusal names the point and a shift that works", async () => {
  await openFormula("1/(x^2 + y^2)");
  const said = await h.page.textContent("#err-fhalf");
  assert.match(said, /U = inf at \(0, 0\), and U must be finite over the whole box: move the box so that it leaves out \(0, 0\) /);
  assert.match(said, /1\/\(x\^2 \+ y\^2 \+ 1e-6\)/);
  assert.equal(await drawnAt(2, 2), true);
  await setControl("formula", "1/(x^2 + y^2 + 1e-6)");
  assert.equal(await h.page.textContent("#err-fhalf"), "");
  assert.equal(await h.page.textContent("#error"), "");
});

test("a formula finite everywhere but with a kink: the refusal is about its gradient, and smoothing fixes it", async () => {
  await openFormula("sqrt(x^2 + y^2)");
  const said = await h.page.textContent("#err-fhalf");
  assert.match(said, /U = 0 at \(0, 0\) is finite, but its gradient is not \(NaN, NaN\), and the chains follow the gradient: move the box so that it leaves out \(0, 0\), or smooth the formula there/);
  assert.match(said, /sqrt\(x\^2 \+ y\^2 \+ 1e-6\)/);
  assert.doesNotMatch(said, /smaller box/);
  // U is finite everywhere: all of the box is drawn.
  for (const [x, y] of [[0, 0], [-4, 4], [4, -4]]) assert.equal(await drawnAt(x, y), true, `at (${x}, ${y})`);
  assert.equal(await h.page.isVisible("#potential-undefined"), false);
  await setControl("formula", "sqrt(x^2 + y^2 + 1e-6)");
  assert.equal(await h.page.textContent("#err-fhalf"), "");
  assert.equal(await h.page.textContent("#error"), "");
  // A formula that cannot be read keeps the last picture.
  await setControl("formula", "sqrt(x^2 +");
  assert.match(await h.page.textContent("#err-formula"), /column/);
  assert.equal(await drawnAt(1, 1), true);
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

test("a saddle unbounded below: runaways are failures, P is not scored, and the advice can work", async () => {
  // U = 2xy falls without bound along x = -y: chains run downhill and away.
  await openFormula("2x y", { spf: 200 });
  let k = 0;
  while ((await readout("out-lost")) === 0) await advance((k += 200));
  // A lost chain never counts as its group's best, however low its U.
  const wrong = await h.page.evaluate(() => {
    const r = window.hrlaDemo.state.runs[0];
    const i = r.count - 1;
    let bad = 0;
    for (let g = 0; g < r.groups; g++) {
      let m = Infinity;
      for (let c = g * r.groupSize; c < (g + 1) * r.groupSize; c++) if (!r.isLost(c)) m = Math.min(m, r.u[c]);
      if (r.groupBest[i * r.groups + g] !== m) bad++;
    }
    return bad;
  });
  assert.equal(wrong, 0);
  // Some chains have run away downhill: no success is scored.
  assert.equal(await h.page.getAttribute("#out-prob", "data-value"), "NaN");
  assert.equal(await h.page.textContent("#out-prob"), "none: U went below U*");
  // Nor in the plot of P: no point of the series is 1 once U went below U*.
  const series = await h.page.evaluate(() => {
    const r = window.hrlaDemo.state.runs[0];
    return [...r.probabilitySeries(0.1, new Float64Array(r.count))].slice(-1)[0];
  });
  assert.ok(Number.isNaN(series), `P at the last point: ${series}`);
  const status = await h.page.textContent("#status");
  assert.match(status, /chains ran away downhill \(to U = -[0-9.e+]+\), below U\* = -50: U looks unbounded below beyond the box, so no success can be scored/);
  assert.match(status, /No step h or temperature a holds chains on it: give U a floor/);
  assert.doesNotMatch(status, /smaller step h/);
  // On until every chain has gone: the run fails, and says why in the same terms.
  await h.page.fill("#spf", "5000");
  await h.page.press("#spf", "Tab");
  while ((await h.page.textContent("#error")) === "") {
    await h.page.evaluate(() => document.activeElement?.blur());
    await h.page.keyboard.press(".");
    await h.page.waitForFunction(() => window.hrlaDemo.state.pending === 0 || !window.hrlaDemo.state.runs[0].live, null, { timeout: 60_000 });
  }
  const error = await h.page.textContent("#error");
  assert.match(error, /^all 256 chains ran away beyond \|x\| = 5000 .*downhill to U = -.*U looks unbounded below/);
  assert.doesNotMatch(error, /smaller/);
  assert.equal(await h.page.getAttribute("#out-prob", "data-value"), "NaN");
});

test("no console error, failed request or request leaving 127.0.0.1", () => noProblems());
