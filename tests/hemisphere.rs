//! The integral at a point: the quadrature of the integrand map over the
//! hemisphere equals the estimators' mean at the pixel's first hit, for
//! L1 and L2, area and point lights, Lambert and Phong, both integrators;
//! a point light is a direction, not an area; L2's map is zero where the
//! sources are.

use glam::{Vec2, Vec3};

use lumiere::analysis::domains::{SourceDomains, source_domains};
use lumiere::analysis::hemisphere::{
    Factor, HemisphereError, IntegrandMap, ShadingPoint, Vertex, estimator_mean, integrand_map,
};
use lumiere::analysis::hemisphere_colour::colour_map;
use lumiere::analysis::noise::Scale;
use lumiere::course::color::luminance;
use lumiere::course::{Integrator, LightMode};
use lumiere::geometry::Ray;
use lumiere::scene::builtin;
use lumiere::{BrdfOverride, RenderContext, RenderSettings, Term, TermSet};

const WIDTH: u32 = 64;
const HEIGHT: u32 = 48;

fn context(scene: &str, settings: RenderSettings) -> RenderContext {
    let settings = RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        terms: TermSet::ALL,
        ..settings
    };
    RenderContext::new(builtin::load(scene).unwrap(), settings)
}

fn pixel_ray(context: &RenderContext, x: u32, y: u32) -> Ray {
    context.camera.generate(x, y, Vec2::splat(0.5))
}

/// The map's quadrature against the estimator's mean: within four combined
/// standard errors (fixed seeds), the quadrature's error below 5%.
fn assert_quadrature_agrees(what: &str, context: &RenderContext, x: u32, y: u32, terms: TermSet) {
    assert_fine_quadrature_agrees(what, context, x, y, terms, (4, 0.05));
}

/// [`assert_quadrature_agrees`] with `directions` per pixel of the map,
/// its standard error below `coarseness` of the value.
fn assert_fine_quadrature_agrees(
    what: &str,
    context: &RenderContext,
    x: u32,
    y: u32,
    terms: TermSet,
    (directions, coarseness): (u32, f64),
) {
    let ray = pixel_ray(context, x, y);
    let map = integrand_map(context, &ray, terms, 96, directions, 7)
        .unwrap_or_else(|e| panic!("{what}: {e}"));
    let (mean, mean_error) = estimator_mean(context, &ray, terms, (y * WIDTH + x) as u64, 8192);
    let (quadrature, mean) = (luminance(map.quadrature()) as f64, luminance(mean) as f64);
    assert!(mean > 1e-4, "{what}: the term is not zero there ({mean})");
    let combined = (map.integral_standard_error.powi(2) + mean_error.powi(2)).sqrt();
    let z = (quadrature - mean) / combined.max(1e-5 * mean);
    assert!(
        z.abs() < 4.0,
        "{what}: quadrature {quadrature} ± {}, estimator {mean} ± {mean_error} (z = {z:.2})",
        map.integral_standard_error
    );
    assert!(
        map.integral_standard_error < coarseness * mean.max(quadrature),
        "{what}: the map is too coarse to tell ({quadrature} ± {})",
        map.integral_standard_error
    );
}

#[test]
fn the_quadrature_of_direct_lighting_is_the_estimators_mean() {
    let cornell = context("cornell", RenderSettings::default());
    // the back wall, under the light, and the red wall
    assert_quadrature_agrees("L1, back wall", &cornell, 32, 15, TermSet::only(Term::L1));
    assert_quadrature_agrees("L1, red wall", &cornell, 10, 40, TermSet::only(Term::L1));
    let phong = context(
        "cornell",
        RenderSettings {
            brdf: BrdfOverride::Phong,
            ..RenderSettings::default()
        },
    );
    assert_quadrature_agrees("L1, Phong", &phong, 32, 15, TermSet::only(Term::L1));
    let spheres = context(
        "cornell-point",
        RenderSettings {
            light_mode: LightMode::Area,
            ..RenderSettings::default()
        },
    );
    // a small sphere: few pixels of the map, finely sampled
    let l1 = TermSet::only(Term::L1);
    assert_fine_quadrature_agrees("L1, a sphere light", &spheres, 32, 15, l1, (64, 0.05));
}

