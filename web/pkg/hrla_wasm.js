/* @ts-self-types="./hrla_wasm.d.ts" */

/**
 * Gradient descent with random restarts on one landscape, with the
 * buffers JavaScript views (in the layout of [`crate::Optimizer`]'s).
 */
export class Descent {
    __destroy_into_raw() {
        const ptr = this.__wbg_ptr;
        this.__wbg_ptr = 0;
        DescentFinalization.unregister(this);
        return ptr;
    }
    free() {
        const ptr = this.__destroy_into_raw();
        wasm.__wbg_descent_free(ptr, 0);
    }
    /**
     * `steps` more steps of every chain (a whole number from 0 to
     * `2^32 - 1`, else an `Error` with `field` `"steps"`); returns them.
     * @param {any} steps
     * @returns {number}
     */
    advance(steps) {
        const ret = wasm.descent_advance(this.__wbg_ptr, steps);
        if (ret[2]) {
            throw takeFromExternrefTable0(ret[1]);
        }
        return ret[0] >>> 0;
    }
    /**
     * Number of chains.
     * @returns {number}
     */
    chains() {
        const ret = wasm.descent_chains(this.__wbg_ptr);
        return ret >>> 0;
    }
    /**
     * Descent from a settings object (see [`Settings::from_js`]; its
     * sampler and temperature play no part) restarting within `bounds`,
     * an array `[x0, x1, y0, y1]`; throws an `Error` with a `field` when
     * a setting is refused (`box` for the bounds).
     * @param {any} settings
     * @param {any} bounds
     */
    constructor(settings, bounds) {
        const ret = wasm.descent_new_js(settings, bounds);
        if (ret[2]) {
            throw takeFromExternrefTable0(ret[1]);
        }
        this.__wbg_ptr = ret[0];
        DescentFinalization.register(this, this.__wbg_ptr, this);
        return this;
    }
    /**
     * Address of the positions, `2 * chains()` f64.
     * @returns {number}
     */
    positions_ptr() {
        const ret = wasm.descent_positions_ptr(this.__wbg_ptr);
        return ret >>> 0;
    }
    /**
     * Restarts so far.
     * @returns {number}
     */
    restarts() {
        const ret = wasm.descent_restarts(this.__wbg_ptr);
        return ret;
    }
    /**
     * The seed of this run (a BigInt).
     * @returns {bigint}
     */
    seed() {
        const ret = wasm.descent_seed(this.__wbg_ptr);
        return BigInt.asUintN(64, ret);
    }
    /**
     * Address of the summary, `Summary.Len` f64 indexed by `Summary`.
     * @returns {number}
     */
    summary_ptr() {
        const ret = wasm.descent_summary_ptr(this.__wbg_ptr);
        return ret >>> 0;
    }
    /**
     * Descent never stops by a rule: always `undefined`.
     * @returns {string | undefined}
     */
    termination() {
        const ret = wasm.descent_termination(this.__wbg_ptr);
        let v1;
        if (ret[0] !== 0) {
            v1 = getStringFromWasm0(ret[0], ret[1]);
            wasm.__wbindgen_free(ret[0], ret[1] * 1, 1);
        }
        return v1;
    }
    /**
     * Address of the per-chain values, `chains()` f64: an
     * optimiser's `U` of each chain (NaN for a chain that diverged,
     * finite for every other), descent's best of each so far.
     * @returns {number}
     */
    values_ptr() {
        const ret = wasm.descent_values_ptr(this.__wbg_ptr);
        return ret >>> 0;
    }
    /**
     * Address of the velocities, `2 * chains()` f64 (zeros for
     * OLA and for descent).
     * @returns {number}
     */
    velocities_ptr() {
        const ret = wasm.descent_velocities_ptr(this.__wbg_ptr);
        return ret >>> 0;
    }
}
if (Symbol.dispose) Descent.prototype[Symbol.dispose] = Descent.prototype.free;

/**
 * HRLA, ULA and OLA side by side on `d`-dimensional Rastrigin, with the
 * record JavaScript views.
 */
export class Experiment {
    __destroy_into_raw() {
        const ptr = this.__wbg_ptr;
        this.__wbg_ptr = 0;
        ExperimentFinalization.unregister(this);
        return ptr;
    }
    free() {
        const ptr = this.__destroy_into_raw();
        wasm.__wbg_experiment_free(ptr, 0);
    }
    /**
     * Up to `steps` more steps of every run (a whole number from 0 to
     * `K`, else an `Error` with `field` `"steps"`), never past `K`;
     * returns the steps done.
     * @param {any} steps
     * @returns {number}
     */
    advance(steps) {
        const ret = wasm.experiment_advance(this.__wbg_ptr, steps);
        if (ret[2]) {
            throw takeFromExternrefTable0(ret[1]);
        }
        return ret[0];
    }
    /**
     * Iterates done, `k`.
     * @returns {number}
     */
    iteration() {
        const ret = wasm.experiment_iteration(this.__wbg_ptr);
        return ret;
    }
    /**
     * The comparison of a settings object `{ d, runs, chains, a, h, eps,
     * steps, seed }` (each optional: the paper's E2 panel `a = 4, eps =
     * 2` in `d = 10`, `M = 100`, `N = 10`, `h = 0.01`, `K = 14000`, seed
     * 2025); throws an `Error` with a `field` when one is refused.
     * @param {any} settings
     */
    constructor(settings) {
        const ret = wasm.experiment_new_js(settings);
        if (ret[2]) {
            throw takeFromExternrefTable0(ret[1]);
        }
        this.__wbg_ptr = ret[0];
        ExperimentFinalization.register(this, this.__wbg_ptr, this);
        return this;
    }
    /**
     * Address of the record: `(iteration() + 1) * rowLength()` f64, row
     * `k` holding the hits of HRLA, ULA, OLA at iterate `k`, then their
     * mean running bests. Its address never changes; its valid length
     * grows with `iteration()`.
     * @returns {number}
     */
    record_ptr() {
        const ret = wasm.experiment_record_ptr(this.__wbg_ptr);
        return ret >>> 0;
    }
    /**
     * Numbers per row of the record.
     * @returns {number}
     */
    static rowLength() {
        const ret = wasm.experiment_rowLength();
        return ret >>> 0;
    }
    /**
     * Runs per sampler, `M`.
     * @returns {number}
     */
    runs() {
        const ret = wasm.experiment_runs(this.__wbg_ptr);
        return ret >>> 0;
    }
    /**
     * The run's length `K`.
     * @returns {number}
     */
    steps() {
        const ret = wasm.experiment_steps(this.__wbg_ptr);
        return ret;
    }
}
if (Symbol.dispose) Experiment.prototype[Symbol.dispose] = Experiment.prototype.free;

