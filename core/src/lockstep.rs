//! Four independent xoshiro256++ generators stepped in lockstep, one per
//! vector lane: [`Xoshiro256Lanes`].
//!
//! A chain's generator is a serial recurrence: each word depends on the one
//! before, so one chain's normals come out one after another however wide
//! the machine is. The chains' generators are independent of one another,
//! so [`LANES`] of them, laid out structure-of-arrays (word `j` of every
//! lane's state side by side), advance together in one vector operation per
//! state word: one 256-bit register with AVX2, two 128-bit ones with SSE2,
//! NEON or wasm SIMD128, and one lane after another, with the same
//! results, on targets without vectors (the `wide` crate picks).
//!
//! Lane `l` produces exactly the stream of the `Xoshiro256PlusPlus` it was
//! loaded from: lockstep changes the speed, never the bits. Words a lane
//! needs out of step (the Ziggurat's rare slow path) come from
//! [`Xoshiro256Lanes::lane`], a view of one lane that advances only that
//! lane.

use core::convert::Infallible;

use rand_core::{SeedableRng, TryRng, utils};
use rand_xoshiro::Xoshiro256PlusPlus;
use wide::u64x4;

/// Chains stepped in lockstep: four 64-bit generators, one AVX2 register
/// per state word.
pub const LANES: usize = 4;

/// [`LANES`] xoshiro256++ generators in lockstep, structure-of-arrays.
///
/// ```
/// use hrla::Xoshiro256Lanes;
/// use rand_xoshiro::Xoshiro256PlusPlus;
/// use rand_xoshiro::rand_core::{Rng, SeedableRng};
///
/// let mut g: [Xoshiro256PlusPlus; 4] =
///     core::array::from_fn(|i| Xoshiro256PlusPlus::seed_from_u64(i as u64));
/// let mut lanes = Xoshiro256Lanes::load(g.each_ref());
/// let words = lanes.next_u64();
/// assert_eq!(words, g.each_mut().map(|g| g.next_u64()));
/// // Lane 1 alone, then all again: each lane keeps its own stream.
/// assert_eq!(lanes.lane(1).next_u64(), g[1].next_u64());
/// assert_eq!(lanes.next_u64(), g.each_mut().map(|g| g.next_u64()));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Xoshiro256Lanes {
    /// `s[j]`: word `j` of every lane's state.
    s: [u64x4; 4],
}

impl Xoshiro256Lanes {
    /// The lanes, lane `l` in the state of `generators[l]`.
    #[inline]
    pub fn load(generators: [&Xoshiro256PlusPlus; LANES]) -> Self {
        let rows = generators.map(|g| u64x4::new(utils::read_words(&g.state())));
        Self {
            s: u64x4::transpose(rows),
        }
    }

    /// Writes lane `l`'s state back into `generators[l]`, which then goes on
    /// where the lane stopped.
    #[inline]
    pub fn store(&self, generators: [&mut Xoshiro256PlusPlus; LANES]) {
        for (g, row) in generators.into_iter().zip(u64x4::transpose(self.s)) {
            let mut bytes = [0u8; 32];
            for (chunk, w) in bytes.chunks_exact_mut(8).zip(row.to_array()) {
                chunk.copy_from_slice(&w.to_le_bytes());
            }
            // A state reached from a seed is never all zero, so `from_seed`
            // (which remaps only that one) restores it exactly.
            *g = Xoshiro256PlusPlus::from_seed(bytes);
        }
    }

    /// The next word of every lane.
    #[inline(always)]
    pub fn next_u64(&mut self) -> [u64; LANES] {
        self.next_vector().to_array()
    }

    /// The next word of every lane, as a vector.
    #[inline(always)]
    pub(crate) fn next_vector(&mut self) -> u64x4 {
        let [s0, s1, s2, s3] = &mut self.s;
        let out = rotate_left::<23>(*s0 + *s3) + *s0;
        let t = *s1 << 17;
        *s2 ^= *s0;
        *s3 ^= *s1;
        *s1 ^= *s2;
        *s0 ^= *s3;
        *s2 ^= t;
        *s3 = rotate_left::<45>(*s3);
        out
    }

