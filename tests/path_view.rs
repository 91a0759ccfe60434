//! The path view: camera projection, and the recorded rays of a probed sample.

mod common;

use glam::{Affine3A, Vec2, Vec3};
use lumiere::analysis::path_view::{RayRole, path_lines};
use lumiere::analysis::probe::{MAX_PROBE_SAMPLES, probe_pixel};
use lumiere::course::color::luminance;
use lumiere::geometry::camera::CameraRays;
use lumiere::render::{PassBuffer, render_pass};
use lumiere::scene::{Camera, Projection, builtin};
use lumiere::transport::path_log::SegmentKind;
use lumiere::{Film, RenderContext, RenderSettings, Term, TermSet};

/// Where `project_segment` puts its near plane: this fraction of the
/// segment's deepest point.
const NEAR_FRACTION: f32 = 1e-4;

/// The test cameras, with the film sizes they are bound to.
fn test_cameras() -> Vec<(&'static str, Camera, u32, u32)> {
    let tilted = Affine3A::from_rotation_translation(
        glam::Quat::from_euler(glam::EulerRot::YXZ, 0.7, -0.3, 0.2),
        Vec3::new(3.0, -1.0, 1e3),
    );
    let camera = |projection| Camera {
        name: String::new(),
        world_from_camera: tilted,
        projection,
    };
    vec![
        ("cornell", builtin::cornell().default_camera(), 64, 48),
        (
            "perspective",
            camera(Projection::Perspective { yfov: 1.1 }),
            40,
            30,
        ),
        (
            "orthographic",
            camera(Projection::Orthographic { half_height: 2.5 }),
            40,
            30,
        ),
    ]
}

fn cameras() -> Vec<(&'static str, CameraRays)> {
    test_cameras()
        .into_iter()
        .map(|(name, camera, width, height)| (name, CameraRays::new(&camera, width, height)))
        .collect()
}

/// A camera ray's points project back to its film point up to f32 rounding
/// (ε = 2⁻²³). Going to world space and back, a point's camera-space
/// coordinates q pick up an absolute error of a few roundings of the world
/// coordinates summed in each step: |δq| ≤ 8ε(|eye| + |p|) for the eye and
/// the point p. The film takes q.x/(d·w) to pixels at W/(2w) per unit (d
/// the depth, 1 for an orthographic camera; w the half-width of the image
/// plane), and the quotient's two error terms add at most a factor
/// (1 + max(w, h)) for points on the film: |δx| ≤ W/(2w)·(1 + max(w, h))·|δq|/d.
/// Each way also rounds the film coordinate itself a few times (±8ε·W).
///
/// A perspective ray starts at the eye, which has no image: the segment is
/// clipped where the near plane, at 10⁻⁴ of the far end's depth, cuts it.
/// The clipped point is b·(1 − s) with 1 − s = 10⁻⁴ (the eye maps to the
/// origin); the product b·s rounds by ε/2 of |b|, which is 5000ε of the
/// clipped coordinates, 10⁴ε of their ratio x/z: another
/// W/(2w)·max(w, h)·10⁴ε pixels.
#[test]
fn points_of_a_camera_ray_project_to_its_pixel_point() {
    for (name, scene_camera, width, height) in test_cameras() {
        let camera = CameraRays::new(&scene_camera, width, height);
        let size = camera.film_size();
        let aspect = width as f32 / height as f32;
        let (half_height, perspective) = match scene_camera.projection {
            Projection::Perspective { yfov } => ((0.5 * yfov).tan(), true),
            Projection::Orthographic { half_height } => (half_height, false),
        };
        let half_width = half_height * aspect;
        let pixels_per_unit = size.x / (2.0 * half_width);
        let camera_from_world = scene_camera.world_from_camera.inverse();
        let eye = scene_camera.world_from_camera.translation.length();
        for k in 0..200u32 {
            // a low-discrepancy walk over the film
            let film = Vec2::new(
                (k as f32 * 0.618_034).fract() * size.x,
                (k as f32 * 0.754_877_7).fract() * size.y,
            );
            let (x, y) = (film.x as u32, film.y as u32);
            let ray = camera.generate(x, y, film - Vec2::new(x as f32, y as f32));
            for t in [0.5, 1.0, 7.5] {
                let (from, to) = camera
                    .project_segment(ray.origin, ray.at(t))
                    .expect("in front of the camera");
                let point = ray.at(t);
                let depth = if perspective {
                    -camera_from_world.transform_point3(point).z
                } else {
                    1.0
                };
                let camera_space_error = 8.0 * f32::EPSILON * (eye + point.length());
                let point_tolerance =
                    pixels_per_unit * (1.0 + half_width.max(half_height)) * camera_space_error
                        / depth
                        + 8.0 * f32::EPSILON * size.x;
                let clip_tolerance = if perspective {
                    pixels_per_unit * half_width.max(half_height) * f32::EPSILON / NEAR_FRACTION
                } else {
                    0.0
                };
                for (p, tolerance) in [
                    (from, point_tolerance + clip_tolerance),
                    (to, point_tolerance),
                ] {
                    assert!(
                        (p - film).abs().max_element() <= tolerance,
                        "{name}: {p} against {film} at t = {t} (tolerance {tolerance:.1e} px)"
                    );
                }
            }
        }
    }
}

