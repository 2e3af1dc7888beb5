// The 2-D Rastrigin landscape: heat map, contours, axes and the global
// minimum, drawn once per size or view on the background canvas; and the
// chains, their trails and the best point, redrawn every frame on top.

import { VIRIDIS } from "./colormap.js";

/** Margins of the plot area inside the canvas, in CSS pixels. */
const MARGIN = { left: 34, right: 10, top: 10, bottom: 26 };

const TAU = 2 * Math.PI;

/** Rastrigin in the paper's form, for the picture only (the run is in wasm). */
function rastrigin(x, y) {
  return 2 + x * x + y * y - Math.cos(TAU * x) - Math.cos(TAU * y);
}

/** Relief exaggeration of the hill shading, in units of x. */
const RELIEF = 4;
/** Light from the upper left, above the plane (unit vector). */
const LIGHT = (() => {
  const v = [-1, 1, 1.6];
  const n = Math.hypot(...v);
  return v.map((c) => c / n);
})();

/**
 * Brightness factor of the surface z = log(1 + U) lit from the upper left:
 * the quadratic bowl dominates the colours far from the origin, and the
 * shading keeps every local minimum visible there.
 */
function shade(x, y, u) {
  const gx = (RELIEF * (2 * x + TAU * Math.sin(TAU * x))) / (1 + u);
  const gy = (RELIEF * (2 * y + TAU * Math.sin(TAU * y))) / (1 + u);
  const lambert = (-gx * LIGHT[0] - gy * LIGHT[1] + LIGHT[2]) / Math.hypot(gx, gy, 1);
  return Math.min(1.2, Math.max(0.55, 0.35 + 0.65 * (lambert / LIGHT[2])));
}

/** Maps the square view [-half, half]^2 to the canvas' plot area. */
export class Frame {
  constructor(cssSize, half) {
    this.size = cssSize;
    this.half = half;
    this.left = MARGIN.left;
    this.top = MARGIN.top;
    this.width = cssSize - MARGIN.left - MARGIN.right;
    this.height = cssSize - MARGIN.top - MARGIN.bottom;
  }
  px(x) {
    return this.left + ((x + this.half) / (2 * this.half)) * this.width;
  }
  py(y) {
    return this.top + ((this.half - y) / (2 * this.half)) * this.height;
  }
}

/** The heat map of log(1 + U) with contour lines, axes and x* = 0. */
export function drawLandscape(canvas, frame, dpr) {
  const ctx = canvas.getContext("2d");
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.fillStyle = getComputedStyle(canvas).getPropertyValue("--panel") || "#111";
  ctx.fillRect(0, 0, canvas.width, canvas.height);

  // Pixels of the plot area, in device pixels.
  const x0 = Math.round(frame.left * dpr);
  const y0 = Math.round(frame.top * dpr);
  const w = Math.round(frame.width * dpr);
  const h = Math.round(frame.height * dpr);
  const half = frame.half;
  const uMax = rastrigin(half, half) + 2;
  const scale = 1 / Math.log1p(uMax);
  // Contours every 1/12 of the colour range, that is, at geometrically
  // spaced levels of 1 + U: they crowd where U is small.
  const levels = 12;
  const t = new Float32Array(w * h);
  const light = new Float32Array(w * h);
  for (let j = 0; j < h; j++) {
    const y = half - ((j + 0.5) / h) * 2 * half;
    for (let i = 0; i < w; i++) {
      const x = ((i + 0.5) / w) * 2 * half - half;
      const u = rastrigin(x, y);
      t[j * w + i] = Math.min(1, Math.log1p(u) * scale);
      light[j * w + i] = shade(x, y, u);
    }
  }
  const image = ctx.createImageData(w, h);
  const data = image.data;
  for (let j = 0; j < h; j++) {
    for (let i = 0; i < w; i++) {
      const k = j * w + i;
      const level = Math.floor(t[k] * levels);
      const edge =
        (i + 1 < w && Math.floor(t[k + 1] * levels) !== level) ||
        (j + 1 < h && Math.floor(t[k + w] * levels) !== level);
      const c = 3 * Math.round(255 * t[k]);
      const dim = (edge ? 0.55 : 1) * light[k];
      data[4 * k] = VIRIDIS[c] * dim;
      data[4 * k + 1] = VIRIDIS[c + 1] * dim;
      data[4 * k + 2] = VIRIDIS[c + 2] * dim;
      data[4 * k + 3] = 255;
    }
  }
  ctx.putImageData(image, x0, y0);

  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  drawAxes(ctx, frame, getComputedStyle(canvas).color);
  // The global minimum x* = 0.
  const cx = frame.px(0);
  const cy = frame.py(0);
  ctx.strokeStyle = "#fff";
  ctx.lineWidth = 1.5;
  ctx.beginPath();
  ctx.moveTo(cx - 7, cy);
  ctx.lineTo(cx + 7, cy);
  ctx.moveTo(cx, cy - 7);
  ctx.lineTo(cx, cy + 7);
  ctx.stroke();
  ctx.font = "12px system-ui, sans-serif";
  ctx.fillStyle = "#fff";
  ctx.textAlign = "left";
  ctx.textBaseline = "bottom";
  ctx.fillText("x*", cx + 5, cy - 3);
}

