//! Random numbers: what a sample draws, from which sampler.
//!
//! The warps that turn them into directions and points are in `warps.rs`.
//!
//! A sample's numbers are a pure function of
//! (sampler, seed, pixel, sample index, dimension): no state is carried
//! between calls, so the image does not depend on which thread renders which
//! pixel, and skipping a computation (a term switched off) does not shift the
//! numbers used by the others: each use has its own fixed dimension ([`dim`]).
//! Three samplers ([`Sampler`]) produce them:
//!
//! * **independent** — a hash of (seed, pixel, sample, dimension): plain
//!   Monte Carlo, error ∝ 1/√N.
//! * **stratified** (jittered) — sample indices go in blocks of 16. Within a
//!   block, a pair `uniform2(d)` puts one point in each cell of a 4 × 4 grid,
//!   and a single `uniform(d)` one number in each sixteenth of [0, 1): a
//!   per-(pixel, block, dimension) permutation of the strata (Kensler's hashed
//!   permutation, then a random xor), plus a hashed jitter inside the stratum.
//!   The variance of a smooth integrand drops fully at multiples of 16 samples.
//! * **Sobol** — padded Owen-scrambled Sobol points (Burley 2020, the
//!   `sobol_burley` crate; pbrt-v4's `PaddedSobolSampler`): each dimension
//!   read alone, and each pair read by `uniform2`, has its own 2D sequence
//!   made of Sobol's first two dimensions (a (0, 2)-sequence: every 2^k
//!   consecutive aligned samples fill each elementary interval of area 2^−k
//!   once), under a scramble and an index shuffle hashed from the seed, the
//!   pixel and the dimension. The shuffle keeps aligned blocks together, so
//!   every pair stays stratified, and decorrelates the pairs. (One sequence
//!   over all dimensions, dimension d being Sobol dimension d, stratified
//!   the high dimensions' pairs poorly: it barely beat independent numbers.)
//!   Past the 2^16 points of a sequence, the samples continue in a sequence
//!   of another scramble.
//!
//! **Why every estimator stays unbiased.** Each number taken alone is uniform
//! on [0, 1) over the random scramble, whatever its sample index: a stratum
//! permutation followed by a random xor puts any slot in any stratum with
//! probability 1/16 before the uniform jitter, and Owen scrambling makes each
//! point of a net uniform. Each sample therefore estimates the integral
//! without bias, and so does any prefix of samples: a progressive render may
//! stop anywhere, not only at a multiple of 16 or at a power of two. The
//! samplers only make the errors of a pixel's samples cancel better.
//!
//! **Repetitions.** The j-th of N repeated uses within sample n (light samples,
//! continuations) reads [`SampleStream::split`]: for the stratified and Sobol
//! samplers it is sample n·N + j of the same dimensions, so N light samples
//! per pixel sample are N consecutive, well-spread points.

use glam::Vec2;

use crate::course::Sampler;

/// Fixed dimensions of a sample: each use of a random number has its own.
///
/// Uses repeated within one sample (the j-th of N light samples, the m-th of
/// M continuations) do not get new dimensions: they read the same dimensions
/// of a sub-stream, [`SampleStream::split`], so a quasi-random sampler sees
/// them as N (or M) consecutive points of the same low dimensions.
pub mod dim {
    /// Position inside the pixel (2D).
    pub const PIXEL: u32 = 0;
    /// Dimensions used at path vertex `vertex` start at `vertex_base(vertex)`.
    pub const PER_VERTEX: u32 = 8;
    /// Which light a light sample picks, in scenes of too many lights for
    /// the position pair to pick it (`LightTable::pick_with_position`).
    pub const LIGHT_SELECT: u32 = 0;
    /// Where on the light (2D); with few lights, also which light.
    pub const LIGHT_POSITION: u32 = 1;
    /// Direction gathered to find lights (2D); with a Phong BRDF, also its lobe.
    pub const GATHER_DIRECTION: u32 = 3;
    /// Direction of the next reflection (2D); with a Phong BRDF, also its lobe.
    pub const BRDF_DIRECTION: u32 = 5;
    pub const RUSSIAN_ROULETTE: u32 = 7;

