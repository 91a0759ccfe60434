//! Work the settings and the scene make unnecessary is not done, and is counted.

mod common;

use common::small;
use lumiere::render::settings::LightSampling;
use lumiere::render::{Budget, render};
use lumiere::scene::builtin;
use lumiere::transport::counts::RayCounts;
use lumiere::{Film, LightMode, RenderContext, RenderSettings, Term, TermSet};

fn rays_of(settings: &RenderSettings, spp: u32) -> RayCounts {
    let context = RenderContext::new(builtin::cornell(), settings.clone());
    let mut film = Film::new(settings.width, settings.height);
    let rays = render(&context, &mut film, Budget::Samples(spp), |_| {}).rays;
    common::assert_no_invalid_samples(&rays);
    rays
}

#[test]
fn l0_and_l1_with_area_sampling_trace_no_bounce_and_count_each_one_skipped() {
    let mut settings = small(32, 24, TermSet::only(Term::L0).with(Term::L1, true));
    settings.light_sampling = LightSampling::Area;
    let rays = rays_of(&settings, 4);
    assert_eq!(rays.bounce, 0);
    assert_eq!(rays.gather, 0);
    // every first vertex had no use for a continuation; each drew at most one
    // light sample (none on the light itself, which cannot see itself)
    let light_samples = rays.shadow + rays.skipped.shadow_rays;
    assert!(rays.skipped.shadow_rays > 0, "{rays:?}");
    assert!(
        rays.skipped.continuations >= light_samples && light_samples > 0,
        "{rays:?}"
    );
    assert_eq!(rays.skipped.direct_lighting, 0);
}

#[test]
fn l2_alone_estimates_no_direct_lighting_at_the_first_hit() {
    let rays = rays_of(&small(32, 24, TermSet::only(Term::L2)), 4);
    assert_eq!(rays.per_term[Term::L1.index()], 0, "{rays:?}");
    // one skipped estimate per first vertex: as many as an L1 render skips
    // continuations there (same camera rays)
    let mut l1 = small(32, 24, TermSet::only(Term::L1));
    l1.light_sampling = LightSampling::Area;
    let l1 = rays_of(&l1, 4);
    assert!(rays.skipped.direct_lighting > 0);
    assert_eq!(rays.skipped.direct_lighting, l1.skipped.continuations);
}

#[test]
fn point_lights_gather_no_direction_and_count_the_ones_skipped() {
    let mut settings = small(32, 24, TermSet::COURSE);
    settings.light_mode = LightMode::Point;
    let rays = rays_of(&settings, 4);
    assert_eq!(rays.gather, 0);
    assert!(rays.skipped.gathered > 0, "{rays:?}");
    // and with the area light, nothing is skipped for that reason
    let area = rays_of(&small(32, 24, TermSet::COURSE), 4);
    assert_eq!(area.skipped.gathered, 0);
    assert_eq!(area.skipped.roulette, 0, "roulette starts after L2");
}

#[test]
fn russian_roulette_ends_some_l3_paths() {
    let rays = rays_of(&small(32, 24, TermSet::ALL), 4);
    assert!(rays.skipped.roulette > 0, "{rays:?}");
    assert!(rays.skipped.describe().contains("Russian roulette"));
}

/// Russian roulette starts after the fourth reflection: capped at three
/// reflections (their last continuation traced only to find the emitter)
/// no path is ended by it, capped at four some are.
#[test]
fn russian_roulette_starts_after_the_fourth_reflection() {
    let roulette = |max_bounces: u32| {
        let mut settings = small(16, 16, TermSet::ALL);
        settings.max_bounces = max_bounces;
        let context = RenderContext::new(builtin::furnace(0.6, 1.0), settings.clone());
        let mut film = Film::new(settings.width, settings.height);
        let rays = render(&context, &mut film, Budget::Samples(4), |_| {}).rays;
        common::assert_no_invalid_samples(&rays);
        assert!(rays.bounce >= 2 * rays.camera, "{rays:?}");
        rays.skipped.roulette
    };
    assert_eq!(roulette(3), 0);
    assert!(roulette(4) > 0);
}

#[test]
fn light_searches_that_meet_no_light_skip_the_scene_search_and_are_counted() {
    // L0,L1 with MIS: every continuation only looks for the light
    let settings = small(32, 24, TermSet::only(Term::L0).with(Term::L1, true));
    let rays = rays_of(&settings, 4);
    let searches = rays.bounce;
    let skipped = rays.skipped.scene_searches;
    // the ceiling light is small: most miss it, some find it (or a blocker)
    assert!(
        skipped > searches / 2 && skipped < searches,
        "{skipped} of {searches} searches skipped: {rays:?}"
    );
    // in a furnace everything emits: the search is the plain closest hit
    let furnace = RenderContext::new(builtin::furnace(0.5, 1.0), settings.clone());
    let mut film = Film::new(settings.width, settings.height);
    let rays = render(&furnace, &mut film, Budget::Samples(4), |_| {}).rays;
    common::assert_no_invalid_samples(&rays);
    assert!(rays.bounce > 0, "{rays:?}");
    assert_eq!(rays.skipped.scene_searches, 0, "{rays:?}");
}
