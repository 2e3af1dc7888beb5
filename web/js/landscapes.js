// What the page knows of each landscape beyond the kernel: how to show it
// (view box, formula, every global minimiser to mark) and the settings a
// visitor starts from (a start away from the global basin, a temperature
// at which the search can be watched). The potential itself, U* and the
// pictures' values come from the kernel through the wasm wrapper.

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
  },
  levy: {
    label: "Levy",
    formula: "U(x) = sin² πw₁ + (w₁ − 1)² (1 + 10 sin²(πw₁ + 1)) + (w₂ − 1)² (1 + sin² 2πw₂), w = 1 + (x − 1)/4",
    about: "ridges of local minima; U* = 0 at (1, 1)",
    view: { cx: 0, cy: 0, half: 10 },
    start: { cx: -6, cy: -6, spread: 0.5 },
    a: 1.5,
    h: 0.01,
    eps: 0.5,
    minimisers: [[1, 1]],
  },
  "styblinski-tang": {
    label: "Styblinski–Tang",
    formula: "U(x) = ½ Σ (xᵢ⁴ − 16 xᵢ² + 5 xᵢ)",
    about: "four wells; the deepest, U* = −78.33, at (−2.90, −2.90), the start's well, at (2.75, 2.75), 28.3 higher",
    view: { cx: 0, cy: 0, half: 5 },
    start: { cx: 2.75, cy: 2.75, spread: 0.3 },
    a: 0.3,
    h: 0.01,
    eps: 2,
    minimisers: [[-2.903534027771177, -2.903534027771177]],
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
  },
};
