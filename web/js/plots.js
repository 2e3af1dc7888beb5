// Line plots of a run's history against the iteration: running best U on a
// log scale, and the empirical probability of being within eps of U*.

const PAD = { left: 46, right: 10, top: 8, bottom: 22 };

/** Sizes a canvas to its CSS box at the device pixel ratio; returns [w, h]. */
export function fitCanvas(canvas) {
  const dpr = window.devicePixelRatio || 1;
  const w = canvas.clientWidth;
  const h = canvas.clientHeight;
  if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
    canvas.width = Math.round(w * dpr);
    canvas.height = Math.round(h * dpr);
  }
  const ctx = canvas.getContext("2d");
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  return [w, h];
}

/**
 * Draws y against x (typed arrays, first `count` entries).
 * options: { log: bool, yMin, yMax (linear only), color, yTicks (linear only) }
 */
export function drawLinePlot(canvas, xs, ys, count, options) {
  const [w, h] = fitCanvas(canvas);
  const ctx = canvas.getContext("2d");
  const style = getComputedStyle(canvas);
  ctx.clearRect(0, 0, w, h);
  const left = PAD.left;
  const top = PAD.top;
  const pw = w - PAD.left - PAD.right;
  const ph = h - PAD.top - PAD.bottom;

  const xMax = Math.max(1, count > 0 ? xs[count - 1] : 1);
  let yLo;
  let yHi;
  let map;
  if (options.log) {
    let lo = Infinity;
    let hi = -Infinity;
    for (let i = 0; i < count; i++) {
      const v = Math.max(ys[i], 1e-12);
      lo = Math.min(lo, v);
      hi = Math.max(hi, v);
    }
    if (!Number.isFinite(lo)) {
      lo = 1e-3;
      hi = 10;
    }
    yLo = Math.floor(Math.log10(lo));
    yHi = Math.max(yLo + 1, Math.ceil(Math.log10(hi)));
    map = (v) => top + ph * (1 - (Math.log10(Math.max(v, 1e-12)) - yLo) / (yHi - yLo));
  } else {
    yLo = options.yMin;
    yHi = options.yMax;
    map = (v) => top + ph * (1 - (v - yLo) / (yHi - yLo));
  }
  const mapX = (v) => left + (pw * v) / xMax;

  // Grid and ticks.
  ctx.strokeStyle = style.getPropertyValue("--grid") || "#333";
  ctx.fillStyle = style.color;
  ctx.font = "11px system-ui, sans-serif";
  ctx.lineWidth = 1;
  ctx.textAlign = "right";
  ctx.textBaseline = "middle";
  ctx.beginPath();
  const yTicks = [];
  if (options.log) {
    const every = Math.ceil((yHi - yLo) / 5);
    for (let e = yLo; e <= yHi; e += every) yTicks.push([10 ** e, `1e${e}`]);
  } else {
    for (const v of options.yTicks) yTicks.push([v, String(v)]);
  }
  for (const [v, label] of yTicks) {
    const y = Math.round(map(v)) + 0.5;
    ctx.moveTo(left, y);
    ctx.lineTo(left + pw, y);
    ctx.fillText(label, left - 5, y);
  }
  ctx.stroke();
  ctx.textAlign = "center";
  ctx.textBaseline = "top";
  const xStep = niceStep(xMax / 4);
  for (let v = 0; v <= xMax + 1e-9; v += xStep) {
    ctx.fillText(formatCount(v), Math.min(mapX(v), left + pw - 12), top + ph + 5);
  }
  ctx.strokeStyle = style.color;
  ctx.strokeRect(left - 0.5, top - 0.5, pw + 1, ph + 1);

  // The series.
  ctx.strokeStyle = options.color;
  ctx.lineWidth = 1.5;
  ctx.beginPath();
  for (let i = 0; i < count; i++) {
    const x = mapX(xs[i]);
    const y = map(ys[i]);
    if (i === 0) ctx.moveTo(x, y);
    else ctx.lineTo(x, y);
  }
  ctx.stroke();
}

function niceStep(raw) {
  const p = 10 ** Math.floor(Math.log10(Math.max(raw, 1)));
  for (const m of [1, 2, 5, 10]) if (m * p >= raw) return m * p;
  return 10 * p;
}

/** 1500 -> "1.5k", 2000000 -> "2M". */
export function formatCount(v) {
  if (v >= 1e6) return `${+(v / 1e6).toPrecision(3)}M`;
  if (v >= 1e3) return `${+(v / 1e3).toPrecision(3)}k`;
  return String(v);
}
