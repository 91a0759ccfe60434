//! `lumiere bench`: a tiny run's files and columns, the time-to-threshold
//! interpolation, peer CSV parsing, the reference's cache key, the glTF
//! writer, and the throughput replay tracing exactly the renderer's rays.
//! Nothing here is timed.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use lumiere::course::Choice;
use lumiere::course::{LightSampling, Sampler};
use lumiere::render::{Budget, render};
use lumiere::scene::{builtin, gltf};
use lumiere::tools::bench::csv::{ErrorRow, parse_error_csv};
use lumiere::tools::bench::error_curve::{
    ErrorBench, Estimator, TimeRatio, reference_file_name, sample_counts, summarize, time_to_relmse,
};
use lumiere::tools::bench::run::{BenchConfig, BenchReport, run};
use lumiere::tools::bench::scaling::{ScalingBench, procedural_scene, write_gltf};
use lumiere::tools::bench::throughput::{RayKind, record_segments, replay_matches};
use lumiere::tools::bench::{Section, Silent};
use lumiere::{Film, RenderContext, RenderSettings, Term, TermSet};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lumiere-bench-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn tiny_settings() -> RenderSettings {
    RenderSettings {
        width: 32,
        height: 32,
        ..RenderSettings::default()
    }
}

fn tiny_config() -> BenchConfig {
    // direct lighting only: a 32×32 image of L2 has fireflies that make a
    // few-spp relMSE curve jump about
    let settings = RenderSettings {
        terms: "L0,L1".parse().unwrap(),
        ..tiny_settings()
    };
    BenchConfig {
        sections: Section::all(),
        error: ErrorBench {
            scene: "cornell".into(),
            settings: settings.clone(),
            estimators: Estimator::all_pairs(
                &[LightSampling::Mis, LightSampling::Area],
                &[Sampler::Independent],
                None,
            ),
            max_spp: 16,
            extend_spp: 16,
            reference_spp: 256,
            reference: None,
        },
        peer: None,
        peer_csvs: Vec::new(),
        throughput_passes: 1,
        throughput_repeats: 1,
        scaling: ScalingBench {
            triangle_counts: vec![200, 2000],
            gltf_triangles: 500,
            resolutions: vec![16, 24],
            thread_counts: vec![1, 2],
            triangle_image_size: 16,
            spp: 1,
            repeats: 1,
            settings,
        },
    }
}

fn csv_rows(path: &Path) -> (String, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (header, rows)
}

