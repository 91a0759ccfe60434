//! The slide's layout, its text fitting, file names, frame counts and index.

use super::canvas::{fit_line, fit_paragraph, text_width, wrap};
use super::*;

#[test]
fn a_full_hd_slide_has_the_documented_sizes_and_a_centred_4_3_image() {
    let layout = SlideLayout::new(1920, 1080);
    assert!(layout.check().is_ok());
    assert_eq!(
        (layout.title_size, layout.formula_size, layout.caption_size),
        (54.0, 40.0, 34.0)
    );
    // the bands: padding, one title and one formula line; three caption lines
    assert_eq!((layout.top_band.y, layout.top_band.height), (0, 168));
    assert_eq!(layout.bottom_band.bottom(), 1080);
    assert_eq!(layout.bottom_band.height, 173);
    let image = layout.image;
    assert_eq!((image.width, image.height), (985, 739), "as documented");
    assert_eq!(image.y, layout.top_band.bottom());
    assert_eq!(image.bottom(), layout.bottom_band.y);
    assert_eq!(image.x, (1920 - 985) / 2, "centred");
    // the frame's aspect, to a pixel
    assert!((image.width as f32 / image.height as f32 - 4.0 / 3.0).abs() < 2.0 / 739.0);
}

#[test]
fn sizes_follow_the_slide_height_and_a_narrow_slide_fits_the_image_to_its_width() {
    let small = SlideLayout::new(960, 540);
    assert_eq!(small.title_size, 27.0);
    assert!((small.image.height as i64 - 739 / 2).abs() <= 1);
    // 4:3 slide: the image is as wide as the text and centred vertically
    let narrow = SlideLayout::new(800, 1080);
    assert_eq!(narrow.image.width, 800 - 2 * 48);
    assert_eq!(narrow.image.height, (800 - 2 * 48) * 3 / 4);
    let area = narrow.bottom_band.y - narrow.top_band.bottom();
    assert_eq!(
        narrow.image.y - narrow.top_band.bottom(),
        (area - narrow.image.height) / 2
    );
}

#[test]
fn slides_too_small_or_too_large_are_refused() {
    let error = SlideLayout::new(320, 10).check().unwrap_err();
    assert!(
        error.contains("320×10") && error.contains("between its text bands"),
        "{error}"
    );
    let error = SlideLayout::new(20, 180).check().unwrap_err();
    assert!(error.contains("leaves an image"), "{error}");
    let error = SlideLayout::new(16385, 1080).check().unwrap_err();
    assert!(error.contains("16384"), "{error}");
    assert!(SlideLayout::new(320, 180).check().is_ok());
}

#[test]
fn captions_wrap_between_words_and_keep_french_punctuation_with_its_word() {
    let size = 34.0;
    let text = "Chaque point du sol voit une partie de la source : l'ombre a une pénombre.";
    let width = text_width(text, size);
    assert_eq!(wrap(text, size, width), [text], "fits on one line");
    let lines = wrap(text, size, width * 0.6);
    assert_eq!(lines.len(), 2);
    assert_eq!(lines.join(" "), text, "no word lost");
    for line in &lines {
        assert!(text_width(line, size) <= width * 0.6);
        assert!(!line.starts_with(':'), "{line:?}");
    }
    // the colon's line break falls before the word it follows, not before ':'
    let before_colon = text_width("Chaque point du sol voit une partie de la source", size);
    let lines = wrap(text, size, before_colon + 1.0);
    assert!(lines[0].ends_with("de la"), "{lines:?}");
    assert!(lines[1].starts_with("source :"), "{lines:?}");
}

