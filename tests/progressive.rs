//! The viewer's render worker: restarts only when radiance changes, term
//! toggles keep the film, pause and "stop at N spp" stop the passes.

use std::sync::Arc;
use std::time::{Duration, Instant};

use lumiere::render::progressive::{ProgressiveRenderer, Snapshot, ViewRequest};
use lumiere::scene::builtin;
use lumiere::transport::continuations::Continuations;
use lumiere::transport::splitting::choose_continuations;
use lumiere::{BrdfOverride, RenderContext, RenderSettings, Term, TermSet};

fn request() -> ViewRequest {
    let scene = Arc::new(builtin::cornell());
    ViewRequest {
        camera: scene.default_camera(),
        scene: scene.into(),
        settings: RenderSettings {
            width: 48,
            height: 36,
            ..RenderSettings::default()
        },
        paused: false,
        stop_at_spp: None,
        term_images: false,
        film: 0,
    }
}

/// Polls the worker until `done` holds (fails after 60 s rather than hang).
fn wait_for(
    renderer: &ProgressiveRenderer,
    what: &str,
    done: impl Fn(&Snapshot) -> bool,
) -> Arc<Snapshot> {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let snapshot = renderer.snapshot();
        if done(&snapshot) {
            return snapshot;
        }
        assert!(
            Instant::now() < deadline,
            "timed out waiting for {what}; last snapshot {snapshot:?}"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn term_toggles_keep_the_film_and_radiance_changes_restart_it() {
    let mut request = request();
    let renderer = ProgressiveRenderer::spawn(request.clone(), || {});
    let first = wait_for(&renderer, "4 spp", |s| s.samples_per_pixel() >= 4);
    assert_eq!(first.restarts, 1);
    assert_eq!((first.width, first.height), (48, 36));

    // switching L2 off: no restart, L2 stops accumulating, the others go on
    request.settings.terms = TermSet::COURSE.with(Term::L2, false);
    renderer.request(request.clone());
    let hidden = wait_for(&renderer, "L2 hidden", |s| {
        s.terms == request.settings.terms
    });
    let l2_samples = hidden.term_samples[Term::L2.index()];
    let later = wait_for(&renderer, "more L1 samples", |s| {
        s.term_samples[Term::L1.index()] >= hidden.term_samples[Term::L1.index()] + 3
    });
    assert_eq!(later.restarts, 1, "hiding a term must not restart the film");
    assert_eq!(
        later.term_samples[Term::L2.index()],
        l2_samples,
        "a hidden term is not computed"
    );

    // switching it back on: still no restart, L2 resumes from its own count
    request.settings.terms = TermSet::COURSE;
    renderer.request(request.clone());
    let shown = wait_for(&renderer, "L2 resumed", |s| {
        s.term_samples[Term::L2.index()] > l2_samples
    });
    assert_eq!(shown.restarts, 1);

    // a BRDF override changes radiance: restart from zero. Paused, the
    // restart publishes only its preview, whose counts are zero; this does
    // not depend on how many passes the worker ran while the test slept.
    request.settings.brdf = BrdfOverride::Mirror;
    request.paused = true;
    renderer.request(request.clone());
    let restarted = wait_for(&renderer, "the restart", |s| s.restarts == 2);
    assert!(restarted.preview);
    assert_eq!(restarted.term_samples, [0; Term::COUNT]);

    // resumed with a stop at one sample: the film holds exactly one, well
    // below the count it had before the restart
    assert!(shown.samples_per_pixel() >= 4);
    request.paused = false;
    request.stop_at_spp = Some(1);
    renderer.request(request.clone());
    let one = wait_for(&renderer, "one sample", |s| s.idle && !s.preview);
    assert_eq!(one.restarts, 2, "resuming must not restart again");
    assert_eq!(one.samples_per_pixel(), 1);
}

#[test]
fn a_restart_publishes_a_quarter_resolution_preview_first() {
    let mut request = request();
    request.paused = true; // after the preview, nothing more
    let renderer = ProgressiveRenderer::spawn(request, || {});
    let preview = wait_for(&renderer, "the preview", |s| s.generation >= 1);
    assert!(preview.preview);
    assert_eq!((preview.width, preview.height), (12, 9));
    assert!(preview.radiance.iter().any(|p| p[0] > 0.0));
    std::thread::sleep(Duration::from_millis(200));
    assert_eq!(
        renderer.snapshot().generation,
        1,
        "paused: no pass after the preview"
    );
}

/// The preview does not wait for the splitting pilot: it takes one
/// continuation per first hit, and the full passes the pilot's counts,
/// the same as a render of the same settings chooses.
#[test]
fn the_pilot_runs_after_the_preview_and_chooses_as_a_render_does() {
    let mut request = request();
    request.settings.width = 96;
    request.settings.height = 72;
    request.stop_at_spp = Some(1);
    assert!(request.settings.auto_indirect_samples, "the default");
    let renderer = ProgressiveRenderer::spawn(request.clone(), || {});
    let preview = wait_for(&renderer, "the preview", |s| s.generation >= 1);
    assert!(preview.preview);
    assert_eq!(preview.continuations, Continuations::uniform(1));
    let full = wait_for(&renderer, "one full pass", |s| s.idle && !s.preview);
    let mut context = RenderContext::new(Arc::clone(&request.scene), request.settings.clone());
    choose_continuations(&mut context);
    assert!(
        context.continuations.map.is_some() || context.continuations.count > 1,
        "the Cornell box's L2 is worth splitting"
    );
    assert_eq!(full.continuations, context.continuations);
}

/// A new film serial (a lesson step opened) restarts the film even when
/// nothing else changed; the same serial again does not.
#[test]
fn a_new_film_serial_restarts_the_film() {
    let mut request = request();
    request.stop_at_spp = Some(2);
    let renderer = ProgressiveRenderer::spawn(request.clone(), || {});
    wait_for(&renderer, "2 spp", |s| s.idle && !s.preview);
    request.film += 1;
    renderer.request(request.clone());
    let restarted = wait_for(&renderer, "the restart", |s| {
        s.restarts == 2 && s.idle && !s.preview
    });
    assert_eq!(restarted.samples_per_pixel(), 2);
    request.stop_at_spp = Some(3);
    renderer.request(request.clone());
    let more = wait_for(&renderer, "3 spp", |s| s.samples_per_pixel() >= 3 && s.idle);
    assert_eq!(more.restarts, 2, "the same serial keeps the film");
}

#[test]
fn stop_at_spp_stops_exactly_and_pause_holds() {
    let mut request = request();
    request.stop_at_spp = Some(5);
    let renderer = ProgressiveRenderer::spawn(request.clone(), || {});
    let done = wait_for(&renderer, "the stop", |s| s.idle && !s.preview);
    assert_eq!(done.samples_per_pixel(), 5);
    std::thread::sleep(Duration::from_millis(100));
    assert_eq!(renderer.snapshot().samples_per_pixel(), 5);

    // raising the stop resumes without a restart
    request.stop_at_spp = Some(8);
    renderer.request(request);
    let resumed = wait_for(&renderer, "8 spp", |s| s.samples_per_pixel() == 8 && s.idle);
    assert_eq!(resumed.restarts, 1);
}

/// What the lights are built from — a source switched off, the light
/// selection — reaches the image at once: the worker rebuilds its lights,
/// not only its settings.
#[test]
fn a_change_of_what_the_lights_are_built_from_rebuilds_them() {
    use lumiere::course::SourceQuality;
    let mut request = request();
    let renderer = ProgressiveRenderer::spawn(request.clone(), || {});
    wait_for(&renderer, "2 spp", |s| s.samples_per_pixel() >= 2);
    request.settings.sources = vec![SourceQuality::off("light")];
    renderer.request(request.clone());
    let off = wait_for(&renderer, "the light switched off", |s| {
        s.source
            .as_ref()
            .is_some_and(|source| source.settings == request.settings)
            && !s.preview
            && s.samples_per_pixel() >= 2
    });
    let brightest = off
        .radiance
        .iter()
        .map(|l| l[0].max(l[1]).max(l[2]))
        .fold(0.0f32, f32::max);
    assert_eq!(brightest, 0.0, "the Cornell box's only source is off");
    request.settings.sources = vec![SourceQuality::samples("light", 2)];
    renderer.request(request.clone());
    let on = wait_for(&renderer, "the light back on", |s| {
        s.source
            .as_ref()
            .is_some_and(|source| source.settings == request.settings)
            && !s.preview
            && s.samples_per_pixel() >= 2
    });
    assert!(on.radiance.iter().any(|l| l[0] > 0.0));
}

/// Asked for them, the worker publishes each visible term's image beside
/// their sum, without restarting the film; the sum is theirs, pixel by pixel.
#[test]
fn term_images_come_with_the_sum_and_do_not_restart() {
    let mut request = request();
    let renderer = ProgressiveRenderer::spawn(request.clone(), || {});
    let first = wait_for(&renderer, "2 spp", |s| s.samples_per_pixel() >= 2);
    assert!(first.term_images.iter().all(Option::is_none));
    request.term_images = true;
    renderer.request(request.clone());
    let with = wait_for(&renderer, "the term images", |s| {
        s.term_images.iter().any(Option::is_some) && !s.preview
    });
    assert_eq!(with.restarts, first.restarts);
    for term in Term::ALL {
        assert_eq!(
            with.term_images[term.index()].is_some(),
            with.terms.contains(term),
            "{term}"
        );
    }
    for (i, sum) in with.radiance.iter().enumerate() {
        for c in 0..3 {
            let added: f32 = with
                .term_images
                .iter()
                .flatten()
                .map(|image| image[i][c])
                .sum();
            assert!(
                (added - sum[c]).abs() <= 1e-6 * sum[c].max(1.0),
                "pixel {i}: {added} against {}",
                sum[c]
            );
        }
    }
    // a hidden term has no image
    request.settings.terms = TermSet::COURSE.with(Term::L1, false);
    renderer.request(request.clone());
    let hidden = wait_for(&renderer, "L1 hidden", |s| {
        s.terms == request.settings.terms
    });
    assert!(hidden.term_images[Term::L1.index()].is_none());
    assert!(hidden.term_images[Term::L2.index()].is_some());
    assert_eq!(hidden.restarts, first.restarts);
}

/// Without a thread of its own (a web page with one thread), the worker
/// renders a few tiles per call and ends with the film a worker thread
/// renders, bit for bit; a term hidden and shown again in the middle of a
/// pass starts that pass again rather than keep tiles of other terms.
#[test]
fn between_frames_the_worker_renders_the_same_film_a_few_tiles_at_a_time() {
    let mut request = request();
    request.stop_at_spp = Some(3);
    let threaded = ProgressiveRenderer::spawn(request.clone(), || {});
    let expected = wait_for(&threaded, "3 spp", |s| {
        s.idle && !s.preview && s.samples_per_pixel() == 3
    });
    assert!(
        ProgressiveRenderer::between_frames(request.clone(), || {})
            .snapshot()
            .radiance
            .is_empty(),
        "nothing is rendered before the first call"
    );
    let renderer = ProgressiveRenderer::between_frames(request.clone(), || {});
    // no budget: one step per call (the preview, then one band of 4 rows)
    let mut calls = 0;
    while renderer.run_between_frames(Duration::ZERO) {
        calls += 1;
        assert!(calls < 10_000, "the worker never finishes");
        // in the middle of the second pass
        if calls == 12 || calls == 14 {
            let mut changed = request.clone();
            changed.settings.terms = request.settings.terms.with(Term::L2, calls == 14);
            renderer.request(changed);
        }
    }
    let got = renderer.snapshot();
    let bands = 36 / 4;
    assert_eq!(
        calls,
        1 + 3 * bands + 2 + 2,
        "the preview, 3 passes, two passes begun again"
    );
    assert!(got.idle && !got.preview);
    assert_eq!(got.term_samples, expected.term_samples);
    assert_eq!(
        got.continuations, expected.continuations,
        "the pilot's choice"
    );
    let bits = |s: &Snapshot| -> Vec<[u32; 4]> {
        s.radiance.iter().map(|p| p.map(f32::to_bits)).collect()
    };
    assert!(
        bits(&got) == bits(&expected),
        "the film rendered between frames differs from the worker thread's"
    );
}

/// A request that does not restart (here a pause) stops the pass between
/// tiles; the pass goes on from its tiles once the worker runs again, and
/// the film is the one rendered without the pause, bit for bit.
#[test]
fn a_pause_in_the_middle_of_a_pass_keeps_its_tiles() {
    let mut request = request();
    request.stop_at_spp = Some(2);
    let whole = ProgressiveRenderer::between_frames(request.clone(), || {});
    while whole.run_between_frames(Duration::ZERO) {}
    let renderer = ProgressiveRenderer::between_frames(request.clone(), || {});
    // the preview, then five bands of 4 rows of the first pass
    for call in 0..6 {
        assert!(renderer.run_between_frames(Duration::ZERO), "call {call}");
    }
    let mut paused = request.clone();
    paused.paused = true;
    renderer.request(paused);
    assert!(
        !renderer.run_between_frames(Duration::ZERO),
        "paused: nothing to do"
    );
    renderer.request(request);
    let mut calls = 0;
    while renderer.run_between_frames(Duration::ZERO) {
        calls += 1;
    }
    let bands = 36 / 4;
    assert_eq!(calls, 2 * bands - 5, "the rest of the first pass, then one");
    let (got, expected) = (renderer.snapshot(), whole.snapshot());
    assert_eq!(got.term_samples, expected.term_samples);
    assert_eq!(got.restarts, 1, "a pause does not restart");
    let bits = |s: &Snapshot| -> Vec<[u32; 4]> {
        s.radiance.iter().map(|p| p.map(f32::to_bits)).collect()
    };
    assert!(bits(&got) == bits(&expected));
}
