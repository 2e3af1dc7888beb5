// A visitor's own landscape: the formula typed for U(x, y) over a square
// box, described as the built-in landscapes are (landscapes.js), with what
// the page cannot know said plainly: its U* is an estimate.

/** What the page starts a visitor's formula from: Himmelblau's function, four global minima at U = 0. */
export const FORMULA_DEFAULT = { text: "(x^2 + y - 11)^2 + (x + y^2 - 7)^2", cx: 0, cy: 0, half: 5 };

/**
 * The landscape entry of a formula: `arg` is the wrapper's potential
 * `{ formula, box }`, `view` the square box { cx, cy, half }, `estimate`
 * the wrapper's { minimum, minimiser } (null when the formula or box is
 * refused).
 */
export function customLandscape(arg, view, estimate) {
  const u = estimate ? +estimate.minimum.toPrecision(6) : NaN;
  return {
    name: "formula",
    arg,
    label: "Your own U(x, y)",
    formula: `U(x, y) = ${arg.formula.trim()}`,
    about: estimate
      ? `your formula over its box; U* is not known: ${u} is the lowest value found on a 201 × 201 grid of the box, refined by gradient descent (a chain may find lower)`
      : "your formula over its box",
    view,
    start: { cx: view.cx, cy: view.cy, spread: view.half / 10 },
    a: 1,
    h: 0.01,
    eps: 0.1,
    minimisers: estimate ? [estimate.minimiser] : [],
    headline: "For a function of yours nothing was measured in advance: compare the curves.",
    compare:
      "For a function of yours nothing was measured in advance: the table above compares the three on this run only. Try a landscape whose small ripples sit on a big bowl (momentum helps ULA), or deep wells far apart (ULA's slow wandering hurts it).",
    measured: null,
  };
}