/**
 * One run of Algorithm 1 on a 2-D landscape, with its chains and the
 * buffers that JavaScript views.
 */
export class Optimizer {
    __destroy_into_raw() {
        const ptr = this.__wbg_ptr;
        this.__wbg_ptr = 0;
        OptimizerFinalization.unregister(this);
        return ptr;
    }
    free() {
        const ptr = this.__destroy_into_raw();
        wasm.__wbg_optimizer_free(ptr, 0);
    }
    /**
     * Advances every live chain by `steps` steps, refreshes the buffers
     * and returns the steps done: fewer once a stopping rule holds, and 0
     * at once when one already held. `steps` must be a JS number holding
     * a whole number from 0 to [`MAX_STEPS`], else it throws an `Error`
     * with `field` `"steps"` and nothing is done. Throws an `Error` with
     * the kernel's message once every chain has diverged (`all N chains
     * diverged ...`, again on every later call), or if annealing reaches
     * a temperature the sampler refuses; the buffers then show the state
     * reached.
     * @param {any} steps
     * @returns {number}
     */
    advance(steps) {
        const ret = wasm.optimizer_advance(this.__wbg_ptr, steps);
        if (ret[2]) {
            throw takeFromExternrefTable0(ret[1]);
        }
        return ret[0] >>> 0;
    }
    /**
     * Number of chains.
     * @returns {number}
     */
    chains() {
        const ret = wasm.optimizer_chains(this.__wbg_ptr);
        return ret >>> 0;
    }
    /**
     * The landscape's global minimiser `x*`, `[x0, x1]` (one of them
     * when there are several).
     * @returns {Float64Array}
     */
    minimiser() {
        const ret = wasm.optimizer_minimiser(this.__wbg_ptr);
        var v1 = getArrayF64FromWasm0(ret[0], ret[1]).slice();
        wasm.__wbindgen_free(ret[0], ret[1] * 8, 8);
        return v1;
    }
    /**
     * Creates a run from a settings object (see [`Settings::from_js`]);
     * throws an `Error` with the reason when a setting is refused.
     * @param {any} settings
     */
    constructor(settings) {
        const ret = wasm.optimizer_new(settings);
        if (ret[2]) {
            throw takeFromExternrefTable0(ret[1]);
        }
        this.__wbg_ptr = ret[0];
        OptimizerFinalization.register(this, this.__wbg_ptr, this);
        return this;
    }
    /**
     * The law of chain `chain`'s next step (see [`Optimizer::next_step`]),
     * flat as [`NextStep::to_array`]: `[a, x0, x1, y0, y1, g0, g1,` then
     * per coordinate `mean_x, mean_y, var_x, cov_xy, var_y`, then the
     * gradient's and the velocity's push of the mean, two each`]`. `chain` must
     * be a JS number holding a whole number below `chains()`; throws an
     * `Error` with `field` `"chain"` otherwise, or for a chain that has
     * diverged.
     * @param {any} chain
     * @returns {Float64Array}
     */
    nextStep(chain) {
        const ret = wasm.optimizer_nextStep(this.__wbg_ptr, chain);
        if (ret[3]) {
            throw takeFromExternrefTable0(ret[2]);
        }
        var v1 = getArrayF64FromWasm0(ret[0], ret[1]).slice();
        wasm.__wbindgen_free(ret[0], ret[1] * 8, 8);
        return v1;
    }
    /**
     * Address of the positions, `2 * chains()` f64.
     * @returns {number}
     */
    positions_ptr() {
        const ret = wasm.optimizer_positions_ptr(this.__wbg_ptr);
        return ret >>> 0;
    }
    /**
     * The landscape's name.
     * @returns {string}
     */
    potential() {
        let deferred1_0;
        let deferred1_1;
        try {
            const ret = wasm.optimizer_potential(this.__wbg_ptr);
            deferred1_0 = ret[0];
            deferred1_1 = ret[1];
            return getStringFromWasm0(ret[0], ret[1]);
        } finally {
            wasm.__wbindgen_free(deferred1_0, deferred1_1, 1);
        }
    }
    /**
     * Sets the step `h` and the inverse temperature `a` of the next steps
     * without a restart (see [`Optimizer::retune`]); `a` `undefined` or
     * `null` keeps the temperature (an annealing run takes no `a`).
     * Throws an `Error` with `field` `"h"` or `"a"` on a value refused.
     * @param {any} h
     * @param {any} a
     */
    retune(h, a) {
        const ret = wasm.optimizer_retune(this.__wbg_ptr, h, a);
        if (ret[1]) {
            throw takeFromExternrefTable0(ret[0]);
        }
    }
    /**
     * The seed of this run (a BigInt).
     * @returns {bigint}
     */
    seed() {
        const ret = wasm.optimizer_seed(this.__wbg_ptr);
        return BigInt.asUintN(64, ret);
    }
    /**
     * Address of the summary, `Summary.Len` f64 indexed by `Summary`.
     * @returns {number}
     */
    summary_ptr() {
        const ret = wasm.optimizer_summary_ptr(this.__wbg_ptr);
        return ret >>> 0;
    }
    /**
     * Why the run stopped (`"target reached"`, `"step budget spent"`), or
     * `undefined` while it runs.
     * @returns {string | undefined}
     */
    termination() {
        const ret = wasm.optimizer_termination(this.__wbg_ptr);
        let v1;
        if (ret[0] !== 0) {
            v1 = getStringFromWasm0(ret[0], ret[1]);
            wasm.__wbindgen_free(ret[0], ret[1] * 1, 1);
        }
        return v1;
    }
    /**
     * Address of the per-chain values, `chains()` f64: an
     * optimiser's `U` of each chain (NaN for a chain that diverged,
     * finite for every other), descent's best of each so far.
     * @returns {number}
     */
    values_ptr() {
        const ret = wasm.optimizer_values_ptr(this.__wbg_ptr);
        return ret >>> 0;
    }
    /**
     * Address of the velocities, `2 * chains()` f64 (zeros for
     * OLA and for descent).
     * @returns {number}
     */
    velocities_ptr() {
        const ret = wasm.optimizer_velocities_ptr(this.__wbg_ptr);
        return ret >>> 0;
    }
}
if (Symbol.dispose) Optimizer.prototype[Symbol.dispose] = Optimizer.prototype.free;

