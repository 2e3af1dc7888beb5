// N independent chains of Algorithm 1, one invocation per chain. A chain's
// position, velocity, gradient, value, running best and generator live in
// registers across all the steps of one dispatch; only the running best's
// point (when it improves) and, at the end, the state go back to memory.
//
// Layout: coordinate-major (`xs[i * N + c]`), so that the invocations of a
// warp read and write neighbouring words. The sampler's step, the start's
// draw and the potential (`value_and_gradient`) are spliced in by the host.

struct Params {
    chains: u32,
    steps: u32,
    first_step: u32,
    stride: u32,
    group_size: u32,
    groups: u32,
    eps_count: u32,
    pass_len: u32,
    pass_in: u32,
    pass_out: u32,
    coef_offset: u32,
    // Invocations per row of a two-dimensional dispatch (a dimension holds
    // at most 65535 workgroups).
    row: u32,
    // 0, -0.0 and 1.0, unknown to the compiler: see `rounded` and `mul`.
    zero: u32,
    negative_zero: f32,
    one: f32,
}

// A chain's scalars. `stopped`: the iterate at which it diverged;
// `starts`: the points its start drew.
struct Status {
    value: Real,
    best: Real,
    best_iter: u32,
    flags: u32,
    stopped: u32,
    starts: u32,
}

const DIVERGED: u32 = 1u;
const UNBOUNDED: u32 = 2u;
const BAD_START_POSITION: u32 = 4u;
const BAD_START_VALUE: u32 = 8u;
const BAD_START_GRADIENT: u32 = 16u;

@group(0) @binding(0) var<uniform> params: Params;
// The Ziggurat's X and F, the start, U* and the eps of the empirical
// probability, then the step's coefficients of this dispatch.
@group(0) @binding(1) var<storage, read> tables: array<Real>;
@group(0) @binding(2) var<storage, read_write> rngs: array<vec4<u32>>;
@group(0) @binding(3) var<storage, read_write> xs: array<Real>;
@group(0) @binding(4) var<storage, read_write> ys: array<Real>;
@group(0) @binding(5) var<storage, read_write> best_xs: array<Real>;
@group(0) @binding(6) var<storage, read_write> status: array<Status>;
@group(0) @binding(7) var<storage, read_write> candidates: array<u32>;
@group(0) @binding(8) var<storage, read_write> counts: array<atomic<u32>>;

fn all_finite(v: ptr<function, Point>) -> bool {
    var ok = true;
    for (var i = 0u; i < D; i++) {
        ok = ok && finite((*v)[i]);
    }
    return ok;
}

// One coefficient of the step at iterate `k` of this dispatch's table.
fn coef(s: u32, j: u32) -> Real {
    return tables[params.coef_offset + 8u * s + j];
}

@compute @workgroup_size(WORKGROUP)
fn init(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = gid.y * params.row + gid.x;
    let n = params.chains;
    if c >= n {
        return;
    }
    rng = rngs[c];
    var x: Point;
    var y: Point;
    var g: Point;
    var value: Real;
    var flags = 0u;
    // The CPU builder's rule: an infeasible start is drawn again from the
    // chain's generator, up to START_TRIES points; a start below the floor
    // ends the build at once.
    var tries = 0u;
    loop {
        for (var i = 0u; i < D; i++) {
            START_COORDINATE
            y[i] = 0.0;
        }
        value = value_and_gradient(&x, &g);
        tries += 1u;
        if value < FLOOR && all_finite(&x) {
            flags = UNBOUNDED;
        } else if finite(value) && all_finite(&g) && all_finite(&x) {
            flags = 0u;
        } else if !all_finite(&x) {
            flags = BAD_START_POSITION;
        } else if !finite(value) {
            flags = BAD_START_VALUE;
        } else {
            flags = BAD_START_GRADIENT;
        }
        if flags == 0u || flags == UNBOUNDED || tries >= START_TRIES {
            break;
        }
    }
    for (var i = 0u; i < D; i++) {
        xs[i * n + c] = x[i];
        ys[i * n + c] = y[i];
        best_xs[i * n + c] = x[i];
    }
    rngs[c] = rng;
    status[c] = Status(value, select(none(), value, START_IN_BEST), 0u, flags, 0u, tries);
}

@compute @workgroup_size(WORKGROUP)
fn step(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = gid.y * params.row + gid.x;
    let n = params.chains;
    if c >= n {
        return;
    }
    var st = status[c];
    if (st.flags & DIVERGED) != 0u {
        return;
    }
    rng = rngs[c];
    var x: Point;
    var y: Point;
    var g: Point;
    for (var i = 0u; i < D; i++) {
        x[i] = xs[i * n + c];
        y[i] = ys[i * n + c];
    }
    // The gradient at the stored point: the same function of the same
    // bits as the one the previous step computed.
    var value = value_and_gradient(&x, &g);
    for (var s = 0u; s < params.steps; s++) {
        STEP_CHAIN
        value = value_and_gradient(&x, &g);
        let k = params.first_step + s + 1u;
        if value < FLOOR {
            st.flags |= DIVERGED | UNBOUNDED;
            st.stopped = k;
            break;
        }
        if !(finite(value) && all_finite(&g) && all_finite(&x)) {
            st.flags |= DIVERGED;
            st.stopped = k;
            break;
        }
        if k % params.stride == 0u && value < st.best {
            st.best = value;
            st.best_iter = k;
            for (var i = 0u; i < D; i++) {
                best_xs[i * n + c] = x[i];
            }
        }
    }
    st.value = value;
    for (var i = 0u; i < D; i++) {
        xs[i * n + c] = x[i];
        ys[i * n + c] = y[i];
    }
    rngs[c] = rng;
    status[c] = st;
}