function drawAxes(ctx, frame, color) {
  const half = frame.half;
  const step = half <= 6 ? 1 : half <= 12 ? 2 : 5;
  ctx.strokeStyle = color;
  ctx.fillStyle = color;
  ctx.lineWidth = 1;
  ctx.font = "11px system-ui, sans-serif";
  ctx.strokeRect(frame.left - 0.5, frame.top - 0.5, frame.width + 1, frame.height + 1);
  ctx.beginPath();
  for (let v = -Math.floor(half / step) * step; v <= half + 1e-9; v += step) {
    const x = frame.px(v);
    const y = frame.py(v);
    ctx.moveTo(x, frame.top + frame.height);
    ctx.lineTo(x, frame.top + frame.height + 4);
    ctx.moveTo(frame.left, y);
    ctx.lineTo(frame.left - 4, y);
  }
  ctx.stroke();
  ctx.textAlign = "center";
  ctx.textBaseline = "top";
  for (let v = -Math.floor(half / step) * step; v <= half + 1e-9; v += step) {
    ctx.fillText(String(v), frame.px(v), frame.top + frame.height + 6);
  }
  ctx.textAlign = "right";
  ctx.textBaseline = "middle";
  for (let v = -Math.floor(half / step) * step; v <= half + 1e-9; v += step) {
    ctx.fillText(String(v), frame.left - 6, frame.py(v));
  }
  // Axis names inside the plot, outlined so they read on any colour.
  ctx.font = "13px system-ui, sans-serif";
  ctx.lineWidth = 3;
  ctx.strokeStyle = "rgba(0, 0, 0, 0.75)";
  ctx.fillStyle = "#fff";
  ctx.textAlign = "right";
  ctx.textBaseline = "bottom";
  ctx.strokeText("x₁", frame.left + frame.width - 4, frame.top + frame.height - 3);
  ctx.fillText("x₁", frame.left + frame.width - 4, frame.top + frame.height - 3);
  ctx.textAlign = "left";
  ctx.textBaseline = "top";
  ctx.strokeText("x₂", frame.left + 5, frame.top + 4);
  ctx.fillText("x₂", frame.left + 5, frame.top + 4);
}

/**
 * Trails (oldest faintest), then the chains, then the running best.
 * `trails` is a TrailBuffer; `best` is [x0, x1] or null.
 */
export function drawChains(canvas, frame, dpr, trails, positions, n, best) {
  const ctx = canvas.getContext("2d");
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.clearRect(0, 0, frame.size, frame.size);
  ctx.save();
  ctx.beginPath();
  ctx.rect(frame.left, frame.top, frame.width, frame.height);
  ctx.clip();

  ctx.strokeStyle = "#ffffff";
  ctx.lineWidth = 1;
  const ages = trails.count - 1;
  for (let age = ages; age >= 1; age--) {
    // Segment from snapshot `age` (older) to `age - 1` (newer).
    const older = trails.snapshot(age);
    const newer = trails.snapshot(age - 1);
    ctx.globalAlpha = 0.55 * (1 - (age - 1) / ages);
    ctx.beginPath();
    for (let c = 0; c < n; c++) {
      const ax = older[2 * c];
      const bx = newer[2 * c];
      if (!(Number.isFinite(ax) && Number.isFinite(bx))) continue;
      ctx.moveTo(frame.px(ax), frame.py(older[2 * c + 1]));
      ctx.lineTo(frame.px(bx), frame.py(newer[2 * c + 1]));
    }
    ctx.stroke();
  }
  ctx.globalAlpha = 1;

  ctx.fillStyle = "#ffffff";
  ctx.strokeStyle = "rgba(0, 0, 0, 0.45)";
  ctx.lineWidth = 0.75;
  ctx.beginPath();
  for (let c = 0; c < n; c++) {
    const x = positions[2 * c];
    const y = positions[2 * c + 1];
    if (!(Number.isFinite(x) && Number.isFinite(y))) continue;
    const px = frame.px(x);
    const py = frame.py(y);
    ctx.moveTo(px + 2.5, py);
    ctx.arc(px, py, 2.5, 0, 2 * Math.PI);
  }
  ctx.fill();
  ctx.stroke();

  if (best) {
    const px = frame.px(best[0]);
    const py = frame.py(best[1]);
    ctx.lineWidth = 2.5;
    ctx.strokeStyle = "#000";
    ctx.beginPath();
    ctx.arc(px, py, 8, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.lineWidth = 1.5;
    ctx.strokeStyle = "#ff5a36";
    ctx.beginPath();
    ctx.arc(px, py, 8, 0, 2 * Math.PI);
    ctx.stroke();
  }
  ctx.restore();
}

/** The last `length` snapshots of every chain's position, in fixed memory. */
export class TrailBuffer {
  constructor(length, chains) {
    this.length = length;
    this.stride = 2 * chains;
    this.data = new Float32Array(length * this.stride);
    this.head = 0;
    this.count = 0;
  }
  push(positions) {
    this.head = (this.head + 1) % this.length;
    this.data.set(positions, this.head * this.stride);
    this.count = Math.min(this.count + 1, this.length);
  }
  /** Snapshot `age` frames ago (0 = newest). */
  snapshot(age) {
    const slot = (this.head - age + this.length) % this.length;
    return this.data.subarray(slot * this.stride, (slot + 1) * this.stride);
  }
}
