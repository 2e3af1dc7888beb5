// The demo page: controls and address -> settings -> one wasm run (three in
// compare mode) -> canvases, plots and readouts, stepped within a time
// budget every animation frame.

import { LANDSCAPES } from "./landscapes.js";
import { FIELDS, fieldOf, parseNumber, plain, readAddress } from "./fields.js";
import { stepWithin } from "./pace.js";
import { Frame, RUN_COLOURS, colourScale, drawChains, drawColourBar, drawLandscape } from "./landscape.js";
import { drawHistogram, drawLinePlot, exactMarginals, formatCount, histogram } from "./plots.js";

const $ = (id) => document.getElementById(id);

/** Controls whose change restarts the run from the seed. */
const RUN_INPUTS = ["potential", "sampler", "compare", "h", "chains", "a", "aLow", "aHigh", "K", "cx", "cy", "spread", "seed", "stopSteps", "stopTarget", "group"];
/** Controls that only change the display or the pace. */
const VIEW_INPUTS = ["spf", "eps"];
const SAMPLERS = ["hrla", "ula", "ola"];
/** Grid of the exact marginals, per axis. */
const MARGINAL_GRID = 240;
/** The background's grid per axis at most: beyond, the picture is scaled. */
const MAX_PIXELS = 1200;
/** Histogram bins per axis. */
const BINS = 40;

let sim = null;
const state = {
  runs: [],
  playing: true,
  /** Steps the Step control asked for and the frames have not done yet. */
  pending: 0,
  frame: null,
  dpr: 1,
  view: LANDSCAPES.rastrigin.view,
  potential: "rastrigin",
  /** U on the plot area's pixels, and on the marginals' grid. */
  grid: null,
  marginalGrid: null,
  /** The a the background and the exact marginals were computed at. */
  shownA: NaN,
  marginals: null,
  scale: null,
  probability: [],
  gaps: [],
  /** Problems found in the address, by control (null: not a control's). */
  addressProblems: [],
  /** The clock of the time budget: replaceable by a test's clock. */
  now: () => performance.now(),
  lastFrame: { asked: 0, done: 0 },
  meter: { since: performance.now(), frames: 0, steps: 0 },
};

/** Options of a select, for the address check. */
const options = (id) => [...$(id).options].map((o) => o.value);

function text(id) {
  return $(id).value.trim();
}

function radio(name) {
  return document.querySelector(`input[name=${name}]:checked`).value;
}

/**
 * The settings of the wasm Optimizer from the controls, and every problem
 * the page can see before the kernel (a field that is not a number):
 * returns { settings, problems: [{ id, text }] }.
 */
function readSettings() {
  const problems = [];
  const num = (id, optional = false) => {
    const t = text(id);
    if (optional && t === "") return null;
    const v = parseNumber(t);
    if (!Number.isFinite(v)) problems.push({ id, text: t === "" ? "is empty: enter a number" : `“${t}” is not a number` });
    return v;
  };
  const linear = radio("schedule") === "linear";
  const seedText = text("seed");
  if (!/^[0-9]+$/.test(seedText) || BigInt(seedText) >= 2n ** 64n) {
    problems.push({ id: "seed", text: "must be a whole number between 0 and 2^64 − 1" });
  }
  const potential = $("potential").value;
  const gap = num("stopTarget", true);
  const settings = {
    potential,
    sampler: $("sampler").value,
    a: linear ? NaN : num("a"),
    annealing: linear ? { aLow: num("aLow"), aHigh: num("aHigh"), steps: num("K") } : null,
    h: num("h"),
    chains: num("chains"),
    centre: [num("cx"), num("cy")],
    spread: num("spread"),
    seed: problems.some((p) => p.id === "seed") ? 0n : BigInt(seedText),
    stopSteps: num("stopSteps", true),
    stopTarget: gap === null ? null : sim.globalMinimum(potential) + gap,
  };
  return { settings, problems };
}

function groupSize() {
  const n = parseNumber(text("group"));
  if (!(Number.isInteger(n) && n >= 1)) throw Object.assign(new Error("must be a whole number, 1 or more"), { id: "group" });
  return n;
}

