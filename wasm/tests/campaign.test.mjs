// A seeded property campaign over the wasm wrapper's entry points: the
// settings object of `new Optimizer`, `advance`, `potential_grid` and
// `global_minimum`, fed valid values spoilt with wrong types, missing and
// extra keys, hostile numbers (NaN, ±inf, ±1e308, -0, subnormals, 2^53,
// 2^64), huge and sparse arrays, getters that throw and Proxies. Whatever
// comes in:
//   - nothing traps: every throw is a typed Error (isTypedError), and the
//     module still computes the same numbers at the end as at the start;
//   - nothing hangs: the work is bounded (every count asked of a live run
//     is at most MAX_ASK steps; larger counts only go to runs that have
//     stopped, which must return 0 at once), and a call returns at most
//     the steps asked;
//   - nothing returned without an error is non-finite: the summary of a
//     run (best value and point, a, U*), the values of its live chains
//     (exactly `chains - diverged` of them finite), every grid value and
//     every global minimum.
// The generator is seeded: the same cases every run. Needs the Node build:
// see load.mjs.
import assert from "node:assert/strict";
import { test } from "node:test";
import { OK, isTypedError, positions, summary, values, wasm } from "./load.mjs";

const S = wasm.Summary;
const NAMES = [...wasm.potential_names()];
const MAX_STEPS = 2 ** 32 - 1;
/** The most steps asked of a run that has not stopped: bounds the work. */
const MAX_ASK = 200;

/** mulberry32: a small seeded generator, enough to pick test inputs. */
function generator(seed) {
  let a = seed >>> 0;
  const next = () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 2 ** 32;
  };
  const int = (lo, hi) => lo + Math.floor(next() * (hi - lo + 1));
  const pick = (xs) => xs[Math.floor(next() * xs.length)];
  const chance = (p) => next() < p;
  return { next, int, pick, chance };
}

const HOSTILE_NUMBERS = [
  NaN,
  Infinity,
  -Infinity,
  1e308,
  -1e308,
  Number.MAX_VALUE,
  -0,
  0,
  5e-324,
  -5e-324,
  2 ** 53,
  2 ** 53 - 1,
  2 ** 64,
  2 ** 32 + 3,
  2 ** 32 - 1,
  -1,
  0.5,
  2.5,
  1e-300,
  1e154,
];

/** A thrower for getters and traps: Errors, and things that are not. */
function thrown(r) {
  return r.pick([new Error("getter error"), new TypeError("type"), "a string", 42, undefined, null, { message: 7 }]);
}

/** Anything a careless or hostile caller might pass where a value goes. */
function hostileValue(r) {
  switch (r.int(0, 9)) {
    case 0:
    case 1:
    case 2:
      return r.pick(HOSTILE_NUMBERS);
    case 3:
      return r.pick(["3", "", "hrla", "rastrigin", "NaN"]);
    case 4:
      return r.pick([3n, -1n, 2n ** 64n, 2n ** 64n - 1n, 0n]);
    case 5:
      return r.pick([null, undefined, true, false, Symbol("s")]);
    case 6:
      return r.pick([{}, [], [1, 2], [3, 3, 3], new Array(1e6), new Array(2 ** 32 - 1), Float64Array.of(1, 2)]);
    case 7:
      return r.pick([new Number(3), () => 3, new Proxy({}, {}), new Proxy([1, 2], {})]);
    case 8: {
      const { proxy, revoke } = Proxy.revocable([0, 0], {});
      revoke();
      return proxy;
    }
    default: {
      const t = thrown(r);
      return new Proxy([0, 0], {
        get() {
          throw t;
        },
      });
    }
  }
}

