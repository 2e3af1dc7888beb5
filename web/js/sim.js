// One run of the wasm optimiser as the page sees it: typed-array views into
// wasm memory, trails that follow the chains' paths, and a bounded history
// for the plots. Imported dynamically by main.js, so that a missing
// web/pkg/ is reported on the page rather than leaving it blank.

import init, {
  Descent,
  Optimizer,
  Summary,
  formulaPicture,
  global_minimiser,
  global_minimum,
  max_chains,
  potential_grid,
  potential_names,
  random_seed,
  wasm_memory,
} from "../pkg/hrla_wasm.js";

export { Summary };

/** Loads and instantiates the wasm module (once, before anything else). */
export const loadKernel = () => init();
/** The wrapper's capacity in chains. */
export const maxChains = () => max_chains();
/** A seed from the browser's crypto, as a BigInt. */
export const randomSeed = () => random_seed();
/** The landscapes' names, in the kernel's order. */
export const potentialNames = () => potential_names();
/** The landscape's U* (the kernel's; a formula's estimate). */
export const globalMinimum = (potential) => global_minimum(potential);
/** A landscape's x* (for a formula, where its estimated U* was found). */
export const globalMinimiser = (potential) => global_minimiser(potential);
/** The kernel's U on a grid (see the wrapper's potential_grid). */
export const potentialGrid = (name, x0, x1, y0, y1, nx, ny) => potential_grid(name, x0, x1, y0, y1, nx, ny);
/** A formula's U on a grid laid out as potentialGrid's, NaN where it is not finite. */
export const formulaGrid = (text, x0, x1, y0, y1, nx, ny) => formulaPicture(text, x0, x1, y0, y1, nx, ny);
/** Throws the wrapper's Error when it refuses `settings`; creates and frees a run otherwise. */
export function probe(settings) {
  new Optimizer(settings).free();
}

/** Points kept per plotted series; the history is halved when full. */
const HISTORY = 1024;
/** Steps between two trail points: short enough to follow the path. */
export const TRAIL_STRIDE = 2;
/** Trail points kept per chain. */
export const TRAIL_POINTS = 40;

/**
 * The chains are read as `groups = floor(N / n)` independent runs of `n`
 * chains each (the paper's M runs of N = 10 chains), so that the fraction of
 * groups whose current best chain has U - U* <= eps estimates the paper's
 * empirical probability. Leftover chains (N mod n) are not in any group; a
 * group size above N is taken as N (one group).
 */
