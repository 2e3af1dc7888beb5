// Plots of a run's history against the iteration (running best U − U* on
// a log scale, drawn as the staircase it is; the empirical probability),
// and the marginal histograms of the chains against the exact marginals.

const PAD = { left: 46, right: 10, top: 8, bottom: 22 };

/**
 * Sizes a canvas to its CSS box at the device pixel ratio; returns [w, h].
 * Only a change of size resizes it (which clears it and resets its
 * context): its drawers clear or fill it and set what they draw with.
 */
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
 * Fits and clears a canvas for a plot; returns its context, its computed
 * style, its width and the plot area inside PAD: { ctx, style, w, left,
 * top, pw, ph }.
 */
function startPlot(canvas) {
  const [w, h] = fitCanvas(canvas);
  const ctx = canvas.getContext("2d");
  const style = getComputedStyle(canvas);
  ctx.clearRect(0, 0, w, h);
  const pw = w - PAD.left - PAD.right;
  const ph = h - PAD.top - PAD.bottom;
  return { ctx, style, w, left: PAD.left, top: PAD.top, pw, ph };
}

/** The plot area's frame, in the text's colour; leaves that colour and the labels' font set. */
function drawFrame(ctx, style, left, top, pw, ph) {
  ctx.strokeStyle = style.color;
  ctx.lineWidth = 1;
  ctx.strokeRect(left - 0.5, top - 0.5, pw + 1, ph + 1);
  ctx.fillStyle = style.color;
  ctx.font = "11px system-ui, sans-serif";
}

/**
 * The polyline of a series: with `stairs`, a value holds until the next
 * point, where the line drops vertically (the running best only ever steps
 * down; a slope would show values never reached). Returns [x0, y0, x1, y1, ...].
 */
export function seriesPoints(xs, ys, count, stairs) {
  const out = [];
  for (let i = 0; i < count; i++) {
    if (stairs && i > 0) out.push(xs[i], ys[i - 1]);
    out.push(xs[i], ys[i]);
  }
  return out;
}

/**
 * Draws series against the iteration. `series`: [{ xs, ys, count, color,
 * stairs }]; options: { log, yMin, yMax, yTicks (linear only) }.
 */
export function drawLinePlot(canvas, series, options) {
  const { ctx, style, left, top, pw, ph } = startPlot(canvas);
  let xMax = 1;
  for (const s of series) if (s.count > 0) xMax = Math.max(xMax, s.xs[s.count - 1]);
  let yLo;
  let yHi;
  let map;
  const floor = 1e-12;
  if (options.log) {
    let lo = Infinity;
    let hi = -Infinity;
    for (const s of series) {
      for (let i = 0; i < s.count; i++) {
        const v = Math.max(s.ys[i], floor);
        if (Number.isFinite(v)) {
          lo = Math.min(lo, v);
          hi = Math.max(hi, v);
        }
      }
    }
    if (!Number.isFinite(lo)) {
      lo = 1e-3;
      hi = 10;
    }
    yLo = Math.floor(Math.log10(lo));
    yHi = Math.max(yLo + 1, Math.ceil(Math.log10(hi)));
    map = (v) => top + ph * (1 - (Math.log10(Math.max(v, floor)) - yLo) / (yHi - yLo));
  } else {
    yLo = options.yMin;
    yHi = options.yMax;
    map = (v) => top + ph * (1 - (v - yLo) / (yHi - yLo));
  }
  const mapX = (v) => left + (pw * v) / xMax;

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
  drawFrame(ctx, style, left, top, pw, ph);

  for (const s of series) {
    const p = seriesPoints(s.xs, s.ys, s.count, s.stairs);
    ctx.strokeStyle = s.color;
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    for (let i = 0; i < p.length; i += 2) {
      if (i === 0) ctx.moveTo(mapX(p[i]), map(p[i + 1]));
      else ctx.lineTo(mapX(p[i]), map(p[i + 1]));
    }
    ctx.stroke();
  }
}

/**
 * A histogram of `values` (positions, every `step`-th entry from `offset`)
 * over [lo, hi] in `bins` bins, as a density against the exact one.
 * Only chains inside the view box count (`inside(c)`), the exact marginal
 * being of the density restricted to the same box. Returns the counts.
 */
export function histogram(values, offset, n, inside, lo, hi, bins) {
  const counts = new Float64Array(bins);
  for (let c = 0; c < n; c++) {
    if (!inside(c)) continue;
    const v = values[2 * c + offset];
    const b = Math.min(bins - 1, Math.floor(((v - lo) / (hi - lo)) * bins));
    counts[b]++;
  }
  return counts;
}

/**
 * Bars: each histogram (counts, colour) scaled to a density; the exact
 * marginal (values at `exact.length` evenly spaced points over [lo, hi])
 * as a line.
 */