/**
 * Slots of the summary buffer ([`Optimizer::summary_ptr`]), all f64.
 * @enum {0 | 1 | 2 | 3 | 4 | 5 | 6 | 7 | 8 | 9}
 */
export const Summary = Object.freeze({
    /**
     * Steps done (the current iterate index `k`); exact below `2^53`.
     */
    Iteration: 0, "0": "Iteration",
    /**
     * First coordinate of the running best point.
     */
    BestX0: 1, "1": "BestX0",
    /**
     * Second coordinate of the running best point.
     */
    BestX1: 2, "2": "BestX1",
    /**
     * `U` at the running best point.
     */
    BestValue: 3, "3": "BestValue",
    /**
     * Iterate at which the running best was visited.
     */
    BestIteration: 4, "4": "BestIteration",
    /**
     * Inverse temperature `a` of the last step (of the first, before any).
     */
    A: 5, "5": "A",
    /**
     * Chains that diverged (frozen, excluded from the best).
     */
    Diverged: 6, "6": "Diverged",
    /**
     * The landscape's global minimum `U*`.
     */
    Minimum: 7, "7": "Minimum",
    /**
     * Why the run stopped ([`termination_code`]): 0 while it runs.
     */
    Termination: 8, "8": "Termination",
    /**
     * Number of slots.
     */
    Len: 9, "9": "Len",
});

/**
 * The kernel's step coefficients of `sampler` (`"hrla"`, `"ula"`,
 * `"ola"`) at step `h` and inverse temperature `a`, in f64 (see the
 * module's layout); an `Error` with the kernel's message when it refuses
 * `h` or `a`.
 * @param {string} sampler
 * @param {number} h
 * @param {number} a
 * @returns {Float64Array}
 */
export function coefficients(sampler, h, a) {
    const val2 = +h;
    const val3 = +a;
    const ptr0 = passStringToWasm0(sampler, wasm.__wbindgen_malloc, wasm.__wbindgen_realloc);
    const len0 = WASM_VECTOR_LEN;
    const ret = wasm.coefficients(ptr0, len0, val2, val3);
    if (ret[3]) {
        throw takeFromExternrefTable0(ret[2]);
    }
    var v4 = getArrayF64FromWasm0(ret[0], ret[1]).slice();
    wasm.__wbindgen_free(ret[0], ret[1] * 8, 8);
    return v4;
}

/**
 * A visitor's formula `U` on a grid laid out as [`potential_grid`]'s, NaN
 * where it is not finite ([`formula_picture`]): the picture of a formula
 * the page refuses on its box, or sees beyond it. Throws an `Error` with
 * `field` `"formula"` (with a `column`) when the formula cannot be read,
 * and as [`potential_grid`] on the bounds and counts.
 * @param {string} formula
 * @param {any} x0
 * @param {any} x1
 * @param {any} y0
 * @param {any} y1
 * @param {any} nx
 * @param {any} ny
 * @returns {Float64Array}
 */
