// The demo page: controls -> settings -> wasm run -> canvases, plots and
// readouts, one batch of steps per animation frame.

import { loadKernel, maxChains, randomSeed, Run, Summary } from "./sim.js";
import { Frame, drawChains, drawLandscape } from "./landscape.js";
import { drawLinePlot, formatCount } from "./plots.js";

const $ = (id) => document.getElementById(id);

/** Inputs that define a run: changing one restarts from the seed. */
const RUN_INPUTS = ["sampler", "h", "chains", "a", "aLow", "aHigh", "K", "cx", "cy", "spread", "seed", "group"];
/** Inputs that only change the display or the pace (no restart). */
const VIEW_INPUTS = ["spf", "eps"];
/** Frames of trail behind each chain. */
const TRAIL = 16;

const state = {
  run: null,
  playing: true,
  frame: null,
  dpr: 1,
  half: 10,
  probability: new Float64Array(1024),
  // Rates over the last second.
  meter: { since: performance.now(), frames: 0, steps: 0, chainSteps: 0 },
};

function number(id) {
  const text = $(id).value.trim();
  // Number("") is 0: an empty field must be refused, not read as zero.
  return text === "" ? NaN : Number(text);
}

function schedule() {
  return $("schedule-linear").checked ? "linear" : "constant";
}

/** The settings object of the wasm Optimizer, from the controls. */
function readSettings() {
  const seedText = $("seed").value.trim();
  if (!/^[0-9]+$/.test(seedText)) {
    throw new Error("`seed` must be a whole number between 0 and 2^64 - 1");
  }
  return {
    sampler: $("sampler").value,
    a: number("a"),
    annealing: schedule() === "linear" ? { aLow: number("aLow"), aHigh: number("aHigh"), steps: number("K") } : null,
    h: number("h"),
    chains: number("chains"),
    centre: [number("cx"), number("cy")],
    spread: number("spread"),
    seed: BigInt(seedText),
  };
}

function groupSize(chains) {
  const n = number("group");
  if (!(Number.isInteger(n) && n >= 1 && n <= chains)) {
    throw new Error(`the group size n must be a whole number between 1 and the number of chains (${chains})`);
  }
  return n;
}

/** Half-width of the square view: the start's bulk and the minimum both show. */
function viewHalf(settings) {
  const [cx, cy] = settings.centre;
  const reach = Math.max(Math.abs(cx), Math.abs(cy)) + 2 * settings.spread;
  return Number.isFinite(reach) ? Math.min(20, Math.max(4, Math.ceil(reach))) : 10;
}

/** Inputs named by the kernel's and the wrapper's messages (`name`). */
const NAMED_INPUTS = {
  h: ["h"],
  a: ["a"],
  a_low: ["aLow"],
  a_high: ["aHigh"],
  steps: ["K"],
  chains: ["chains"],
  std_dev: ["spread"],
  mean: ["cx", "cy"],
  seed: ["seed"],
  sampler: ["sampler"],
};

function showError(message) {
  $("error").textContent = message;
  const name = /^`([a-z_]+)`/.exec(message)?.[1];
  for (const id of NAMED_INPUTS[name] ?? []) $(id).setAttribute("aria-invalid", "true");
  if (/group size/.test(message)) $("group").setAttribute("aria-invalid", "true");
  // The kernel's AllDiverged: "all N chains diverged (...): try a smaller step h".
  if (/^all \d+ chains diverged/.test(message)) $("h").setAttribute("aria-invalid", "true");
}

function clearError() {
  $("error").textContent = "";
  for (const el of document.querySelectorAll("[aria-invalid]")) el.removeAttribute("aria-invalid");
}

/** Starts the run the controls describe, from its seed. */
function restart() {
  clearError();
  state.run?.free();
  state.run = null;
  let settings;
  try {
    settings = readSettings();
    state.run = new Run(settings, groupSize(settings.chains), TRAIL);
  } catch (e) {
    showError(e.message);
  }
  if (settings) {
    const half = viewHalf(settings);
    if (half !== state.half) {
      state.half = half;
      layout(true);
    }
  }
  syncSchedule();
  writeUrl();
  resetMeter();
  render();
}

function advance() {
  const run = state.run;
  if (!run) return;
  const steps = Math.max(1, Math.floor(number("spf")) || 1);
  try {
    run.advance(steps);
  } catch (e) {
    showError(e.message);
    setPlaying(false);
    return;
  }
  state.meter.steps += steps;
  state.meter.chainSteps += steps * run.n;
}

function resetMeter() {
  state.meter = { since: performance.now(), frames: 0, steps: 0, chainSteps: 0 };
}

