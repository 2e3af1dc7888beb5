// Same numbers everywhere: the wasm build, run in Node, against the native
// build of the same wrapper (wasm/examples/trace.rs), on the cases of
// wasm/tests/trace-cases.txt. Bit patterns are compared, not values.
//
// Needs $HRLA_WEB_OUT/pkg-node (wasm-bindgen --target nodejs) and
// $HRLA_WEB_OUT/native-trace.txt: scripts/test-web.sh makes both.
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join } from "node:path";
import { test } from "node:test";
import { OUT, ROOT } from "./browser.mjs";

const require = createRequire(import.meta.url);
const wasm = require(join(OUT, "pkg-node", "hrla_wasm.js"));

const bits = new Float64Array(1);
const words = new BigUint64Array(bits.buffer);
/** The f64's bit pattern as 16 hex digits, as Rust's `{:016x}` of `to_bits()`. */
function hex(v) {
  bits[0] = v;
  return words[0].toString(16).padStart(16, "0");
}

/** One line of trace-cases.txt as the wrapper's settings object. */
function parseCase(line) {
  const [name, potential, sampler, a, h, chains, cx, cy, spread, seed, stop, steps] = line.split(/\s+/);
  const t = a.split(":").map(Number);
  // `-`, a step budget `N`, a target `@T`, or both `N@T`.
  const [k, target] = stop === "-" ? ["", undefined] : stop.split("@");
  return {
    name,
    steps: Number(steps),
    settings: {
      potential,
      sampler,
      a: t[0],
      annealing: t.length === 3 ? { aLow: t[0], aHigh: t[1], steps: t[2] } : null,
      h: Number(h),
      chains: Number(chains),
      centre: [Number(cx), Number(cy)],
      spread: Number(spread),
      seed: BigInt(seed),
      stopSteps: k === "" ? null : Number(k),
      stopTarget: target === undefined ? null : Number(target),
    },
  };
}

/** The trace format of wasm/examples/trace.rs. */
function trace(name, opt) {
  const mem = wasm.wasm_memory().buffer;
  const n = opt.chains();
  const s = new Float64Array(mem, opt.summary_ptr(), wasm.Summary.Len);
  const x = new Float64Array(mem, opt.positions_ptr(), 2 * n);
  const y = new Float64Array(mem, opt.velocities_ptr(), 2 * n);
  const u = new Float64Array(mem, opt.values_ptr(), n);
  const S = wasm.Summary;
  const lines = [
    `${name} iteration ${s[S.Iteration]} stopped ${s[S.Termination]}`,
    `${name} best ${hex(s[S.BestValue])} ${hex(s[S.BestX0])} ${hex(s[S.BestX1])} at ${s[S.BestIteration]}`,
  ];
  for (let c = 0; c < n; c++) {
    lines.push(
      `${name} chain ${c} x ${hex(x[2 * c])} ${hex(x[2 * c + 1])} y ${hex(y[2 * c])} ${hex(y[2 * c + 1])} u ${hex(u[c])}`,
    );
  }
  return lines;
}

test("wasm in Node and native give bit-identical runs", () => {
  const cases = readFileSync(join(ROOT, "wasm", "tests", "trace-cases.txt"), "utf8")
    .split("\n")
    .map((l) => l.trim())
    .filter((l) => l && !l.startsWith("#"))
    .map(parseCase);
  assert.ok(cases.length >= 10);
  // Every landscape and both stopping rules are covered.
  assert.deepEqual([...new Set(cases.map((c) => c.settings.potential))].sort(), [...wasm.potential_names()].sort());
  assert.ok(cases.some((c) => c.settings.stopSteps !== null) && cases.some((c) => c.settings.stopTarget !== null));
  const native = readFileSync(join(OUT, "native-trace.txt"), "utf8").trimEnd().split("\n");
  const ours = [];
  for (const { name, steps, settings } of cases) {
    const opt = new wasm.Optimizer(settings);
    opt.advance(steps);
    ours.push(...trace(name, opt));
    opt.free();
  }
  assert.equal(ours.length, native.length);
  assert.deepEqual(ours, native);
});

test("a seed given as a number or as a BigInt is the same seed", () => {
  const base = { sampler: "hrla", a: 4, h: 0.01, chains: 5, centre: [3, 3], spread: 3 };
  const a = new wasm.Optimizer({ ...base, seed: 77 });
  const b = new wasm.Optimizer({ ...base, seed: 77n });
  a.advance(200);
  b.advance(200);
  const mem = () => wasm.wasm_memory().buffer;
  assert.deepEqual(
    [...new Float64Array(mem(), a.positions_ptr(), 10)],
    [...new Float64Array(mem(), b.positions_ptr(), 10)],
  );
  assert.equal(b.seed(), 77n);
  a.free();
  b.free();
});

