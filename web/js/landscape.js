// The landscape panel: the background (U on a log colour scale, or the
// density exp(-a U) at the current a, also on a log scale) with contour
// lines, axes, the global minimisers and a colour bar, drawn when the view,
// the size or a changes. The chains over it are chains.js's.

import { VIRIDIS, viridisCss } from "./colormap.js";
import { fitCanvas } from "./plots.js";

/** Margins of the plot area inside the canvas, in CSS pixels. */
const MARGIN = { left: 34, right: 10, top: 10, bottom: 26 };
/** Colour levels between contour lines. */
const LEVELS = 12;
/** One colour per run in compare mode (and the single run's is the first). */
export const RUN_COLOURS = ["#ffffff", "#4fd1ff", "#ff7ad9"];
/**
 * Decades of the density's log scale: below 1e-6 of its peak the density
 * has the darkest colour. On a linear scale the wells next to the global
 * one, which hold 1e-2..1e-4 of its peak density at a = 4, would all have
 * the floor's colour.
 */
export const DENSITY_DECADES = 6;

/** Maps the square view [cx - half, cx + half] x [cy - half, cy + half] to the canvas' plot area. */
export class Frame {
  constructor(cssSize, view) {
    this.size = cssSize;
    this.view = view;
    this.x0 = view.cx - view.half;
    this.x1 = view.cx + view.half;
    this.y0 = view.cy - view.half;
    this.y1 = view.cy + view.half;
    this.left = MARGIN.left;
    this.top = MARGIN.top;
    this.width = cssSize - MARGIN.left - MARGIN.right;
    this.height = cssSize - MARGIN.top - MARGIN.bottom;
  }
  px(x) {
    return this.left + ((x - this.x0) / (this.x1 - this.x0)) * this.width;
  }
  py(y) {
    return this.top + ((this.y1 - y) / (this.y1 - this.y0)) * this.height;
  }
}

/**
 * The colour scale of the background: t in [0, 1] for each grid value.
 * "u": log(1 + U - U*) over the view's range, so that low basins get most
 * of the colours; "density": exp(-a (U - min U)) relative to the view's
 * mode, on a log scale over DENSITY_DECADES decades. Returns
 * { t: Float32Array, ticks: [[t, label]], title }.
 */
export function colourScale(grid, mode, a, minimum) {
  const t = new Float32Array(grid.length);
  let lo = Infinity;
  let hi = -Infinity;
  for (const u of grid) {
    if (u < lo) lo = u;
    if (u > hi) hi = u;
  }
  if (mode === "density") {
    // log10 of the density relative to its peak is -a (U - lo) / ln 10.
    const perUnit = a / (Math.LN10 * DENSITY_DECADES);
    for (let k = 0; k < grid.length; k++) t[k] = Math.max(0, 1 - (grid[k] - lo) * perUnit);
    const ticks = [];
    for (let d = 0; d <= DENSITY_DECADES; d++) ticks.push([1 - d / DENSITY_DECADES, d === 0 ? "1" : `1e−${d}`]);
    return { t, ticks, title: `density exp(−aU) / max (log scale), a = ${+a.toPrecision(3)}` };
  }
  const scale = 1 / Math.log1p(Math.max(hi - minimum, 1e-12));
  for (let k = 0; k < grid.length; k++) t[k] = Math.min(1, Math.max(0, Math.log1p(grid[k] - minimum) * scale));
  const ticks = [];
  for (const d of [0, 0.1, 0.3, 1, 3, 10, 30, 100, 300, 1000, 3000]) {
    const v = Math.log1p(d) * scale;
    if (v <= 1) ticks.push([v, String(d)]);
  }
  return { t, ticks, title: "U − U* (log scale)" };
}

/**
 * The background: `scale.t` over the plot area (a w x h grid, row by row
 * from the top, one value per device pixel unless the area is larger than
 * the grid), contour lines where the colour level changes,
 * axes, and a cross at each global minimiser. No shading: a colour means
 * one value everywhere.
 */
