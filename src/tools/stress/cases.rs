//! The render cases: for each, the scenes it renders, their settings and
//! light modes, whether they are closed, the exact image mean of each term
//! (mostly the furnace's L_k = ρᵏ E) and the systematic tolerance allowed
//! beyond the noise; then the renders, and the checks filed in a
//! [`CaseReport`].

use glam::Vec3;

use super::scenes::{
    add_zero_area_triangles, corridor_scene, furnace_scene, glowing_wall, grazing_scene,
    light_on_surface_scene, point_in_sphere_scene,
};
use super::{Case, CaseReport, Effort, term_mean};
use crate::course::Choice;
use crate::course::{BrdfOverride, LightMode, RenderSettings, Term, TermSet};
use crate::render::film::Film;
use crate::render::{PassBuffer, render_pass};
use crate::scene::{Material, Scene};
use crate::transport::context::RenderContext;
use crate::transport::counts::RayCounts;

/// Film size and passes for a render case.
fn film_size(effort: Effort) -> (u32, u32, u32) {
    match effort {
        Effort::Quick => (16, 12, 8),
        Effort::Full => (64, 48, 64),
    }
}

/// Renders `scene` with `settings` for `passes`.
fn render_scene(scene: &Scene, settings: &RenderSettings, passes: u32) -> (Film, RayCounts) {
    let context = RenderContext::new(scene.clone(), settings.clone());
    let mut film = Film::new(settings.width, settings.height);
    let mut buffer = PassBuffer::default();
    let mut counts = RayCounts::default();
    for pass in 0..passes {
        counts.add(&render_pass(&context, &mut film, pass, &mut buffer));
    }
    (film, counts)
}

/// One scene and what to check in it.
struct Setup {
    scene: Scene,
    settings: RenderSettings,
    light_modes: &'static [LightMode],
    closed: bool,
    /// Exact image mean of each term over the pixels kept, per light mode.
    exact: fn(LightMode) -> [Option<f64>; Term::COUNT],
    /// Which pixels the means are over (all, or those seeing a surface).
    keep: fn(&Film, usize) -> bool,
    /// Relative bias allowed beyond the noise per term, where the closed
    /// form is known to be approximate (zero elsewhere).
    tolerance: [f64; Term::COUNT],
}

fn every_pixel(_: &Film, _: usize) -> bool {
    true
}

/// Pixels wholly on the lit plane: L1 above zero and the same in every sample
/// (a pixel across the horizon mixes plane and sky).
fn lit_pixels(film: &Film, i: usize) -> bool {
    film.term(Term::L1)
        .is_some_and(|b| b.luminance[i].mean > 0.0 && b.standard_error(i) == 0.0)
}

const AUTHORED: &[LightMode] = &[LightMode::Authored];
const ALL_MODES: &[LightMode] = &[LightMode::Authored, LightMode::Point, LightMode::Area];

/// L_k of a furnace of reflectance ρ and emission E, and L3+ up to `max_bounces`.
pub(super) fn furnace_terms(rho: f64, emission: f64, max_bounces: u32) -> [f64; Term::COUNT] {
    let l3: f64 = (3..=max_bounces).map(|k| rho.powi(k as i32)).sum();
    [
        emission,
        rho * emission,
        rho * rho * emission,
        l3 * emission,
    ]
}

/// The furnace closed form for ρ = 0.5, E = 1 and 16 bounces.
fn half_furnace(_: LightMode) -> [Option<f64>; Term::COUNT] {
    furnace_terms(0.5, 1.0, 16).map(Some)
}

/// The reflections every render case allows (unless it says otherwise).
const CASE_BOUNCES: u32 = 16;

/// The settings every render case starts from: all terms, 16 bounces.
fn case_settings(effort: Effort) -> RenderSettings {
    let (width, height, _) = film_size(effort);
    RenderSettings {
        width,
        height,
        terms: TermSet::ALL,
        max_bounces: CASE_BOUNCES,
        ..RenderSettings::default()
    }
}

