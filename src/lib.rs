//! lumiere: a CPU path tracer that teaches light transport term by term.
//!
//! The lighting terms of the course: L0 (emission seen directly), L1 (direct
//! lighting, one reflection), L2 (one indirect bounce, two reflections) and
//! L3+ (three reflections or more). See `docs/light-transport.md`.

pub mod error;
pub mod scene;

pub use error::SceneError;
