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
//!   where tol is the case's stated systematic tolerance (0 unless the closed
//!   form is approximate: a tessellated sphere, f32 positions 10⁵ m out); must
//!   stay within the noise (z < [`Z_LIMIT`]) or, for noiseless terms, within
//!   [`NOISELESS_TOLERANCE`];
//! * **time**.
//!
//! Most closed forms are the furnace's: inside a closed surface of uniform
//! emission E whose BRDF reflects a fraction ρ of the light at every
//! incidence, every point sees L_k = ρᵏ E after k reflections, whatever the
//! shape, its size or its place — so scale, offset, slivers, coincident faces
//! and mirrors must all give it back. With at most `max_bounces` reflections,
//! L3+ = Σ_{k=3}^{max} ρᵏ E.

use std::time::{Duration, Instant};

use glam::{Affine3A, Vec3};

use crate::geometry::Ray;
use crate::geometry::accel::Accel;
use crate::render::color::luminance;
use crate::render::context::RenderContext;
use crate::render::film::Film;
use crate::render::settings::Choice;
use crate::render::settings::{BrdfOverride, LightMode, RenderSettings, Term, TermSet};
use crate::render::{PassBuffer, render_pass};
use crate::scene::builtin::uv_sphere;
use crate::scene::{Camera, Material, Projection, PunctualKind, PunctualLight, Scene};
use crate::transport::counts::RayCounts;

/// Largest |z| of a noisy term's mean against its exact value.
pub const Z_LIMIT: f64 = 5.0;

/// Largest relative error of a term with no noise (every sample equal).
pub const NOISELESS_TOLERANCE: f64 = 1e-4;

/// How much work each case does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effort {
    /// Small films and ray counts: the test suite's size (seconds).
    Quick,
    /// The figures of `lumiere stress`: 10⁶ rays into the sphere, 10⁶ samples on one pixel.
    Full,
}

/// The cases of the suite.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
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
    /// One pixel accumulating 10⁶ samples.
    MillionSamples,
}

impl Case {
    pub const ALL: [Case; 12] = [
        Case::TinyScale,
        Case::HugeScale,
        Case::FarFromOrigin,
        Case::Grazing,
        Case::Slivers,
        Case::CoincidentFaces,
        Case::LightOnSurface,
        Case::SharpPhong,
        Case::MirrorCorridor,
        Case::SphereLeaks,
        Case::WhiteFurnace,
        Case::MillionSamples,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Case::TinyScale => "tiny-scale",
            Case::HugeScale => "huge-scale",
            Case::FarFromOrigin => "far-from-origin",
            Case::Grazing => "grazing",
            Case::Slivers => "slivers",
            Case::CoincidentFaces => "coincident-faces",
            Case::LightOnSurface => "light-on-surface",
            Case::SharpPhong => "sharp-phong",
            Case::MirrorCorridor => "mirror-corridor",
            Case::SphereLeaks => "sphere-leaks",
            Case::WhiteFurnace => "white-furnace",
            Case::MillionSamples => "million-samples",
        }
    }

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
            Case::MillionSamples => "one pixel of the furnace, 1e6 samples: no drift in the sums",
        }
    }

    /// Runs the case.
    pub fn run(self, effort: Effort) -> CaseReport {
        let started = Instant::now();
        let mut report = match self {
            Case::SphereLeaks => sphere_leaks(effort),
            Case::MillionSamples => million_samples(effort),
            _ => render_case(self, effort),
        };
        report.case = self;
        report.time = started.elapsed();
        report
    }
}

impl std::fmt::Display for Case {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Case {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Case::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Case::ALL.iter().map(|c| c.name()).collect();
                format!("unknown case '{s}' (cases: {})", names.join(", "))
            })
    }
}

