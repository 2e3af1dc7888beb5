// Bad input to the wasm wrapper, as a careless or hostile caller would give
// it: each is refused with a real Error whose `field` names the setting or
// argument at fault (and whose message names it in backticks), never
// accepted with a part silently dropped, swallowed, coerced or wrapped,
// and never a trap. Needs the Node build: see load.mjs.
import assert from "node:assert/strict";
import { test } from "node:test";
import { OK, isTypedError, positions, summary, values, wasm } from "./load.mjs";

const S = wasm.Summary;

/** Asserts that `f` throws a typed Error naming `field`, its message matching `pattern`. */
function refused(f, field, pattern) {
  assert.throws(f, (e) => {
    assert.ok(isTypedError(e), `not a typed Error: ${e}`);
    assert.equal(e.field, field, e.message);
    assert.ok(e.message.includes(`\`${field}\``), `the message does not name \`${field}\`: ${e.message}`);
    if (pattern) assert.match(e.message, pattern);
    return true;
  });
}

/** The message of what `f` throws, which must be a typed Error naming `box`. */
function refused2(f) {
  try {
    f();
  } catch (e) {
    assert.ok(isTypedError(e));
    assert.equal(e.field, "box");
    return e.message;
  }
  assert.fail("not refused");
}

/** `settings` with `key` read through a getter that throws `thrown`. */
function throwingGetter(key, thrown) {
  const s = { ...OK };
  delete s[key];
  return Object.defineProperty(s, key, {
    enumerable: true,
    get() {
      throw thrown;
    },
  });
}

/** A run of the OK settings, stepped `steps` times: its published state. */
function reference(steps = 20) {
  const opt = new wasm.Optimizer(OK);
  opt.advance(steps);
  const state = [summary(opt), positions(opt), values(opt)];
  opt.free();
  return state;
}

test("a centre with a third value, or with one, is refused naming `centre`", () => {
  refused(() => new wasm.Optimizer({ ...OK, centre: [0, 0, 99] }), "centre");
  refused(() => new wasm.Optimizer({ ...OK, centre: [0] }), "centre");
  refused(() => new wasm.Optimizer({ ...OK, centre: [] }), "centre");
  // Huge and sparse arrays: refused by their length, nothing iterated.
  refused(() => new wasm.Optimizer({ ...OK, centre: new Array(2 ** 32 - 1) }), "centre");
  refused(() => new wasm.Optimizer({ ...OK, centre: [, 1] }), "centre"); // eslint-disable-line no-sparse-arrays
  refused(() => new wasm.Optimizer({ ...OK, centre: ["1", "2"] }), "centre");
  refused(() => new wasm.Optimizer({ ...OK, centre: Float64Array.of(0, 0) }), "centre");
  refused(() => new wasm.Optimizer({ ...OK, centre: { 0: 1, 1: 2, length: 2 } }), "centre");
  // Exactly two numbers still work.
  new wasm.Optimizer({ ...OK, centre: [0, -0] }).free();
});

test("a setting whose getter throws is refused naming it, with the thrown message", () => {
  for (const key of ["potential", "sampler", "a", "h", "chains", "centre", "spread", "seed", "stopSteps", "stopTarget", "annealing"]) {
    refused(() => new wasm.Optimizer(throwingGetter(key, new RangeError(`no ${key} here`))), key, new RegExp(`threw: no ${key} here`));
  }
  // Whatever is thrown, its message reaches the Error.
  refused(() => new wasm.Optimizer(throwingGetter("h", "a bare string")), "h", /threw: a bare string/);
  refused(() => new wasm.Optimizer(throwingGetter("h", 42)), "h", /threw: 42/);
  refused(() => new wasm.Optimizer(throwingGetter("h", undefined)), "h", /threw: a thrown value without a message/);
  const hostile = Object.defineProperty({}, "message", {
    get() {
      throw new Error("again");
    },
  });
  refused(() => new wasm.Optimizer(throwingGetter("h", hostile)), "h", /threw: a thrown value without a message/);
  // Inside the annealing object and the centre array too.
  const annealing = Object.defineProperty({ aLow: 0.1, aHigh: 4 }, "steps", {
    enumerable: true,
    get() {
      throw new Error("no K");
    },
  });
  refused(() => new wasm.Optimizer({ ...OK, annealing }), "steps", /threw: no K/);
  const centre = [3, 3];
  Object.defineProperty(centre, 1, {
    get() {
      throw new Error("no y");
    },
  });
  refused(() => new wasm.Optimizer({ ...OK, centre }), "centre", /threw: no y/);
  const noLength = new Proxy([3, 3], {
    get() {
      throw new Error("no length");
    },
  });
  refused(() => new wasm.Optimizer({ ...OK, centre: noLength }), "centre", /threw: no length/);
});

