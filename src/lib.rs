//! lumiere: a CPU path tracer that teaches light transport term by term.
//!
//! The lighting terms of the course: L0 (emission seen directly), L1 (direct
//! lighting, one reflection), L2 (one indirect bounce, two reflections) and
//! L3+ (three reflections or more). See `docs/light-transport.md` for the
//! estimators and `docs/architecture.md` for how a sample flows through the
//! modules below.
//!
//! The folders run in one direction, each importing only those above it in
//! this table (`tests/architecture.rs` checks it):
//!
//! | folder | what it holds |
//! |---|---|
//! | [`platform`] | what differs in the browser: the clock, threads, the memory ceiling |
//! | [`course`] | the course's vocabulary: the terms, the options, the render settings, colour |
//! | [`scene`] | the scene as plain data, loaded from glTF or built in |
//! | [`geometry`] | rays, robust offsets, the camera's rays, the BVH |
//! | [`transport`] | the estimators of the terms: integrators, BRDFs, lights, sampling |
//! | [`render`] | the film, the render loop, the viewer's worker, display settings, export |
//! | [`analysis`] | error metrics, convergence, noise views, the probe, the path view |
//! | [`lesson`] | the course's lessons: steps of settings, titles, formulas, captions |
//! | [`tools`] | `lumiere bench`, `stress`, `strip` and the slides of `lesson --export` |
//! | `app` | the viewer (feature `gui`) |
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

pub mod analysis;
#[cfg(feature = "gui")]
pub mod app;
pub mod course;
pub mod geometry;
pub mod lesson;
pub mod platform;
pub mod render;
pub mod scene;
pub mod tools;
pub mod transport;

pub use course::{BrdfOverride, LightMode, RenderSettings, Term, TermSet};
pub use render::film::Film;
pub use scene::Scene;
pub use scene::error::SceneError;
pub use transport::context::RenderContext;