#[test]
fn the_quadrature_of_one_indirect_bounce_is_the_estimators_mean() {
    let cornell = context("cornell", RenderSettings::default());
    assert_quadrature_agrees("L2, back wall", &cornell, 32, 15, TermSet::only(Term::L2));
    assert_quadrature_agrees("L2, floor", &cornell, 20, 44, TermSet::only(Term::L2));
    let lecture = context(
        "cornell",
        RenderSettings {
            integrator: Integrator::Lecture,
            ..RenderSettings::default()
        },
    );
    assert_quadrature_agrees("L2, lecture", &lecture, 20, 44, TermSet::only(Term::L2));
    let phong = context(
        "cornell",
        RenderSettings {
            brdf: BrdfOverride::Phong,
            ..RenderSettings::default()
        },
    );
    assert_quadrature_agrees("L2, Phong", &phong, 32, 15, TermSet::only(Term::L2));
    // the ceiling beside a point light: a peak of 1/d², finely sampled
    let point = context("cornell-point", RenderSettings::default());
    let l2 = TermSet::only(Term::L2);
    assert_fine_quadrature_agrees("L2, point light", &point, 20, 44, l2, (64, 0.1));
    // the floor beside the glass block: light through the glass is L2
    let glass = context("cornell-glass", RenderSettings::default());
    assert_quadrature_agrees("L2, glass", &glass, 20, 44, TermSet::only(Term::L2));
    let both = TermSet::only(Term::L1).with(Term::L2, true);
    assert_quadrature_agrees("L1 + L2", &cornell, 20, 44, both);
}

/// A point light lights p from one direction: no area of the map, one
/// Dirac whose contribution is the estimator's (which has no noise).
#[test]
fn a_point_light_is_a_direction_not_an_area() {
    let point = context("cornell-point", RenderSettings::default());
    let ray = pixel_ray(&point, 20, 44);
    let map = integrand_map(&point, &ray, TermSet::only(Term::L1), 32, 1, 0).unwrap();
    assert!(map.values.iter().all(|v| *v == Vec3::ZERO), "no area");
    assert_eq!(map.diracs.len(), 1);
    let dirac = map.diracs[0].clone();
    assert!(!dirac.occluded && dirac.disk.length() < 1.0, "{dirac:?}");
    // above p: the light is in the ceiling
    assert!(dirac.direction.z > 0.0);
    let (mean, error) = estimator_mean(&point, &ray, TermSet::only(Term::L1), 0, 16);
    assert_eq!(error, 0.0, "one point light: every sample is the same");
    let relative = (map.quadrature() - mean).abs().max_element() / mean.max_element();
    assert!(relative < 1e-5, "{:?} vs {mean:?}", map.quadrature());
}

/// Ω = Ω⁺ − Ω_S: where the map of L1 sees the light, the map of L2 is zero
/// (the light reflects nothing), and it is not zero elsewhere.
#[test]
fn l2_lives_outside_the_sources_domains() {
    let cornell = context("cornell", RenderSettings::default());
    let ray = pixel_ray(&cornell, 32, 15);
    let direct = integrand_map(&cornell, &ray, TermSet::only(Term::L1), 48, 1, 1).unwrap();
    let indirect = integrand_map(&cornell, &ray, TermSet::only(Term::L2), 48, 1, 1).unwrap();
    let mut inside_sources = 0;
    for (l1, l2) in direct.values.iter().zip(&indirect.values) {
        if *l1 != Vec3::ZERO {
            inside_sources += 1;
            assert_eq!(*l2, Vec3::ZERO, "L2 inside Ω_s");
        }
    }
    assert!(
        inside_sources > 10,
        "the light covers {inside_sources} pixels"
    );
    let outside = indirect.values.iter().filter(|v| **v != Vec3::ZERO).count();
    assert!(outside > 48 * 48 / 4, "L2 is seen in {outside} pixels");
}