#[test]
fn a_tiny_bench_writes_every_file_with_its_columns() {
    let folder = scratch("tiny");
    let report = run(&tiny_config(), &folder, &Silent).unwrap();
    for name in [
        "error.csv",
        "error.png",
        "throughput.csv",
        "scaling.csv",
        "scaling.png",
    ] {
        assert!(folder.join(name).is_file(), "{name} missing");
    }
    let (header, rows) = csv_rows(&folder.join("error.csv"));
    assert_eq!(header, "renderer,estimator,spp,seconds,rmse,relmse");
    assert_eq!(rows.len(), 2 * sample_counts(16).len());
    for estimator in ["mis/independent", "area/independent"] {
        let curve: Vec<&Vec<String>> = rows.iter().filter(|r| r[1] == estimator).collect();
        let spp: Vec<u32> = curve.iter().map(|r| r[2].parse().unwrap()).collect();
        assert_eq!(spp, [1, 2, 4, 8, 16]);
        let relmse: Vec<f64> = curve.iter().map(|r| r[5].parse().unwrap()).collect();
        assert!(relmse[0] > relmse[4], "{estimator}: relMSE {relmse:?}");
    }
    let (header, rows) = csv_rows(&folder.join("throughput.csv"));
    assert_eq!(header, "measure,rays_of,rays,seconds,mrays_per_second");
    assert_eq!(rows[0][0], "renderer");
    assert_eq!(rows[1][0], "traversal");
    assert_eq!(
        rows[0][2], rows[1][2],
        "the replay traces as many rays as the renderer"
    );
    // the Cornell box's queries test blocks: the CWBVH replays the same rays too
    let cwbvh = rows.iter().find(|r| r[0] == "cwbvh").expect("a cwbvh row");
    assert_eq!(cwbvh[2], rows[0][2], "{cwbvh:?}");
    let (header, rows) = csv_rows(&folder.join("scaling.csv"));
    assert!(header.starts_with("axis,triangles,width,height,threads,load_seconds,build_seconds"));
    let axes: Vec<&str> = rows.iter().map(|r| r[0].as_str()).collect();
    assert_eq!(
        axes,
        [
            "triangles",
            "triangles",
            "gltf-triangles",
            "resolution",
            "resolution",
            "threads",
            "threads"
        ]
    );
    let threads: Vec<&str> = rows[5..].iter().map(|r| r[4].as_str()).collect();
    assert_eq!(threads, ["1", "2"]);
    // the triangle rows replay their rays; the others leave the column empty
    assert!(header.ends_with(",renderer_over_traversal"), "{header}");
    for row in &rows {
        let ratio = row.last().unwrap();
        if row[0].ends_with("triangles") {
            let ratio: f64 = ratio.parse().unwrap();
            assert!(ratio > 0.0 && ratio.is_finite(), "{row:?}");
        } else {
            assert!(ratio.is_empty(), "{row:?}");
        }
    }
    // the glTF file is removed after loading
    assert!(!folder.join("scaling-500.gltf").exists());
    assert!(report.summary().contains("renderer ÷ traversal"));
    // the machine comes first: a ratio to a vectorised peer depends on its vectors
    let first_line = report.summary().lines().next().unwrap_or("").to_string();
    assert!(
        first_line.starts_with("machine: ") && first_line.contains(" threads, widest vectors "),
        "{first_line}"
    );

    // a second run finds the cached reference instead of rendering one
    let references = |dir: &Path| {
        std::fs::read_dir(dir)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .unwrap()
                    .file_name()
                    .to_string_lossy()
                    .starts_with("reference-")
            })
            .count()
    };
    let mut config = tiny_config();
    config.sections = vec![Section::Error];
    run(&config, &folder, &Silent).unwrap();
    assert_eq!(references(&folder), 1);
    std::fs::remove_dir_all(&folder).unwrap();
}

#[test]
fn time_to_threshold_is_log_log_interpolation() {
    // relMSE = 0.1 / t: a line of slope −1 in log-log, crossing 0.03 at t = 10/3
    let curve: Vec<(f64, f64)> = [1.0, 2.0, 4.0, 8.0].iter().map(|&t| (t, 0.1 / t)).collect();
    let t = time_to_relmse(&curve, 0.03).unwrap();
    assert!((t - 10.0 / 3.0).abs() < 1e-9, "{t}");
    // exactly on a measured point
    assert!((time_to_relmse(&curve, 0.025).unwrap() - 4.0).abs() < 1e-9);
    // already below at the first point, never reached, empty
    assert_eq!(time_to_relmse(&curve, 0.5), Some(1.0));
    assert_eq!(time_to_relmse(&curve, 1e-3), None);
    assert_eq!(time_to_relmse(&[], 1e-3), None);
    // a noisy curve: the first crossing counts
    let noisy = [(1.0, 0.1), (2.0, 0.005), (4.0, 0.02), (8.0, 0.001)];
    let t = time_to_relmse(&noisy, 0.01).unwrap();
    assert!(t > 1.0 && t < 2.0, "{t}");
}

#[test]
fn sample_counts_double_up_to_the_last() {
    assert_eq!(sample_counts(1), [1]);
    assert_eq!(sample_counts(8), [1, 2, 4, 8]);
    assert_eq!(sample_counts(12), [1, 2, 4, 8, 12]);
}

