//! Russian roulette, one rule for both integrators.
//!
//! At a segment where roulette decides, the path goes on with probability
//! q = min(max(β), 0.95) and its throughput becomes β / q; it ends
//! otherwise. E[1{u < q} β / q] = β, so the mean is kept, while paths that
//! carry little end early.
//!
//! Roulette never touches L1, L2 or L3: its weights 1/q would add noise to
//! the terms the course shows, and to L3, the largest part of L3+. It
//! decides first on the first segment all of whose light is
//! [`FIRST_TERM`] or beyond. The two integrators file the light of a
//! segment differently, hence their first segments (segment k reaches
//! the vertex x_k, x_0 = p the first hit):
//!
//! | integrator | light of segment k | first segment decided |
//! |---|---|---|
//! | lecture | the direct lighting of x_k: L_{k+1} | [`LECTURE_FIRST_SEGMENT`] = 3 |
//! | fast | also the emission it hits: L_k | [`FAST_FIRST_SEGMENT`] = 4 |

use glam::Vec3;

/// The lowest term (in reflections) roulette may touch: L4, inside L3+.
pub const FIRST_TERM: u32 = 4;

/// The lecture integrator's first segment decided: the segment reaching x_3,
/// which carries x_3's direct lighting, L4.
pub const LECTURE_FIRST_SEGMENT: u32 = FIRST_TERM - 1;

/// The fast integrator's first segment decided: the segment reaching x_4,
/// whose emission hit is L4 (the one reaching x_3 hits L3 emission).
pub const FAST_FIRST_SEGMENT: u32 = FIRST_TERM;

/// The probability q that a path of throughput `throughput` goes on.
#[inline(always)]
pub fn survival(throughput: Vec3) -> f32 {
    throughput.max_element().min(0.95)
}