export function drawLandscape(canvas, frame, dpr, scale, w, h, minimisers) {
  const ctx = canvas.getContext("2d");
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.fillStyle = "#171a21";
  ctx.fillRect(0, 0, canvas.width, canvas.height);
  const t = scale.t;
  const image = ctx.createImageData(w, h);
  const data = image.data;
  for (let j = 0; j < h; j++) {
    for (let i = 0; i < w; i++) {
      const k = j * w + i;
      if (Number.isNaN(t[k])) {
        // Where U is not finite (a visitor's formula): grey hatching.
        const grey = (i + j) % 8 < 2 ? 150 : 90;
        data.fill(grey, 4 * k, 4 * k + 3);
        data[4 * k + 3] = 255;
        continue;
      }
      const level = Math.floor(t[k] * LEVELS);
      // Neighbours on both sides: a contour is placed the same way under
      // any mirror of the landscape.
      const edge =
        (i + 1 < w && Math.floor(t[k + 1] * LEVELS) !== level) ||
        (i > 0 && Math.floor(t[k - 1] * LEVELS) !== level) ||
        (j + 1 < h && Math.floor(t[k + w] * LEVELS) !== level) ||
        (j > 0 && Math.floor(t[k - w] * LEVELS) !== level);
      const c = 3 * Math.round(255 * t[k]);
      const dim = edge ? 0.6 : 1;
      data[4 * k] = VIRIDIS[c] * dim;
      data[4 * k + 1] = VIRIDIS[c + 1] * dim;
      data[4 * k + 2] = VIRIDIS[c + 2] * dim;
      data[4 * k + 3] = 255;
    }
  }
  const x0 = Math.round(frame.left * dpr);
  const y0 = Math.round(frame.top * dpr);
  const width = Math.round(frame.width * dpr);
  const height = Math.round(frame.height * dpr);
  if (w === width && h === height) {
    ctx.putImageData(image, x0, y0);
  } else {
    // A grid coarser than the screen's pixels (very large canvases): scaled.
    const off = document.createElement("canvas");
    off.width = w;
    off.height = h;
    off.getContext("2d").putImageData(image, 0, 0);
    ctx.drawImage(off, x0, y0, width, height);
  }
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  drawAxes(ctx, frame, getComputedStyle(canvas).color);
  for (const [mx, my] of minimisers) {
    const cx = frame.px(mx);
    const cy = frame.py(my);
    const cross = () => {
      ctx.moveTo(cx - 7, cy);
      ctx.lineTo(cx + 7, cy);
      ctx.moveTo(cx, cy - 7);
      ctx.lineTo(cx, cy + 7);
    };
    strokeOutlined(ctx, cross, "#fff", 1.5, 3.5);
  }
  if (minimisers.length) {
    const [mx, my] = minimisers[0];
    label(ctx, "x*", frame.px(mx) + 6, frame.py(my) - 4, "left", "bottom");
  }
}

/**
 * Strokes the path `trace` adds twice: black, `outline` wide, then `colour`,
 * `width` wide, over it; the black edge keeps a mark seen on every colour
 * of the background.
 */
export function strokeOutlined(ctx, trace, colour, width, outline) {
  for (const [c, w] of [
    ["#000", outline],
    [colour, width],
  ]) {
    ctx.strokeStyle = c;
    ctx.lineWidth = w;
    ctx.beginPath();
    trace();
    ctx.stroke();
  }
}