    /// Lane `l` alone, as a generator (panics if `l >= LANES`).
    #[inline]
    pub fn lane(&mut self, l: usize) -> impl rand_core::Rng + '_ {
        assert!(l < LANES, "lane {l} of {LANES}");
        Lane { lanes: self, l }
    }

    /// `f` with lane `l` as a generator of its own, for the words a lane
    /// draws out of step. Out of line and by value: the caller's lanes
    /// never have their address taken, so they stay in vector registers.
    #[inline(always)]
    pub(crate) fn with_lane<T>(&mut self, l: usize, f: impl FnOnce(&mut OneLane) -> T) -> T {
        let (lanes, out) = self.lane_out_of_line(l, f);
        *self = lanes;
        out
    }

    #[cold]
    #[inline(never)]
    fn lane_out_of_line<T>(mut self, l: usize, f: impl FnOnce(&mut OneLane) -> T) -> (Self, T) {
        let mut one = OneLane(self.s.map(|s| s.to_array()[l]));
        let out = f(&mut one);
        let mut mask = [0; LANES];
        mask[l] = u64::MAX;
        let mask = u64x4::new(mask);
        for (s, w) in self.s.iter_mut().zip(one.0) {
            *s = mask.bitselect(u64x4::splat(w), *s);
        }
        (self, out)
    }
}

/// One lane's state, out of the vectors: xoshiro256++ one word at a time.
#[derive(Debug)]
pub(crate) struct OneLane([u64; 4]);

impl OneLane {
    #[inline]
    fn next(&mut self) -> u64 {
        let [s0, s1, s2, s3] = &mut self.0;
        let out = s0.wrapping_add(*s3).rotate_left(23).wrapping_add(*s0);
        let t = *s1 << 17;
        *s2 ^= *s0;
        *s3 ^= *s1;
        *s1 ^= *s2;
        *s0 ^= *s3;
        *s2 ^= t;
        *s3 = s3.rotate_left(45);
        out
    }
}

impl TryRng for OneLane {
    type Error = Infallible;

    #[inline]
    fn try_next_u32(&mut self) -> Result<u32, Infallible> {
        Ok((self.next() >> 32) as u32)
    }

    #[inline]
    fn try_next_u64(&mut self) -> Result<u64, Infallible> {
        Ok(self.next())
    }

    fn try_fill_bytes(&mut self, dest: &mut [u8]) -> Result<(), Infallible> {
        utils::fill_bytes_via_next_word(dest, || self.try_next_u64())
    }
}

#[inline(always)]
fn rotate_left<const K: u32>(v: u64x4) -> u64x4 {
    (v << K) | (v >> (64 - K))
}

/// One lane of [`Xoshiro256Lanes`] as a generator: its words are those of
/// the lane's `Xoshiro256PlusPlus` (`next_u32` too: the high half of the
/// next word, as `Xoshiro256PlusPlus` gives).
#[derive(Debug)]
struct Lane<'a> {
    lanes: &'a mut Xoshiro256Lanes,
    l: usize,
}

impl TryRng for Lane<'_> {
    type Error = Infallible;

    #[inline]
    fn try_next_u32(&mut self) -> Result<u32, Infallible> {
        self.try_next_u64().map(|w| (w >> 32) as u32)
    }

    #[inline]
    fn try_next_u64(&mut self) -> Result<u64, Infallible> {
        let l = self.l;
        Ok(self.lanes.with_lane(l, |g| g.next()))
    }

    fn try_fill_bytes(&mut self, dest: &mut [u8]) -> Result<(), Infallible> {
        utils::fill_bytes_via_next_word(dest, || self.try_next_u64())
    }
}

#[cfg(test)]
mod tests {
    use rand_core::Rng;

    use super::*;

    /// Every lane reproduces its generator's stream through any mix of
    /// lockstep words, single-lane words, `next_u32` and a store/load.
    #[test]
    fn lanes_reproduce_their_generators() {
        let mut g: [Xoshiro256PlusPlus; LANES] =
            core::array::from_fn(|i| Xoshiro256PlusPlus::seed_from_u64(i as u64 * 77 + 5));
        let mut lanes = Xoshiro256Lanes::load(g.each_ref());
        for round in 0..1000u64 {
            let words = lanes.next_u64();
            for l in 0..LANES {
                assert_eq!(words[l], g[l].next_u64());
            }
            let l = (round % 4) as usize;
            if round % 3 == 0 {
                assert_eq!(lanes.lane(l).next_u32(), g[l].next_u32());
            } else {
                assert_eq!(lanes.lane(l).next_u64(), g[l].next_u64());
            }
        }
        let mut stored: [Xoshiro256PlusPlus; LANES] =
            core::array::from_fn(|_| Xoshiro256PlusPlus::seed_from_u64(0));
        lanes.store(stored.each_mut());
        assert_eq!(stored, g);
    }
}
