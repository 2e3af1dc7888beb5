// What a first-time visitor meets: the comparison told truthfully, a
// density view that shows something, defaults that succeed on every
// landscape, failures called failures, a step one can see, every refused
// field flagged at once, a phone layout with the run first, and the jargon
// explained beside the controls. Driven by exact step counts (see harness.mjs).
import assert from "node:assert/strict";
import { join } from "node:path";
import { test } from "node:test";
import {
  SHOTS,
  advance,
  colourAt,
  colourDistance,
  h,
  noProblems,
  openPaused,
  particleAt,
  readout,
  setControl,
  setUp,
  untilIteration,
} from "./harness.mjs";

setUp();

// ---- 1. Compare mode tells the true story. ----

// Defect: HRLA's white dots were drawn first, under ULA's and OLA's. At
// iteration 0 the three runs share their starts, so the top colour at a
// chain is that of the run drawn last.
test("compare mode draws HRLA's chains on top", async () => {
  await openPaused({ compare: 1, chains: 64 });
  const at = await h.page.evaluate(async () => {
    const { Summary: S } = await import("/js/sim.js");
    const { state } = window.hrlaDemo;
    const r = state.runs[0];
    const best = [r.s[S.BestX0], r.s[S.BestX1]];
    // A chain away from the circled best point (whose ring is drawn over all).
    for (let c = 0; c < r.n; c++) {
      const x = [r.x[2 * c], r.x[2 * c + 1]];
      const far = Math.hypot(state.frame.px(x[0]) - state.frame.px(best[0]), state.frame.py(x[1]) - state.frame.py(best[1]));
      if (far > 14) return x;
    }
    return null;
  });
  assert.ok(at, "no chain away from the best point");
  const [r, g, b, alpha] = await particleAt(at[0], at[1]);
  assert.equal(alpha, 255);
  assert.ok(r > 230 && g > 230 && b > 230, `the top dot is (${r}, ${g}, ${b}), not HRLA's white`);
});

test("compare mode says what the visitor sees, which dynamics this landscape favours, and the paper's claim against the measurement", async () => {
  await openPaused({ chains: 64 });
  assert.equal(await h.page.isVisible("#compare-about"), false);
  assert.equal(await h.page.isVisible("#compare-lead"), false);
  await h.page.check("#compare");
  assert.equal(await h.page.isVisible("#compare-about"), true);
  // The gist is on the first screen, under the picture's buttons.
  const lead = await h.page.evaluate(() => ({ text: document.getElementById("compare-lead").textContent, bottom: document.getElementById("compare-lead").getBoundingClientRect().bottom, height: window.innerHeight }));
  assert.match(lead.text, /ULA wins here.*momentum/);
  assert.ok(lead.bottom < lead.height, `the compare line ends at ${lead.bottom}px, below the first screen (${lead.height})`);
  const rastrigin = await h.page.textContent("#compare-about");
  // What is on the screen.
  assert.match(rastrigin, /same seed/);
  assert.match(rastrigin, /HRLA.*on top/s);
  // Which dynamics the landscape favours, and why.
  assert.match(rastrigin, /ULA/);
  assert.match(rastrigin, /momentum/);
  // The paper's claim and this project's measurement.
  assert.match(rastrigin, /paper/);
  assert.match(rastrigin, /E2/);
  assert.match(rastrigin, /indistinguishable/);
  assert.match(rastrigin, /docs\/REPRODUCTION\.md/);
  // The note follows the landscape.
  await h.page.selectOption("#potential", "ackley");
  const ackley = await h.page.textContent("#compare-landscape");
  assert.notEqual(ackley, "");
  assert.ok(!rastrigin.includes(ackley), "the note did not change with the landscape");
  assert.match(ackley, /Ackley/);
});

// ---- 2. The density view shows the density. ----

