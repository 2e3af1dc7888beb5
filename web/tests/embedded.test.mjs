// The firmware example's computation (examples/firmware/shared, crate hrla-embedded)
// compiled to wasm (examples/firmware/wasm) and run in Node prints the same
// report, byte for byte, as the host (hrla-embedded-host) and as the
// firmware under QEMU on each of its three cores (Cortex-M3, Cortex-M4F,
// RISC-V): in f32 and f64, with either per-chain generator, and with
// micromath (on the cores where test-firmware.sh runs it).
//
// Needs, from scripts/test-web.sh: $HRLA_WEB_OUT/embedded-node and
// embedded-node-micromath (wasm-bindgen --target nodejs) and
// $HRLA_WEB_OUT/embedded/<variant>.host.txt. The firmware's output,
// <core>.<variant>.qemu-results.txt, is read from $HRLA_FIRMWARE_OUT, which
// scripts/test.sh sets after a fresh firmware run; run alone, test-web.sh
// does not set it and those comparisons are skipped (with a warning from
// test-web.sh and this reason in node's report) rather than made against a
// possibly stale run.
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join } from "node:path";
import { test } from "node:test";
import { OUT } from "./browser.mjs";

const require = createRequire(import.meta.url);
const plain = require(join(OUT, "embedded-node", "hrla_embedded_wasm.js"));
const micromath = require(join(OUT, "embedded-node-micromath", "hrla_embedded_wasm.js"));
const FIRMWARE = process.env.HRLA_FIRMWARE_OUT;
/** Why the QEMU comparisons are skipped; scripts/test-web.sh prints the same. */
const NO_FIRMWARE =
  "HRLA_FIRMWARE_OUT is not set, so the wasm report is not compared with the firmware's under QEMU; " +
  "to compare, run scripts/test.sh, or scripts/test-firmware.sh then " +
  `HRLA_FIRMWARE_OUT=${process.env.CARGO_TARGET_DIR ?? "target"}/firmware-check scripts/test-web.sh`;

const ALL_CORES = ["cortex-m3", "cortex-m4f", "riscv32"];
// Variant names as test-firmware.sh names its files, and the cores it runs
// each on.
const VARIANTS = [
  { name: "f32", float: "f32", rng: "xoshiro128", wasm: plain, cores: ALL_CORES },
  { name: "f64", float: "f64", rng: "xoshiro128", wasm: plain, cores: ALL_CORES },
  { name: "f32+xoshiro256", float: "f32", rng: "xoshiro256", wasm: plain, cores: ALL_CORES },
  { name: "f64+xoshiro256", float: "f64", rng: "xoshiro256", wasm: plain, cores: ALL_CORES },
  {
    name: "f32+micromath",
    float: "f32",
    rng: "xoshiro128",
    wasm: micromath,
    cores: ["cortex-m3", "cortex-m4f"],
  },
  { name: "f64+micromath", float: "f64", rng: "xoshiro128", wasm: micromath, cores: ["cortex-m3"] },
];

/** Four lines of "<float> <label> <hex>...", as hrla_embedded::report writes them. */
function assertWellFormed(text, float) {
  const lines = text.split("\n");
  assert.equal(lines.pop(), "", "the report ends with a newline");
  assert.deepEqual(
    lines.map((l) => l.split(" ").slice(0, 2).join(" ")),
    ["best.value", "best.x", "best.iteration", "chains.fnv1a"].map((l) => `${float} ${l}`),
  );
  for (const l of lines) assert.match(l, /^f(32|64) [a-z.0-9]+( [0-9a-f]{8}| [0-9a-f]{16})+$/);
}

const reports = new Map(VARIANTS.map((v) => [v.name, v.wasm.report(v.float, v.rng)]));

for (const { name, float, cores } of VARIANTS) {
  test(`embedded ${name}: wasm in Node == host, bit for bit`, () => {
    const host = readFileSync(join(OUT, "embedded", `${name}.host.txt`), "utf8");
    assertWellFormed(host, float);
    assert.equal(reports.get(name), host);
  });

  for (const core of cores) {
    test(
      `embedded ${name}: wasm in Node == firmware under QEMU on ${core}, bit for bit`,
      { skip: FIRMWARE ? false : NO_FIRMWARE },
      () => {
        const qemu = readFileSync(join(FIRMWARE, `${core}.${name}.qemu-results.txt`), "utf8");
        assertWellFormed(qemu, float);
        assert.equal(reports.get(name), qemu);
      },
    );
  }
}

test("embedded: the wasm builds and generators are the ones intended", () => {
  // Else the micromath comparisons would silently repeat the plain ones.
  assert.equal(plain.micromath(), false);
  assert.equal(micromath.micromath(), true);
  assert.notEqual(reports.get("f32+micromath"), reports.get("f32"));
  assert.equal(reports.get("f64+micromath"), reports.get("f64"));
  // The generator is not ignored.
  assert.notEqual(reports.get("f32+xoshiro256"), reports.get("f32"));
  assert.notEqual(reports.get("f64+xoshiro256"), reports.get("f64"));
  assert.throws(() => plain.report("f16", "xoshiro128"), /unknown float type "f16"/);
  assert.throws(() => plain.report("f32", "pcg32"), /unknown generator "pcg32"/);
});