fn setup(case: Case, effort: Effort) -> Setup {
    let settings = case_settings(effort);
    let furnace = |radius: f32, centre: Vec3| Setup {
        scene: furnace_scene(radius, centre, glowing_wall(0.5, 1.0), 48, 24),
        settings: settings.clone(),
        light_modes: AUTHORED,
        closed: true,
        exact: half_furnace,
        keep: every_pixel,
        tolerance: [0.0; Term::COUNT],
    };
    match case {
        Case::TinyScale => furnace(1e-4, Vec3::ZERO),
        Case::HugeScale => furnace(1e5, Vec3::ZERO),
        // f32 positions 10⁵ m out are u = 7.8 mm apart, so the density of a
        // light point d away is off by up to about u/d, and the MIS weights
        // of one light point taken from its two strategies (a light sample
        // from the hit point, a direction traced from the offset origin) no
        // longer sum to one. Over the cosine-weighted directions of a
        // sphere's wall, where d = 2R cos θ, u/d averages u/R: up to u/R per
        // weighted reflection, max_bounces of them in L3+. (Area sampling
        // alone and BRDF sampling alone keep the mean.)
        Case::FarFromOrigin => {
            let centre = Vec3::new(1e5, -1e5, 1e5);
            let radius = 10.0;
            let spacing =
                (centre.abs().max_element().next_up() - centre.abs().max_element()) as f64;
            Setup {
                tolerance: [settings.max_bounces as f64 * spacing / radius as f64; Term::COUNT],
                ..furnace(radius, centre)
            }
        }
        Case::Slivers => {
            let mut scene = furnace_scene(1.0, Vec3::ZERO, glowing_wall(0.5, 1.0), 4096, 3);
            add_zero_area_triangles(&mut scene);
            Setup {
                scene,
                ..furnace(1.0, Vec3::ZERO)
            }
        }
        Case::CoincidentFaces => point_in_sphere(&settings, 1.0, Vec3::ZERO, 3),
        Case::SharpPhong => {
            let scene = furnace_scene(
                1.0,
                Vec3::ZERO,
                Material {
                    emission: Vec3::ONE,
                    ..Material::lambert("phong", Vec3::ZERO)
                },
                48,
                24,
            );
            let tolerance = sharp_lobe_tolerance(&scene, Vec3::ZERO, 0.5, settings.max_bounces);
            Setup {
                scene,
                settings: RenderSettings {
                    brdf: BrdfOverride::Phong,
                    phong_exponent: 1e6,
                    phong_specular: 0.5,
                    ..settings.clone()
                },
                tolerance,
                ..furnace(1.0, Vec3::ZERO)
            }
        }
        Case::WhiteFurnace => Setup {
            scene: furnace_scene(1.0, Vec3::ZERO, glowing_wall(1.0, 1.0), 48, 24),
            settings: RenderSettings {
                max_bounces: 8,
                ..settings.clone()
            },
            light_modes: AUTHORED,
            closed: true,
            exact: |_| furnace_terms(1.0, 1.0, 8).map(Some),
            keep: every_pixel,
            tolerance: [0.0; Term::COUNT],
        },
        Case::MirrorCorridor => Setup {
            scene: corridor_scene(
                Vec3::new(1.0, 1.0, 40.0),
                Material {
                    emission: Vec3::ONE,
                    double_sided: true,
                    ..Material::mirror("mirror", Vec3::splat(0.9))
                },
            ),
            settings: RenderSettings {
                max_bounces: 64,
                ..settings.clone()
            },
            light_modes: AUTHORED,
            closed: true,
            exact: |_| furnace_terms(0.9, 1.0, 64).map(Some),
            keep: every_pixel,
            tolerance: [0.0; Term::COUNT],
        },
        Case::GlassBall => glass_ball(settings),
        Case::Grazing => grazing(settings),
        Case::LightOnSurface => light_on_surface(settings),
        Case::SphereLeaks | Case::MillionSamples => unreachable!("not a render case"),
    }
}

/// The largest angle between a facet's normal and the direction from
/// `centre` to one of its corners.
fn facet_tilt(scene: &Scene, centre: Vec3) -> f64 {
    scene
        .triangles
        .iter()
        .flat_map(|t| {
            let [a, b, c] = t
                .vertices
                .map(|v| (scene.positions[v as usize] - centre).as_dvec3());
            let normal = (b - a).cross(c - a).normalize();
            [a, b, c].map(|v| normal.dot(v.normalize()).abs().clamp(0.0, 1.0).acos())
        })
        .fold(0.0, f64::max)
}

