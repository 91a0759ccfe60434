//! What a render counts: the rays it traced, by kind and by term, the work
//! it skipped, and the samples the film's guard dropped.

use crate::course::Term;
use glam::Vec3;

/// Rays traced, by kind and by the lowest selected term each serves: the
/// shadow ray or gathered direction at the k-th reflection serves L_k; a ray
/// leaving the camera (k = 0) or the k-th reflection serves L_k and every
/// later term.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    pub camera: u64,
    pub shadow: u64,
    pub bounce: u64,
    /// Directions traced only to find lights (not continuing the path).
    pub gather: u64,
    pub per_term: [u64; Term::COUNT],
    /// Work the settings and the scene made unnecessary.
    pub skipped: SkippedWork,
    /// Samples with a NaN, infinite or negative term, zeroed before they reach the film.
    pub invalid_samples: u64,
    /// Camera rays, bounces and gathered directions that left the scene (in a
    /// closed scene, leaks).
    pub escaped: u64,
}

/// Work not done because nothing would come of it, counted to show what the
/// settings and the scene save.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SkippedWork {
    /// Shadow rays not traced: the light sample was behind the surface or carried nothing.
    pub shadow_rays: u64,
    /// Vertices whose direct lighting was not estimated: its term is off.
    pub direct_lighting: u64,
    /// Directions not gathered: the scene has no light a ray can hit.
    pub gathered: u64,
    /// Continuations not traced: no selected term needs another reflection.
    pub continuations: u64,
    /// Paths ended by Russian roulette.
    pub roulette: u64,
    /// Samples of a pixel's term not taken: adaptive sampling had stopped it.
    pub converged: u64,
    /// Searches of the whole scene's BVH not made: a direction traced only to
    /// find a light met no light's box or triangle (the ray itself is traced,
    /// against the lights alone).
    pub scene_searches: u64,
}

impl SkippedWork {
    /// Rays that were not traced.
    pub fn rays(&self) -> u64 {
        self.shadow_rays + self.gathered + self.continuations + self.roulette
    }

    pub fn add(&mut self, other: &SkippedWork) {
        self.shadow_rays += other.shadow_rays;
        self.direct_lighting += other.direct_lighting;
        self.gathered += other.gathered;
        self.continuations += other.continuations;
        self.roulette += other.roulette;
        self.converged += other.converged;
        self.scene_searches += other.scene_searches;
    }

    /// One line for summaries: the non-zero counts.
    pub fn describe(&self) -> String {
        let parts: Vec<String> = [
            (self.shadow_rays, "shadow rays (light behind the surface)"),
            (self.direct_lighting, "light samplings (term off)"),
            (self.gathered, "gathered directions (no light to hit)"),
            (self.continuations, "continuations (no term needs them)"),
            (self.roulette, "paths ended by Russian roulette"),
            (
                self.converged,
                "term samples of converged pixels (adaptive)",
            ),
            (
                self.scene_searches,
                "scene searches (light searches that met no light)",
            ),
        ]
        .iter()
        .filter(|(n, _)| *n > 0)
        .map(|(n, what)| format!("{n} {what}"))
        .collect();
        if parts.is_empty() {
            "nothing".into()
        } else {
            parts.join(", ")
        }
    }
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.camera + self.shadow + self.bounce + self.gather
    }

    pub fn add(&mut self, other: &RayCounts) {
        self.camera += other.camera;
        self.shadow += other.shadow;
        self.bounce += other.bounce;
        self.gather += other.gather;
        for (mine, theirs) in self.per_term.iter_mut().zip(other.per_term) {
            *mine += theirs;
        }
        self.skipped.add(&other.skipped);
        self.invalid_samples += other.invalid_samples;
        self.escaped += other.escaped;
    }
}

/// What the continuations of one pilot sample brought (`transport::pilot_sample`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContinuationSplit {
    /// The radiance of each of the two continuations, summed over the
    /// terms and unweighted (what it would bring alone, M = 1).
    pub continuations: [Vec3; 2],
    /// `RayCounts::total` once the first vertex's light samples are traced,
    /// then once the continuations are: the rays of each part, by difference
    /// with the count before the sample.
    pub first_rays: u64,
    pub continuation_rays: u64,
}
