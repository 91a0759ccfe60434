//! lumiere: a CPU path tracer that teaches light transport term by term.
//!
//! The lighting terms of the course: L0 (emission seen directly), L1 (direct
//! lighting, one reflection), L2 (one indirect bounce, two reflections) and
//! L3+ (three reflections or more). See `docs/light-transport.md` for the
//! estimators and `docs/architecture.md` for how a sample flows through the
//! modules below.
//!
//! Rendering one term of a scene whose answer is known — the furnace, a
//! closed sphere emitting L_e = 2 with albedo ½, where L1 = ρ·L_e = 1:
//!
//! ```
//! use lumiere::render::{Budget, render};
//! use lumiere::{Film, RenderContext, RenderSettings, Term, TermSet, scene::builtin};
//!
//! let settings = RenderSettings { width: 8, height: 8, terms: TermSet::only(Term::L1), ..Default::default() };
//! let context = RenderContext::new(builtin::furnace(0.5, 2.0), settings);
//! let mut film = Film::new(8, 8);
//! render(&context, &mut film, Budget::Samples(16), |_| {});
//! let l1 = film.radiance(TermSet::only(Term::L1));
//! let mean = l1.iter().map(|p| p.x).sum::<f32>() / l1.len() as f32;
//! assert!((mean - 1.0).abs() < 0.05, "L1 = {mean}");
//! ```

pub mod accel;
pub mod adaptive;
#[cfg(feature = "gui")]
pub mod app;
pub mod bench;
pub mod brdf;
pub mod camera;
pub mod capture;
pub mod color;
pub mod convergence;
pub mod error;
pub mod export;
pub mod film;
pub mod geometry;
pub mod integrator;
pub mod lights;
pub mod metrics;
pub mod noise;
pub mod path_view;
pub mod probe;
pub mod progressive;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod settings;
pub mod shading;
pub mod sidecar;
pub mod splitting;
pub mod stress;
pub mod strip;

pub use error::SceneError;
pub use film::Film;
pub use integrator::RenderContext;
pub use scene::Scene;
pub use settings::{BrdfOverride, LightMode, RenderSettings, Term, TermSet};
