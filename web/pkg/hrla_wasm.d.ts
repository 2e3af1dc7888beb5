/* tslint:disable */
/* eslint-disable */

/**
 * Gradient descent with random restarts on one landscape, with the
 * buffers JavaScript views (in the layout of [`crate::Optimizer`]'s).
 */
export class Descent {
    free(): void;
    [Symbol.dispose](): void;
    /**
     * `steps` more steps of every chain (a whole number from 0 to
     * `2^32 - 1`, else an `Error` with `field` `"steps"`); returns them.
     */
    advance(steps: any): number;
    /**
     * Number of chains.
     */
    chains(): number;
    /**
     * Descent from a settings object (see [`Settings::from_js`]; its
     * sampler and temperature play no part) restarting within `bounds`,
     * an array `[x0, x1, y0, y1]`; throws an `Error` with a `field` when
     * a setting is refused (`box` for the bounds).
     */
    constructor(settings: any, bounds: any);
    /**
     * Address of the positions, `2 * chains()` f64.
     */
    positions_ptr(): number;
    /**
     * Restarts so far.
     */
    restarts(): number;
    /**
     * The seed of this run (a BigInt).
     */
    seed(): bigint;
    /**
     * Address of the summary, `Summary.Len` f64 indexed by `Summary`.
     */
    summary_ptr(): number;
    /**
     * Descent never stops by a rule: always `undefined`.
     */
    termination(): string | undefined;
    /**
     * Address of the per-chain values, `chains()` f64: an
     * optimiser's `U` of each chain (NaN for a chain that diverged,
     * finite for every other), descent's best of each so far.
     */
    values_ptr(): number;
    /**
     * Address of the velocities, `2 * chains()` f64 (zeros for
     * OLA and for descent).
     */
    velocities_ptr(): number;
}

/**
 * HRLA, ULA and OLA side by side on `d`-dimensional Rastrigin, with the
 * record JavaScript views.
 */
export class Experiment {
    free(): void;
    [Symbol.dispose](): void;
    /**
     * Up to `steps` more steps of every run (a whole number from 0 to
     * `K`, else an `Error` with `field` `"steps"`), never past `K`;
     * returns the steps done.
     */
    advance(steps: any): number;
    /**
     * Iterates done, `k`.
     */
    iteration(): number;
    /**
     * The comparison of a settings object `{ d, runs, chains, a, h, eps,
     * steps, seed }` (each optional: the paper's E2 panel `a = 4, eps =
     * 2` in `d = 10`, `M = 100`, `N = 10`, `h = 0.01`, `K = 14000`, seed
     * 2025); throws an `Error` with a `field` when one is refused.
     */
    constructor(settings: any);
    /**
     * Address of the record: `(iteration() + 1) * rowLength()` f64, row
     * `k` holding the hits of HRLA, ULA, OLA at iterate `k`, then their
     * mean running bests. Its address never changes; its valid length
     * grows with `iteration()`.
     */
    record_ptr(): number;
    /**
     * Numbers per row of the record.
     */
    static rowLength(): number;
    /**
     * Runs per sampler, `M`.
     */
    runs(): number;
    /**
     * The run's length `K`.
     */
    steps(): number;
}

/**
 * One run of Algorithm 1 on a 2-D landscape, with its chains and the
 * buffers that JavaScript views.
 */