#[test]
fn an_extended_curve_doubles_until_the_lowest_threshold_or_the_limit() {
    use lumiere::tools::bench::error_curve::next_extended_count;
    assert_eq!(next_extended_count(16, 2e-3, 64), Some(32));
    assert_eq!(next_extended_count(32, 2e-3, 64), Some(64));
    assert_eq!(next_extended_count(64, 2e-3, 64), None, "the limit");
    assert_eq!(next_extended_count(48, 2e-3, 64), None, "96 is past it");
    assert_eq!(next_extended_count(16, 1e-3, 64), None, "reached");
    assert_eq!(next_extended_count(u32::MAX / 2 + 1, 1.0, u32::MAX), None);

    // curves that start above 10⁻³ go on past --max-spp: Sobol's reaches
    // it on the way, the independent numbers' stops at the limit
    let folder = scratch("extended");
    let mut config = tiny_config();
    config.sections = vec![Section::Error];
    config.error.estimators = Estimator::all_pairs(
        &[LightSampling::Mis],
        &[Sampler::Independent, Sampler::Sobol],
        None,
    );
    config.error.max_spp = 2;
    config.error.extend_spp = 128;
    config.error.reference_spp = 4096;
    let report = run(&config, &folder, &Silent).unwrap();
    let curve = |estimator: &str| -> Vec<(u32, f64)> {
        report
            .error_rows
            .iter()
            .filter(|r| r.estimator == estimator)
            .map(|r| (r.spp, r.relmse))
            .collect()
    };
    let (independent, sobol) = (curve("mis/independent"), curve("mis/sobol"));
    for points in [&independent, &sobol] {
        let spp: Vec<u32> = points.iter().map(|p| p.0).collect();
        let doubling: Vec<u32> = (0..spp.len()).map(|k| 1 << k).collect();
        assert_eq!(spp, doubling, "{points:?}");
        assert!(
            points[..points.len() - 1].iter().all(|p| p.1 > 1e-3),
            "{points:?}"
        );
    }
    let (last_independent, last_sobol) = (independent.last().unwrap(), sobol.last().unwrap());
    assert_eq!(last_independent.0, 128, "{independent:?}");
    assert!(last_independent.1 > 1e-3, "{independent:?}");
    assert!(last_sobol.0 < 128 && last_sobol.1 <= 1e-3, "{sobol:?}");
    let summary = &report.curves;
    let sobol_summary = summary.iter().find(|c| c.estimator == "mis/sobol").unwrap();
    assert!(sobol_summary.seconds_to[1].is_some(), "{summary:?}");
    std::fs::remove_dir_all(&folder).unwrap();
}

#[test]
fn peer_rows_merge_into_the_summary() {
    let text = "renderer,estimator,spp,seconds,rmse,relmse\n\
                mitsuba,path,1,0.5,0.3,0.1\n\
                mitsuba,path,4,2.0,0.15,0.025\n\
                mitsuba,path,16,8.0,0.07,0.00625\n";
    let mut rows = parse_error_csv(text, Path::new("peer.csv")).unwrap();
    assert_eq!(rows.len(), 3);
    assert_eq!(rows[2].spp, 16);
    rows.push(ErrorRow {
        renderer: "lumiere".into(),
        estimator: "mis/independent".into(),
        spp: 1,
        seconds: 0.1,
        rmse: 0.3,
        relmse: 0.001,
    });
    let curves = summarize(&rows);
    assert_eq!(curves.len(), 2);
    assert_eq!(curves[0].renderer, "mitsuba");
    // 0.025 → 0.00625 over 2 s → 8 s: slope −1, so 1e-2 at 5 s; 1e-3 not reached
    assert!((curves[0].seconds_to[0].unwrap() - 5.0).abs() < 1e-9);
    assert_eq!(curves[0].seconds_to[1], None);
    assert_eq!(curves[1].seconds_to[1], Some(0.1));
}

