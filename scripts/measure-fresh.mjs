// How long a fresh checkout takes to show a moving page: clones this
// repository's HEAD into a temporary directory, runs ./scripts/serve.sh there
// with a PATH of Node, bash and dirname only (no cargo, rustup or
// wasm-bindgen: the committed web/pkg/ must be served as it is), and times,
// from the start of serve.sh, until it prints the address and until headless
// Chromium sees the page's iteration counter move. The browser is started
// first, as a visitor's would be. A measurement for the README, not a test.
//
//   node scripts/measure-fresh.mjs [RUNS]   (default 3; needs web/tests'
//                                            npm ci and /usr/bin/chromium)
import { execFileSync, spawn } from "node:child_process";
import { mkdirSync, mkdtempSync, rmSync, symlinkSync } from "node:fs";
import { cpus, loadavg, tmpdir } from "node:os";
import { join } from "node:path";
import { launch, ROOT } from "../web/tests/browser.mjs";

const runs = Number(process.argv[2] ?? 3);
const head = execFileSync("git", ["-C", ROOT, "rev-parse", "--short", "HEAD"], { encoding: "utf8" }).trim();
console.log(`commit ${head}, ${cpus().length} cores, load average ${loadavg().map((x) => x.toFixed(2)).join(" ")}`);
console.log("run | git clone s | serve.sh to address s | serve.sh to a moving counter s");

for (let run = 1; run <= runs; run++) {
  const dir = mkdtempSync(join(tmpdir(), "hrla-fresh-"));
  const repo = join(dir, "hrla");
  const t = performance.now();
  execFileSync("git", ["clone", "--quiet", "--no-hardlinks", ROOT, repo]);
  const cloneS = (performance.now() - t) / 1000;
  const bin = join(dir, "bin");
  mkdirSync(bin);
  symlinkSync(process.execPath, join(bin, "node"));
  symlinkSync(execFileSync("bash", ["-c", "command -v dirname"], { encoding: "utf8" }).trim(), join(bin, "dirname"));

  const browser = await launch();
  const page = browser.context.pages()[0] ?? (await browser.context.newPage());
  const t0 = performance.now();
  const server = spawn("/bin/bash", ["./scripts/serve.sh"], {
    cwd: repo,
    env: { PATH: bin, PORT: "0", HOME: dir },
    stdio: ["ignore", "pipe", "inherit"],
  });
  const url = await new Promise((done, fail) => {
    let out = "";
    server.stdout.on("data", (d) => {
      out += d;
      const m = out.match(/at (http:\/\/127\.0\.0\.1:\d+\/)/);
      if (m) done(m[1]);
    });
    server.on("exit", (code) => fail(new Error(`serve.sh exited (${code}) before serving:\n${out}`)));
  });
  const servingS = (performance.now() - t0) / 1000;
  await page.goto(url);
  await page.waitForSelector("body[data-ready=true]", { timeout: 120_000 });
  const first = await page.textContent("#out-iteration");
  await page.waitForFunction((v) => document.getElementById("out-iteration").textContent !== v, first, { timeout: 120_000 });
  const movingS = (performance.now() - t0) / 1000;
  console.log(`${run} | ${cloneS.toFixed(1)} | ${servingS.toFixed(2)} | ${movingS.toFixed(2)}`);

  server.kill();
  await browser.close();
  rmSync(dir, { recursive: true, force: true });
}
console.log(`load average after: ${loadavg().map((x) => x.toFixed(2)).join(" ")}`);