/// The sources' domains: named, and where something stands between p and
/// a source, L1's integrand has a hole (the shadow) inside Ω_s, which L2
/// does not fill either (the source reflects nothing).
#[test]
fn a_shadow_is_a_hole_in_the_sources_domain() {
    let cornell = context("cornell", RenderSettings::default());
    let size = 128;
    // the floor beside the boxes, until a point deep in their penumbra:
    // a third of the light hidden or more (looked for on a coarse map)
    let counts = |domains: &SourceDomains| {
        let of = |visible: bool| {
            (0..domains.source.len())
                .filter(|&i| domains.source[i].is_some() && domains.visible[i] == visible)
                .count()
        };
        (of(false), of(true))
    };
    let found = (28..HEIGHT)
        .rev()
        .flat_map(|y| (4..WIDTH - 4).map(move |x| (x, y)))
        .find_map(|(x, y)| {
            let ray = pixel_ray(&cornell, x, y);
            let p = ShadingPoint::seen(&cornell, &ray)?;
            let (hidden, seen) = counts(&source_domains(&cornell, &p, 32));
            if hidden == 0 || seen == 0 {
                return None;
            }
            let domains = source_domains(&cornell, &p, size);
            let (hidden, seen) = counts(&domains);
            (hidden * 2 >= seen && seen * 2 >= hidden).then_some((ray, domains))
        });
    let (ray, domains) = found.expect("a point of the floor sees the light partly hidden");
    assert_eq!(domains.names, ["light"], "the source, by its name");
    let labels = domains.labels();
    assert_eq!(labels.len(), 1);
    assert!(labels[0].share > 0.0 && labels[0].share < 0.5, "{labels:?}");
    assert!(!domains.outline().is_empty());
    let direct = integrand_map(&cornell, &ray, TermSet::only(Term::L1), size, 1, 3).unwrap();
    let indirect = integrand_map(&cornell, &ray, TermSet::only(Term::L2), size, 1, 3).unwrap();
    let (mut hole, mut lit) = (0, 0);
    // a pixel's centre decides its domain, its one direction is jittered:
    // a pixel is judged when its four neighbours are of its kind, or, for
    // the shadow, when none of them sees the light
    let kind = |i: usize| (domains.source[i].is_some(), domains.visible[i]);
    let n = size as usize;
    let neighbours = |i: usize| [i - 1, i + 1, i - n, i + n];
    for i in n + 1..domains.source.len() - n - 1 {
        match kind(i) {
            (true, true) if neighbours(i).iter().all(|&j| kind(j) == (true, true)) => {
                lit += usize::from(direct.values[i] != Vec3::ZERO);
                assert_eq!(indirect.values[i], Vec3::ZERO, "L2 inside Ω_s, pixel {i}");
            }
            (true, false) if neighbours(i).iter().all(|&j| kind(j) != (true, true)) => {
                hole += 1;
                assert_eq!(direct.values[i], Vec3::ZERO, "L1 in the shadow, pixel {i}");
            }
            _ => {}
        }
    }
    assert!(hole > 0 && lit > 0, "{hole} pixels of shadow, {lit} lit");
}

/// The factors apart multiply to the integrand, direction by direction;
/// f_r of a Lambert surface is its albedo over π; cos θ is 1 − r² on the
/// equal-area disk.
#[test]
fn the_factors_multiply_to_the_integrand() {
    let cornell = context("cornell", RenderSettings::default());
    let ray = pixel_ray(&cornell, 32, 15);
    let size = 32;
    let map = integrand_map(&cornell, &ray, TermSet::only(Term::L2), size, 1, 5).unwrap();
    let mut lit = 0;
    for i in 0..map.values.len() {
        let product = map.incident[i] * map.brdf[i] * map.cosine[i];
        assert!(
            (product - map.values[i]).abs().max_element()
                <= 1e-5 * map.values[i].max_element().max(1e-6)
        );
        lit += usize::from(map.incident[i] != Vec3::ZERO);
        let centre =
            IntegrandMap::disk_point(size, i as u32 % size, i as u32 / size, Vec2::splat(0.5));
        if centre.length() < 0.9 {
            assert!(
                (map.cosine[i] - (1.0 - centre.length_squared())).abs() < 0.1,
                "cos θ at {centre}"
            );
            let albedo_over_pi = map.brdf[i] * std::f32::consts::PI;
            assert!(albedo_over_pi.max_element() < 1.0 && albedo_over_pi.min_element() > 0.0);
            assert!(
                (map.brdf[i] - map.brdf[size as usize * size as usize / 2 + size as usize / 2])
                    .abs()
                    .max_element()
                    < 1e-6,
                "Lambert: one f_r"
            );
        }
    }
    assert!(lit > 100, "L_i is seen in {lit} pixels");
    let layer = map.layer(Factor::Cosine);
    assert_eq!(layer, map.cosine);
}

