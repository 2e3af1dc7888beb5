// The demo page: controls and address -> settings -> one wasm run (three in
// compare mode) -> canvases, plots and readouts, stepped within a time
// budget every animation frame.

import { LANDSCAPES, MEASURED, PAPER_AND_MEASUREMENT } from "./landscapes.js";
import { FIELDS, fieldOf, parseNumber, plain, readAddress } from "./fields.js";
import { DrawBudget, stepWithin } from "./pace.js";
import { Frame, RUN_COLOURS, colourScale, drawColourBar, drawLandscape } from "./landscape.js";
import { drawChains } from "./chains.js";
import { drawHistogram, drawLinePlot, drawSchedule, exactMarginals, formatCount, histogram } from "./plots.js";
import { describe, drawPhaseInset, drawPositionInset, readNextStep } from "./anatomy.js";
import { STAGES, drawStepView, held, sharedReach, stageAt } from "./step-view.js";
import { COMPARE_HINT, SAMPLER_HINTS } from "./words.js";
import { FORMULA_DEFAULT, customLandscape } from "./custom.js";
import { SLIDERS, advanceWithChanges, formatChanges, fromSlider, parseChanges, record, toSlider } from "./tune.js";
import { ZOOM_STEP, formatView, keyView, pan, parseView, sameView, zoomAbout } from "./view.js";
import { ddimParams, setUpDdim, withoutDdim } from "./ddim.js";
import { setUpPresets } from "./presets.js";

const $ = (id) => document.getElementById(id);

/** Controls whose change restarts the run from the seed. */
const RUN_INPUTS = ["potential", "formula", "fcx", "fcy", "fhalf", "sampler", "compare", "descent", "chains", "aLow", "aHigh", "K", "cx", "cy", "spread", "seed", "stopSteps", "stopTarget", "group"];
/** Controls that only change the display or the pace. */
const VIEW_INPUTS = ["spf", "eps"];
const SAMPLERS = ["hrla", "ula", "ola"];
/** Gradient descent's colour, beside the samplers'. */
const DESCENT_COLOUR = "#ff9f43";
/** Each run's label. */
const LABEL = { hrla: "HRLA", ula: "ULA", ola: "OLA", gd: "GD + restarts" };
/** Grid of the exact marginals, per axis. */
const MARGINAL_GRID = 240;
/** The background's grid per axis at most: beyond, the picture is scaled. */
const MAX_PIXELS = 1200;
/** Histogram bins per axis. */
const BINS = 40;
/**
 * A chain beyond this many half-widths of the landscape's view has run
 * away: no exact sampler of exp(-aU) goes there for any landscape offered,
 * so it is the step's instability, or a potential that does not hold the
 * chains.
 */
const ESCAPE_HALF_WIDTHS = 1000;
/** The settings a landscape suggests, by control, and how the notes name them. */
const SUGGESTED = { cx: "c₁", cy: "c₂", spread: "s", a: "a", aHigh: "a_high", h: "h", eps: "ε" };