/** The colour bar: the scale's colours bottom to top, with its ticks and title. */
export function drawColourBar(canvas, scale) {
  const [w, h] = fitCanvas(canvas);
  const ctx = canvas.getContext("2d");
  ctx.clearRect(0, 0, w, h);
  // The title runs up the left edge, the ticks' labels right of the bar.
  const bar = { left: 15, top: 8, width: 10, height: h - 16 };
  for (let y = 0; y < bar.height; y++) {
    ctx.fillStyle = viridisCss(1 - y / (bar.height - 1));
    ctx.fillRect(bar.left, bar.top + y, bar.width, 1);
  }
  const colour = getComputedStyle(canvas).color;
  ctx.strokeStyle = colour;
  ctx.fillStyle = colour;
  ctx.lineWidth = 1;
  ctx.strokeRect(bar.left - 0.5, bar.top - 0.5, bar.width + 1, bar.height + 1);
  ctx.font = "10px system-ui, sans-serif";
  ctx.textAlign = "left";
  ctx.textBaseline = "middle";
  ctx.save();
  ctx.translate(7, bar.top + bar.height / 2);
  ctx.rotate(-Math.PI / 2);
  ctx.textAlign = "center";
  ctx.fillText(scale.title, 0, 0, bar.height);
  ctx.restore();
  const drawn = [];
  for (const [t, text] of scale.ticks) {
    const y = Math.round(bar.top + (1 - t) * bar.height) + 0.5;
    // Labels closer than a line of text to one drawn would overlap: keep
    // the first (ticks come in either order: up in U, down in density).
    if (drawn.some((d) => Math.abs(d.y - y) < 12)) continue;
    drawn.push({ y, text });
    ctx.beginPath();
    ctx.moveTo(bar.left + bar.width, y);
    ctx.lineTo(bar.left + bar.width + 4, y);
    ctx.stroke();
    ctx.fillText(text, bar.left + bar.width + 6, y, w - (bar.left + bar.width + 7));
  }
  canvas.setAttribute("aria-label", `colour bar: ${scale.title}, ticks ${scale.ticks.map((k) => k[1]).join(", ")}`);
  // For the tests: what the bar shows.
  canvas.dataset.title = scale.title;
  canvas.dataset.ticks = drawn.map((d) => d.text).join(", ");
}

function label(ctx, text, x, y, align, baseline) {
  ctx.font = "13px system-ui, sans-serif";
  ctx.lineWidth = 3;
  ctx.strokeStyle = "rgba(0, 0, 0, 0.75)";
  ctx.fillStyle = "#fff";
  ctx.textAlign = align;
  ctx.textBaseline = baseline;
  ctx.strokeText(text, x, y);
  ctx.fillText(text, x, y);
}

/** Ticks at multiples of a round step, about five per axis. */
function ticks(lo, hi) {
  const span = hi - lo;
  const step = [0.5, 1, 2, 5, 10].find((s) => span / s <= 10) ?? 20;
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + 1e-9; v += step) out.push(+v.toFixed(6));
  return out;
}

function drawAxes(ctx, frame, color) {
  ctx.strokeStyle = color;
  ctx.fillStyle = color;
  ctx.lineWidth = 1;
  ctx.font = "11px system-ui, sans-serif";
  ctx.strokeRect(frame.left - 0.5, frame.top - 0.5, frame.width + 1, frame.height + 1);
  const xs = ticks(frame.x0, frame.x1);
  const ys = ticks(frame.y0, frame.y1);
  ctx.beginPath();
  for (const v of xs) {
    ctx.moveTo(frame.px(v), frame.top + frame.height);
    ctx.lineTo(frame.px(v), frame.top + frame.height + 4);
  }
  for (const v of ys) {
    ctx.moveTo(frame.left, frame.py(v));
    ctx.lineTo(frame.left - 4, frame.py(v));
  }
  ctx.stroke();
  ctx.textAlign = "center";
  ctx.textBaseline = "top";
  for (const v of xs) ctx.fillText(String(v), frame.px(v), frame.top + frame.height + 6);
  ctx.textAlign = "right";
  ctx.textBaseline = "middle";
  for (const v of ys) ctx.fillText(String(v), frame.left - 6, frame.py(v));
  label(ctx, "x₁", frame.left + frame.width - 4, frame.top + frame.height - 3, "right", "bottom");
  label(ctx, "x₂", frame.left + 5, frame.top + 4, "left", "top");
}
