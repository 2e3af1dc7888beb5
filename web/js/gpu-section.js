// The page's WebGPU section: where the browser offers an adapter, up to 10^6
// chains of the page's settings on the device, drawn as their density over
// the view; where it does not, the section says so and the page's runs
// (on the CPU, in WebAssembly) are all there is.
//
// For the browser tests: `window.hrlaGpu` holds the run, and the section's
// state is in data attributes (`#gpu-status[data-state]`, each readout's
// `data-value`). Steps happen only on "+ steps" (an exact count) or Play.

import { GpuRun, findAdapter, maxGpuChains, openDevice, paintDensity } from "./gpu.js";
import { VIRIDIS } from "./colormap.js";

/** Bins per side of the density. */
const BINS = 256;

const $ = (id) => document.getElementById(id);

function setOutput(id, text, value) {
  const el = $(id);
  el.textContent = text;
  el.dataset.value = String(value);
}

function setState(state, message) {
  const el = $("gpu-status");
  el.dataset.state = state;
  el.textContent = message;
}

/**
 * Over the density (on its own canvas, so that the density's pixels stay
 * the counts' colours): the global minimisers as crosses, the axes where
 * they cross the view, and the view's box in words.
 */
function drawMarks(box, minimisers) {
  const canvas = $("gpu-marks");
  const size = Math.round(canvas.clientWidth * (window.devicePixelRatio || 1)) || 512;
  canvas.width = canvas.height = size;
  const ctx = canvas.getContext("2d");
  const [x0, x1, y0, y1] = box;
  const px = (x) => ((x - x0) / (x1 - x0)) * size;
  const py = (y) => ((y1 - y) / (y1 - y0)) * size;
  ctx.strokeStyle = "rgba(255, 255, 255, 0.25)";
  ctx.lineWidth = 1;
  ctx.beginPath();
  if (x0 < 0 && x1 > 0) ctx.moveTo(px(0), 0), ctx.lineTo(px(0), size);
  if (y0 < 0 && y1 > 0) ctx.moveTo(0, py(0)), ctx.lineTo(size, py(0));
  ctx.stroke();
  ctx.strokeStyle = "rgba(255, 90, 54, 0.9)";
  ctx.lineWidth = 2;
  const arm = size / 40;
  for (const [x, y] of minimisers) {
    ctx.beginPath();
    ctx.moveTo(px(x) - arm, py(y) - arm);
    ctx.lineTo(px(x) + arm, py(y) + arm);
    ctx.moveTo(px(x) - arm, py(y) + arm);
    ctx.lineTo(px(x) + arm, py(y) - arm);
    ctx.stroke();
  }
  const f = (v) => +v.toPrecision(4);
  $("gpu-view").textContent = `The view [${f(x0)}, ${f(x1)}] × [${f(y0)}, ${f(y1)}] (the picture's above), ${BINS} × ${BINS} cells; crosses: the global minimisers; faint lines: the axes.`;
}

/**
 * Wires the section to the page: `page.settings()` gives the page's run
 * settings and problems ({ settings, problems }), `page.box()` the view
 * [x0, x1, y0, y1], `page.minimisers()` the landscape's global
 * minimisers, `page.cpuChains()` the CPU runs' most chains,
 * `page.annealing()` whether a schedule is chosen.
 */