export class Optimizer {
    free(): void;
    [Symbol.dispose](): void;
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
     */
    advance(steps: any): number;
    /**
     * Number of chains.
     */
    chains(): number;
    /**
     * The landscape's global minimiser `x*`, `[x0, x1]` (one of them
     * when there are several).
     */
    minimiser(): Float64Array;
    /**
     * Creates a run from a settings object (see [`Settings::from_js`]);
     * throws an `Error` with the reason when a setting is refused.
     */
    constructor(settings: any);
    /**
     * The law of chain `chain`'s next step (see [`Optimizer::next_step`]),
     * flat as [`NextStep::to_array`]: `[a, x0, x1, y0, y1, g0, g1,` then
     * per coordinate `mean_x, mean_y, var_x, cov_xy, var_y`, then the
     * gradient's and the velocity's push of the mean, two each`]`. `chain` must
     * be a JS number holding a whole number below `chains()`; throws an
     * `Error` with `field` `"chain"` otherwise, or for a chain that has
     * diverged.
     */
    nextStep(chain: any): Float64Array;
    /**
     * Address of the positions, `2 * chains()` f64.
     */
    positions_ptr(): number;
    /**
     * The landscape's name.
     */
    potential(): string;
    /**
     * Sets the step `h` and the inverse temperature `a` of the next steps
     * without a restart (see [`Optimizer::retune`]); `a` `undefined` or
     * `null` keeps the temperature (an annealing run takes no `a`).
     * Throws an `Error` with `field` `"h"` or `"a"` on a value refused.
     */
    retune(h: any, a: any): void;
    /**
     * The seed of this run (a BigInt).
     */
    seed(): bigint;
    /**
     * Address of the summary, `Summary.Len` f64 indexed by `Summary`.
     */
    summary_ptr(): number;
    /**
     * Why the run stopped (`"target reached"`, `"step budget spent"`), or
     * `undefined` while it runs.
     */
    termination(): string | undefined;
    /**
     * Address of the per-chain values, `chains()` f64: an
     * optimiser's `U` of each chain (NaN for a chain that diverged,
     * finite for every other), descent's best of each so far.
     */
    values_ptr(): number;
    /**
     * Address of the velocities, `2 * chains()` f64 (zeros for
     * OLA and for descent).
     */
    velocities_ptr(): number;
}

/**
 * Slots of the summary buffer ([`Optimizer::summary_ptr`]), all f64.
 */
export enum Summary {
    /**
     * Steps done (the current iterate index `k`); exact below `2^53`.
     */
    Iteration = 0,
    /**
     * First coordinate of the running best point.
     */
    BestX0 = 1,
    /**
     * Second coordinate of the running best point.
     */
    BestX1 = 2,
    /**
     * `U` at the running best point.
     */
    BestValue = 3,
    /**
     * Iterate at which the running best was visited.
     */
    BestIteration = 4,
    /**
     * Inverse temperature `a` of the last step (of the first, before any).
     */
    A = 5,
    /**
     * Chains that diverged (frozen, excluded from the best).
     */
    Diverged = 6,
    /**
     * The landscape's global minimum `U*`.
     */
    Minimum = 7,
    /**
     * Why the run stopped ([`termination_code`]): 0 while it runs.
     */
    Termination = 8,
    /**
     * Number of slots.
     */
    Len = 9,
}

/**
 * The kernel's step coefficients of `sampler` (`"hrla"`, `"ula"`,
 * `"ola"`) at step `h` and inverse temperature `a`, in f64 (see the
 * module's layout); an `Error` with the kernel's message when it refuses
 * `h` or `a`.
 */
export function coefficients(sampler: string, h: number, a: number): Float64Array;

/**
 * A visitor's formula `U` on a grid laid out as [`potential_grid`]'s, NaN
 * where it is not finite ([`formula_picture`]): the picture of a formula
 * the page refuses on its box, or sees beyond it. Throws an `Error` with
 * `field` `"formula"` (with a `column`) when the formula cannot be read,
 * and as [`potential_grid`] on the bounds and counts.
 */
export function formulaPicture(formula: string, x0: any, x1: any, y0: any, y1: any, nx: any, ny: any): Float64Array;

/**
 * A global minimiser `x*` of the landscape `potential` (one of them when
 * there are several; for a visitor's formula, where its estimated `U*`
 * was found), `[x0, x1]`; throws like [`global_minimum`].
 */
export function global_minimiser(potential: any): Float64Array;

/**
 * The global minimum `U*` of the landscape `name` (the kernel's
 * [`KnownMinimum`]; for a visitor's formula, the estimate of
 * [`Landscape::formula`]); throws an `Error` with `field` `"potential"`
 * when `name` is not a landscape's name or a formula object, `"formula"`
 * (with a `column`) when the formula cannot be read, `"box"` when it
 * cannot be evaluated finitely over its box.
 */
export function global_minimum(name: any): number;

/**
 * Where the coefficients start in the constants buffer.
 */