/// How far below the furnace's ρᵏ a lobe this sharp (a mirror of
/// reflectance ks cos θ) can bring each term in a tessellated sphere whose
/// facets tilt up to t from the radial direction. A camera ray from the
/// centre meets its first facet at most t from the normal; each reflection
/// turns the ray by twice its angle to the facet, and the next facet tilts
/// by t again, so the k-th reflection happens at most (2k − 1) t from the
/// normal and L_k keeps at least Π_{i ≤ k} cos((2i − 1) t) of ρᵏ.
fn sharp_lobe_tolerance(
    scene: &Scene,
    centre: Vec3,
    ks: f64,
    max_bounces: u32,
) -> [f64; Term::COUNT] {
    let tilt = facet_tilt(scene, centre);
    let kept = |k: u32| -> f64 {
        (1..=k)
            .map(|i| {
                ((2 * i - 1) as f64 * tilt)
                    .min(std::f64::consts::FRAC_PI_2)
                    .cos()
            })
            .product()
    };
    let beyond_two: f64 = (3..=max_bounces).map(|k| ks.powi(k as i32)).sum();
    let beyond_two_kept: f64 = (3..=max_bounces).map(|k| ks.powi(k as i32) * kept(k)).sum();
    [
        0.0,
        1.0 - kept(1),
        1.0 - kept(2),
        1.0 - beyond_two_kept / beyond_two,
    ]
}

/// The relative error of I/R² as the irradiance a point light at `centre`
/// gives the tessellated sphere of radius `radius` around it: each facet
/// lies between its plane, at distance h, and the sphere, so I cos θ / d² =
/// I h / d³ lies within [h/R, (R/h)²] of I/R²; the larger excursion is
/// (R/h)² − 1 for the closest plane.
pub(super) fn tessellation_error(scene: &Scene, centre: Vec3, radius: f32) -> f64 {
    let closest = scene
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t
                .vertices
                .map(|v| (scene.positions[v as usize] - centre).as_dvec3());
            (b - a).cross(c - a).normalize().dot(a).abs()
        })
        .fold(f64::INFINITY, f64::min);
    (radius as f64 / closest).powi(2) - 1.0
}

/// The relative error of 1/d² when the light and the wall are f32
/// positions near `centre`, `radius` apart: each coordinate is rounded by
/// up to half its spacing u, so d moves by up to √3 u (both ends) and
/// 1/d² by 2√3 u / d.
fn position_rounding(centre: Vec3, radius: f32) -> f64 {
    let largest = centre.abs().max_element().max(radius);
    let spacing = (largest.next_up() - largest) as f64;
    2.0 * 3f64.sqrt() * spacing / radius as f64
}

/// A point light of intensity I = π R² in a sphere of radius R and albedo
/// ½, its surface there `copies` times: whichever copy a ray meets,
/// L1 = ρ I / (π R²) = ½ and L_k = ρ^(k−1) L1, and no copy may shadow
/// another. As a sphere light (`area` mode) the light gets a radius of
/// 10⁻³ R, which absorbs a negligible 10⁻⁶ of L2.
fn point_in_sphere(settings: &RenderSettings, radius: f32, centre: Vec3, copies: usize) -> Setup {
    let scene = point_in_sphere_scene(radius, centre, copies);
    // the same sphere at the origin, where f32 keeps its facets: far out,
    // rounding makes the few-millimetre triangles at its poles meaningless
    // (a negligible area), and moves the others by the rounding bound
    let at_origin = point_in_sphere_scene(radius, Vec3::ZERO, 1);
    let tolerance =
        tessellation_error(&at_origin, Vec3::ZERO, radius) + position_rounding(centre, radius);
    Setup {
        scene,
        settings: RenderSettings {
            light_radius: Some(1e-3 * radius),
            ..settings.clone()
        },
        light_modes: ALL_MODES,
        closed: true,
        exact: |_| {
            let [_, l1, l2, l3] = furnace_terms(0.5, 1.0, 16);
            [Some(0.0), Some(l1), Some(l2), Some(l3)]
        },
        keep: every_pixel,
        tolerance: [tolerance; Term::COUNT],
    }
}

/// The plane lit 89.9° from its normal: on the pixels wholly on it,
/// L1 = ρ E⊥ cos θ / π, and nothing reflects twice.
/// Index of refraction of the glass ball (diamond's): F = ((η − 1)/(η + 1))²
/// = 0.17 at normal incidence, so internal reflections go on for long.
const BALL_IOR: f64 = 2.4;

