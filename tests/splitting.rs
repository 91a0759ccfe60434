//! The splitting pilot (`--indirect-samples auto`): it measures where the
//! noise is, splits when the continuations are the noisier part, never
//! when they bring nothing, and chooses the same whatever the threads.

mod common;

use std::process::Command;
use std::sync::Arc;

use common::{add_floor, small};
use glam::Vec3;
use lumiere::course::Sampler;
use lumiere::render::{Budget, render};
use lumiere::scene::builtin;
use lumiere::scene::{Camera, Material, Projection, Scene};
use lumiere::transport::context::RenderContext;
use lumiere::transport::counts::RayCounts;
use lumiere::transport::sampler::SampleStream;
use lumiere::transport::splitting::{SplitChoice, choose_continuations, choose_indirect_samples};
use lumiere::{Film, RenderSettings, TermSet};

fn auto(settings: RenderSettings) -> RenderSettings {
    RenderSettings {
        auto_indirect_samples: true,
        ..settings
    }
}

fn choice(scene: Scene, settings: RenderSettings) -> SplitChoice {
    choose_indirect_samples(&RenderContext::new(scene, settings))
}

/// The Cornell box's L2 is most of its noise: the pilot must find the
/// continuations the noisier part (V_w > V_b) and split them.
///
/// Each pilot measures within − between, whose expectation is V_w − V_b
/// (relMSE-weighted), and pilots of different seeds are independent: over
/// 16 of them the mean difference must exceed zero by 4.5 of its standard
/// errors, the pilots' spread giving the standard error (a t statistic with
/// 15 degrees of freedom: P(t > 4.5) ≈ 2·10⁻⁴ were the parts equal).
#[test]
fn the_cornell_box_splits_its_continuations() {
    let settings = small(64, 48, TermSet::COURSE);
    let pilots: Vec<SplitChoice> = (0..16u64)
        .map(|seed| {
            let settings = RenderSettings {
                seed,
                ..settings.clone()
            };
            choice(builtin::cornell(), settings)
        })
        .collect();
    let differences: Vec<f64> = pilots.iter().map(|p| p.within - p.between).collect();
    let n = differences.len() as f64;
    let mean = differences.iter().sum::<f64>() / n;
    let variance = differences.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let t = mean / (variance / n).sqrt();
    assert!(
        t > 4.5,
        "continuation noise less first-vertex noise {mean:.4}: t = {t:.2} ({differences:?})"
    );
    let independent = pilots[0].clone();
    assert!(independent.first_rays > 1.0 && independent.continuation_rays > 1.0);
    assert!(independent.count >= 2, "{independent:?}");
    let sobol = choice(
        builtin::cornell(),
        RenderSettings {
            sampler: Sampler::Sobol,
            ..settings
        },
    );
    // the same pilot (independent numbers), rounded up for the Sobol points
    assert_eq!(sobol.optimum, independent.optimum);
    assert!(sobol.count >= independent.count);

    // and a context built for auto takes it
    let mut context = RenderContext::new(builtin::cornell(), auto(small(64, 48, TermSet::COURSE)));
    choose_continuations(&mut context);
    assert_eq!(context.continuations, independent.continuations());
}

/// Without L2 no continuation is split, and the pilot does not run.
#[test]
fn direct_lighting_alone_is_not_split() {
    let l0_l1: TermSet = "L0,L1".parse().expect("terms");
    let c = choice(builtin::cornell(), small(64, 48, l0_l1));
    assert_eq!(c.count, 1);
    assert_eq!(c.continuation_rays, 0.0);
}

/// A floor under a light and nothing else: a continuation from the floor
/// finds only the light (weighted 0 under area light sampling, the light
/// samples count it) or the sky, so it brings exactly nothing and must not
/// be split, although it is traced. (Under `mis` it would bring the
/// light's share found by the BRDF.)
#[test]
fn continuations_that_bring_nothing_are_not_split() {
    let mut scene = Scene::default();
    let floor = scene.add_material(Material::lambert("floor", Vec3::splat(0.5)));
    add_floor(&mut scene, floor, 5.0);
    let light = scene.add_material(Material::emitter("light", Vec3::splat(4.0)));
    let h = 0.5;
    let square = [
        Vec3::new(-h, -h, 2.0),
        Vec3::new(-h, h, 2.0),
        Vec3::new(h, h, 2.0),
        Vec3::new(h, -h, 2.0),
    ];
    scene.add_mesh("light", light, &square, &[[0, 1, 2], [0, 2, 3]]);
    // looking straight down at the floor from below the light
    scene.cameras.push(Camera {
        name: "down".into(),
        world_from_camera: glam::Affine3A::from_translation(Vec3::new(0.0, 0.0, 1.5)),
        projection: Projection::Perspective { yfov: 1.0 },
    });
    let settings = RenderSettings {
        light_sampling: lumiere::course::LightSampling::Area,
        ..small(32, 32, TermSet::COURSE)
    };
    let c = choice(scene, settings);
    assert!(c.continuation_rays > 0.5, "{c:?}");
    assert!(c.between > 0.0, "{c:?}");
    assert_eq!(c.within, 0.0, "{c:?}");
    assert_eq!(c.count, 1);
}

