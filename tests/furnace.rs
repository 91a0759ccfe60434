//! Closed-form scenes: the furnace and a point light inside a sphere.

mod common;

use common::{
    F32_ROUNDING, assert_agrees, mean_and_error, render_film, small, sphere_tessellation_error,
};
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
            F32_ROUNDING,
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
        let scene = point_in_sphere(albedo as f32, intensity as f32, radius as f32);
        let tessellation = sphere_tessellation_error(&scene, radius);
        let film = render_film(scene, &settings, 64);
        assert_agrees(
            &format!("point in sphere {term}"),
            mean_and_error(&film, term),
            value,
            4.0,
            tessellation + F32_ROUNDING,
        );
    }
}

/// The same with `--lights area`: the point light becomes a sphere of radius
/// r and radiance I/(π r²), whose irradiance at distance R is π L (r/R)² =
/// I/R², so L1 keeps its closed form. For L2, the sphere now hides the cone
/// of half-angle asin(r/R) around each wall point's normal, whose projected
/// solid angle is π (r/R)²: L2 = ρ L1 (1 − (r/R)²). The sphere itself is seen
/// in L0 with radiance I/(π r²).
#[test]
fn sphere_light_in_a_sphere_keeps_the_point_lights_power() {
    let (albedo, intensity, radius, light_radius) = (0.5f64, 3.0f64, 2.0f64, 0.3f64);
    let l1 = albedo * intensity / (std::f64::consts::PI * radius * radius);
    let hidden = (light_radius / radius).powi(2);
    for (term, value) in [(Term::L1, l1), (Term::L2, albedo * l1 * (1.0 - hidden))] {
        let mut settings = small(24, 24, TermSet::only(term));
        settings.light_mode = lumiere::LightMode::Area;
        settings.light_radius = Some(light_radius as f32);
        // the camera must not sit inside the light: beside it, looking away
        let mut scene = point_in_sphere(albedo as f32, intensity as f32, radius as f32);
        scene.cameras[0].world_from_camera = glam::Affine3A::from_rotation_translation(
            glam::Quat::from_rotation_y(std::f32::consts::PI),
            glam::Vec3::new(0.0, 0.0, 1.0),
        );
        let tessellation = sphere_tessellation_error(&scene, radius);
        let film = render_film(scene, &settings, 64);
        assert_agrees(
            &format!("sphere light {term}"),
            mean_and_error(&film, term),
            value,
            4.0,
            tessellation + F32_ROUNDING,
        );
    }
    // seen directly, the sphere has radiance I/(π r²)
    let mut scene = point_in_sphere(albedo as f32, intensity as f32, radius as f32);
    scene.cameras[0].world_from_camera =
        glam::Affine3A::from_translation(glam::Vec3::new(0.0, 0.0, 1.5));
    scene.cameras[0].projection = lumiere::scene::Projection::Perspective { yfov: 0.02 };
    let mut settings = small(4, 4, TermSet::only(Term::L0));
    settings.light_mode = lumiere::LightMode::Area;
    settings.light_radius = Some(light_radius as f32);
    let film = render_film(scene, &settings, 4);
    let expected = intensity / (std::f64::consts::PI * light_radius * light_radius);
    let (mean, _) = mean_and_error(&film, Term::L0);
    assert!(
        (mean - expected).abs() < F32_ROUNDING * expected,
        "sphere light seen with radiance {mean}, expected {expected}"
    );
}
