// One run of the wasm optimiser as the page sees it: typed-array views into
// wasm memory, fading trails, and a bounded history for the plots.

import init, { Optimizer, Summary, max_chains, random_seed, wasm_memory } from "../pkg/hrla_wasm.js";
import { TrailBuffer } from "./landscape.js";

export { Summary };

/** Loads and instantiates the wasm module (once, before anything else). */
export const loadKernel = () => init();
/** The wrapper's capacity in chains. */
export const maxChains = () => max_chains();
/** A seed from the browser's crypto, as a BigInt. */
export const randomSeed = () => random_seed();

/** Points kept per plotted series; the history is halved when full. */
const HISTORY = 1024;

/**
 * The chains are read as `groups = floor(N / n)` independent runs of `n`
 * chains each (the paper's M runs of N = 10 chains), so that the fraction of
 * groups whose current best chain has U <= eps estimates the paper's
 * empirical probability. Leftover chains (N mod n) are not in any group.
 */
export class Run {
  constructor(settings, groupSize, trailLength) {
    // Throws an Error with the kernel's message when a setting is refused.
    this.opt = new Optimizer(settings);
    this.n = this.opt.chains();
    this.seed = this.opt.seed();
    this.groupSize = groupSize;
    this.groups = Math.floor(this.n / groupSize);
    this.trails = new TrailBuffer(trailLength, this.n);
    this.iters = new Float64Array(HISTORY);
    this.best = new Float64Array(HISTORY);
    this.groupBest = new Float64Array(HISTORY * Math.max(1, this.groups));
    this.count = 0;
    this.every = 1;
    this.snapshots = 0;
    this.bind();
    this.trails.push(this.x);
    this.record();
  }

  /** (Re)creates the views; needed after wasm memory grew. */
  bind() {
    const buffer = wasm_memory().buffer;
    this.x = new Float64Array(buffer, this.opt.positions_ptr(), 2 * this.n);
    this.y = new Float64Array(buffer, this.opt.velocities_ptr(), 2 * this.n);
    this.u = new Float64Array(buffer, this.opt.values_ptr(), this.n);
    this.s = new Float64Array(buffer, this.opt.summary_ptr(), Summary.Len);
  }

  /**
   * `steps` more steps of every live chain. Throws the kernel's Error once
   * every chain has diverged (and on every later call), or on a refused
   * temperature; the state reached is recorded first, so what the page
   * draws is where the run stopped.
   */
  advance(steps) {
    let failure = null;
    try {
      this.opt.advance(steps);
    } catch (e) {
      failure = e;
    }
    // A grown memory detaches the old buffer: its views read as empty.
    if (this.s.length === 0) this.bind();
    this.trails.push(this.x);
    this.record();
    if (failure) throw failure;
  }

  get iteration() {
    return this.s[Summary.Iteration];
  }

  free() {
    this.opt.free();
  }

  /** Fraction of groups whose current best chain has U <= eps, at history point i. */
  fractionWithin(eps, i = this.count - 1) {
    if (this.groups === 0 || i < 0) return NaN;
    let hit = 0;
    const row = this.groupBest.subarray(i * this.groups, (i + 1) * this.groups);
    for (const v of row) if (v <= eps) hit++;
    return hit / this.groups;
  }

  /** The whole probability series at eps, in `out` (length >= count). */
  probabilitySeries(eps, out) {
    for (let i = 0; i < this.count; i++) out[i] = this.fractionWithin(eps, i);
    return out;
  }

  record() {
    if (this.snapshots++ % this.every !== 0) return;
    if (this.count === HISTORY) {
      // Keep every other point and record half as often: fixed memory for
      // runs of any length.
      const g = this.groups;
      for (let i = 0; i < HISTORY / 2; i++) {
        this.iters[i] = this.iters[2 * i];
        this.best[i] = this.best[2 * i];
        this.groupBest.copyWithin(i * g, 2 * i * g, (2 * i + 1) * g);
      }
      this.count = HISTORY / 2;
      this.every *= 2;
    }
    const i = this.count++;
    this.iters[i] = this.s[Summary.Iteration];
    this.best[i] = this.s[Summary.BestValue];
    for (let g = 0; g < this.groups; g++) {
      let m = Infinity;
      for (let c = g * this.groupSize; c < (g + 1) * this.groupSize; c++) {
        // A diverged chain's value is not finite: it is never within eps.
        if (this.u[c] < m) m = this.u[c];
      }
      this.groupBest[i * this.groups + g] = m;
    }
  }
}
