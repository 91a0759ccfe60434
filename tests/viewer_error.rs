//! The viewer's error measurement, driven through its widgets in a headless
//! egui: a reference captured from the UI, the RMSE readout falling as the
//! image converges, the convergence curves, and the equal-time comparison.
#![cfg(feature = "gui")]

use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use lumiere::analysis::convergence::EstimatorKey;
use lumiere::app::{LumiereApp, ViewOptions};
use lumiere::course::LightSampling;
use lumiere::render::settings_override::SettingsOverride;
use lumiere::{BrdfOverride, RenderSettings, Term};

fn harness(width: u32, height: u32) -> Harness<'static, LumiereApp> {
    let options = ViewOptions {
        settings: RenderSettings {
            width,
            height,
            ..RenderSettings::default()
        },
        ..ViewOptions::default()
    };
    let mut harness = Harness::builder()
        .with_size([1200.0, 1400.0])
        .wgpu()
        .build_eframe(|cc| LumiereApp::new(cc, options).expect("the Cornell box loads"));
    harness.run_steps(2);
    harness
}

/// Steps the UI until `done` holds for the app (60 s at most).
fn wait_for(
    harness: &mut Harness<'static, LumiereApp>,
    what: &str,
    done: impl Fn(&LumiereApp) -> bool,
) {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        harness.step();
        if done(harness.state()) {
            return;
        }
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Clicks "Capture reference" at `spp` and waits for the reference.
fn capture_reference(harness: &mut Harness<'static, LumiereApp>, spp: u32) {
    harness.state_mut().errors.capture_spp = spp;
    if harness.query_by_label("Capture reference").is_none() {
        harness.get_by_label("Error").click();
        harness.run_steps(2);
    }
    harness.get_by_label("Capture reference").click();
    harness.run_steps(2);
    wait_for(harness, "the reference", |app| app.reference.is_some());
}

/// The error of A's image last measured: (spp, RMSE).
fn measured_a(app: &LumiereApp) -> Option<(u32, f64)> {
    app.errors.latest[0].map(|m| (m.point.samples_per_pixel, m.point.error.rmse))
}

#[test]
fn a_captured_reference_gives_a_falling_rmse_and_a_growing_curve() {
    let mut harness = harness(32, 32);
    capture_reference(&mut harness, 64);
    let reference = harness.state().reference.clone().unwrap();
    assert_eq!((reference.width, reference.height), (32, 32));
    assert!(reference.label.starts_with("64 spp"), "{}", reference.label);

    // from 1 spp again, held at 2 spp
    harness.state_mut().state.stop_at_spp = Some(2);
    harness.get_by_label("Restart render").click();
    wait_for(&mut harness, "the error at 2 spp", |app| {
        measured_a(app).is_some_and(|(spp, _)| spp == 2)
    });
    let (_, early) = measured_a(harness.state()).unwrap();
    harness.get_by_label_contains("A RMSE");
    let key = EstimatorKey::of(&harness.state().state.settings);
    let early_points = harness.state().errors.curves.get(&key).unwrap().len();

    // held at each octave in turn, so that every octave is measured however
    // fast the renderer runs against the UI's frames
    for stop in [4, 8, 16, 32, 64] {
        harness.state_mut().state.stop_at_spp = Some(stop);
        wait_for(&mut harness, &format!("the error at {stop} spp"), |app| {
            measured_a(app).is_some_and(|(spp, _)| spp == stop)
        });
    }
    let (spp, late) = measured_a(harness.state()).unwrap();
    // E[MSE] = σ²(1/N + 1/64): from 2 to ≥ 64 spp the RMSE falls to about a
    // quarter. Over 1,024 pixels each RMSE is known to a few per cent, so
    // chance cannot cross half, and an error that does not fall (1) fails.
    assert!(
        late < 0.5 * early,
        "RMSE {early:.4} at 2 spp, {late:.4} at {spp} spp"
    );
    let curve = harness.state().errors.curves.get(&key).unwrap();
    assert!(
        curve.len() > early_points,
        "the curve has {} points (had {early_points})",
        curve.len()
    );
    // every octave held is on the curve (the 2-spp point may belong to the
    // run before the restart, if that run stood at 2 spp when measured)
    let spps: Vec<u32> = curve.points().map(|p| p.samples_per_pixel).collect();
    for stop in [4, 8, 16, 32, 64] {
        assert!(spps.contains(&stop), "no point at {stop} spp: {spps:?}");
    }
    assert!(spps.windows(2).all(|w| w[0] < w[1]), "{spps:?}");

    // the plot window, and its table
    harness.get_by_label("Convergence plot").click();
    harness.run_steps(3);
    harness.get_by_label("Clear curves");
    harness.get_by_label("efficiency");

    // another set of terms: not what the reference is for
    harness.get_by_label("L2").click();
    harness.run_steps(3);
    assert!(!harness.state().state.settings.terms.contains(Term::L2));
    wait_for(&mut harness, "the error readout to go", |app| {
        app.errors.latest[0].is_none()
    });
    assert!(
        harness
            .query_all_by_label("reference is for other settings")
            .count()
            >= 1
    );
}

#[test]
fn compare_shows_a_left_and_b_right_for_equal_time() {
    let (width, height) = (32, 24);
    let mut harness = harness(width, height);
    harness.get_by_label("Comparison").click();
    harness.run_steps(2);
    harness.get_by_label("Compare").click();
    harness.run_steps(2);
    harness.get_by_label("B light sampling");
    assert_eq!(
        harness.state().compare.b,
        SettingsOverride {
            light_sampling: Some(LightSampling::Area),
            ..Default::default()
        }
    );
    wait_for(&mut harness, "both halves rendered", |app| {
        app.compare.composite().is_some_and(|c| {
            !c.a.preview
                && !c.b.preview
                && c.a.samples_per_pixel() >= 2
                && c.b.samples_per_pixel() >= 2
        })
    });
    assert_eq!(
        harness
            .get_all_by_label_contains("A: mis light sampling · ")
            .count(),
        1
    );
    assert_eq!(
        harness
            .get_all_by_label_contains("B: area light sampling · ")
            .count(),
        1
    );

    let composite = harness.state().compare.composite().unwrap().clone();
    let (a, b, image) = (&composite.a, &composite.b, &composite.image);
    assert_eq!(composite.divider_column, width / 2);
    assert_eq!((image.width, image.height), (width, height));
    let b_settings = &b.source.as_ref().unwrap().settings;
    assert_eq!(b_settings.light_sampling, LightSampling::Area);
    assert_ne!(b_settings.seed, a.source.as_ref().unwrap().settings.seed);
    let (mut left_differs, mut right_differs) = (false, false);
    for y in 0..height as usize {
        for x in 0..width as usize {
            let i = y * width as usize + x;
            let from = if x < width as usize / 2 { a } else { b };
            assert_eq!(image.radiance[i], from.radiance[i], "pixel {x},{y}");
            if a.radiance[i] != b.radiance[i] {
                if x < width as usize / 2 {
                    left_differs = true;
                } else {
                    right_differs = true;
                }
            }
        }
    }
    assert!(
        left_differs && right_differs,
        "A and B render the same image"
    );

    // with a reference both are measured, each on its own curve
    capture_reference(&mut harness, 16);
    wait_for(&mut harness, "both errors", |app| {
        app.errors.latest.iter().all(Option::is_some) && app.errors.curves.iter().count() == 2
    });
    assert_eq!(harness.get_all_by_label_contains(" RMSE ").count(), 2);

    // the divider moves the seam
    harness.state_mut().compare.divider = 0.25;
    wait_for(&mut harness, "the seam at a quarter", |app| {
        app.compare
            .composite()
            .is_some_and(|c| c.divider_column == width / 4)
    });

    // and off again: A alone, on every core
    harness.get_by_label("Compare").click();
    harness.run_steps(3);
    assert!(harness.state().compare.composite().is_none());
    assert!(harness.state().compare.snapshot().is_none());
}

/// B = A with mirrors for every material: the setting reaches B's worker
/// (and only it), each half is labelled with its material, and the halves
/// differ where the material matters: the floor, lit directly in A, is a
/// mirror in B that shows little with L0 + L1 + L2.
#[test]
fn compare_b_with_another_material_labels_each_half_with_its_own() {
    let (width, height) = (48, 36);
    let mut harness = harness(width, height);
    harness.get_by_label("Comparison").click();
    harness.run_steps(2);
    harness.get_by_label("Compare").click();
    harness.run_steps(2);
    harness.get_by_label("B light sampling").click();
    harness.run_steps(2);
    harness.get_by_label("as A (mis)").click();
    harness.run_steps(2);
    harness.get_by_label("B material").click();
    harness.run_steps(2);
    harness.get_by_label("mirror").click();
    harness.run_steps(2);
    assert_eq!(
        harness.state().compare.b,
        SettingsOverride {
            brdf: Some(BrdfOverride::Mirror),
            ..Default::default()
        }
    );
    wait_for(&mut harness, "both halves, B in mirrors", |app| {
        app.compare.composite().is_some_and(|c| {
            c.b.source
                .as_ref()
                .is_some_and(|s| s.settings.brdf == BrdfOverride::Mirror)
                && !c.a.preview
                && !c.b.preview
                && c.a.samples_per_pixel() >= 4
                && c.b.samples_per_pixel() >= 4
        })
    });
    harness.run_steps(2);
    assert_eq!(
        harness
            .get_all_by_label_contains("A: authored materials · ")
            .count(),
        1
    );
    assert_eq!(harness.get_all_by_label_contains("B: mirror · ").count(), 1);

    let composite = harness.state().compare.composite().unwrap().clone();
    let a_settings = composite.a.source.as_ref().unwrap().settings.clone();
    let b_settings = composite.b.source.as_ref().unwrap().settings.clone();
    assert_eq!(a_settings.brdf, BrdfOverride::Authored);
    // B is A but for its material and its seed
    assert_eq!(
        RenderSettings {
            brdf: a_settings.brdf,
            seed: a_settings.seed,
            ..b_settings.clone()
        },
        a_settings
    );
    assert_ne!(b_settings.seed, a_settings.seed);
    // the floor: the bottom sixth of the image, both halves
    let floor_mean = |snapshot: &lumiere::render::progressive::Snapshot| {
        let rows = height as usize * 5 / 6..height as usize;
        let pixels: Vec<f32> = rows
            .flat_map(|y| (0..width as usize).map(move |x| y * width as usize + x))
            .map(|i| {
                let p = snapshot.radiance[i];
                lumiere::course::color::luminance(glam::Vec3::new(p[0], p[1], p[2]))
            })
            .collect();
        pixels.iter().sum::<f32>() / pixels.len() as f32
    };
    let (a_floor, b_floor) = (floor_mean(&composite.a), floor_mean(&composite.b));
    assert!(
        b_floor < 0.5 * a_floor,
        "the floor: {a_floor} in Lambert (A), {b_floor} in mirrors (B)"
    );
    // and the composed image shows B right of the divider
    let image = &composite.image;
    let divider = composite.divider_column as usize;
    for y in 0..height as usize {
        for x in 0..width as usize {
            let i = y * width as usize + x;
            let from = if x < divider {
                &composite.a
            } else {
                &composite.b
            };
            assert_eq!(image.radiance[i], from.radiance[i], "pixel {x},{y}");
        }
    }
}
