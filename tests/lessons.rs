//! Lessons: the built-in lesson loads and every step is a valid view; a
//! broken lesson file is refused with its line and field; `lumiere lessons`
//! lists the lessons and scenes; the viewer refuses a lesson it cannot open.

mod common;

use std::process::Command;

use lumiere::BrdfOverride;
use lumiere::course::{Integrator, LightMode, Sampler};
use lumiere::lesson::{Lang, Lesson};
use lumiere::render::display::Layout;
use lumiere::{Term, TermSet};

fn lumiere() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lumiere"))
}

/// A lesson of one step whose settings table holds `settings`.
fn one_step(settings: &str) -> String {
    format!(
        r#"name = "test"
title = {{ fr = "Essai", en = "Test" }}

[[steps]]
slug = "only"
formula = "L = L₀"
title = {{ fr = "Un", en = "One" }}
caption = {{ fr = "Une phrase.", en = "A sentence." }}
[steps.settings]
{settings}
"#
    )
}

/// The problem a lesson's text is refused with.
fn refusal(text: &str) -> String {
    Lesson::parse(text, "test.toml")
        .expect_err("a broken lesson must be refused")
        .to_string()
}

#[test]
fn the_built_in_lesson_follows_the_lecture_in_at_least_twelve_valid_steps() {
    let lesson = Lesson::load("simulation-notions").unwrap_or_else(|e| panic!("{e}"));
    assert!(lesson.steps.len() >= 12, "{} steps", lesson.steps.len());
    for (i, step) in lesson.steps.iter().enumerate() {
        for lang in [Lang::Fr, Lang::En] {
            assert!(!step.title.get(lang).trim().is_empty(), "step {}", i + 1);
            assert!(!step.caption.get(lang).trim().is_empty(), "step {}", i + 1);
        }
        assert!(!step.formula.trim().is_empty(), "step {}", i + 1);
        let view = lesson
            .view(i, 640, 480)
            .unwrap_or_else(|e| panic!("step {}: {e}", i + 1));
        assert_eq!((view.settings.width, view.settings.height), (640, 480));
        // every source a step gives a quality to is a source of its scene
        let scene = lumiere::scene::builtin::load(&view.scene).unwrap();
        lumiere::transport::sources::check(&view.settings, &scene)
            .unwrap_or_else(|e| panic!("step {}: {e}", i + 1));
    }
    // the lecture's "a quality for each source": steps with counts that differ, and one with a source off
    let qualities: Vec<_> = (0..lesson.steps.len())
        .map(|i| lesson.view(i, 640, 480).unwrap().settings.sources)
        .collect();
    assert!(qualities.iter().any(|q| {
        let counts: Vec<_> = q.iter().filter_map(|s| s.samples).collect();
        counts.windows(2).any(|w| w[0] != w[1])
    }));
    assert!(qualities.iter().flatten().any(|s| !s.on));
    // the lecture's order: emission, direct, indirect first
    let first_terms: Vec<TermSet> = (0..3)
        .map(|i| lesson.view(i, 640, 480).unwrap().settings.terms)
        .collect();
    assert_eq!(
        first_terms,
        [Term::L0, Term::L1, Term::L2].map(TermSet::only).to_vec()
    );
}

#[test]
fn steps_set_only_what_they_say_over_the_lessons_defaults() {
    let text = one_step("lights = \"point\"").replace(
        "[[steps]]",
        "[defaults]\nsampler = \"sobol\"\nspp = 16\n\n[[steps]]",
    );
    let lesson = Lesson::parse(&text, "test.toml").unwrap_or_else(|e| panic!("{e}"));
    let view = lesson.view(0, 320, 240).unwrap();
    assert_eq!(view.settings.light_mode, LightMode::Point);
    assert_eq!(view.settings.sampler, Sampler::Sobol);
    assert_eq!(view.spp, 16);
    assert_eq!(view.settings.terms, TermSet::COURSE);
    assert_eq!(view.scene, "cornell");
    // a probe is written for 640×480 and lands on the same place of any film
    let probed = one_step("probe = [320, 400]");
    let lesson = Lesson::parse(&probed, "test.toml").unwrap();
    assert_eq!(lesson.view(0, 64, 48).unwrap().probe, Some((32, 40)));
    assert_eq!(lesson.view(0, 640, 480).unwrap().probe, Some((320, 400)));
}