/// The colour bar: linear from 0 to the largest value, log over four
/// decades below it; no colour outside the disk.
#[test]
fn the_coloured_map_states_its_range() {
    let cornell = context("cornell", RenderSettings::default());
    let ray = pixel_ray(&cornell, 32, 15);
    let map = integrand_map(&cornell, &ray, TermSet::only(Term::L2), 32, 1, 5).unwrap();
    let largest = map.values.iter().map(|&v| luminance(v)).fold(0.0, f32::max);
    let linear = colour_map(&map, Factor::Integrand, Scale::Linear);
    assert_eq!(linear.range, (0.0, largest));
    assert_eq!(linear.srgba.len(), 32 * 32 * 4);
    assert_eq!(
        &linear.srgba[..4],
        &[0, 0, 0, 0],
        "a corner is outside the disk"
    );
    let log = colour_map(&map, Factor::Integrand, Scale::Log);
    assert!((log.range.0 / log.range.1 - 1e-4).abs() < 1e-7);
    assert!((log.value_at(0.5) - largest * 1e-2).abs() < 1e-3 * largest);
    assert!((log.position_of(largest * 1e-2) - 0.5).abs() < 1e-4);
}

/// The map is the same for any number of threads.
#[test]
fn the_map_does_not_depend_on_the_threads() {
    let cornell = context("cornell", RenderSettings::default());
    let ray = pixel_ray(&cornell, 20, 44);
    let map = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let map: IntegrandMap = pool
            .install(|| integrand_map(&cornell, &ray, TermSet::only(Term::L2), 24, 2, 3).unwrap());
        map.values
            .iter()
            .map(|v| v.to_array().map(f32::to_bits))
            .collect::<Vec<_>>()
    };
    assert!(map(1) == map(2));
}

#[test]
fn what_has_no_map_is_refused_with_the_reason() {
    let cornell = context("cornell", RenderSettings::default());
    let ray = pixel_ray(&cornell, 20, 44);
    let refused = |context: &RenderContext, ray: &Ray, terms: TermSet| {
        integrand_map(context, ray, terms, 8, 1, 0).err()
    };
    assert_eq!(
        refused(&cornell, &ray, TermSet::only(Term::L0)),
        Some(HemisphereError::NotAnIntegral)
    );
    let sky = Ray::new(Vec3::new(0.0, 10.0, 0.0), Vec3::Y, f32::INFINITY);
    assert_eq!(
        refused(&cornell, &sky, TermSet::only(Term::L1)),
        Some(HemisphereError::NoSurface)
    );
    let mirror = context(
        "cornell",
        RenderSettings {
            brdf: BrdfOverride::Mirror,
            ..RenderSettings::default()
        },
    );
    assert_eq!(
        refused(&mirror, &ray, TermSet::only(Term::L1)),
        Some(HemisphereError::DiracBrdf)
    );
    let without_l1 = RenderContext::new(
        builtin::cornell(),
        RenderSettings {
            width: WIDTH,
            height: HEIGHT,
            terms: TermSet::only(Term::L2),
            ..RenderSettings::default()
        },
    );
    assert_eq!(
        refused(&without_l1, &ray, TermSet::only(Term::L2)),
        Some(HemisphereError::TermsLeftOut(TermSet::only(Term::L1)))
    );
}

fn lumiere(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(args)
        .output()
        .expect("lumiere runs")
}

