//! The splitting pilot (`--indirect-samples auto`): it measures where the
//! noise is, splits when the continuations are the noisier part, never
//! when they bring nothing, and chooses the same whatever the threads.

mod common;

use std::process::Command;
use std::sync::Arc;

use common::{add_floor, small};
use glam::Vec3;
use lumiere::render::context::RenderContext;
use lumiere::render::settings::Sampler;
use lumiere::render::{Budget, render};
use lumiere::scene::builtin;
use lumiere::scene::{Camera, Material, Projection, Scene};
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

/// The Cornell box's L2 is most of its noise (96 % of the relMSE at 64 spp):
/// the pilot must find the continuations the noisier part and split them.
#[test]
fn the_cornell_box_splits_its_continuations() {
    let settings = small(64, 48, TermSet::COURSE);
    let independent = choice(builtin::cornell(), settings.clone());
    assert!(
        independent.within > 2.0 * independent.between,
        "continuation noise {} against first-vertex noise {}",
        independent.within,
        independent.between
    );
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
        light_sampling: lumiere::render::settings::LightSampling::Area,
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

/// Splitting divides a continuation's weight by M, not its chance to go on:
/// Russian roulette lets the continuations of a furnace run as many
/// reflections with M = 4 as with M = 1 (3.32 and 3.32; with survival read
/// off the continuation's β / M, when roulette started a reflection
/// earlier, they ran 2.13 with M = 4 against 2.54).
#[test]
fn splitting_does_not_shorten_the_continuations() {
    let scene = Arc::new(builtin::furnace(0.6, 1.0));
    let reflections_per_continuation = |m: u32| {
        let mut settings = small(16, 16, TermSet::ALL);
        settings.indirect_samples = m;
        let context = RenderContext::new(scene.clone(), settings.clone());
        let mut film = Film::new(settings.width, settings.height);
        let rays = render(&context, &mut film, Budget::Samples(16), |_| {}).rays;
        common::assert_no_invalid_samples(&rays);
        assert!(rays.skipped.roulette > 0, "{rays:?}");
        rays.bounce as f64 / (rays.camera * m as u64) as f64
    };
    let (one, four) = (
        reflections_per_continuation(1),
        reflections_per_continuation(4),
    );
    assert!(one > 2.0, "{one} reflections per continuation with M = 1");
    assert!(
        (four / one - 1.0).abs() < 0.03,
        "{four} reflections per continuation with M = 4, {one} with M = 1"
    );
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
    use lumiere::render::settings::Term;
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
    // the standard errors of the ×8 pixels, summed, in both films
    let noise = |film: &Film| {
        let buffer = film.term(Term::L2).expect("L2");
        (0..film.pixel_count())
            .filter(|&i| map.at(i as u32 % 32, i as u32 / 32) == 8)
            .map(|i| buffer.standard_error(i))
            .sum::<f64>()
    };
    let (one, eight) = (noise(&uniform), noise(&split));
    assert!(
        eight < 0.6 * one,
        "×8 pixels: noise {eight:.4} against {one:.4} with one continuation"
    );
}