#[test]
fn long_texts_are_set_smaller_then_cut_with_an_ellipsis() {
    let (line, size) = fit_line("a short title", 54.0, 32.4, 1000.0);
    assert_eq!((line.as_str(), size), ("a short title", 54.0));
    let long = "L₂(p, ωₒ) = ∫ f_r |cos θ| dω ".repeat(3);
    let width = text_width(&long, 40.0);
    let (line, size) = fit_line(&long, 40.0, 24.0, width * 0.8);
    assert_eq!(line, long, "set smaller, whole");
    assert!((size - 32.0).abs() < 0.01 && text_width(&line, size) <= width * 0.8 + 0.01);
    let (line, size) = fit_line(&long, 40.0, 24.0, width * 0.3);
    assert_eq!(size, 24.0);
    assert!(line.ends_with('…') && text_width(&line, size) <= width * 0.3);

    let caption = "word ".repeat(200);
    let (lines, size) = fit_paragraph(&caption, 34.0, 23.8, 900.0, CAPTION_LINES);
    assert_eq!(lines.len(), CAPTION_LINES);
    assert!((23.8..34.0).contains(&size));
    assert!(lines[2].ends_with('…'));
    assert!(lines.iter().all(|l| text_width(l, size) <= 900.0));
}

#[test]
fn every_built_in_text_fits_at_full_size_on_a_full_hd_slide() {
    let layout = SlideLayout::new(1920, 1080);
    let lesson = Lesson::load("simulation-notions").unwrap();
    for lang in [Lang::Fr, Lang::En] {
        for i in 0..lesson.steps.len() {
            let texts = SlideTexts::of(&lesson, i, lang);
            let lines = wrap(&texts.caption, layout.caption_size, layout.text_width());
            assert!(lines.len() <= CAPTION_LINES, "step {}: {lines:?}", i + 1);
            let (_, size) = fit_line(&texts.title, layout.title_size, 0.0, layout.text_width());
            assert_eq!(size, layout.title_size, "step {} title", i + 1);
            let (_, size) = fit_line(
                &texts.formula,
                layout.formula_size,
                0.0,
                layout.text_width(),
            );
            assert_eq!(size, layout.formula_size, "step {} formula", i + 1);
        }
    }
}

#[test]
fn file_names_number_the_steps_on_two_digits_or_more() {
    assert_eq!(file_stem(4, 25, "l0-l1-l2"), "04-l0-l1-l2");
    assert_eq!(file_stem(12, 25, "x"), "12-x");
    assert_eq!(file_stem(7, 120, "x"), "007-x");
}

#[test]
fn frames_double_up_to_the_step_count() {
    assert_eq!(frame_counts(1), [1]);
    assert_eq!(frame_counts(2), [1, 2]);
    assert_eq!(frame_counts(5), [1, 2, 4, 5]);
    assert_eq!(frame_counts(64), [1, 2, 4, 8, 16, 32, 64]);
}

#[test]
fn the_summary_names_what_a_step_changes_and_the_index_lists_every_slide() {
    let lesson = Lesson::load("simulation-notions").unwrap();
    let view = lesson.view(2, 640, 480).unwrap(); // L2, +2 EV
    let summary = settings_summary(&view);
    assert_eq!(
        summary,
        "scene cornell, terms L2, exposure +2 EV · 64 spp, seed 0"
    );
    let layout = SlideLayout::new(1920, 1080);
    let entries: Vec<IndexEntry> = (0..lesson.steps.len())
        .map(|i| IndexEntry {
            texts: SlideTexts::of(&lesson, i, Lang::En),
            stem: file_stem(i + 1, lesson.steps.len(), &lesson.steps[i].slug),
            settings: settings_summary(&lesson.view(i, 640, 480).unwrap()),
            gif: i == 0,
        })
        .collect();
    let index = index_markdown(&lesson, Lang::En, &layout, "lumiere lesson x", &entries);
    assert!(index.starts_with("# Simulation – notions\n"));
    assert!(index.contains("\n## 5. L = L₀ + L₁ + L₂\n"));
    assert!(index.contains("![5. L = L₀ + L₁ + L₂](05-l0-l1-l2.png)"));
    assert!(index.contains("`L₀(p, ωₒ) = Lₑ(p, ωₒ)`"));
    assert!(index.contains("[01-l0-emission.gif](01-l0-emission.gif)"));
    assert_eq!(index.matches(".gif)").count(), 1);
    assert_eq!(index.matches("\nSettings: ").count(), lesson.steps.len());
    assert_eq!(escape_markdown("f_r *x* [a]"), "f\\_r \\*x\\* \\[a\\]");
}