/** Valid settings, drawn at random. */
function validSettings(r) {
  const linear = r.chance(0.3);
  const aLow = r.pick([0.1, 0.5, 1]);
  return {
    potential: r.pick(NAMES),
    sampler: r.pick(["hrla", "ula", "ola", "HRLA"]),
    a: linear ? NaN : r.pick([0.5, 1, 4, 10]),
    annealing: linear ? { aLow, aHigh: aLow * r.pick([2, 8, 40]), steps: r.int(1, 300) } : null,
    h: r.pick([0.001, 0.01, 0.05, 0.2, 1, 5]),
    chains: r.pick([1, 2, 5, 10, 33, 64, 1024]),
    centre: [r.pick([0, 3, -2.5, 1e3]), r.pick([0, 3, -6])],
    spread: r.pick([0, 0.1, 1, Math.sqrt(10), 100]),
    seed: r.chance(0.5) ? r.int(0, 2 ** 31) : BigInt(r.int(0, 2 ** 31)) * 2n ** 32n + BigInt(r.int(0, 2 ** 31)),
    stopSteps: r.chance(0.3) ? r.int(1, 400) : null,
    stopTarget: r.chance(0.2) ? r.pick([-1, 0.01, 1, 100]) : null,
    escape: r.chance(0.3) ? r.pick([1, 100, 5000]) : null,
  };
}

/** `s[key] = value`, even over a getter an earlier spoiling put there. */
function put(s, key, value) {
  Object.defineProperty(s, key, { value, enumerable: true, configurable: true, writable: true });
}

/** One to three spoilings of valid settings (sometimes none). */
function spoil(r, settings) {
  const keys = Object.keys(settings);
  let s = { ...settings };
  const n = r.chance(0.15) ? 0 : r.int(1, 3);
  for (let i = 0; i < n; i++) {
    switch (r.int(0, 9)) {
      case 0:
      case 1:
      case 2:
        put(s, r.pick(keys), hostileValue(r));
        break;
      case 3:
        delete s[r.pick(keys)];
        break;
      case 4:
        put(s, r.pick(["stopstep", "center", "K", "steps", "aLow", "0", "__proto__x"]), r.pick([1, null, "x"]));
        break;
      case 5:
        put(s, "centre", r.pick([[0], [0, 0, 99], [, 1], ["1", "2"], [NaN, 0], [1e308, -1e308], [-0, 5e-324], new Array(2 ** 32 - 1)])); // eslint-disable-line no-sparse-arrays
        break;
      case 6:
        put(s, "annealing", r.pick([
          { aLow: hostileValue(r), aHigh: 4, steps: 10 },
          { aLow: 0.1, aHigh: 4, steps: hostileValue(r) },
          { aLow: 0.1, aHigh: 4, steps: 10, extra: 1 },
          { aLow: 0.1, aHigh: 4 },
          true,
          "linear",
          [0.1, 4, 10],
          { aLow: 4, aHigh: 0.1, steps: 2 ** 53 - 1 },
        ]));
        break;
      case 7: {
        const key = r.pick(keys);
        const t = thrown(r);
        delete s[key];
        Object.defineProperty(s, key, {
          enumerable: true,
          configurable: true,
          get() {
            throw t;
          },
        });
        break;
      }
      case 8: {
        const key = r.pick(keys);
        const t = thrown(r);
        const which = r.int(0, 2);
        s = new Proxy(s, {
          get(target, k) {
            if (which === 0 && k === key) throw t;
            return target[k];
          },
          ownKeys(target) {
            if (which === 1) throw t;
            return Reflect.ownKeys(target);
          },
        });
        break;
      }
      default: {
        // A Proxy that answers differently each time it is asked.
        let calls = 0;
        s = new Proxy(s, {
          get(target, k) {
            calls++;
            return calls % 3 === 0 ? hostileValue(r) : target[k];
          },
        });
      }
    }
  }
  return s;
}

/** `{ value }` of `f()`, or `{ error }` with what it threw: assertions stay out of the try. */
function attempt(f) {
  try {
    return { value: f() };
  } catch (error) {
    return { error: error ?? new Error(`threw ${error}`) };
  }
}

const isCount = (v, max) => typeof v === "number" && Number.isInteger(v) && v >= 0 && v <= max;

/** A count for a live run's `advance`: mostly small and valid, often hostile, never a valid count above MAX_ASK. */
function stepCount(r) {
  if (r.chance(0.6)) return r.int(0, MAX_ASK);
  const v = r.chance(0.7) ? r.pick(HOSTILE_NUMBERS) : hostileValue(r);
  return isCount(v, MAX_STEPS) && v > MAX_ASK ? -v : v;
}

/** A value in a message, safely: String() itself throws on Symbols and hostile Proxies. */
function show(v) {
  try {
    return String(v);
  } catch {
    return `(a ${typeof v})`;
  }
}