/// What one case measured.
#[derive(Clone, Debug)]
pub struct CaseReport {
    pub case: Case,
    /// Renders (light modes × settings) or ray batches.
    pub variants: u32,
    /// Samples rendered, or rays traced for the sphere case.
    pub samples: u64,
    pub invalid_samples: u64,
    pub leaked_rays: u64,
    /// Largest relative error of a term with a known value, if any.
    pub energy_error: Option<f64>,
    /// Largest |z| among the noisy terms with a known value, counting only
    /// the deviation beyond the case's systematic tolerance.
    pub worst_z: Option<f64>,
    pub time: Duration,
    /// What went wrong, empty if the case passed.
    pub failures: Vec<String>,
}

impl CaseReport {
    fn new(case: Case) -> Self {
        Self {
            case,
            variants: 0,
            samples: 0,
            invalid_samples: 0,
            leaked_rays: 0,
            energy_error: None,
            worst_z: None,
            time: Duration::ZERO,
            failures: Vec::new(),
        }
    }

    pub fn passed(&self) -> bool {
        self.failures.is_empty()
    }

    /// Files the counts of one render, failing on invalid samples and, in a
    /// closed scene, on leaks.
    fn add_counts(&mut self, counts: &RayCounts, closed: bool, variant: &str) {
        self.variants += 1;
        self.invalid_samples += counts.invalid_samples;
        if counts.invalid_samples > 0 {
            self.failures.push(format!(
                "{variant}: {} invalid samples",
                counts.invalid_samples
            ));
        }
        if closed {
            self.leaked_rays += counts.escaped;
            if counts.escaped > 0 {
                self.failures
                    .push(format!("{variant}: {} rays leaked", counts.escaped));
            }
        }
    }

    /// Compares a term's measured mean with its exact value.
    fn check_energy(
        &mut self,
        variant: &str,
        term: Term,
        measured: Mean,
        exact: f64,
        tolerance: f64,
    ) {
        if exact == 0.0 {
            // nothing may reach this term: a single sample would be an error
            if measured.value != 0.0 {
                self.failures.push(format!(
                    "{variant}: {} = {:.3e}, exact 0",
                    term.label(),
                    measured.value
                ));
            }
            return;
        }
        let error = (measured.value - exact).abs() / exact.abs();
        self.energy_error = Some(self.energy_error.unwrap_or(0.0).max(error));
        if measured.standard_error > 0.0 {
            let z = (measured.value - exact) / measured.standard_error;
            // the deviation beyond the case's systematic tolerance, in standard errors
            let excess = ((measured.value - exact).abs() - tolerance * exact.abs()).max(0.0)
                / measured.standard_error;
            self.worst_z = Some(self.worst_z.unwrap_or(0.0).max(excess));
            if excess > Z_LIMIT {
                self.failures.push(format!(
                    "{variant}: {} = {:.6} ± {:.2e}, exact {exact:.6} (z = {z:.1})",
                    term.label(),
                    measured.value,
                    measured.standard_error
                ));
            }
        } else if error > NOISELESS_TOLERANCE {
            self.failures.push(format!(
                "{variant}: {} = {:.6}, exact {exact:.6} (no noise; error {error:.1e})",
                term.label(),
                measured.value
            ));
        }
    }
}

/// A term's image mean and its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mean {
    pub value: f64,
    pub standard_error: f64,
}

/// The mean luminance of `term` over the pixels of `film` where `keep` holds,
/// and its standard error (pixels are independent; one pixel: its own error).
pub fn term_mean(film: &Film, term: Term, keep: impl Fn(usize) -> bool) -> Mean {
    let Some(buffer) = film.term(term) else {
        return Mean {
            value: 0.0,
            standard_error: 0.0,
        };
    };
    let pixels: Vec<usize> = (0..film.pixel_count()).filter(|&i| keep(i)).collect();
    if pixels.len() == 1 {
        return Mean {
            value: buffer.luminance[pixels[0]].mean,
            standard_error: buffer.standard_error(pixels[0]),
        };
    }
    let n = pixels.len().max(1) as f64;
    let values: Vec<f64> = pixels.iter().map(|&i| buffer.luminance[i].mean).collect();
    let mean = values.iter().sum::<f64>() / n;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    Mean {
        value: mean,
        standard_error: (variance / n).sqrt(),
    }
}

