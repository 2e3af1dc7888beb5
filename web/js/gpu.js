// The chains on the browser's WebGPU device: hrla-gpu's WGSL program
// (xoshiro128++ streams from chain_seed, the kernel's Ziggurat, the
// sampler's step, the built-in potential), assembled by the wasm wrapper
// with the step's coefficients that the kernel computes in f64, run here by
// the page, and binned on the device into a density of the chains that
// comes back as one small grid of counts per picture.

import { gpu_coef_offset, gpu_generators, gpu_max_chains, gpu_max_steps, gpu_program, gpu_tables } from "../pkg/hrla_wasm.js";

/** Invocations per workgroup of hrla-gpu's kernels and of the binning. */
const WORKGROUP = 64;
/** Chains whose generators are seeded per call into wasm. */
const SEED_SLICE = 1 << 16;
/** Bytes of hrla-gpu's `Status` (value, best, best_iter, flags, stopped, starts). */
const STATUS_BYTES = 24;
/** hrla-gpu's `Status.flags` bit of a diverged chain. */
const DIVERGED = 1;

/** The most chains a run holds. */
export const maxGpuChains = () => gpu_max_chains();

/**
 * The browser's WebGPU adapter, or why there is none: { adapter, label } or
 * { why }. The device itself is asked for only when a run starts
 * (`openDevice`), so that a visitor who never starts one holds none.
 */
export async function findAdapter() {
  if (!navigator.gpu) return { why: "this browser has no WebGPU" };
  let adapter;
  try {
    adapter = await navigator.gpu.requestAdapter();
  } catch (e) {
    return { why: `WebGPU refused an adapter (${e.message})` };
  }
  if (!adapter) return { why: "this browser offers no WebGPU adapter" };
  const info = adapter.info ?? {};
  const label = [info.vendor, info.architecture, info.description].filter(Boolean).join(" ") || "WebGPU adapter";
  return { adapter, label };
}

/** A device of `adapter` with storage bindings large enough for 10^6 chains (the status: 24 MB). */
export function openDevice(adapter) {
  const want = 128 * 1024 * 1024;
  const requiredLimits = {};
  for (const name of ["maxStorageBufferBindingSize", "maxBufferSize"]) {
    requiredLimits[name] = Math.min(adapter.limits[name], want);
  }
  return adapter.requestDevice({ requiredLimits });
}

/** Bins each live chain's position into a grid, and finds the lowest running best and current value. */
const DENSITY_WGSL = /* wgsl */ `
struct Grid { x0: f32, y1: f32, sx: f32, sy: f32, w: u32, h: u32, n: u32, pad: u32 }
struct Status { value: f32, best: f32, best_iter: u32, flags: u32, stopped: u32, starts: u32 }
@group(0) @binding(0) var<uniform> grid: Grid;
@group(0) @binding(1) var<storage, read> xs: array<f32>;
@group(0) @binding(2) var<storage, read> status: array<Status>;
// w * h bins, then: diverged chains, live chains outside the grid, the
// lowest running best and the lowest current value (as ordered words).
@group(0) @binding(3) var<storage, read_write> bins: array<atomic<u32>>;

// A float's bits as a word whose unsigned order is the float's order.
fn ordered(v: f32) -> u32 {
  let b = bitcast<u32>(v);
  return select(b | 0x80000000u, ~b, (b >> 31u) == 1u);
}

@compute @workgroup_size(${WORKGROUP})
fn bin(@builtin(global_invocation_id) gid: vec3<u32>) {
  let c = gid.x;
  if c >= grid.n { return; }
  let tail = grid.w * grid.h;
  let st = status[c];
  atomicMin(&bins[tail + 2u], ordered(st.best));
  if (st.flags & ${DIVERGED}u) != 0u {
    atomicAdd(&bins[tail], 1u);
    return;
  }
  atomicMin(&bins[tail + 3u], ordered(st.value));
  let i = floor((xs[c] - grid.x0) * grid.sx);
  let j = floor((grid.y1 - xs[grid.n + c]) * grid.sy);
  if i >= 0.0 && j >= 0.0 && i < f32(grid.w) && j < f32(grid.h) {
    atomicAdd(&bins[u32(j) * grid.w + u32(i)], 1u);
  } else {
    atomicAdd(&bins[tail + 1u], 1u);
  }
}
`;

