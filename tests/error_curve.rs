//! Error against a reference: the capture job renders what `render` renders,
//! a reference is valid for the radiance settings and not the estimator, and
//! the RMSE of a Monte Carlo render against it falls as N^(−1/2).

mod common;

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use lumiere::analysis::capture::{ReferenceCapture, ReferenceJob, ReferenceKey, reference_seed};
use lumiere::analysis::convergence::log_log_slope;
use lumiere::analysis::metrics::image_error;
use lumiere::course::{LightSampling, Sampler};
use lumiere::render::{Budget, render};
use lumiere::scene::builtin;
use lumiere::{Film, RenderContext, Term, TermSet};

use common::{render_film, small};

#[test]
fn the_capture_job_renders_what_render_renders() {
    let scene = Arc::new(builtin::cornell());
    let settings = small(24, 18, TermSet::COURSE);
    let job = ReferenceJob::new(Arc::clone(&scene), scene.default_camera(), &settings, 8);
    assert_eq!(job.settings.seed, reference_seed(settings.seed));
    assert_ne!(
        job.settings.seed, settings.seed,
        "a reference has a seed of its own"
    );

    let mut progress = Vec::new();
    let image = job
        .run(&AtomicBool::new(false), |spp| progress.push(spp))
        .expect("not cancelled");
    assert_eq!(progress, (1..=8).collect::<Vec<u32>>());
    let film = render_film(builtin::cornell(), &job.settings, 8);
    assert_eq!((image.width, image.height), (24, 18));
    assert_eq!(image.radiance, film.radiance(settings.terms));

    // on its own thread: the same image, and the key of the view it was made for
    let capture = ReferenceCapture::spawn(job.clone(), || {});
    let (threaded, key) = capture.join().expect("not cancelled");
    assert_eq!(threaded.radiance, image.radiance);
    assert!(key.matches(&Arc::downgrade(&scene), &scene.default_camera(), &settings));

    // cancelled before the first pass: nothing
    assert!(job.run(&AtomicBool::new(true), |_| {}).is_none());
}

#[test]
fn a_reference_is_valid_for_the_radiance_not_the_estimator() {
    let scene = Arc::new(builtin::cornell());
    let camera = scene.default_camera();
    let settings = small(24, 18, TermSet::COURSE);
    let key = ReferenceKey::new(&scene, &camera, &settings);
    let weak = Arc::downgrade(&scene);

    let mut other_estimator = settings.clone();
    other_estimator.light_sampling = LightSampling::Area;
    other_estimator.sampler = Sampler::Sobol;
    other_estimator.light_samples = 4;
    other_estimator.seed = 7;
    assert!(key.matches(&weak, &camera, &other_estimator));

    let other_terms = small(24, 18, TermSet::only(Term::L1));
    assert!(!key.matches(&weak, &camera, &other_terms));
    let other_size = small(24, 20, TermSet::COURSE);
    assert!(!key.matches(&weak, &camera, &other_size));
    let mut other_bounces = settings.clone();
    other_bounces.max_bounces = 2;
    assert!(!key.matches(&weak, &camera, &other_bounces));
    // an equal but distinct scene object (an edit makes a new one)
    let copy = Arc::new(builtin::cornell());
    assert!(!key.matches(&Arc::downgrade(&copy), &camera, &settings));
    let mut moved = camera.clone();
    moved.world_from_camera.translation.x += 0.1;
    assert!(!key.matches(&weak, &moved, &settings));
}

/// Convergence, not correctness: the reference is lumiere's own render, so
/// this checks that the error falls as an unbiased estimator's does.
///
/// With a reference of M samples and an independent seed, a pixel of
/// per-sample variance σ² has E[(x_N − r_M)²] = σ²(1/N + 1/M): the MSE at N
/// samples is k_N = (1/N + 1/M)/(1/N_last + 1/M) times the MSE at the last
/// count (RMSE slope −1/2, flattened by the reference's noise). Per pixel,
/// dᵢ = eᵢ(N) − k_N·eᵢ(N_last) has mean zero whatever σᵢ; pixels are
/// independent, so the mean of dᵢ over the image is a z-test with its
/// standard error from the dᵢ themselves.
#[test]
fn rmse_against_a_reference_render_converges_as_one_over_root_n() {
    // direct lighting: light sampling of the area light has light tails, so
    // the squared errors are close enough to normal for a mean over 768 pixels
    let scene = Arc::new(builtin::cornell());
    let settings = small(32, 24, TermSet::only(Term::L1));
    let reference_spp = 2048u32;
    let reference = ReferenceJob::new(
        Arc::clone(&scene),
        scene.default_camera(),
        &settings,
        reference_spp,
    )
    .run(&AtomicBool::new(false), |_| {})
    .unwrap();

    let context = RenderContext::new(Arc::clone(&scene), settings.clone());
    let mut film = Film::new(settings.width, settings.height);
    let mut points = Vec::new();
    let mut squared_errors = Vec::new();
    let mut spp = 0;
    for target in [4u32, 16, 64, 256] {
        let stats = render(&context, &mut film, Budget::Samples(target - spp), |_| {});
        common::assert_no_invalid_samples(&stats.rays);
        spp = target;
        let image = film.radiance(settings.terms);
        let error = image_error(&image, &reference.radiance).unwrap();
        points.push((spp as f64, error.rmse));
        let per_pixel: Vec<f64> = common::pixel_errors(&image, &reference.radiance)
            .iter()
            .map(|e| e.rmse * e.rmse)
            .collect();
        squared_errors.push((spp, per_pixel));
    }
    let slope = log_log_slope(points.iter().copied()).unwrap();

    let expected_mse = |n: u32| 1.0 / n as f64 + 1.0 / reference_spp as f64;
    let (last_spp, last_errors) = squared_errors.last().unwrap();
    for (spp, errors) in &squared_errors[..squared_errors.len() - 1] {
        let ratio = expected_mse(*spp) / expected_mse(*last_spp);
        let scaled_last: Vec<f64> = last_errors.iter().map(|e| ratio * e).collect();
        let (difference, error) = common::paired_difference(errors, &scaled_last);
        let z = difference / error;
        assert!(
            z.abs() <= 4.5,
            "MSE at {spp} spp is not {ratio:.2} × MSE at {last_spp} spp: z = {z:.2} \
             (log-log slope of RMSE {slope:.3}, {points:?})"
        );
    }
}