// ── scenes ─────────────────────────────────────────────────────────────

/// A camera at `position` looking along `forward` (world +Y up unless `forward` is vertical).
fn look(position: Vec3, forward: Vec3, yfov: f32) -> Camera {
    let forward = forward.normalize();
    let up_hint = if forward.y.abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    };
    let right = forward.cross(up_hint).normalize();
    let up = right.cross(forward);
    Camera {
        name: "stress".into(),
        world_from_camera: Affine3A::from_cols(
            right.into(),
            up.into(),
            (-forward).into(),
            position.into(),
        ),
        projection: Projection::Perspective { yfov },
    }
}

/// A furnace: a closed sphere of `radius` at `centre`, of `material` (its
/// emission is the furnace's E), `segments × rings`, seen from its centre.
fn furnace_scene(
    radius: f32,
    centre: Vec3,
    material: Material,
    segments: u32,
    rings: u32,
) -> Scene {
    let mut scene = Scene {
        name: "furnace".into(),
        ..Scene::default()
    };
    let material = scene.add_material(material);
    let (positions, triangles) = uv_sphere(centre, radius, segments, rings, true);
    scene.add_mesh("sphere", material, &positions, &triangles);
    scene
        .cameras
        .push(look(centre, Vec3::new(0.3, -0.2, -1.0), 1.2));
    scene
}

/// A reflecting emitter: albedo `albedo`, emission `emission` (grey).
fn glowing_wall(albedo: f32, emission: f32) -> Material {
    Material {
        emission: Vec3::splat(emission),
        ..Material::lambert("wall", Vec3::splat(albedo))
    }
}

/// L_k of a furnace of reflectance ρ and emission E, and L3+ up to `max_bounces`.
fn furnace_terms(rho: f64, emission: f64, max_bounces: u32) -> [f64; Term::COUNT] {
    let l3: f64 = (3..=max_bounces).map(|k| rho.powi(k as i32)).sum();
    [
        emission,
        rho * emission,
        rho * rho * emission,
        l3 * emission,
    ]
}

/// Adds zero-area triangles on the sphere: repeated vertices, and three
/// points of one edge (its ends and its midpoint).
fn add_zero_area_triangles(scene: &mut Scene) {
    let material = scene.triangles[0].material;
    let edges: Vec<(Vec3, Vec3)> = scene
        .triangles
        .iter()
        .step_by(7)
        .map(|t| {
            let [a, b, _] = t.vertices;
            (scene.positions[a as usize], scene.positions[b as usize])
        })
        .collect();
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for (k, (a, b)) in edges.into_iter().enumerate() {
        let base = positions.len() as u32;
        positions.extend([a, b, 0.5 * (a + b)]);
        triangles.push(if k % 2 == 0 {
            [base, base, base + 1]
        } else {
            [base, base + 2, base + 1]
        });
    }
    scene.add_mesh("zero-area", material, &positions, &triangles);
}

/// A closed box `size` (x, y, z) of `material` from the origin, seen from
/// near one end looking down +z.
fn corridor_scene(size: Vec3, material: Material) -> Scene {
    let mut scene = Scene {
        name: "corridor".into(),
        ..Scene::default()
    };
    let material = scene.add_material(material);
    let corners: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 != 0 { size.x } else { 0.0 },
                if i & 2 != 0 { size.y } else { 0.0 },
                if i & 4 != 0 { size.z } else { 0.0 },
            )
        })
        .collect();
    // faces counter-clockwise seen from inside
    let quads = [
        [0, 2, 3, 1], // z = 0
        [4, 5, 7, 6], // z = max
        [0, 4, 6, 2], // x = 0
        [1, 3, 7, 5], // x = max
        [0, 1, 5, 4], // y = 0
        [2, 6, 7, 3], // y = max
    ];
    let triangles: Vec<[u32; 3]> = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    scene.add_mesh("corridor", material, &corners, &triangles);
    scene.cameras.push(look(
        Vec3::new(0.5 * size.x, 0.5 * size.y, 0.3),
        Vec3::new(0.05, 0.03, 1.0),
        0.9,
    ));
    scene
}

