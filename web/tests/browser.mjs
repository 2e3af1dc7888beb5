// Shared by the browser tests and the measurement: Debian's Chromium driven
// by playwright-core, with a fresh profile and no background traffic (this
// machine has no network beyond loopback and package registries).
import { mkdtempSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { dirname, join, resolve } from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";

export const ROOT = resolve(dirname(fileURLToPath(import.meta.url)), "..", "..");
/** Where test artefacts (screenshots, traces) go: $HRLA_WEB_OUT or target/web-tests. */
export const OUT = process.env.HRLA_WEB_OUT ?? join(ROOT, "target", "web-tests");
/** Where the screenshots go: $HRLA_WEB_SHOTS or target/web-screenshots. */
export const SHOTS = process.env.HRLA_WEB_SHOTS ?? join(ROOT, "target", "web-screenshots");

const FLAGS = [
  "--headless",
  "--no-sandbox",
  "--disable-gpu",
  "--disable-quic",
  "--no-first-run",
  "--disable-background-networking",
  "--disable-component-update",
  "--disable-sync",
];

/**
 * A browser context on a fresh user data dir; close() also removes the dir.
 * `args`: more command-line flags (the WebGPU tests' `--enable-unsafe-webgpu`).
 */
export async function launch(viewport = { width: 1280, height: 800 }, args = []) {
  const profile = mkdtempSync(join(tmpdir(), "hrla-chromium-"));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: process.env.CHROMIUM ?? "/usr/bin/chromium",
    headless: true,
    args: [...FLAGS, ...args],
    viewport,
  });
  const close = async () => {
    await context.close();
    rmSync(profile, { recursive: true, force: true });
  };
  return { context, close };
}
