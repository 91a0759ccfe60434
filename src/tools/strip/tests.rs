//! The strip's layout and labels: sizes, bands, and text that stays whole inside its band.

use super::*;

fn counts(s: &str) -> SampleCounts {
    s.parse().unwrap()
}

#[test]
fn sample_counts_parse_increasing_lists_only() {
    assert_eq!(counts("1, 4,16").as_slice(), &[1, 4, 16]);
    assert_eq!(counts("1,4,16").labels(), ["1 spp", "4 spp", "16 spp"]);
    for (bad, says) in [
        ("0", "at least 1"),
        ("4,2", "increase"),
        ("4,4", "increase"),
        ("abc", "'abc' is not a sample count"),
        ("", "not a sample count"),
        ("1,,4", "not a sample count"),
        ("-1", "not a sample count"),
        ("200000000", "limit"),
    ] {
        let error = bad.parse::<SampleCounts>().unwrap_err();
        assert!(error.contains(says), "{bad:?}: {error}");
    }
}

#[test]
fn row_sweeps_parse_and_apply() {
    let sweep: RowSweep = "light-sampling=area,solid-angle,MIS".parse().unwrap();
    assert_eq!(sweep.option, RowOption::LightSampling);
    let rows = sweep.rows(&RenderSettings::default());
    let labels: Vec<_> = rows.iter().map(|r| r.label.clone().unwrap()).collect();
    assert_eq!(labels, ["area", "solid-angle", "mis"]);
    assert_eq!(rows[1].settings.light_sampling, LightSampling::SolidAngle);

    let terms: RowSweep = "terms=L1,L1+L2,L3+,all".parse().unwrap();
    let sets: Vec<_> = terms
        .rows(&RenderSettings::default())
        .iter()
        .map(|r| (r.settings.terms, r.label.clone().unwrap()))
        .collect();
    assert_eq!(sets[1].0, "L1,L2".parse().unwrap());
    assert_eq!(sets[1].1, "L1+L2");
    assert_eq!(sets[2].0, TermSet::only(crate::Term::L3Plus));
    assert_eq!(sets[3].0, TermSet::ALL);

    let samples: RowSweep = "light-samples=1,16".parse().unwrap();
    assert_eq!(
        samples.rows(&RenderSettings::default())[1]
            .settings
            .light_samples,
        16
    );
    for option in RowOption::ALL {
        let text = format!("{option}=x");
        let error = text.parse::<RowSweep>().unwrap_err();
        assert!(error.starts_with(option.label()), "{error}");
    }
    for (bad, says) in [
        ("light-sampling", "OPTION=V1,V2"),
        ("colour=red", "unknown option 'colour'"),
        ("light-sampling=area,lasers", "unknown value 'lasers'"),
        ("light-samples=0", "within 1..=256"),
        ("terms=L7", "unknown term"),
        ("brdf=", "unknown value ''"),
    ] {
        let error = bad.parse::<RowSweep>().unwrap_err();
        assert!(error.contains(says), "{bad:?}: {error}");
    }
}

fn labels(texts: &[&str]) -> Vec<String> {
    texts.iter().map(|s| s.to_string()).collect()
}