export class Run {
  /**
   * A sampler's run of `settings`; with `descentBox` ([x0, x1, y0, y1]),
   * gradient descent with random restarts in that box from the same
   * initial points instead (its values are each chain's best so far).
   */
  constructor(settings, groupSize, descentBox = null) {
    // Throws an Error with the kernel's message (and `field`) when a
    // setting is refused.
    this.opt = descentBox ? new Descent(settings, descentBox) : new Optimizer(settings);
    this.descent = descentBox !== null;
    this.sampler = this.descent ? "gd" : settings.sampler;
    /** Beyond this |x| a chain has run away (the wrapper's `escape`); descent restarts instead. */
    this.escape = this.descent ? Infinity : (settings.escape ?? Infinity);
    this.n = this.opt.chains();
    this.seed = this.opt.seed();
    this.groupSize = Math.min(groupSize, this.n);
    this.groups = Math.floor(this.n / this.groupSize);
    this.trails = new TrailBuffer(TRAIL_POINTS, this.n);
    this.sinceTrail = 0;
    this.failure = null;
    this.iters = new Float64Array(HISTORY);
    this.best = new Float64Array(HISTORY);
    this.groupBest = new Float64Array(HISTORY * Math.max(1, this.groups));
    /** The lowest U of any chain not diverged (run away included), per history point. */
    this.lowest = new Float64Array(HISTORY);
    this.count = 0;
    this.every = 1;
    this.snapshots = 0;
    this.bind();
    this.minimum = this.s[Summary.Minimum];
    this.trails.push(this.x, this.iteration);
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

  /** Whether the run can go on: not failed, not stopped by a rule. */
  get live() {
    return !this.failure && this.s[Summary.Termination] === 0;
  }

  /** Why a stopping rule ended the run, or undefined. */
  get termination() {
    return this.opt.termination();
  }

  /**
   * `steps` more steps of every live chain. Trail points are taken every
   * TRAIL_STRIDE steps over the last TRAIL_POINTS of them; steps before
   * that window go in one call, and the trail restarts after them, so a
   * trail never joins two points further apart than the stride. On the
   * kernel's error (every chain diverged, a refused temperature) the run
   * keeps the state reached, records the error in `failure` and throws it.
   */
  advance(steps) {
    if (!this.live) return;
    const window = TRAIL_POINTS * TRAIL_STRIDE;
    try {
      if (steps > window + TRAIL_STRIDE) {
        const bulk = steps - window;
        this.opt.advance(bulk);
        steps -= bulk;
        this.rebind();
        this.trails.clear();
        this.trails.push(this.x, this.iteration);
        this.sinceTrail = 0;
      }
      while (steps > 0) {
        const k = Math.min(steps, TRAIL_STRIDE - this.sinceTrail);
        this.opt.advance(k);
        steps -= k;
        this.sinceTrail += k;
        if (this.sinceTrail === TRAIL_STRIDE) {
          this.rebind();
          this.trails.push(this.x, this.iteration);
          this.sinceTrail = 0;
        }
        if (!this.live) break;
      }
    } catch (e) {
      this.failure = e;
    }
    this.rebind();
    this.record();
    if (this.failure) throw this.failure;
  }

  /** A grown memory detaches the old buffer: its views read as empty. */
  rebind() {
    if (this.s.length === 0) this.bind();
  }

  get iteration() {
    return this.s[Summary.Iteration];
  }

  free() {
    this.opt.free();
  }

  /**
   * Fraction of groups whose current best chain has U - U* <= eps, at
   * history point i; NaN when a chain was below U* by more than eps then
   * (U* is no minimum: no success can be scored against it).
   */
  fractionWithin(eps, i = this.count - 1) {
    if (this.groups === 0 || i < 0 || this.lowest[i] < this.minimum - Math.max(eps, 0)) return NaN;
    return this.groupsWithin(eps, i) / this.groups;
  }

  /** How many groups have their best chain within eps of U*, at history point i. */
  groupsWithin(eps, i = this.count - 1) {
    let hit = 0;
    const row = this.groupBest.subarray(i * this.groups, (i + 1) * this.groups);
    for (const v of row) if (v - this.minimum <= eps) hit++;
    return hit;
  }

  /** The whole probability series at eps, in `out` (length >= count). */
  probabilitySeries(eps, out) {
    for (let i = 0; i < this.count; i++) out[i] = this.fractionWithin(eps, i);
    return out;
  }

  /** Whether chain c diverged (its value is not finite) or ran away beyond the escape radius. */
  isLost(c) {
    return !Number.isFinite(this.u[c]) || Math.hypot(this.x[2 * c], this.x[2 * c + 1]) > this.escape;
  }

  /** Chains lost: { diverged, ranAway }. */
  lost() {
    let diverged = 0;
    let ranAway = 0;
    for (let c = 0; c < this.n; c++) {
      if (!Number.isFinite(this.u[c])) diverged++;
      else if (this.isLost(c)) ranAway++;
    }
    return { diverged, ranAway };
  }

  /**
   * The lowest U of any chain not diverged (run away included), when it is
   * below U* by more than eps: then U* (a formula's lowest value on its
   * box) is not the landscape's minimum, U looks unbounded below, and no
   * success can be scored against it. null otherwise.
   */
  belowMinimum(eps) {
    let low = Infinity;
    for (let c = 0; c < this.n; c++) if (this.u[c] < low) low = this.u[c];
    return low < this.minimum - Math.max(eps, 0) ? low : null;
  }

  /** How many of the chains that ran away went downhill, below U*. */
  ranDownhill() {
    let n = 0;
    for (let c = 0; c < this.n; c++) if (this.isLost(c) && this.u[c] < this.minimum) n++;
    return n;
  }

  /** Chains not lost whose position is outside the box [x0, x1] x [y0, y1]. */
  outside(x0, x1, y0, y1) {
    let n = 0;
    for (let c = 0; c < this.n; c++) {
      const x = this.x[2 * c];
      const y = this.x[2 * c + 1];
      if (!this.isLost(c) && !(x >= x0 && x <= x1 && y >= y0 && y <= y1)) n++;
    }
    return n;
  }

  /** The largest |x_i| of a chain not lost. */
  reach() {
    let r = 0;
    for (let c = 0; c < this.n; c++) {
      if (this.isLost(c)) continue;
      r = Math.max(r, Math.abs(this.x[2 * c]), Math.abs(this.x[2 * c + 1]));
    }
    return r;
  }

  /** The law of chain c's next step (the wrapper's nextStep); null for descent, whose step draws nothing. */
  nextStep(c) {
    return this.descent ? null : Float64Array.from(this.opt.nextStep(c));
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
        this.lowest[i] = this.lowest[2 * i];
        this.groupBest.copyWithin(i * g, 2 * i * g, (2 * i + 1) * g);
      }
      this.count = HISTORY / 2;
      this.every *= 2;
    }
    const i = this.count++;
    this.iters[i] = this.s[Summary.Iteration];
    this.best[i] = this.s[Summary.BestValue];
    let low = Infinity;
    for (const u of this.u) if (u < low) low = u;
    this.lowest[i] = low;
    for (let g = 0; g < this.groups; g++) {
      let m = Infinity;
      for (let c = g * this.groupSize; c < (g + 1) * this.groupSize; c++) {
        // A lost chain (diverged, or run away however low its U) is a
        // failure: it is never within eps.
        if (this.u[c] < m && !this.isLost(c)) m = this.u[c];
      }
      this.groupBest[i * this.groups + g] = m;
    }
  }
}

/** The last `length` trail points of every chain, with their iterations, in fixed memory. */
export class TrailBuffer {
  constructor(length, chains) {
    this.length = length;
    this.stride = 2 * chains;
    this.data = new Float32Array(length * this.stride);
    this.iterations = new Float64Array(length);
    this.head = 0;
    this.count = 0;
  }
  clear() {
    this.count = 0;
  }
  push(positions, iteration) {
    this.head = (this.head + 1) % this.length;
    this.data.set(positions, this.head * this.stride);
    this.iterations[this.head] = iteration;
    this.count = Math.min(this.count + 1, this.length);
  }
  slot(age) {
    return (this.head - age + this.length) % this.length;
  }
  /** Trail point `age` points ago (0 = newest). */
  snapshot(age) {
    const slot = this.slot(age);
    return this.data.subarray(slot * this.stride, (slot + 1) * this.stride);
  }
  /** The iteration of trail point `age`. */
  iteration(age) {
    return this.iterations[this.slot(age)];
  }
}
