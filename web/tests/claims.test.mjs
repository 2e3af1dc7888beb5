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
