// The paper's own experiment (spec section 7, E2) live: M independent runs
// of N chains on d-dimensional Rastrigin for HRLA, ULA and OLA from the same
// starts, computed by the wasm kernel's `Experiment` and drawn as the
// success probability and the mean running best against the step, beside
// the numbers the project's reproduction measured for the same setting.
//
// Its settings live in the address under `dd_*` keys (the page's own
// reader is given the address without them, and its one writer asks
// `ddimParams` for them), so a link replays the same
// curves bit for bit. It steps only while its section is on screen and
// playing, or when "+ steps" asks for an exact count; and then within a
// share of the frame budget.
//
// For the browser tests: `window.hrlaDdim` holds the run, and the readouts
// carry their exact values in `data-value`.

import { FRAME_BUDGET_MS, stepWithin } from "./pace.js";
import { drawLinePlot } from "./plots.js";
import { RUN_COLOURS } from "./landscape.js";
import { parseNumber } from "./fields.js";

/** The samplers, in the order of the kernel's record. */
const NAMES = ["HRLA", "ULA", "OLA"];

/**
 * The settings, their address keys and defaults: the paper's E2 panel
 * (a = 4, ε = 2) in d = 10, with the reproduction tool's base seed, so the
 * default curves are the tool's own.
 */
export const DDIM_FIELDS = [
  { id: "d", key: "dd_d", value: "10" },
  { id: "runs", key: "dd_M", value: "100" },
  { id: "chains", key: "dd_N", value: "10" },
  { id: "a", key: "dd_a", value: "4" },
  { id: "h", key: "dd_h", value: "0.01" },
  { id: "eps", key: "dd_eps", value: "2" },
  { id: "steps", key: "dd_K", value: "14000" },
  { id: "seed", key: "dd_seed", value: "2025" },
];

/**
 * The project's E2 (docs/REPRODUCTION.md, docs/repro/e2): at K = 14 000,
 * per a, the share of the 100 runs within ε = 2 and ε = 4, and the mean
 * running best, for HRLA, ULA, OLA.
 */
const E2 = {
  2: { p2: [0.12, 0.21, 0.09], p4: [0.78, 0.91, 0.86], best: [0.3301, 0.6964, 0.3326] },
  3: { p2: [0.91, 0.56, 0.79], p4: [1.0, 1.0, 1.0], best: [0.1497, 0.5913, 0.1512] },
  4: { p2: [1.0, 0.58, 1.0], p4: [1.0, 1.0, 1.0], best: [0.1091, 1.0499, 0.1103] },
  5: { p2: [0.62, 0.24, 0.57], p4: [1.0, 0.95, 1.0], best: [0.8555, 1.7752, 1.0041] },
};

/**
 * Of the frame's stepping budget, the share this view takes: the main
 * picture may step in the same frame with the whole budget of its own.
 */
const BUDGET_MS = FRAME_BUDGET_MS / 2;

/** Points per curve drawn: every r-th iterate, exact there. */
const DRAWN = 600;

const $ = (id) => document.getElementById(id);

/** The view's settings as the address gives them (defaults for the rest). */
function fromAddress(search) {
  const q = new URLSearchParams(search);
  const values = {};
  for (const f of DDIM_FIELDS) values[f.id] = q.get(f.key) ?? f.value;
  return values;
}

/** The view's settings now: read from the address when the module loads, then from its controls. */
let current = fromAddress(typeof location === "undefined" ? "" : location.search);

/** Whether an address key is this view's. */
export function isDdimKey(key) {
  return key.startsWith("dd_");
}

/** The address without this view's keys (for the page's own reader). */
export function withoutDdim(search) {
  const q = new URLSearchParams(search);
  for (const key of [...q.keys()]) if (isDdimKey(key)) q.delete(key);
  return `?${q}`;
}

/** This view's settings that differ from their defaults, as address pairs. */
export function ddimParams() {
  return DDIM_FIELDS.filter((f) => current[f.id] !== f.value).map((f) => [f.key, current[f.id]]);
}