#[test]
fn layout_sizes_and_tile_places() {
    let spp = labels(&["1 spp", "4 spp", "256 spp"]);
    // the text grows with the tiles (32 px at 256 × 192 px) and fits them
    let at = |width: u32| StripLayout::new(width, width * 3 / 4, spp.clone(), vec![]);
    let sizes = [128, 256, 512].map(|w| at(w).text_size);
    assert_eq!(sizes, [16, 32, 64]);
    // wide, low tiles take the text their height allows
    let low = StripLayout::new(512, 96, spp.clone(), vec![]);
    assert_eq!(low.text_size, 16);
    for width in [128, 160, 256, 512, 2048] {
        let layout = at(width);
        let widest = text_width("256 spp", layout.text_size);
        assert!(widest > 3.0 * layout.text_size as f32, "{width}: {widest}");
        assert!(
            widest as u32 + 2 * layout.margin() <= width,
            "{width}: '256 spp' is {widest} px at {} px",
            layout.text_size
        );
    }
    assert_eq!(at(2048).text_size, MAX_TEXT_SIZE);
    // a long label takes smaller text rather than overflow its tile
    let long = StripLayout::new(400, 300, labels(&["1 spp", "1048576 spp (8 rows)"]), vec![]);
    assert!(
        MIN_TEXT_SIZE < long.text_size && long.text_size < 50,
        "{long:?}"
    );
    assert!(text_width("1048576 spp (8 rows)", long.text_size) as u32 + 2 * long.margin() <= 400);
    // narrow tiles keep the smallest legible text, and clip it
    let narrow = StripLayout::new(24, 16, labels(&["1 spp", "4 spp"]), vec![]);
    assert_eq!(narrow.text_size, MIN_TEXT_SIZE);

    let plain = at(160);
    let band = plain.band_height();
    assert_eq!((plain.text_size, band), (20, 34));
    assert_eq!(
        (plain.width(), plain.height()),
        (3 * 160, 120 + band as u64)
    );
    assert_eq!(plain.tile_origin(0, 2), (320, 0));
    assert_eq!(plain.label_column_width(), 0);

    let rows = StripLayout::new(
        640,
        480,
        labels(&["1 spp", "16 spp"]),
        labels(&["area", "solid-angle"]),
    );
    assert_eq!(rows.text_size, 64);
    let band = rows.band_height();
    let left = rows.label_column_width();
    let widest = text_width("solid-angle", 64);
    assert_eq!(left, widest.ceil() as u32 + 2 * rows.margin());
    assert!(widest > text_width("area", 64));
    assert_eq!(rows.width(), left as u64 + 2 * 640);
    assert_eq!(rows.height(), 2 * (480 + band as u64));
    assert_eq!(rows.tile_origin(1, 1), (left + 640, 480 + band));
    assert!(rows.check_size().is_ok());

    let huge = StripLayout::new(4000, 3000, labels(&["1 spp"; 5]), vec![]);
    let error = huge.check_size().unwrap_err();
    let height = 3000 + huge.band_height();
    assert!(error.contains(&format!("20000×{height}")), "{error}");
}

/// The pixels of `image` in the rectangle that differ from the band
/// colour: a label's ink.
fn ink(image: &StripImage, x0: u32, y0: u32, width: u32, height: u32) -> Vec<(u32, u32)> {
    (y0..y0 + height)
        .flat_map(|y| (x0..x0 + width).map(move |x| (x, y)))
        .filter(|&(x, y)| image.pixel(x, y) != BAND_COLOR)
        .collect()
}

/// (left, top, right, bottom) of the ink, inclusive.
fn ink_box(ink: &[(u32, u32)]) -> (u32, u32, u32, u32) {
    ink.iter()
        .fold((u32::MAX, u32::MAX, 0, 0), |(l, t, r, b), &(x, y)| {
            (l.min(x), t.min(y), r.max(x), b.max(y))
        })
}