// ── rendering cases ────────────────────────────────────────────────────

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
    /// Relative bias allowed beyond the noise, where the closed form is
    /// known to be approximate (zero elsewhere).
    tolerance: f64,
}

fn every_pixel(_: &Film, _: usize) -> bool {
    true
}

/// Pixels whose L1 is not zero: those that see the lit plane.
/// Pixels wholly on the lit plane: L1 above zero and the same in every sample
/// (a pixel across the horizon mixes plane and sky).
fn lit_pixels(film: &Film, i: usize) -> bool {
    film.term(Term::L1)
        .is_some_and(|b| b.luminance[i].mean > 0.0 && b.standard_error(i) == 0.0)
}

const AUTHORED: &[LightMode] = &[LightMode::Authored];
const ALL_MODES: &[LightMode] = &[LightMode::Authored, LightMode::Point, LightMode::Area];

/// The furnace closed form for ρ = 0.5, E = 1 and 16 bounces.
fn half_furnace(_: LightMode) -> [Option<f64>; Term::COUNT] {
    furnace_terms(0.5, 1.0, 16).map(Some)
}

fn setup(case: Case, effort: Effort) -> Setup {
    let (width, height, _) = film_size(effort);
    let settings = RenderSettings {
        width,
        height,
        terms: TermSet::ALL,
        max_bounces: 16,
        ..RenderSettings::default()
    };
    let furnace = |radius: f32, centre: Vec3| Setup {
        scene: furnace_scene(radius, centre, glowing_wall(0.5, 1.0), 48, 24),
        settings: settings.clone(),
        light_modes: AUTHORED,
        closed: true,
        exact: half_furnace,
        keep: every_pixel,
        tolerance: 0.0,
    };
    match case {
        Case::TinyScale => furnace(1e-4, Vec3::ZERO),
        Case::HugeScale => furnace(1e5, Vec3::ZERO),
        // f32 positions 1e5 m out are 7.8 mm apart and rays leave the surface
        // about 2 cm out: the MIS weights of a light point, taken from the
        // hit point, and of the direction traced from the offset origin no
        // longer sum to one, which loses about 0.5 % (area sampling alone
        // and BRDF sampling alone keep the mean)
        Case::FarFromOrigin => Setup {
            tolerance: 0.015,
            ..furnace(10.0, Vec3::new(1e5, -1e5, 1e5))
        },
        Case::Slivers => {
            let mut scene = furnace_scene(1.0, Vec3::ZERO, glowing_wall(0.5, 1.0), 4096, 3);
            add_zero_area_triangles(&mut scene);
            Setup {
                scene,
                ..furnace(1.0, Vec3::ZERO)
            }
        }
        Case::CoincidentFaces => point_in_sphere(&settings, 1.0, Vec3::ZERO, 3),
        Case::SharpPhong => Setup {
            scene: furnace_scene(
                1.0,
                Vec3::ZERO,
                Material {
                    emission: Vec3::ONE,
                    ..Material::lambert("phong", Vec3::ZERO)
                },
                48,
                24,
            ),
            settings: RenderSettings {
                brdf: BrdfOverride::Phong,
                phong_exponent: 1e6,
                phong_specular: 0.5,
                ..settings.clone()
            },
            // a lobe this sharp reflects ks cos θ, and the facets of the
            // tessellated sphere tilt up to 3.75° from the rays through its
            // centre: 0.2 % per reflection, compounding in L3+
            tolerance: 0.05,
            ..furnace(1.0, Vec3::ZERO)
        },
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
            tolerance: 0.0,
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
            tolerance: 0.0,
        },
        Case::Grazing => grazing(settings),
        Case::LightOnSurface => light_on_surface(settings),
        Case::SphereLeaks | Case::MillionSamples => unreachable!("not a render case"),
    }
}

