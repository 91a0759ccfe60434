//! "Save as shown": the picture's layout, its scaling, and what is drawn
//! over the image (colour bar, divider and labels, tiles, rays, texts).

use std::sync::Arc;

use glam::Vec2;

use super::canvas::{Canvas, Rect, Rgb8};
use super::shown::*;
use super::{BACKGROUND, Slide, SlideLayout, SlideTexts};
use crate::analysis::noise::{DisplayMode, NoiseView, colour_values};
use crate::analysis::path_view::{PathLine, RayRole};
use crate::course::Term;
use crate::course::color::linear_to_srgb;

/// A `width`×`height` image whose pixel (x, y) is (x, y, 7) (`width`, `height` ≤ 256).
fn ramp(width: u32, height: u32) -> SrgbImage {
    let pixels = (0..height)
        .flat_map(|y| (0..width).flat_map(move |x| [x as u8, y as u8, 7]))
        .collect();
    SrgbImage::new(width, height, pixels)
}

/// A `width`×`height` image of one colour.
fn plain(width: u32, height: u32, colour: Rgb8) -> SrgbImage {
    SrgbImage::new(width, height, colour.repeat((width * height) as usize))
}

fn picture(image: ShownImage) -> ShownPicture {
    ShownPicture {
        image,
        paths: Vec::new(),
        film: (64, 48),
        texts: None,
    }
}

fn compose(picture: &ShownPicture, width: u32, height: u32) -> (Canvas, ShownLayout) {
    let layout = ShownLayout::new(picture, width, height).unwrap();
    let canvas = compose_shown(picture, width, height).unwrap();
    (canvas, layout)
}

/// Pixels of `rect` that are light grey to white: text, or a divider.
fn bright_pixels(canvas: &Canvas, rect: Rect) -> usize {
    (rect.y..rect.bottom())
        .flat_map(|y| (rect.x..rect.right()).map(move |x| (x, y)))
        .filter(|&(x, y)| canvas.pixel(x, y).iter().all(|&c| c >= 200))
        .count()
}

#[test]
fn sizes_outside_16_to_16384_are_refused() {
    assert!(check_size(16, 16384).is_ok());
    for (w, h) in [(15, 100), (100, 15), (16385, 100), (0, 0)] {
        let error = check_size(w, h).unwrap_err();
        assert!(error.contains(&format!("{w}×{h}")) && error.contains("16..=16384"));
    }
    let refused = compose_shown(&picture(ShownImage::Image(ramp(4, 3))), 20000, 1080);
    assert!(refused.unwrap_err().contains("20000×1080"));
}

#[test]
fn the_image_fills_the_picture_keeping_its_aspect_in_blocks_when_enlarged() {
    let shown = picture(ShownImage::Image(ramp(64, 48)));
    let (canvas, layout) = compose(&shown, 640, 360);
    assert_eq!((canvas.width(), canvas.height()), (640, 360));
    assert_eq!(layout.image, Rect::new(80, 0, 480, 360), "4:3, centred");
    // 7.5 picture pixels a film pixel: a block of 7 or 8 pixels of its value,
    // the pixel its edge runs through mixes the two
    let mut blocks = 0;
    for y in 0..360u32 {
        for x in 0..640u32 {
            let shown = canvas.pixel(x, y);
            if !layout.image.contains(x as i64, y as i64) {
                assert_eq!(shown, BACKGROUND, "({x}, {y})");
                continue;
            }
            let footprint = |i: u32| (2 * i / 15, (2 * i + 1) / 15);
            let ((x0, x1), (y0, y1)) = (footprint(x - 80), footprint(y));
            if (x0, y0) == (x1, y1) {
                assert_eq!(shown, [x0 as u8, y0 as u8, 7], "({x}, {y})");
                blocks += 1;
            } else {
                assert!(
                    (x0..=x1).contains(&(shown[0] as u32)),
                    "({x}, {y}): {shown:?}"
                );
                assert!(
                    (y0..=y1).contains(&(shown[1] as u32)),
                    "({x}, {y}): {shown:?}"
                );
                assert_eq!(shown[2], 7);
            }
        }
    }
    assert!(blocks > 480 * 360 * 3 / 4, "{blocks}");
    // a whole factor: blocks only, nearest neighbour
    let (canvas, _) = compose(&picture(ShownImage::Image(ramp(160, 120))), 640, 360);
    for (x, y) in [(80, 0), (82, 2), (83, 3), (559, 359), (300, 200)] {
        let expected = [((x - 80) / 3) as u8, (y / 3) as u8, 7];
        assert_eq!(canvas.pixel(x, y), expected, "({x}, {y})");
    }
    // a tall picture: the image as wide as it, centred vertically
    let (_, layout) = compose(&shown, 300, 900);
    assert_eq!(layout.image, Rect::new(0, 337, 300, 225));
}

