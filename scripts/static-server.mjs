// A tiny static file server for the demo page, bound to 127.0.0.1 only.
// Used by scripts/serve.sh and by the browser tests (which import it).
//
//   node scripts/static-server.mjs ROOT [PORT]
//
// It serves .wasm as application/wasm, so that the generated glue can use
// WebAssembly.instantiateStreaming, and nothing outside ROOT.
import { createServer } from "node:http";
import { readFile } from "node:fs/promises";
import { extname, join, normalize, resolve, sep } from "node:path";
import { pathToFileURL } from "node:url";

const TYPES = {
  ".html": "text/html; charset=utf-8",
  ".js": "text/javascript; charset=utf-8",
  ".mjs": "text/javascript; charset=utf-8",
  ".css": "text/css; charset=utf-8",
  ".svg": "image/svg+xml",
  ".png": "image/png",
  ".json": "application/json",
  ".wasm": "application/wasm",
  ".ts": "text/plain; charset=utf-8",
};

/** Serves ROOT on 127.0.0.1:port (0 = any free port); resolves to the server. */
export function startServer(root, port = 0) {
  const base = resolve(root);
  const server = createServer(async (req, res) => {
    let path;
    try {
      path = decodeURIComponent(new URL(req.url, "http://127.0.0.1").pathname);
    } catch {
      res.writeHead(400).end("bad request");
      return;
    }
    const file = normalize(join(base, path.endsWith("/") ? path + "index.html" : path));
    if (file !== base && !file.startsWith(base + sep)) {
      res.writeHead(403).end("forbidden");
      return;
    }
    try {
      const body = await readFile(file);
      res.writeHead(200, {
        "content-type": TYPES[extname(file)] ?? "application/octet-stream",
        // A rebuilt wasm must not meet a stale cached glue file.
        "cache-control": "no-cache",
      });
      res.end(body);
    } catch {
      res.writeHead(404, { "content-type": "text/plain" }).end("not found");
    }
  });
  return new Promise((ok, fail) => {
    server.once("error", fail);
    server.listen(port, "127.0.0.1", () => ok(server));
  });
}

if (import.meta.url === pathToFileURL(process.argv[1]).href) {
  const [root = "web", wanted = "8000"] = process.argv.slice(2);
  let server;
  try {
    server = await startServer(root, Number(wanted));
  } catch (e) {
    if (e.code !== "EADDRINUSE") throw e;
    console.log(`port ${wanted} is taken; using a free one`);
    server = await startServer(root, 0);
  }
  const { port } = server.address();
  console.log(`serving ${resolve(root)} at http://127.0.0.1:${port}/  (Ctrl-C stops)`);
}