/// The choice is a function of the scene, the settings and the seed.
#[test]
fn the_choice_does_not_depend_on_the_thread_count() {
    let settings = small(64, 48, TermSet::ALL);
    let context = Arc::new(RenderContext::new(builtin::cornell(), settings));
    let with_threads = |n| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("pool");
        pool.install(|| choose_indirect_samples(&context))
    };
    let one = with_threads(1);
    assert_eq!(one, with_threads(2));
    assert_eq!(one, with_threads(3));
    assert!(one.count >= 1);
}

/// `lumiere render --indirect-samples auto` says what it chose; a count of 0 is refused.
#[test]
fn the_command_line_takes_auto() {
    let out_dir = std::env::temp_dir().join(format!("lumiere-split-{}", std::process::id()));
    std::fs::create_dir_all(&out_dir).expect("temp dir");
    let output = out_dir.join("auto.png");
    let run = |count: &str| {
        Command::new(env!("CARGO_BIN_EXE_lumiere"))
            .args([
                "render", "cornell", "--width", "32", "--height", "24", "--spp", "2",
            ])
            .args(["--indirect-samples", count, "-o"])
            .arg(&output)
            .output()
            .expect("lumiere runs")
    };
    let auto = run("auto");
    let stdout = String::from_utf8_lossy(&auto.stdout);
    assert!(
        auto.status.success(),
        "{}",
        String::from_utf8_lossy(&auto.stderr)
    );
    assert!(
        stdout.contains("indirect samples: ") && stdout.contains("per first hit (auto)"),
        "{stdout}"
    );
    assert_eq!(common::invalid_samples(&auto), 0);
    let zero = run("0");
    assert_eq!(zero.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&zero.stderr).contains("--indirect-samples"));
    let _ = std::fs::remove_dir_all(&out_dir);
}

/// Splitting divides a continuation's weight by M, not its chance to go on.
///
/// In the furnace (albedo ρ, every ray hits the wall) a cosine-sampled
/// reflection multiplies β by ρ, and the roulette from reflection 4 on
/// survives with probability min(M β, 0.95) and divides β by it: M β is ρ⁴
/// at reflection 4, then ρ at each one after, so reflection k ≥ 4 is traced
/// with probability ρᵏ whatever M, and a continuation traces
///
/// ```text
/// E[reflections] = 3 + Σ_{k=4}^{64} ρᵏ = 3 + ρ⁴ (1 − ρ⁶¹) / (1 − ρ)
/// ```
///
/// (64 the bounce limit), 3.324 for ρ = 0.6. Reading survival off β alone
/// would give 3 + ρ⁴/M · 1/(1 − ρ), 3.081 for M = 4. Each camera sample's
/// reflections per continuation are one draw (its M continuations share a
/// first vertex), so the mean over samples is a z-test with its standard
/// error from their spread.
#[test]
fn splitting_does_not_shorten_the_continuations() {
    let albedo = 0.6f64;
    let max_bounces = 64;
    let expected = 3.0 + albedo.powi(4) * (1.0 - albedo.powi(max_bounces - 3)) / (1.0 - albedo);
    let scene = Arc::new(builtin::furnace(albedo as f32, 1.0));
    for m in [1u32, 4] {
        let mut settings = small(16, 16, TermSet::ALL);
        settings.max_bounces = max_bounces as u32;
        settings.indirect_samples = m;
        let context = RenderContext::new(scene.clone(), settings.clone());
        let (mut sum, mut sum2, mut roulette) = (0.0f64, 0.0f64, 0);
        let samples_per_pixel = 16u64;
        for pixel in 0..(settings.width * settings.height) as u64 {
            let (x, y) = (pixel as u32 % settings.width, pixel as u32 / settings.width);
            for sample in 0..samples_per_pixel {
                let stream = SampleStream::new(settings.seed, pixel, sample);
                let mut rays = RayCounts::default();
                lumiere::transport::sample_pixel(
                    &context,
                    x,
                    y,
                    &stream,
                    context.settings.terms,
                    &mut rays,
                );
                common::assert_no_invalid_samples(&rays);
                assert_eq!(rays.camera, 1);
                roulette += rays.skipped.roulette;
                let per_continuation = rays.bounce as f64 / m as f64;
                sum += per_continuation;
                sum2 += per_continuation * per_continuation;
            }
        }
        assert!(roulette > 0, "the roulette never ended a path");
        let n = (settings.width * settings.height) as f64 * samples_per_pixel as f64;
        let mean = sum / n;
        let standard_error = ((sum2 / n - mean * mean) / (n - 1.0)).sqrt();
        let z = (mean - expected) / standard_error;
        assert!(
            z.abs() <= 4.5,
            "M = {m}: {mean:.4} ± {standard_error:.4} reflections per continuation, \
             expected {expected:.4} (z = {z:.2})"
        );
    }
}