/** The settings object of the kernel's `Experiment`, or the field at fault. */
function settingsOf(values) {
  const out = {};
  for (const f of DDIM_FIELDS) {
    const text = String(values[f.id]).trim();
    if (f.id === "seed") {
      if (!/^[0-9]+$/.test(text)) return { field: "seed", message: "The seed must be a whole number from 0 to 2^64 − 1." };
      out.seed = BigInt(text);
    } else {
      const v = parseNumber(text);
      if (!Number.isFinite(v)) return { field: f.id, message: `“${text}” is not a number.` };
      out[f.id] = v;
    }
  }
  return { settings: out };
}

/** The run and the view's state. */
const x = {
  kernel: null,
  run: null,
  record: null,
  playing: false,
  visible: false,
  pending: 0,
  drawn: -1,
  now: () => performance.now(),
  /** The record's rows 0..k, as a plain array (for the tests). */
  rows: () => (x.run ? Array.from(recordView().subarray(0, (x.run.iteration() + 1) * x.kernel.Experiment.rowLength())) : []),
};

function recordView() {
  const memory = x.kernel.wasm_memory();
  if (!x.record || x.record.buffer !== memory.buffer) {
    const len = (x.run.steps() + 1) * x.kernel.Experiment.rowLength();
    x.record = new Float64Array(memory.buffer, x.run.record_ptr(), len);
  }
  return x.record;
}

function clearErrors() {
  for (const f of DDIM_FIELDS) {
    $(`ddim-${f.id}`).removeAttribute("aria-invalid");
  }
  $("ddim-error").textContent = "";
}

/** (Re)starts the run from the controls' settings. */
function restart() {
  clearErrors();
  x.run?.free();
  x.run = null;
  x.record = null;
  x.pending = 0;
  x.drawn = -1;
  const { settings, field, message } = settingsOf(current);
  let error = message ? { field, message } : null;
  if (!error) {
    try {
      x.run = new x.kernel.Experiment(settings);
    } catch (e) {
      error = { field: e.field, message: e.message };
    }
  }
  if (error) {
    const id = { runs: "runs", chains: "chains", steps: "steps" }[error.field] ?? error.field;
    if (id && $(`ddim-${id}`)) $(`ddim-${id}`).setAttribute("aria-invalid", "true");
    $("ddim-error").textContent = `${error.message}${id ? ` (${id})` : ""}`;
  }
  syncTransport();
  draw();
}

function syncTransport() {
  const live = x.run !== null && x.run.iteration() < x.run.steps();
  $("ddim-play").disabled = !live;
  $("ddim-forward").disabled = !live;
  if (!live) x.playing = false;
  $("ddim-play").textContent = x.playing ? "Pause" : "Play";
  $("ddim-play").setAttribute("aria-pressed", String(x.playing));
}

function setOutput(el, text, value) {
  el.textContent = text;
  el.dataset.value = String(value);
}

const fmt = (v) => (Number.isFinite(v) ? (v >= 100 ? v.toFixed(0) : v.toPrecision(3)) : "–");

/** The curves, the readouts and the table. */
function draw() {
  const run = x.run;
  const k = run ? run.iteration() : 0;
  if (run && x.drawn === k) return;
  x.drawn = run ? k : -1;
  const K = run ? run.steps() : Number(current.steps) || 0;
  setOutput($("ddim-iteration"), run ? `${k} of ${K}` : "–", k);
  const rows = $("ddim-table").tBodies[0].rows;
  if (!run) {
    for (const row of rows) for (const cell of [row.cells[1], row.cells[2]]) setOutput(cell, "–", NaN);
    drawLinePlot($("ddim-prob"), [], { log: false, yMin: 0, yMax: 1, yTicks: [0, 0.5, 1] });
    drawLinePlot($("ddim-best"), [], { log: true });
    return;
  }
  const rec = recordView();
  const row = x.kernel.Experiment.rowLength();
  const m = run.runs();
  const r = Math.max(1, Math.ceil(k / DRAWN));
  const at = [];
  for (let i = 0; i <= k; i += r) at.push(i);
  if (at[at.length - 1] !== k) at.push(k);
  const prob = [];
  const best = [];
  for (let s = 0; s < NAMES.length; s++) {
    const xs = Float64Array.from(at);
    prob.push({ xs, ys: at.map((i) => rec[i * row + s] / m), count: at.length, color: RUN_COLOURS[s] });
    const bx = Float64Array.from(at.filter((i) => i > 0));
    best.push({ xs: bx, ys: [...bx].map((i) => rec[i * row + NAMES.length + s]), count: bx.length, color: RUN_COLOURS[s], stairs: true });
    const p = rec[k * row + s] / m;
    const b = rec[k * row + NAMES.length + s];
    setOutput(rows[s].cells[1], p.toFixed(2), p);
    setOutput(rows[s].cells[2], fmt(b), b);
  }
  // An invisible point at K keeps the axis at the run's length, so the
  // curves grow across a fixed frame.
  const last = best[0].count > 0 ? best[0].ys[best[0].count - 1] : 1;
  const anchor = (y) => ({ xs: [K], ys: [y], count: 1, color: "rgba(0, 0, 0, 0)" });
  // HRLA drawn last, on top, as in the picture above.
  drawLinePlot($("ddim-prob"), [...prob.reverse(), anchor(0)], { log: false, yMin: 0, yMax: 1, yTicks: [0, 0.5, 1] });
  drawLinePlot($("ddim-best"), [...best.reverse(), anchor(last)], { log: true });
  syncTransport();
}