export async function setUpGpuSection(page) {
  const g = { adapter: null, device: null, label: "", run: null, playing: false, busy: null, lastRate: NaN };
  window.hrlaGpu = g;
  const found = await findAdapter();
  if (!found.adapter) {
    setState(
      "unavailable",
      `No WebGPU here: ${found.why}. The chains run on the CPU, in WebAssembly, in the picture above (up to ${page.cpuChains()} of them).`,
    );
    return g;
  }
  g.adapter = found.adapter;
  g.label = found.label;
  $("gpu-panel").hidden = false;
  setState("ready", `WebGPU adapter: ${g.label}. Start runs the settings above on it.`);

  /** The device, asked for at the first start. */
  const device = async () => {
    if (g.device) return g.device;
    g.device = await openDevice(g.adapter);
    g.device.lost.then((info) => {
      if (info.reason !== "destroyed") setState("lost", `The WebGPU device was lost (${info.message}); reload the page to use it again.`);
    });
    g.device.addEventListener("uncapturederror", (e) => fail(new Error(`the device reported: ${e.error.message}`)));
    return g.device;
  };

  const fail = (e) => {
    setPlaying(false);
    $("gpu-error").textContent = e.message;
    setState("error", "The WebGPU run stopped: see the message below.");
  };

  /** Serialises the device work: one start, step or picture at a time. */
  const exclusive = (work) => {
    const next = (g.busy ?? Promise.resolve()).then(work).catch(fail);
    g.busy = next;
    return next;
  };

  const draw = async () => {
    const run = g.run;
    if (!run) return;
    const d = await run.density(page.box(), BINS, BINS);
    g.density = d;
    paintDensity($("gpu-density"), d, VIRIDIS);
    drawMarks(page.box(), page.minimisers());
    setOutput("gpu-iteration", String(run.iteration), run.iteration);
    setOutput("gpu-best", Number.isFinite(d.best) ? d.best.toExponential(3) : "–", d.best);
    setOutput("gpu-lowest", Number.isFinite(d.lowest) ? d.lowest.toExponential(3) : "–", d.lowest);
    setOutput("gpu-outside", String(d.outside), d.outside);
    setOutput("gpu-diverged", String(d.diverged), d.diverged);
    setOutput("gpu-rate", Number.isFinite(g.lastRate) ? g.lastRate.toExponential(2) : "–", g.lastRate);
    if (run.n > 0 && d.diverged === run.n) throw new Error("Every chain diverged: the step h is too long for this landscape.");
  };

  const start = () =>
    exclusive(async () => {
      $("gpu-error").textContent = "";
      $("err-gpu-chains").textContent = "";
      setPlaying(false);
      g.run?.destroy();
      g.run = null;
      $("gpu-forward").disabled = $("gpu-play").disabled = true;
      const { settings, problems } = page.settings();
      if (problems.length > 0) throw new Error(`Fix the settings above first: ${problems.map((p) => `${p.id} ${p.text}`).join("; ")}.`);
      if (page.annealing()) throw new Error("The WebGPU run takes a constant a: choose a constant a above.");
      if (typeof settings.potential !== "string") throw new Error("A formula of your own runs on the CPU only: choose a built-in landscape.");
      const text = $("gpu-chains").value.trim();
      const chains = /^[0-9]+$/.test(text) ? Number(text) : NaN;
      try {
        g.run = new GpuRun(await device(), { ...settings, chains });
      } catch (e) {
        if (e.field === "gpu-chains") $("err-gpu-chains").textContent = `N ${e.message}`;
        throw e;
      }
      setState("running", `WebGPU adapter: ${g.label}. ${chains} chains.`);
      await g.run.start();
      await draw();
      $("gpu-forward").disabled = $("gpu-play").disabled = false;
      setState("ready", `WebGPU adapter: ${g.label}. ${chains} chains at iteration ${g.run.iteration}.`);
    });

  /** `k` steps, then the picture. */
  const forward = (k) =>
    exclusive(async () => {
      if (!g.run) return;
      setState("running", `WebGPU adapter: ${g.label}. ${g.run.n} chains, stepping.`);
      const t0 = performance.now();
      await g.run.step(k);
      const seconds = (performance.now() - t0) / 1000;
      if (seconds > 0) g.lastRate = (k * g.run.n) / seconds;
      await draw();
      setState("ready", `WebGPU adapter: ${g.label}. ${g.run.n} chains at iteration ${g.run.iteration}.`);
    });

  const stepsWanted = () => {
    const k = Number($("gpu-steps").value.trim());
    return Number.isInteger(k) && k >= 1 && k <= 100000 ? k : null;
  };

  function setPlaying(on) {
    g.playing = on;
    $("gpu-play").setAttribute("aria-pressed", String(on));
    $("gpu-play").textContent = on ? "Pause" : "Play";
    if (on) loop();
  }

  async function loop() {
    while (g.playing && g.run) {
      await forward(stepsWanted() ?? 100);
      await new Promise((next) => requestAnimationFrame(next));
    }
  }

  $("gpu-start").addEventListener("click", start);
  $("gpu-forward").addEventListener("click", () => {
    const k = stepsWanted();
    if (k === null) {
      $("gpu-error").textContent = "steps per click must be a whole number from 1 to 100000";
      return;
    }
    forward(k);
  });
  $("gpu-play").addEventListener("click", () => setPlaying(!g.playing));
  g.start = start;
  g.forward = forward;
  return g;
}

export { maxGpuChains };