/// A point light of intensity π R² at the centre of a closed sphere of
/// radius R at `centre` and albedo ½, its surface there `copies` times (the
/// third inside out), seen from halfway to the wall: whichever copy a ray
/// meets, L1 = ρ I / (π R²) = ½ and L_k = ρ^(k−1) L1, and no copy may shadow
/// another. As a sphere light (`area` mode) the light gets a radius of
/// 10⁻³ R, which absorbs a negligible 10⁻⁶ of L2.
fn point_in_sphere(settings: &RenderSettings, radius: f32, centre: Vec3, copies: usize) -> Setup {
    let mut scene = Scene {
        name: "point in sphere".into(),
        ..Scene::default()
    };
    let wall = scene.add_material(Material {
        double_sided: true,
        ..Material::lambert("wall", Vec3::splat(0.5))
    });
    for copy in 0..copies {
        let (positions, triangles) = uv_sphere(centre, radius, 256, 128, copy != 2);
        scene.add_mesh("sphere", wall, &positions, &triangles);
    }
    scene.lights.push(PunctualLight {
        name: "centre".into(),
        kind: PunctualKind::Point,
        position: centre,
        direction: -Vec3::Z,
        intensity: Vec3::splat(std::f32::consts::PI * radius * radius),
    });
    scene.cameras.push(look(
        centre + Vec3::new(0.5 * radius, 0.0, 0.0),
        Vec3::new(1.0, 0.2, 0.1),
        1.2,
    ));
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
        // the facets lie up to 1 − cos(0.7°) inside the sphere: irradiance
        // I cos θ / d² is up to 1.5e-4 above I / R² there
        tolerance: 3e-4,
    }
}

/// The plane y = 0 (albedo 0.5), a directional light 89.9° from its normal
/// (irradiance E⊥ = 1000 W/m²), the camera 89.5° from it.
fn grazing(settings: RenderSettings) -> Setup {
    let mut scene = Scene {
        name: "grazing".into(),
        ..Scene::default()
    };
    let material = scene.add_material(Material::lambert("plane", Vec3::splat(0.5)));
    let size = 1e3;
    let corners = [
        Vec3::new(-size, 0.0, -size),
        Vec3::new(size, 0.0, -size),
        Vec3::new(size, 0.0, size),
        Vec3::new(-size, 0.0, size),
    ];
    scene.add_mesh("plane", material, &corners, &[[0, 2, 1], [0, 3, 2]]);
    let light_angle = 89.9f32.to_radians();
    scene.lights.push(PunctualLight {
        name: "sun".into(),
        kind: PunctualKind::Directional,
        position: Vec3::ZERO,
        direction: -Vec3::new(light_angle.sin(), light_angle.cos(), 0.0),
        intensity: Vec3::splat(1000.0),
    });
    let view_angle = 89.5f32.to_radians();
    scene.cameras.push(look(
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, -view_angle.cos(), -view_angle.sin()),
        0.02,
    ));
    Setup {
        scene,
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
        tolerance: 0.0,
    }
}

