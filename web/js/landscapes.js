// What the page knows of each landscape beyond the kernel: how to show it
// (view box, formula, every global minimiser to mark), the settings a
// visitor starts from (a start away from the global basin, a temperature
// and step at which a success shows within about 20 s of the default
// pace), and what compare mode says about it: which dynamics this
// landscape favours and why, with the success probabilities measured on
// the page's own kernel (web/tests/claims.test.mjs recomputes every one).
// The potential itself, U* and the pictures' values come from the kernel
// through the wasm wrapper.

/**
 * How `measured` was made: each landscape's defaults (below), 256 chains,
 * seeds 1..10; the mean over the seeds of P, the share of the 25 groups of
 * 10 chains whose best current value is within the landscape's ε of U*,
 * after each number of steps.
 */
export const MEASURED = { chains: 256, group: 10, seeds: 10, steps: [600, 1000, 2000] };

/** Keyed by the wrapper's `potential` names, in the order listed. */
export const LANDSCAPES = {
  rastrigin: {
    label: "Rastrigin",
    formula: "U(x) = 2 + |x|² − cos 2πx₁ − cos 2πx₂",
    about: "a local minimum near every integer point; the global one, U* = 0, at the origin",
    view: { cx: 0, cy: 0, half: 5 },
    start: { cx: 3, cy: 3, spread: 0.5 },
    a: 4,
    h: 0.01,
    eps: 0.5,
    minimisers: [[0, 0]],
    headline: "On Rastrigin ULA wins here: its momentum carries its chains over the ripples down the bowl.",
    compare:
      "On Rastrigin, ULA wins. Its ripples (height 2) sit on a big bowl, and the start at (3, 3) is 18 above the bottom. ULA moves its position only through its velocity, which gathers the bowl's slope as momentum (friction removes it only over a time 1/α = 1) and carries its chains over the ripples to the centre. HRLA's velocity follows exactly ULA's equation and gathers the same momentum, but HRLA also pulls the position straight down the local gradient (β∇U, β = 1), toward the minimum of whichever ripple it sits in: that pull holds its chains in a ripple until a random kick on the position carries them over, rare at a = 4. OLA has the same pull and no momentum at all.",
    measured: { hrla: [0.08, 0.31, 0.79], ula: [0.94, 0.98, 0.99], ola: [0.06, 0.3, 0.78] },
  },
  ackley: {
    label: "Ackley",
    formula: "U(x) = 20 (1 − e^(−0.2 |x|/√2)) + e (1 − e^(−q)), q = ½ Σ (1 − cos 2πxᵢ)",
    about: "a nearly flat plateau of local minima around one deep funnel; U* = 0 at the origin",
    view: { cx: 0, cy: 0, half: 5 },
    start: { cx: 3, cy: 3, spread: 0.5 },
    a: 4,
    h: 0.01,
    eps: 0.5,
    minimisers: [[0, 0]],
    headline: "On Ackley HRLA and OLA lead and ULA trails: no slope to roll down, and ULA wanders slowly.",
    compare:
      "On Ackley, HRLA and OLA lead and ULA trails. The plateau has almost no slope to roll down, so momentum does not help; the chains must wander until they fall into the funnel, and ULA moves its position only through its velocity, whose spread is fixed by b = 10: its chains wander more slowly than OLA's and HRLA's, whose kicks on the position grow as a falls.",
    measured: { hrla: [0.22, 0.52, 0.96], ula: [0.03, 0.24, 0.5], ola: [0.12, 0.48, 0.95] },
  },
  levy: {
    label: "Levy",
    formula: "U(x) = sin² πw₁ + (w₁ − 1)² (1 + 10 sin²(πw₁ + 1)) + (w₂ − 1)² (1 + sin² 2πw₂), w = 1 + (x − 1)/4",
    about: "ridges of local minima; U* = 0 at (1, 1)",
    view: { cx: 0, cy: 0, half: 10 },
    start: { cx: -6, cy: -6, spread: 0.5 },
    // Its features are four times wider than Rastrigin's, so the search
    // takes longer in time: at a = 1.5, h = 0.01 no group of 10 succeeded
    // within 2400 steps. h = 0.03 gives the same success at equal time as
    // h = 0.01 (h = 0.05 already more: an artefact of the long step).
    a: 1,
    h: 0.03,
    eps: 0.5,
    minimisers: [[1, 1]],
    headline: "On Levy HRLA and OLA are alike and ULA is far behind: its chains wander slowly.",
    compare:
      "On Levy, HRLA and OLA are alike and ULA is far behind: the wells are wide and far apart, so the search is a long wander, and ULA's position wanders only through its velocity (spread fixed by b = 10), about ten times more slowly at a = 1 than OLA's.",
    measured: { hrla: [0.23, 0.32, 0.51], ula: [0.01, 0.02, 0.08], ola: [0.2, 0.34, 0.51] },
  },
  "styblinski-tang": {
    label: "Styblinski–Tang",
    formula: "U(x) = ½ Σ (xᵢ⁴ − 16 xᵢ² + 5 xᵢ)",
    about: "four wells; the deepest, U* = −78.33, at (−2.90, −2.90), the start's well, at (2.75, 2.75), 28.3 higher",
    view: { cx: 0, cy: 0, half: 5 },
    start: { cx: 2.75, cy: 2.75, spread: 0.3 },
    // The barrier out of the start's well is 25 per coordinate: at a = 0.3
    // a chain waits about e^7.5 for a kick over it (no success within 6000
    // steps); at a = 0.15 about e^3.8.
    a: 0.15,
    h: 0.01,
    eps: 2,
    minimisers: [[-2.903534027771177, -2.903534027771177]],
    headline: "On Styblinski–Tang HRLA and OLA are alike; ULA never leaves the start's well.",
    compare:
      "On Styblinski–Tang, HRLA and OLA are alike and ULA never leaves the start's well: the way out is a barrier of 25 per coordinate, crossed by a large kick, and at a = 0.15 OLA's and HRLA's kicks on the position are large while ULA's position moves only through its velocity, whose spread does not depend on a.",
    measured: { hrla: [0.2, 0.43, 0.65], ula: [0, 0, 0], ola: [0.2, 0.43, 0.66] },
  },
  "double-well": {
    label: "Double well",
    formula: "U(x) = (x₁² − 1)² + (x₂² − 1)²",
    about: "four global minima, U* = 0 at (±1, ±1), a hill of height 2 at the origin",
    view: { cx: 0, cy: 0, half: 2 },
    start: { cx: 0, cy: 0, spread: 0.2 },
    a: 4,
    h: 0.01,
    eps: 0.1,
    minimisers: [
      [1, 1],
      [-1, 1],
      [-1, -1],
      [1, -1],
    ],
    headline: "The double well favours no one: every sampler slides into a global minimum at once.",
    compare:
      "The double well favours no one: the start sits on the hill between four equally deep minima, every sampler slides into one at once, and all three level off where their law exp(−aU) puts them: within ε of U* about 96% of the time for the best of 10.",
    measured: { hrla: [0.96, 0.95, 0.96], ula: [0.96, 0.96, 0.97], ola: [0.97, 0.98, 0.96] },
  },
  quadratic: {
    label: "Quadratic bowl",
    formula: "U(x) = |x|² / 2",
    about: "one minimum, U* = 0 at the origin; the density exp(−aU) is the Gaussian N(0, I/a), the exact case",
    view: { cx: 0, cy: 0, half: 4 },
    start: { cx: 3, cy: 3, spread: 0.5 },
    a: 1,
    h: 0.01,
    eps: 0.1,
    minimisers: [[0, 0]],
    headline: "In the bowl all three reach the same Gaussian; ULA slides down more slowly.",
    compare:
      "The bowl has no trap: all three end in the same Gaussian N(0, I/a). ULA arrives later: it feels the slope only through its velocity, pulled by γ = a/b = 0.1 of the gradient against friction 1, so it slides down about ten times more slowly than OLA and HRLA.",
    measured: { hrla: [0.6, 0.64, 0.65], ula: [0.04, 0.21, 0.6], ola: [0.68, 0.62, 0.62] },
  },
};

/** The paper's claim and this project's measurement of it, for compare mode. */
export const PAPER_AND_MEASUREMENT =
  "The paper reports HRLA ahead of both baselines on 10-dimensional Rastrigin. This project's reproduction (E2 in docs/REPRODUCTION.md: d = 10, a = 2 to 5, h = 0.01, start N(3·1, 10 I), 100 runs each) confirms HRLA well ahead of ULA, but finds HRLA and OLA indistinguishable: with the paper's α = β = 1, b = 10 and h = 0.01, HRLA's position update is OLA's plus a small velocity term, and both keep the same law exp(−aU). This page runs the same kernels in 2-D from a tight start, where, as above, the ranking depends on the landscape.";