#[test]
fn scaled_pixels_average_what_they_cover_in_linear_light() {
    // black and white columns, halved: each pixel the mean of one of each
    let mut pixels = Vec::new();
    for _ in 0..2 {
        for x in 0..4 {
            pixels.extend([if x % 2 == 0 { 0 } else { 255 }; 3]);
        }
    }
    let mut canvas = Canvas::new(2, 1, [1, 2, 3]);
    canvas.put_scaled(Rect::new(0, 0, 2, 1), (4, 2), &pixels);
    let grey = (linear_to_srgb(0.5) * 255.0 + 0.5) as u8;
    assert_eq!(grey, 188);
    assert_eq!(canvas.pixel(0, 0), [grey; 3]);
    assert_eq!(canvas.pixel(1, 0), [grey; 3]);
    // black | white enlarged to three pixels: the middle one covers half of each
    let mut canvas = Canvas::new(3, 1, [1, 2, 3]);
    canvas.put_scaled(Rect::new(0, 0, 3, 1), (2, 1), &[0, 0, 0, 255, 255, 255]);
    assert_eq!(canvas.pixel(0, 0), [0; 3]);
    assert_eq!(canvas.pixel(1, 0), [grey; 3]);
    assert_eq!(canvas.pixel(2, 0), [255; 3]);
}

/// A standard-error map of `width`×`height` rising from left to right.
fn noise(width: u32, height: u32) -> Arc<crate::analysis::noise::FalseColour> {
    let values = (0..height)
        .flat_map(|_| (0..width).map(|x| x as f32 * 0.01))
        .collect();
    let view = NoiseView {
        mode: DisplayMode::StandardError,
        ..NoiseView::default()
    };
    Arc::new(colour_values(width, height, view, values))
}

/// The columns of `rect` whose pixels take many colours from top to bottom: a colour bar.
fn bar_columns(canvas: &Canvas, rect: Rect) -> Vec<u32> {
    (rect.x..rect.right())
        .filter(|&x| {
            let mut colours: Vec<Rgb8> = (rect.y..rect.bottom())
                .map(|y| canvas.pixel(x, y))
                .collect();
            colours.dedup();
            colours.len() > rect.height as usize / 3
        })
        .collect()
}

