// The chains over the landscape, redrawn every frame: their trails, their
// dots and each run's running best. Drawing is the frame's heavy part at
// a thousand chains, and the trails are most of it (forty segments per
// chain): they are drawn newest first up to the frame's budget of
// segments (pace.js's DrawBudget), so that they shorten rather than slow
// the page. The dots, the positions, are never cut.

import { strokeOutlined } from "./landscape.js";
import { trailAges } from "./pace.js";

/** The dots' radius and their dark rim's width, in CSS pixels. */
const DOT = 2.5;
const RIM = 0.75;

/**
 * For each run: its trails (the newest `ages` segments per chain, oldest
 * faintest; consecutive trail points are TRAIL_STRIDE steps apart, so a
 * trail is the chain's path), its chains, and its running best, circled.
 * `runs` is [{ trails, x, n, best: [x0, x1], colour, square }], the first
 * drawn last, on top (HRLA's in compare mode); `square` draws the chains
 * as squares (gradient descent's). `mark`, when given, is a point [x1, x2]
 * ringed (the chain whose step is laid bare). `cap`: trail segments at
 * most, over all runs. Returns { ages, segments } (the trails drawn).
 */
export function drawChains(canvas, frame, dpr, runs, mark = null, cap = Infinity) {
  const ctx = canvas.getContext("2d");
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, frame.size, frame.size);
  ctx.save();
  ctx.beginPath();
  ctx.rect(frame.left, frame.top, frame.width, frame.height);
  ctx.clip();
  // Descent's restarts jump across the picture: no trails for it.
  const trailed = runs.filter((r) => !r.square);
  const available = Math.min(...trailed.map((r) => r.trails.count - 1));
  const ages = trailAges(available, trailed.reduce((s, r) => s + r.n, 0), cap);
  let segments = 0;
  for (const run of [...runs].reverse()) {
    const { trails, n } = run;
    ctx.strokeStyle = run.colour;
    ctx.lineWidth = 1;
    const drawn = run.square ? 0 : ages;
    for (let age = drawn; age >= 1; age--) {
      const older = trails.snapshot(age);
      const newer = trails.snapshot(age - 1);
      ctx.globalAlpha = 0.5 * (1 - (age - 1) / drawn);
      ctx.beginPath();
      for (let c = 0; c < n; c++) {
        const ax = older[2 * c];
        const bx = newer[2 * c];
        if (!(Number.isFinite(ax) && Number.isFinite(bx))) continue;
        ctx.moveTo(frame.px(ax), frame.py(older[2 * c + 1]));
        ctx.lineTo(frame.px(bx), frame.py(newer[2 * c + 1]));
      }
      ctx.stroke();
      segments += n;
    }
    ctx.globalAlpha = 1;
    if (run.square) drawSquares(ctx, frame, run);
    else drawDots(ctx, frame, run);
  }
  for (const run of [...runs].reverse()) {
    const px = frame.px(run.best[0]);
    const py = frame.py(run.best[1]);
    const colour = runs.length > 1 ? run.colour : "#ff5a36";
    strokeOutlined(ctx, () => ctx.arc(px, py, 8, 0, 2 * Math.PI), colour, 1.6, 3);
  }
  if (mark) {
    const px = frame.px(mark[0]);
    const py = frame.py(mark[1]);
    ctx.setLineDash([3, 3]);
    strokeOutlined(ctx, () => ctx.arc(px, py, 12, 0, 2 * Math.PI), "#ffd166", 1.5, 3);
    ctx.setLineDash([]);
  }
  ctx.restore();
  return { ages, segments };
}

/**
 * Every rim, then every fill over them: a dense cluster is a light patch
 * with one dark edge, not a knot of outlines. Each is one filled path (a
 * stroked outline costs more to rasterise than a fill).
 */
function drawDots(ctx, frame, run) {
  for (const [radius, colour] of [
    [DOT + RIM, "rgba(0, 0, 0, 0.5)"],
    [DOT, run.colour],
  ]) {
    ctx.fillStyle = colour;
    ctx.beginPath();
    for (let c = 0; c < run.n; c++) {
      const x = run.x[2 * c];
      const y = run.x[2 * c + 1];
      if (!(Number.isFinite(x) && Number.isFinite(y))) continue;
      const px = frame.px(x);
      const py = frame.py(y);
      ctx.moveTo(px + radius, py);
      ctx.arc(px, py, radius, 0, 2 * Math.PI);
    }
    ctx.fill();
  }
}

function drawSquares(ctx, frame, run) {
  ctx.fillStyle = run.colour;
  ctx.strokeStyle = "rgba(0, 0, 0, 0.5)";
  ctx.lineWidth = 1.5;
  ctx.beginPath();
  for (let c = 0; c < run.n; c++) {
    const x = run.x[2 * c];
    const y = run.x[2 * c + 1];
    if (!(Number.isFinite(x) && Number.isFinite(y))) continue;
    ctx.rect(frame.px(x) - 2.2, frame.py(y) - 2.2, 4.4, 4.4);
  }
  ctx.stroke();
  ctx.fill();
}
