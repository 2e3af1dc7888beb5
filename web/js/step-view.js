// The step laid bare where the eye is: a magnified loupe on the main
// picture beside the chosen chain (one per sampler in compare mode, all at
// one magnification), building the step in stages: the frozen gradient's
// push, the velocity's carry, the mean, the exact Gaussian, the draw. The
// stage is state, not a timer's side effect: `stageAt` maps the time since
// the step to a stage, and a caller may hold any stage (the tests do;
// reduced motion holds the last).

import { COLOURS, arrow, dot, num, reachOf, tag as label } from "./anatomy.js";

/** The stages, in the order the loupe builds them. */
export const STAGES = ["gradient", "momentum", "mean", "gaussian", "draw"];
/** What each stage adds, as the loupe's caption says it. */
const WORDS = ["gradient's push", "velocity's carry", "the mean", "exact Gaussian", "the draw"];
/** Each stage's colour (the caption's, and its part's). */
const STAGE_COLOURS = [COLOURS.gradient, COLOURS.velocity, COLOURS.mean, COLOURS.mean, COLOURS.draw];
/** Milliseconds per stage: long enough to read its caption. */
export const STAGE_MS = 900;
/** Share of a stage spent growing its part; the rest holds it still. */
const GROW = 0.5;

/**
 * The stage shown `elapsed` ms after the step: { stage (index into
 * STAGES), progress (0 to 1, how much of its part is drawn), settled
 * (the last stage, complete) }.
 */
export function stageAt(elapsed) {
  const k = Math.floor(Math.max(0, elapsed) / STAGE_MS);
  if (k >= STAGES.length) return { stage: STAGES.length - 1, progress: 1, settled: true };
  return { stage: k, progress: Math.min(1, (elapsed - k * STAGE_MS) / (GROW * STAGE_MS)), settled: false };
}

/** The stage `index` complete and held. */
export const held = (index) => ({ stage: index, progress: 1, settled: index === STAGES.length - 1 });

/** The one reach (units from the mean) that holds every part's step: one magnification for all. */
export const sharedReach = (parts) => Math.max(...parts.map((p) => reachOf(p.law, p.draw)));

/**
 * Where the loupes go on the picture's plot area, in CSS pixels: one, in
 * the corner away from its chain; several, in a row along the edge away
 * from the chains. Returns [[x, y, side]].
 */
export function loupeBoxes(frame, anchors) {
  const gap = 6;
  const n = anchors.length;
  const midX = frame.left + frame.width / 2;
  const midY = frame.top + frame.height / 2;
  const meanY = anchors.reduce((s, a) => s + a[1], 0) / n;
  if (n === 1) {
    const side = Math.round(0.5 * Math.min(frame.width, frame.height));
    const [ax, ay] = anchors[0];
    const x = ax > midX ? frame.left + gap : frame.left + frame.width - gap - side;
    const y = ay > midY ? frame.top + gap : frame.top + frame.height - gap - side;
    return [[x, y, side]];
  }
  const side = Math.floor(Math.min((frame.width - (n + 1) * gap) / n, 0.46 * frame.height));
  const y = meanY > midY ? frame.top + gap : frame.top + frame.height - gap - side;
  const spare = frame.width - n * side - (n + 1) * gap;
  return anchors.map((_, k) => [frame.left + gap + spare / 2 + k * (side + gap), y, side]);
}

/** The point of box [x, y, side] nearest (px, py): where the leader line meets it. */
function nearestOnBox([x, y, side], px, py) {
  return [Math.min(x + side, Math.max(x, px)), Math.min(y + side, Math.max(y, py))];
}

/**
 * Draws the loupes on `canvas` (the picture's overlay) at `shown` (see
 * stageAt). `parts`: [{ label, colour, law, draw }]. Returns the geometry,
 * for the page's readers: { magnification, loupes: [{ box, scale,
 * start, mean, draw (CSS pixels on the canvas) }] }.
 */
export function drawStepView(canvas, frame, dpr, parts, shown) {
  const ctx = canvas.getContext("2d");
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, frame.size, frame.size);
  if (parts.length === 0) return { magnification: NaN, loupes: [] };
  const anchors = parts.map((p) => [frame.px(p.draw[0]), frame.py(p.draw[1])]);
  const boxes = loupeBoxes(frame, anchors);
  const reach = sharedReach(parts);
  const inner = Math.min(...boxes.map((b) => b[2])) / 2 - 20;
  const scale = inner / reach;
  const magnification = scale / (frame.width / (frame.x1 - frame.x0));
  const loupes = parts.map((part, k) => drawLoupe(ctx, boxes[k], anchors[k], part, scale, magnification, shown));
  return { magnification, loupes };
}

