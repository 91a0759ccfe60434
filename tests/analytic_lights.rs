//! Direct lighting against closed forms: a quad light over a Lambert plane
//! (Lambert's polygon formula), the same light collapsed to a point, and a
//! mirror reflecting the light.

mod common;

use common::{add_floor, estimate, polygon_irradiance};

use glam::Vec3;
use lumiere::geometry::Ray;
use lumiere::scene::{Material, Scene};
use lumiere::transport::context::RenderContext;
use lumiere::{LightMode, RenderSettings, Term, TermSet};

const ALBEDO: f32 = 0.5;
const RADIANCE: f32 = 4.0;
const HEIGHT: f32 = 1.0;
const HALF_SIDE: f32 = 0.25;

/// The light's corners, counter-clockwise seen from below (it faces −z).
fn light_corners(center: Vec3) -> [Vec3; 4] {
    let h = HALF_SIDE;
    [
        center + Vec3::new(-h, -h, 0.0),
        center + Vec3::new(-h, h, 0.0),
        center + Vec3::new(h, h, 0.0),
        center + Vec3::new(h, -h, 0.0),
    ]
}

/// A large plane z = 0 (floor material) under a square light at height HEIGHT.
fn quad_over_plane(floor: Material, light_center: Vec3) -> Scene {
    let mut scene = Scene::default();
    let floor = scene.add_material(floor);
    let light = scene.add_material(Material::emitter("light", Vec3::splat(RADIANCE)));
    add_floor(&mut scene, floor, 20.0);
    scene.add_mesh(
        "light",
        light,
        &light_corners(light_center),
        &[[0, 1, 2], [0, 2, 3]],
    );
    scene
}

/// A ray that reaches floor point (x, y, 0) from the side, below the light.
fn ray_to_floor(x: f32, y: f32) -> Ray {
    let target = Vec3::new(x, y, 0.0);
    let origin = target + Vec3::new(1.5, 0.3, 0.4);
    Ray::new(origin, (target - origin).normalize(), f32::INFINITY)
}

const POINTS: [(f32, f32); 4] = [(0.0, 0.0), (0.3, 0.1), (-0.8, 0.5), (2.0, -1.0)];

#[test]
fn quad_light_matches_lamberts_polygon_formula() {
    let center = Vec3::new(0.0, 0.0, HEIGHT);
    let scene = quad_over_plane(Material::lambert("floor", Vec3::splat(ALBEDO)), center);
    let settings = RenderSettings {
        terms: TermSet::only(Term::L1),
        ..RenderSettings::default()
    };
    let context = RenderContext::new(scene, settings);
    for (x, y) in POINTS {
        let p = Vec3::new(x, y, 0.0);
        let expected = ALBEDO as f64 / std::f64::consts::PI
            * polygon_irradiance(p, Vec3::Z, &light_corners(center), RADIANCE as f64);
        let measured = estimate(&context, ray_to_floor(x, y), Term::L1, 40_000, 11);
        common::assert_agrees(
            &format!("L1 at ({x}, {y})"),
            measured,
            expected,
            4.0,
            common::F32_ROUNDING,
        );
    }
}

#[test]
fn quad_light_as_a_point_matches_inverse_square_law() {
    let center = Vec3::new(0.0, 0.0, HEIGHT);
    let scene = quad_over_plane(Material::lambert("floor", Vec3::splat(ALBEDO)), center);
    let settings = RenderSettings {
        terms: TermSet::only(Term::L1),
        light_mode: LightMode::Point,
        ..RenderSettings::default()
    };
    let context = RenderContext::new(scene, settings);
    let area = (2.0 * HALF_SIDE as f64).powi(2);
    for (x, y) in POINTS {
        let p = Vec3::new(x, y, 0.0).as_dvec3();
        let d = center.as_dvec3() - p;
        let distance = d.length();
        let cos_surface = d.z / distance;
        // cosine lobe: I(ω) = Le · A · (n_light · ω), n_light = −z
        let intensity = RADIANCE as f64 * area * cos_surface;
        let expected =
            ALBEDO as f64 / std::f64::consts::PI * intensity * cos_surface / (distance * distance);
        let measured = estimate(&context, ray_to_floor(x, y), Term::L1, 64, 11);
        common::assert_agrees(
            &format!("point L1 at ({x}, {y})"),
            measured,
            expected,
            4.0,
            common::F32_ROUNDING,
        );
    }
}

