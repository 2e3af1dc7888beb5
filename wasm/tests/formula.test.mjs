// A visitor's formula as a careless or hostile caller would give it: the
// wrapper reads `{ formula, box }` wherever it takes a potential, refuses
// what it cannot read with a typed Error (field `formula` and the column
// where reading stopped, or `box`, or `potential` for a malformed object),
// and never traps, hangs or returns a non-finite number. A seeded campaign
// of formulas built from the language's own pieces, and of random
// characters, checks that for every case. Needs the Node build: see load.mjs.
import assert from "node:assert/strict";
import { test } from "node:test";
import { OK, isTypedError, positions, summary, wasm } from "./load.mjs";

const BOX = [-3, 3, -3, 3];
const S = wasm.Summary;

/** Asserts that `f` throws a typed Error naming `field`; returns the error. */
function refused(f, field) {
  let caught = null;
  assert.throws(f, (e) => {
    assert.ok(isTypedError(e), `not a typed Error: ${e}`);
    assert.equal(e.field, field, e.message);
    caught = e;
    return true;
  });
  return caught;
}

test("a formula is read wherever a potential is, with the same numbers", () => {
  const p = { formula: "2 + x^2 + y^2 - cos(2 pi x) - cos(2 pi y)", box: [-5, 5, -5, 5] };
  const typed = wasm.potential_grid(p, -5, 5, -5, 5, 41, 41);
  const built = wasm.potential_grid("rastrigin", -5, 5, -5, 5, 41, 41);
  for (let i = 0; i < built.length; i++) assert.ok(Math.abs(typed[i] - built[i]) <= 1e-12 * (1 + built[i]), `cell ${i}`);
  assert.ok(Math.abs(wasm.global_minimum(p)) < 1e-12);
  assert.ok([...wasm.global_minimiser(p)].every((v) => Math.abs(v) < 1e-6));
  const opt = new wasm.Optimizer({ ...OK, potential: p });
  assert.equal(opt.potential(), "formula");
  opt.advance(100);
  assert.ok(summary(opt).every(Number.isFinite));
  opt.free();
});

test("a malformed potential object is refused naming `potential`, a bad box naming `box`", () => {
  for (const bad of [{}, { formula: 1, box: BOX }, { formula: "x", box: [0, 1, 0] }, { formula: "x", box: "0,1,0,1" }, { formula: "x", box: [0, 1, 0, "1"] }, { formula: "x", box: BOX, extra: 1 }, ["x"], 7, null]) {
    refused(() => wasm.global_minimum(bad), "potential");
    refused(() => new wasm.Optimizer({ ...OK, potential: bad ?? 7 }), "potential");
  }
  for (const box of [[1, 0, 0, 1], [0, 1, NaN, 1], [0, Infinity, 0, 1], [-1e308, 1e308, 0, 1]]) {
    refused(() => wasm.global_minimum({ formula: "x", box }), "box");
  }
  // Finite formula, non-finite somewhere on its box.
  const e = refused(() => wasm.potential_grid({ formula: "1 / x", box: [-1, 1, -1, 1] }, -1, 1, -1, 1, 8, 8), "box");
  assert.match(e.message, /U = inf at \(0, -1\), and U must be finite over the whole box: move the box so that it leaves out the part with x = 0 and y from -1 to 1/);
  // A getter that throws while the formula is read.
  const throwing = Object.defineProperty({ box: BOX }, "formula", { enumerable: true, get: () => { throw new RangeError("no formula"); } });
  assert.match(refused(() => wasm.global_minimum(throwing), "formula").message, /threw: no formula/);
});

test("an unreadable formula is refused naming `formula`, with the column", () => {
  for (const [text, column] of [["", 1], ["x +", 4], ["x ++* y", 5], ["(((x)", 6], ["sin", 4], ["x y z", 5], ["x".repeat(401), 401], ["(".repeat(33) + "x", 33]]) {
    const e = refused(() => wasm.global_minimum({ formula: text, box: BOX }), "formula");
    assert.equal(e.column, column, `${JSON.stringify(text.slice(0, 40))}: ${e.message}`);
    assert.ok(e.message.includes("`formula`, column"), e.message);
  }
});

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
  return { next, pick: (xs) => xs[Math.floor(next() * xs.length)], int: (lo, hi) => lo + Math.floor(next() * (hi - lo + 1)) };
}