/// `lumiere probe … --hemisphere`: the map as a linear EXR of its size, and
/// one `name: value` per line; the quadrature agrees with the mean.
#[test]
fn cli_writes_the_map_and_prints_the_quadrature_beside_the_mean() {
    let dir = std::env::temp_dir().join(format!("lumiere-hemisphere-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let exr = dir.join("map.exr");
    let output = lumiere(&[
        "probe",
        "cornell",
        "--pixel",
        "20,44",
        "--width",
        "64",
        "--height",
        "48",
        "--terms",
        "L2",
        "--hemisphere",
        exr.to_str().unwrap(),
        "--size",
        "40",
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let value = |name: &str| -> f64 {
        let line = stdout
            .lines()
            .find_map(|l| l.strip_prefix(&format!("{name}: ")))
            .unwrap_or_else(|| panic!("no `{name}:` in\n{stdout}"));
        line.parse().unwrap_or_else(|_| panic!("{name}: {line}"))
    };
    assert!(value("quadrature") > 0.0);
    assert!(value("z").abs() < 4.0, "{stdout}");
    assert!(value("estimator standard error") > 0.0);
    let map = image::open(&exr).unwrap();
    assert_eq!((map.width(), map.height()), (40, 40));
    // outside the disk there are no directions
    assert_eq!(map.to_rgb32f().get_pixel(0, 0).0, [0.0; 3]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn cli_refuses_what_has_no_map_naming_the_problem() {
    let out = std::env::temp_dir().join("lumiere-never-written.exr");
    let out = out.to_str().unwrap();
    let base = ["probe", "cornell", "--width", "64", "--height", "48"];
    let refused = |extra: &[&str], code: i32, says: &str| {
        let output = lumiere(&[&base[..], extra].concat());
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(code), "{extra:?}: {stderr}");
        assert!(stderr.contains(says), "{extra:?}: {stderr}");
    };
    refused(
        &["--pixel", "64,10", "--hemisphere", out],
        2,
        "outside the 64×48 image",
    );
    refused(
        &["--pixel", "10,10", "--terms", "L0", "--hemisphere", out],
        2,
        "not an integral",
    );
    refused(
        &["--pixel", "10,10", "--hemisphere", "map.txt"],
        2,
        "map.txt",
    );
    refused(&["--pixel", "1,1", "--hemisphere", out], 1, "no surface");
    refused(
        &["--pixel", "20,44", "--brdf", "mirror", "--hemisphere", out],
        1,
        "Dirac",
    );
}

/// The samples drawn at p are the film's own: pass by pass the term's value
/// is what `sample_pixel` gives with the film's random streams, and the
/// directions' values sum to it. With MIS both strategies draw, each
/// direction with its weight in [0, 1]; each strategy's density is a
/// density over the directions it can draw.
#[test]
fn the_samples_drawn_at_p_are_the_estimators_own() {
    use lumiere::analysis::strategy_samples::{Strategy, drawn_samples, strategy_density};
    use lumiere::render::sample_stream;
    use lumiere::transport::counts::RayCounts;
    use lumiere::transport::sample_pixel;
    let settings = RenderSettings {
        width: WIDTH,
        height: HEIGHT,
        auto_indirect_samples: false,
        ..RenderSettings::default()
    };
    let cornell = RenderContext::new(builtin::load("cornell").unwrap(), settings.clone());
    let (x, y) = (32, 15);
    let ray = pixel_ray(&cornell, x, y);
    let p = ShadingPoint::seen(&cornell, &ray).unwrap();
    for term in [Term::L1, Term::L2] {
        let drawn = drawn_samples(&cornell, &p, (x, y), Vertex::FirstHit, term, 64);
        assert_eq!(drawn.per_pass.len(), 64);
        for (pass, value) in drawn.per_pass.iter().enumerate() {
            let stream = sample_stream(&settings, (y * WIDTH + x) as u64, pass as u32);
            let film = sample_pixel(
                &cornell,
                x,
                y,
                &stream,
                settings.terms,
                &mut RayCounts::default(),
            );
            assert_eq!(*value, film[term.index()], "{term:?}, pass {pass}");
            let sum: Vec3 = drawn
                .first(pass as u32 + 1)
                .filter(|s| s.pass == pass as u32)
                .map(|s| s.value)
                .sum();
            assert!(
                (sum - *value).abs().max_element() <= 1e-5 * value.max_element().max(1e-3),
                "{term:?}, pass {pass}: {sum} vs {value}"
            );
        }
        let estimates = drawn.running_estimate();
        assert_eq!(
            estimates.iter().map(|e| e.n).collect::<Vec<_>>(),
            [1, 2, 4, 8, 16, 32, 64]
        );
        let last = estimates.last().unwrap();
        assert!(
            (last.mean - luminance(drawn.mean()) as f64).abs() < 1e-6 && last.standard_error > 0.0
        );
    }
    let l1 = drawn_samples(&cornell, &p, (x, y), Vertex::FirstHit, Term::L1, 1024);
    let (light, directions): (
        Vec<&lumiere::analysis::strategy_samples::DrawnSample>,
        Vec<_>,
    ) = l1
        .samples
        .iter()
        .partition(|s| s.strategy == Strategy::Light);
    assert!(
        light.len() >= 1000 && directions.len() >= 1000,
        "MIS draws by both: {} and {}",
        light.len(),
        directions.len()
    );
    assert!(l1.samples.iter().all(|s| (0.0..=1.0).contains(&s.weight)));
    // the light is small: its light samples weigh nearly one, the BRDF's
    // directions that find it little
    let found: Vec<_> = directions.iter().filter(|s| s.reached_light).collect();
    assert!(
        !found.is_empty() && found.iter().all(|s| s.weight < 0.5),
        "{found:?}"
    );
    assert!(light.iter().all(|s| s.weight > 0.5));
    // densities: the directions' integrates to one over Ω⁺, the light's is
    // zero away from the light
    let size = 64;
    let pixel_solid_angle = 2.0 * (2.0 / size as f32).powi(2);
    let brdf = strategy_density(&cornell, &p, Term::L1, Strategy::Directions, size);
    let total: f32 = brdf.iter().sum::<f32>() * pixel_solid_angle;
    assert!((total - 1.0).abs() < 0.03, "∫ pdf dω = {total}");
    let towards_light = strategy_density(&cornell, &p, Term::L1, Strategy::Light, size);
    let lit = towards_light.iter().filter(|&&d| d > 0.0).count();
    assert!(
        lit > 0 && lit < (size * size / 10) as usize,
        "{lit} pixels of light density"
    );
}

/// The nested integral: at q, where a drawn path's bounce from p lands,
/// the map of L1 integrates to the estimator's L1 along the bounce (what
/// L2's integrand at p takes as L_i there), ωo at q points back to p, and
/// the samples drawn at q are the estimator's along p → q.
#[test]
fn the_integral_at_q_is_the_light_arriving_at_p_along_the_bounce() {
    use lumiere::analysis::strategy_samples::drawn_samples;
    use lumiere::render::sample_stream;
    use lumiere::transport::counts::RayCounts;
    use lumiere::transport::path_log::{PathLog, SegmentKind};
    use lumiere::transport::{sample_pixel_logged, trace};
    // Phong, so that f_r at q depends on ωo, the way back to p
    let phong = context(
        "cornell",
        RenderSettings {
            brdf: BrdfOverride::Phong,
            auto_indirect_samples: false,
            ..RenderSettings::default()
        },
    );
    let (x, y) = (32, 40);
    let l1 = TermSet::only(Term::L1);
    let (mut checked, mut lit) = (0, 0);
    for pass in 0..12 {
        let stream = sample_stream(&phong.settings, (y * WIDTH + x) as u64, pass);
        let mut log = PathLog::default();
        sample_pixel_logged(&phong, x, y, &stream, &mut RayCounts::default(), &mut log);
        let Some(bounce) = log
            .segments
            .iter()
            .find(|s| matches!(s.kind, SegmentKind::Bounce { .. }) && s.term == Term::L1)
            .map(|s| s.ray)
        else {
            continue;
        };
        let vertex = Vertex::Second { bounce };
        let ray = vertex.ray(&phong, (x, y));
        let Some(q) = ShadingPoint::seen(&phong, &ray) else {
            continue; // the bounce left the box
        };
        let back = q.frame.to_world(q.wo_local);
        assert!(
            (back + bounce.direction.normalize()).length() < 1e-4,
            "ωo at q is towards p"
        );
        let map = integrand_map(&phong, &ray, l1, 96, 4, 11).unwrap();
        let (mean, mean_error) = estimator_mean(&phong, &ray, l1, 5, 8192);
        let (quadrature, mean) = (luminance(map.quadrature()) as f64, luminance(mean) as f64);
        let combined = (map.integral_standard_error.powi(2) + mean_error.powi(2)).sqrt();
        // q on the ceiling, beside the light, or on the light: no L1 at all
        let z = if quadrature == 0.0 && mean == 0.0 {
            0.0
        } else {
            (quadrature - mean) / combined.max(1e-5 * mean)
        };
        lit += u32::from(mean > 1e-4);
        assert!(
            z.abs() < 4.0,
            "pass {pass}: at q {quadrature} ± {}, estimator along the bounce {mean} ± {mean_error} (z = {z:.2})",
            map.integral_standard_error
        );
        // the samples at q: the estimator's own along p → q, pass by pass
        let drawn = drawn_samples(&phong, &q, (x, y), vertex, Term::L1, 16);
        for (k, value) in drawn.per_pass.iter().enumerate() {
            let stream = sample_stream(&phong.settings, (y * WIDTH + x) as u64, k as u32);
            let along = trace(&phong, bounce, &stream, l1, &mut RayCounts::default());
            assert_eq!(*value, along[Term::L1.index()], "pass {pass}, sample {k}");
        }
        assert!(drawn.samples.iter().all(|s| s.direction.z > 0.0));
        checked += 1;
    }
    assert!(
        checked >= 4 && lit >= 3,
        "only {checked} bounces landed in the box, {lit} on a lit point"
    );
}