/// The pilot's map on the Cornell box: the regions differ, and the
/// ceiling, lit only by the walls (all L2 and beyond), splits more than
/// the lit floor in front of the blocks, whose noise is mostly L1's.
#[test]
fn the_cornell_box_splits_its_dark_regions_more() {
    let settings = RenderSettings {
        sampler: Sampler::Sobol,
        ..small(96, 96, TermSet::COURSE)
    };
    let choice = choice(builtin::cornell(), settings);
    let map = choice.map.as_ref().expect("the regions differ");
    assert_eq!((map.columns, map.rows), (8, 8));
    // the ceiling beside the light, and the floor between the blocks
    let ceiling = map.at(20, 6);
    let floor = map.at(48, 88);
    assert!(
        ceiling > floor,
        "ceiling ×{ceiling}, floor ×{floor}: {map:?}"
    );
    let (lo, hi) = choice.continuations().range();
    assert!(lo < hi && hi <= lumiere::transport::splitting::MAX_AUTO_INDIRECT_SAMPLES);
}

/// Splitting region by region changes the noise, not the mean: with a
/// map of 1 and 8 continuations in a checkerboard, the image's L2 agrees
/// with one continuation everywhere, and the pixels of the ×8 regions are
/// less noisy than with one.
#[test]
fn a_map_of_counts_keeps_the_mean_and_cuts_the_noise_where_it_splits() {
    use lumiere::course::Term;
    use lumiere::transport::continuations::{Continuations, SplitMap};
    let settings = small(32, 24, TermSet::COURSE);
    let scene = Arc::new(builtin::cornell());
    let render_with = |continuations: Continuations| {
        let mut context = RenderContext::new(scene.clone(), settings.clone());
        context.continuations = continuations;
        let mut film = Film::new(settings.width, settings.height);
        let stats = render(&context, &mut film, Budget::Samples(64), |_| {});
        common::assert_no_invalid_samples(&stats.rays);
        film
    };
    let map = SplitMap {
        width: 32,
        height: 24,
        columns: 4,
        rows: 3,
        counts: (0..12)
            .map(|i| if (i + i / 4) % 2 == 0 { 8 } else { 1 })
            .collect(),
    };
    let uniform = render_with(Continuations::uniform(1));
    let split = render_with(Continuations {
        count: 1,
        map: Some(Arc::new(map.clone())),
    });
    let (a, b) = (
        common::mean_and_error(&uniform, Term::L2),
        common::mean_and_error(&split, Term::L2),
    );
    let z = (a.0 - b.0) / (a.1 * a.1 + b.1 * b.1).sqrt();
    assert!(
        z.abs() < 4.0,
        "L2 {a:?} with one continuation, {b:?} with the map: z = {z:.2}"
    );
    // the noise where the map splits: each ×8 pixel's squared standard
    // error (its variance of the mean) in both films, paired pixel by pixel;
    // pixels are independent, so the mean difference is a one-sided z-test
    // that splitting lowered the variance (V_b + V_w/8 < V_b + V_w)
    let squared_errors = |film: &Film| {
        let buffer = film.term(Term::L2).expect("L2");
        (0..film.pixel_count())
            .filter(|&i| map.at(i as u32 % 32, i as u32 / 32) == 8)
            .map(|i| buffer.standard_error(i).powi(2))
            .collect::<Vec<f64>>()
    };
    let (lowered, error) =
        common::paired_difference(&squared_errors(&uniform), &squared_errors(&split));
    let z = lowered / error;
    assert!(
        z > 4.5,
        "×8 pixels: variance lowered by {lowered:.3e} ± {error:.1e} (z = {z:.2})"
    );
}