/// A floor; a point light on it (cos θ = 0 at every floor point: L1 = 0),
/// another 1 µm above, an emitting quad crossing the floor.
fn light_on_surface(settings: RenderSettings) -> Setup {
    let mut scene = Scene {
        name: "light on surface".into(),
        ..Scene::default()
    };
    let floor = scene.add_material(Material::lambert("floor", Vec3::splat(0.5)));
    let corners = [
        Vec3::new(-2.0, 0.0, -2.0),
        Vec3::new(2.0, 0.0, -2.0),
        Vec3::new(2.0, 0.0, 2.0),
        Vec3::new(-2.0, 0.0, 2.0),
    ];
    scene.add_mesh("floor", floor, &corners, &[[0, 2, 1], [0, 3, 2]]);
    let emitter = scene.add_material(Material {
        double_sided: true,
        ..Material::emitter("through the floor", Vec3::splat(5.0))
    });
    let quad = [
        Vec3::new(0.5, -0.5, -0.5),
        Vec3::new(0.5, -0.5, 0.5),
        Vec3::new(0.5, 0.5, 0.5),
        Vec3::new(0.5, 0.5, -0.5),
    ];
    scene.add_mesh("emitter", emitter, &quad, &[[0, 1, 2], [0, 2, 3]]);
    for (name, height) in [("on the floor", 0.0), ("1 um above", 1e-6)] {
        scene.lights.push(PunctualLight {
            name: name.into(),
            kind: PunctualKind::Point,
            position: Vec3::new(-0.5, height, 0.0),
            direction: -Vec3::Z,
            intensity: Vec3::splat(10.0),
        });
    }
    scene
        .cameras
        .push(look(Vec3::new(0.0, 3.0, 0.01), -Vec3::Y, 1.0));
    Setup {
        scene,
        settings,
        light_modes: ALL_MODES,
        closed: false,
        exact: |_| [None; Term::COUNT],
        keep: every_pixel,
        tolerance: 0.0,
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
    let (width, height, _) = film_size(effort);
    let settings = RenderSettings {
        width,
        height,
        terms: TermSet::ALL,
        max_bounces: 16,
        ..RenderSettings::default()
    };
    let point = |radius: f32, centre: Vec3| point_in_sphere(&settings, radius, centre, 1);
    let mut list = vec![setup(case, effort)];
    match case {
        Case::TinyScale => list.push(point(1e-4, Vec3::ZERO)),
        Case::HugeScale => list.push(point(1e5, Vec3::ZERO)),
        // 1/d² from f32 positions 1e5 m out: 10⁻⁴ low
        Case::FarFromOrigin => list.push(Setup {
            tolerance: 1e-3,
            ..point(10.0, Vec3::new(1e5, -1e5, 1e5))
        }),
        _ => {}
    }
    list
}

fn render_case(case: Case, effort: Effort) -> CaseReport {
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
                report.check_energy(&variant, term, measured, exact, setup.tolerance);
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

// ── the sphere, traced from inside ─────────────────────────────────────

/// Rays from points near the centre of a closed tessellated sphere towards
/// its vertices, the midpoints of its edges and random points: all must hit.
fn sphere_leaks(effort: Effort) -> CaseReport {
    let rays_per_centre: u64 = match effort {
        Effort::Quick => 50_000,
        Effort::Full => 1_000_000,
    };
    let mut report = CaseReport::new(Case::SphereLeaks);
    for centre in [Vec3::ZERO, Vec3::splat(1e4)] {
        let mut scene = Scene::default();
        let material = scene.add_material(Material::lambert("sphere", Vec3::splat(0.5)));
        let (positions, triangles) = uv_sphere(centre, 1.0, 64, 32, true);
        scene.add_mesh("sphere", material, &positions, &triangles);
        let accel = Accel::build(&scene, |_| true, Vec::new());
        let mut targets: Vec<Vec3> = positions.clone();
        for t in &triangles {
            for e in 0..3 {
                let (a, b) = (positions[t[e] as usize], positions[t[(e + 1) % 3] as usize]);
                targets.push(0.5 * (a + b));
            }
        }
        let mut rng = SplitMix(centre.x.to_bits() as u64 ^ 0x5eed);
        let mut leaks = 0u64;
        for k in 0..rays_per_centre {
            // half the rays from the centre itself, half from points near it
            let origin = if k % 2 == 0 {
                centre
            } else {
                centre + 0.1 * Vec3::new(rng.signed(), rng.signed(), rng.signed())
            };
            let target = if k % 3 == 2 {
                centre + Vec3::new(rng.signed(), rng.signed(), rng.signed())
            } else {
                targets[(rng.next() % targets.len() as u64) as usize]
            };
            let direction = (target - origin).normalize_or_zero();
            if direction == Vec3::ZERO {
                continue;
            }
            let ray = Ray::new(origin, direction, f32::INFINITY);
            if accel.closest_hit(&ray).is_none() {
                leaks += 1;
            }
        }
        report.variants += 1;
        report.samples += rays_per_centre;
        report.leaked_rays += leaks;
        if leaks > 0 {
            report.failures.push(format!(
                "centre {centre}: {leaks} of {rays_per_centre} rays escaped"
            ));
        }
    }
    report
}

/// A small deterministic generator for the sphere's rays.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [−1, 1).
    fn signed(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 23) as f32 - 1.0
    }
}