/** A formula of the language, up to `depth` deep. */
function formula(r, depth) {
  if (depth === 0 || r.next() < 0.3) return r.pick(["x", "y", "pi", "e", "2", "0.5", "1e-3", "3x", "1e300", "0"]);
  switch (r.int(0, 5)) {
    case 0:
      return `${formula(r, depth - 1)} ${r.pick(["+", "-", "*", "/", "^", "**", "−", "×"])} ${formula(r, depth - 1)}`;
    case 1:
      return `${r.pick(["sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "exp", "log", "ln", "sqrt", "abs"])}(${formula(r, depth - 1)})`;
    case 2:
      return `${r.pick(["min", "max"])}(${formula(r, depth - 1)}, ${formula(r, depth - 1)})`;
    case 3:
      return `-(${formula(r, depth - 1)})`;
    case 4:
      return `${formula(r, depth - 1)}${formula(r, depth - 1)}`;
    default:
      return `(${formula(r, depth - 1)})`;
  }
}

/** A formula spoilt: a character dropped, doubled or replaced. */
function spoil(r, text) {
  const chars = [...text];
  const at = r.int(0, chars.length);
  const junk = r.pick(["(", ")", ",", "+", "^", "$", "é", "\u0000", "𝑥", " ", "1e", "sin", ".", "..", "e+"]);
  switch (r.int(0, 2)) {
    case 0:
      chars.splice(at, 1);
      break;
    case 1:
      chars.splice(at, 0, junk);
      break;
    default:
      chars[at] = junk;
  }
  return chars.join("");
}

test("a seeded campaign of formulas: each is read with finite numbers or refused with its column, nothing traps", () => {
  const r = generator(2026);
  const count = { cases: 0, read: 0, refusedFormula: 0, refusedBox: 0, ran: 0, runFailed: 0 };
  const reference = () => {
    const opt = new wasm.Optimizer({ ...OK, potential: { formula: "x^2 + y^2", box: BOX } });
    opt.advance(20);
    const state = [summary(opt), positions(opt)];
    opt.free();
    return state;
  };
  const before = reference();
  for (let i = 0; i < 1500; i++) {
    count.cases++;
    let text = formula(r, r.int(0, 5));
    if (r.next() < 0.4) text = spoil(r, text);
    const potential = { formula: text, box: BOX };
    let grid;
    try {
      grid = wasm.potential_grid(potential, -3, 3, -3, 3, 9, 9);
    } catch (e) {
      assert.ok(isTypedError(e), `${text}: not a typed Error: ${e}`);
      assert.ok(["formula", "box"].includes(e.field), `${text}: ${e.field} ${e.message}`);
      if (e.field === "formula") {
        count.refusedFormula++;
        assert.ok(Number.isInteger(e.column) && e.column >= 1 && e.column <= [...text].length + 1, `${text}: column ${e.column}`);
      } else count.refusedBox++;
      continue;
    }
    count.read++;
    assert.ok([...grid].every(Number.isFinite), text);
    assert.ok(Number.isFinite(wasm.global_minimum(potential)), text);
    if (i % 5 === 0) {
      // Building may be refused too: a start below the floor is the
      // kernel's UnboundedBelow, a start with no feasible redraw its
      // NonFiniteStart.
      let opt;
      try {
        opt = new wasm.Optimizer({ ...OK, potential, escape: 3000 });
        opt.advance(50);
        count.ran++;
        const s = summary(opt);
        assert.ok(Number.isFinite(s[S.BestValue]), text);
      } catch (e) {
        assert.ok(isTypedError(e), `${text}: ${e}`);
        count.runFailed++;
      }
      opt?.free();
    }
  }
  console.log(`# ${JSON.stringify(count)}`);
  assert.equal(count.cases, 1500);
  assert.ok(count.read > 300 && count.refusedFormula > 200 && count.refusedBox > 50, JSON.stringify(count));
  // The module still computes the same numbers.
  assert.deepEqual(reference(), before);
});
