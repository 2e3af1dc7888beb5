// The stamp that ties the committed web/pkg/ to the sources it was built
// from, so that scripts/serve.sh can serve it without Rust when they have
// not changed. Node's standard library only: on a fresh machine Node is all
// the fast path has.
//
//   node scripts/pkg-stamp.mjs check [DIR]   exit 0 when DIR (web/pkg) matches
//                                            the sources, else 1 and the reason
//   node scripts/pkg-stamp.mjs sources       the sources' hash
//   node scripts/pkg-stamp.mjs write DIR HASH  DIR/stamp.json for a package just
//                                            built from sources with that hash
import { execFileSync } from "node:child_process";
import { createHash } from "node:crypto";
import { existsSync, readdirSync, readFileSync, statSync, writeFileSync } from "node:fs";
import { dirname, join, relative, resolve, sep } from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";

export const ROOT = resolve(dirname(fileURLToPath(import.meta.url)), "..");
export const STAMP = "stamp.json";
/** The one command that rebuilds web/pkg/ and its stamp. */
export const REFRESH = "scripts/build-pkg.sh";

/**
 * The crates whose sources go into hrla_wasm_bg.wasm: hrla-wasm and its path
 * dependencies (web/tests/pkg.test.mjs checks this list against cargo's).
 */
export const CRATES = ["core", "dyn", "gpu", "wasm"];
// The build's inputs outside the crates: the lock file pins every
// dependency and wasm-bindgen's version, the config and toolchain files set
// flags and compiler, wasm-tools.sh holds the build's own flags.
const WORKSPACE_FILES = [
  "Cargo.toml",
  "Cargo.lock",
  ".cargo/config.toml",
  "rust-toolchain",
  "rust-toolchain.toml",
  "scripts/wasm-tools.sh",
];

function walk(dir, out) {
  for (const entry of readdirSync(dir, { withFileTypes: true })) {
    const path = join(dir, entry.name);
    if (entry.isDirectory()) walk(path, out);
    else if (entry.isFile()) out.push(path);
  }
}

/**
 * The files that determine the package, relative to `root`, sorted: each
 * crate's Cargo.toml, build.rs and src/, and the workspace's files above.
 * Tests, benches, examples and docs are left out, so editing them does not
 * make the package stale.
 */
export function sourceFiles(root = ROOT) {
  const files = [];
  for (const crate of CRATES) {
    for (const name of ["Cargo.toml", "build.rs"]) {
      if (existsSync(join(root, crate, name))) files.push(join(root, crate, name));
    }
    walk(join(root, crate, "src"), files);
  }
  for (const name of WORKSPACE_FILES) {
    if (existsSync(join(root, name))) files.push(join(root, name));
  }
  // Paths with "/" on every system, so that the hash does not depend on it.
  return files.map((f) => relative(root, f).split(sep).join("/")).sort();
}

/** SHA-256 over every source file's path and bytes. */
export function sourcesHash(root = ROOT) {
  const hash = createHash("sha256");
  for (const name of sourceFiles(root)) {
    // A checkout with CRLF line ends (git's autocrlf) builds the same bytes:
    // rustc and cargo read CRLF as LF.
    const bytes = Buffer.from(readFileSync(join(root, name), "latin1").replaceAll("\r\n", "\n"), "latin1");
    hash.update(`${name}\0${bytes.length}\0`);
    hash.update(bytes);
  }
  return hash.digest("hex");
}

const sha256 = (path) => createHash("sha256").update(readFileSync(path)).digest("hex");

/** The package's files (all but the stamp), sorted. */
export function packageFiles(dir) {
  return readdirSync(dir)
    .filter((name) => name !== STAMP && statSync(join(dir, name)).isFile())
    .sort();
}

export function readStamp(dir) {
  return JSON.parse(readFileSync(join(dir, STAMP), "utf8"));
}

/** Why `dir` may not be served as the build of the sources in `root`, or null when it may. */
export function staleReason(dir = join(ROOT, "web", "pkg"), root = ROOT) {
  const shown = relative(root, dir) || dir;
  let stamp;
  try {
    stamp = readStamp(dir);
  } catch (e) {
    if (e.code === "ENOENT" && !existsSync(dir)) return `${shown}/ is missing (in a git checkout, git checkout -- ${shown} restores it)`;
    return `${shown}/${STAMP} cannot be read (${e.code ?? e.message})`;
  }
  const now = sourcesHash(root);
  if (stamp.sources !== now) {
    return `the sources have changed since ${shown}/ was built (sources ${now.slice(0, 12)}, built from ${String(stamp.sources).slice(0, 12)})`;
  }
  const names = packageFiles(dir);
  const listed = Object.keys(stamp.files ?? {}).sort();
  if (names.join("\n") !== listed.join("\n")) {
    return `${shown}/ holds ${names.join(", ")}, its stamp lists ${listed.join(", ")}`;
  }
  for (const name of names) {
    if (sha256(join(dir, name)) !== stamp.files[name]) return `${shown}/${name} is not the file its stamp records`;
  }
  return null;
}

/** Writes DIR/stamp.json for a package built from sources whose hash is `sources`. */
export function writeStamp(dir, sources) {
  const version = (cmd) => execFileSync(cmd, ["--version"], { encoding: "utf8" }).trim();
  const stamp = {
    about: `web/pkg/ as ${REFRESH} builds it from these sources (scripts/pkg-stamp.mjs lists them)`,
    sources,
    rustc: version("rustc"),
    "wasm-bindgen": version("wasm-bindgen"),
    files: Object.fromEntries(packageFiles(dir).map((name) => [name, sha256(join(dir, name))])),
  };
  writeFileSync(join(dir, STAMP), JSON.stringify(stamp, null, 2) + "\n");
}

if (import.meta.url === pathToFileURL(process.argv[1]).href) {
  const [command, dir, sources] = process.argv.slice(2);
  if (command === "check") {
    const why = staleReason(dir ? resolve(dir) : undefined);
    if (why) {
      console.error(why);
      process.exit(1);
    }
  } else if (command === "sources") {
    console.log(sourcesHash());
  } else if (command === "write" && dir && sources) {
    writeStamp(resolve(dir), sources);
  } else {
    console.error("usage: node scripts/pkg-stamp.mjs check [DIR] | sources | write DIR HASH");
    process.exit(2);
  }
}