    /// First dimension of path vertex `vertex` (0 = the first surface hit).
    pub const fn vertex_base(vertex: u32) -> u32 {
        2 + vertex * PER_VERTEX
    }
}

/// SplitMix64's finaliser: a fast, well-mixing 64-bit hash.
#[inline]
pub(crate) fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Odd constants that spread small integers over 64 bits before hashing.
const SAMPLE_SPREAD: u64 = 0x9e37_79b9_7f4a_7c15;
const DIMENSION_SPREAD: u64 = 0xd1b5_4a32_d192_ed03;

/// The hash of (key, dimension): what the numbers of one dimension hang on.
#[inline]
fn dimension_key(key: u64, dimension: u32) -> u64 {
    mix64(key ^ (dimension as u64 + 1).wrapping_mul(DIMENSION_SPREAD))
}

/// `bits` in [0, 2²⁴) as a number in [0, 1): exact, never 1.0.
#[inline]
fn unit_from_24_bits(bits: u64) -> f32 {
    bits as f32 * (1.0 / (1u64 << 24) as f32)
}

/// Sample indices per block of the stratified sampler; a power of two.
pub const STRATIFIED_BLOCK: u64 = 16;
/// Side of the stratified sampler's 2D grid: `STRATIFIED_GRID²` = [`STRATIFIED_BLOCK`].
pub const STRATIFIED_GRID: u32 = 4;
/// Sample indices of one Owen-scrambled Sobol sequence (the crate's limit);
/// later indices continue in a sequence of another scramble.
const SOBOL_SEQUENCE_LENGTH: u64 = 1 << 16;

/// The random numbers of one sample of one pixel.
#[derive(Clone, Copy, Debug)]
pub struct SampleStream {
    sampler: Sampler,
    /// Independent: the hash of (seed, pixel, sample, splits). Others: the
    /// hash of (seed, pixel), which scrambles the pixel's points.
    key: u64,
    /// Others than independent: the sample index, splits folded in (n·N + j).
    index: u64,
    /// Sobol: the index's point in its sequence, bits reversed (the form
    /// every dimension's shuffle reads, reversed once here).
    point_rev: u32,
}

impl SampleStream {
    /// Sample `sample` of pixel `pixel`, with independent numbers.
    pub fn new(seed: u64, pixel: u64, sample: u64) -> Self {
        Self::with_sampler(Sampler::Independent, seed, pixel, sample)
    }

    /// Sample `sample` of pixel `pixel`, with the numbers of `sampler`.
    pub fn with_sampler(sampler: Sampler, seed: u64, pixel: u64, sample: u64) -> Self {
        let pixel_key = mix64(mix64(seed ^ 0x5851_f42d_4c95_7f2d) ^ pixel);
        match sampler {
            Sampler::Independent => Self {
                sampler,
                key: mix64(pixel_key ^ sample.wrapping_mul(SAMPLE_SPREAD)),
                index: 0,
                point_rev: 0,
            },
            Sampler::Stratified | Sampler::Sobol => Self {
                sampler,
                key: pixel_key,
                index: sample,
                point_rev: sobol_point_rev(sample),
            },
        }
    }

    pub fn sampler(&self) -> Sampler {
        self.sampler
    }

    /// The stream of repetition `index` of `count` within this sample (the
    /// j-th light sample, the m-th continuation); repetition 0 of 1 is `self`.
    ///
    /// Stratified and Sobol read repetition j of sample n as sample n·N + j,
    /// so the N repetitions are N consecutive points of the same dimensions.
    pub fn split(&self, index: u32, count: u32) -> SampleStream {
        if count <= 1 {
            return *self;
        }
        match self.sampler {
            Sampler::Independent => Self {
                key: mix64(self.key ^ mix64((index as u64) << 32 | count as u64)),
                ..*self
            },
            Sampler::Stratified | Sampler::Sobol => {
                let index = self
                    .index
                    .wrapping_mul(count as u64)
                    .wrapping_add(index as u64);
                Self {
                    index,
                    point_rev: sobol_point_rev(index),
                    ..*self
                }
            }
        }
    }

