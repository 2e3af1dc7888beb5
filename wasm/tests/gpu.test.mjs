// The exports of the page's WebGPU path (wasm/src/gpu.rs) fed hostile
// input: each gives finite numbers or a typed Error with a message, never a
// trap, a NaN or an infinity; and a seeded campaign of mixed settings.
import assert from "node:assert/strict";
import { test } from "node:test";
import { OK, isTypedError, wasm } from "./load.mjs";

const BAD_NUMBERS = [NaN, Infinity, -Infinity, 0, -1, 1e300];

/** Calls `f`; returns its value, or "refused" after checking the Error is typed. */
function outcome(f) {
  try {
    return f();
  } catch (e) {
    assert.ok(isTypedError(e), `not a typed error: ${e}`);
    return "refused";
  }
}

const allFinite = (xs) => Array.from(xs).every(Number.isFinite);

test("coefficients: the kernel's refusals of sampler, h and a", () => {
  for (const s of ["hrla", "ula", "ola", "HRLA"]) {
    const c = wasm.coefficients(s, 0.01, 4);
    assert.equal(c.length, 8);
    assert.ok(allFinite(c), `${s}: ${c}`);
  }
  assert.equal(outcome(() => wasm.coefficients("sgd", 0.01, 4)), "refused");
  assert.equal(outcome(() => wasm.coefficients("", 0.01, 4)), "refused");
  for (const bad of BAD_NUMBERS.filter((v) => v !== 1e300)) {
    assert.equal(outcome(() => wasm.coefficients("hrla", bad, 4)), "refused", `h = ${bad}`);
    assert.equal(outcome(() => wasm.coefficients("ola", 0.01, bad)), "refused", `a = ${bad}`);
  }
  // The kernel's message names the setting.
  assert.throws(() => wasm.coefficients("hrla", -1, 4), /h/);
});

test("gpu_tables: a start that is not finite in f32 is refused", () => {
  const t = wasm.gpu_tables("hrla", 0.01, 4, 3, 3, 0.5);
  assert.equal(t.length, wasm.gpu_coef_offset() + 8 * wasm.gpu_max_steps());
  assert.ok(allFinite(t));
  for (const bad of [NaN, Infinity, 1e39]) {
    assert.equal(outcome(() => wasm.gpu_tables("hrla", 0.01, 4, bad, 0, 1)), "refused", `cx = ${bad}`);
    assert.equal(outcome(() => wasm.gpu_tables("hrla", 0.01, 4, 0, bad, 1)), "refused", `cy = ${bad}`);
    assert.equal(outcome(() => wasm.gpu_tables("hrla", 0.01, 4, 0, 0, bad)), "refused", `spread = ${bad}`);
  }
  assert.equal(outcome(() => wasm.gpu_tables("hrla", 0.01, 4, 0, 0, -0.5)), "refused");
  assert.equal(outcome(() => wasm.gpu_tables("ula", 0, 4, 0, 0, 1)), "refused");
  // Coefficients finite in f64 but not in f32 (OLA's drift is h).
  assert.ok(allFinite(wasm.coefficients("ola", 1e39, 40)));
  assert.throws(() => wasm.gpu_tables("ola", 1e39, 40, 0, 0, 1), /exceeds f32/);
});

test("gpu_generators and gpu_kernel_starts: chains beyond 10^6 refused; seeds of 64 bits", () => {
  const max = wasm.gpu_max_chains();
  assert.equal(max, 1_000_000);
  assert.equal(wasm.gpu_generators(1n, max - 2, 2).length, 8);
  assert.equal(outcome(() => wasm.gpu_generators(1n, max - 1, 2)), "refused");
  assert.equal(outcome(() => wasm.gpu_generators(1n, 2 ** 32 - 1, 2)), "refused");
  const a = wasm.gpu_generators(2n ** 64n - 1n, 0, 3);
  const b = wasm.gpu_generators(2n ** 64n - 2n, 0, 3);
  assert.notDeepEqual(Array.from(a), Array.from(b));
  // Chain c's generator does not depend on where the slice starts.
  assert.deepEqual(Array.from(wasm.gpu_generators(5n, 0, 4)).slice(8), Array.from(wasm.gpu_generators(5n, 2, 2)));
  const x = wasm.gpu_kernel_starts(5n, 0, 100, 1, 2, 0.5);
  assert.equal(x.length, 200);
  assert.ok(allFinite(x));
  assert.equal(outcome(() => wasm.gpu_kernel_starts(5n, 0, 100, 1, 2, NaN)), "refused");
  assert.equal(outcome(() => wasm.gpu_kernel_starts(5n, max, 1, 1, 2, 0.5)), "refused");
});