/** The float of an ordered word (see DENSITY_WGSL's `ordered`). */
function unordered(u) {
  const bits = u >>> 31 === 1 ? u & 0x7fffffff : ~u >>> 0;
  return new Float32Array(new Uint32Array([bits]).buffer)[0];
}

/**
 * One run of `chains` chains of the page's settings on `device`: the
 * settings' landscape, sampler, h, constant a, start N(centre, spread² I)
 * and seed. Throws an Error with the kernel's message when it refuses a
 * setting.
 */
export class GpuRun {
  constructor(device, settings) {
    const n = settings.chains;
    if (!Number.isInteger(n) || n < 1 || n > gpu_max_chains()) {
      throw Object.assign(new Error(`must be a whole number from 1 to ${gpu_max_chains()}`), { field: "gpu-chains" });
    }
    this.device = device;
    this.n = n;
    this.settings = settings;
    this.iteration = 0;
    // The wrapper checks the sampler, h, a and the start, with the kernel's messages.
    const tables = new Float32Array(
      gpu_tables(settings.sampler, settings.h, settings.a, settings.centre[0], settings.centre[1], settings.spread),
    );
    this.code = gpu_program(settings.potential, settings.sampler);
    const S = GPUBufferUsage.STORAGE;
    const buffer = (size, usage) => device.createBuffer({ size, usage });
    this.params = buffer(64, GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST);
    this.tables = buffer(tables.byteLength, S | GPUBufferUsage.COPY_DST);
    device.queue.writeBuffer(this.tables, 0, tables);
    this.rngs = buffer(16 * n, S | GPUBufferUsage.COPY_DST | GPUBufferUsage.COPY_SRC);
    this.xs = buffer(8 * n, S | GPUBufferUsage.COPY_SRC);
    this.ys = buffer(8 * n, S);
    this.bestXs = buffer(8 * n, S);
    this.status = buffer(STATUS_BYTES * n, S | GPUBufferUsage.COPY_SRC);
    for (let first = 0; first < n; first += SEED_SLICE) {
      const count = Math.min(SEED_SLICE, n - first);
      device.queue.writeBuffer(this.rngs, 16 * first, new Uint32Array(gpu_generators(settings.seed, first, count)));
    }
    this.workgroups = Math.ceil(n / WORKGROUP);
    this.grid = null;
  }

  /** Compiles the programs and draws the start; resolves when the device has done so. */
  async start() {
    const device = this.device;
    device.pushErrorScope("validation");
    const module = device.createShaderModule({ code: this.code });
    const chains = ["init", "step"].map((entryPoint) =>
      device.createComputePipeline({ layout: "auto", compute: { module, entryPoint } }),
    );
    const buffers = [this.params, this.tables, this.rngs, this.xs, this.ys, this.bestXs, this.status];
    [this.init, this.stepper] = chains.map((pipeline) => ({
      pipeline,
      group: device.createBindGroup({
        layout: pipeline.getBindGroupLayout(0),
        entries: buffers.map((buffer, binding) => ({ binding, resource: { buffer } })),
      }),
    }));
    const densityModule = device.createShaderModule({ code: DENSITY_WGSL });
    this.binner = device.createComputePipeline({ layout: "auto", compute: { module: densityModule, entryPoint: "bin" } });
    this.dispatch(this.init, 0);
    const error = await device.popErrorScope();
    if (error) throw new Error(`the device refused the program: ${error.message}`);
    await device.queue.onSubmittedWorkDone();
  }

  /** One dispatch of `steps` steps (0: the start) from the current iteration. */
  dispatch(kernel, steps) {
    const p = new DataView(new ArrayBuffer(64));
    const words = [this.n, steps, this.iteration, 1, 1, 0, 0, 0, 0, 0, gpu_coef_offset(), this.workgroups * WORKGROUP, 0];
    words.forEach((w, i) => p.setUint32(4 * i, w, true));
    p.setFloat32(52, -0, true);
    p.setFloat32(56, 1, true);
    this.device.queue.writeBuffer(this.params, 0, p.buffer);
    const encoder = this.device.createCommandEncoder();
    const pass = encoder.beginComputePass();
    pass.setPipeline(kernel.pipeline);
    pass.setBindGroup(0, kernel.group);
    pass.dispatchWorkgroups(this.workgroups);
    pass.end();
    this.device.queue.submit([encoder.finish()]);
  }