    /// A number in [0, 1) for dimension `dimension`.
    #[inline]
    pub fn uniform(&self, dimension: u32) -> f32 {
        match self.sampler {
            Sampler::Independent => self.independent(dimension),
            Sampler::Stratified => self.stratified(dimension),
            Sampler::Sobol => self.sobol(dimension),
        }
    }

    /// A point in [0, 1)² for the dimension pair `dimension`, `dimension + 1`:
    /// (`uniform(dimension)`, `uniform(dimension + 1)`) for independent
    /// numbers; the stratified and Sobol samplers stratify the pair jointly
    /// (so a dimension is read either alone or as part of one pair, never both).
    #[inline]
    pub fn uniform2(&self, dimension: u32) -> Vec2 {
        match self.sampler {
            Sampler::Independent => {
                Vec2::new(self.independent(dimension), self.independent(dimension + 1))
            }
            Sampler::Stratified => self.stratified2(dimension),
            Sampler::Sobol => self.sobol2(dimension),
        }
    }

    #[inline]
    fn independent(&self, dimension: u32) -> f32 {
        // 24 random bits: every value exactly representable, never 1.0
        unit_from_24_bits(dimension_key(self.key, dimension) >> 40)
    }

    /// Which of the [`STRATIFIED_BLOCK`] strata this sample takes in its block,
    /// and 64 bits of jitter.
    #[inline]
    fn stratum_and_jitter(&self, dimension: u32) -> (u32, u64) {
        let key = dimension_key(self.key, dimension);
        let block = self.index / STRATIFIED_BLOCK;
        let slot = (self.index % STRATIFIED_BLOCK) as u32;
        let shuffle = mix64(key ^ block.wrapping_mul(SAMPLE_SPREAD));
        // a permutation of the slots, then a random xor: whatever the
        // permutation, each slot lands in each stratum with probability 1/16
        let stratum = permute_16(slot, shuffle as u32) ^ (shuffle >> 60) as u32;
        let jitter = mix64(key ^ mix64(self.index));
        (stratum, jitter)
    }

    /// Stratum of 1/16 of [0, 1), jittered.
    #[inline]
    fn stratified(&self, dimension: u32) -> f32 {
        let (stratum, jitter) = self.stratum_and_jitter(dimension);
        unit_from_24_bits((stratum as u64) << 20 | jitter >> 44)
    }

    /// Cell of the 4×4 grid, jittered.
    #[inline]
    fn stratified2(&self, dimension: u32) -> Vec2 {
        let (stratum, jitter) = self.stratum_and_jitter(dimension);
        let (column, row) = (stratum % STRATIFIED_GRID, stratum / STRATIFIED_GRID);
        let low_22 = (1u64 << 22) - 1;
        Vec2::new(
            unit_from_24_bits((column as u64) << 22 | jitter >> 42),
            unit_from_24_bits((row as u64) << 22 | jitter & low_22),
        )
    }

    /// This sample's number in the Owen-scrambled Sobol sequence of
    /// dimension `dimension` (padded sampling, pbrt-v4's
    /// `PaddedSobolSampler`): every dimension, or pair of dimensions read
    /// together, has a sequence of its own, made of
    /// Sobol's first two dimensions (a (0, 2)-sequence, the best-stratified
    /// pair) under a scramble and an index shuffle of its own. The shuffle
    /// keeps aligned blocks of 2^k indices together, so each block still
    /// stratifies every pair, and decorrelates the dimensions from one
    /// another (the higher Sobol dimensions' 2D projections are poorly
    /// stratified: one 30-dimensional sequence barely beat independent
    /// numbers on the Cornell box).
    #[inline]
    fn sobol(&self, dimension: u32) -> f32 {
        let (point, scramble) = self.sobol_point(dimension);
        sobol_0(point, scramble)
    }