// ---- Messages: each next to its control, in plain words. ----

function fieldError(id, message) {
  const el = $(`err-${id}`) ?? $("err-general");
  el.textContent = el.textContent ? `${el.textContent} ${message}` : message;
  const input = $(id);
  if (input) input.setAttribute("aria-invalid", "true");
}

function clearErrors() {
  $("error").textContent = "";
  for (const el of document.querySelectorAll(".field-error")) el.textContent = "";
  for (const el of document.querySelectorAll("[aria-invalid]")) el.removeAttribute("aria-invalid");
  for (const p of state.addressProblems) fieldError(p.id ?? "general", p.text);
}

/** A refused setting or a failed run: next to the control it is about, and why nothing runs. */
function showKernelError(e, sampler = null) {
  const id = fieldOf(e);
  const who = sampler ? `${sampler.toUpperCase()}: ` : "";
  if (id) fieldError(id, who + plain(e.message));
  return id;
}

// ---- The run. ----

function clearRuns() {
  for (const run of state.runs) run.free();
  state.runs = [];
}

/** Starts the run(s) the controls describe, from the seed. */
function restart() {
  clearRuns();
  clearErrors();
  state.pending = 0;
  const potential = $("potential").value;
  if (potential !== state.potential || !state.grid) {
    state.potential = potential;
    state.view = LANDSCAPES[potential].view;
    state.grid = null;
  }
  describeLandscape();
  const { settings, problems } = readSettings();
  let n = 10;
  try {
    n = groupSize();
  } catch (e) {
    problems.push({ id: e.id, text: e.message });
  }
  for (const p of problems) fieldError(p.id, p.text);
  const compare = $("compare").checked;
  $("sampler").disabled = compare;
  if (problems.length === 0) {
    const samplers = compare ? SAMPLERS : [settings.sampler];
    try {
      state.runs = samplers.map((sampler) => new sim.Run({ ...settings, sampler }, n));
    } catch (e) {
      clearRuns();
      showKernelError(e);
      if (!fieldOf(e)) $("error").textContent = plain(e.message);
    }
  }
  if (state.runs.length === 0) {
    const count = document.querySelectorAll("[aria-invalid]").length;
    $("error").textContent ||= `No run: ${count === 1 ? "a setting is" : "some settings are"} refused (marked beside ${count === 1 ? "it" : "them"}).`;
  } else if (n > state.runs[0].n) {
    $("err-group").textContent = `only ${state.runs[0].n} chains: one group of ${state.runs[0].n}`;
  }
  syncControls();
  writeUrl();
  resetMeter();
  layout(true);
}

/** Advances every live run by k steps; false once none can go on. */
function advanceRuns(k) {
  for (const run of state.runs) {
    if (!run.live) continue;
    try {
      run.advance(k);
    } catch (e) {
      const multi = state.runs.length > 1;
      showKernelError(e, multi ? run.sampler : null);
      $("error").textContent = (multi ? `${run.sampler.toUpperCase()} stopped: ` : "") + plain(e.message);
    }
  }
  return state.runs.some((r) => r.live);
}

/** Up to `wanted` steps within the frame's time budget; returns the steps done. */
function stepFrame(wanted) {
  if (state.runs.length === 0 || wanted <= 0) return 0;
  const { done } = stepWithin(wanted, advanceRuns, state.now);
  state.lastFrame = { asked: wanted, done };
  state.meter.steps += done;
  if (!state.runs.some((r) => r.live)) {
    state.pending = 0;
    setPlaying(false);
  }
  return done;
}

function stepsPerFrame() {
  const v = Math.floor(parseNumber(text("spf")));
  return Number.isFinite(v) && v >= 1 ? Math.min(v, 1e9) : 1;
}

function resetMeter() {
  state.meter = { since: performance.now(), frames: 0, steps: 0 };
}