/** The message of what `f` throws, which must be a typed Error naming `field`. */
function refusal(f, field) {
  try {
    f();
  } catch (e) {
    assert.ok(isTypedError(e), `not a typed error: ${e}`);
    assert.equal(e.field, field, e.message);
    return e.message;
  }
  assert.fail(`not refused (${field})`);
}

test("gpu_generators and gpu_kernel_starts read counts and seeds as new Optimizer does, not modulo 2^32 or 2^64", () => {
  const starts = (seed, first, count) => wasm.gpu_kernel_starts(seed, first, count, 1, 2, 0.5);
  for (const f of [wasm.gpu_generators, starts]) {
    for (const bad of [2 ** 32 + 2, NaN, -1, 2.5, Infinity, "2", 2n, null, undefined, {}, [2], new Number(2)]) {
      assert.match(refusal(() => f(1n, 0, bad), "count"), /^`count` must be a whole number between 0 and 1000000, got /);
      assert.match(refusal(() => f(1n, bad, 2), "first"), /^`first` must be a whole number between 0 and 1000000, got /);
    }
    assert.match(refusal(() => f(1n, 0, 2n), "count"), /got a BigInt 2n; pass a Number$/);
    for (const seed of [-1n, 2n ** 64n, 2n ** 64n + 1n, -1, 2 ** 53, 1.5, NaN, "1", null, undefined]) {
      const message = refusal(() => f(seed, 0, 2), "seed");
      // The same refusal as the optimiser's.
      assert.throws(() => new wasm.Optimizer({ ...OK, seed }), (e) => isTypedError(e) && e.field === "seed" && e.message === message);
    }
  }
  // A seed is the same seed as a number or a BigInt; -0 counts as 0.
  assert.deepEqual(Array.from(wasm.gpu_generators(7, -0, 3)), Array.from(wasm.gpu_generators(7n, 0, 3)));
  assert.deepEqual(Array.from(starts(2 ** 53 - 1, 4, 2)), Array.from(starts(2n ** 53n - 1n, 4, 2)));
  assert.equal(wasm.gpu_generators(1n, 5, 0).length, 0);
});

test("gpu_program: every built-in landscape and sampler; a formula or an unknown name refused", () => {
  for (const name of wasm.potential_names()) {
    assert.equal(wasm.gpu_supports(name), true, name);
    for (const s of ["hrla", "ula", "ola"]) {
      const p = wasm.gpu_program(name, s);
      assert.match(p, /fn init\(/);
      assert.match(p, /fn step\(/);
    }
  }
  for (const name of ["formula", "", "Rastrigin ", "x*x"]) {
    assert.equal(wasm.gpu_supports(name), false);
    assert.equal(outcome(() => wasm.gpu_program(name, "hrla")), "refused", name);
  }
  assert.equal(outcome(() => wasm.gpu_program("rastrigin", "nope")), "refused");
});

test("campaign: 2000 seeded settings, each finite or refused with a typed Error", () => {
  // A fixed xorshift stream: the same cases on every run.
  let state = 0x2545f491;
  const next = () => {
    state ^= state << 13;
    state ^= state >>> 17;
    state ^= state << 5;
    return (state >>> 0) / 2 ** 32;
  };
  const pick = (xs) => xs[Math.floor(next() * xs.length)];
  const numbers = [0.01, 0.1, 1, 4, 40, 1e-8, 1e8, 1e30, 1e39, -1, 0, -0, NaN, Infinity, -Infinity, 5e-324, 1.7976931348623157e308];
  let refused = 0;
  for (let i = 0; i < 2000; i++) {
    const s = pick(["hrla", "ula", "ola", "x", ""]);
    const [h, a, cx, cy, spread] = [pick(numbers), pick(numbers), pick(numbers), pick(numbers), pick(numbers)];
    const r = outcome(() => wasm.gpu_tables(s, h, a, cx, cy, spread));
    if (r === "refused") refused++;
    else assert.ok(allFinite(r), `gpu_tables(${s}, ${h}, ${a}, ${cx}, ${cy}, ${spread})`);
    const c = outcome(() => wasm.coefficients(s, h, a));
    if (c !== "refused") assert.ok(allFinite(c), `coefficients(${s}, ${h}, ${a})`);
  }
  // Both outcomes occur: the campaign reaches the refusals and the runs.
  assert.ok(refused > 100 && refused < 2000, `refused ${refused}`);
});