test("settings behind a Proxy: its throws are refused naming the setting; a plain Proxy works", () => {
  const trap = (key) =>
    new Proxy(
      { ...OK },
      {
        get(target, k) {
          if (k === key) throw new TypeError(`trap on ${key}`);
          return target[k];
        },
      },
    );
  refused(() => new wasm.Optimizer(trap("stopSteps")), "stopSteps", /threw: trap on stopSteps/);
  refused(() => new wasm.Optimizer(trap("potential")), "potential", /threw: trap on potential/);
  const noKeys = new Proxy(
    { ...OK },
    {
      ownKeys() {
        throw new Error("no keys");
      },
    },
  );
  refused(() => new wasm.Optimizer(noKeys), "settings", /threw: no keys/);
  const { proxy, revoke } = Proxy.revocable({ ...OK }, {});
  revoke();
  refused(() => new wasm.Optimizer(proxy), "settings", /threw: .*revoked/);
  const { proxy: centre, revoke: revokeCentre } = Proxy.revocable([3, 3], {});
  revokeCentre();
  refused(() => new wasm.Optimizer({ ...OK, centre }), "centre", /revoked/);
  // A Proxy that only forwards gives the very same run.
  const opt = new wasm.Optimizer(new Proxy({ ...OK, centre: new Proxy([3, 3], {}) }, {}));
  opt.advance(20);
  assert.deepEqual([summary(opt), positions(opt), values(opt)], reference(20));
  opt.free();
});

test("a key that is no setting is refused by name, not ignored", () => {
  for (const [settings, key] of [
    [{ ...OK, stopstep: 100 }, "stopstep"],
    [{ ...OK, center: [0, 0] }, "center"],
    [{ ...OK, annealing: { aLow: 0.1, aHigh: 4, steps: 10, K: 20 } }, "K"],
  ]) {
    assert.throws(
      () => new wasm.Optimizer(settings),
      (e) => isTypedError(e) && e.message.startsWith(`\`${key}\` is not a setting`),
    );
  }
  refused(() => new wasm.Optimizer({ ...OK, annealing: true }), "annealing");
  refused(() => new wasm.Optimizer({ ...OK, annealing: "linear" }), "annealing");
  refused(() => new wasm.Optimizer({ ...OK, annealing: [0.1, 4, 10] }), "annealing");
  assert.throws(() => new wasm.Optimizer([OK]), (e) => isTypedError(e) && e.message === "settings must be an object");
});

test("advance takes a whole number of steps from 0 to 2^32 - 1, nothing else", () => {
  const opt = new wasm.Optimizer(OK);
  for (const steps of [NaN, 2 ** 32 + 3, -1, 2.5, Infinity, -Infinity, 2 ** 53, 1e308, "5", 5n, undefined, null, true, {}, [5], new Number(5)]) {
    refused(() => opt.advance(steps), "steps", /must be a whole number between 0 and 4294967295/);
    assert.equal(summary(opt)[S.Iteration], 0, `advance(${String(steps)}) stepped`);
  }
  assert.equal(opt.advance(-0), 0);
  assert.equal(opt.advance(0), 0);
  assert.equal(opt.advance(7), 7);
  assert.equal(summary(opt)[S.Iteration], 7);
  opt.free();
});