// ── one pixel, many samples ────────────────────────────────────────────

/// One pixel of the furnace (ρ = 0.5, E = 1) for 10⁶ passes: L0 is exactly
/// 1 in every sample, so its mean must be exactly 1 (a drifting sum would
/// not be); L1 and L2 must agree with ρE and ρ²E within their noise.
fn million_samples(effort: Effort) -> CaseReport {
    let passes: u32 = match effort {
        Effort::Quick => 100_000,
        Effort::Full => 1_000_000,
    };
    let mut report = CaseReport::new(Case::MillionSamples);
    let scene = furnace_scene(1.0, Vec3::ZERO, glowing_wall(0.5, 1.0), 48, 24);
    let settings = RenderSettings {
        width: 1,
        height: 1,
        terms: TermSet::COURSE,
        ..RenderSettings::default()
    };
    let context = RenderContext::new(scene, settings);
    let mut film = Film::new(1, 1);
    let mut counts = RayCounts::default();
    let stream_settings = &context.settings;
    let mut radiance = [[Vec3::ZERO; Term::COUNT]];
    for pass in 0..passes {
        // one pixel: no thread pool, one sample at a time
        let stream = crate::render::sample_stream(stream_settings, 0, pass);
        radiance[0] = context.sample_pixel(0, 0, &stream, &mut counts);
        film.add_pass(stream_settings.terms, pass, &radiance);
    }
    report.samples = passes as u64;
    report.add_counts(&counts, true, "1 pixel");
    let exact = furnace_terms(0.5, 1.0, 16);
    for term in [Term::L0, Term::L1, Term::L2] {
        let measured = term_mean(&film, term, |_| true);
        report.check_energy("1 pixel", term, measured, exact[term.index()], 0.0);
    }
    // L0 is the same in every sample: its sum must not drift by a single bit
    let l0 = film.term(Term::L0).map(|b| b.mean(0));
    let expected = luminance(Vec3::ONE) as f64;
    if l0.is_none_or(|m| (luminance(m.as_vec3()) as f64 - expected).abs() > 0.0) {
        report
            .failures
            .push(format!("L0 drifted: {l0:?} after {passes} samples"));
    }
    report
}

/// The table `lumiere stress` prints.
pub fn table(reports: &[CaseReport]) -> String {
    let mut out = format!(
        "{:<18} {:>8} {:>10} {:>8} {:>7} {:>12} {:>7} {:>8}  {}\n",
        "case", "variants", "samples", "invalid", "leaked", "energy err", "|z|", "time", "result"
    );
    for r in reports {
        let energy = r
            .energy_error
            .map_or("—".to_string(), |e| format!("{e:.2e}"));
        let z = r.worst_z.map_or("—".to_string(), |z| format!("{z:.2}"));
        out += &format!(
            "{:<18} {:>8} {:>10} {:>8} {:>7} {:>12} {:>7} {:>7.2}s  {}\n",
            r.case.name(),
            r.variants,
            r.samples,
            r.invalid_samples,
            r.leaked_rays,
            energy,
            z,
            r.time.as_secs_f64(),
            if r.passed() { "ok" } else { "FAILED" }
        );
        for failure in &r.failures {
            out += &format!("    {failure}\n");
        }
    }
    out
}