/// `[steps.settings.split]`: B's changes to the step's settings, with the
/// command line's names; a step without it shows no split.
#[test]
fn a_step_splits_the_image_with_the_changes_of_b() {
    let text = one_step(
        "terms = \"L1\"\nlights = \"point\"\n[steps.settings.split]\nlights = \"area\"\nbrdf = \"mirror\"\nterms = \"L0,L1\"\nintegrator = \"lecture\"",
    );
    let lesson = Lesson::parse(&text, "test.toml").unwrap_or_else(|e| panic!("{e}"));
    let view = lesson.view(0, 64, 48).unwrap();
    let split = view.split.clone().expect("the step splits the image");
    assert_eq!(split.light_mode, Some(LightMode::Area));
    assert_eq!(split.brdf, Some(BrdfOverride::Mirror));
    assert_eq!(split.integrator, Some(Integrator::Lecture));
    assert_eq!(
        split.terms,
        Some(TermSet::only(Term::L0).with(Term::L1, true))
    );
    assert_eq!(split.light_sampling, None);
    // A is the step's settings; B is A with the changes
    assert_eq!(view.settings.light_mode, LightMode::Point);
    let b = view.split_settings().unwrap();
    assert_eq!(
        (b.light_mode, b.brdf),
        (LightMode::Area, BrdfOverride::Mirror)
    );
    assert_eq!(b.seed, view.settings.seed);
    assert_eq!(
        lumiere::render::settings_override::side_labels(&view.settings, &b).1,
        "L0+L1, extended lights, mirror, lecture integrator"
    );
    assert_eq!(
        Lesson::parse(&one_step(""), "t")
            .unwrap()
            .view(0, 64, 48)
            .unwrap()
            .split,
        None
    );

    // an unknown value: its line and the choices
    let problem = refusal(&one_step("[steps.settings.split]\nbrdf = \"velvet\""));
    assert!(
        problem.contains("line 11")
            && problem.contains("velvet")
            && problem.contains("authored, lambert, phong, mirror"),
        "{problem}"
    );
    // a step shows the four-up or a split, not both
    let four_up = one_step("layout = \"four-up\"");
    let view = Lesson::parse(&four_up, "t")
        .unwrap()
        .view(0, 64, 48)
        .unwrap();
    assert_eq!(view.display.layout, Layout::FourUp);
    let problem = refusal(&one_step(
        "layout = \"four-up\"\n[steps.settings.split]\nbrdf = \"mirror\"",
    ));
    assert!(
        problem.contains("either a split or the four-up"),
        "{problem}"
    );
    // an unknown key
    let problem = refusal(&one_step("[steps.settings.split]\nseed = 3"));
    assert!(problem.contains("unknown field `seed`"), "{problem}");
    // B's settings out of range: the step, and that it is the split's
    let problem = refusal(&one_step("[steps.settings.split]\nlight_samples = 1000"));
    assert!(
        problem.contains("step 1") && problem.contains("split: light samples 1000"),
        "{problem}"
    );
}

#[test]
fn a_broken_lesson_is_refused_with_its_line_and_field() {
    // an unknown key in a step's settings: its line and its name
    let problem = refusal(&one_step("colour = \"red\""));
    assert!(
        problem.starts_with("test.toml: line 10") && problem.contains("colour"),
        "{problem}"
    );
    // a value of the wrong kind: the line of the field, and the choices
    let problem = refusal(&one_step("lights = \"lasers\""));
    assert!(
        problem.contains("line 10") && problem.contains("lasers") && problem.contains("point"),
        "{problem}"
    );
    // a setting out of range: the step and the setting
    let problem = refusal(&one_step("phong_specular = 3.0"));
    assert!(
        problem.contains("step 1") && problem.contains("specular"),
        "{problem}"
    );
    // a source's quality with a field it does not have, or a count out of range
    let problem = refusal(&one_step("sources = [{ name = \"light\", colour = 3 }]"));
    assert!(
        problem.contains("line 10") && problem.contains("colour"),
        "{problem}"
    );
    let problem = refusal(&one_step("sources = [{ name = \"light\", samples = 0 }]"));
    assert!(
        problem.contains("step 1") && problem.contains("light samples 0"),
        "{problem}"
    );
    // a probe off the image
    let problem = refusal(&one_step("probe = [5000, 2]"));
    assert!(problem.contains("probe"), "{problem}");
    // not TOML at all
    let problem = refusal("name = \"x\"\n[[steps]\n");
    assert!(problem.contains("line 2"), "{problem}");
    // a missing caption
    let problem = refusal(&one_step("").replace(
        "caption = { fr = \"Une phrase.\", en = \"A sentence.\" }\n",
        "",
    ));
    assert!(problem.contains("caption"), "{problem}");
    // two steps with one slug
    let twice = one_step("").replace("[[steps]]", "[[steps]]\nslug = \"only\"\nformula = \"x\"\ntitle = { fr = \"a\", en = \"a\" }\ncaption = { fr = \"a\", en = \"a\" }\n\n[[steps]]");
    let problem = refusal(&twice);
    assert!(
        problem.contains("step 2") && problem.contains("slug"),
        "{problem}"
    );
    // no steps
    let problem = refusal("name = \"x\"\ntitle = { fr = \"a\", en = \"a\" }\nsteps = []\n");
    assert!(problem.contains("no [[steps]]"), "{problem}");
}