export function drawHistogram(canvas, lo, hi, hists, exact) {
  const { ctx, style, w, top, ph } = startPlot(canvas);
  // No axis on the left to label: the bars take all but 10 px each side.
  const left = 10;
  const pw = w - 20;
  const densities = hists.map(({ counts }) => {
    const total = counts.reduce((s, v) => s + v, 0);
    const width = (hi - lo) / counts.length;
    return counts.map((v) => (total > 0 ? v / (total * width) : 0));
  });
  let yMax = 0;
  for (const v of exact) yMax = Math.max(yMax, v);
  for (const d of densities) for (const v of d) yMax = Math.max(yMax, v);
  yMax = yMax > 0 ? yMax * 1.08 : 1;
  const mapX = (v) => left + ((v - lo) / (hi - lo)) * pw;
  const mapY = (v) => top + ph * (1 - v / yMax);
  densities.forEach((d, k) => {
    ctx.fillStyle = hists[k].colour;
    ctx.globalAlpha = hists.length > 1 ? 0.35 : 0.55;
    const width = pw / d.length;
    for (let b = 0; b < d.length; b++) {
      if (d[b] > 0) ctx.fillRect(left + b * width + 0.5, mapY(d[b]), width - 1, top + ph - mapY(d[b]));
    }
  });
  ctx.globalAlpha = 1;
  ctx.strokeStyle = "#ffb000";
  ctx.lineWidth = 2;
  ctx.beginPath();
  for (let i = 0; i < exact.length; i++) {
    const x = mapX(lo + ((i + 0.5) / exact.length) * (hi - lo));
    if (i === 0) ctx.moveTo(x, mapY(exact[i]));
    else ctx.lineTo(x, mapY(exact[i]));
  }
  ctx.stroke();
  drawFrame(ctx, style, left, top, pw, ph);
  ctx.textBaseline = "top";
  ctx.textAlign = "left";
  ctx.fillText(String(+lo.toFixed(2)), left, top + ph + 5);
  ctx.textAlign = "right";
  ctx.fillText(String(+hi.toFixed(2)), left + pw, top + ph + 5);
}

/**
 * The exact marginals of exp(-a U) restricted to the view, from U on an
 * nx x ny grid of cell centres (rows from the top): each a density over
 * its axis (sum * cell width = 1), by the midpoint rule. Returns { x, y }
 * with x from left to right and y from bottom to top.
 */
export function exactMarginals(grid, nx, ny, a, width, height) {
  let lo = Infinity;
  for (const u of grid) if (u < lo) lo = u;
  const mx = new Float64Array(nx);
  const my = new Float64Array(ny);
  for (let j = 0; j < ny; j++) {
    for (let i = 0; i < nx; i++) {
      // Relative to the lowest value: no underflow of the whole density.
      const p = Math.exp(-a * (grid[j * nx + i] - lo));
      mx[i] += p;
      my[ny - 1 - j] += p;
    }
  }
  const dx = width / nx;
  const dy = height / ny;
  const total = mx.reduce((s, v) => s + v, 0) * dx * dy;
  for (let i = 0; i < nx; i++) mx[i] *= dy / total;
  for (let j = 0; j < ny; j++) my[j] *= dx / total;
  return { x: mx, y: my };
}

/**
 * The annealing schedule a_k = aLow + (aHigh - aLow) k / K, then aHigh,
 * over [0, max(1.25 K, iteration)], with a dot at the run's (iteration, a).
 * Returns what it drew: { points: [[k, a]], marker: [k, a] }.
 */
export function drawSchedule(canvas, aLow, aHigh, K, iteration, aNow) {
  const { ctx, style, left, top, pw, ph } = startPlot(canvas);
  const kMax = Math.max(1.25 * K, iteration, 1);
  const lo = Math.min(aLow, aHigh, aNow);
  const hi = Math.max(aLow, aHigh, aNow);
  const span = hi - lo || 1;
  const mapX = (k) => left + (pw * k) / kMax;
  const mapY = (a) => top + ph * (1 - (a - lo) / span);
  const points = [
    [0, aLow],
    [K, aHigh],
    [kMax, aHigh],
  ];
  drawFrame(ctx, style, left, top, pw, ph);
  ctx.textAlign = "right";
  ctx.textBaseline = "middle";
  ctx.fillText(String(+hi.toPrecision(3)), left - 5, mapY(hi));
  ctx.fillText(String(+lo.toPrecision(3)), left - 5, mapY(lo));
  ctx.textAlign = "center";
  ctx.textBaseline = "top";
  ctx.fillText("0", left, top + ph + 5);
  ctx.fillText(`K = ${formatCount(K)}`, mapX(K), top + ph + 5);
  ctx.strokeStyle = "#35b779";
  ctx.lineWidth = 1.5;
  ctx.beginPath();
  points.forEach(([k, a], i) => (i === 0 ? ctx.moveTo(mapX(k), mapY(a)) : ctx.lineTo(mapX(k), mapY(a))));
  ctx.stroke();
  ctx.fillStyle = "#ff5a36";
  ctx.beginPath();
  ctx.arc(mapX(iteration), mapY(aNow), 4, 0, 2 * Math.PI);
  ctx.fill();
  return { points, marker: [iteration, aNow], px: [mapX(iteration), mapY(aNow)] };
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
