// The committed web/pkg/ is what the sources build: byte for byte the
// fresh build that scripts/test-web.sh makes in $HRLA_WEB_OUT/pkg-web, with
// a stamp that matches the sources, so that scripts/serve.sh may serve it
// without Rust. And serve.sh itself: with Node alone it serves an unchanged
// checkout, and refuses a changed one, naming the command that rebuilds.
import assert from "node:assert/strict";
import { execFileSync, spawn } from "node:child_process";
import { cpSync, existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync, symlinkSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
import { test } from "node:test";
import { CRATES, REFRESH, packageFiles, readStamp, sourceFiles, staleReason } from "../../scripts/pkg-stamp.mjs";
import { OUT, ROOT } from "./browser.mjs";

const PKG = join(ROOT, "web", "pkg");
const FRESH = join(OUT, "pkg-web");
const REFRESH_HINT = `run ${REFRESH} and commit web/pkg/`;

test("the committed web/pkg/ is byte for byte a fresh build of the sources", () => {
  assert.ok(existsSync(FRESH), `no fresh build in ${FRESH}: scripts/test-web.sh makes it`);
  const fresh = packageFiles(FRESH);
  assert.deepEqual(packageFiles(PKG), fresh, `web/pkg/ holds other files than a fresh build: ${REFRESH_HINT}`);
  const rustc = execFileSync("rustc", ["--version"], { encoding: "utf8" }).trim();
  const built = readStamp(PKG).rustc;
  const compiler = built === rustc ? "" : ` (web/pkg/ was built with ${built}, this build with ${rustc}: the bytes depend on the compiler)`;
  for (const name of fresh) {
    const a = readFileSync(join(PKG, name));
    const b = readFileSync(join(FRESH, name));
    assert.ok(a.equals(b), `web/pkg/${name} (${a.length} bytes) is not the fresh build's (${b.length} bytes)${compiler}: ${REFRESH_HINT}`);
  }
});

test("web/pkg/'s stamp matches the sources and the package's files", () => {
  const why = staleReason(PKG, ROOT);
  assert.equal(why, null, `${why}: ${REFRESH_HINT}`);
});

test("the stamp hashes the sources of every crate that the wasm is built from", () => {
  // Path dependencies show their directory in cargo tree's output.
  const tree = execFileSync(
    "cargo",
    ["tree", "--offline", "-p", "hrla-wasm", "--target", "wasm32-unknown-unknown", "-e", "normal,build", "--prefix", "none"],
    { cwd: ROOT, encoding: "utf8" },
  );
  const local = new Set();
  for (const m of tree.matchAll(/\((\/[^)]*)\)/g)) local.add(resolve(m[1]).slice(ROOT.length + 1));
  assert.deepEqual([...local].sort(), [...CRATES].sort(), `update CRATES in scripts/pkg-stamp.mjs, then ${REFRESH_HINT}`);
});

/**
 * A copy of what serve.sh reads (the scripts, web/ without its tests, the
 * sources the stamp hashes) in a temporary directory, and a PATH of Node,
 * bash and dirname only: no cargo, rustup or wasm-bindgen.
 */
function checkout() {
  const dir = mkdtempSync(join(tmpdir(), "hrla-pkg-"));
  for (const name of ["serve.sh", "build-pkg.sh", "wasm-tools.sh", "pkg-stamp.mjs", "static-server.mjs"]) {
    cpSync(join(ROOT, "scripts", name), join(dir, "scripts", name));
  }
  for (const name of ["index.html", "style.css", "icon.svg", "js", "pkg"]) {
    cpSync(join(ROOT, "web", name), join(dir, "web", name), { recursive: true });
  }
  for (const name of sourceFiles(ROOT)) cpSync(join(ROOT, name), join(dir, name));
  const bin = join(dir, "bin");
  mkdirSync(bin);
  symlinkSync(process.execPath, join(bin, "node"));
  const which = (cmd) => execFileSync("bash", ["-c", `command -v ${cmd}`], { encoding: "utf8" }).trim();
  symlinkSync(which("dirname"), join(bin, "dirname"));
  return { dir, bin };
}

/**
 * Runs serve.sh in `dir` with PATH=`bin`; resolves when it prints the
 * address (then fetches `path` from it and stops the server) or exits.
 */
