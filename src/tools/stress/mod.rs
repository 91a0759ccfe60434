//! The numerical stress suite: generated scenes that break naive tracers.
//!
//! Each case renders every term (L0, L1, L2, L3+ in their own accumulators)
//! under each light mode that changes it, and reports:
//!
//! * **invalid samples** — NaN, infinite or negative terms the film's guard
//!   dropped (`RayCounts::invalid_samples`); must be 0;
//! * **leaked rays** — in a closed scene, rays that left it
//!   (`RayCounts::escaped`), or for the sphere case rays that missed it; must be 0;
//! * **energy error** — where the answer is known, the largest relative error
//!   of a term's image mean, and its z-score z = (|mean − exact| − tol·exact) / se
//!   where tol is the case's systematic tolerance per term (0 unless the
//!   closed form is approximate; then computed from the tessellated sphere
//!   or the f32 spacing of positions 10⁵ m out); must stay within the noise
//!   (z < [`Z_LIMIT`]) or, for noiseless terms, within [`NOISELESS_TOLERANCE`];
//! * **time**.
//!
//! Most closed forms are the furnace's: inside a closed surface of uniform
//! emission E whose BRDF reflects a fraction ρ of the light at every
//! incidence, every point sees L_k = ρᵏ E after k reflections, whatever the
//! shape, its size or its place — so scale, offset, slivers, coincident faces
//! and mirrors must all give it back. With at most `max_bounces` reflections,
//! L3+ = Σ_{k=3}^{max} ρᵏ E.
//!
//! Where things are: `cases` — the render cases, each one's scenes,
//! settings, light modes, closed form and tolerance, rendered and checked;
//! `scenes` — the generated scenes (furnaces, slivers, the mirror corridor,
//! a point light in a sphere, the grazing plane); `sphere_leaks` and
//! `million_samples` — the two cases that are not renders; `report` — what
//! a case measured, how it is judged, and the table.

mod cases;
mod million_samples;
mod report;
mod scenes;
mod sphere_leaks;

use strum::{Display, EnumIter, EnumString, IntoStaticStr};

use crate::course::unknown_choice;
use crate::platform::time::Instant;

pub use cases::case_scene;
pub use report::{CaseReport, Mean, NOISELESS_TOLERANCE, Z_LIMIT, table, term_mean};

/// How much work each case does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effort {
    /// Small films and ray counts: the test suite's size (seconds).
    Quick,
    /// The figures of `lumiere stress`: 10⁶ rays into the sphere, 10⁶ samples on one pixel.
    Full,
}

/// The cases of the suite.
#[derive(Clone, Copy, Debug, PartialEq, Eq, EnumIter, IntoStaticStr, EnumString, Display)]
#[strum(serialize_all = "kebab-case", parse_err_ty = String, parse_err_fn = unknown_choice::<Case>)]
pub enum Case {
    /// The furnace 0.1 mm across.
    TinyScale,
    /// The furnace 100 km across.
    HugeScale,
    /// The furnace 10 m across, 10⁵ m from the origin on every axis.
    FarFromOrigin,
    /// A plane lit and seen at 89.9° from its normal.
    Grazing,
    /// The furnace tessellated into slivers, with zero-area triangles added.
    Slivers,
    /// The furnace's surface three times over, one copy inside out.
    CoincidentFaces,
    /// A point light on a floor, another 1 µm above, an emitter through it.
    LightOnSurface,
    /// The furnace with a Phong lobe of exponent 10⁶.
    SharpPhong,
    /// A closed mirror corridor 40 m long: specular chains of 64 reflections.
    MirrorCorridor,
    /// Rays from inside a closed tessellated sphere through its vertices and edges.
    SphereLeaks,
    /// Albedo 1: every term equals the emission.
    WhiteFurnace,
    /// The camera inside a diamond ball: radiance η² denser, chains of
    /// internal reflections.
    GlassBall,
    /// One pixel accumulating 10⁶ samples.
    MillionSamples,
}

impl Case {
    pub fn description(self) -> &'static str {
        match self {
            Case::TinyScale => "furnace of radius 1e-4 m (rho 0.5): L_k = rho^k E",
            Case::HugeScale => "furnace of radius 1e5 m: L_k = rho^k E",
            Case::FarFromOrigin => "furnace of radius 10 m centred at (1e5, -1e5, 1e5) m",
            Case::Grazing => {
                "plane under a light 89.9 deg from its normal, camera 89.5 deg: L1 = rho E cos / pi, L2 = 0"
            }
            Case::Slivers => {
                "furnace of 4096 x 3 slivers (aspect up to 1e3) plus zero-area triangles"
            }
            Case::CoincidentFaces => "furnace surface three times, one copy inside out",
            Case::LightOnSurface => {
                "point light on a floor (the 1/d^2 singularity), one 1 um above, an emitter crossing the floor"
            }
            Case::SharpPhong => "furnace of Phong walls, exponent 1e6 (specular 0.5)",
            Case::MirrorCorridor => "closed mirror corridor 1 x 1 x 40 m, 64 reflections",
            Case::SphereLeaks => {
                "closed sphere, rays through its vertices and edges, at 0 and 1e4 m"
            }
            Case::WhiteFurnace => "furnace of albedo 1: L0 = L1 = L2 = E, L3+ = (max - 2) E",
            Case::GlassBall => {
                "camera inside a glass ball of eta 2.4 in a black furnace: L_k = F^(k-1) (1 - F) eta^2 E"
            }
            Case::MillionSamples => "one pixel of the furnace, 1e6 samples: no drift in the sums",
        }
    }

    /// Runs the case.
    pub fn run(self, effort: Effort) -> CaseReport {
        let started = Instant::now();
        let mut report = match self {
            Case::SphereLeaks => sphere_leaks::run(effort),
            Case::MillionSamples => million_samples::run(effort),
            _ => cases::render_case(self, effort),
        };
        report.case = self;
        report.time = started.elapsed();
        report
    }
}