/** The invariants of a run's published state. */
function checkRun(opt, where) {
  const s = summary(opt);
  const n = opt.chains();
  assert.ok(isCount(s[S.Iteration], 2 ** 53), `${where}: iteration ${s[S.Iteration]}`);
  for (const k of ["BestValue", "BestX0", "BestX1", "BestIteration", "A", "Minimum"]) {
    assert.ok(Number.isFinite(s[S[k]]), `${where}: ${k} = ${s[S[k]]}`);
  }
  assert.ok(s[S.A] > 0, `${where}: a = ${s[S.A]}`);
  assert.ok(s[S.BestValue] >= s[S.Minimum] - 1e-9 * Math.max(1, Math.abs(s[S.Minimum])), `${where}: best below U*`);
  const live = values(opt).filter(Number.isFinite).length;
  assert.equal(live, n - s[S.Diverged], `${where}: ${live} finite values, ${s[S.Diverged]} of ${n} diverged`);
  assert.ok(live > 0, `${where}: no live chain and no error`);
  const x = positions(opt);
  const u = values(opt);
  for (let c = 0; c < n; c++) {
    if (Number.isFinite(u[c])) assert.ok(Number.isFinite(x[2 * c]) && Number.isFinite(x[2 * c + 1]), `${where}: chain ${c}`);
  }
}

/** The run every case is measured against: the module must still compute it bit for bit at the end. */
function fingerprint() {
  const opt = new wasm.Optimizer({ ...OK, chains: 16, seed: 99n });
  opt.advance(50);
  const f = [summary(opt), positions(opt), values(opt)];
  opt.free();
  return f;
}

test("the settings object and advance: no trap, no hang, nothing non-finite without an error", (t) => {
  const before = fingerprint();
  const r = generator(0x5eed_0022);
  const count = { cases: 0, built: 0, refused: 0, fields: {}, advances: 0, advanceOk: 0, advanceRefused: 0, runFailed: 0, runErrors: {}, stoppedCalls: 0, steps: 0 };
  const CASES = 3000;
  for (let i = 0; i < CASES; i++) {
    const settings = spoil(r, validSettings(r));
    count.cases++;
    let opt;
    try {
      opt = new wasm.Optimizer(settings);
    } catch (e) {
      assert.ok(isTypedError(e), `case ${i}: ${show(e)}`);
      assert.ok(e.field === undefined || typeof e.field === "string");
      count.refused++;
      count.fields[e.field ?? "(none)"] = (count.fields[e.field ?? "(none)"] ?? 0) + 1;
      continue;
    }
    count.built++;
    checkRun(opt, `case ${i} built`);
    assert.equal(summary(opt)[S.Iteration], 0);
    let failed = false;
    for (let j = r.int(1, 3); j > 0 && !failed; j--) {
      const stopped = summary(opt)[S.Termination] !== 0;
      // Counts beyond MAX_ASK only go to stopped runs: they must do nothing.
      const steps = stopped && r.chance(0.5) ? r.pick([MAX_STEPS, 2 ** 30, MAX_ASK]) : stepCount(r);
      const valid = isCount(steps, MAX_STEPS);
      if (valid && !stopped) assert.ok(steps <= MAX_ASK);
      const k0 = summary(opt)[S.Iteration];
      count.advances++;
      if (stopped) count.stoppedCalls++;
      const { value: done, error: e } = attempt(() => opt.advance(steps));
      if (e === undefined) {
        assert.ok(valid, `case ${i}: advance(${show(steps)}) accepted`);
        assert.ok(isCount(done, steps), `case ${i}: advance(${show(steps)}) returned ${done}`);
        if (stopped) assert.equal(done, 0, `case ${i}: a stopped run stepped`);
        assert.equal(summary(opt)[S.Iteration], k0 + done);
        count.advanceOk++;
        count.steps += done;
        checkRun(opt, `case ${i} after advance(${show(steps)})`);
      } else {
        assert.ok(isTypedError(e), `case ${i}: advance(${show(steps)}): ${show(e)}`);
        if (e.field === "steps") {
          assert.ok(!valid, `case ${i}: advance(${show(steps)}) refused: ${e.message}`);
          assert.equal(summary(opt)[S.Iteration], k0, `case ${i}: a refused advance stepped`);
          count.advanceRefused++;
        } else {
          // The run failed on the way (every chain diverged): no result to check.
          assert.ok(valid, `case ${i}: advance(${show(steps)}): ${e.message}`);
          count.runFailed++;
          const kind = e.message.replace(/[0-9]+/g, "N");
          count.runErrors[kind] = (count.runErrors[kind] ?? 0) + 1;
          failed = true;
        }
      }
    }
    opt.free();
  }
  assert.deepEqual(fingerprint(), before, "the module computes differently after the campaign");
  t.diagnostic(JSON.stringify(count));
  // Not vacuous: both sides of every property were exercised.
  assert.equal(count.cases, CASES);
  assert.ok(count.built > 300 && count.refused > 300, JSON.stringify(count));
  assert.ok(count.advanceOk > 300 && count.advanceRefused > 100 && count.stoppedCalls > 20, JSON.stringify(count));
  assert.ok(count.fields.settings > 0 && count.fields.centre > 0 && count.fields["(none)"] > 0, JSON.stringify(count.fields));
});

