//! The closed sets of options of a render: light mode, BRDF override, the
//! estimators' strategies, the sampler, the integrator. Each is declared
//! through [`closed_set!`], so the command line, the viewer and saved
//! settings share one list of names.

use strum::IntoEnumIterator;

/// Declares a closed set of options: an enum with the derives every option
/// shares (copy, compare, hash, serde) and strum's names in kebab-case,
/// parsed in any case, whose parse error lists the choices
/// ([`unknown_choice`]). The first `#[default]` variant is the default.
macro_rules! closed_set {
    ($(#[$meta:meta])* pub enum $name:ident { $($variants:tt)* }) => {
        $(#[$meta])*
        #[derive(
            Clone, Copy, Debug, Default, PartialEq, Eq, Hash,
            serde::Serialize, serde::Deserialize,
            strum::EnumIter, strum::IntoStaticStr, strum::EnumString, strum::Display,
        )]
        #[strum(
            serialize_all = "kebab-case",
            ascii_case_insensitive,
            parse_err_ty = String,
            parse_err_fn = $crate::course::options::unknown_choice::<$name>
        )]
        pub enum $name { $($variants)* }
    };
}
pub(crate) use closed_set;

closed_set! {
    /// Which kind of light sources a render uses (the course's point ↔ extended swap).
    pub enum LightMode {
        /// As the scene defines them.
        #[default]
        Authored,
        /// Every area light becomes a point light at its centroid (cosine lobe, same power).
        Point,
        /// Every point or spot light becomes a sphere light of the light radius (same power).
        Area,
    }
}

closed_set! {
    /// A global replacement of every material's reflection model.
    pub enum BrdfOverride {
        /// Each material's own model (from its metallic-roughness parameters).
        #[default]
        Authored,
        Lambert,
        Phong,
        Mirror,
        /// Smooth glass of index of refraction `glass_ior`, tinted by the base colour.
        Glass,
    }
}

closed_set! {
    /// Which estimator computes the terms.
    pub enum Integrator {
        /// The lecture's estimator, written as the slides write it
        /// (`transport/lecture.rs`): one light sample and one BRDF direction per
        /// point, nothing else.
        Lecture,
        /// The fast path tracer (`transport/fast.rs`): the strategies, MIS,
        /// splitting and skipped work of the other settings.
        #[default]
        Fast,
    }
}

closed_set! {
    /// How direct lighting from extended lights is estimated at each vertex.
    pub enum LightSampling {
        /// Uniform points on the light's surface (pdf 1/A, converted to solid angle).
        Area,
        /// Uniform directions in the solid angle a triangle subtends (Arvo's
        /// spherical triangle sampling); area sampling for tiny or huge angles.
        SolidAngle,
        /// Sample the BRDF and count the directions that hit a light.
        Brdf,
        /// Uniform directions on the hemisphere that happen to see a light.
        Hemisphere,
        /// Light (area) and BRDF sampling combined by multiple importance sampling.
        #[default]
        Mis,
    }
}

closed_set! {
    /// The weighting of the two strategies of `LightSampling::Mis`.
    pub enum MisHeuristic {
        /// w = p_a / (p_a + p_b).
        Balance,
        /// w = p_a² / (p_a² + p_b²).
        #[default]
        Power,
    }
}

closed_set! {
    /// How the direction of the next reflection (L2, L3+) is drawn.
    pub enum IndirectSampling {
        /// pdf 1/2π.
        Uniform,
        /// pdf cos θ/π.
        Cosine,
        /// The BRDF's own sampling routine (pdf ∝ f cos θ where it can).
        #[default]
        Brdf,
    }
}

closed_set! {
    /// How a light is picked for a light sample.
    pub enum LightSelection {
        /// Every light with the same probability.
        Uniform,
        /// In proportion to emitted power.
        #[default]
        Power,
    }
}

closed_set! {
    /// Where the random numbers of a sample come from.
    pub enum Sampler {
        /// Independent uniform numbers (plain Monte Carlo).
        Independent,
        /// Jittered strata: each dimension pair of a block of samples covers a grid.
        Stratified,
        /// Owen-scrambled Sobol points (quasi-Monte Carlo), scrambled per pixel:
        /// the default, the fastest to a given error measured.
        #[default]
        Sobol,
    }
}

/// A closed set of options (light mode, BRDF, strategies, sampler, …):
/// strum derives the list of its values (`iter`), their names (kebab-case,
/// the same on the command line, in the viewer, the strips and the bench)
/// and the parser (any case), whose error lists the choices.
pub trait Choice: Copy + IntoEnumIterator + Into<&'static str> {
    /// The value's name.
    fn label(self) -> &'static str {
        self.into()
    }

    /// Every value, in declaration order.
    fn all() -> Vec<Self> {
        Self::iter().collect()
    }
}

impl<T: Copy + IntoEnumIterator + Into<&'static str>> Choice for T {}

/// The parse error of an unknown name `s` of the closed set `T`.
pub fn unknown_choice<T: Choice>(s: &str) -> String {
    let names: Vec<&str> = T::iter().map(T::label).collect();
    format!(
        "unknown value '{s}' (expected one of: {})",
        names.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enums_parse_their_labels() {
        for m in LightMode::all() {
            assert_eq!(m.label().parse::<LightMode>().unwrap(), m);
        }
        for b in BrdfOverride::all() {
            assert_eq!(b.label().parse::<BrdfOverride>().unwrap(), b);
        }
        assert!("points".parse::<LightMode>().is_err());
        for s in LightSampling::all() {
            assert_eq!(s.label().parse::<LightSampling>().unwrap(), s);
        }
        for s in IndirectSampling::all() {
            assert_eq!(s.label().parse::<IndirectSampling>().unwrap(), s);
        }
        for s in Sampler::all() {
            assert_eq!(s.label().parse::<Sampler>().unwrap(), s);
        }
        assert_eq!(
            "Solid-Angle".parse::<LightSampling>(),
            Ok(LightSampling::SolidAngle)
        );
        assert_eq!(
            "lights".parse::<LightMode>().unwrap_err(),
            "unknown value 'lights' (expected one of: authored, point, area)"
        );
    }
}