export function formulaPicture(formula, x0, x1, y0, y1, nx, ny) {
    const ptr0 = passStringToWasm0(formula, wasm.__wbindgen_malloc, wasm.__wbindgen_realloc);
    const len0 = WASM_VECTOR_LEN;
    const ret = wasm.formulaPicture(ptr0, len0, x0, x1, y0, y1, nx, ny);
    if (ret[3]) {
        throw takeFromExternrefTable0(ret[2]);
    }
    var v2 = getArrayF64FromWasm0(ret[0], ret[1]).slice();
    wasm.__wbindgen_free(ret[0], ret[1] * 8, 8);
    return v2;
}

/**
 * A global minimiser `x*` of the landscape `potential` (one of them when
 * there are several; for a visitor's formula, where its estimated `U*`
 * was found), `[x0, x1]`; throws like [`global_minimum`].
 * @param {any} potential
 * @returns {Float64Array}
 */
export function global_minimiser(potential) {
    const ret = wasm.global_minimiser(potential);
    if (ret[3]) {
        throw takeFromExternrefTable0(ret[2]);
    }
    var v1 = getArrayF64FromWasm0(ret[0], ret[1]).slice();
    wasm.__wbindgen_free(ret[0], ret[1] * 8, 8);
    return v1;
}

/**
 * The global minimum `U*` of the landscape `name` (the kernel's
 * [`KnownMinimum`]; for a visitor's formula, the estimate of
 * [`Landscape::formula`]); throws an `Error` with `field` `"potential"`
 * when `name` is not a landscape's name or a formula object, `"formula"`
 * (with a `column`) when the formula cannot be read, `"box"` when it
 * cannot be evaluated finitely over its box.
 * @param {any} name
 * @returns {number}
 */
export function global_minimum(name) {
    const ret = wasm.global_minimum(name);
    if (ret[2]) {
        throw takeFromExternrefTable0(ret[1]);
    }
    return ret[0];
}

/**
 * Where the coefficients start in the constants buffer.
 * @returns {number}
 */
export function gpu_coef_offset() {
    const ret = wasm.gpu_coef_offset();
    return ret >>> 0;
}

/**
 * The generators of chains `first .. first + count` of a run of `seed`
 * (a whole number or a BigInt, as `new Optimizer` takes it; `first` and
 * `count` whole numbers, the chains within [`GPU_MAX_CHAINS`]): four
 * 32-bit words each, chain `c`'s
 * `Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, c))` as `hrla-gpu`
 * seeds it (its state's bytes read as little-endian words).
 * @param {any} seed
 * @param {any} first
 * @param {any} count
 * @returns {Uint32Array}
 */
export function gpu_generators(seed, first, count) {
    const ret = wasm.gpu_generators(seed, first, count);
    if (ret[3]) {
        throw takeFromExternrefTable0(ret[2]);
    }
    var v1 = getArrayU32FromWasm0(ret[0], ret[1]).slice();
    wasm.__wbindgen_free(ret[0], ret[1] * 4, 4);
    return v1;
}

/**
 * The start of chains `first .. first + count` of a run of `seed` (read
 * as [`gpu_generators`] reads them) from `N(centre, spread^2 I)`, as the
 * kernel draws it in f32 on the CPU from the generators of
 * [`gpu_generators`]: `centre_i + spread * z` with the kernel's
 * `f32::standard_normal`, coordinate-major (`x1` of the `k`-th chain at
 * `k`, `x2` at `count + k`). The device's `init` draws the same numbers;
 * the browser tests compare the two bit for bit.
 * @param {any} seed
 * @param {any} first
 * @param {any} count
 * @param {number} centre_x
 * @param {number} centre_y
 * @param {number} spread
 * @returns {Float32Array}
 */
export function gpu_kernel_starts(seed, first, count, centre_x, centre_y, spread) {
    const ret = wasm.gpu_kernel_starts(seed, first, count, centre_x, centre_y, spread);
    if (ret[3]) {
        throw takeFromExternrefTable0(ret[2]);
    }
    var v1 = getArrayF32FromWasm0(ret[0], ret[1]).slice();
    wasm.__wbindgen_free(ret[0], ret[1] * 4, 4);
    return v1;
}

/**
 * The most chains the page's device path runs.
 * @returns {number}
 */
export function gpu_max_chains() {
    const ret = wasm.gpu_max_chains();
    return ret >>> 0;
}

/**
 * The most steps of one dispatch.
 * @returns {number}
 */
export function gpu_max_steps() {
    const ret = wasm.gpu_max_steps();
    return ret >>> 0;
}

/**
 * The WGSL program of `hrla-gpu` (f32, IEEE products, a Gaussian start)
 * for landscape `name` in 2-D and `sampler`'s step: entry points `init`
 * and `step` of `hrla-gpu`'s `chains.wgsl`, over its bindings 0 to 6.
 * It is written for Chromium's compiler, which would warn on the
 * visitor's console about the `return` that naga asks for.
 * @param {string} name
 * @param {string} sampler
 * @returns {string}
 */