#[test]
fn segments_are_clipped_at_the_camera() {
    for (name, camera) in cameras() {
        let ray = camera.generate(10, 7, Vec2::splat(0.5));
        let (ahead, behind) = (ray.at(2.0), ray.at(-2.0));
        // a point off to the side behind the camera: only the part in front is drawn
        let side = camera.generate(30, 20, Vec2::splat(0.5));
        let behind_side = side.at(-3.0);
        let (_, to) = camera.project_segment(behind_side, ahead).unwrap();
        let (_, alone) = camera.project_segment(ahead, ahead).unwrap();
        assert!((to - alone).length() < 1e-3, "{name}: {to} {alone}");
        assert_eq!(
            camera.project_segment(behind, behind_side),
            None,
            "{name}: wholly behind"
        );
    }
}

/// A Cornell film of `spp` passes with L0, L1, L2 and its context.
fn cornell_film(spp: u32) -> (RenderContext, Film) {
    let settings = RenderSettings {
        width: 32,
        height: 24,
        ..RenderSettings::default()
    };
    let context = RenderContext::new(builtin::cornell(), settings);
    let mut film = Film::new(32, 24);
    let mut buffer = PassBuffer::default();
    for pass in 0..spp {
        let counts = render_pass(&context, &mut film, pass, &mut buffer);
        common::assert_no_invalid_samples(&counts);
    }
    (context, film)
}

#[test]
fn a_recorded_path_is_the_probed_sample_and_starts_at_its_pixel() {
    let (context, film) = cornell_film(12);
    let terms = context.settings.terms;
    let mut shadow_rays = 0;
    for (x, y) in [(16, 10), (5, 18), (27, 6)] {
        let probe = probe_pixel(&context, &film, x, y, terms, MAX_PROBE_SAMPLES);
        assert_eq!(probe.passes, (0..12).collect::<Vec<_>>());
        for (position, &pass) in probe.passes.iter().enumerate() {
            let log = probe.record_path(&context, pass);
            let radiance = log.radiance();
            // the rays add up to the sample the film summed, bit for bit
            for term in &probe.terms {
                assert_eq!(
                    radiance[term.term.index()],
                    term.samples[position],
                    "{:?} of pass {pass} at ({x}, {y})",
                    term.term
                );
            }
            let total: f64 = probe
                .terms
                .iter()
                .map(|t| luminance(t.samples[position]) as f64)
                .sum();
            assert_eq!(probe.pass_luminance[position], total);

            let lines = path_lines(&log, &context.camera, terms);
            let pixel = |p: Vec2| {
                p.x > x as f32 - 0.01
                    && p.x < x as f32 + 1.01
                    && p.y > y as f32 - 0.01
                    && p.y < y as f32 + 1.01
            };
            assert_eq!(lines[0].role, RayRole::Camera);
            assert!(pixel(lines[0].to), "camera hit at {}", lines[0].to);
            for (line, segment) in lines[1..].iter().map(|l| (l, &log.segments[l.segment])) {
                match line.role {
                    RayRole::ShadowLit { term } | RayRole::ShadowBlocked { term }
                        if term == Term::L1 =>
                    {
                        // L1 light samples leave the first hit, seen in the pixel
                        assert!(pixel(line.from), "L1 shadow ray from {}", line.from);
                        shadow_rays += 1;
                    }
                    RayRole::ShadowLit { term } | RayRole::ShadowBlocked { term } => {
                        assert_eq!(term, Term::L2)
                    }
                    RayRole::Bounce { term, .. } => assert_eq!(term, Term::L2),
                    // L3+ is off: the second continuation only looks for a light
                    RayRole::LastBounce { term, .. } => assert_eq!(term, Term::L2),
                    RayRole::GatherLit { .. } | RayRole::GatherMissed { .. } => {
                        panic!("mis with brdf indirect sampling reuses the bounce")
                    }
                    RayRole::Camera => panic!("one camera ray"),
                }
                assert_eq!(
                    line.role.is_dashed(),
                    matches!(
                        segment.kind,
                        SegmentKind::Shadow { occluded: true, .. }
                            | SegmentKind::Gather { hit_light: false }
                    )
                );
            }
        }
        let brightest = probe.brightest().unwrap();
        let max = probe.pass_luminance.iter().cloned().fold(0.0, f64::max);
        assert_eq!(probe.pass_luminance[brightest], max);
    }
    assert!(shadow_rays >= 30, "{shadow_rays} L1 shadow rays");
}