/// When only one curve reaches a threshold, the ratio is bounded by the
/// other's last render, and the summary says which way.
#[test]
fn a_threshold_one_curve_misses_gives_a_bounded_ratio() {
    let row = |renderer: &str, spp, seconds, relmse| ErrorRow {
        renderer: String::from(renderer),
        estimator: "e".into(),
        spp,
        seconds,
        rmse: 0.1,
        relmse,
    };
    // the peer reaches 1e-2 at 5 s (as above) but not 1e-3 by its last render, at 8 s
    let peer_rows = [
        row("mitsuba", 4, 2.0, 0.025),
        row("mitsuba", 16, 8.0, 0.00625),
    ];
    let fast = summarize(&[row("lumiere", 1, 0.5, 0.02), row("lumiere", 4, 2.0, 0.0005)]);
    let slow = summarize(&[row("lumiere", 1, 4.0, 0.2), row("lumiere", 4, 16.0, 0.05)]);
    let peer = &summarize(&peer_rows)[0];
    assert_eq!(peer.last_seconds, 8.0);
    let TimeRatio::Measured(at_1e2) = TimeRatio::of(&fast[0], peer, 0) else {
        panic!("both reach 1e-2");
    };
    assert!((at_1e2 - fast[0].seconds_to[0].unwrap() / 5.0).abs() < 1e-12);
    let TimeRatio::Below(bound) = TimeRatio::of(&fast[0], peer, 1) else {
        panic!("only lumiere reaches 1e-3");
    };
    assert!((bound - fast[0].seconds_to[1].unwrap() / 8.0).abs() < 1e-12);
    let TimeRatio::Above(above) = TimeRatio::of(&slow[0], peer, 0) else {
        panic!("only the peer reaches 1e-2");
    };
    assert!((above - 16.0 / peer.seconds_to[0].unwrap()).abs() < 1e-12);
    assert_eq!(TimeRatio::of(&slow[0], peer, 1), TimeRatio::Unknown);

    let mut curves = fast;
    curves.push(peer.clone());
    let report = BenchReport {
        curves,
        reference: Some("64 spp".into()),
        ..BenchReport::default()
    };
    let summary = report.summary();
    assert!(summary.contains("lumiere ÷ mitsuba e"), "{summary}");
    assert!(summary.contains("reference: 64 spp"), "{summary}");
    assert!(summary.contains(&format!("{at_1e2:.2}")), "{summary}");
    assert!(summary.contains(&format!("< {bound:.2}")), "{summary}");
    assert!(summary.contains("only lumiere reached τ"), "{summary}");
}

#[test]
fn a_malformed_peer_csv_is_a_clear_error() {
    let path = Path::new("peer.csv");
    let header = parse_error_csv("renderer,spp,seconds\nmitsuba,1,0.5\n", path).unwrap_err();
    assert!(
        header.to_string().contains("peer.csv: line 1: header"),
        "{header}"
    );
    let number = parse_error_csv(
        "renderer,estimator,spp,seconds,rmse,relmse\nmitsuba,path,1,fast,0.3,0.1\n",
        path,
    )
    .unwrap_err();
    assert!(
        number.to_string().contains("line 2: seconds 'fast'"),
        "{number}"
    );
    let fields = parse_error_csv(
        "renderer,estimator,spp,seconds,rmse,relmse\nmitsuba,path,1\n",
        path,
    )
    .unwrap_err();
    assert!(
        fields.to_string().contains("3 fields, expected 6"),
        "{fields}"
    );
    assert!(
        parse_error_csv("", path)
            .unwrap_err()
            .to_string()
            .contains("empty")
    );
}