let sim = null;
const state = {
  runs: [],
  /** Whether the visitor wants the run to play (it does when there is a live run). */
  playing: true,
  /** Steps the "." key asked for and the frames have not done yet. */
  pending: 0,
  frame: null,
  dpr: 1,
  view: LANDSCAPES.rastrigin.view,
  /** The landscape shown: a LANDSCAPES entry with its `name` and the wrapper's `arg`. */
  land: { ...LANDSCAPES.rastrigin, name: "rastrigin", arg: "rastrigin" },
  /** A view from the address, taken once the landscape is set. */
  pendingView: null,
  /** A drag on the picture: { x, y (client pixels at the start), view, moved }. */
  drag: null,
  /** The wrapper's estimate of a formula's U*, by formula and box. */
  estimates: new Map(),
  /** U on the plot area's pixels, and on the marginals' grid. */
  grid: null,
  marginalGrid: null,
  /** The last formula typed that could be read: drawn while the field holds one that cannot. */
  readableFormula: null,
  /** The a the background and the exact marginals were computed at. */
  shownA: NaN,
  marginals: null,
  scale: null,
  probability: [],
  gaps: [],
  /** Problems found in the address, by control (null: not a control's). */
  addressProblems: [],
  /** The values the current landscape suggested, by control. */
  suggested: {},
  /** The last step laid bare: { iteration, chain, parts: [{ sampler, colour, law, draw, drawY }] }. */
  anatomy: null,
  /** The chain whose step is laid bare. */
  anatomyChain: 0,
  /** The loupe on the picture: { since (state.now() at the step), hold (a stage index, or null: by the clock), geometry }. */
  stepView: null,
  /** What the a(t) plot shows: { points, marker } (see drawSchedule). */
  schedulePlot: null,
  /** The h and a (as typed) the run started with, and the changes made to them since, by iteration (see tune.js). */
  base: { h: "", a: "" },
  changes: [],
  /** Changes from the address, for the run the address starts. */
  pendingChanges: null,
  /** The clock of the time budget: replaceable by a test's clock. */
  now: () => performance.now(),
  lastFrame: { asked: 0, done: 0, ended: false },
  /** The trails' segments per frame, adapted to the frame rate (on state.now, a test's clock included). */
  drawBudget: new DrawBudget(() => state.now()),
  /** What the last frame drew of the trails: { ages, segments, cap }. */
  lastDraw: null,
  /** What the chains' canvas shows (see render): unchanged, it is not redrawn. */
  chainsKey: null,
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

/** The escape radius of a landscape: ESCAPE_HALF_WIDTHS of its view. */
function escapeRadius(land) {
  const v = land.view;
  return ESCAPE_HALF_WIDTHS * v.half + Math.hypot(v.cx, v.cy);
}

/** The wrapper's { minimum, minimiser } of a formula, or null when it refuses it (cached). */
function estimate(arg) {
  const key = JSON.stringify(arg);
  if (!state.estimates.has(key)) {
    let value = null;
    try {
      value = { minimum: sim.globalMinimum(arg), minimiser: [...sim.globalMinimiser(arg)] };
    } catch {
      // Refused: restart() shows why, beside the field at fault.
    }
    if (state.estimates.size > 32) state.estimates.clear();
    state.estimates.set(key, value);
  }
  return state.estimates.get(key);
}

/**
 * A built-in of the kernel's list (which the menu shows, from the wasm
 * module) that landscapes.js does not describe: plain settings around the
 * origin, its minimiser from the kernel, nothing measured in advance.
 */
function undescribed(name) {
  const minimiser = [...sim.globalMinimiser(name)];
  return {
    label: name,
    formula: "",
    about: `the kernel's built-in ${name}; U* = ${+sim.globalMinimum(name).toPrecision(6)}`,
    view: { cx: 0, cy: 0, half: 5 },
    start: { cx: 3, cy: 3, spread: 0.5 },
    a: 1,
    h: 0.01,
    eps: 0.1,
    minimisers: [minimiser],
    headline: "Nothing was measured in advance for this landscape: compare the curves.",
    compare: "Nothing was measured in advance for this landscape: the table above compares the three on this run only.",
    measured: null,
  };
}

/** The landscape the controls name: a built-in one, or the visitor's formula over its box. */
function landscapeOf(name) {
  if (name !== "formula") return { ...(LANDSCAPES[name] ?? undescribed(name)), name, arg: name };
  const [cx, cy, half] = ["fcx", "fcy", "fhalf"].map((id) => parseNumber(text(id)));
  const ok = [cx, cy, half].every(Number.isFinite) && half > 0;
  const view = ok ? { cx, cy, half } : { cx: FORMULA_DEFAULT.cx, cy: FORMULA_DEFAULT.cy, half: FORMULA_DEFAULT.half };
  const arg = { formula: $("formula").value, box: [view.cx - view.half, view.cx + view.half, view.cy - view.half, view.cy + view.half] };
  return customLandscape(arg, view, ok ? estimate(arg) : null);
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
  const land = state.land;
  if (land.name === "formula") {
    for (const id of ["fcx", "fcy", "fhalf"]) num(id);
    const half = parseNumber(text("fhalf"));
    if (Number.isFinite(half) && !(half > 0)) problems.push({ id: "fhalf", text: "must be a number above 0" });
  }
  const gap = num("stopTarget", true);
  const minimum = land.name === "formula" ? (estimate(land.arg)?.minimum ?? 0) : sim.globalMinimum(land.arg);
  const settings = {
    potential: land.arg,
    sampler: $("sampler").value,
    a: linear ? NaN : num("a"),
    annealing: linear ? { aLow: num("aLow"), aHigh: num("aHigh"), steps: num("K") } : null,
    h: num("h"),
    chains: num("chains"),
    centre: [num("cx"), num("cy")],
    spread: num("spread"),
    seed: problems.some((p) => p.id === "seed") ? 0n : BigInt(seedText),
    stopSteps: num("stopSteps", true),
    stopTarget: gap === null ? null : minimum + gap,
    escape: escapeRadius(land),
  };
  return { settings, problems };
}

/** `settings` with the control `id`'s part replaced by a value the kernel accepts. */
function withFallback(settings, id) {
  const l = state.land;
  const s = { ...settings, centre: [...settings.centre] };
  const annealing = s.annealing && { ...s.annealing };
  switch (id) {
    case "h":
      s.h = l.h;
      break;
    case "a":
      s.a = l.a;
      break;
    case "aLow":
      if (annealing) annealing.aLow = 0.1;
      break;
    case "aHigh":
      if (annealing) annealing.aHigh = l.a;
      break;
    case "K":
      if (annealing) annealing.steps = 10000;
      break;
    case "chains":
      s.chains = 256;
      break;
    case "cx":
    case "cy":
      s.centre = [l.start.cx, l.start.cy];
      break;
    case "spread":
      s.spread = l.start.spread;
      break;
    case "seed":
      s.seed = 1n;
      break;
    case "stopSteps":
      s.stopSteps = null;
      break;
    case "stopTarget":
      s.stopTarget = null;
      break;
    case "sampler":
      s.sampler = "hrla";
      break;
    default:
      return null;
  }
  s.annealing = annealing;
  return s;
}

/**
 * Every setting the kernel refuses, not only the first: each refusal's
 * field is given an accepted value and the settings are tried again, so
 * that every bad field is named at once, each in the kernel's own words.
 * Returns [{ id, text }] (id null for a refusal of no field).
 */
function refusals(settings, problems) {
  const found = [];
  let s = settings;
  for (const p of problems) s = withFallback(s, p.id) ?? s;
  const seen = new Set(problems.map((p) => p.id));
  for (let tries = 0; tries <= FIELDS.length; tries++) {
    try {
      sim.probe(s);
      return found;
    } catch (e) {
      const id = fieldOf(e);
      found.push({ id, text: plain(e.message), column: e.column });
      const next = id && !seen.has(id) ? withFallback(s, id) : null;
      if (!next) return found;
      seen.add(id);
      s = next;
    }
  }
  return found;
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

/** Under the formula as typed, a caret at the column where reading stopped. */
function showCaret(column) {
  const typed = $("formula").value;
  const caret = $("formula-caret");
  caret.textContent = `${typed}\n${" ".repeat(Math.max(0, column - 1))}^`;
  caret.dataset.column = String(column);
  caret.hidden = false;
}

function clearErrors() {
  $("formula-caret").hidden = true;
  $("error").textContent = "";
  for (const el of document.querySelectorAll(".field-error")) el.textContent = "";
  for (const el of document.querySelectorAll("[aria-invalid]")) el.removeAttribute("aria-invalid");
  for (const p of state.addressProblems) fieldError(p.id ?? "general", p.text);
}

// ---- The run. ----

function clearRuns() {
  for (const run of state.runs) run.free();
  state.runs = [];
}

/**
 * Starts the run(s) the controls describe, from the seed. With `replay`,
 * the same run again: from the h and a it started with, their changes
 * applied at the same iterations; without, from the values shown, with no
 * changes.
 */
function restart(replay = false) {
  if (replay) {
    $("h").value = state.base.h;
    $("a").value = state.base.a;
  } else {
    state.changes = state.pendingChanges ?? [];
    state.pendingChanges = null;
  }
  state.base = { h: $("h").value, a: $("a").value };
  syncSliders();
  clearRuns();
  clearErrors();
  state.pending = 0;
  state.anatomy = null;
  state.stepView = null;
  const land = landscapeOf($("potential").value);
  if (JSON.stringify(land.arg) !== JSON.stringify(state.land.arg) || !state.grid) {
    state.view = state.pendingView ?? land.view;
    state.pendingView = null;
    state.grid = null;
  }
  state.land = land;
  $("formula-fields").hidden = land.name !== "formula";
  describeLandscape();
  const { settings, problems } = readSettings();
  let n = 10;
  try {
    n = groupSize();
  } catch (e) {
    problems.push({ id: e.id, text: e.message });
  }
  const compare = $("compare").checked;
  $("sampler").disabled = compare;
  const samplers = compare ? SAMPLERS : [settings.sampler];
  const refused = [...problems, ...refusals({ ...settings, sampler: samplers[0] }, problems.filter((p) => p.id !== "group"))];
  for (const p of refused) {
    if (p.id) fieldError(p.id, p.text);
    else $("error").textContent = p.text;
    if (p.id === "formula" && p.column) showCaret(p.column);
  }
  if (refused.length === 0) {
    try {
      state.runs = samplers.map((sampler) => new sim.Run({ ...settings, sampler }, n));
      if ($("descent").checked) {
        // Restarts cover the landscape's own box, whatever the zoom.
        const v = state.land.view;
        state.runs.push(new sim.Run({ ...settings, sampler: samplers[0] }, n, [v.cx - v.half, v.cx + v.half, v.cy - v.half, v.cy + v.half]));
      }
    } catch (e) {
      // Refused by one sampler only (the settings passed HRLA's check).
      clearRuns();
      const id = fieldOf(e);
      if (id) fieldError(id, plain(e.message));
      else $("error").textContent = plain(e.message);
    }
  }
  if (state.runs.length === 0) {
    const count = document.querySelectorAll("[aria-invalid]").length;
    $("error").textContent ||= `No run: ${count === 1 ? "a setting is" : `${count} settings are`} refused (marked beside ${count === 1 ? "it" : "them"}).`;
  } else if (n > state.runs[0].n) {
    $("err-group").textContent = `only ${state.runs[0].n} chains: one group of ${state.runs[0].n}`;
  }
  // Each run takes the recorded changes of h and a from the first.
  for (const run of state.runs) run.applied = 0;
  if (state.anatomyChain >= (state.runs[0]?.n ?? 0)) state.anatomyChain = 0;
  syncControls();
  writeUrl();
  resetMeter();
  layout(true);
}

/** Each run's colour: white for a single sampler, the run colours in compare mode, orange for descent. */
function coloursOf(runs) {
  const samplers = runs.filter((r) => !r.descent).length;
  let k = 0;
  return runs.map((r) => (r.descent ? DESCENT_COLOUR : samplers > 1 ? RUN_COLOURS[k++] : "#ffffff"));
}

/** Whether any run can still step. */
const anyLive = () => state.runs.some((r) => r.live);

/** A run's failure, said once: in the alert, with its field marked and a short hint there. */
function showFailure(run, e) {
  const multi = state.runs.length > 1;
  $("error").textContent = (multi ? `${LABEL[run.sampler]} stopped: ` : "") + plain(e.message);
  const id = fieldOf(e);
  if (id === "h") {
    $("err-h").textContent = "too long for this landscape: try a smaller h";
    $("h").setAttribute("aria-invalid", "true");
  } else if (id) {
    $(id)?.setAttribute("aria-invalid", "true");
  }
}

/** Advances every live run by k steps, each recorded change of h and a at its iteration; false once none can go on. */
function advanceRuns(k) {
  for (const run of state.runs) {
    if (!run.live) continue;
    try {
      advanceWithChanges(run, k, state.changes, retuneRun);
    } catch (e) {
      showFailure(run, e);
    }
  }
  return anyLive();
}

// ---- h and a on the running chains (see tune.js). ----

/** Applies one recorded change to a run, and shows its values. */
function retuneRun(run, change) {
  // Descent's steps are its own: it keeps the h it started with, in a replay too.
  if (!run.descent) run.opt.retune(change.h, annealing() ? null : change.a);
  run.rebind();
  $("h").value = String(change.h);
  if (change.a !== null) $("a").value = String(change.a);
  syncSliders();
}

const annealing = () => radio("schedule") === "linear";

/** The sliders where the fields say. */
function syncSliders() {
  for (const [id, { slider }] of Object.entries(SLIDERS)) {
    const at = toSlider(parseNumber(text(id)));
    if (at !== null) $(slider).value = at;
  }
}

/**
 * h or a changed: the running chains take the new value from where they
 * are, and the change is recorded at this iteration. Before the first
 * step, or with no run going on, the run starts afresh instead.
 */
function tune(id) {
  forgetAddressProblem(id);
  const runs = state.runs.filter((r) => !r.descent && r.live);
  const at = runs[0]?.iteration ?? 0;
  if (runs.length === 0 || at === 0 || runs.some((r) => r.iteration !== at)) {
    restart();
    return;
  }
  $(`err-${id}`).textContent = "";
  $(id).removeAttribute("aria-invalid");
  const h = parseNumber(text("h"));
  const a = annealing() ? null : parseNumber(text("a"));
  const change = { k: at, h, a };
  try {
    runs[0].opt.retune(h, a);
  } catch (e) {
    // Refused: the run goes on as it was, the field says why.
    fieldError(fieldOf(e) ?? id, plain(e.message));
    return;
  }
  try {
    for (const run of runs.slice(1)) run.opt.retune(h, a);
  } catch {
    // Another sampler refuses what the first took: that run cannot go on as it was.
    restart();
    return;
  }
  for (const run of state.runs) run.rebind();
  state.changes = record(state.changes, change);
  for (const run of state.runs) run.applied = state.changes.length;
  syncSliders();
  writeUrl();
  render();
}

/** Up to `wanted` steps within the frame's time budget; returns the steps done. */
function stepFrame(wanted) {
  if (!anyLive() || wanted <= 0) return 0;
  const { done } = stepWithin(wanted, advanceRuns, state.now);
  const ended = !anyLive();
  state.lastFrame = { asked: wanted, done, ended };
  state.meter.steps += done;
  if (ended) {
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
  state.drawBudget.frame();
  render();
  if (state.stepView && !state.stepView.settled) drawStepViewNow();
  requestAnimationFrame(tick);
}

/** Writes a readout; `exact` (a number) goes to data-value for scripts. */
function setOutput(id, text, exact) {
  const el = $(id);
  if (el.textContent !== text) el.textContent = text;
  el.dataset.value = exact === undefined ? "" : String(exact);
}

// ---- One step laid bare. ----

/**
 * One step of every live run, paused, with the law of the chosen chain's
 * step read from the kernel before it and the draw after it.
 */
function stepOnce() {
  setPlaying(false);
  state.pending = 0;
  if (!anyLive()) return;
  const c = state.anatomyChain;
  const before = state.runs.map((run) => {
    if (!run.live || run.descent || run.isLost(c)) return null;
    try {
      return readNextStep(run.nextStep(c));
    } catch {
      // A chain that diverged has no next step: nothing to lay bare.
      return null;
    }
  });
  advanceRuns(1);
  state.lastFrame = { asked: 1, done: 1, ended: !anyLive() };
  if (!anyLive()) setPlaying(false);
  const colours = coloursOf(state.runs);
  state.anatomy = {
    iteration: state.runs[0].iteration,
    chain: c,
    parts: state.runs
      .map((run, k) => {
        run.rebind();
        const law = before[k];
        if (!law) return null;
        return { sampler: run.sampler, colour: colours[k], law, draw: [run.x[2 * c], run.x[2 * c + 1]], drawY: [run.y[2 * c], run.y[2 * c + 1]] };
      })
      .filter(Boolean),
  };
  buildAnatomy();
  render();
  // Reduced motion: the finished step at once, no build-up.
  const still = matchMedia("(prefers-reduced-motion: reduce)").matches;
  state.stepView = { since: state.now(), hold: still ? STAGES.length - 1 : null, settled: false, geometry: null };
  drawStepViewNow();
}

/** Draws the loupe at its stage (held, or by the time since the step); returns its geometry. */
function drawStepViewNow() {
  const canvas = $("step-overlay");
  const v = state.stepView;
  const parts = state.anatomy?.parts ?? [];
  if (!v || parts.length === 0 || !state.frame) {
    canvas.getContext("2d").clearRect(0, 0, canvas.width, canvas.height);
    canvas.dataset.stage = "";
    canvas.dataset.settled = "false";
    return null;
  }
  const shown = v.hold === null ? stageAt(state.now() - v.since) : held(v.hold);
  const labelled = parts.map((p) => ({ ...p, label: LABEL[p.sampler], hasVelocity: p.sampler !== "ola" }));
  v.geometry = drawStepView(canvas, state.frame, state.dpr, labelled, shown);
  v.settled = shown.settled;
  canvas.dataset.stage = STAGES[shown.stage];
  canvas.dataset.settled = String(shown.settled);
  canvas.dataset.magnification = String(v.geometry.magnification);
  canvas.setAttribute("aria-label", `The step of chain ${state.anatomy.chain}, magnified ×${Math.round(v.geometry.magnification)}: ${STAGES.slice(0, shown.stage + 1).join(", ")}`);
  return v.geometry;
}

/** Holds the loupe at stage `name` (one of STAGES), for the tests; returns its geometry. */
function holdStage(name) {
  if (!state.stepView) return null;
  state.stepView.hold = STAGES.indexOf(name);
  return drawStepViewNow();
}

/** The anatomy panel's canvases and words, one column per run. */
function buildAnatomy() {
  const a = state.anatomy;
  const box = $("anatomy-runs");
  box.replaceChildren();
  if (!a || a.parts.length === 0) return;
  $("anatomy-intro").textContent =
    `Step ${a.iteration - 1} → ${a.iteration} of chain ${a.chain} (ringed in the picture), at a = ${+a.parts[0].law.a.toPrecision(4)}, ` +
    `magnified${a.parts.length > 1 ? ", all at one magnification" : ""}. Click a chain in the picture to follow another one; Step (s) takes the next step.`;
  for (const part of a.parts) {
    const column = document.createElement("div");
    column.className = "anatomy-run";
    const title = document.createElement("h3");
    title.innerHTML = `<span class="swatch" style="background:${part.colour}"></span>${LABEL[part.sampler]} <span class="zoom"></span>`;
    const position = document.createElement("canvas");
    position.className = "position";
    position.setAttribute("role", "img");
    position.setAttribute("aria-label", `${part.sampler.toUpperCase()}: the step in the position plane, magnified`);
    const phase = document.createElement("canvas");
    phase.className = "phase";
    phase.setAttribute("role", "img");
    phase.setAttribute("aria-label", `${part.sampler.toUpperCase()}: the step's law of the first coordinate's position and velocity`);
    const list = document.createElement("ol");
    list.innerHTML = describe(part.sampler, part.law, part.draw)
      .map((t) => `<li>${t}</li>`)
      .join("");
    column.append(title, position, phase, list);
    box.append(column);
  }
  $("anatomy").hidden = false;
  drawAnatomy();
}

/** Draws the insets; returns their geometry (see drawPositionInset). */
function drawAnatomy() {
  const a = state.anatomy;
  if (!a) return [];
  const columns = $("anatomy-runs").children;
  // One magnification for every sampler: their steps' sizes compare.
  const reach = sharedReach(a.parts);
  return a.parts.map((part, k) => {
    const geometry = drawPositionInset(columns[k].querySelector("canvas.position"), part.law, part.draw, reach);
    drawPhaseInset(columns[k].querySelector("canvas.phase"), part.law, [part.draw[0], part.drawY[0]]);
    const zoom = geometry.scale / (state.frame.width / (state.frame.x1 - state.frame.x0));
    columns[k].querySelector(".zoom").textContent = `magnified ×${formatCount(Math.round(zoom))}`;
    return { ...geometry, zoom };
  });
}

/** Hides the panel once the run has moved on or restarted. */
function syncAnatomy() {
  const a = state.anatomy;
  const current = a && state.runs.length > 0 && state.runs[0].iteration === a.iteration;
  if (!current && !$("anatomy").hidden) {
    $("anatomy").hidden = true;
    state.anatomy = null;
    state.stepView = null;
    drawStepViewNow();
  }
}

/** Picks the chain nearest a click on the picture for the next step laid bare. */
function pickChain(event) {
  const run = state.runs[0];
  if (!run) return;
  const box = $("particles").getBoundingClientRect();
  const px = event.clientX - box.left;
  const py = event.clientY - box.top;
  let best = -1;
  let bestD = Infinity;
  for (let c = 0; c < run.n; c++) {
    if (run.isLost(c)) continue;
    const d = Math.hypot(state.frame.px(run.x[2 * c]) - px, state.frame.py(run.x[2 * c + 1]) - py);
    if (d < bestD) {
      bestD = d;
      best = c;
    }
  }
  if (best >= 0 && bestD < 24) {
    state.anatomyChain = best;
    render();
  }
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
  const land = state.land;
  if (!state.grid || state.grid.w !== w || state.grid.h !== h) {
    const grid = landscapeGrid(land, frame, w, h);
    if (!grid) return;
    state.grid = { w, h, u: grid.u, undefinedCells: grid.undefinedCells };
    state.marginalGrid = grid.undefinedCells ? null : landscapeGrid(land, frame, MARGINAL_GRID, MARGINAL_GRID)?.u;
  }
  const minimum = land.name === "formula" ? lowestFinite(state.grid.u) : sim.globalMinimum(land.arg);
  $("potential-undefined").hidden = !state.grid.undefinedCells;
  if (force || mode === "density") {
    state.scale = colourScale(state.grid.u, mode, a, minimum);
    drawLandscape($("landscape"), frame, state.dpr, state.scale, w, h, land.minimisers);
    drawColourBar($("colorbar"), state.scale);
  }
  // Where a formula is not finite there is no law to draw beside the chains.
  state.marginals = state.marginalGrid && exactMarginals(state.marginalGrid, MARGINAL_GRID, MARGINAL_GRID, a, frame.x1 - frame.x0, frame.y1 - frame.y0);
}

/**
 * U over the frame on a w × h grid: { u, undefinedCells }. A formula is
 * drawn wherever it is finite, its undefined cells left dark, so that a
 * refused formula (or one seen beyond its box) still shows where it is
 * defined; null only when a formula cannot be read at all.
 */
function landscapeGrid(land, frame, w, h) {
  if (land.name !== "formula") return { u: sim.potentialGrid(land.arg, frame.x0, frame.x1, frame.y0, frame.y1, w, h), undefinedCells: 0 };
  let u;
  try {
    u = sim.formulaGrid(land.arg.formula, frame.x0, frame.x1, frame.y0, frame.y1, w, h);
    state.readableFormula = land.arg.formula;
  } catch {
    // Not a formula (the caret beside the field says why): the last one
    // that could be read stays in the picture.
    if (state.readableFormula === null) return null;
    u = sim.formulaGrid(state.readableFormula, frame.x0, frame.x1, frame.y0, frame.y1, w, h);
  }
  let undefinedCells = 0;
  for (const v of u) if (Number.isNaN(v)) undefinedCells++;
  return { u, undefinedCells };
}

/** The lowest finite value of a grid. */
function lowestFinite(u) {
  let m = Infinity;
  for (const v of u) if (v < m) m = v;
  return m;
}

function render() {
  const frame = state.frame;
  if (!frame) return;
  refreshBackground(false);
  syncAnatomy();
  syncTransport();
  const runs = state.runs;
  // The grids are allocated in wasm memory: it may have grown.
  for (const r of runs) r.rebind();
  const S = sim.Summary;
  if (runs.length === 0) {
    for (const id of ["particles", "plot-best", "plot-prob", "plot-mx", "plot-my"]) {
      const c = $(id);
      c.getContext("2d").clearRect(0, 0, c.width, c.height);
    }
    for (const id of ["out-iteration", "out-best", "out-best-x", "out-best-at", "out-a", "out-lost", "out-outside", "out-prob", "out-frame-steps"]) setOutput(id, "–");
    $("status").replaceChildren();
    delete $("status").dataset.key;
    return;
  }
  const colours = coloursOf(runs);
  const lead = runs[0];
  const c = state.anatomyChain;
  const mark = state.anatomy && !lead.isLost(c) ? [lead.x[2 * c], lead.x[2 * c + 1]] : null;
  // The budget bounds the frames that move the chains; a still picture is
  // drawn whole, once, and not again until something in it changes.
  const moving = anyLive() && (state.playing || state.pending > 0);
  const cap = moving ? state.drawBudget.cap : Infinity;
  const key = JSON.stringify([frame.size, frame.view, state.dpr, runs.map((r) => r.iteration), colours, mark, cap]);
  if (state.chainsKey !== key) {
    state.chainsKey = key;
    const drawn = drawChains(
      $("particles"),
      frame,
      state.dpr,
      runs.map((r, k) => ({ trails: r.trails, x: r.x, n: r.n, best: [r.s[S.BestX0], r.s[S.BestX1]], colour: colours[k], square: r.descent })),
      mark,
      cap,
    );
    state.lastDraw = { ...drawn, cap };
  }
  const lineColours = runs.length > 1 ? colours : ["#ff5a36"];
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
  const probColours = runs.length > 1 ? colours : ["#35b779"];
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
  drawScheduleIfAnnealing(runs[0]);
}

/** Under annealing, a(t) of the schedule with the run's place on it. */
function drawScheduleIfAnnealing(run) {
  const figure = $("schedule-figure");
  const linear = radio("schedule") === "linear";
  figure.hidden = !linear;
  state.schedulePlot = null;
  if (!linear || !run) return;
  const [aLow, aHigh, K] = ["aLow", "aHigh", "K"].map((id) => parseNumber(text(id)));
  state.schedulePlot = drawSchedule($("plot-a"), aLow, aHigh, K, run.iteration, run.s[sim.Summary.A]);
}

function drawMarginals(allRuns, allColours) {
  const f = state.frame;
  if (!state.marginals) return;
  // Descent samples no law: its histogram against exp(-aU) would mislead.
  const runs = allRuns.filter((r) => !r.descent);
  const colours = allColours.filter((_, k) => !allRuns[k].descent);
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
  const lost = r.lost();
  setOutput("out-lost", `${lost.diverged + lost.ranAway} of ${r.n}`, lost.diverged + lost.ranAway);
  $("lost-box").title =
    `Chains lost: ${lost.diverged} diverged (their position overflowed: frozen), ${lost.ranAway} ran away beyond |x| = ${formatRadius(r.escape)} ` +
    `(${ESCAPE_HALF_WIDTHS} times the view's half-width); they count as failures in P`;
  const outside = r.outside(f.x0, f.x1, f.y0, f.y1);
  setOutput("out-outside", `${outside} of ${r.n}`, outside);
  const p = r.fractionWithin(eps);
  setOutput(
    "out-prob",
    r.belowMinimum(eps) !== null
      ? "none: U went below U*"
      : Number.isFinite(p)
        ? `${p.toFixed(2)}: ${r.groupsWithin(eps)} of ${r.groups} groups of ${r.groupSize}`
        : "–",
    p,
  );
  const { asked, done, ended } = state.lastFrame;
  const why = ended ? "the run ended" : "time budget";
  setOutput("out-frame-steps", asked ? (done < asked ? `${formatCount(done)} of ${formatCount(asked)} (${why})` : `${formatCount(done)}`) : "–", done);
  // What went wrong or ended, in words, beside the picture; a failed run's
  // failure is said once, in the alert above.
  const lines = [];
  for (const run of runs) {
    if (run.failure) continue;
    const who = runs.length > 1 ? `${LABEL[run.sampler]}: ` : "";
    const l = run.lost();
    const below = run.descent ? null : run.belowMinimum(eps);
    if (below !== null) lines.push(["warn", unboundedAdvice(run, below, who)]);
    else if (l.diverged + l.ranAway > 0) {
      const parts = [];
      if (l.diverged) parts.push(`${l.diverged} diverged (their position overflowed)`);
      if (l.ranAway) parts.push(`${l.ranAway} ran away beyond |x| = ${formatRadius(run.escape)}`);
      lines.push(["warn", `${who}${parts.join(" and ")}, of ${run.n} chains: they count as failures. A smaller step h avoids this.`]);
    }
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
  $("readouts-for").textContent = `The readouts below are ${LABEL[runs[0].sampler]}'s; the table under them compares the ${runs.length} runs.`;
  if (runs.length > 1) {
    const body = table.tBodies[0];
    const key = runs.map((r) => r.sampler).join();
    if (body.dataset.key !== key) {
      body.dataset.key = key;
      const colours = coloursOf(runs);
      body.replaceChildren(
        ...runs.map((run, k) => {
          const tr = document.createElement("tr");
          tr.innerHTML = `<th scope="row"><span class="swatch" style="background:${colours[k]}"></span>${LABEL[run.sampler]}</th><td><output id="cmp-best-${run.sampler}"></output></td><td><output id="cmp-at-${run.sampler}"></output></td><td><output id="cmp-prob-${run.sampler}"></output></td><td><output id="cmp-lost-${run.sampler}"></output></td>`;
          return tr;
        }),
      );
    }
    for (const run of runs) {
      const q = run.s;
      setOutput(`cmp-best-${run.sampler}`, q[S.BestValue].toExponential(3), q[S.BestValue]);
      setOutput(`cmp-at-${run.sampler}`, String(q[S.BestIteration]), q[S.BestIteration]);
      const pr = run.fractionWithin(eps);
      setOutput(`cmp-prob-${run.sampler}`, Number.isFinite(pr) ? pr.toFixed(2) : "none", pr);
      const l = run.lost();
      setOutput(`cmp-lost-${run.sampler}`, String(l.diverged + l.ranAway), l.diverged + l.ranAway);
    }
  }
}

/** What the status says of a run whose chains went below U*: why, and what can help. */
function unboundedAdvice(run, below, who) {
  const l = run.lost();
  const down = run.ranDownhill();
  const away = down > 0 ? `${down} of ${run.n} chains ran away downhill (to U = ${below.toPrecision(3)})` : `chains went down to U = ${below.toPrecision(3)}`;
  const fix =
    state.land.name === "formula"
      ? "give U a floor (add a term that grows, such as (x^2 + y^2)^2 / 1000) or choose a box that holds its minimum"
      : "choose another landscape";
  return (
    `${who}${away}, below U* = ${+run.minimum.toPrecision(6)}: U looks unbounded below${state.land.name === "formula" ? " beyond the box" : ""}, so no success can be scored` +
    `${l.diverged + l.ranAway > 0 ? ` and the ${l.diverged + l.ranAway} lost chains count as failures` : ""}. ` +
    `No step h or temperature a holds chains on it: ${fix}.`
  );
}

/** An escape radius in a few characters. */
function formatRadius(r) {
  return Number.isFinite(r) ? String(+r.toPrecision(3)) : "∞";
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
  for (const id of ["landscape", "particles", "step-overlay"]) {
    $(id).width = Math.round(size * dpr);
    $(id).height = Math.round(size * dpr);
  }
  // Resized, the chains' canvas is blank.
  state.chainsKey = null;
  refreshBackground(true);
  render();
  drawAnatomy();
  drawStepViewNow();
}

function describeLandscape() {
  const l = state.land;
  $("potential-about").textContent = l.about;
  $("formula-shown").textContent = l.formula;
  $("compare-landscape").textContent = l.compare;
  $("compare-headline").textContent = l.headline;
  $("compare-measured").hidden = !l.measured;
  if (!l.measured) return;
  $("compare-measured-caption").textContent =
    `Success rate P on ${l.label} at its defaults (a = ${l.a}, h = ${l.h}, ε = ${l.eps}), mean over seeds 1 to ${MEASURED.seeds}, ` +
    `${MEASURED.chains} chains in groups of ${MEASURED.group}, measured on this page's kernel`;
  const head = $("compare-measured").tHead.rows[0];
  head.replaceChildren(...["method", ...MEASURED.steps.map((k) => `after ${k} steps`)].map((t) => Object.assign(document.createElement("th"), { scope: "col", textContent: t })));
  $("compare-measured").tBodies[0].replaceChildren(
    ...SAMPLERS.map((s, k) => {
      const tr = document.createElement("tr");
      tr.innerHTML = `<th scope="row"><span class="swatch" style="background:${RUN_COLOURS[k]}"></span>${s.toUpperCase()}</th>${l.measured[s].map((v) => `<td>${v.toFixed(2)}</td>`).join("")}`;
      return tr;
    }),
  );
  $("compare-paper").innerHTML = PAPER_AND_MEASUREMENT.replace("docs/REPRODUCTION.md", "<code>docs/REPRODUCTION.md</code>");
}

function syncControls() {
  const linear = radio("schedule") === "linear";
  $("a").disabled = linear;
  $("a-slider").disabled = linear;
  $("a-slider").title = linear ? "Annealing sets a at every step (a_low to a_high over K steps): change those, which restarts the run" : "";
  for (const id of ["aLow", "aHigh", "K"]) $(id).disabled = !linear;
  const compare = $("compare").checked;
  $("hint-sampler").textContent = compare ? COMPARE_HINT : SAMPLER_HINTS[$("sampler").value];
  $("compare-about").hidden = state.runs.filter((r) => !r.descent).length < 2;
  $("compare-lead").hidden = $("compare-about").hidden;
  $("descent-about").hidden = !state.runs.some((r) => r.descent);
  const legend = $("legend");
  legend.hidden = state.runs.length < 2;
  if (state.runs.length > 1) {
    const colours = coloursOf(state.runs);
    legend.innerHTML = state.runs.map((r, k) => `<span class="swatch" style="background:${colours[k]}"></span>${LABEL[r.sampler]}`).join(" ");
  }
  syncTransport();
}

/** Play and Step only when there is a live run; Play's label says what a press does. */
function syncTransport() {
  const live = anyLive();
  const playing = state.playing && live;
  const play = $("play");
  const label = playing ? "Pause" : "Play";
  if (play.textContent !== label) play.textContent = label;
  play.setAttribute("aria-pressed", String(playing));
  play.disabled = !live;
  $("step").disabled = !live;
}

function setPlaying(on) {
  state.playing = on;
  syncTransport();
  resetMeter();
  writeUrl();
}

// ---- The address: every setting, so a run can be shared and replayed. ----

function writeUrl() {
  const q = new URLSearchParams();
  for (const f of FIELDS) {
    if (f.id === "play" || f.id === "view" || f.id === "tune") continue;
    if (f.kind === "choice") q.set(f.id, radio(f.id));
    else if (f.kind === "flag") q.set(f.id, $(f.id).checked ? "1" : "0");
    else q.set(f.id, $(f.id).value);
  }
  if (!state.playing) q.set("play", "0");
  if (!sameView(state.view, state.land.view)) q.set("view", formatView(state.view));
  if (state.changes.length > 0) {
    // The run starts from the base values; the changes come at their iterations.
    q.set("h", state.base.h);
    q.set("a", state.base.a);
    q.set("tune", formatChanges(state.changes));
  }
  for (const [k, v] of ddimParams()) q.set(k, v);
  history.replaceState(null, "", `?${q}`);
}

function readUrl() {
  const { values, problems } = readAddress(withoutDdim(location.search), options);
  state.addressProblems = problems;
  // A landscape brings its own start, temperature and step first; the
  // address's other values then override them.
  if (values.potential) applyLandscape(values.potential, false);
  for (const [id, value] of Object.entries(values)) {
    const f = FIELDS.find((g) => g.id === id);
    if (f.kind === "choice") {
      if (id !== "play") $(`${id}-${value}`).checked = true;
    } else if (f.kind === "flag") $(id).checked = value === "1";
    else if (f.kind === "view") state.pendingView = parseView(value);
    else if (f.kind === "tune") state.pendingChanges = parseChanges(value);
    else if (id !== "potential") $(id).value = value;
  }
  if (values.play === "0") state.playing = false;
}

// ---- Zoom and pan: the view only; the run goes on. ----

/** Shows the landscape over `view` (within the zoom range of its own). */
function setView(view) {
  state.view = zoomAbout(view, [view.cx, view.cy], 1, state.land.view);
  state.grid = null;
  layout(true);
  writeUrl();
}

/** The landscape's point under a client position. */
function pointAt(clientX, clientY) {
  const box = $("particles").getBoundingClientRect();
  const f = state.frame;
  const px = clientX - box.left;
  const py = clientY - box.top;
  return [f.x0 + ((px - f.left) / f.width) * (f.x1 - f.x0), f.y1 - ((py - f.top) / f.height) * (f.y1 - f.y0)];
}

function wireView() {
  const canvas = $("particles");
  canvas.addEventListener(
    "wheel",
    (e) => {
      e.preventDefault();
      setView(zoomAbout(state.view, pointAt(e.clientX, e.clientY), 1.2 ** (-e.deltaY / 100), state.land.view));
    },
    { passive: false },
  );
  // Pointers down on the picture, by id: one pans (mouse, pen, or a finger
  // swiping sideways: an upward or downward swipe scrolls the page, so a
  // phone's visitor is never trapped on the picture), two pinch (zoom
  // about their midpoint, pan with it).
  const pointers = new Map();
  const gesture = () => {
    const [p, q] = [...pointers.values()];
    const mid = q ? [(p.x + q.x) / 2, (p.y + q.y) / 2] : [p.x, p.y];
    return { mid, at: pointAt(...mid), spread: q ? Math.hypot(p.x - q.x, p.y - q.y) : 0, view: state.view, moved: false };
  };
  canvas.addEventListener("pointerdown", (e) => {
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
    state.drag = pointers.size <= 2 ? gesture() : null;
    // A second finger makes a pinch, never a click.
    if (state.drag && pointers.size === 2) state.drag.moved = true;
    try {
      canvas.setPointerCapture(e.pointerId);
    } catch {
      // A pointer the browser no longer tracks: the gesture goes on uncaptured.
    }
  });
  canvas.addEventListener("pointermove", (e) => {
    if (!pointers.has(e.pointerId)) return;
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
    const d = state.drag;
    if (!d) return;
    const now = gesture();
    const dx = now.mid[0] - d.mid[0];
    const dy = now.mid[1] - d.mid[1];
    // A few pixels of jitter are still a click (which picks a chain).
    if (!d.moved && Math.hypot(dx, dy) < 4) return;
    d.moved = true;
    if (!(d.spread > 0 && now.spread > 0)) {
      const perPixel = (2 * d.view.half) / state.frame.width;
      setView(pan(d.view, [dx * perPixel, -dy * perPixel]));
      return;
    }
    // A pinch: the point first under the fingers' midpoint stays under it, at the scale their spread gives.
    const { half } = zoomAbout(d.view, [d.view.cx, d.view.cy], now.spread / d.spread, state.land.view);
    const box = canvas.getBoundingClientRect();
    const f = state.frame;
    const perPixel = (2 * half) / f.width;
    const centre = [box.left + f.left + f.width / 2, box.top + f.top + f.height / 2];
    setView({ cx: d.at[0] - (now.mid[0] - centre[0]) * perPixel, cy: d.at[1] + (now.mid[1] - centre[1]) * perPixel, half });
  });
  const end = (e) => {
    const d = state.drag;
    pointers.delete(e.pointerId);
    // A lone finger's swipe that the browser took to scroll the page (an
    // upward or downward one: touch-action pan-y) is not a pan: the view
    // goes back to where the swipe found it.
    if (d && e.type === "pointercancel" && pointers.size === 0 && d.spread === 0) setView(d.view);
    // The fingers left go on from where the view is.
    state.drag = pointers.size > 0 ? { ...gesture(), moved: true } : null;
    if (d && !d.moved && e.type === "pointerup") pickChain(e);
  };
  canvas.addEventListener("pointerup", end);
  canvas.addEventListener("pointercancel", end);
  canvas.addEventListener("keydown", (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    const view = keyView(state.view, e.key, state.land.view);
    if (!view) return;
    e.preventDefault();
    setView(view);
  });
  $("zoom-in").addEventListener("click", () => setView(zoomAbout(state.view, [state.view.cx, state.view.cy], ZOOM_STEP, state.land.view)));
  $("zoom-out").addEventListener("click", () => setView(zoomAbout(state.view, [state.view.cx, state.view.cy], 1 / ZOOM_STEP, state.land.view)));
  $("zoom-home").addEventListener("click", () => setView(state.land.view));
}

// ---- The link: the address holds every setting. ----

async function copyLink() {
  writeUrl();
  const link = location.href;
  const note = $("copy-note");
  try {
    await navigator.clipboard.writeText(link);
    note.textContent = "Link copied: it replays this run, every setting included.";
    $("link-field").hidden = true;
  } catch {
    // No clipboard (permission refused, or not a secure context): the
    // link, selected, to copy by hand.
    const field = $("link-field");
    field.value = link;
    field.hidden = false;
    field.select();
    note.textContent = "Copy the link below (Ctrl+C or ⌘C): it replays this run.";
  }
}

/** The settings landscape `name` suggests, by control. */
function suggestions(name) {
  const l = landscapeOf(name);
  return { cx: l.start.cx, cy: l.start.cy, spread: l.start.spread, a: l.a, aHigh: l.a, h: l.h, eps: l.eps };
}

/**
 * Sets the landscape and the start, a, h and ε it suggests. With `keep`,
 * a setting the visitor changed from the previous landscape's suggestion
 * is kept, and the note beside the landscape says which, with a button
 * that takes the landscape's own.
 */
function applyLandscape(name, keep) {
  const want = suggestions(name);
  const kept = [];
  for (const id of Object.keys(SUGGESTED)) {
    const mine = text(id);
    if (keep && state.suggested[id] !== undefined && mine !== String(state.suggested[id])) kept.push({ id, mine });
    else $(id).value = String(want[id]);
  }
  $("potential").value = name;
  state.suggested = want;
  const note = $("landscape-note");
  if (kept.length === 0) {
    note.replaceChildren();
    return;
  }
  const label = landscapeOf(name).label;
  note.textContent = `${label}'s suggested settings are in place, except yours: ${kept
    .map(({ id, mine }) => `kept your ${SUGGESTED[id]} = ${mine} (${label}'s: ${want[id]})`)
    .join("; ")}.`;
  const use = document.createElement("button");
  use.type = "button";
  use.id = "use-suggested";
  use.textContent = `use ${label}'s`;
  use.addEventListener("click", () => {
    for (const { id } of kept) forgetAddressProblem(id);
    applyLandscape(name, false);
    restart();
  });
  note.append(" ", use);
}

function forgetAddressProblem(id) {
  state.addressProblems = state.addressProblems.filter((p) => p.id !== id);
}

function wire() {
  for (const id of RUN_INPUTS) {
    $(id).addEventListener("change", () => {
      forgetAddressProblem(id);
      // A formula's box moves its suggested start and view as a landscape does.
      if (id === "potential" || ["formula", "fcx", "fcy", "fhalf"].includes(id)) applyLandscape($("potential").value, true);
      restart();
    });
  }
  for (const [id, { slider }] of Object.entries(SLIDERS)) {
    $(id).addEventListener("change", () => tune(id));
    // The number follows the slider as it moves; the chains take it when it is let go.
    $(slider).addEventListener("input", () => ($(id).value = String(fromSlider($(slider).value))));
    $(slider).addEventListener("change", () => {
      $(id).value = String(fromSlider($(slider).value));
      tune(id);
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
  $("step").addEventListener("click", stepOnce);
  $("reset").addEventListener("click", () => restart(true));
  wireView();
  $("copy-link").addEventListener("click", copyLink);
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
      if (anyLive()) setPlaying(!state.playing);
    } else if (e.key === ".") {
      frameOfSteps();
    } else if (e.key === "s") {
      stepOnce();
    } else if (e.key === "r") {
      restart(true);
    }
  });
  // A button is pressed by space on key up: on the transport buttons that
  // would undo the shortcut.
  document.addEventListener("keyup", (e) => {
    if (e.key === " " && transport.has(e.target.id)) e.preventDefault();
  });
  new ResizeObserver(() => layout()).observe($("canvas-wrap"));
  for (const id of ["plot-best", "plot-prob", "plot-mx", "plot-my", "plot-a"]) new ResizeObserver(() => render()).observe($(id));
}

/** One frame of steps, paused: as much as the budget allows now, the rest on the next frames. */
function frameOfSteps() {
  setPlaying(false);
  if (!anyLive()) return;
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
        "(it serves the page and its module, web/pkg/, rebuilding the module if its sources have changed), " +
        "then open the address it prints.",
    );
    return;
  }
  const select = $("potential");
  for (const name of sim.potentialNames()) {
    select.add(new Option(LANDSCAPES[name]?.label ?? name, name));
  }
  select.add(new Option("Your own U(x, y)…", "formula"));
  applyLandscape("rastrigin", false);
  readUrl();
  wire();
  restart();
  // For the browser tests: the runs, the budget's clock, the anatomy's geometry.
  window.hrlaDemo = { state, stepWithin, setClock: (now) => (state.now = now), anatomySpans: drawAnatomy, holdStage };
  document.body.dataset.ready = "true";
  requestAnimationFrame(tick);
  await setUpDdim({ paused: !state.playing, writeAddress: writeUrl });
  setUpPresets();
  // The WebGPU section (its own runs; the page's above are unchanged).
  const gpu = await import("./gpu-section.js");
  await gpu.setUpGpuSection({
    settings: readSettings,
    box: () => [state.frame.x0, state.frame.x1, state.frame.y0, state.frame.y1],
    minimisers: () => state.land.minimisers ?? [],
    cpuChains: () => sim.maxChains(),
    annealing: () => radio("schedule") === "linear",
  });
}

main().catch((e) => fatal(`The demo stopped: ${e.message}`));