test("potential_grid and global_minimum: no trap, and every value returned is finite", (t) => {
  const r = generator(0x9e1d_0022);
  const count = { grids: 0, gridOk: 0, gridRefused: 0, fields: {}, minima: 0, minimumOk: 0, minimumRefused: 0 };
  const coordinate = () =>
    r.chance(0.5) ? r.pick([-10, -5, -1, 0, 1, 2, 5, 10, -1e150, 1e150, -1e200, 1e200]) : r.pick(HOSTILE_NUMBERS);
  const points = () => (r.chance(0.7) ? r.int(1, 64) : r.chance(0.5) ? r.pick(HOSTILE_NUMBERS) : hostileValue(r));
  const GRIDS = 3000;
  for (let i = 0; i < GRIDS; i++) {
    // Two cases in five are well-formed (the box may still be too wide, or U
    // overflow in it); the others have hostile parts.
    const wellFormed = r.chance(0.4);
    const name = wellFormed || r.chance(0.8) ? r.pick(NAMES) : hostileValue(r);
    let [x0, x1, y0, y1] = [coordinate(), coordinate(), coordinate(), coordinate()];
    if (wellFormed || r.chance(0.5)) {
      [x0, x1, y0, y1] = [Math.min(x0, x1), Math.max(x0, x1), Math.min(y0, y1), Math.max(y0, y1)];
    }
    if (!wellFormed && r.chance(0.1)) x0 = hostileValue(r);
    const [nx, ny] = wellFormed ? [r.int(1, 64), r.int(1, 64)] : [points(), points()];
    count.grids++;
    const { value: g, error: e } = attempt(() => wasm.potential_grid(name, x0, x1, y0, y1, nx, ny));
    if (e === undefined) {
      assert.equal(g.length, nx * ny, `grid ${i}`);
      assert.ok(
        g.every(Number.isFinite),
        `grid ${i}: ${show(name)} [${show(x0)}, ${show(x1)}] x [${show(y0)}, ${show(y1)}] ${nx} x ${ny} has non-finite values`,
      );
      count.gridOk++;
    } else {
      assert.ok(isTypedError(e), `grid ${i}: ${show(e)}`);
      assert.equal(typeof e.field, "string", e.message);
      count.gridRefused++;
      count.fields[e.field] = (count.fields[e.field] ?? 0) + 1;
    }
  }
  for (let i = 0; i < 500; i++) {
    const name = r.chance(0.5) ? r.pick(NAMES) : hostileValue(r);
    count.minima++;
    const { value: m, error: e } = attempt(() => wasm.global_minimum(name));
    if (e === undefined) {
      assert.ok(Number.isFinite(m), `global_minimum(${show(name)}) = ${m}`);
      count.minimumOk++;
    } else {
      assert.ok(isTypedError(e) && e.field === "potential", `global_minimum(${show(name)}): ${show(e)}`);
      count.minimumRefused++;
    }
  }
  t.diagnostic(JSON.stringify(count));
  assert.ok(count.gridOk > 300 && count.gridRefused > 300, JSON.stringify(count));
  for (const field of ["potential", "box", "nx", "ny", "x0"]) assert.ok(count.fields[field] > 0, JSON.stringify(count.fields));
  assert.ok(count.minimumOk > 50 && count.minimumRefused > 50, JSON.stringify(count));
});
