//! Whole renders: term additivity, determinism across thread counts, and the
//! command line's outputs and exit codes.

mod common;

use std::process::Command;

use common::{render_film, small};
use lumiere::scene::builtin;
use lumiere::{Film, LightMode, RenderContext, RenderSettings, Term, TermSet};

/// L0, L1 and L2 rendered one at a time with one seed sum to the L0,L1,L2
/// render: each term's accumulator is filled by the same numbers either way.
#[test]
fn terms_rendered_apart_add_up_to_the_combined_render() {
    for mode in [LightMode::Authored, LightMode::Point] {
        let mut settings = small(48, 36, TermSet::COURSE);
        settings.light_mode = mode;
        // the pilot chooses the continuations for the terms asked: only a
        // fixed count makes the renders trace the same paths
        settings.auto_indirect_samples = false;
        let together = render_film(builtin::cornell(), &settings, 4).radiance(TermSet::COURSE);
        let mut summed = vec![glam::Vec3::ZERO; together.len()];
        for term in [Term::L0, Term::L1, Term::L2] {
            settings.terms = TermSet::only(term);
            let alone = render_film(builtin::cornell(), &settings, 4).radiance(TermSet::only(term));
            for (s, a) in summed.iter_mut().zip(alone) {
                *s += a;
            }
        }
        let worst = together
            .iter()
            .zip(&summed)
            .map(|(t, s)| (*t - *s).abs().max_element() / t.max_element().max(1e-3))
            .fold(0.0f32, f32::max);
        // the film sums a pixel's term means in f64 and rounds once to f32;
        // the test rounds each term to f32 and adds them in f32: at most 2.5
        // roundings of half an ulp apart, relative to the largest channel
        assert!(
            worst <= 3.0 * f32::EPSILON,
            "{mode}: separate terms differ from the combined render by {worst}"
        );
        assert!(together.iter().any(|p| p.max_element() > 0.0));
    }
}

/// The film is bit-identical whatever the number of threads.
#[test]
fn same_seed_same_image_for_any_thread_count() {
    let settings = small(40, 30, TermSet::ALL);
    let render_with = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| render_film(builtin::cornell(), &settings, 3).radiance(TermSet::ALL))
    };
    let one = render_with(1);
    for threads in [2, 3, 5] {
        let other = render_with(threads);
        let same = one
            .iter()
            .zip(&other)
            .all(|(a, b)| a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits));
        assert!(
            same,
            "{threads} threads gave a different image than 1 thread"
        );
    }
    let mut reseeded = settings.clone();
    reseeded.seed = 1;
    let different = render_film(builtin::cornell(), &reseeded, 3).radiance(TermSet::ALL);
    assert_ne!(one, different, "the seed must change the noise");
}

/// A pass rendered a few tiles at a time, as a page with one thread renders
/// between frames, adds to the film exactly what the parallel pass adds,
/// adaptive sampling included.
#[test]
fn a_pass_rendered_tile_by_tile_gives_the_same_film() {
    use lumiere::course::Adaptive;
    use lumiere::platform::time::Instant;
    use lumiere::render::{Pass, PassBuffer, Until, render_pass};

    let settings = RenderSettings {
        adaptive: Some(Adaptive {
            threshold: 0.3,
            min_samples: 2,
        }),
        ..small(40, 30, TermSet::ALL)
    };
    let context = RenderContext::new(builtin::cornell(), settings);
    let (mut whole, mut tiled) = (Film::new(40, 30), Film::new(40, 30));
    let (mut buffer, mut tiled_buffer) = (PassBuffer::default(), PassBuffer::default());
    let mut skipped = 0;
    for pass in 0..6 {
        let counts = render_pass(&context, &mut whole, pass, &mut buffer);
        skipped += counts.skipped.converged;
        // a deadline already passed: one tile per call
        let mut partial = Pass::new(&context, &tiled, pass);
        let mut calls = 1;
        let tiled_counts = loop {
            let until = Until {
                cancel: None,
                deadline: Some(Instant::now()),
            };
            match partial.render(&context, &mut tiled, &mut tiled_buffer, &until) {
                Some(counts) => break counts,
                None => calls += 1,
            }
        };
        assert_eq!(
            calls,
            30 / 4 + 1,
            "pass {pass}: one call per band of 4 rows"
        );
        assert_eq!(tiled_counts, counts, "pass {pass}: the rays traced");
    }
    assert!(skipped > 0, "adaptive sampling stopped some pixels");
    for term in Term::ALL {
        assert_eq!(whole.samples(term), tiled.samples(term), "{term:?}");
    }
    let bits = |film: &Film| -> Vec<[u32; 3]> {
        film.radiance(TermSet::ALL)
            .iter()
            .map(|p| p.to_array().map(f32::to_bits))
            .collect()
    };
    assert_eq!(bits(&whole), bits(&tiled), "the tiled passes differ");
}

