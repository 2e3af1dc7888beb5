// One step of one chain, laid bare: the gradient frozen at the chain's
// position, the velocity's carry, the mean of the next position, the exact
// Gaussian it is drawn from (in the position plane, and in the plane of
// position and velocity of the first coordinate, where HRLA's closed-form
// covariance couples the two), and the draw. Everything shown is the
// kernel's own: the law comes from the wrapper's `nextStep`, the draw is
// the step the run then took.

import { fitCanvas } from "./plots.js";

/** Offsets in the wrapper's `nextStep` array. */
const N = { A: 0, X: 1, Y: 3, G: 5, M: 7, PUSH_G: 17, PUSH_Y: 19 };
/** Offsets within one coordinate's moments. */
const M = { MEAN_X: 0, MEAN_Y: 1, VAR_X: 2, COV: 3, VAR_Y: 4 };

export const COLOURS = { gradient: "#ff9f43", velocity: "#4fd1ff", mean: "#ffd166", gauss: "rgba(255, 209, 102, 0.16)", draw: "#ff5a36" };

/** The wrapper's flat `nextStep` array as named parts. */
export function readNextStep(a) {
  const pair = (o) => [a[o], a[o + 1]];
  const moments = [0, 1].map((i) => {
    const o = N.M + 5 * i;
    return { meanX: a[o + M.MEAN_X], meanY: a[o + M.MEAN_Y], varX: a[o + M.VAR_X], cov: a[o + M.COV], varY: a[o + M.VAR_Y] };
  });
  return {
    a: a[N.A],
    x: pair(N.X),
    y: pair(N.Y),
    g: pair(N.G),
    moments,
    mean: moments.map((m) => m.meanX),
    pushG: pair(N.PUSH_G),
    pushY: pair(N.PUSH_Y),
  };
}

/** A number in at most 8 characters. */
export function num(v) {
  if (v === 0) return "0";
  const a = Math.abs(v);
  return a >= 1e4 || a < 1e-3 ? v.toExponential(2) : String(+v.toPrecision(3));
}

const vec = (v) => `(${num(v[0])}, ${num(v[1])})`;

export function arrow(ctx, x0, y0, x1, y1, colour) {
  const len = Math.hypot(x1 - x0, y1 - y0);
  ctx.strokeStyle = colour;
  ctx.fillStyle = colour;
  ctx.lineWidth = 2;
  ctx.beginPath();
  ctx.moveTo(x0, y0);
  ctx.lineTo(x1, y1);
  ctx.stroke();
  if (len < 4) return;
  const ux = (x1 - x0) / len;
  const uy = (y1 - y0) / len;
  const head = Math.min(8, len / 2);
  ctx.beginPath();
  ctx.moveTo(x1, y1);
  ctx.lineTo(x1 - head * ux - (head / 2) * uy, y1 - head * uy + (head / 2) * ux);
  ctx.lineTo(x1 - head * ux + (head / 2) * uy, y1 - head * uy - (head / 2) * ux);
  ctx.fill();
}

export function dot(ctx, x, y, r, fill, stroke = "#000") {
  ctx.beginPath();
  ctx.arc(x, y, r, 0, 2 * Math.PI);
  ctx.lineWidth = 1.5;
  ctx.strokeStyle = stroke;
  ctx.stroke();
  ctx.fillStyle = fill;
  ctx.fill();
}

/** A label above and right of (x, y), moved left where it would pass `right` (a box's edge). */
export function tag(ctx, text, x, y, colour, right = Infinity) {
  ctx.font = "11px system-ui, sans-serif";
  const at = Math.min(x + 5, right - 3 - ctx.measureText(text).width);
  ctx.textAlign = "left";
  ctx.textBaseline = "bottom";
  ctx.lineWidth = 3;
  ctx.strokeStyle = "rgba(0, 0, 0, 0.8)";
  ctx.strokeText(text, at, y - 3);
  ctx.fillStyle = colour;
  ctx.fillText(text, at, y - 3);
}

/**
 * How far the step's parts lie from its mean (start, gradient's push,
 * draw, 2.2 σ of the Gaussian): the radius a picture of the step must
 * hold. In compare mode the largest of the samplers' sets one
 * magnification for all, so that their sizes can be compared.
 */
export function reachOf(law, draw) {
  const mid = law.mean;
  const pushed = [law.x[0] + law.pushG[0], law.x[1] + law.pushG[1]];
  const far = (p) => Math.hypot(p[0] - mid[0], p[1] - mid[1]);
  return Math.max(far(law.x), far(pushed), far(draw), 2.2 * Math.sqrt(law.moments[0].varX), 1e-300);
}

/**
 * The position plane around the step, magnified so that it fills the inset:
 * the start x, the gradient's push, the velocity's push, the mean, the
 * Gaussian's 1σ and 2σ circles (the position's covariance is σ² I: the
 * coordinates are independent given the state), and the draw, with `reach`
 * units from the mean filling the inset. Returns the
 * geometry, for the readers of the page: { scale (px per unit), moved (px
 * from start to draw), sigmaPx }.
 */