test("bad settings throw an Error with the kernel's message, and the module still works", () => {
  const ok = { sampler: "hrla", a: 4, h: 0.01, chains: 8, centre: [0, 0], spread: 1, seed: 1 };
  const refuse = (patch, message) =>
    assert.throws(() => new wasm.Optimizer({ ...ok, ...patch }), (e) => {
      assert.ok(e instanceof Error);
      if (message instanceof RegExp) assert.match(e.message, message);
      else assert.equal(e.message, message);
      return true;
    });
  refuse({ h: -1 }, "`h` must be finite and > 0, got -1");
  refuse({ potential: "sphere" }, /`potential` must be one of rastrigin, ackley/);
  refuse({ stopSteps: 0 }, "`step budget` must be at least 1, got 0");
  refuse({ stopSteps: 2.5 }, "`stopSteps` must be a whole number >= 0");
  refuse({ stopTarget: NaN }, "`target` must be finite, got NaN");
  // The setting at fault, for the page to mark its field.
  for (const [patch, field] of [
    [{ h: -1 }, "h"],
    [{ chains: 0 }, "chains"],
    [{ spread: -1 }, "std_dev"],
    [{ annealing: { aLow: -1, aHigh: 4, steps: 10 } }, "a_low"],
    [{ potential: "sphere" }, "potential"],
  ]) {
    assert.throws(() => new wasm.Optimizer({ ...ok, ...patch }), (e) => e.field === field);
  }
  refuse({ h: NaN }, "`h` must be finite and > 0, got NaN");
  refuse({ sampler: "ola", h: 0 }, "`h` must be finite and > 0, got 0");
  refuse({ chains: 5000 }, `\`chains\` must be between 1 and ${wasm.max_chains()}, got 5000`);
  refuse({ chains: 0 }, `\`chains\` must be between 1 and ${wasm.max_chains()}, got 0`);
  refuse({ chains: 2.5 }, "`chains` must be a whole number >= 0");
  refuse({ a: -4 }, "`a` must be finite and > 0, got -4");
  refuse({ annealing: { aLow: 0.1, aHigh: 4, steps: 0 } }, "`steps` must be at least 1, got 0");
  refuse({ spread: -1 }, "`std_dev` must be finite and >= 0, got -1");
  refuse({ centre: [0, Infinity] }, "`mean` must be finite, got inf");
  refuse({ sampler: "sgd" }, '`sampler` must be "hrla", "ula" or "ola"');
  refuse({ seed: 2n ** 64n }, "`seed` must be a whole number between 0 and 2^53 - 1, or a BigInt between 0 and 2^64 - 1");
  refuse({ seed: 2 ** 53 }, "`seed` must be a whole number between 0 and 2^53 - 1, or a BigInt between 0 and 2^64 - 1");
  const opt = new wasm.Optimizer(ok);
  opt.advance(10);
  opt.free();
});

test("a run whose chains all diverge throws the kernel's message, and keeps refusing", () => {
  // h = 5 is far too long a step for Rastrigin at a = 4: every chain overflows
  // within about 150 steps.
  const opt = new wasm.Optimizer({ sampler: "hrla", a: 4, h: 5, chains: 10, centre: [3, 3], spread: 3, seed: 1 });
  const message = "all 10 chains diverged (non-finite position, potential or gradient): try a smaller step h";
  const s = () => new Float64Array(wasm.wasm_memory().buffer, opt.summary_ptr(), wasm.Summary.Len);
  assert.throws(() => opt.advance(1000), (e) => e instanceof Error && e.message === message);
  const stopped = s()[wasm.Summary.Iteration];
  assert.ok(stopped > 0 && stopped < 1000, `stopped at iteration ${stopped}`);
  assert.equal(s()[wasm.Summary.Diverged], 10);
  assert.ok(Number.isFinite(s()[wasm.Summary.BestValue]));
  assert.throws(() => opt.advance(1), (e) => e instanceof Error && e.message === message);
  assert.equal(s()[wasm.Summary.Iteration], stopped);
  opt.free();
});

test("random seeds are BigInts and differ", () => {
  const a = wasm.random_seed();
  const b = wasm.random_seed();
  assert.equal(typeof a, "bigint");
  assert.notEqual(a, b);
});