/** The project's numbers for these settings, when they are E2's. */
function reference() {
  const e2 = E2[current.a];
  const same =
    e2 &&
    current.d === "10" &&
    current.runs === "100" &&
    current.chains === "10" &&
    current.h === "0.01" &&
    current.steps === "14000" &&
    ["2", "4"].includes(current.eps);
  const rows = $("ddim-table").tBodies[0].rows;
  for (let s = 0; s < NAMES.length; s++) {
    const [p, b] = same ? [e2[current.eps === "2" ? "p2" : "p4"][s], e2.best[s]] : [NaN, NaN];
    setOutput(rows[s].cells[3], same ? p.toFixed(2) : "–", p);
    setOutput(rows[s].cells[4], same ? b.toFixed(4) : "–", b);
  }
  $("ddim-reference").textContent = same
    ? `The last two columns: the project's reproduction of E2 at K = 14 000 (100 runs; seed ${current.seed === "2025" ? "2025, the same as here: the curves end there" : "2025, another sample"}).`
    : "The last two columns hold the project's E2 numbers when the settings are E2's: d = 10, M = 100, N = 10, h = 0.01, K = 14 000, a from 2 to 5, ε = 2 or 4.";
}

function frame() {
  requestAnimationFrame(frame);
  const run = x.run;
  if (!run) return;
  const left = run.steps() - run.iteration();
  const wanted = x.playing && x.visible ? left : Math.min(x.pending, left);
  if (wanted > 0) {
    const { done } = stepWithin(
      wanted,
      (k) => {
        try {
          run.advance(k);
        } catch (e) {
          $("ddim-error").textContent = e.message;
          x.playing = false;
          x.pending = 0;
          return false;
        }
        return run.iteration() < run.steps();
      },
      x.now,
      BUDGET_MS,
    );
    x.pending = Math.max(0, x.pending - done);
  } else {
    x.pending = 0;
  }
  draw();
}

/**
 * Wires the section; `paused`: the page was opened paused, so this view is
 * too; `writeAddress`: the page's one writer of the address, called when a
 * setting here changes (it asks `ddimParams` for this view's keys).
 */
export async function setUpDdim({ paused, writeAddress }) {
  x.kernel = await import("../pkg/hrla_wasm.js");
  window.hrlaDdim = x;
  for (const f of DDIM_FIELDS) {
    const el = $(`ddim-${f.id}`);
    el.value = current[f.id];
    el.addEventListener("change", () => {
      current = { ...current, [f.id]: el.value.trim() };
      writeAddress();
      reference();
      restart();
    });
  }
  $("ddim-play").addEventListener("click", () => {
    x.playing = !x.playing;
    syncTransport();
  });
  $("ddim-forward").addEventListener("click", () => {
    const n = parseNumber($("ddim-count").value);
    if (Number.isInteger(n) && n > 0) x.pending += n;
  });
  $("ddim-reset").addEventListener("click", restart);
  new IntersectionObserver((entries) => {
    for (const e of entries) x.visible = e.isIntersecting;
  }).observe($("ddim"));
  for (const id of ["ddim-prob", "ddim-best"]) {
    new ResizeObserver(() => {
      x.drawn = -1;
      draw();
    }).observe($(id));
  }
  x.playing = !paused;
  reference();
  restart();
  $("ddim").dataset.ready = "true";
  requestAnimationFrame(frame);
}