function tick() {
  if (state.playing) advance();
  state.meter.frames++;
  const now = performance.now();
  const dt = (now - state.meter.since) / 1000;
  if (dt >= 1) {
    const m = state.meter;
    setOutput("out-fps", (m.frames / dt).toFixed(1), m.frames / dt);
    setOutput("out-rate", state.playing ? formatCount(Math.round(m.steps / dt)) : "–", m.steps / dt);
    setOutput("out-chain-rate", state.playing ? formatCount(Math.round(m.chainSteps / dt)) : "–", m.chainSteps / dt);
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

function render() {
  const run = state.run;
  const frame = state.frame;
  if (!frame) return;
  const canvas = $("particles");
  if (!run) {
    // No run (refused settings): nothing stale may remain on screen.
    for (const c of [canvas, $("plot-best"), $("plot-prob")]) c.getContext("2d").clearRect(0, 0, c.width, c.height);
    for (const id of ["out-iteration", "out-best", "out-best-x", "out-best-at", "out-a", "out-diverged", "out-prob"]) {
      setOutput(id, "–");
    }
    return;
  }
  const s = run.s;
  drawChains(canvas, frame, state.dpr, run.trails, run.x, run.n, [s[Summary.BestX0], s[Summary.BestX1]]);
  drawLinePlot($("plot-best"), run.iters, run.best, run.count, { log: true, color: "#ff5a36" });
  const eps = number("eps");
  run.probabilitySeries(eps, state.probability);
  drawLinePlot($("plot-prob"), run.iters, state.probability, run.count, {
    log: false,
    yMin: 0,
    yMax: 1,
    yTicks: [0, 0.5, 1],
    color: "#35b779",
  });

  setOutput("out-iteration", String(s[Summary.Iteration]), s[Summary.Iteration]);
  const best = s[Summary.BestValue];
  setOutput("out-best", best.toExponential(3), best);
  setOutput("out-best-x", `(${coordinate(s[Summary.BestX0])}, ${coordinate(s[Summary.BestX1])})`);
  setOutput("out-best-at", String(s[Summary.BestIteration]), s[Summary.BestIteration]);
  setOutput("out-a", s[Summary.A].toPrecision(4), s[Summary.A]);
  setOutput("out-diverged", `${s[Summary.Diverged]} of ${run.n}`, s[Summary.Diverged]);
  const p = run.fractionWithin(eps);
  setOutput("out-prob", Number.isFinite(p) ? `${p.toFixed(2)} of ${run.groups}` : "–", p);
}

/** A coordinate in at most 9 characters, without rounding a small one to 0. */
function coordinate(v) {
  return v !== 0 && Math.abs(v) < 1e-3 ? v.toExponential(2) : v.toFixed(4);
}

/** Sizes the canvases to their boxes; redraws the landscape when needed. */
function layout(force = false) {
  const wrap = $("canvas-wrap");
  const size = Math.floor(wrap.clientWidth);
  const dpr = window.devicePixelRatio || 1;
  if (!force && state.frame && state.frame.size === size && state.dpr === dpr) return;
  state.dpr = dpr;
  state.frame = new Frame(size, state.half);
  for (const id of ["landscape", "particles"]) {
    const c = $(id);
    c.width = Math.round(size * dpr);
    c.height = Math.round(size * dpr);
  }
  drawLandscape($("landscape"), state.frame, dpr);
  render();
}

function syncSchedule() {
  const linear = schedule() === "linear";
  $("a").disabled = linear;
  for (const id of ["aLow", "aHigh", "K"]) $(id).disabled = !linear;
}

function setPlaying(on) {
  state.playing = on;
  $("play").textContent = on ? "Pause" : "Play";
  $("play").setAttribute("aria-pressed", String(on));
  resetMeter();
}

// Every setting lives in the address, so a run can be shared and replayed.
function writeUrl() {
  const q = new URLSearchParams();
  for (const id of [...RUN_INPUTS, ...VIEW_INPUTS]) q.set(id, $(id).value);
  q.set("schedule", schedule());
  history.replaceState(null, "", `?${q}`);
}

function readUrl() {
  const q = new URLSearchParams(location.search);
  for (const id of [...RUN_INPUTS, ...VIEW_INPUTS]) {
    if (q.has(id)) $(id).value = q.get(id);
  }
  if (q.get("schedule") === "linear") $("schedule-linear").checked = true;
  if (q.get("play") === "0") setPlaying(false);
}

function wire() {
  for (const id of RUN_INPUTS) $(id).addEventListener("change", restart);
  for (const el of document.getElementsByName("schedule")) el.addEventListener("change", restart);
  for (const id of VIEW_INPUTS) {
    $(id).addEventListener("change", () => {
      writeUrl();
      render();
    });
  }
  $("controls").addEventListener("submit", (e) => e.preventDefault());
  $("play").addEventListener("click", () => setPlaying(!state.playing));
  $("step").addEventListener("click", () => {
    setPlaying(false);
    advance();
    render();
  });
  $("reset").addEventListener("click", restart);
  $("random-seed").addEventListener("click", () => {
    $("seed").value = randomSeed().toString();
    restart();
  });
  document.addEventListener("keydown", (e) => {
    if (e.target.closest("input, select, textarea, button") || e.ctrlKey || e.metaKey || e.altKey) return;
    if (e.key === " ") {
      e.preventDefault();
      setPlaying(!state.playing);
    } else if (e.key === ".") {
      $("step").click();
    } else if (e.key === "r") {
      restart();
    }
  });
  new ResizeObserver(() => layout()).observe($("canvas-wrap"));
  for (const id of ["plot-best", "plot-prob"]) new ResizeObserver(() => render()).observe($(id));
}

async function main() {
  await loadKernel();
  $("chains").max = String(maxChains());
  readUrl();
  wire();
  restart();
  layout(true);
  document.body.dataset.ready = "true";
  requestAnimationFrame(tick);
}

main().catch((e) => showError(`the demo could not start: ${e.message}`));