test("a refused count names what was given: a BigInt by its digits, a non-number by its type", () => {
  const opt = new wasm.Optimizer(OK);
  const got = (steps) => {
    try {
      opt.advance(steps);
    } catch (e) {
      assert.ok(isTypedError(e));
      return e.message.slice(e.message.indexOf(", got ") + 6);
    }
    assert.fail(`advance(${String(steps)}) not refused`);
  };
  assert.equal(got(5n), "a BigInt 5n; pass a Number");
  assert.equal(got(-3n), "a BigInt -3n; pass a Number");
  assert.equal(got(2n ** 64n - 1n), "a BigInt 18446744073709551615n; pass a Number");
  assert.equal(got(10n ** 30n), "a BigInt of 31 characters; pass a Number");
  assert.equal(got("5"), "a string; pass a Number");
  assert.equal(got(undefined), "undefined; pass a Number");
  assert.equal(got(null), "null; pass a Number");
  assert.equal(got(true), "a boolean; pass a Number");
  assert.equal(got(Symbol("s")), "a symbol; pass a Number");
  assert.equal(got(() => 5), "a function; pass a Number");
  assert.equal(got(new Number(5)), "an object; pass a Number");
  assert.equal(got(NaN), "NaN");
  assert.equal(got(2.5), "2.5");
  assert.equal(got(-1), "-1");
  assert.equal(summary(opt)[S.Iteration], 0);
  opt.free();
});

test("advance on a run that has stopped does nothing and says so, whatever the count", () => {
  const opt = new wasm.Optimizer({ ...OK, stopSteps: 5 });
  assert.equal(opt.advance(10), 5);
  assert.equal(opt.termination(), "step budget spent");
  // Returns at once: no stepping through 2^32 - 1 empty iterations.
  assert.equal(opt.advance(2 ** 32 - 1), 0);
  assert.equal(opt.advance(2 ** 30), 0);
  assert.equal(summary(opt)[S.Iteration], 5);
  opt.free();
});

test("potential_grid refuses a box whose grid cannot be computed finitely", () => {
  const grid = (...args) => wasm.potential_grid("rastrigin", ...args);
  // The width overflows: every cell centre would be NaN.
  refused(() => grid(-1e308, 1e308, -1e308, 1e308, 4, 4), "box", /too wide/);
  refused(() => grid(-1, 1, -Number.MAX_VALUE, Number.MAX_VALUE, 4, 4), "box", /too wide/);
  // U itself overflows far out (x^2 beyond 1.3e154).
  refused(() => grid(-1e200, 1e200, -1, 1, 4, 4), "box", /U = inf at/);
  refused(() => grid(-Infinity, 1, -1, 1, 4, 4), "box", /must be finite with x0 < x1/);
  refused(() => grid(1, 1, -1, 1, 4, 4), "box", /must be finite with x0 < x1/);
  // Every value of an accepted grid is finite, even out to 1e150.
  const far = grid(-1e150, 1e150, -1e150, 1e150, 9, 9);
  assert.equal(far.length, 81);
  assert.ok(far.every(Number.isFinite));
  // Numbers must be numbers, counts whole numbers in 1..=MAX_GRID: no
  // coercion, no wrapping modulo 2^32.
  refused(() => grid("0", 1, 0, 1, 4, 4), "x0");
  refused(() => grid(0, 1, 0, 1n, 4, 4), "y1");
  refused(() => grid(0, 1, 0, 1, 2 ** 32 + 5, 4), "nx");
  refused(() => grid(0, 1, 0, 1, 4, 2.5), "ny");
  refused(() => grid(0, 1, 0, 1, -1, 4), "nx");
  refused(() => grid(0, 1, 0, 1, 0, 4), "nx");
  refused(() => grid(0, 1, 0, 1, 4096, 4096), "nx", /between 1 and 4194304 points/);
  assert.equal(grid(0, 1, 0, 1, 3, 2).length, 6);
});

test("an argument that is not a landscape's name is refused, not a trap", () => {
  const before = reference();
  for (const name of [42, 7, undefined, null, {}, ["rastrigin"], 1n, "sphere", ""]) {
    refused(() => wasm.potential_grid(name, 0, 1, 0, 1, 4, 4), "potential", /must be one of rastrigin/);
    refused(() => wasm.global_minimum(name), "potential", /must be one of rastrigin/);
  }
  refused(() => new wasm.Optimizer({ ...OK, potential: 42 }), "potential");
  // The module is intact.
  assert.equal(wasm.global_minimum("rastrigin"), 0);
  assert.deepEqual(reference(), before);
});