#[test]
fn tiles_land_in_place_and_labels_are_drawn_on_dark_bands() {
    let layout = StripLayout::new(
        128,
        96,
        labels(&["1 spp", "16 spp"]),
        labels(&["area", "mis"]),
    );
    let mut image = StripImage::new(layout.clone());
    let (w, h) = (layout.tile_width, layout.tile_height);
    for row in 0..2 {
        for column in 0..2 {
            let value = (10 + 40 * row + 80 * column) as u8;
            image.put_tile(row, column, &vec![value; (w * h * 3) as usize]);
        }
    }
    let (band, size) = (layout.band_height(), layout.text_size);
    let left = layout.label_column_width();
    for row in 0..2u32 {
        for column in 0..2u32 {
            let value = (10 + 40 * row + 80 * column) as u8;
            let (x0, y0) = layout.tile_origin(row, column);
            // the tile covers its rectangle exactly
            for (x, y) in [(x0, y0), (x0 + w - 1, y0 + h - 1)] {
                assert_eq!(image.pixel(x, y), [value; 3], "tile ({row}, {column})");
            }
            // its band is dark with light, antialiased text: every pixel a
            // blend of the two colours (grey between them)
            let at = format!("band ({row}, {column})");
            let ink = ink(&image, x0, y0 + h, w, band);
            for &(x, y) in &ink {
                let [r, g, b] = image.pixel(x, y);
                assert!(r == g && g == b, "{at}: ({x}, {y}) is {:?}", [r, g, b]);
                assert!((BAND_COLOR[0]..=TEXT_COLOR[0]).contains(&r), "{at}: {r}");
            }
            let full = ink
                .iter()
                .filter(|&&(x, y)| image.pixel(x, y)[0] >= 200)
                .count();
            let partial = ink.len() - full;
            assert!(full > 2 * size as usize, "{at}: {full} solid text pixels");
            assert!(partial > 0, "{at}: no antialiasing");
            // the whole label is in the band with room around it: not
            // clipped, centred, as tall as the text size allows
            let (l, t, r, b) = ink_box(&ink);
            assert!(l > x0 && r < x0 + w - 1, "{at}: ink from x {l} to {r}");
            assert!(
                t > y0 + h && b < y0 + h + band - 1,
                "{at}: ink from y {t} to {b}"
            );
            let (space_left, space_right) = (l - x0, x0 + w - 1 - r);
            assert!(
                space_left.abs_diff(space_right) <= size / 4,
                "{at}: {space_left} | {space_right}"
            );
            let (space_above, space_below) = (t - (y0 + h), y0 + h + band - 1 - b);
            assert!(
                space_above.abs_diff(space_below) <= size / 3,
                "{at}: {space_above} / {space_below}"
            );
            // digits and the descender of 'p': most of the text size
            let height = b - t + 1;
            assert!(
                (size / 2..=size).contains(&height),
                "{at}: ink {height} px high"
            );
            let label = &layout.column_labels[column as usize];
            let width = text_width(label, size);
            assert!((r - l + 1) as f32 > 0.8 * width && ((r - l + 1) as f32) < width + 2.0);
        }
        // the row label column holds its label, whole
        let (_, y0) = layout.tile_origin(row, 0);
        let ink = ink(&image, 0, y0, left, h + band);
        assert!(
            ink.len() > 4 * size as usize,
            "row {row}: {} ink pixels",
            ink.len()
        );
        let (l, t, r, b) = ink_box(&ink);
        assert!(
            l > 0 && r < left - 1 && t > y0 && b < y0 + h + band - 1,
            "row {row}"
        );
    }
}

#[test]
fn labels_stay_in_their_band() {
    // a label wider than its tile is clipped to its band: the next band
    // (an empty label) and the tiles (black until placed) keep no ink
    let layout = StripLayout::new(24, 16, labels(&["1048576 spp", ""]), vec![]);
    let image = StripImage::new(layout.clone());
    let (w, h, band) = (24, 16, layout.band_height());
    assert_eq!(ink(&image, 24, h, w, band), []);
    let clipped = ink(&image, 0, h, w, band);
    assert!(clipped.len() > 50, "{}", clipped.len());
    let (l, _, r, _) = ink_box(&clipped);
    assert!(
        l < 4 && r > w - 5,
        "the clipped label spans its band: {l}..={r}"
    );
    for y in 0..h {
        for x in 0..2 * w {
            assert_eq!(image.pixel(x, y), [0; 3], "({x}, {y})");
        }
    }

    // more text, more ink; none without text
    let lit = |text: &str| {
        let layout = StripLayout::new(200, 4, labels(&[text]), vec![]);
        let image = StripImage::new(layout);
        ink(&image, 0, 4, 200, image.height() - 4).len()
    };
    assert_eq!(lit(""), 0);
    assert_eq!(lit("   "), 0);
    assert!(lit("1 spp") > lit("1") && lit("1") > 0);
    // a character the font lacks prints as '?'
    assert_eq!(lit("\u{10FFFD}"), lit("?"));
}
