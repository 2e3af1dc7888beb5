// The wrapper's Node build (wasm-bindgen --target nodejs), for the tests in
// this folder: $HRLA_WASM_PKG when set (to try another build, such as an
// older one), else $HRLA_WEB_OUT/pkg-node, else target/web-tests/pkg-node,
// where scripts/test-web.sh puts it.
import { createRequire } from "node:module";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";

const ROOT = resolve(dirname(fileURLToPath(import.meta.url)), "..", "..");
const OUT = process.env.HRLA_WEB_OUT ?? join(ROOT, "target", "web-tests");
const PKG = process.env.HRLA_WASM_PKG ?? join(OUT, "pkg-node");

export const wasm = createRequire(import.meta.url)(join(PKG, "hrla_wasm.js"));

/** Settings the wrapper accepts, to be spoilt one field at a time. */
export const OK = Object.freeze({
  potential: "rastrigin",
  sampler: "hrla",
  a: 4,
  annealing: null,
  h: 0.01,
  chains: 8,
  centre: [3, 3],
  spread: 1,
  seed: 1,
  stopSteps: null,
  stopTarget: null,
});

/** The summary of a run, as a plain array (a fresh view each time). */
export function summary(opt) {
  return [...new Float64Array(wasm.wasm_memory().buffer, opt.summary_ptr(), wasm.Summary.Len)];
}

/** The per-chain values of a run. */
export function values(opt) {
  return [...new Float64Array(wasm.wasm_memory().buffer, opt.values_ptr(), opt.chains())];
}

/** The positions of a run, two per chain. */
export function positions(opt) {
  return [...new Float64Array(wasm.wasm_memory().buffer, opt.positions_ptr(), 2 * opt.chains())];
}

/**
 * Whether `e` is what the wrapper throws for bad input: a real `Error`
 * that is not a wasm trap (`WebAssembly.RuntimeError` is an `Error` too:
 * "unreachable", "memory access out of bounds").
 */
export function isTypedError(e) {
  return e instanceof Error && !(e instanceof WebAssembly.RuntimeError) && typeof e.message === "string" && e.message.length > 0;
}