function tick() {
  if (state.playing) stepFrame(stepsPerFrame());
  else if (state.pending > 0) state.pending -= stepFrame(state.pending);
  state.meter.frames++;
  const dt = (performance.now() - state.meter.since) / 1000;
  if (dt >= 1) {
    const m = state.meter;
    setOutput("out-fps", (m.frames / dt).toFixed(1), m.frames / dt);
    setOutput("out-rate", formatCount(Math.round(m.steps / dt)), m.steps / dt);
    resetMeter();
  }
  render();
  requestAnimationFrame(tick);
}

/** Writes a readout; `exact` (a number) goes to data-value for scripts. */
function setOutput(id, text, exact) {
  const el = $(id);
  if (el.textContent !== text) el.textContent = text;
  el.dataset.value = exact === undefined ? "" : String(exact);
}

// ---- Drawing. ----

/** The background and the exact marginals, at the current a (recomputed when a moved by over 1%). */
function refreshBackground(force) {
  const frame = state.frame;
  const run = state.runs[0];
  run?.rebind();
  const a = run ? run.s[sim.Summary.A] : parseNumber(text("a")) || 1;
  if (!force && Math.abs(a - state.shownA) <= 0.01 * state.shownA) return;
  const mode = radio("show");
  state.shownA = a;
  const w = Math.min(MAX_PIXELS, Math.round(frame.width * state.dpr));
  const h = Math.min(MAX_PIXELS, Math.round(frame.height * state.dpr));
  if (!state.grid || state.grid.w !== w || state.grid.h !== h) {
    state.grid = { w, h, u: sim.potentialGrid(state.potential, frame.x0, frame.x1, frame.y0, frame.y1, w, h) };
    state.marginalGrid = sim.potentialGrid(state.potential, frame.x0, frame.x1, frame.y0, frame.y1, MARGINAL_GRID, MARGINAL_GRID);
  }
  const minimum = sim.globalMinimum(state.potential);
  if (force || mode === "density") {
    state.scale = colourScale(state.grid.u, mode, a, minimum);
    drawLandscape($("landscape"), frame, state.dpr, state.scale, w, h, LANDSCAPES[state.potential].minimisers);
    drawColourBar($("colorbar"), state.scale);
  }
  state.marginals = exactMarginals(state.marginalGrid, MARGINAL_GRID, MARGINAL_GRID, a, frame.x1 - frame.x0, frame.y1 - frame.y0);
}

function render() {
  const frame = state.frame;
  if (!frame) return;
  refreshBackground(false);
  const runs = state.runs;
  // The grids are allocated in wasm memory: it may have grown.
  for (const r of runs) r.rebind();
  const S = sim.Summary;
  if (runs.length === 0) {
    for (const id of ["particles", "plot-best", "plot-prob", "plot-mx", "plot-my"]) {
      const c = $(id);
      c.getContext("2d").clearRect(0, 0, c.width, c.height);
    }
    for (const id of ["out-iteration", "out-best", "out-best-x", "out-best-at", "out-a", "out-diverged", "out-outside", "out-prob", "out-frame-steps"]) setOutput(id, "–");
    $("status").replaceChildren();
    return;
  }
  const colours = runs.length > 1 ? RUN_COLOURS : ["#ffffff"];
  drawChains(
    $("particles"),
    frame,
    state.dpr,
    runs.map((r, k) => ({ trails: r.trails, x: r.x, n: r.n, best: [r.s[S.BestX0], r.s[S.BestX1]], colour: colours[k] })),
  );
  const lineColours = runs.length > 1 ? RUN_COLOURS : ["#ff5a36"];
  drawLinePlot(
    $("plot-best"),
    runs.map((r, k) => {
      const gaps = (state.gaps[k] ??= new Float64Array(1024));
      for (let i = 0; i < r.count; i++) gaps[i] = r.best[i] - r.minimum;
      return { xs: r.iters, ys: gaps, count: r.count, color: lineColours[k], stairs: true };
    }),
    { log: true },
  );
  const eps = parseNumber(text("eps"));
  const probColours = runs.length > 1 ? RUN_COLOURS : ["#35b779"];
  drawLinePlot(
    $("plot-prob"),
    runs.map((r, k) => {
      const out = (state.probability[k] ??= new Float64Array(1024));
      r.probabilitySeries(eps, out);
      return { xs: r.iters, ys: out, count: r.count, color: probColours[k], stairs: false };
    }),
    { log: false, yMin: 0, yMax: 1, yTicks: [0, 0.5, 1] },
  );
  drawMarginals(runs, colours);
  readouts(runs, eps);
}