function serve({ dir, bin }, path = "/") {
  return new Promise((done, fail) => {
    const child = spawn("/bin/bash", [join(dir, "scripts", "serve.sh")], {
      cwd: dir,
      env: { PATH: bin, PORT: "0", HOME: dir },
      stdio: ["ignore", "pipe", "pipe"],
    });
    let stdout = "";
    let stderr = "";
    let answered = false;
    child.stderr.on("data", (d) => (stderr += d));
    child.stdout.on("data", async (d) => {
      stdout += d;
      const url = stdout.match(/at (http:\/\/127\.0\.0\.1:\d+\/)/)?.[1];
      if (!url || answered) return;
      answered = true;
      try {
        const res = await fetch(new URL(path, url));
        const body = await res.text();
        child.kill();
        done({ served: true, status: res.status, body, stdout, stderr });
      } catch (e) {
        child.kill();
        fail(e);
      }
    });
    child.on("exit", (code) => {
      if (!answered) done({ served: false, code, stdout, stderr });
    });
    child.on("error", fail);
  });
}

test("serve.sh serves an unchanged checkout with Node alone", async () => {
  const c = checkout();
  try {
    const r = await serve(c, "/pkg/hrla_wasm.js");
    assert.ok(r.served, `serve.sh did not serve: ${r.stdout}${r.stderr}`);
    assert.equal(r.status, 200);
    assert.equal(r.body, readFileSync(join(PKG, "hrla_wasm.js"), "utf8"));
    assert.match(r.stdout, /web\/pkg\/ matches the sources/);
  } finally {
    rmSync(c.dir, { recursive: true, force: true });
  }
});

test("an edit to a test, a bench or the docs leaves web/pkg/ servable", async () => {
  const c = checkout();
  try {
    for (const name of ["wasm/tests/extra.test.mjs", "gpu/benches/extra.rs", "docs/EXTRA.md", "dyn/tests/extra.rs"]) {
      mkdirSync(dirname(join(c.dir, name)), { recursive: true });
      writeFileSync(join(c.dir, name), "// not part of the wasm\n");
    }
    assert.equal(staleReason(join(c.dir, "web", "pkg"), c.dir), null);
    const r = await serve(c);
    assert.ok(r.served, `serve.sh did not serve: ${r.stdout}${r.stderr}`);
  } finally {
    rmSync(c.dir, { recursive: true, force: true });
  }
});

test("an edited source makes web/pkg/ stale, and without Rust serve.sh says what to run", async () => {
  for (const [name, edit] of [
    ["wasm/src/lib.rs", (s) => s + "\n// edited\n"],
    ["core/src/lib.rs", (s) => s.replace("\n", "\n\n")],
    ["Cargo.lock", (s) => s + "\n"],
    ["scripts/wasm-tools.sh", (s) => s + "\n"],
  ]) {
    const c = checkout();
    try {
      const file = join(c.dir, name);
      writeFileSync(file, edit(readFileSync(file, "utf8")));
      assert.match(staleReason(join(c.dir, "web", "pkg"), c.dir) ?? "", /sources have changed/, name);
      const r = await serve(c);
      assert.equal(r.served, false, `serve.sh served a stale web/pkg/ after an edit of ${name}`);
      assert.equal(r.code, 1);
      assert.match(r.stdout, /web\/pkg\/ needs a rebuild: the sources have changed/);
      assert.match(r.stderr, /needs Rust.*scripts\/build-pkg\.sh/s);
    } finally {
      rmSync(c.dir, { recursive: true, force: true });
    }
  }
});

test("a package file that is not the one its stamp records is not served", async () => {
  const c = checkout();
  try {
    const wasm = join(c.dir, "web", "pkg", "hrla_wasm_bg.wasm");
    const bytes = readFileSync(wasm);
    bytes[bytes.length - 1] ^= 1;
    writeFileSync(wasm, bytes);
    assert.match(staleReason(join(c.dir, "web", "pkg"), c.dir) ?? "", /hrla_wasm_bg\.wasm is not the file its stamp records/);
    const r = await serve(c);
    assert.equal(r.served, false);
    assert.match(r.stderr, /scripts\/build-pkg\.sh/);
  } finally {
    rmSync(c.dir, { recursive: true, force: true });
  }
});