  /** `steps` more steps of every live chain; resolves when the device has done them. */
  async step(steps) {
    const most = gpu_max_steps();
    while (steps > 0) {
      const k = Math.min(steps, most);
      this.dispatch(this.stepper, k);
      this.iteration += k;
      steps -= k;
    }
    await this.device.queue.onSubmittedWorkDone();
  }

  /** Copies a device buffer's first `bytes` back to the page. */
  async read(buffer, bytes) {
    const out = this.device.createBuffer({ size: bytes, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
    const encoder = this.device.createCommandEncoder();
    encoder.copyBufferToBuffer(buffer, 0, out, 0, bytes);
    this.device.queue.submit([encoder.finish()]);
    await out.mapAsync(GPUMapMode.READ);
    const copy = out.getMappedRange().slice(0);
    out.destroy();
    return copy;
  }

  /** Every chain's position, coordinate-major: x1 of chain c at [c], x2 at [n + c]. */
  async positions() {
    return new Float32Array(await this.read(this.xs, 8 * this.n));
  }

  /**
   * The chains binned over the box [x0, x1] x [y0, y1] in a w x h grid
   * (row 0 at the top): { counts, w, h, diverged, outside, best, lowest }
   * (the lowest running best and the lowest current value of a live chain).
   */
  async density(box, w, h) {
    const device = this.device;
    const cells = w * h;
    if (!this.grid || this.grid.cells !== cells) {
      this.grid?.bins.destroy();
      const bins = device.createBuffer({ size: 4 * (cells + 4), usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_DST | GPUBufferUsage.COPY_SRC });
      const uniform = device.createBuffer({ size: 32, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
      const group = device.createBindGroup({
        layout: this.binner.getBindGroupLayout(0),
        entries: [uniform, this.xs, this.status, bins].map((buffer, binding) => ({ binding, resource: { buffer } })),
      });
      const blank = new Uint32Array(cells + 4);
      blank[cells + 2] = blank[cells + 3] = 0xffffffff;
      this.grid = { cells, bins, uniform, group, blank };
    }
    const [x0, x1, y0, y1] = box;
    const g = new DataView(new ArrayBuffer(32));
    [x0, y1, w / (x1 - x0), h / (y1 - y0)].forEach((v, i) => g.setFloat32(4 * i, v, true));
    [w, h, this.n, 0].forEach((v, i) => g.setUint32(16 + 4 * i, v, true));
    device.queue.writeBuffer(this.grid.uniform, 0, g.buffer);
    device.queue.writeBuffer(this.grid.bins, 0, this.grid.blank);
    const encoder = device.createCommandEncoder();
    const pass = encoder.beginComputePass();
    pass.setPipeline(this.binner);
    pass.setBindGroup(0, this.grid.group);
    pass.dispatchWorkgroups(this.workgroups);
    pass.end();
    device.queue.submit([encoder.finish()]);
    const words = new Uint32Array(await this.read(this.grid.bins, 4 * (cells + 4)));
    return {
      counts: words.subarray(0, cells),
      w,
      h,
      diverged: words[cells],
      outside: words[cells + 1],
      best: unordered(words[cells + 2]),
      lowest: words[cells + 3] === 0xffffffff ? NaN : unordered(words[cells + 3]),
    };
  }

  destroy() {
    for (const b of [this.params, this.tables, this.rngs, this.xs, this.ys, this.bestXs, this.status, this.grid?.bins, this.grid?.uniform]) b?.destroy();
  }
}

/**
 * Paints a density into `canvas`: each bin's count on a log scale through
 * the colour map (empty bins black), so that the few chains of a far tail
 * stay visible beside a dense mode.
 */
export function paintDensity(canvas, d, lut) {
  canvas.width = d.w;
  canvas.height = d.h;
  const ctx = canvas.getContext("2d");
  const image = ctx.createImageData(d.w, d.h);
  let max = 0;
  for (const c of d.counts) if (c > max) max = c;
  const scale = max > 0 ? 255 / Math.log1p(max) : 0;
  const px = image.data;
  for (let k = 0; k < d.counts.length; k++) {
    const c = d.counts[k];
    const o = 4 * k;
    px[o + 3] = 255;
    if (c === 0) continue;
    const i = 3 * Math.max(40, Math.round(Math.log1p(c) * scale));
    px[o] = lut[i];
    px[o + 1] = lut[i + 1];
    px[o + 2] = lut[i + 2];
  }
  ctx.putImageData(image, 0, 0);
  return max;
}