// Defect: a linear scale normalised to the peak showed one bright spot on
// a uniform purple square at a = 4: the wells around the global one, where
// the density is 1e-2..1e-4 of its peak, had the floor's colour.
test("the density view at the defaults shows the wells around the global one", async () => {
  await openPaused({ show: "density" });
  const peak = await colourAt(0, 0);
  const ring = await colourAt(1, 0); // a local minimum, U = 1
  const far = await colourAt(4.5, 4.5);
  assert.ok(colourDistance(ring, far) > 80, `well (1, 0) ${ring} against the corner ${far}`);
  assert.ok(colourDistance(ring, peak) > 40, `well (1, 0) ${ring} against the peak ${peak}`);
  assert.match(await h.page.getAttribute("#colorbar", "aria-label"), /log/);
});

test("under annealing the density view follows a and stays readable", async () => {
  await openPaused({ show: "density", schedule: "linear", spf: 500 });
  const structure = async () => {
    const peak = await colourAt(0, 0);
    const ring = await colourAt(1, 0);
    const far = await colourAt(4.5, 4.5);
    return [colourDistance(ring, far), colourDistance(peak, far)];
  };
  for (const k of [0, 500, 2000, 10000]) {
    if (k > 0) {
      await setControl("spf", k - (await readout("out-iteration")));
      await advance(k);
    }
    const [ringFar, peakFar] = await structure();
    assert.ok(peakFar > 80, `at iteration ${k}: peak against corner ${peakFar}`);
    assert.ok(ringFar > 20 || k === 0, `at iteration ${k}: well against corner ${ringFar}`);
  }
});

// ---- 3. Every landscape's defaults show a success at the default pace. ----

// Defect: Levy and Styblinski–Tang showed P = 0.00 after 20 s. Twenty
// seconds of the default pace (2 steps per frame at 60 frames/s) is 2400
// steps; stepped here 300 at a time.
for (const [potential, steps] of [
  ["levy", 2400],
  ["styblinski-tang", 2400],
]) {
  test(`${potential}: the defaults show a success within 20 s of the default pace`, async () => {
    await openPaused({ potential });
    assert.equal(await h.page.inputValue("#spf"), "2");
    await setControl("spf", 300);
    for (let k = 300; k <= steps; k += 300) await advance(k);
    const p = await readout("out-prob");
    assert.ok(p >= 0.2, `P = ${p} after ${steps} steps`);
  });
}

// ---- 4. A runaway is a failure, said once. ----

// Defect: with h = 1 on Rastrigin every chain grows geometrically to
// |x| = 1e20 with finite values: "diverged 0 of 256", and the run played on.
test("h = 1: chains that run away are counted as lost, and when all have, the run stops and says to lower h", async () => {
  await openPaused({ h: 1, spf: 50 });
  let stopped = false;
  for (let i = 1; i <= 20 && !stopped; i++) {
    await h.page.keyboard.press(".");
    await h.page.waitForFunction(
      (n) => Number(document.getElementById("out-iteration").dataset.value) === n || document.getElementById("error").textContent !== "",
      50 * i,
      { timeout: 60_000 },
    );
    stopped = (await h.page.textContent("#error")) !== "";
  }
  assert.ok(stopped, "the run never stopped");
  const error = await h.page.textContent("#error");
  assert.match(error, /all 256 chains ran away/);
  assert.match(error, /smaller step h/);
  assert.equal(await h.page.getAttribute("#h", "aria-invalid"), "true");
  assert.equal(await readout("out-lost"), 256);
  assert.equal(await h.page.textContent("#play"), "Play");
  const at = await readout("out-iteration");
  assert.ok(at > 0 && at < 1000, `stopped at ${at}`);
  // Stopped means stopped.
  await h.page.keyboard.press(".");
  assert.equal(await readout("out-iteration"), at);
});