#[test]
fn a_noise_view_has_its_colour_bar_right_of_the_image() {
    let map = noise(64, 48);
    let shown = picture(ShownImage::Noise(Arc::clone(&map)));
    let (canvas, layout) = compose(&shown, 640, 360);
    let image = layout.image;
    assert_eq!((image.width, image.height, image.y), (480, 360, 0));
    assert!(
        image.x < 80 && 640 - image.right() > 80,
        "room for the bar's title"
    );
    let srgb = super::false_colour_srgb8(&map);
    let at = |x: u32, y: u32| {
        let i = (y * 64 + x) as usize * 3;
        [srgb[i], srgb[i + 1], srgb[i + 2]]
    };
    assert_eq!(canvas.pixel(image.x, 0), at(0, 0));
    assert_eq!(canvas.pixel(image.right() - 1, 359), at(63, 47));
    let margin = layout.colour_bar();
    let bar = bar_columns(&canvas, margin);
    assert!(!bar.is_empty(), "no colour bar in {margin:?}");
    // yellow (the range's end) at the top, dark violet (its start) at the bottom
    let x = bar[bar.len() / 2];
    let (upper, lower) = (canvas.pixel(x, 60), canvas.pixel(x, 340));
    assert!(
        upper[0] > 150 && upper[1] > 200 && upper[2] < 100,
        "{upper:?}"
    );
    assert!(
        lower[0] < 100 && lower[1] < 60 && lower[2] > 60,
        "{lower:?}"
    );
    // the mode, the unit and the values: light grey text, small at this size
    let text = (margin.y..margin.bottom())
        .flat_map(|y| (margin.x..margin.right()).map(move |x| (x, y)))
        .map(|(x, y)| canvas.pixel(x, y))
        .filter(|p| p.iter().min() >= Some(&120) && p[0].abs_diff(p[2]) < 20)
        .count();
    assert!(text > 50, "{text} pixels of text");

    // a 4:3 picture leaves no margin: the image moves left and shrinks for the bar
    let (canvas, layout) = compose(&shown, 480, 360);
    assert!(
        layout.image.x < 5 && layout.image.right() < 400,
        "{layout:?}"
    );
    assert!(!bar_columns(&canvas, layout.colour_bar()).is_empty());
}

#[test]
fn the_split_has_its_divider_and_both_labels() {
    // A red, B blue, divided at column 32 of 64
    let mut pixels = Vec::new();
    for _ in 0..48 {
        for x in 0..64 {
            pixels.extend(if x < 32 { [200, 30, 30] } else { [30, 30, 200] });
        }
    }
    let labels = [
        "A: point lights · 64 spp · 1.2 s".to_string(),
        "B: extended lights · 60 spp · 1.2 s".to_string(),
    ];
    let shown = picture(ShownImage::Split {
        image: SrgbImage::new(64, 48, pixels),
        divider: 32,
        labels,
    });
    let (canvas, layout) = compose(&shown, 640, 360);
    let image = layout.image;
    let middle = image.x + image.width / 2;
    assert_eq!(middle, 320);
    // the divider, and the halves away from it and from the labels
    assert!(canvas.pixel(middle, 300).iter().all(|&c| c >= 200));
    assert_eq!(canvas.pixel(middle - 20, 300), [200, 30, 30]);
    assert_eq!(canvas.pixel(middle + 20, 300), [30, 30, 200]);
    // each label near the top of its half, B's at the right
    let band = 30;
    let a = Rect::new(image.x, image.y, image.width / 2 - 5, band);
    let b = Rect::new(middle + 5, image.y, image.width / 2 - 5, band);
    assert!(bright_pixels(&canvas, a) > 40, "A's label");
    assert!(bright_pixels(&canvas, b) > 40, "B's label");
    let right_end = Rect::new(image.right() - 40, image.y, 40, band);
    assert!(
        bright_pixels(&canvas, right_end) > 10,
        "B's label is right-aligned"
    );
    let no_label = Rect::new(image.x, image.y + 100, image.width / 2 - 5, band);
    assert_eq!(bright_pixels(&canvas, no_label), 0);
}