// Algorithm 1's best: the chain with the lowest running best, the earliest
// iterate on ties, then the lowest index (the order in which the kernel's
// optimiser meets them). One pass reduces each workgroup's candidates to
// one; the host repeats until one is left. Pass 0 reads chain indices
// directly.
var<workgroup> wg_best: array<u32, WORKGROUP>;

fn before(a: u32, b: u32) -> bool {
    let sa = status[a];
    let sb = status[b];
    if sa.best != sb.best {
        return sa.best < sb.best;
    }
    if sa.best_iter != sb.best_iter {
        return sa.best_iter < sb.best_iter;
    }
    return a < b;
}

@compute @workgroup_size(WORKGROUP)
fn argmin(@builtin(global_invocation_id) gid: vec3<u32>,
          @builtin(local_invocation_id) lid: vec3<u32>,
          @builtin(workgroup_id) wid: vec3<u32>) {
    let j = gid.y * params.row + gid.x;
    let len = params.pass_len;
    var mine = 0xffffffffu;
    if j < len {
        if params.pass_in == 0xffffffffu {
            mine = j;
        } else {
            mine = candidates[params.pass_in + j];
        }
    }
    wg_best[lid.x] = mine;
    workgroupBarrier();
    for (var half = WORKGROUP / 2u; half > 0u; half /= 2u) {
        if lid.x < half {
            let a = wg_best[lid.x];
            let b = wg_best[lid.x + half];
            if b != 0xffffffffu && (a == 0xffffffffu || before(b, a)) {
                wg_best[lid.x] = b;
            }
        }
        workgroupBarrier();
    }
    if lid.x == 0u {
        candidates[params.pass_out + wid.y * (params.row / WORKGROUP) + wid.x] = wg_best[0];
    }
}

// The paper's empirical probability: for each group of `group_size`
// consecutive chains (one run of Algorithm 1), whether its best current
// value (live chains only), and its best running best, lie within each eps
// of U*; counts[2e] and counts[2e + 1] count the groups that do.
@compute @workgroup_size(WORKGROUP)
fn groups(@builtin(global_invocation_id) gid: vec3<u32>) {
    let m = gid.y * params.row + gid.x;
    if m >= params.groups {
        return;
    }
    var current = none();
    var running = none();
    let first = m * params.group_size;
    for (var c = first; c < first + params.group_size; c++) {
        let st = status[c];
        if (st.flags & DIVERGED) == 0u && st.value < current {
            current = st.value;
        }
        if st.best < running {
            running = st.best;
        }
    }
    let u_star = tables[U_STAR_AT];
    for (var e = 0u; e < params.eps_count; e++) {
        let eps = tables[U_STAR_AT + 1u + e];
        if current - u_star <= eps {
            atomicAdd(&counts[2u * e], 1u);
        }
        if running - u_star <= eps {
            atomicAdd(&counts[2u * e + 1u], 1u);
        }
    }
}

// The run's failures: counts[0] counts the diverged chains, counts[1]
// takes the earliest iterate at which a chain fell below the floor.
@compute @workgroup_size(WORKGROUP)
fn census(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = gid.y * params.row + gid.x;
    if c >= params.chains {
        return;
    }
    let st = status[c];
    if (st.flags & DIVERGED) != 0u {
        atomicAdd(&counts[0], 1u);
    }
    if (st.flags & UNBOUNDED) != 0u {
        atomicMin(&counts[1], st.stopped);
    }
}

// Then counts[2] takes the lowest chain that fell at that iterate: the
// chain the CPU optimiser reports.
@compute @workgroup_size(WORKGROUP)
fn first_unbounded(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = gid.y * params.row + gid.x;
    if c >= params.chains {
        return;
    }
    let st = status[c];
    if (st.flags & UNBOUNDED) != 0u && st.stopped == atomicLoad(&counts[1]) {
        atomicMin(&counts[2], c);
    }
}

// Draws for the stream tests: `count` normals (or pairs, when PAIRS) of
// chain c into xs[c * count ..], from its generator, which is stored back.
@compute @workgroup_size(WORKGROUP)
fn normals(@builtin(global_invocation_id) gid: vec3<u32>) {
    let c = gid.y * params.row + gid.x;
    if c >= params.chains {
        return;
    }
    rng = rngs[c];
    let count = params.steps;
    for (var j = 0u; j < count; j++) {
        if params.stride == 2u {
            let z = normal_pair();
            xs[(c * count + j) * 2u] = z.x;
            xs[(c * count + j) * 2u + 1u] = z.y;
        } else {
            xs[c * count + j] = normal();
        }
    }
    rngs[c] = rng;
}
