//! The course's vocabulary, which every folder above may use: the lighting
//! terms, the options of the estimators, the render settings, colour and
//! the measure of error. It imports nothing of lumiere's.
//!
//! | file | what it holds |
//! |---|---|
//! | `terms.rs` | `Term` (L0, L1, L2, L3+), `TermSet`, `TermRadiance` |
//! | `options.rs` | the closed sets of options: light mode, BRDF override, strategies, sampler, integrator |
//! | `settings.rs` | `RenderSettings`, `Adaptive`, `SourceQuality`: plain serde data, and their limits |
//! | `color.rs` | luminance and the sRGB transfer function |
//! | `error.rs` | the ε of relMSE |

pub mod color;
pub mod error;
pub mod options;
pub mod settings;
pub mod terms;

pub use options::{
    BrdfOverride, Choice, IndirectSampling, Integrator, LightMode, LightSampling, LightSelection,
    MisHeuristic, Sampler, unknown_choice,
};
pub use settings::{
    Adaptive, DEFAULT_IOR, MAX_IOR, MAX_SAMPLES_PER_VERTEX, MAX_SOURCE_SAMPLES_PER_VERTEX,
    RenderSettings, SourceQuality,
};
pub use terms::{Term, TermRadiance, TermSet};
