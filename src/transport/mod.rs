//! Light transport: how the radiance of each term is estimated.
//!
//! | file | what it holds |
//! |---|---|
//! | `lecture.rs` | the lecture's estimator, L0 + L1 + L2 + L3+ as the slides write them |
//! | `fast.rs` | the fast path tracer: MIS, splitting, skipped work, counters |
//! | `brdf.rs` | Lambert, Phong and the mirror: evaluation and sampling |
//! | `lights.rs` | the light sources and how a point on them is drawn |
//! | `surface.rs` | what a ray hit, seen as a surface: normals, emission, BRDF |
//! | `sampling.rs` | random numbers (independent, stratified, Sobol) and warps |
//! | `splitting.rs` | the pilot that chooses continuations per first hit |

pub mod brdf;
pub mod fast;
pub mod lights;
pub mod sampling;
pub mod splitting;
pub mod surface;