#[test]
fn the_command_line_lists_the_lessons_and_refuses_a_broken_one() {
    let out = lumiere()
        .args(["lessons", "--lang", "fr"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let listing = String::from_utf8_lossy(&out.stdout);
    let lesson = Lesson::load("simulation-notions").unwrap();
    assert!(listing.contains("simulation-notions") && listing.contains("cornell"));
    assert!(
        listing.contains(lesson.steps[0].title.get(Lang::Fr)),
        "{listing}"
    );

    let dir = std::env::temp_dir().join(format!("lumiere-lessons-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let broken = dir.join("broken.toml");
    std::fs::write(&broken, one_step("lights = \"lasers\"")).unwrap();
    // (a build without the viewer refuses `view` itself)
    if cfg!(feature = "gui") {
        for lesson in [broken.to_str().unwrap(), "no-such-lesson"] {
            let out = lumiere()
                .args(["view", "--lesson", lesson])
                .output()
                .unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(1), "{lesson}: {stderr}");
            assert!(stderr.contains(lesson), "{stderr}");
            assert!(!stderr.contains("panicked"), "{stderr}");
        }
        let out = lumiere()
            .args(["view", "--lesson", "simulation-notions", "--step", "99"])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&out.stderr).contains("--step 99"));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The complete example of `docs/lessons.md` is a lesson that loads.
#[test]
fn the_documented_example_is_a_valid_lesson() {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/lessons.md"))
        .expect("docs/lessons.md");
    let example = doc
        .split("```toml\n")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .expect("a ```toml block");
    let lesson = Lesson::parse(example, "docs/lessons.md").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(lesson.steps.len(), 3);
    let point = lesson.view(1, 64, 48).unwrap();
    assert_eq!(point.settings.light_mode, LightMode::Point);
    assert_eq!(point.settings.terms, TermSet::only(Term::L1));
    assert_eq!(point.split, None);
    let both = lesson.view(2, 64, 48).unwrap();
    assert_eq!(both.settings.light_mode, LightMode::Point);
    assert_eq!(
        both.split_settings().map(|b| b.light_mode),
        Some(LightMode::Area)
    );
}

/// Every scene of the library loads by name and renders without invalid
/// samples; `indirect-room` is what its name says: its lamp lights no
/// visible surface, so L1 is black and L2 carries the picture.
#[test]
fn the_scene_library_loads_by_name_and_renders() {
    for scene in &lumiere::scene::builtin::SCENES {
        let loaded = lumiere::scene::builtin::load(scene.name)
            .unwrap_or_else(|e| panic!("{}: {e}", scene.name));
        assert!(
            loaded.warnings.is_empty(),
            "{}: {:?}",
            scene.name,
            loaded.warnings
        );
        let film = common::render_film(loaded, &common::small(32, 24, TermSet::ALL), 4);
        assert!(
            film.radiance(TermSet::ALL)
                .iter()
                .any(|p| p.max_element() > 0.0),
            "{}: black",
            scene.name
        );
    }
    let room = lumiere::scene::builtin::load("indirect-room").unwrap();
    let film = common::render_film(room, &common::small(32, 24, TermSet::COURSE), 16);
    let (l1, _) = common::mean_and_error(&film, Term::L1);
    let (l2, _) = common::mean_and_error(&film, Term::L2);
    assert!(l1 == 0.0 && l2 > 0.0, "indirect-room: L1 {l1}, L2 {l2}");
}