export function drawPositionInset(canvas, law, draw, reach = reachOf(law, draw)) {
  const [w, h] = fitCanvas(canvas);
  const ctx = canvas.getContext("2d");
  ctx.fillStyle = "#0c0e12";
  ctx.fillRect(0, 0, w, h);
  const sd = Math.sqrt(law.moments[0].varX);
  const mid = law.mean;
  const pushed = [law.x[0] + law.pushG[0], law.x[1] + law.pushG[1]];
  const scale = (Math.min(w, h) / 2 - 16) / reach;
  const px = (v) => w / 2 + (v - mid[0]) * scale;
  const py = (v) => h / 2 - (v - mid[1]) * scale;
  // The Gaussian: 2σ and 1σ discs.
  for (const k of [2, 1]) {
    ctx.beginPath();
    ctx.arc(px(mid[0]), py(mid[1]), k * sd * scale, 0, 2 * Math.PI);
    ctx.fillStyle = COLOURS.gauss;
    ctx.fill();
    ctx.strokeStyle = "rgba(255, 209, 102, 0.6)";
    ctx.lineWidth = 1;
    ctx.stroke();
  }
  arrow(ctx, px(law.x[0]), py(law.x[1]), px(pushed[0]), py(pushed[1]), COLOURS.gradient);
  arrow(ctx, px(pushed[0]), py(pushed[1]), px(mid[0]), py(mid[1]), COLOURS.velocity);
  ctx.setLineDash([3, 3]);
  ctx.strokeStyle = COLOURS.draw;
  ctx.lineWidth = 1;
  ctx.beginPath();
  ctx.moveTo(px(mid[0]), py(mid[1]));
  ctx.lineTo(px(draw[0]), py(draw[1]));
  ctx.stroke();
  ctx.setLineDash([]);
  dot(ctx, px(law.x[0]), py(law.x[1]), 4.5, "#ffffff");
  tag(ctx, "x", px(law.x[0]), py(law.x[1]), "#ffffff", w);
  ctx.strokeStyle = COLOURS.mean;
  ctx.lineWidth = 2;
  ctx.beginPath();
  ctx.moveTo(px(mid[0]) - 6, py(mid[1]));
  ctx.lineTo(px(mid[0]) + 6, py(mid[1]));
  ctx.moveTo(px(mid[0]), py(mid[1]) - 6);
  ctx.lineTo(px(mid[0]), py(mid[1]) + 6);
  ctx.stroke();
  tag(ctx, "mean", px(mid[0]), py(mid[1]), COLOURS.mean, w);
  dot(ctx, px(draw[0]), py(draw[1]), 4.5, COLOURS.draw);
  tag(ctx, "draw", px(draw[0]), py(draw[1]), COLOURS.draw, w);
  // A scale bar of a round length.
  const unit = 10 ** Math.floor(Math.log10(reach));
  const bar = unit * scale;
  ctx.strokeStyle = "#9aa3b2";
  ctx.fillStyle = "#9aa3b2";
  ctx.lineWidth = 1;
  ctx.beginPath();
  ctx.moveTo(8, h - 8);
  ctx.lineTo(8 + bar, h - 8);
  ctx.stroke();
  ctx.font = "10px system-ui, sans-serif";
  ctx.textAlign = "left";
  ctx.textBaseline = "bottom";
  ctx.fillText(num(unit), 8, h - 10);
  return { scale, moved: Math.hypot(draw[0] - law.x[0], draw[1] - law.x[1]) * scale, sigmaPx: sd * scale };
}

/**
 * The plane of the first coordinate's position and velocity: the start,
 * the mean, the exact joint Gaussian of (x₁′, y₁′) (1σ and 2σ ellipses of
 * its covariance) and the draw. OLA has no velocity: its law is a segment.
 */
