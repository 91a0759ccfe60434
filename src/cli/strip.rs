//! `lumiere strip`: one progressive render shown at several sample counts,
//! a row per value of a swept option, labelled, as a PNG.

use std::path::PathBuf;

use clap::Args;

use lumiere::render::export::ImageFormat;
use lumiere::tools::strip::{
    RowSweep, SampleCounts, StripImage, StripLayout, StripRow, render_strip,
};
use lumiere::{Film, RenderSettings};

use super::options::SceneOptions;
use super::{Failure, check_sources, load_scene, strip_progress_bar, summary, worker_pool};

/// The arguments of `lumiere strip`.
#[derive(Args)]
pub struct StripArgs {
    /// A .gltf/.glb file, or a built-in scene: `cornell` (the default) or another `lumiere lessons` lists.
    #[arg(default_value = "cornell")]
    scene: String,
    /// Output image: a .png (labels are display pixels; no EXR).
    #[arg(short, long)]
    output: PathBuf,
    /// Samples per pixel of the tiles, increasing: one render, snapshotted at each count.
    #[arg(long, default_value = "1,4,16,64,256")]
    spp: SampleCounts,
    /// One row per value of an option, e.g. light-sampling=area,solid-angle,mis
    /// (terms are joined by '+': terms=L1,L2,L1+L2).
    #[arg(long)]
    rows: Option<RowSweep>,
    /// Width of each tile (the same as --width).
    #[arg(long, conflicts_with = "width", value_parser = clap::value_parser!(u32).range(1..=16384))]
    tile_width: Option<u32>,
    /// Height of each tile (the same as --height).
    #[arg(long, conflicts_with = "height", value_parser = clap::value_parser!(u32).range(1..=16384))]
    tile_height: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    threads: Option<u32>,
    #[command(flatten)]
    options: SceneOptions,
}

/// The settings of one tile: the scene options at the tile's size.
fn tile_settings(args: &StripArgs) -> RenderSettings {
    let mut base = args.options.settings();
    base.width = args.tile_width.unwrap_or(base.width);
    base.height = args.tile_height.unwrap_or(base.height);
    base
}

/// Every check of a strip's arguments: the output's format, each row's
/// settings and film, the whole image's size. Returns the layout.
fn check(
    args: &StripArgs,
    base: &RenderSettings,
    rows: &[StripRow],
) -> Result<StripLayout, Failure> {
    if ImageFormat::from_path(&args.output) != Some(ImageFormat::Png) {
        return Err(Failure::usage_message(format_args!(
            "{}: a strip is written as PNG only (its labels are display pixels); the output must end in .png",
            args.output.display()
        )));
    }
    for row in rows {
        row.settings.validate().map_err(Failure::usage_message)?;
    }
    for row in rows {
        Film::check_memory(base.width, base.height, row.settings.terms).map_err(Failure::usage)?;
    }
    let row_labels = rows.iter().filter_map(|r| r.label.clone()).collect();
    let layout = StripLayout::new(base.width, base.height, args.spp.labels(), row_labels);
    layout.check_size().map_err(Failure::usage_message)?;
    Ok(layout)
}

/// Renders the strip row by row, printing each row's summary, and saves it.
pub fn run(args: &StripArgs) -> Result<(), Failure> {
    let base = tile_settings(args);
    let rows = match &args.rows {
        Some(sweep) => sweep.rows(&base),
        None => vec![StripRow {
            label: None,
            settings: base.clone(),
        }],
    };
    let layout = check(args, &base, &rows)?;
    let scene = load_scene(&args.scene)?;
    check_sources(&base, &scene, &args.scene)?;
    let pool = worker_pool(args.threads)?;
    let mut image = StripImage::new(layout);
    let bar = strip_progress_bar(args.spp.max() as u64 * rows.len() as u64);
    let row_name = |r: usize| match (&args.rows, &rows[r].label) {
        (Some(sweep), Some(label)) => format!("{}={label}: ", sweep.option),
        _ => String::new(),
    };
    pool.install(|| {
        render_strip(
            scene.into(),
            &rows,
            &args.spp,
            args.options.display(),
            &mut image,
            |r, stats| {
                bar.set_position(r as u64 * args.spp.max() as u64 + stats.samples_per_pixel as u64);
                bar.set_message(row_name(r));
            },
            |r, stats| bar.suspend(|| println!("{}{}", row_name(r), summary(stats))),
        )
    });
    bar.finish_and_clear();
    image.save_png(&args.output).map_err(Failure::runtime)?;
    Ok(())
}