#[test]
fn a_malformed_peer_csv_fails_the_command_with_its_name() {
    let folder = scratch("peer-cli");
    let peer = folder.join("peer.csv");
    std::fs::write(&peer, "renderer,estimator,spp\nmitsuba,path,1\n").unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args([
            "bench",
            "--only",
            "error",
            "--width",
            "8",
            "--height",
            "8",
            "--max-spp",
            "1",
            "--reference-spp",
            "1",
            "-o",
        ])
        .arg(&folder)
        .arg("--peer-csv")
        .arg(&peer)
        .output()
        .unwrap();
    assert_eq!(output.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("peer.csv: line 1: header"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let bad_section = Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(["bench", "--only", "speed", "-o"])
        .arg(&folder)
        .output()
        .unwrap();
    assert_eq!(bad_section.status.code(), Some(2));
    let message = String::from_utf8_lossy(&bad_section.stderr);
    assert!(
        message.contains("'--only <ONLY>': unknown value 'speed'")
            && message.contains("error, throughput, scaling"),
        "{message}"
    );
    // curves extended past their reference would measure the reference's own noise
    let past_reference = Command::new(env!("CARGO_BIN_EXE_lumiere"))
        .args(["bench", "--only", "error", "--reference-spp", "64"])
        .args(["--max-spp", "16", "--extend-spp", "128", "-o"])
        .arg(&folder)
        .output()
        .unwrap();
    assert_eq!(past_reference.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&past_reference.stderr);
    assert!(
        stderr.contains("--reference-spp 64 is below --extend-spp 128"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&folder).unwrap();
}

#[test]
fn the_reference_cache_key_follows_the_radiance_not_the_estimator() {
    let settings = tiny_settings();
    let key = reference_file_name("cornell", &settings, 64);
    let other_estimator = RenderSettings {
        light_sampling: LightSampling::Area,
        sampler: Sampler::Sobol,
        seed: 7,
        ..settings.clone()
    };
    assert_eq!(reference_file_name("cornell", &other_estimator, 64), key);
    let other_terms = RenderSettings {
        terms: TermSet::only(Term::L1),
        ..settings.clone()
    };
    assert_ne!(reference_file_name("cornell", &other_terms, 64), key);
    let other_size = RenderSettings {
        width: 33,
        ..settings.clone()
    };
    assert_ne!(reference_file_name("cornell", &other_size, 64), key);
    assert_ne!(reference_file_name("cornell", &settings, 128), key);
}

#[test]
fn the_written_gltf_loads_as_the_same_scene() {
    let folder = scratch("gltf");
    let scene = procedural_scene(3000);
    let path = folder.join("sphere.gltf");
    write_gltf(&scene, &path).unwrap();
    let loaded = gltf::load(&path).unwrap();
    assert_eq!(loaded.triangles.len(), scene.triangles.len());
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let emitters = |s: &lumiere::Scene| {
        s.triangles
            .iter()
            .filter(|t| s.materials[t.material as usize].is_emissive())
            .count()
    };
    assert_eq!(emitters(&loaded), 2);
    let emission = loaded
        .materials
        .iter()
        .map(|m| m.emission.x)
        .fold(0.0, f32::max);
    assert!((emission - 8.0).abs() < 1e-5, "{emission}");
    std::fs::remove_dir_all(&folder).unwrap();
}

/// The replay traces the rays the renderer traced, as many of each kind,
/// and each finds what the renderer found.
#[test]
fn the_replay_traces_the_renderers_rays_and_finds_the_same_hits() {
    for light_sampling in [LightSampling::Mis, LightSampling::Brdf] {
        let settings = RenderSettings {
            width: 16,
            height: 12,
            terms: TermSet::ALL,
            light_sampling,
            light_samples: 2,
            ..RenderSettings::default()
        };
        let context = RenderContext::new(Arc::new(builtin::cornell()), settings);
        let mut film = Film::new(16, 12);
        let stats = render(&context, &mut film, Budget::Samples(2), |_| {});
        common::assert_no_invalid_samples(&stats.rays);
        let segments = record_segments(&context, 2);
        let count = |kind: RayKind| {
            segments
                .iter()
                .filter(|s| RayKind::of(s.kind) == kind)
                .count() as u64
        };
        assert_eq!(count(RayKind::Camera), stats.rays.camera);
        assert_eq!(count(RayKind::Shadow), stats.rays.shadow);
        assert_eq!(count(RayKind::Bounce), stats.rays.bounce);
        assert_eq!(count(RayKind::Gather), stats.rays.gather);
        assert!(stats.rays.shadow + stats.rays.gather > 0);
        let mismatches = segments
            .iter()
            .filter(|s| !replay_matches(&context, s))
            .count();
        assert_eq!(
            mismatches,
            0,
            "{light_sampling}: of {} rays",
            segments.len()
        );
    }
}

#[test]
fn with_adaptive_sampling_every_curve_is_measured_uniform_and_adaptive() {
    use lumiere::course::Adaptive;
    let adaptive = Adaptive {
        threshold: 0.01,
        min_samples: 128,
    };
    let estimators = Estimator::all_pairs(
        &[LightSampling::Mis],
        &[Sampler::Independent, Sampler::Stratified],
        Some(adaptive),
    );
    let labels: Vec<String> = estimators.iter().map(Estimator::label).collect();
    assert_eq!(
        labels,
        [
            "mis/independent",
            "mis/independent/adaptive 0.01",
            "mis/stratified",
            "mis/stratified/adaptive 0.01"
        ]
    );
    assert_eq!(estimators[1].adaptive, Some(adaptive));
    assert_eq!(
        Estimator::all_pairs(&[LightSampling::Mis], &[Sampler::Independent], None).len(),
        1
    );
}

/// The peer renders the scene lumiere renders: `--brdf` (Phong with its
/// exponent and ks) and `--lights area` (with the radius lumiere uses) or
/// `--lights point` pass to it; the estimator's settings change nothing.
#[test]
fn the_peer_renders_lumieres_overrides() {
    use lumiere::course::{BrdfOverride, LightMode};
    use lumiere::tools::bench::peer::scene_overrides;
    let scene = builtin::cornell();
    let mut settings = RenderSettings {
        sampler: Sampler::Sobol,
        light_sampling: LightSampling::Area,
        indirect_samples: 4,
        seed: 7,
        ..RenderSettings::default()
    };
    assert!(scene_overrides(&scene, &settings).is_empty());

    settings.brdf = BrdfOverride::Mirror;
    settings.light_mode = LightMode::Area;
    let arguments = scene_overrides(&scene, &settings);
    let radius = 0.02 * scene.bounds().diagonal();
    assert_eq!(
        arguments[..3],
        [
            "--sphere-lights".to_string(),
            radius.to_string(),
            "--brdf".into()
        ]
    );
    assert_eq!(arguments[3], "mirror");
    settings.light_radius = Some(0.125);
    settings.brdf = BrdfOverride::Lambert;
    let arguments = scene_overrides(&scene, &settings);
    assert_eq!(arguments, ["--sphere-lights", "0.125", "--brdf", "lambert"]);

    // lumiere's Phong is a Mitsuba BSDF of the script's: its parameters go along
    settings.brdf = BrdfOverride::Phong;
    settings.phong_exponent = 12.5;
    settings.phong_specular = 0.4;
    let arguments = scene_overrides(&scene, &settings);
    assert_eq!(
        arguments[2..],
        [
            "--brdf",
            "phong",
            "--phong-exponent",
            "12.5",
            "--phong-specular",
            "0.4"
        ]
    );

    // and lumiere's cosine points are a Mitsuba emitter of the script's
    settings.light_mode = LightMode::Point;
    settings.brdf = BrdfOverride::Authored;
    let arguments = scene_overrides(&scene, &settings);
    assert_eq!(arguments, ["--point-emitters"]);
}

/// The reference spends the rays of its sample budget with Sobol numbers
/// and the pilot's continuations: fewer samples of M continuations each
/// where the continuations are noisy (a power of two), all the budget's
/// samples with one where there is nothing to split.
#[test]
fn the_reference_spends_its_budget_on_the_least_noisy_estimator() {
    use lumiere::tools::bench::error_curve::reference_plan;
    let scene = Arc::new(builtin::cornell());
    let settings = RenderSettings {
        width: 32,
        height: 32,
        ..RenderSettings::default()
    };
    let (context, spp) = reference_plan(&scene, &settings, 4096);
    assert_eq!(context.settings.sampler, Sampler::Sobol);
    // the Cornell box's walls split: 1.94 continuations on average with
    // these numbers, where a pilot that split nothing would give 1
    let continuations = context.continuations.mean();
    assert!(continuations >= 1.5, "{:?}", context.continuations);
    assert!(spp.is_power_of_two() && spp < 4096, "{spp}");
    // the rays of 4096 samples with one continuation, to the nearest power of two
    assert!(spp as f64 * continuations >= 4096.0 / 2.0, "{spp}");
    assert_ne!(context.settings.seed, settings.seed);

    let direct = RenderSettings {
        terms: "L0,L1".parse::<TermSet>().unwrap(),
        ..settings
    };
    let (context, spp) = reference_plan(&scene, &direct, 1000);
    assert_eq!((context.continuations.mean(), spp), (1.0, 1000));
}

#[test]
fn a_scene_without_light_measures_no_curve_and_says_why() {
    // one triangle, no light: the reference is black and every render matches it
    let folder = scratch("black");
    let mut config = tiny_config();
    config.sections = vec![Section::Error];
    config.error.scene = "tests/data/gltf/cameras.gltf".into();
    config.error.max_spp = 4;
    config.error.reference_spp = 16;
    config.peer = Some(lumiere::tools::bench::peer::Peer::Mitsuba);
    let report = run(&config, &folder, &Silent).unwrap();
    assert!(report.curves.is_empty(), "{:?}", report.curves);
    assert_eq!(report.notes.len(), 1, "{:?}", report.notes);
    assert!(report.notes[0].contains("the reference is black"));
    let summary = report.summary();
    assert!(summary.contains("error curves not measured"), "{summary}");
    assert!(!summary.contains("0.00 s"), "{summary}");
    // the files are still written: the reference, an empty CSV, the plot's frame
    let (header, rows) = csv_rows(&folder.join("error.csv"));
    assert_eq!(header, "renderer,estimator,spp,seconds,rmse,relmse");
    assert!(rows.is_empty());
    assert!(folder.join("error.png").is_file());
}

#[test]
fn a_file_without_a_camera_gives_the_peer_lumieres_framing_camera() {
    use lumiere::scene::Projection;
    use lumiere::tools::bench::peer::camera_arguments;
    // the Cornell box has its camera: the peer reads it from the file
    assert_eq!(camera_arguments(&builtin::cornell()), Ok(vec![]));

    let mut scene = builtin::cornell();
    scene.cameras.clear();
    let arguments = camera_arguments(&scene).unwrap();
    assert_eq!(arguments[0], "--camera");
    let values: Vec<f32> = arguments[1]
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(values.len(), 13);
    let framing = scene.default_camera();
    let world = framing.world_from_camera;
    // rows of [R | t]: row i holds the i-th coordinate of each axis, then of the origin
    for row in 0..3 {
        let expected = [
            world.matrix3.x_axis[row],
            world.matrix3.y_axis[row],
            world.matrix3.z_axis[row],
            world.translation[row],
        ];
        assert_eq!(values[4 * row..4 * row + 4], expected, "row {row}");
    }
    let Projection::Perspective { yfov } = framing.projection else {
        panic!("the framing camera is a perspective one");
    };
    assert_eq!(values[12], yfov);
    // the framing camera stands back from the box, on its +z side
    assert!(values[11] > scene.bounds().max.z, "{values:?}");
}