fn lumiere() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lumiere"))
}

fn temp_path(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("lumiere-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn cli_renders_png_and_exr_and_prints_a_summary() {
    let png = temp_path("cornell.png");
    let out = lumiere()
        .args(["render", "cornell", "-o"])
        .arg(&png)
        .args([
            "--width", "32", "--height", "24", "--spp", "2", "--terms", "all",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary = String::from_utf8_lossy(&out.stdout);
    assert!(
        summary.contains("2 spp") && summary.contains("Mrays/s"),
        "summary: {summary}"
    );
    assert_eq!(common::invalid_samples(&out), 0);
    let image = image::open(&png).unwrap();
    assert_eq!((image.width(), image.height()), (32, 24));

    let exr = temp_path("cornell.exr");
    let out = lumiere()
        .args(["render", "-o"])
        .arg(&exr)
        .args([
            "--width", "16", "--height", "16", "--spp", "1", "--lights", "point", "--brdf", "phong",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(common::invalid_samples(&out), 0);
    let (w, h, pixels) = lumiere::render::export::load_exr(&exr).unwrap();
    assert_eq!((w, h), (16, 16));
    assert!(pixels.iter().any(|p| p.max_element() > 0.0));
}

#[test]
fn cli_rejects_bad_arguments_with_code_2() {
    let out = temp_path("x.png");
    for args in [
        vec!["--terms", "L7"],
        vec!["--lights", "lasers"],
        vec!["--brdf", "velvet"],
        vec!["--width", "0"],
        vec!["--spp", "-3"],
        vec!["--light-radius", "-1"],
        vec!["--phong-exponent", "nan"],
        vec!["--time", "0"],
    ] {
        let result = lumiere()
            .args(["render", "-o"])
            .arg(&out)
            .args(&args)
            .output()
            .unwrap();
        assert_eq!(result.status.code(), Some(2), "{args:?} should be refused");
        assert!(!result.stderr.is_empty());
    }
    let result = lumiere()
        .args(["render", "-o", "image.tiff"])
        .output()
        .unwrap();
    assert_eq!(result.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&result.stderr).contains(".exr or .png"));
}

#[test]
fn cli_reports_an_unloadable_scene_with_code_1() {
    let bad = temp_path("broken.gltf");
    std::fs::write(&bad, b"{ this is not json").unwrap();
    let out = temp_path("y.png");
    for scene in [bad.clone(), temp_path("missing.gltf")] {
        let result = lumiere()
            .arg("render")
            .arg(&scene)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        assert_eq!(result.status.code(), Some(1));
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert!(
            stderr.contains(&*scene.to_string_lossy()),
            "the error must name the file: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{stderr}");
    }
}

/// Every valid corpus file renders without invalid samples; every
/// invalid one makes the command line exit with 1 and a message naming it.
#[test]
fn corpus_files_render_or_fail_cleanly() {
    let corpus = common::corpus_dir();
    for path in common::gltf_files(&corpus.join("valid")) {
        let scene = lumiere::scene::gltf::load(&path).unwrap_or_else(|e| panic!("{e}"));
        // `render_film` asserts that the film's guard dropped no sample
        // (most corpus files have no light: their images are black)
        eprintln!("rendering {}", path.display());
        render_film(scene, &small(16, 12, TermSet::ALL), 2);
    }
    let out = temp_path("corpus.png");
    for path in common::gltf_files(&corpus.join("invalid")) {
        let result = lumiere()
            .arg("render")
            .arg(&path)
            .arg("-o")
            .arg(&out)
            .args(["--width", "8", "--height", "8", "--spp", "1"])
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&result.stderr);
        assert!(!stderr.contains("panicked"), "{}: {stderr}", path.display());
        let name = path.file_name().unwrap().to_string_lossy();
        match result.status.code() {
            Some(0) => assert!(
                stderr.contains("warning"),
                "{}: loaded without a warning",
                path.display()
            ),
            Some(1) => assert!(
                stderr.contains(&*name),
                "{}: the error must name the file: {stderr}",
                path.display()
            ),
            code => panic!("{}: exit code {code:?}", path.display()),
        }
    }
}

/// A screenshot's sidecar reproduces the image: `lumiere render --settings`
/// renders with its scene, camera, settings and sample count.
#[test]
fn cli_render_reproduces_a_sidecar() {
    use lumiere::render::sidecar::Sidecar;

    let scene = builtin::cornell();
    let mut camera = scene.default_camera();
    camera.world_from_camera = glam::Affine3A::from_translation(glam::Vec3::new(0.05, 0.0, 0.1))
        * camera.world_from_camera;
    let mut settings = small(24, 18, TermSet::only(Term::L1));
    settings.brdf = lumiere::BrdfOverride::Phong;
    settings.seed = 3;
    let sidecar = Sidecar {
        scene: "cornell".into(),
        camera: camera.clone(),
        settings: settings.clone(),
        display: Default::default(),
        samples_per_pixel: 3,
        edits: Default::default(),
        split: None,
    };
    let json = temp_path("shot.json");
    sidecar.save(&json).unwrap();
    let exr = temp_path("again.exr");
    let out = lumiere()
        .args(["render", "--settings"])
        .arg(&json)
        .arg("-o")
        .arg(&exr)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("3 spp"));
    assert_eq!(common::invalid_samples(&out), 0);

    let mut context = lumiere::RenderContext::new(scene, settings.clone());
    context.set_camera(&camera);
    let mut film = lumiere::Film::new(24, 18);
    lumiere::render::render(
        &context,
        &mut film,
        lumiere::render::Budget::Samples(3),
        |_| {},
    );
    let expected = film.radiance(settings.terms);
    let (_, _, pixels) = lumiere::render::export::load_exr(&exr).unwrap();
    assert_eq!(pixels, expected, "the sidecar's render differs");

    std::fs::write(&json, b"{\"scene\": 3}").unwrap();
    let out = lumiere()
        .args(["render", "--settings"])
        .arg(&json)
        .arg("-o")
        .arg(&exr)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("shot.json"));
}

/// A screenshot of an edited scene (one block's colour and roughness, the
/// light twice as bright) records its edits, and `render --settings`
/// renders the edited scene, bit for bit.
#[test]
fn cli_render_reproduces_the_scene_edits_of_a_sidecar() {
    use lumiere::render::sidecar::Sidecar;
    use lumiere::scene::edits::SceneEdits;

    let original = builtin::cornell();
    let mut edited = original.clone();
    let block = edited
        .objects
        .iter()
        .position(|o| {
            o.name.to_lowercase().contains("block") || o.name.to_lowercase().contains("box")
        })
        .unwrap_or(0) as u32;
    let material = edited.own_material(block);
    material.base_color = glam::Vec3::new(0.1, 0.2, 0.8);
    material.roughness = 0.3;
    let light = edited
        .materials
        .iter()
        .position(|m| m.is_emissive())
        .unwrap();
    edited.materials[light].emission *= 2.0;
    let edits = SceneEdits::between(&original, &edited);
    assert!(!edits.objects.is_empty());
    // the edits applied to the file as loaded give the edited scene back
    let mut again = builtin::cornell();
    edits.apply(&mut again).unwrap();
    assert_eq!(SceneEdits::between(&original, &again), edits);

    let settings = small(24, 18, TermSet::COURSE);
    let sidecar = Sidecar {
        scene: "cornell".into(),
        camera: original.default_camera(),
        settings: settings.clone(),
        display: Default::default(),
        samples_per_pixel: 2,
        edits,
        split: None,
    };
    let json = temp_path("edited.json");
    sidecar.save(&json).unwrap();
    let exr = temp_path("edited.exr");
    let out = lumiere()
        .args(["render", "--settings"])
        .arg(&json)
        .arg("-o")
        .arg(&exr)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let expected = render_film(edited, &settings, 2).radiance(settings.terms);
    let unedited = render_film(original, &settings, 2).radiance(settings.terms);
    let (_, _, pixels) = lumiere::render::export::load_exr(&exr).unwrap();
    assert_eq!(
        pixels, expected,
        "the sidecar's render is not the edited scene's"
    );
    assert_ne!(pixels, unedited);

    // an edit of an object the scene does not have is refused, naming the file
    let mut wrong = sidecar.clone();
    wrong.edits.objects[0].object = 999;
    wrong.save(&json).unwrap();
    let out = lumiere()
        .args(["render", "--settings"])
        .arg(&json)
        .arg("-o")
        .arg(&exr)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("edited.json") && stderr.contains("object 999"),
        "{stderr}"
    );
}