export function gpu_program(name, sampler) {
    let deferred4_0;
    let deferred4_1;
    try {
        let ptr0, len0, ptr1, len1;
        try {
            ptr0 = passStringToWasm0(name, wasm.__wbindgen_malloc, wasm.__wbindgen_realloc);
            len0 = WASM_VECTOR_LEN;
            ptr1 = passStringToWasm0(sampler, wasm.__wbindgen_malloc, wasm.__wbindgen_realloc);
            len1 = WASM_VECTOR_LEN;
        } catch (e) {
            if (ptr1) { wasm.__wbindgen_free(ptr1, len1 * 1, 1); }
            if (ptr0) { wasm.__wbindgen_free(ptr0, len0 * 1, 1); }
            throw e;
        }
        const ret = wasm.gpu_program(ptr0, len0, ptr1, len1);
        var ptr3 = ret[0];
        var len3 = ret[1];
        if (ret[3]) {
            ptr3 = 0; len3 = 0;
            throw takeFromExternrefTable0(ret[2]);
        }
        deferred4_0 = ptr3;
        deferred4_1 = len3;
        return getStringFromWasm0(ptr3, len3);
    } finally {
        wasm.__wbindgen_free(deferred4_0, deferred4_1, 1);
    }
}

/**
 * Whether the device path runs landscape `name` (a visitor's formula runs
 * on the CPU only).
 * @param {string} name
 * @returns {boolean}
 */
export function gpu_supports(name) {
    const ptr0 = passStringToWasm0(name, wasm.__wbindgen_malloc, wasm.__wbindgen_realloc);
    const len0 = WASM_VECTOR_LEN;
    const ret = wasm.gpu_supports(ptr0, len0);
    return ret !== 0;
}

/**
 * The constants buffer of a run (see the module's layout), in f32: the
 * Ziggurat's tables rounded as the kernel's f32 normals round them, the
 * start `N(centre, spread^2 I)`, and [`GPU_MAX_STEPS`] copies of the
 * step's coefficients at constant `a`, each the kernel's f64 value
 * rounded once.
 * @param {string} sampler
 * @param {number} h
 * @param {number} a
 * @param {number} centre_x
 * @param {number} centre_y
 * @param {number} spread
 * @returns {Float32Array}
 */
export function gpu_tables(sampler, h, a, centre_x, centre_y, spread) {
    const val2 = +h;
    const val3 = +a;
    const val4 = +centre_x;
    const val5 = +centre_y;
    const val6 = +spread;
    const ptr0 = passStringToWasm0(sampler, wasm.__wbindgen_malloc, wasm.__wbindgen_realloc);
    const len0 = WASM_VECTOR_LEN;
    const ret = wasm.gpu_tables(ptr0, len0, val2, val3, val4, val5, val6);
    if (ret[3]) {
        throw takeFromExternrefTable0(ret[2]);
    }
    var v7 = getArrayF32FromWasm0(ret[0], ret[1]).slice();
    wasm.__wbindgen_free(ret[0], ret[1] * 4, 4);
    return v7;
}

/**
 * The capacity in chains, [`MAX_CHAINS`].
 * @returns {number}
 */
export function max_chains() {
    const ret = wasm.max_chains();
    return ret >>> 0;
}

/**
 * `U` of the landscape `name` at the cell centres of an `nx` by `ny` grid
 * over `[x0, x1] x [y0, y1]`, row by row from the top: the kernel's own
 * potential, for the page's pictures (see [`Landscape::grid`]). Every
 * value is finite. Throws an `Error` with a `field` (`potential`, `x0`,
 * ..., `nx`, `ny`, `box`) on a name that is not a landscape's, a bound
 * that is not a JS number, a count that is not a whole number in
 * `1..=MAX_GRID`, a box that is not finite and increasing or whose width
 * overflows, more than [`MAX_GRID`] points, or a cell where `U` is not
 * finite.
 * @param {any} name
 * @param {any} x0
 * @param {any} x1
 * @param {any} y0
 * @param {any} y1
 * @param {any} nx
 * @param {any} ny
 * @returns {Float64Array}
 */
export function potential_grid(name, x0, x1, y0, y1, nx, ny) {
    const ret = wasm.potential_grid(name, x0, x1, y0, y1, nx, ny);
    if (ret[3]) {
        throw takeFromExternrefTable0(ret[2]);
    }
    var v1 = getArrayF64FromWasm0(ret[0], ret[1]).slice();
    wasm.__wbindgen_free(ret[0], ret[1] * 8, 8);
    return v1;
}

/**
 * The names of the landscapes, as `potential` takes them.
 * @returns {string[]}
 */
export function potential_names() {
    const ret = wasm.potential_names();
    var v1 = getArrayJsValueFromWasm0(ret[0], ret[1]);
    wasm.__wbindgen_free(ret[0], ret[1] * 4, 4);
    return v1;
}

/**
 * A fresh seed from the browser's `crypto.getRandomValues` (the OS
 * natively), as a BigInt, for the "random" button: the page shows it so
 * the run can be replayed.
 * @returns {bigint}
 */
export function random_seed() {
    const ret = wasm.random_seed();
    if (ret[2]) {
        throw takeFromExternrefTable0(ret[1]);
    }
    return BigInt.asUintN(64, ret[0]);
}

/**
 * The module's `WebAssembly.Memory`, for typed-array views (named so as
 * not to clash with the module's own `memory` export).
 * @returns {any}
 */