#[test]
fn a_camera_ray_that_leaves_the_scene_is_a_point_and_nothing_else() {
    let (context, film) = cornell_film(2);
    // the top-left corner of the Cornell view looks past the box
    let probe = probe_pixel(&context, &film, 0, 0, context.settings.terms, 16);
    let log = probe.record_path(&context, 0);
    let lines = path_lines(&log, &context.camera, context.settings.terms);
    assert_eq!(lines.len(), 1);
    assert_eq!(lines[0].role, RayRole::Camera);
    assert!((lines[0].to - Vec2::new(0.5, 0.5)).length() < 0.75);
    let roles_of_l1 = TermSet::only(Term::L1);
    assert_eq!(path_lines(&log, &context.camera, roles_of_l1).len(), 1);
}

/// Through the glass block of `cornell-glass` a path refracts: the path
/// view marks every continuation that crossed the glass as a refraction
/// (outlined in white, "refraction" in the list), and only those.
#[test]
fn refractions_through_glass_are_marked_in_the_path_view() {
    use lumiere::geometry::accel::Hit;
    use lumiere::transport::counts::RayCounts;
    use lumiere::transport::path_log::PathLog;
    use lumiere::transport::sampler::SampleStream;
    let settings = RenderSettings {
        width: 64,
        height: 64,
        terms: TermSet::ALL,
        ..RenderSettings::default()
    };
    let context = RenderContext::new(builtin::load("cornell-glass").unwrap(), settings);
    // the pixels whose centre sees the glass block
    let sees_glass = |x: u32, y: u32| {
        let ray = context.camera.generate(x, y, Vec2::splat(0.5));
        matches!(context.accel.closest_hit(&ray), Some(Hit::Triangle { triangle, .. })
            if context.scene.objects[context.scene.object_of_triangle(triangle) as usize].name == "glass block")
    };
    let pixels: Vec<(u32, u32)> = (0..64)
        .flat_map(|y| (0..64).map(move |x| (x, y)))
        .filter(|&(x, y)| sees_glass(x, y))
        .step_by(7)
        .collect();
    assert!(pixels.len() >= 10, "{} pixels on the block", pixels.len());
    let (mut refractions, mut bounces) = (0, 0);
    for (x, y) in pixels {
        for sample in 0..16 {
            let stream = SampleStream::new(3, (y * 64 + x) as u64, sample);
            let mut log = PathLog::default();
            lumiere::transport::sample_pixel_logged(
                &context,
                x,
                y,
                &stream,
                &mut RayCounts::default(),
                &mut log,
            );
            for line in path_lines(&log, &context.camera, TermSet::ALL) {
                let SegmentKind::Bounce { refracted } = log.segments[line.segment].kind else {
                    assert!(!line.role.is_refracted());
                    continue;
                };
                assert_eq!(line.role.is_refracted(), refracted);
                assert_eq!(line.role.describe().contains("refraction"), refracted);
                if refracted {
                    refractions += 1;
                } else {
                    bounces += 1;
                }
            }
        }
    }
    assert!(
        refractions > 100 && bounces > 10,
        "{refractions} refractions, {bounces} bounces"
    );
}