export function drawPhaseInset(canvas, law, draw) {
  const [w, h] = fitCanvas(canvas);
  const ctx = canvas.getContext("2d");
  ctx.fillStyle = "#0c0e12";
  ctx.fillRect(0, 0, w, h);
  const m = law.moments[0];
  const sx = Math.sqrt(m.varX);
  const sy = Math.sqrt(m.varY);
  const start = [law.x[0], law.y[0]];
  const mean = [m.meanX, m.meanY];
  const reachX = Math.max(Math.abs(start[0] - mean[0]), Math.abs(draw[0] - mean[0]), 2.2 * sx, 1e-300);
  const reachY = sy > 0 ? Math.max(Math.abs(start[1] - mean[1]), Math.abs(draw[1] - mean[1]), 2.2 * sy) : 1;
  const px = (v) => w / 2 + ((v - mean[0]) / reachX) * (w / 2 - 12);
  const py = (v) => h / 2 - ((v - mean[1]) / reachY) * (h / 2 - 12);
  ctx.strokeStyle = "#2b303b";
  ctx.lineWidth = 1;
  ctx.beginPath();
  ctx.moveTo(0, h / 2);
  ctx.lineTo(w, h / 2);
  ctx.moveTo(w / 2, 0);
  ctx.lineTo(w / 2, h);
  ctx.stroke();
  // Cholesky of [[varX, cov], [cov, varY]]: the ellipse is mean + L (cos t, sin t) k.
  const l11 = sx;
  const l21 = sx > 0 ? m.cov / sx : 0;
  const l22 = Math.sqrt(Math.max(0, m.varY - l21 * l21));
  for (const k of [2, 1]) {
    ctx.beginPath();
    for (let i = 0; i <= 96; i++) {
      const t = (2 * Math.PI * i) / 96;
      const u = k * Math.cos(t);
      const v = k * Math.sin(t);
      const x = px(mean[0] + l11 * u);
      const y = py(mean[1] + l21 * u + l22 * v);
      if (i === 0) ctx.moveTo(x, y);
      else ctx.lineTo(x, y);
    }
    ctx.fillStyle = COLOURS.gauss;
    ctx.fill();
    ctx.strokeStyle = "rgba(255, 209, 102, 0.6)";
    ctx.stroke();
  }
  ctx.setLineDash([3, 3]);
  ctx.strokeStyle = "#9aa3b2";
  ctx.beginPath();
  ctx.moveTo(px(start[0]), py(start[1]));
  ctx.lineTo(px(mean[0]), py(mean[1]));
  ctx.stroke();
  ctx.setLineDash([]);
  dot(ctx, px(start[0]), py(start[1]), 4, "#ffffff");
  tag(ctx, "(x₁, y₁)", px(start[0]), py(start[1]), "#ffffff", w);
  dot(ctx, px(mean[0]), py(mean[1]), 3, COLOURS.mean);
  dot(ctx, px(draw[0]), py(draw[1]), 4, COLOURS.draw);
  tag(ctx, "draw", px(draw[0]), py(draw[1]), COLOURS.draw, w);
  ctx.font = "10px system-ui, sans-serif";
  ctx.fillStyle = "#9aa3b2";
  ctx.textAlign = "right";
  ctx.textBaseline = "bottom";
  ctx.fillText("x₁ →", w - 4, h / 2 - 2);
  ctx.textAlign = "left";
  ctx.textBaseline = "top";
  ctx.fillText("y₁ ↑", w / 2 + 4, 3);
  // Its shape (the tilt) is what this inset shows; sizes compare in the position inset above.
  ctx.textBaseline = "bottom";
  ctx.fillText("axes scaled to this law", 4, h - 2);
}

/** The correlation of the new x₁ and y₁ under the step's law (0 without a velocity). */
export function correlation(law) {
  const m = law.moments[0];
  return m.varY > 0 ? m.cov / Math.sqrt(m.varX * m.varY) : 0;
}

/** The five parts of a step in words, with the kernel's numbers. */
export function describe(sampler, law, draw) {
  const sd = Math.sqrt(law.moments[0].varX);
  const z = [0, 1].map((i) => (draw[i] - law.mean[i]) / sd);
  const rho = correlation(law);
  const velocity =
    sampler === "ola"
      ? "<b>momentum</b>: none, OLA has no velocity."
      : `<b>momentum</b>: the velocity y = ${vec(law.y)} carries the mean by ${vec(law.pushY)} (blue).`;
  // The words say only what the (x₁, y₁) picture below shows: a tilt of
  // its ellipse, or none worth the name.
  const shape =
    Math.abs(rho) < 0.1
      ? `nearly uncorrelated (ρ = ${num(rho)}): the ellipse below barely tilts`
      : `correlated, ρ = ${num(rho)}: the ellipse below tilts`;
  const gauss = {
    hrla: `<b>the exact Gaussian</b> around it, σ = ${num(sd)} per coordinate, with noise of its own on the position; in the (x₁, y₁) plane, position and velocity are ${shape}.`,
    ula: `<b>the exact Gaussian</b> around it, σ = ${num(sd)} per coordinate, all of it through the velocity: ULA has no noise of its own on the position; in the (x₁, y₁) plane, position and velocity are ${shape}.`,
    ola: `<b>Euler's Gaussian</b> around it, σ = √(2h/a) = ${num(sd)} per coordinate, nothing on a velocity.`,
  }[sampler];
  return [
    `<b>gradient, frozen</b> at x = ${vec(law.x)}: ∇U = ${vec(law.g)}, held over the whole step; it pushes the mean by ${vec(law.pushG)} (orange).`,
    velocity,
    `<b>mean</b> of the next position: ${vec(law.mean)} (cross).`,
    gauss,
    `<b>the draw</b>: ${vec(draw)}, z = ${vec(z)} standard deviations from the mean (red).`,
  ];
}