export function gpu_coef_offset(): number;

/**
 * The generators of chains `first .. first + count` of a run of `seed`
 * (a whole number or a BigInt, as `new Optimizer` takes it; `first` and
 * `count` whole numbers, the chains within [`GPU_MAX_CHAINS`]): four
 * 32-bit words each, chain `c`'s
 * `Xoshiro128PlusPlus::seed_from_u64(chain_seed(seed, c))` as `hrla-gpu`
 * seeds it (its state's bytes read as little-endian words).
 */
export function gpu_generators(seed: any, first: any, count: any): Uint32Array;

/**
 * The start of chains `first .. first + count` of a run of `seed` (read
 * as [`gpu_generators`] reads them) from `N(centre, spread^2 I)`, as the
 * kernel draws it in f32 on the CPU from the generators of
 * [`gpu_generators`]: `centre_i + spread * z` with the kernel's
 * `f32::standard_normal`, coordinate-major (`x1` of the `k`-th chain at
 * `k`, `x2` at `count + k`). The device's `init` draws the same numbers;
 * the browser tests compare the two bit for bit.
 */
export function gpu_kernel_starts(seed: any, first: any, count: any, centre_x: number, centre_y: number, spread: number): Float32Array;

/**
 * The most chains the page's device path runs.
 */
export function gpu_max_chains(): number;

/**
 * The most steps of one dispatch.
 */
export function gpu_max_steps(): number;

/**
 * The WGSL program of `hrla-gpu` (f32, IEEE products, a Gaussian start)
 * for landscape `name` in 2-D and `sampler`'s step: entry points `init`
 * and `step` of `hrla-gpu`'s `chains.wgsl`, over its bindings 0 to 6.
 * It is written for Chromium's compiler, which would warn on the
 * visitor's console about the `return` that naga asks for.
 */
export function gpu_program(name: string, sampler: string): string;

/**
 * Whether the device path runs landscape `name` (a visitor's formula runs
 * on the CPU only).
 */
export function gpu_supports(name: string): boolean;

/**
 * The constants buffer of a run (see the module's layout), in f32: the
 * Ziggurat's tables rounded as the kernel's f32 normals round them, the
 * start `N(centre, spread^2 I)`, and [`GPU_MAX_STEPS`] copies of the
 * step's coefficients at constant `a`, each the kernel's f64 value
 * rounded once.
 */
export function gpu_tables(sampler: string, h: number, a: number, centre_x: number, centre_y: number, spread: number): Float32Array;

/**
 * The capacity in chains, [`MAX_CHAINS`].
 */
export function max_chains(): number;

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
 */
export function potential_grid(name: any, x0: any, x1: any, y0: any, y1: any, nx: any, ny: any): Float64Array;

/**
 * The names of the landscapes, as `potential` takes them.
 */
export function potential_names(): string[];

/**
 * A fresh seed from the browser's `crypto.getRandomValues` (the OS
 * natively), as a BigInt, for the "random" button: the page shows it so
 * the run can be replayed.
 */
export function random_seed(): bigint;

/**
 * The module's `WebAssembly.Memory`, for typed-array views (named so as
 * not to clash with the module's own `memory` export).
 */
export function wasm_memory(): any;

export type InitInput = RequestInfo | URL | Response | BufferSource | WebAssembly.Module;

