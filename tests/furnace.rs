//! Closed-form scenes: the furnace and a point light inside a sphere.

mod common;

use common::{assert_agrees, mean_and_error, render_film, small};
use lumiere::scene::builtin::{furnace, point_in_sphere};
use lumiere::{Term, TermSet};

/// Inside a closed sphere emitting Le with Lambert albedo ρ, the light after
/// k reflections is ρᵏ Le, so L0 = Le, L1 = ρ Le, L2 = ρ² Le and
/// L3+ = Σ_{k≥3} ρᵏ Le = ρ³ Le / (1 − ρ).
#[test]
fn furnace_terms_match_the_geometric_series() {
    let (albedo, emission) = (0.6f64, 1.5f64);
    let expected = [
        (Term::L0, emission),
        (Term::L1, albedo * emission),
        (Term::L2, albedo.powi(2) * emission),
        (Term::L3Plus, albedo.powi(3) * emission / (1.0 - albedo)),
    ];
    for (term, value) in expected {
        let settings = small(32, 32, TermSet::only(term));
        let film = render_film(furnace(albedo as f32, emission as f32), &settings, 64);
        assert_agrees(
            &format!("furnace {term}"),
            mean_and_error(&film, term),
            value,
            4.0,
            1e-4,
        );
    }
}

/// pbrt's variant: a point light of intensity I at the centre of a diffuse
/// sphere of radius R. Irradiance I/R² everywhere, so L1 = ρ I / (π R²);
/// every wall point then radiates L1, so L2 = ρ L1.
#[test]
fn point_light_in_a_sphere() {
    let (albedo, intensity, radius) = (0.5f64, 3.0f64, 2.0f64);
    let l1 = albedo * intensity / (std::f64::consts::PI * radius * radius);
    for (term, value) in [(Term::L1, l1), (Term::L2, albedo * l1)] {
        let settings = small(24, 24, TermSet::only(term));
        let film = render_film(
            point_in_sphere(albedo as f32, intensity as f32, radius as f32),
            &settings,
            64,
        );
        // the tessellated sphere is up to 1 − cos(π/256) closer than R
        assert_agrees(
            &format!("point in sphere {term}"),
            mean_and_error(&film, term),
            value,
            4.0,
            2e-4,
        );
    }
}