// Defect: after every chain diverged, the frame readout blamed the time
// budget, the diverged chains were counted again as "outside the picture",
// and the failure was stated three times. (h = 5 now ends with every chain
// beyond the escape radius before any overflows.)
test("a failed run states its failure once, blames no time budget and counts no chain twice", async () => {
  await openPaused({ h: 5, chains: 10, spf: 1000 });
  await h.page.keyboard.press(".");
  await h.page.waitForFunction(() => document.getElementById("error").textContent !== "", null, { timeout: 60_000 });
  const said = await h.page.evaluate(() => {
    const places = ["error", "status", "err-h", "err-general", "out-frame-steps", "out-outside"];
    return Object.fromEntries(places.map((id) => [id, document.getElementById(id).textContent]));
  });
  const mentions = Object.values(said).join(" | ").match(/diverged|ran away/g) ?? [];
  assert.equal(mentions.length, 1, `the failure said ${mentions.length} times: ${JSON.stringify(said)}`);
  assert.match(said.error, /all 10 chains ran away/);
  assert.match(said["err-h"], /try a smaller h/);
  assert.doesNotMatch(said["out-frame-steps"], /time budget/);
  assert.match(said["out-frame-steps"], /the run ended/);
  assert.equal(await readout("out-outside"), 0);
  assert.equal(await readout("out-lost"), 10);
});

// ---- 5. A step one can see. ----

// Defect: Step advanced 2 iterations of h = 0.01: a move of a pixel or two.
test("Step shows one step, magnified so that it can be seen", async () => {
  await openPaused();
  await h.page.click("#step");
  await untilIteration(1);
  assert.equal(await h.page.isVisible("#anatomy"), true);
  const spans = await h.page.evaluate(() => window.hrlaDemo.anatomySpans());
  assert.equal(spans.length, 1);
  // Start, mean and draw are drawn tens of pixels apart in the inset.
  assert.ok(spans[0].moved > 30, `the step spans ${spans[0].moved} px in the inset`);
});

// ---- 6. Every refused field at once; Play only with a run; the visitor's
// settings kept; dense clusters light. ----

test("every refused field is flagged at once", async () => {
  await openPaused();
  await setControl("chains", 0);
  await setControl("a", -2);
  assert.match(await h.page.textContent("#err-chains"), /chains N must be between 1 and 1024/);
  assert.match(await h.page.textContent("#err-a"), /a must be a number above 0/);
  await setControl("spread", -1);
  assert.match(await h.page.textContent("#err-chains"), /chains N/);
  assert.match(await h.page.textContent("#err-a"), /a must/);
  assert.match(await h.page.textContent("#err-spread"), /spread s must/);
  assert.match(await h.page.textContent("#error"), /No run: 3 settings are refused/);
});

test("without a run the play button offers nothing to pause", async () => {
  await h.page.goto(`${h.base}?h=-1`);
  await h.page.waitForSelector("body[data-ready=true]");
  assert.equal(await h.page.textContent("#play"), "Play");
  assert.equal(await h.page.isDisabled("#play"), true);
  assert.equal(await h.page.isDisabled("#step"), true);
  await setControl("h", 0.01);
  assert.equal(await h.page.isDisabled("#play"), false);
  // The page was opened to play: it plays once there is a run.
  assert.equal(await h.page.textContent("#play"), "Pause");
  await h.page.click("#play");
});

test("changing the landscape keeps the settings the visitor changed, and says so", async () => {
  await openPaused();
  await setControl("h", 0.02);
  await h.page.selectOption("#potential", "levy");
  // The visitor's h is kept; the untouched a and start take Levy's.
  assert.equal(await h.page.inputValue("#h"), "0.02");
  const { LANDSCAPES } = await h.page.evaluate(() => import("/js/landscapes.js"));
  const levy = LANDSCAPES.levy;
  assert.equal(await h.page.inputValue("#a"), String(levy.a));
  assert.equal(await h.page.inputValue("#cx"), String(levy.start.cx));
  const note = await h.page.textContent("#landscape-note");
  assert.match(note, /kept your h = 0\.02/);
  assert.match(note, new RegExp(`Levy's: ${levy.h}`));
  // One click takes the landscape's own.
  await h.page.click("#use-suggested");
  assert.equal(await h.page.inputValue("#h"), String(levy.h));
  assert.equal(await h.page.textContent("#landscape-note"), "");
});

