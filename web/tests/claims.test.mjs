// The numbers compare mode states are measurements, not prose: every
// success probability in web/js/landscapes.js (`measured`) is recomputed
// here with the wrapper's Node build, at each landscape's page defaults,
// exactly as MEASURED describes, and must come out the same to the two
// decimals shown. The runs are seeded, so the numbers are exact, not
// estimates that could drift.
import assert from "node:assert/strict";
import { test } from "node:test";
import { LANDSCAPES, MEASURED } from "../js/landscapes.js";
import { values, wasm } from "../../wasm/tests/load.mjs";

/** Mean over the seeds of the share of groups whose best current value is within eps of U*. */
function measure(name, sampler) {
  const l = LANDSCAPES[name];
  const minimum = wasm.global_minimum(name);
  const sums = MEASURED.steps.map(() => 0);
  for (let seed = 1; seed <= MEASURED.seeds; seed++) {
    const opt = new wasm.Optimizer({
      potential: name,
      sampler,
      a: l.a,
      annealing: null,
      h: l.h,
      chains: MEASURED.chains,
      centre: [l.start.cx, l.start.cy],
      spread: l.start.spread,
      seed,
      stopSteps: null,
      stopTarget: null,
    });
    let at = 0;
    MEASURED.steps.forEach((k, i) => {
      assert.equal(opt.advance(k - at), k - at);
      at = k;
      const u = values(opt);
      const groups = Math.floor(u.length / MEASURED.group);
      let hit = 0;
      for (let g = 0; g < groups; g++) {
        const best = Math.min(...u.slice(g * MEASURED.group, (g + 1) * MEASURED.group).map((v) => (Number.isFinite(v) ? v : Infinity)));
        if (best - minimum <= l.eps) hit++;
      }
      sums[i] += hit / groups;
    });
    opt.free();
  }
  return sums.map((s) => Number((s / MEASURED.seeds).toFixed(2)));
}

for (const name of Object.keys(LANDSCAPES)) {
  test(`compare mode's numbers for ${name} are what the kernel gives`, () => {
    for (const sampler of ["hrla", "ula", "ola"]) {
      assert.deepEqual(measure(name, sampler), LANDSCAPES[name].measured[sampler], `${name} ${sampler}`);
    }
  });
}

// The notes' rankings follow from the numbers: a note that names a winner
// names the sampler with the highest P after the most steps, or one tied
// with it (within 0.05).
test("each note's ranking agrees with its numbers", () => {
  const claims = {
    rastrigin: { leads: ["ula"] },
    ackley: { leads: ["hrla", "ola"], trails: "ula" },
    levy: { leads: ["hrla", "ola"], trails: "ula" },
    "styblinski-tang": { leads: ["hrla", "ola"], trails: "ula" },
  };
  for (const [name, { leads, trails }] of Object.entries(claims)) {
    const m = LANDSCAPES[name].measured;
    const last = (s) => m[s].at(-1);
    const top = Math.max(...["hrla", "ula", "ola"].map(last));
    for (const s of leads) assert.ok(top - last(s) <= 0.05, `${name}: ${s} at ${last(s)}, the best at ${top}`);
    if (trails) for (const s of leads) assert.ok(last(s) - last(trails) >= 0.3, `${name}: ${trails} does not trail ${s}`);
  }
});

// The Rastrigin note's physics, read from the kernel's own step laws:
// HRLA's velocity follows exactly ULA's equation (the same mean of the new
// velocity, affine in (y, g) with the same coefficients, and the same
// variance), and what HRLA adds is a pull of the position down the local
// gradient, hundreds of times ULA's (ULA's position feels the gradient
// only through the velocity, to second order in h).
test("the Rastrigin note's physics is the kernel's", () => {
  const note = LANDSCAPES.rastrigin.compare;
  assert.match(note, /HRLA's velocity follows exactly ULA's equation/);
  assert.match(note, /pulls the position straight down the local gradient/);
  // HRLA's velocity is ULA's: nothing about it is overdamped.
  assert.doesNotMatch(note, /overdamped/);
  const law = (sampler, steps) => {
    const opt = new wasm.Optimizer({
      potential: "rastrigin",
      sampler,
      a: LANDSCAPES.rastrigin.a,
      annealing: null,
      h: LANDSCAPES.rastrigin.h,
      chains: 3,
      centre: [3, 3],
      spread: 0.5,
      seed: 7,
      stopSteps: null,
      stopTarget: null,
    });
    assert.equal(opt.advance(steps), steps);
    const laws = [0, 1, 2].map((c) => opt.nextStep(c));
    opt.free();
    // a, x0, x1, y0, y1, g0, g1, then per coordinate mean_x, mean_y, var_x, cov_xy, var_y, then the pushes.
    return laws.map((s) => ({ y: s[3], g: s[5], meanY: s[8], varY: s[11], gradientPush: s[17] }));
  };
  // ULA's velocity mean is e·y − c·g: solve for (e, c) from two chains.
  const [p, q, r] = law("ula", 25);
  const det = p.y * q.g - q.y * p.g;
  const e = (p.meanY * q.g - q.meanY * p.g) / det;
  const c = (p.y * q.meanY - q.y * p.meanY) / -det;
  assert.ok(Math.abs(r.meanY - (e * r.y - c * r.g)) <= 1e-12 * (1 + Math.abs(r.meanY)), "ULA's velocity mean is affine in (y, g)");
  for (const s of law("hrla", 40)) {
    assert.ok(s.y !== 0 && s.g !== 0, "a state with velocity and gradient");
    assert.ok(Math.abs(s.meanY - (e * s.y - c * s.g)) <= 1e-12 * (1 + Math.abs(s.meanY)), `HRLA's velocity mean ${s.meanY} is ULA's ${e * s.y - c * s.g}`);
    assert.equal(s.varY, p.varY, "the same velocity variance");
    // The same gradient pushes HRLA's position far more than ULA's.
    const ulaPush = (p.gradientPush / p.g) * s.g;
    assert.ok(Math.abs(s.gradientPush) > 100 * Math.abs(ulaPush), `HRLA's pull ${s.gradientPush} against ULA's ${ulaPush}`);
  }
});
