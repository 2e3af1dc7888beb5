// The chain's generator, xoshiro128++, word for word as rand_xoshiro's
// `Xoshiro128PlusPlus`; the normals of each float type follow (`normal32`,
// `normal64`).
var<private> rng: vec4<u32>;

fn rotl(x: u32, k: u32) -> u32 {
    return (x << k) | (x >> (32u - k));
}

// xoshiro128++ (Blackman and Vigna), as rand_xoshiro's `next_u32`.
fn next_u32() -> u32 {
    let result = rotl(rng.x + rng.w, 7u) + rng.x;
    let t = rng.y << 9u;
    rng.z ^= rng.x;
    rng.w ^= rng.y;
    rng.y ^= rng.z;
    rng.x ^= rng.w;
    rng.z ^= t;
    rng.w = rotl(rng.w, 11u);
    return result;
}

