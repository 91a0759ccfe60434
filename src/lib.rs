//! lumiere: a CPU path tracer that teaches light transport term by term.
//!
//! The lighting terms of the course: L0 (emission seen directly), L1 (direct
//! lighting, one reflection), L2 (one indirect bounce, two reflections) and
//! L3+ (three reflections or more). See `docs/light-transport.md` for the
//! estimators and `docs/architecture.md` for how a sample flows through the
//! modules below.

pub mod accel;
pub mod brdf;
pub mod camera;
pub mod color;
pub mod error;
pub mod export;
pub mod film;
pub mod geometry;
pub mod integrator;
pub mod lights;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod settings;
pub mod shading;

pub use error::SceneError;
pub use film::Film;
pub use integrator::RenderContext;
pub use scene::Scene;
pub use settings::{BrdfOverride, LightMode, RenderSettings, Term, TermSet};