function drawLoupe(ctx, box, anchor, part, scale, magnification, { stage, progress }) {
  const [bx, by, side] = box;
  const { law, draw } = part;
  const amount = (k) => (stage > k ? 1 : stage === k ? progress : 0);
  // The leader: from the chain's dot to the loupe.
  const [lx, ly] = nearestOnBox(box, anchor[0], anchor[1]);
  ctx.setLineDash([4, 3]);
  for (const [colour, width] of [
    ["rgba(0, 0, 0, 0.7)", 3],
    [part.colour, 1.2],
  ]) {
    ctx.strokeStyle = colour;
    ctx.lineWidth = width;
    ctx.beginPath();
    ctx.moveTo(anchor[0], anchor[1]);
    ctx.lineTo(lx, ly);
    ctx.stroke();
  }
  ctx.setLineDash([]);
  ctx.save();
  ctx.beginPath();
  ctx.rect(bx, by, side, side);
  ctx.fillStyle = "rgba(12, 14, 18, 0.94)";
  ctx.fill();
  ctx.lineWidth = 1.5;
  ctx.strokeStyle = part.colour;
  ctx.stroke();
  ctx.clip();
  const cx = bx + side / 2;
  const cy = by + side / 2;
  const mid = law.mean;
  const px = (v) => cx + (v - mid[0]) * scale;
  const py = (v) => cy - (v - mid[1]) * scale;
  const start = [px(law.x[0]), py(law.x[1])];
  const pushed = [px(law.x[0] + law.pushG[0]), py(law.x[1] + law.pushG[1])];
  const mean = [px(mid[0]), py(mid[1])];
  const drawn = [px(draw[0]), py(draw[1])];
  const along = (a, b, t) => [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
  const sd = Math.sqrt(law.moments[0].varX);
  // Points closer than a label's height share one label: the latest
  // stage's (a step far smaller than the loupe, ULA's at one
  // magnification, would otherwise be a knot of words).
  const shown = [];
  const labels = [
    ["draw", drawn, COLOURS.draw, amount(4) === 1],
    ["mean", mean, COLOURS.mean, amount(2) > 0],
    ["x", start, "#ffffff", true],
  ].filter(([, p, , on]) => on && !shown.some((q) => Math.hypot(p[0] - q[0], p[1] - q[1]) < 12) && shown.push(p));
  const tag = (text) => {
    const l = labels.find((k) => k[0] === text);
    if (l) label(ctx, text, l[1][0], l[1][1], l[2], bx + side);
  };
  if (amount(3) > 0) {
    for (const k of [2, 1]) {
      ctx.beginPath();
      // A Gaussian below a pixel is still marked: its size is said in words.
      ctx.arc(mean[0], mean[1], Math.max(0.75, k * sd * scale * amount(3)), 0, 2 * Math.PI);
      ctx.fillStyle = COLOURS.gauss;
      ctx.fill();
      ctx.strokeStyle = "rgba(255, 209, 102, 0.7)";
      ctx.lineWidth = 1;
      ctx.stroke();
    }
  }
  dot(ctx, start[0], start[1], 4, "#ffffff");
  tag("x");
  if (amount(0) > 0) {
    const tip = along(start, pushed, amount(0));
    arrow(ctx, start[0], start[1], tip[0], tip[1], COLOURS.gradient);
  }
  if (amount(1) > 0) {
    const tip = along(pushed, mean, amount(1));
    arrow(ctx, pushed[0], pushed[1], tip[0], tip[1], COLOURS.velocity);
  }
  if (amount(2) > 0) {
    ctx.globalAlpha = amount(2);
    ctx.strokeStyle = COLOURS.mean;
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(mean[0] - 6, mean[1]);
    ctx.lineTo(mean[0] + 6, mean[1]);
    ctx.moveTo(mean[0], mean[1] - 6);
    ctx.lineTo(mean[0], mean[1] + 6);
    ctx.stroke();
    tag("mean");
    ctx.globalAlpha = 1;
  }
  if (amount(4) > 0) {
    const tip = along(mean, drawn, amount(4));
    ctx.setLineDash([3, 3]);
    ctx.strokeStyle = COLOURS.draw;
    ctx.lineWidth = 1.2;
    ctx.beginPath();
    ctx.moveTo(mean[0], mean[1]);
    ctx.lineTo(tip[0], tip[1]);
    ctx.stroke();
    ctx.setLineDash([]);
    if (amount(4) === 1) {
      dot(ctx, drawn[0], drawn[1], 4.5, COLOURS.draw);
      tag("draw");
    }
  }
  // A step that the shared magnification leaves a few pixels wide says so.
  const own = reachOf(law, draw) * scale;
  if (own < 8) {
    ctx.font = "10px system-ui, sans-serif";
    ctx.textAlign = "center";
    ctx.textBaseline = "bottom";
    ctx.fillStyle = "#9aa3b2";
    ctx.fillText(`whole step: ${own < 1 ? "< 1 px" : `${own.toFixed(0)} px`}`, cx, by + side - 20);
  }
  // Title and caption, on bands of their own.
  ctx.fillStyle = "rgba(12, 14, 18, 0.85)";
  ctx.fillRect(bx, by, side, 16);
  ctx.fillRect(bx, by + side - 16, side, 16);
  ctx.font = "11px system-ui, sans-serif";
  ctx.textBaseline = "middle";
  ctx.textAlign = "left";
  ctx.fillStyle = part.colour;
  const title = `${part.label} ×${magnificationText(magnification)}`;
  ctx.fillText(title, bx + 5, by + 8.5);
  const sigma = `σ ${num(sd)}`;
  ctx.textAlign = "right";
  ctx.fillStyle = "#9aa3b2";
  if (ctx.measureText(title).width + ctx.measureText(sigma).width + 16 < side) ctx.fillText(sigma, bx + side - 5, by + 8.5);
  ctx.textAlign = "left";
  ctx.fillStyle = STAGE_COLOURS[stage];
  const words = stage === 1 && !part.hasVelocity ? "no velocity" : WORDS[stage];
  ctx.fillText(`${stage + 1}/${STAGES.length} ${words}`, bx + 5, by + side - 7.5);
  ctx.restore();
  return { box, scale, start, mean, draw: drawn };
}

/** 11 -> "11", 2840 -> "2.84k". */
export function magnificationText(m) {
  return m >= 1e3 ? `${+(m / 1e3).toPrecision(3)}k` : String(+m.toPrecision(2));
}