#[test]
fn mirror_shows_the_light_times_its_reflectance() {
    let reflectance = 0.8;
    let center = Vec3::new(2.0, 0.0, HEIGHT);
    let scene = quad_over_plane(Material::mirror("mirror", Vec3::splat(reflectance)), center);
    let settings = RenderSettings {
        terms: TermSet::ALL,
        ..RenderSettings::default()
    };
    let context = RenderContext::new(scene, settings);
    // origin (−1, 0, 0.5) → mirror at the origin → reflected to (2, 0, 1), the light's centre
    let origin = Vec3::new(-1.0, 0.0, 0.5);
    let ray = Ray::new(origin, (-origin).normalize(), f32::INFINITY);
    let (l1, _) = estimate(&context, ray, Term::L1, 256, 11);
    let (l0, _) = estimate(&context, ray, Term::L0, 16, 11);
    let (l2, _) = estimate(&context, ray, Term::L2, 16, 11);
    let expected = (reflectance * RADIANCE) as f64;
    assert!(
        (l1 - expected).abs() < common::F32_ROUNDING * expected,
        "L1 {l1}, expected {expected}"
    );
    assert_eq!((l0, l2), (0.0, 0.0));
}

/// A plane lit by one punctual light and nothing else.
fn plane_with_light(light: lumiere::scene::PunctualLight) -> Scene {
    let mut scene = Scene::default();
    let floor = scene.add_material(Material::lambert("floor", Vec3::splat(ALBEDO)));
    add_floor(&mut scene, floor, 20.0);
    scene.lights.push(light);
    scene
}

#[test]
fn spot_light_lights_its_cone_only() {
    use lumiere::scene::{PunctualKind, PunctualLight};
    let intensity = 5.0;
    let scene = plane_with_light(PunctualLight {
        name: "spot".into(),
        kind: PunctualKind::Spot {
            inner_cone_angle: 0.3,
            outer_cone_angle: 0.5,
        },
        position: Vec3::new(0.0, 0.0, 2.0),
        direction: -Vec3::Z,
        intensity: Vec3::splat(intensity),
    });
    let settings = RenderSettings {
        terms: TermSet::only(Term::L1),
        ..RenderSettings::default()
    };
    let context = RenderContext::new(scene, settings);
    let rho_over_pi = ALBEDO as f64 / std::f64::consts::PI;
    // inside the inner cone (tan 0.3 · 2 ≈ 0.62): the full intensity
    let x: f64 = 0.4;
    let d2 = 4.0 + x * x;
    let cos = 2.0 / d2.sqrt();
    let expected = rho_over_pi * intensity as f64 * cos / d2;
    let (inside, _) = estimate(&context, ray_to_floor(x as f32, 0.0), Term::L1, 4, 11);
    assert!(
        (inside - expected).abs() < common::F32_ROUNDING * expected,
        "inside the cone: {inside}, expected {expected}"
    );
    // outside the outer cone (tan 0.5 · 2 ≈ 1.09): nothing
    let (outside, _) = estimate(&context, ray_to_floor(1.5, 0.0), Term::L1, 4, 11);
    assert_eq!(outside, 0.0);
}

#[test]
fn directional_light_gives_e_cos_theta() {
    use lumiere::scene::{PunctualKind, PunctualLight};
    let irradiance = 2.0f32;
    let direction = Vec3::new(1.0, 0.0, -1.0).normalize(); // 45° incidence
    let scene = plane_with_light(PunctualLight {
        name: "sun".into(),
        kind: PunctualKind::Directional,
        position: Vec3::ZERO,
        direction,
        intensity: Vec3::splat(irradiance),
    });
    let settings = RenderSettings {
        terms: TermSet::only(Term::L1),
        ..RenderSettings::default()
    };
    let context = RenderContext::new(scene, settings);
    let expected =
        (ALBEDO / std::f32::consts::PI * irradiance * std::f32::consts::FRAC_1_SQRT_2) as f64;
    let (measured, _) = estimate(&context, ray_to_floor(0.0, 0.0), Term::L1, 4, 11);
    assert!(
        (measured - expected).abs() < common::F32_ROUNDING * expected,
        "{measured} vs {expected}"
    );
}