/// The camera at the centre of a clear glass ball of radius 0.5 inside a
/// black furnace of radius 1 emitting E = 1. Each camera ray leaves the
/// ball at normal incidence with probability 1 − F, its radiance η² times
/// that outside (radiance is η² denser in glass), or reflects back through
/// the centre: L0 = 0, L_k = F^(k−1) (1 − F) η² up to the last bounce. The
/// facets tilt the incidence by under 2°, which moves F by under 10⁻⁵ of
/// itself, but each internal reflection moves the ray off the centre a
/// little more: 10⁻³ of each term is allowed.
fn glass_ball(settings: RenderSettings) -> Setup {
    let mut scene = furnace_scene(1.0, Vec3::ZERO, glowing_wall(0.0, 1.0), 48, 24);
    let glass = scene.add_material(Material::glass("diamond", Vec3::ONE, BALL_IOR as f32));
    let (positions, triangles) = crate::scene::builtin::uv_sphere(Vec3::ZERO, 0.5, 96, 48, false);
    scene.add_mesh("ball", glass, &positions, &triangles);
    Setup {
        scene,
        settings,
        light_modes: AUTHORED,
        closed: true,
        exact: |_| {
            let f = ((BALL_IOR - 1.0) / (BALL_IOR + 1.0)).powi(2);
            let inside = BALL_IOR * BALL_IOR;
            // L3+ sums k = 3 … the last bounce
            let beyond: f64 = (3..=CASE_BOUNCES as i32)
                .map(|k| f.powi(k - 1) * (1.0 - f))
                .sum();
            [
                Some(0.0),
                Some((1.0 - f) * inside),
                Some(f * (1.0 - f) * inside),
                Some(beyond * inside),
            ]
        },
        keep: every_pixel,
        tolerance: [1e-3; Term::COUNT],
    }
}

fn grazing(settings: RenderSettings) -> Setup {
    Setup {
        scene: grazing_scene(),
        settings,
        light_modes: ALL_MODES,
        closed: false,
        exact: |_| {
            // the cosine the scene's f32 direction holds
            let cos = 89.9f32.to_radians().cos() as f64;
            // one plane: nothing reflects twice
            [
                Some(0.0),
                Some(0.5 * 1000.0 * cos / std::f64::consts::PI),
                Some(0.0),
                Some(0.0),
            ]
        },
        keep: lit_pixels,
        tolerance: [0.0; Term::COUNT],
    }
}

/// Lights on, just above and through a floor: no closed form, only no
/// invalid sample and a finite mean for every term.
fn light_on_surface(settings: RenderSettings) -> Setup {
    Setup {
        scene: light_on_surface_scene(),
        settings,
        light_modes: ALL_MODES,
        closed: false,
        exact: |_| [None; Term::COUNT],
        keep: every_pixel,
        tolerance: [0.0; Term::COUNT],
    }
}

/// The scene and settings a render case uses (to inspect or render it
/// elsewhere); `None` for the cases that are not renders.
pub fn case_scene(case: Case, effort: Effort) -> Option<(Scene, RenderSettings)> {
    if matches!(case, Case::SphereLeaks | Case::MillionSamples) {
        return None;
    }
    let setup = setup(case, effort);
    Some((setup.scene, setup.settings))
}

/// The scenes of a render case: the scale cases also put a point light in a
/// sphere of their size and place, for the light modes.
fn setups(case: Case, effort: Effort) -> Vec<Setup> {
    let settings = case_settings(effort);
    let point = |radius: f32, centre: Vec3| point_in_sphere(&settings, radius, centre, 1);
    let mut list = vec![setup(case, effort)];
    match case {
        Case::TinyScale => list.push(point(1e-4, Vec3::ZERO)),
        Case::HugeScale => list.push(point(1e5, Vec3::ZERO)),
        Case::FarFromOrigin => list.push(point(10.0, Vec3::new(1e5, -1e5, 1e5))),
        _ => {}
    }
    list
}

pub(super) fn render_case(case: Case, effort: Effort) -> CaseReport {
    let mut report = CaseReport::new(case);
    for setup in setups(case, effort) {
        render_setup(&setup, effort, &mut report);
    }
    report
}

/// Renders `setup` in each of its light modes, filing what it measured in `report`.
fn render_setup(setup: &Setup, effort: Effort, report: &mut CaseReport) {
    let (_, _, passes) = film_size(effort);
    for &mode in setup.light_modes {
        let settings = RenderSettings {
            light_mode: mode,
            ..setup.settings.clone()
        };
        let variant = format!("{}, {} lights", setup.scene.name, mode.label());
        let (film, counts) = render_scene(&setup.scene, &settings, passes);
        report.samples += film.pixel_count() as u64 * passes as u64;
        report.add_counts(&counts, setup.closed, &variant);
        let exact = (setup.exact)(mode);
        for term in Term::ALL {
            if let Some(exact) = exact[term.index()] {
                let measured = term_mean(&film, term, |i| (setup.keep)(&film, i));
                report.check_energy(
                    &variant,
                    term,
                    measured,
                    exact,
                    setup.tolerance[term.index()],
                );
            }
        }
        for term in Term::ALL {
            let mean = term_mean(&film, term, |_| true);
            if !mean.value.is_finite() {
                report
                    .failures
                    .push(format!("{variant}: {} mean {}", term.label(), mean.value));
            }
        }
    }
}