export function wasm_memory() {
    const ret = wasm.wasm_memory();
    return ret;
}
function __wbg_get_imports() {
    const import0 = {
        __proto__: null,
        __wbg_Error_208446807d0d1e30: function(arg0, arg1) {
            const ret = Error(getStringFromWasm0(arg0, arg1));
            return ret;
        },
        __wbg___wbindgen_bigint_get_as_i64_11da4b52cd0aedef: function(arg0, arg1) {
            const v = arg1;
            const ret = typeof(v) === 'bigint' ? v : undefined;
            getDataViewMemory0().setBigInt64((arg0 >>> 0) + 8 * 1, isLikeNone(ret) ? BigInt(0) : ret, true);
            getDataViewMemory0().setInt32((arg0 >>> 0) + 4 * 0, !isLikeNone(ret), true);
        },
        __wbg___wbindgen_boolean_get_4f1baf9a00be3c74: function(arg0) {
            const v = arg0;
            const ret = typeof(v) === 'boolean' ? v : undefined;
            return isLikeNone(ret) ? 0xFFFFFF : ret ? 1 : 0;
        },
        __wbg___wbindgen_is_bigint_5fa10641e039d3ef: function(arg0) {
            const ret = typeof(arg0) === 'bigint';
            return ret;
        },
        __wbg___wbindgen_is_function_741ff2bb612836f5: function(arg0) {
            const ret = typeof(arg0) === 'function';
            return ret;
        },
        __wbg___wbindgen_is_null_c22311b1cc228e3a: function(arg0) {
            const ret = arg0 === null;
            return ret;
        },
        __wbg___wbindgen_is_object_8b968c3ab8e96595: function(arg0) {
            const val = arg0;
            const ret = typeof(val) === 'object' && val !== null;
            return ret;
        },
        __wbg___wbindgen_is_string_fc456fee5d3317de: function(arg0) {
            const ret = typeof(arg0) === 'string';
            return ret;
        },
        __wbg___wbindgen_is_symbol_f846131a047725ea: function(arg0) {
            const ret = typeof(arg0) === 'symbol';
            return ret;
        },
        __wbg___wbindgen_is_undefined_be5b34249ff1fc15: function(arg0) {
            const ret = arg0 === undefined;
            return ret;
        },
        __wbg___wbindgen_jsval_eq_38d7bfbe4cc84039: function(arg0, arg1) {
            const ret = arg0 === arg1;
            return ret;
        },
        __wbg___wbindgen_memory_17a1178bc3328ea3: function() {
            const ret = wasm.memory;
            return ret;
        },
        __wbg___wbindgen_number_get_934b640d0889af78: function(arg0, arg1) {
            const obj = arg1;
            const ret = typeof(obj) === 'number' ? obj : undefined;
            getDataViewMemory0().setFloat64((arg0 >>> 0) + 8 * 1, isLikeNone(ret) ? 0 : ret, true);
            getDataViewMemory0().setInt32((arg0 >>> 0) + 4 * 0, !isLikeNone(ret), true);
        },
        __wbg___wbindgen_string_get_7ce8eee7fd327545: function(arg0, arg1) {
            const obj = arg1;
            const ret = typeof(obj) === 'string' ? obj : undefined;
            var ptr1 = isLikeNone(ret) ? 0 : passStringToWasm0(ret, wasm.__wbindgen_malloc, wasm.__wbindgen_realloc);
            var len1 = WASM_VECTOR_LEN;
            getDataViewMemory0().setInt32((arg0 >>> 0) + 4 * 1, len1, true);
            getDataViewMemory0().setInt32((arg0 >>> 0) + 4 * 0, ptr1, true);
        },
        __wbg___wbindgen_throw_4c88d8bf264fd984: function(arg0, arg1) {
            throw new Error(getStringFromWasm0(arg0, arg1));
        },
        __wbg_getRandomValues_8b6f1f663e6f188d: function() { return handleError(function (arg0, arg1) {
            globalThis.crypto.getRandomValues(getArrayU8FromWasm0(arg0, arg1));
        }, arguments); },
        __wbg_get_2080c49015e35254: function() { return handleError(function (arg0, arg1) {
            const ret = Reflect.get(arg0, arg1);
            return ret;
        }, arguments); },
        __wbg_get_bb8b6b35041e00c9: function() { return handleError(function (arg0, arg1) {
            const ret = Reflect.get(arg0, arg1 >>> 0);
            return ret;
        }, arguments); },
        __wbg_get_unchecked_e6325ad374eff861: function(arg0, arg1) {
            const ret = arg0[arg1 >>> 0];
            return ret;
        },
        __wbg_isArray_2404936036833c41: function() { return handleError(function (arg0) {
            const ret = Array.isArray(arg0);
            return ret;
        }, arguments); },
        __wbg_length_b03a0fabb109b1e9: function(arg0) {
            const ret = arg0.length;
            return ret;
        },
        __wbg_new_787b9fb330d55d78: function(arg0, arg1) {
            const ret = new Error(getStringFromWasm0(arg0, arg1));
            return ret;
        },
        __wbg_ownKeys_c9890d5405932253: function() { return handleError(function (arg0) {
            const ret = Reflect.ownKeys(arg0);
            return ret;
        }, arguments); },
        __wbg_set_2793479888329cb6: function() { return handleError(function (arg0, arg1, arg2) {
            const ret = Reflect.set(arg0, arg1, arg2);
            return ret;
        }, arguments); },
        __wbg_toString_ac62c4a5cb3e62c7: function() { return handleError(function (arg0, arg1) {
            const ret = arg0.toString(arg1);
            return ret;
        }, arguments); },
        __wbindgen_generic_0000000000000001: function(arg0) {
            // Cast intrinsic for `F64 -> Externref`.
            const ret = arg0;
            return ret;
        },
        __wbindgen_generic_0000000000000002: function(arg0, arg1) {
            // Cast intrinsic for `Ref(String) -> Externref`.
            const ret = getStringFromWasm0(arg0, arg1);
            return ret;
        },
        __wbindgen_generic_0000000000000003: function(arg0) {
            // Cast intrinsic for `U64 -> Externref`.
            const ret = BigInt.asUintN(64, arg0);
            return ret;
        },
        __wbindgen_init_externref_table: function() {
            const table = wasm.__wbindgen_externrefs;
            table.set(0, undefined);
            table.set(1024, undefined);
            table.set(1025, null);
            table.set(1026, true);
            table.set(1027, false);
        },
    };
    return {
        __proto__: null,
        "./hrla_wasm_bg.js": import0,
    };
}