// Defect: each dot's dark outline was stroked after all the fills, so a
// dense cluster was a black blob.
test("a dense cluster of chains is drawn light, not as a black blob", async () => {
  await openPaused({ chains: 1024, spread: 0.04 });
  const { mean, counted } = await h.page.evaluate(async () => {
    const { Summary: S } = await import("/js/sim.js");
    const { state } = window.hrlaDemo;
    const r = state.runs[0];
    const bx = state.frame.px(r.s[S.BestX0]) * state.dpr;
    const by = state.frame.py(r.s[S.BestX1]) * state.dpr;
    const x0 = Math.round(state.frame.px(3) * state.dpr) - 6;
    const y0 = Math.round(state.frame.py(3) * state.dpr) - 6;
    const d = document.getElementById("particles").getContext("2d").getImageData(x0, y0, 13, 13).data;
    let sum = 0;
    let counted = 0;
    for (let j = 0; j < 13; j++) {
      for (let i = 0; i < 13; i++) {
        // Off the running best's ring (radius 8, drawn over the dots).
        if (Math.abs(Math.hypot(x0 + i + 0.5 - bx, y0 + j + 0.5 - by) - 8 * state.dpr) < 3.5 * state.dpr) continue;
        const k = 4 * (j * 13 + i);
        sum += (d[k] + d[k + 1] + d[k + 2]) / 3;
        counted++;
      }
    }
    return { mean: sum / counted, counted };
  });
  assert.ok(counted >= 60, `only ${counted} pixels off the best's ring`);
  assert.ok(mean > 200, `the cluster's centre has mean brightness ${mean}`);
});

// ---- 7. On a phone: the run first. ----

test("on a phone the Play button is on the first screen, the plots come before the controls, and no keyboard help is shown", async () => {
  await h.page.setViewportSize({ width: 390, height: 844 });
  await openPaused();
  const r = await h.page.evaluate(() => ({
    play: document.getElementById("play").getBoundingClientRect().bottom,
    plots: document.getElementById("plot-best").getBoundingClientRect().top,
    controls: document.querySelector("#controls fieldset").getBoundingClientRect().top,
    height: window.innerHeight,
  }));
  assert.ok(r.play < r.height, `Play ends at ${r.play}px, below the first screen (${r.height})`);
  assert.ok(r.plots < r.controls, `the plots start at ${r.plots}px, after the controls at ${r.controls}px`);
  assert.equal(await h.page.isVisible(".keys"), false);
  await h.page.screenshot({ path: join(SHOTS, "phone-first-screen.png") });
  await h.page.setViewportSize({ width: 1280, height: 800 });
});

// ---- 8. The jargon, explained where it is used. ----

test("ULA, OLA, a, h and the success probability are explained beside their controls", async () => {
  await openPaused();
  const hint = async (control, id) => {
    assert.equal(await h.page.isVisible(`#${id}`), true, `${id} not shown`);
    const described = (await h.page.getAttribute(`#${control}`, "aria-describedby")) ?? "";
    assert.ok(described.split(" ").includes(id), `#${control} is not described by #${id}`);
    return h.page.textContent(`#${id}`);
  };
  const sampler = await hint("sampler", "hint-sampler");
  assert.match(sampler, /HRLA/);
  await h.page.selectOption("#sampler", "ula");
  assert.match(await hint("sampler", "hint-sampler"), /underdamped.*momentum/is);
  await h.page.selectOption("#sampler", "ola");
  assert.match(await hint("sampler", "hint-sampler"), /overdamped/i);
  assert.match(await hint("a", "hint-a"), /inverse temperature.*higher a/is);
  assert.match(await hint("h", "hint-h"), /step/);
  assert.match(await hint("group", "hint-prob"), /independent runs.*ε/s);
});

test("no console error, failed request or request leaving 127.0.0.1", () => noProblems());