function drawMarginals(runs, colours) {
  const f = state.frame;
  const inside = (r) => (c) => {
    const x = r.x[2 * c];
    const y = r.x[2 * c + 1];
    return x >= f.x0 && x <= f.x1 && y >= f.y0 && y <= f.y1;
  };
  drawHistogram(
    $("plot-mx"),
    f.x0,
    f.x1,
    runs.map((r, k) => ({ counts: histogram(r.x, 0, r.n, inside(r), f.x0, f.x1, BINS), colour: colours[k] })),
    state.marginals.x,
  );
  drawHistogram(
    $("plot-my"),
    f.y0,
    f.y1,
    runs.map((r, k) => ({ counts: histogram(r.x, 1, r.n, inside(r), f.y0, f.y1, BINS), colour: colours[k] })),
    state.marginals.y,
  );
}

function readouts(runs, eps) {
  const S = sim.Summary;
  const r = runs[0];
  const s = r.s;
  const f = state.frame;
  setOutput("out-iteration", String(s[S.Iteration]), s[S.Iteration]);
  setOutput("out-best", s[S.BestValue].toExponential(3), s[S.BestValue]);
  setOutput("out-best-x", `(${coordinate(s[S.BestX0])}, ${coordinate(s[S.BestX1])})`);
  setOutput("out-best-at", String(s[S.BestIteration]), s[S.BestIteration]);
  setOutput("out-a", s[S.A].toPrecision(4), s[S.A]);
  setOutput("out-diverged", `${s[S.Diverged]} of ${r.n}`, s[S.Diverged]);
  const outside = r.outside(f.x0, f.x1, f.y0, f.y1);
  setOutput("out-outside", `${outside} of ${r.n}`, outside);
  const p = r.fractionWithin(eps);
  setOutput(
    "out-prob",
    Number.isFinite(p) ? `${p.toFixed(2)}: ${r.groupsWithin(eps)} of ${r.groups} groups of ${r.groupSize}` : "–",
    p,
  );
  const { asked, done } = state.lastFrame;
  setOutput("out-frame-steps", asked ? (done < asked ? `${formatCount(done)} of ${formatCount(asked)} (time budget)` : `${formatCount(done)}`) : "–", done);
  // What went wrong or ended, in words, beside the picture.
  const lines = [];
  for (const run of runs) {
    const who = runs.length > 1 ? `${run.sampler.toUpperCase()}: ` : "";
    const d = run.s[S.Diverged];
    if (d > 0) lines.push(["warn", `${who}${d} of ${run.n} chains diverged (their position overflowed): they are frozen and no longer count. A smaller step h avoids this.`]);
    const out = run.outside(f.x0, f.x1, f.y0, f.y1);
    if (out > 0) lines.push(["warn", `${who}${out} of ${run.n} chains are outside the picture (the farthest at |x| = ${run.reach().toPrecision(3)}).`]);
    if (run.termination) lines.push(["info", `${who}stopped: ${run.termination} at iteration ${run.iteration}.`]);
  }
  const status = $("status");
  const key = JSON.stringify(lines);
  if (status.dataset.key !== key) {
    status.dataset.key = key;
    status.replaceChildren(
      ...lines.map(([kind, t]) => {
        const li = document.createElement("li");
        li.className = kind;
        li.textContent = t;
        return li;
      }),
    );
  }
  const table = $("compare-table");
  table.hidden = runs.length < 2;
  $("readouts-for").hidden = runs.length < 2;
  if (runs.length > 1) {
    const body = table.tBodies[0];
    if (body.rows.length !== runs.length) {
      body.replaceChildren(
        ...runs.map((run, k) => {
          const tr = document.createElement("tr");
          tr.innerHTML = `<th scope="row"><span class="swatch" style="background:${RUN_COLOURS[k]}"></span>${run.sampler.toUpperCase()}</th><td><output id="cmp-best-${run.sampler}"></output></td><td><output id="cmp-at-${run.sampler}"></output></td><td><output id="cmp-prob-${run.sampler}"></output></td><td><output id="cmp-diverged-${run.sampler}"></output></td>`;
          return tr;
        }),
      );
    }
    for (const run of runs) {
      const q = run.s;
      setOutput(`cmp-best-${run.sampler}`, q[S.BestValue].toExponential(3), q[S.BestValue]);
      setOutput(`cmp-at-${run.sampler}`, String(q[S.BestIteration]), q[S.BestIteration]);
      const pr = run.fractionWithin(eps);
      setOutput(`cmp-prob-${run.sampler}`, Number.isFinite(pr) ? pr.toFixed(2) : "–", pr);
      setOutput(`cmp-diverged-${run.sampler}`, String(q[S.Diverged]), q[S.Diverged]);
    }
  }
}