const DescentFinalization = (typeof FinalizationRegistry === 'undefined')
    ? { register: () => {}, unregister: () => {} }
    : new FinalizationRegistry(ptr => wasm.__wbg_descent_free(ptr, 1));
const ExperimentFinalization = (typeof FinalizationRegistry === 'undefined')
    ? { register: () => {}, unregister: () => {} }
    : new FinalizationRegistry(ptr => wasm.__wbg_experiment_free(ptr, 1));
const OptimizerFinalization = (typeof FinalizationRegistry === 'undefined')
    ? { register: () => {}, unregister: () => {} }
    : new FinalizationRegistry(ptr => wasm.__wbg_optimizer_free(ptr, 1));

function addToExternrefTable0(obj) {
    const idx = wasm.__externref_table_alloc();
    wasm.__wbindgen_externrefs.set(idx, obj);
    return idx;
}

function getArrayF32FromWasm0(ptr, len) {
    ptr = ptr >>> 0;
    return getFloat32ArrayMemory0().subarray(ptr / 4, ptr / 4 + len);
}

function getArrayF64FromWasm0(ptr, len) {
    ptr = ptr >>> 0;
    return getFloat64ArrayMemory0().subarray(ptr / 8, ptr / 8 + len);
}

function getArrayJsValueFromWasm0(ptr, len) {
    ptr = ptr >>> 0;
    const mem = getDataViewMemory0();
    const result = [];
    for (let i = ptr; i < ptr + 4 * len; i += 4) {
        result.push(wasm.__wbindgen_externrefs.get(mem.getUint32(i, true)));
    }
    wasm.__externref_drop_slice(ptr, len);
    return result;
}

function getArrayU32FromWasm0(ptr, len) {
    ptr = ptr >>> 0;
    return getUint32ArrayMemory0().subarray(ptr / 4, ptr / 4 + len);
}

function getArrayU8FromWasm0(ptr, len) {
    ptr = ptr >>> 0;
    return getUint8ArrayMemory0().subarray(ptr / 1, ptr / 1 + len);
}

let cachedDataViewMemory0 = null;
function getDataViewMemory0() {
    if (cachedDataViewMemory0 === null || cachedDataViewMemory0.buffer.detached === true || (cachedDataViewMemory0.buffer.detached === undefined && cachedDataViewMemory0.buffer !== wasm.memory.buffer)) {
        cachedDataViewMemory0 = new DataView(wasm.memory.buffer);
    }
    return cachedDataViewMemory0;
}

let cachedFloat32ArrayMemory0 = null;
function getFloat32ArrayMemory0() {
    if (cachedFloat32ArrayMemory0 === null || cachedFloat32ArrayMemory0.byteLength === 0) {
        cachedFloat32ArrayMemory0 = new Float32Array(wasm.memory.buffer);
    }
    return cachedFloat32ArrayMemory0;
}

let cachedFloat64ArrayMemory0 = null;
function getFloat64ArrayMemory0() {
    if (cachedFloat64ArrayMemory0 === null || cachedFloat64ArrayMemory0.byteLength === 0) {
        cachedFloat64ArrayMemory0 = new Float64Array(wasm.memory.buffer);
    }
    return cachedFloat64ArrayMemory0;
}

function getStringFromWasm0(ptr, len) {
    ptr = ptr >>> 0;
    return decodeText(getUint8ArrayMemory0().subarray(ptr, ptr + len));
}

let cachedUint32ArrayMemory0 = null;
function getUint32ArrayMemory0() {
    if (cachedUint32ArrayMemory0 === null || cachedUint32ArrayMemory0.byteLength === 0) {
        cachedUint32ArrayMemory0 = new Uint32Array(wasm.memory.buffer);
    }
    return cachedUint32ArrayMemory0;
}

let cachedUint8ArrayMemory0 = null;
function getUint8ArrayMemory0() {
    if (cachedUint8ArrayMemory0 === null || cachedUint8ArrayMemory0.byteLength === 0) {
        cachedUint8ArrayMemory0 = new Uint8Array(wasm.memory.buffer);
    }
    return cachedUint8ArrayMemory0;
}

function handleError(f, args) {
    try {
        return f.apply(this, args);
    } catch (e) {
        const idx = addToExternrefTable0(e);
        wasm.__wbindgen_exn_store(idx);
    }
}

function isLikeNone(x) {
    return x === undefined || x === null;
}