/// A light whose emission is textured reads the texture at each sampled
/// point: sampling points on the light (area) and sampling directions
/// (hemisphere, which shades what the ray hits) both agree with the
/// irradiance of the textured light, integrated over the light.
///
/// At floor point p under the light at height H, a light point x adds
/// (ρ/π) L T(uv(x)) cos θ_p cos θ_x / d² = (ρ/π) L T H² / d⁴ per unit area, T
/// the bilinear lookup of the texture (repeat wrap). T is a polynomial in
/// (u, v) between the lines through the texel centres, so Gauss–Legendre on
/// cells cut along them converges fast; the difference between two cell
/// sizes bounds the coarser rule's error and is added to the tolerance.
#[test]
fn a_textured_emitter_is_read_where_the_light_is_sampled() {
    use glam::Vec2;
    use lumiere::course::LightSampling;
    use lumiere::scene::{Texture, TextureRef};

    let center = Vec3::new(0.0, 0.0, HEIGHT);
    let mut scene = quad_over_plane(Material::lambert("floor", Vec3::splat(ALBEDO)), center);
    // 2×2 texels of very different brightness, across the light's UVs
    let texels = [0.05f32, 1.0, 0.4, 0.1];
    let texture = scene.textures.len() as u32;
    scene.textures.push(Texture {
        texels: texels.map(Vec3::splat).to_vec(),
        width: 2,
        height: 2,
        ..Texture::constant(Vec3::ONE)
    });
    let light = scene.objects[1].material as usize;
    scene.materials[light].emission_texture = Some(TextureRef { texture, uv_set: 0 });
    scene.uv0 = vec![Vec2::ZERO; scene.positions.len()];
    let light_vertices = scene.positions.len() - 4;
    // uv = ((x + h)/2h, (y + h)/2h) on the light's corners, so everywhere on it
    for (i, uv) in [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]
        .iter()
        .enumerate()
    {
        scene.uv0[light_vertices + i] = Vec2::from(*uv);
    }
    let estimate_with = |light_sampling| {
        let settings = RenderSettings {
            terms: TermSet::only(Term::L1),
            light_sampling,
            ..RenderSettings::default()
        };
        let context = RenderContext::new(scene.clone(), settings);
        estimate(&context, ray_to_floor(0.1, 0.05), Term::L1, 200_000, 5)
    };

    let p = Vec3::new(0.1, 0.05, 0.0).as_dvec3();
    let h = HALF_SIDE as f64;
    let integrand = |u: f64, v: f64| {
        let x = glam::DVec3::new(-h + 2.0 * h * u, -h + 2.0 * h * v, HEIGHT as f64);
        let d2 = (x - p).length_squared();
        bilinear_repeat(&texels, 2, u, v) * (HEIGHT as f64).powi(2) / (d2 * d2)
    };
    // (u, v) ↦ x has Jacobian (2h)²
    let irradiance = |subdivisions| {
        RADIANCE as f64 * (2.0 * h).powi(2) * gauss_legendre_2d(integrand, subdivisions)
    };
    let (coarse, fine) = (irradiance(2), irradiance(4));
    let expected = ALBEDO as f64 / std::f64::consts::PI * fine;
    let quadrature_error = ALBEDO as f64 / std::f64::consts::PI * (fine - coarse).abs();
    let untextured = ALBEDO as f64 / std::f64::consts::PI
        * polygon_irradiance(
            p.as_vec3(),
            Vec3::Z,
            &light_corners(center),
            RADIANCE as f64,
        );
    for light_sampling in [LightSampling::Area, LightSampling::Hemisphere] {
        let measured = estimate_with(light_sampling);
        let what = format!("L1 under the textured light, {light_sampling}");
        common::assert_agrees(&what, measured, expected, 4.5, quadrature_error / expected);
        // and not the light without its texture
        let z = (untextured - measured.0) / measured.1;
        assert!(
            z > 4.5,
            "{what}: {measured:?}, {untextured} untextured (z = {z:.1})"
        );
    }
}

/// The bilinear lookup of a `width`-texel-wide square texture of `texels`
/// (row-major, v down) with repeat wrap: texel (i, j) centred at
/// ((i + ½)/w, (j + ½)/w).
fn bilinear_repeat(texels: &[f32], width: usize, u: f64, v: f64) -> f64 {
    let (x, y) = (u * width as f64 - 0.5, v * width as f64 - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let texel = |i: f64, j: f64| {
        let (i, j) = (i.rem_euclid(width as f64), j.rem_euclid(width as f64));
        texels[j as usize * width + i as usize] as f64
    };
    let top = texel(x0, y0) * (1.0 - fx) + texel(x0 + 1.0, y0) * fx;
    let bottom = texel(x0, y0 + 1.0) * (1.0 - fx) + texel(x0 + 1.0, y0 + 1.0) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// ∫∫ f over [0, 1]², by 4-point Gauss–Legendre on each cell of the grid
/// cut at 1/4 and 3/4 (the texel centres of a 2×2 texture, where the
/// bilinear lookup has kinks), each cell split into `subdivisions`².
fn gauss_legendre_2d(f: impl Fn(f64, f64) -> f64, subdivisions: u32) -> f64 {
    const NODES: [(f64, f64); 4] = [
        (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
        (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    ];
    let mut cuts = Vec::new();
    for [a, b] in [[0.0, 0.25], [0.25, 0.75], [0.75, 1.0]] {
        for k in 0..subdivisions {
            let step = (b - a) / subdivisions as f64;
            cuts.push((a + k as f64 * step, a + (k + 1) as f64 * step));
        }
    }
    let mut sum = 0.0;
    for &(u0, u1) in &cuts {
        for &(v0, v1) in &cuts {
            let (hu, hv) = ((u1 - u0) / 2.0, (v1 - v0) / 2.0);
            for (xu, wu) in NODES {
                for (xv, wv) in NODES {
                    let (u, v) = (u0 + hu * (1.0 + xu), v0 + hv * (1.0 + xv));
                    sum += wu * wv * hu * hv * f(u, v);
                }
            }
        }
    }
    sum
}