#[test]
fn the_four_up_shows_its_tiles_labelled_and_an_empty_one_saying_off() {
    let colours: [Rgb8; 4] = [
        [200, 150, 50],
        [50, 100, 200],
        [60, 180, 90],
        [220, 220, 60],
    ];
    let tiles: Vec<ShownTile> = colours
        .iter()
        .enumerate()
        .map(|(k, &colour)| ShownTile {
            image: (k != 1).then(|| plain(64, 48, colour)),
            label: ["L0 emission", "L1 direct", "L2 indirect", "L0+L2"][k].into(),
            off: k == 1,
        })
        .collect();
    let shown = picture(ShownImage::FourUp {
        tile_size: (64, 48),
        tiles,
    });
    let (canvas, layout) = compose(&shown, 1920, 1080);
    assert_eq!(
        layout.arrangement,
        Some(crate::render::four_up::Arrangement::Grid)
    );
    assert_eq!(layout.image, Rect::new(240, 0, 1440, 1080));
    assert_eq!(layout.tiles[3], Rect::new(960, 540, 720, 540));
    for (k, rect) in layout.tiles.iter().enumerate() {
        // below the label, away from the middle ("off") and the seams
        let (x, y) = (rect.x + rect.width / 4, rect.y + rect.height * 3 / 4);
        let expected = if k == 1 { BACKGROUND } else { colours[k] };
        assert_eq!(canvas.pixel(x, y), expected, "tile {k}");
        let label = Rect::new(rect.x, rect.y, rect.width / 2, rect.height / 8);
        assert!(bright_pixels(&canvas, label) > 100, "tile {k}'s label");
    }
    let off = layout.tiles[1];
    let middle = Rect::new(
        off.x + off.width / 3,
        off.y + off.height / 3,
        off.width / 3,
        off.height / 3,
    );
    let text = (middle.y..middle.bottom())
        .flat_map(|y| (middle.x..middle.right()).map(move |x| (x, y)))
        .filter(|&(x, y)| canvas.pixel(x, y)[0] > 100)
        .count();
    assert!(text > 100, "the empty tile says off");
    // a wide, low picture takes the tiles in a row
    let (_, layout) = compose(&shown, 1600, 300);
    assert_eq!(
        layout.arrangement,
        Some(crate::render::four_up::Arrangement::Row)
    );
    assert_eq!(layout.image, Rect::new(0, 0, 1600, 300));
}

#[test]
fn the_probe_rays_are_scaled_with_the_image() {
    let line = PathLine {
        from: Vec2::new(0.0, 24.0),
        to: Vec2::new(64.0, 24.0),
        role: RayRole::Bounce {
            term: Term::L2,
            refracted: false,
        },
        segment: 1,
        ends_on_film: false,
    };
    let mut shown = picture(ShownImage::Image(plain(64, 48, [0, 0, 0])));
    let (canvas, _) = compose(&shown, 640, 360);
    assert_eq!(canvas.pixel(320, 180), [0, 0, 0]);
    shown.paths = vec![line];
    let (canvas, _) = compose(&shown, 640, 360);
    // film row 24 is picture row 180; L2's colour, over a dark outline
    assert_eq!(canvas.pixel(320, 180), [110, 200, 120]);
    assert_eq!(canvas.pixel(100, 179), [110, 200, 120]);
    assert_eq!(canvas.pixel(320, 170), [0, 0, 0]);
}

#[test]
fn a_lesson_step_is_laid_out_as_its_slide() {
    let texts = SlideTexts {
        title: "4. L = L₀ + L₁ + L₂".into(),
        formula: "L = L₀ + L₁ + L₂".into(),
        caption: "The sum of the three terms.".into(),
    };
    let mut shown = picture(ShownImage::Image(plain(64, 48, [90, 90, 90])));
    shown.texts = Some(texts.clone());
    let (canvas, layout) = compose(&shown, 640, 360);
    let slide_layout = SlideLayout::new(640, 360);
    assert_eq!(layout.slide.as_ref(), Some(&slide_layout));
    assert_eq!(
        layout.image, slide_layout.image,
        "a 4:3 film fills the region"
    );
    let slide = Slide::new(slide_layout.clone(), &texts).canvas();
    for band in [slide_layout.top_band, slide_layout.bottom_band] {
        for y in band.y..band.bottom() {
            for x in 0..640 {
                assert_eq!(canvas.pixel(x, y), slide.pixel(x, y), "({x}, {y})");
            }
        }
        assert!(bright_pixels(&canvas, band) > 100, "text in {band:?}");
    }
    let image = layout.image;
    assert_eq!(canvas.pixel(image.x, image.y), [90, 90, 90]);
    // too small for the slide's bands: refused with the slide's reason
    let error = compose_shown(&shown, 40, 300).map(|_| ()).unwrap_err();
    assert!(error.contains("between its text bands"), "{error}");
}