    /// [`SampleStream::sobol`] for a pair: Sobol's dimensions 0 and 1 under
    /// one index shuffle for both.
    ///
    /// The pixel pair and the first light sample get a sequence each too.
    /// Taking them as Sobol's dimensions 0–3 of one sequence, to stratify
    /// direct lighting jointly, cut the RMSE of the Cornell box's L1 at
    /// 64 spp by a tenth, but dimensions 2 and 3 are no (0, 2)-sequence: at
    /// 8 spp its relMSE was 3.7 times this one's.
    #[inline]
    fn sobol2(&self, dimension: u32) -> Vec2 {
        let (point, scramble) = self.sobol_point(dimension);
        Vec2::from(sobol_pair(point, scramble))
    }

    /// The point index in its sequence (bits reversed), and the scrambles of `dimension`'s
    /// sequence: one hash of (pixel key, dimension, sequence).
    #[inline]
    fn sobol_point(&self, dimension: u32) -> (u32, SobolScrambles) {
        let sequence = self.index / SOBOL_SEQUENCE_LENGTH;
        let hash = mix64(
            self.key
                ^ (dimension as u64 + 1).wrapping_mul(DIMENSION_SPREAD)
                ^ sequence.wrapping_mul(SAMPLE_SPREAD),
        );
        (self.point_rev, SobolScrambles::of(hash))
    }
}

/// Sample `index`'s point in its Sobol sequence, bits reversed.
#[inline]
fn sobol_point_rev(index: u64) -> u32 {
    ((index % SOBOL_SEQUENCE_LENGTH) as u32).reverse_bits()
}

/// Sobol's dimensions 0 and 1 in `sobol_burley`'s reversed-bit form, per
/// byte of the 16-bit point index: `[dimension][byte][value]`, byte 0 the
/// index's top byte (in reversed form). The generator matrices are linear
/// over GF(2), so a point's value is the XOR of its two bytes' values: two
/// look-ups instead of the crate's loop over the index's set bits, which
/// was most of the padded sampler's cost. Built once (4 KiB) from the
/// crate's own `parts::sobol_rev`.
static SOBOL_BY_BYTE: std::sync::LazyLock<[[[u32; 256]; 2]; 2]> = std::sync::LazyLock::new(|| {
    let mut tables = [[[0; 256]; 2]; 2];
    for (dimension, by_byte) in tables.iter_mut().enumerate() {
        for (byte, values) in by_byte.iter_mut().enumerate() {
            for (value, entry) in values.iter_mut().enumerate() {
                let index_rev = (value as u32) << (24 - 8 * byte);
                *entry = sobol_burley::parts::sobol_rev(index_rev, dimension as u32);
            }
        }
    }
    tables
});

/// The three scrambles of one dimension's sequence: the index shuffle and
/// the Owen scramble of each of Sobol's dimensions 0 and 1, cut from one
/// 64-bit hash (`sobol_burley::sample_4d` hashes a 32-bit seed three times
/// instead).
#[derive(Clone, Copy, Debug)]
struct SobolScrambles {
    shuffle: u32,
    lanes: [u32; 2],
}

impl SobolScrambles {
    #[inline(always)]
    fn of(hash: u64) -> Self {
        Self {
            shuffle: (hash >> 32) as u32,
            lanes: [hash as u32, (hash.wrapping_mul(SAMPLE_SPREAD) >> 32) as u32],
        }
    }
}

/// The two bytes (top first) of point `index_rev` (bits reversed) after the
/// index shuffle, in reversed-bit form: the look-up keys of [`SOBOL_BY_BYTE`].
#[inline(always)]
fn shuffled_bytes(index_rev: u32, scrambles: SobolScrambles) -> (usize, usize) {
    use sobol_burley::parts::owen_scramble_rev;
    let shuffled = owen_scramble_rev(index_rev, scrambles.shuffle);
    ((shuffled >> 24) as usize, (shuffled >> 16 & 0xff) as usize)
}

/// Owen-scrambles Sobol dimension `lane` (0 or 1), given in reversed-bit form.
#[inline(always)]
fn scrambled_lane(sobol_rev: u32, scrambles: SobolScrambles, lane: usize) -> f32 {
    use sobol_burley::parts::{owen_scramble_rev, u32_to_f32_norm};
    u32_to_f32_norm(owen_scramble_rev(sobol_rev, scrambles.lanes[lane]).reverse_bits())
}