/// Rays are filed under the lowest selected term they serve: an L2-only
/// render traces its camera and first-bounce rays for L2, and no shadow ray
/// at the first hit.
#[test]
fn rays_are_counted_under_the_terms_they_serve() {
    let count = |terms: TermSet| {
        common::render_with_stats(builtin::cornell(), &small(16, 12, terms), 2)
            .1
            .rays
    };
    let l0 = count(TermSet::only(Term::L0));
    assert_eq!(l0.per_term, [l0.camera, 0, 0, 0]);
    assert_eq!((l0.shadow, l0.bounce), (0, 0), "L0 needs camera rays only");
    let l2 = count(TermSet::only(Term::L2));
    assert_eq!(l2.per_term[0] + l2.per_term[1] + l2.per_term[3], 0);
    assert_eq!(l2.per_term[2], l2.total());
    let all = count(TermSet::ALL);
    assert_eq!(all.per_term.iter().sum::<u64>(), all.total());
    assert!(all.per_term.iter().all(|&n| n > 0));
}

#[test]
fn cli_refuses_a_film_too_large_for_memory_naming_its_size() {
    let out = lumiere()
        .args(["render", "cornell", "-o"])
        .arg(temp_path("huge.png"))
        .args(["--width", "16384", "--height", "16384", "--terms", "all"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {stderr}");
    assert!(
        stderr.contains("a 16384×16384 image with 4 term(s) needs about 56.0 GiB of film")
            && stderr.contains("224 bytes per pixel")
            && stderr.contains("the limit is"),
        "stderr: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "stderr: {stderr}");
}

#[test]
fn cli_refuses_absurd_sample_counts() {
    for args in [
        ["--spp", "0"],
        ["--spp", "4294967296"],
        ["--spp", "2147483648"],
        ["--light-samples", "0"],
    ] {
        let out = lumiere()
            .args(["render", "cornell", "-o"])
            .arg(temp_path("absurd.png"))
            .args(args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains(&format!("invalid value '{}' for '{}", args[1], args[0])),
            "{args:?}: {stderr}"
        );
    }
}

#[test]
fn view_and_strip_refuse_a_film_too_large_for_memory() {
    let strip = temp_path("huge-strip.png");
    let strip = strip.to_str().unwrap();
    for args in [
        vec!["view", "--width", "16384", "--height", "16384"],
        vec![
            "strip",
            "cornell",
            "-o",
            strip,
            "--spp",
            "1,4",
            "--tile-width",
            "16384",
            "--tile-height",
            "16384",
        ],
    ] {
        // a build without the viewer refuses `view` for that reason instead
        if args[0] == "view" && !cfg!(feature = "gui") {
            continue;
        }
        let out = lumiere().args(&args).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains("GiB of film") && stderr.contains("bytes per pixel"),
            "{args:?}: {stderr}"
        );
    }
}