test("a diverged chain's published value is never finite, even when the kernel's last U was", () => {
  // Levy with a step far too long: chains diverge within 100 steps, some
  // with a finite last U beside an overflowing gradient (seeded: the same
  // chains every run). The page counts a chain with a finite value as live.
  const opt = new wasm.Optimizer({ ...OK, potential: "levy", h: 1, chains: 64, spread: Math.sqrt(10) });
  let diverged = 0;
  for (let k = 0; k < 100; k++) {
    opt.advance(1);
    const s = summary(opt);
    diverged = s[S.Diverged];
    assert.equal(values(opt).filter(Number.isFinite).length, 64 - diverged, `after ${k + 1} steps`);
  }
  assert.ok(diverged > 0, "no chain diverged: the case tests nothing");
  opt.free();
});

test("an escape radius that is not a positive number is refused naming `escape`", () => {
  for (const bad of [0, -1, -0, NaN, Infinity, -Infinity]) refused(() => new wasm.Optimizer({ ...OK, escape: bad }), "escape");
  for (const bad of ["5", 5n, {}, [5], true]) refused(() => new wasm.Optimizer({ ...OK, escape: bad }), "escape", /must be a number/);
  // Absent, null and a positive number are accepted.
  for (const ok of [undefined, null, 1e-300, 5000, Number.MAX_VALUE]) new wasm.Optimizer({ ...OK, escape: ok }).free();
});

test("every chain beyond the escape radius is a typed failure that stays, never a report", () => {
  const opt = new wasm.Optimizer({ ...OK, h: 5, chains: 10, escape: 5000 });
  refused(() => opt.advance(1000), "h", /^all 10 chains ran away beyond \|x\| = 5000/);
  const at = summary(opt)[S.Iteration];
  assert.ok(at > 0 && at < 1000, `failed at ${at}`);
  refused(() => opt.advance(1), "h", /ran away/);
  refused(() => opt.advance(0), "h", /ran away/);
  assert.equal(summary(opt)[S.Iteration], at);
  opt.free();
});

test("the law of a chain's next step: a chain index that is not one is refused naming `chain`", () => {
  const opt = new wasm.Optimizer(OK);
  for (const bad of [-1, 8, 1.5, NaN, Infinity, "0", 0n, null, undefined, {}, [0], 2 ** 32]) {
    refused(() => opt.nextStep(bad), "chain");
  }
  const law = opt.nextStep(7);
  assert.equal(law.length, 21);
  assert.ok(law.every(Number.isFinite));
  // Asking changes nothing: the next step is the same with or without it.
  const other = new wasm.Optimizer(OK);
  opt.advance(5);
  other.advance(5);
  assert.deepEqual(positions(opt), positions(other));
  opt.free();
  other.free();
});

test("a diverged chain has no next step: refused naming `chain`", () => {
  const opt = new wasm.Optimizer({ ...OK, potential: "levy", h: 1, chains: 64, spread: Math.sqrt(10) });
  let gone = -1;
  for (let k = 0; k < 100 && gone < 0; k++) {
    opt.advance(1);
    gone = values(opt).findIndex((u) => !Number.isFinite(u));
  }
  assert.ok(gone >= 0, "no chain diverged: the case tests nothing");
  refused(() => opt.nextStep(gone), "chain", /has diverged/);
  opt.free();
});

test("gradient descent: a bad box or bad settings are refused by name, its advance counts like the optimiser's", () => {
  for (const box of [undefined, null, [0, 1, 0], [0, 1, 0, "1"], "0,1,0,1", [1, 0, 0, 1], [0, 1, NaN, 1], [0, Infinity, 0, 1]]) {
    refused(() => new wasm.Descent(OK, box), "box");
  }
  refused(() => new wasm.Descent({ ...OK, h: -1 }, [-5, 5, -5, 5]), "h");
  refused(() => new wasm.Descent({ ...OK, chains: 0 }, [-5, 5, -5, 5]), "chains");
  assert.throws(() => new wasm.Descent({ ...OK, extra: 1 }, [-5, 5, -5, 5]), (e) => isTypedError(e) && /`extra` is not a setting/.test(e.message));
  assert.match(refused2(() => new wasm.Descent(OK, [0, 1, 0])), /`box` must be an array of four numbers/);
  const d = new wasm.Descent(OK, [-5, 5, -5, 5]);
  for (const bad of [-1, 1.5, NaN, "5", 5n, 2 ** 32]) refused(() => d.advance(bad), "steps");
  assert.equal(d.advance(50), 50);
  assert.equal(d.termination(), undefined);
  assert.ok(summary(d).every((v, i) => i === S.A || Number.isFinite(v)));
  d.free();
});