/// Point `index_rev` (bits reversed) of Sobol's dimension 0 under `scrambles`, by table.
#[inline]
fn sobol_0(index_rev: u32, scrambles: SobolScrambles) -> f32 {
    let (high, low) = shuffled_bytes(index_rev, scrambles);
    let by_byte = &SOBOL_BY_BYTE[0];
    scrambled_lane(by_byte[0][high] ^ by_byte[1][low], scrambles, 0)
}

/// Point `index_rev` (bits reversed) of Sobol's dimensions 0 and 1 under `scrambles`, by table.
#[inline]
fn sobol_pair(index_rev: u32, scrambles: SobolScrambles) -> [f32; 2] {
    let (high, low) = shuffled_bytes(index_rev, scrambles);
    let tables = &*SOBOL_BY_BYTE;
    let lane = |d: usize| scrambled_lane(tables[d][0][high] ^ tables[d][1][low], scrambles, d);
    [lane(0), lane(1)]
}

/// A permutation of 0..16 chosen by `seed` (Kensler 2013, "Correlated
/// Multi-Jittered Sampling", for a power-of-two length): each step is
/// invertible on the low four bits.
#[inline]
fn permute_16(mut i: u32, seed: u32) -> u32 {
    const MASK: u32 = 15;
    i ^= seed;
    i = i.wrapping_mul(0xe170_893d);
    i ^= seed >> 16;
    i ^= seed >> 8;
    i = i.wrapping_mul(0x0929_eb3f);
    i ^= seed >> 23;
    i ^= (i & MASK) >> 1;
    i = i.wrapping_mul(1 | seed >> 27);
    i = i.wrapping_mul(0x6935_fa69);
    i = i.wrapping_mul(0x74dc_b303);
    i ^= (i & MASK) >> 2;
    i = i.wrapping_mul(0x9e50_1cc3);
    i ^= (i & MASK) >> 2;
    i = i.wrapping_mul(0xc860_a3df);
    (i.wrapping_add(seed)) & MASK
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_sobol_is_the_crates_loop_bit_for_bit() {
        use sobol_burley::parts::{owen_scramble_rev, sobol_rev, u32_to_f32_norm};
        for hash in [0, 1, 0x9e37_79b9_7f4a_7c15, u64::MAX] {
            let scrambles = SobolScrambles::of(hash);
            for index in (0u32..1 << 16).step_by(7).chain([0xffff, 0x8000, 0x00ff]) {
                let shuffled = owen_scramble_rev(index.reverse_bits(), scrambles.shuffle);
                let reference = [0, 1].map(|d| {
                    let rev = owen_scramble_rev(sobol_rev(shuffled, d as u32), scrambles.lanes[d]);
                    u32_to_f32_norm(rev.reverse_bits())
                });
                let pair = sobol_pair(index.reverse_bits(), scrambles);
                assert_eq!(
                    pair.map(f32::to_bits),
                    reference.map(f32::to_bits),
                    "{index} {hash}"
                );
                let single = sobol_0(index.reverse_bits(), scrambles);
                assert_eq!(single.to_bits(), reference[0].to_bits());
            }
        }
    }

    /// The mean of n uniform numbers has standard error √(1/12)/√n (the
    /// uniform's variance is 1/12): across 10⁴ dimensions it must lie within
    /// 4.5 of them of ½.
    #[test]
    fn uniform_numbers_are_in_range_and_decorrelated_across_dimensions() {
        let s = SampleStream::new(7, 3, 11);
        let n = 10_000;
        let mut mean = 0.0;
        for d in 0..n {
            let u = s.uniform(d);
            assert!((0.0..1.0).contains(&u));
            mean += u as f64;
        }
        mean /= n as f64;
        let standard_error = (1.0f64 / 12.0).sqrt() / (n as f64).sqrt();
        let z = (mean - 0.5) / standard_error;
        assert!(z.abs() <= 4.5, "mean {mean} of {n} uniforms (z = {z:.2})");
        assert_ne!(
            SampleStream::new(0, 0, 0).uniform(0),
            SampleStream::new(0, 0, 1).uniform(0)
        );
    }
}