/** A coordinate in at most 9 characters, without rounding a small one to 0. */
function coordinate(v) {
  return v !== 0 && Math.abs(v) < 1e-3 ? v.toExponential(2) : v.toFixed(4);
}

/** Sizes the canvases to their boxes; redraws the background when needed. */
function layout(force = false) {
  const size = Math.floor($("canvas-wrap").clientWidth);
  const dpr = window.devicePixelRatio || 1;
  if (!force && state.frame && state.frame.size === size && state.dpr === dpr) return;
  state.dpr = dpr;
  state.frame = new Frame(size, state.view);
  for (const id of ["landscape", "particles"]) {
    $(id).width = Math.round(size * dpr);
    $(id).height = Math.round(size * dpr);
  }
  refreshBackground(true);
  render();
}

function describeLandscape() {
  const l = LANDSCAPES[$("potential").value];
  $("potential-about").textContent = l.about;
  $("formula").textContent = l.formula;
}

function syncControls() {
  const linear = radio("schedule") === "linear";
  $("a").disabled = linear;
  for (const id of ["aLow", "aHigh", "K"]) $(id).disabled = !linear;
  const legend = $("legend");
  legend.hidden = state.runs.length < 2;
  if (state.runs.length > 1) {
    legend.innerHTML = state.runs
      .map((r, k) => `<span class="swatch" style="background:${RUN_COLOURS[k]}"></span>${r.sampler.toUpperCase()}`)
      .join(" ");
  }
}

function setPlaying(on) {
  state.playing = on;
  $("play").textContent = on ? "Pause" : "Play";
  $("play").setAttribute("aria-pressed", String(on));
  resetMeter();
  writeUrl();
}

// ---- The address: every setting, so a run can be shared and replayed. ----

function writeUrl() {
  const q = new URLSearchParams();
  for (const f of FIELDS) {
    if (f.id === "play") continue;
    if (f.kind === "choice") q.set(f.id, radio(f.id));
    else if (f.kind === "flag") q.set(f.id, $(f.id).checked ? "1" : "0");
    else q.set(f.id, $(f.id).value);
  }
  if (!state.playing) q.set("play", "0");
  history.replaceState(null, "", `?${q}`);
}

function readUrl() {
  const { values, problems } = readAddress(location.search, options);
  state.addressProblems = problems;
  // A landscape brings its own start, temperature and step first; the
  // address's other values then override them.
  if (values.potential) applyLandscape(values.potential);
  for (const [id, value] of Object.entries(values)) {
    const f = FIELDS.find((g) => g.id === id);
    if (f.kind === "choice") {
      if (id !== "play") $(`${id}-${value}`).checked = true;
    } else if (f.kind === "flag") $(id).checked = value === "1";
    else if (id !== "potential") $(id).value = value;
  }
  if (values.play === "0") setPlaying(false);
}

/** Sets the landscape and its recommended start, a, h and ε. */
function applyLandscape(name) {
  const l = LANDSCAPES[name];
  $("potential").value = name;
  for (const [id, v] of [
    ["cx", l.start.cx],
    ["cy", l.start.cy],
    ["spread", l.start.spread],
    ["a", l.a],
    ["aHigh", l.a],
    ["h", l.h],
    ["eps", l.eps],
  ]) {
    $(id).value = String(v);
  }
}