function passStringToWasm0(arg, malloc, realloc) {
    if (realloc === undefined) {
        const buf = cachedTextEncoder.encode(arg);
        const ptr = malloc(buf.length, 1) >>> 0;
        getUint8ArrayMemory0().subarray(ptr, ptr + buf.length).set(buf);
        WASM_VECTOR_LEN = buf.length;
        return ptr;
    }

    let len = arg.length;
    let ptr = malloc(len, 1) >>> 0;

    const mem = getUint8ArrayMemory0();

    let offset = 0;

    for (; offset < len; offset++) {
        const code = arg.charCodeAt(offset);
        if (code > 0x7F) break;
        mem[ptr + offset] = code;
    }
    if (offset !== len) {
        if (offset !== 0) {
            arg = arg.slice(offset);
        }
        ptr = realloc(ptr, len, len = offset + arg.length * 3, 1) >>> 0;
        const view = getUint8ArrayMemory0().subarray(ptr + offset, ptr + len);
        const ret = cachedTextEncoder.encodeInto(arg, view);

        offset += ret.written;
        ptr = realloc(ptr, len, offset, 1) >>> 0;
    }

    WASM_VECTOR_LEN = offset;
    return ptr;
}

function takeFromExternrefTable0(idx) {
    const value = wasm.__wbindgen_externrefs.get(idx);
    wasm.__externref_table_dealloc(idx);
    return value;
}

let cachedTextDecoder = new TextDecoder('utf-8', { ignoreBOM: true });
cachedTextDecoder.decode();
const MAX_SAFARI_DECODE_BYTES = 2146435072;
let numBytesDecoded = 0;
function decodeText(bytes) {
    numBytesDecoded += bytes.length;
    if (numBytesDecoded >= MAX_SAFARI_DECODE_BYTES) {
        cachedTextDecoder = new TextDecoder('utf-8', { ignoreBOM: true });
        cachedTextDecoder.decode();
        numBytesDecoded = bytes.length;
    }
    return cachedTextDecoder.decode(bytes);
}

const cachedTextEncoder = new TextEncoder();

if (!('encodeInto' in cachedTextEncoder)) {
    cachedTextEncoder.encodeInto = function (arg, view) {
        const buf = cachedTextEncoder.encode(arg);
        view.set(buf);
        return {
            read: arg.length,
            written: buf.length
        };
    };
}

let WASM_VECTOR_LEN = 0;

let wasmModule, wasmInstance, wasm;
function __wbg_finalize_init(instance, module) {
    wasmInstance = instance;
    wasm = instance.exports;
    wasmModule = module;
    cachedDataViewMemory0 = null;
    cachedFloat32ArrayMemory0 = null;
    cachedFloat64ArrayMemory0 = null;
    cachedUint32ArrayMemory0 = null;
    cachedUint8ArrayMemory0 = null;
    wasm.__wbindgen_start();
    return wasm;
}

async function __wbg_load(module, imports) {
    if (typeof Response === 'function' && module instanceof Response) {
        if (!module.ok) {
            throw new Error(`failed to fetch Wasm: ${module.status} ${module.statusText} fetching '${module.url}'`);
        }

        if (typeof WebAssembly.instantiateStreaming === 'function') {
            try {
                return await WebAssembly.instantiateStreaming(module, imports);
            } catch (e) {
                const validResponse = expectedResponseType(module.type);

                if (validResponse && module.headers.get('Content-Type') !== 'application/wasm') {
                    console.warn("`WebAssembly.instantiateStreaming` failed because your server does not serve Wasm with `application/wasm` MIME type. Falling back to `WebAssembly.instantiate` which is slower. Original error:\n", e);

                } else { throw e; }
            }
        }

        const bytes = await module.arrayBuffer();
        return await WebAssembly.instantiate(bytes, imports);
    } else {
        const instance = await WebAssembly.instantiate(module, imports);

        if (instance instanceof WebAssembly.Instance) {
            return { instance, module };
        } else {
            return instance;
        }
    }

    function expectedResponseType(type) {
        switch (type) {
            case 'basic': case 'cors': case 'default': return true;
        }
        return false;
    }
}

function initSync(module) {
    if (wasm !== undefined) return wasm;


    if (module !== undefined) {
        if (Object.getPrototypeOf(module) === Object.prototype) {
            ({module} = module)
        } else {
            console.warn('using deprecated parameters for `initSync()`; pass a single object instead')
        }
    }

    const imports = __wbg_get_imports();
    if (!(module instanceof WebAssembly.Module)) {
        module = new WebAssembly.Module(module);
    }
    const instance = new WebAssembly.Instance(module, imports);
    return __wbg_finalize_init(instance, module);
}

let __wbg_init_promise;
async function __wbg_init(module_or_path) {
    if (wasm !== undefined) return wasm;
    if (__wbg_init_promise === undefined) {
        __wbg_init_promise = __wbg_init_once(module_or_path);
        __wbg_init_promise.catch(() => { __wbg_init_promise = undefined; });
    }
    return __wbg_init_promise;
}

async function __wbg_init_once(module_or_path) {

    if (module_or_path !== undefined) {
        if (Object.getPrototypeOf(module_or_path) === Object.prototype) {
            ({module_or_path} = module_or_path)
        } else {
            console.warn('using deprecated parameters for the initialization function; pass a single object instead')
        }
    }

    if (module_or_path === undefined) {
        module_or_path = new URL('hrla_wasm_bg.wasm', import.meta.url);
    }
    const imports = __wbg_get_imports();

    if (typeof module_or_path === 'string' || (typeof Request === 'function' && module_or_path instanceof Request) || (typeof URL === 'function' && module_or_path instanceof URL)) {
        module_or_path = fetch(module_or_path);
    }

    const { instance, module } = await __wbg_load(await module_or_path, imports);

    return __wbg_finalize_init(instance, module);
}

export { initSync, __wbg_init as default };