export interface InitOutput {
    readonly memory: WebAssembly.Memory;
    readonly __wbg_descent_free: (a: number, b: number) => void;
    readonly __wbg_experiment_free: (a: number, b: number) => void;
    readonly __wbg_optimizer_free: (a: number, b: number) => void;
    readonly coefficients: (a: number, b: number, c: number, d: number) => [number, number, number, number];
    readonly descent_advance: (a: number, b: any) => [number, number, number];
    readonly descent_chains: (a: number) => number;
    readonly descent_new_js: (a: any, b: any) => [number, number, number];
    readonly descent_positions_ptr: (a: number) => number;
    readonly descent_restarts: (a: number) => number;
    readonly descent_seed: (a: number) => bigint;
    readonly descent_summary_ptr: (a: number) => number;
    readonly descent_termination: (a: number) => [number, number];
    readonly descent_values_ptr: (a: number) => number;
    readonly descent_velocities_ptr: (a: number) => number;
    readonly experiment_advance: (a: number, b: any) => [number, number, number];
    readonly experiment_iteration: (a: number) => number;
    readonly experiment_new_js: (a: any) => [number, number, number];
    readonly experiment_record_ptr: (a: number) => number;
    readonly experiment_rowLength: () => number;
    readonly experiment_runs: (a: number) => number;
    readonly experiment_steps: (a: number) => number;
    readonly formulaPicture: (a: number, b: number, c: any, d: any, e: any, f: any, g: any, h: any) => [number, number, number, number];
    readonly global_minimiser: (a: any) => [number, number, number, number];
    readonly global_minimum: (a: any) => [number, number, number];
    readonly gpu_coef_offset: () => number;
    readonly gpu_generators: (a: any, b: any, c: any) => [number, number, number, number];
    readonly gpu_kernel_starts: (a: any, b: any, c: any, d: number, e: number, f: number) => [number, number, number, number];
    readonly gpu_max_chains: () => number;
    readonly gpu_max_steps: () => number;
    readonly gpu_program: (a: number, b: number, c: number, d: number) => [number, number, number, number];
    readonly gpu_supports: (a: number, b: number) => number;
    readonly gpu_tables: (a: number, b: number, c: number, d: number, e: number, f: number, g: number) => [number, number, number, number];
    readonly max_chains: () => number;
    readonly optimizer_advance: (a: number, b: any) => [number, number, number];
    readonly optimizer_chains: (a: number) => number;
    readonly optimizer_minimiser: (a: number) => [number, number];
    readonly optimizer_new: (a: any) => [number, number, number];
    readonly optimizer_nextStep: (a: number, b: any) => [number, number, number, number];
    readonly optimizer_positions_ptr: (a: number) => number;
    readonly optimizer_potential: (a: number) => [number, number];
    readonly optimizer_retune: (a: number, b: any, c: any) => [number, number];
    readonly optimizer_seed: (a: number) => bigint;
    readonly optimizer_summary_ptr: (a: number) => number;
    readonly optimizer_termination: (a: number) => [number, number];
    readonly optimizer_values_ptr: (a: number) => number;
    readonly optimizer_velocities_ptr: (a: number) => number;
    readonly potential_grid: (a: any, b: any, c: any, d: any, e: any, f: any, g: any) => [number, number, number, number];
    readonly potential_names: () => [number, number];
    readonly random_seed: () => [bigint, number, number];
    readonly wasm_memory: () => any;
    readonly __wbindgen_malloc: (a: number, b: number) => number;
    readonly __wbindgen_realloc: (a: number, b: number, c: number, d: number) => number;
    readonly __wbindgen_free: (a: number, b: number, c: number) => void;
    readonly __wbindgen_exn_store: (a: number) => void;
    readonly __externref_table_alloc: () => number;
    readonly __wbindgen_externrefs: WebAssembly.Table;
    readonly __externref_table_dealloc: (a: number) => void;
    readonly __externref_drop_slice: (a: number, b: number) => void;
    readonly __wbindgen_start: () => void;
}

export type SyncInitInput = BufferSource | WebAssembly.Module;

/**
 * Instantiates the given `module`, which can either be bytes or
 * a precompiled `WebAssembly.Module`.
 *
 * @param {{ module: SyncInitInput }} module - Passing `SyncInitInput` directly is deprecated.
 *
 * @returns {InitOutput}
 */
export function initSync(module: { module: SyncInitInput } | SyncInitInput): InitOutput;

/**
 * If `module_or_path` is {RequestInfo} or {URL}, makes a request and
 * for everything else, calls `WebAssembly.instantiate` directly.
 *
 * @param {{ module_or_path: InitInput | Promise<InitInput> }} module_or_path - Passing `InitInput` directly is deprecated.
 *
 * @returns {Promise<InitOutput>}
 */
export default function __wbg_init (module_or_path?: { module_or_path: InitInput | Promise<InitInput> } | InitInput | Promise<InitInput>): Promise<InitOutput>;