function forgetAddressProblem(id) {
  state.addressProblems = state.addressProblems.filter((p) => p.id !== id);
}

function wire() {
  for (const id of RUN_INPUTS) {
    $(id).addEventListener("change", () => {
      forgetAddressProblem(id);
      if (id === "potential") applyLandscape($("potential").value);
      restart();
    });
  }
  for (const el of document.getElementsByName("schedule")) {
    el.addEventListener("change", () => {
      forgetAddressProblem("schedule");
      restart();
    });
  }
  for (const el of document.getElementsByName("show")) {
    el.addEventListener("change", () => {
      forgetAddressProblem("show");
      writeUrl();
      refreshBackground(true);
      render();
    });
  }
  for (const id of VIEW_INPUTS) {
    $(id).addEventListener("change", () => {
      forgetAddressProblem(id);
      $(`err-${id}`).textContent = "";
      $(id).removeAttribute("aria-invalid");
      const v = parseNumber(text(id));
      if (id === "spf" && !(Number.isInteger(v) && v >= 1)) fieldError(id, "must be a whole number, 1 or more: 1 is used");
      if (id === "eps" && !(v >= 0)) fieldError(id, "must be a number, 0 or more");
      writeUrl();
      render();
    });
  }
  $("controls").addEventListener("submit", (e) => e.preventDefault());
  $("play").addEventListener("click", () => setPlaying(!state.playing));
  $("step").addEventListener("click", step);
  $("reset").addEventListener("click", restart);
  $("random-seed").addEventListener("click", () => {
    $("seed").value = sim.randomSeed().toString();
    forgetAddressProblem("seed");
    restart();
  });
  const transport = new Set(["play", "step", "reset"]);
  document.addEventListener("keydown", (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    const target = e.target;
    if (target.closest("input, select, textarea")) return;
    const onButton = target.closest("button");
    if (e.key === " ") {
      // On Play, Step or Reset (focused by a click), space is the play
      // shortcut, not a second press of that button.
      if (onButton && !transport.has(onButton.id)) return;
      e.preventDefault();
      setPlaying(!state.playing);
    } else if (e.key === ".") {
      step();
    } else if (e.key === "r") {
      restart();
    }
  });
  // A button is pressed by space on key up: on the transport buttons that
  // would undo the shortcut.
  document.addEventListener("keyup", (e) => {
    if (e.key === " " && transport.has(e.target.id)) e.preventDefault();
  });
  new ResizeObserver(() => layout()).observe($("canvas-wrap"));
  for (const id of ["plot-best", "plot-prob", "plot-mx", "plot-my"]) new ResizeObserver(() => render()).observe($(id));
}

/** One frame of steps, paused: as much as the budget allows now, the rest on the next frames. */
function step() {
  setPlaying(false);
  if (state.runs.length === 0) return;
  state.pending += stepsPerFrame();
  state.pending -= stepFrame(state.pending);
  render();
}

/** Says on the page that nothing can run, and why. */
function fatal(message) {
  const el = $("load-error");
  el.textContent = message;
  el.hidden = false;
}

async function main() {
  try {
    sim = await import("./sim.js");
    await sim.loadKernel();
  } catch (e) {
    fatal(
      `The WebAssembly kernel could not be loaded (${e.message}). Run scripts/serve.sh in the repository ` +
        "(it builds the module into web/pkg/ and serves the page), then open the address it prints.",
    );
    return;
  }
  const select = $("potential");
  for (const name of sim.potentialNames()) {
    select.add(new Option(LANDSCAPES[name]?.label ?? name, name));
  }
  applyLandscape("rastrigin");
  readUrl();
  wire();
  restart();
  // For the browser tests: the runs, and a way to replace the budget's clock.
  window.hrlaDemo = { state, stepWithin, setClock: (now) => (state.now = now) };
  document.body.dataset.ready = "true";
  requestAnimationFrame(tick);
}

main().catch((e) => fatal(`The demo stopped: ${e.message}`));
