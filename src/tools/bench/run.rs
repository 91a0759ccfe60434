//! A whole bench: the selected sections in order, their files, and the summary table.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::RenderContext;
use crate::course::RenderSettings;
use crate::scene::builtin;
use crate::transport::splitting::choose_continuations;

use super::csv::{ErrorRow, error_csv, read_error_csv, write_text};
use super::error_curve::{
    CurveSummary, ErrorBench, LUMIERE, TimeRatio, measure_curves, reference, sample_counts,
    summarize,
};
use super::peer::{Peer, PeerRun};
use super::plot::{error_plot, scaling_plot};
use super::scaling::{Axis, ScalingBench, ScalingRow, measure_scaling, scaling_csv};
use super::throughput::{Throughput, measure as measure_throughput, throughput_csv};
use super::{BenchError, Progress, Section};

/// Everything `lumiere bench` was asked to do.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    pub sections: Vec<Section>,
    /// The error section (its scene and settings are the bench's).
    pub error: ErrorBench,
    /// Run this peer renderer on the error section's scene.
    pub peer: Option<Peer>,
    /// Peer rows to merge into the error plot and summary.
    pub peer_csvs: Vec<PathBuf>,
    /// Passes of the throughput section.
    pub throughput_passes: u32,
    /// Timed runs of the throughput section; the fastest counts.
    pub throughput_repeats: u32,
    pub scaling: ScalingBench,
}

impl BenchConfig {
    pub fn settings(&self) -> &RenderSettings {
        &self.error.settings
    }
}

/// What a bench measured and wrote.
#[derive(Clone, Debug, Default)]
pub struct BenchReport {
    /// The processor, threads and widest vectors the bench ran on ([`super::machine`]).
    pub machine: String,
    pub error_rows: Vec<ErrorRow>,
    pub curves: Vec<CurveSummary>,
    /// What the curves were measured against (how it was rendered, or the file).
    pub reference: Option<String>,
    /// Why a peer did not run, if it did not.
    pub notes: Vec<String>,
    pub throughput: Option<Throughput>,
    pub scaling: Vec<ScalingRow>,
    pub files: Vec<PathBuf>,
}

/// Runs the sections of `config` into `folder` (created if needed), on the current rayon pool.
pub fn run(
    config: &BenchConfig,
    folder: &Path,
    progress: &dyn Progress,
) -> Result<BenchReport, BenchError> {
    std::fs::create_dir_all(folder)
        .map_err(|e| BenchError::file(folder, format!("cannot create the folder: {e}")))?;
    // peer files are read first: a malformed one fails before minutes of rendering
    let mut peer_rows = Vec::new();
    for path in &config.peer_csvs {
        peer_rows.extend(read_error_csv(path)?);
    }
    let scene = Arc::new(builtin::load(&config.error.scene)?);
    let mut report = BenchReport {
        machine: super::machine::describe(),
        ..BenchReport::default()
    };
    if config.sections.contains(&Section::Error) {
        let (reference_image, reference_path) = reference(&config.error, &scene, folder, progress)?;
        report.files.push(reference_path.clone());
        report.reference = Some(reference_image.label.clone());
        let black = is_black(&reference_image.radiance);
        let mut rows = Vec::new();
        if black {
            // relMSE against a black image is 0 from the first sample: no curve to measure
            report.notes.push(
                "error curves not measured: the reference is black (no light reaches the \
                 camera under these settings), so every render matches it at once"
                    .into(),
            );
        } else {
            rows = measure_curves(&config.error, &scene, &reference_image, progress);
        }
        if let Some(peer) = config.peer.filter(|_| !black) {
            let counts = sample_counts(config.error.max_spp);
            match super::peer::run(
                peer,
                &config.error,
                &scene,
                &reference_path,
                &counts,
                folder,
                progress,
            )? {
                PeerRun::Rows(rows) => peer_rows.extend(rows),
                PeerRun::Skipped(why) => report.notes.push(format!("{peer} skipped: {why}")),
            }
        }
        rows.extend(peer_rows);
        let csv = folder.join("error.csv");
        write_text(&csv, &error_csv(&rows))?;
        let png = folder.join("error.png");
        error_plot(&rows, &png)?;
        report.files.extend([csv, png]);
        report.curves = summarize(&rows);
        report.error_rows = rows;
    }
    if config.sections.contains(&Section::Throughput) {
        progress.message("throughput: renderer and replay");
        let mut context = RenderContext::new(scene.clone(), config.settings().clone());
        choose_continuations(&mut context);
        let throughput = measure_throughput(
            &context,
            config.throughput_passes,
            config.throughput_repeats,
        );
        let csv = folder.join("throughput.csv");
        write_text(&csv, &throughput_csv(&throughput.rows))?;
        report.files.push(csv);
        report.throughput = Some(throughput);
    }
    if config.sections.contains(&Section::Scaling) {
        let rows = measure_scaling(&config.scaling, &scene, folder, progress)?;
        let csv = folder.join("scaling.csv");
        write_text(&csv, &scaling_csv(&rows))?;
        let png = folder.join("scaling.png");
        scaling_plot(&rows, &png)?;
        report.files.extend([csv, png]);
        report.scaling = rows;
    }
    Ok(report)
}

/// Whether every pixel of a reference is black: the scene sends no light to the camera.
fn is_black(radiance: &[glam::Vec3]) -> bool {
    radiance.iter().all(|p| p.max_element() <= 0.0)
}

/// The table of lumiere's time to each threshold ÷ `peer`'s, one row per lumiere curve.
fn write_peer_ratios(out: &mut String, curves: &[CurveSummary], peer: &CurveSummary, width: usize) {
    let _ = writeln!(
        out,
        "  time to relMSE τ, lumiere ÷ {} {} (targets at 1e-3 with the defaults: ≤ 0.25 on the Cornell box, ≤ 0.50 with --terms all or --lights area)",
        peer.renderer, peer.estimator
    );
    let mut bounded = false;
    for ours in curves.iter().filter(|c| c.renderer == LUMIERE) {
        let ratios = [0, 1].map(|index| TimeRatio::of(ours, peer, index));
        bounded |= ratios
            .iter()
            .any(|r| matches!(r, TimeRatio::Below(_) | TimeRatio::Above(_)));
        let _ = writeln!(
            out,
            "  {:<10} {:<width$} {:>14} {:>14}",
            ours.renderer,
            ours.estimator,
            ratios[0].to_string(),
            ratios[1].to_string()
        );
    }
    if bounded {
        let _ = writeln!(
            out,
            "  (< r: only lumiere reached τ, the peer's time is past its last render's; \
             > r: only the peer did)"
        );
    }
}

fn seconds(value: Option<f64>) -> String {
    value.map_or_else(|| "not reached".into(), |s| format!("{s:.2} s"))
}

impl BenchReport {
    /// The summary table printed at the end of a bench.
    pub fn summary(&self) -> String {
        let mut out = String::new();
        if !self.machine.is_empty() {
            let _ = writeln!(out, "machine: {}", self.machine);
        }
        if !self.curves.is_empty() {
            let _ = writeln!(
                out,
                "error against time (time to reach relMSE ≤ τ, log-log interpolation)"
            );
            if let Some(reference) = &self.reference {
                let _ = writeln!(out, "  reference: {reference}");
            }
            // as wide as the longest label ("mis/independent/auto split ×2")
            let width = self
                .curves
                .iter()
                .map(|c| c.estimator.chars().count())
                .max()
                .unwrap_or(0)
                .max(24);
            let _ = writeln!(
                out,
                "  {:<10} {:<width$} {:>14} {:>14}   last point",
                "renderer", "estimator", "τ = 1e-2", "τ = 1e-3"
            );
            for c in &self.curves {
                let _ = writeln!(
                    out,
                    "  {:<10} {:<width$} {:>14} {:>14}   {} spp, relMSE {:.2e}",
                    c.renderer,
                    c.estimator,
                    seconds(c.seconds_to[0]),
                    seconds(c.seconds_to[1]),
                    c.last_spp,
                    c.last_relmse
                );
            }
            for peer in self.curves.iter().filter(|c| c.renderer != LUMIERE) {
                write_peer_ratios(&mut out, &self.curves, peer, width);
            }
        }
        for note in &self.notes {
            let _ = writeln!(out, "  note: {note}");
        }
        if let Some(t) = &self.throughput {
            let _ = writeln!(out, "throughput (fastest of the runs)");
            let rays = &t.renderer_rays;
            let _ = writeln!(
                out,
                "  renderer rays: {} camera, {} shadow, {} bounce, {} gather",
                rays.camera, rays.shadow, rays.bounce, rays.gather
            );
            for r in &t.rows {
                let _ = writeln!(
                    out,
                    "  {:<10} {:<7} {:>10} rays {:>9.3} s {:>8.2} Mrays/s",
                    r.measure,
                    r.rays_of,
                    r.rays,
                    r.seconds,
                    r.mrays_per_second()
                );
            }
            let _ = writeln!(
                out,
                "  renderer ÷ traversal rays/s: {:.2}",
                t.bvh_ratio.unwrap_or(t.ratio)
            );
            if t.bvh_ratio.is_some() {
                let _ = writeln!(
                    out,
                    "  (traversal: obvhs's CWBVH; the renderer tests this scene's triangles in blocks: renderer ÷ block tests {:.2})",
                    t.ratio
                );
            }
        }
        if !self.scaling.is_empty() {
            let _ = writeln!(out, "scaling");
            let _ = writeln!(
                out,
                "  {:<15} {:>9} {:>9} {:>7} {:>8} {:>8} {:>14} {:>8} {:>8} {:>7}",
                "axis",
                "triangles",
                "image",
                "threads",
                "load s",
                "build s",
                "peak/kept B/tri",
                "s/spp",
                "Mrays/s",
                "÷ trav"
            );
            for r in &self.scaling {
                let memory = r
                    .bytes_per_triangle()
                    .map_or_else(|| "—".into(), |(p, k)| format!("{p:.0}/{k:.0}"));
                let _ = writeln!(
                    out,
                    "  {:<15} {:>9} {:>9} {:>7} {:>8.3} {:>8.3} {:>14} {:>8.3} {:>8.2} {:>7}",
                    r.axis.label(),
                    r.triangles,
                    format!("{}×{}", r.width, r.height),
                    r.threads,
                    r.load_seconds,
                    r.build_seconds,
                    memory,
                    r.seconds_per_spp(),
                    r.mrays_per_second(),
                    r.traversal_ratio()
                        .map_or_else(|| "—".into(), |q| format!("{q:.2}"))
                );
            }
            if let Some(g) = self.scaling.iter().find(|r| r.axis == Axis::GltfTriangles) {
                let _ = writeln!(
                    out,
                    "  glTF of {} triangles: load + build {:.2} s (target at 10⁶ triangles: < 3 s){}",
                    g.triangles,
                    g.load_seconds + g.build_seconds,
                    g.bytes_per_triangle()
                        .map_or_else(String::new, |(p, _)| format!(
                            ", peak {p:.0} bytes/triangle (target < 300)"
                        ))
                );
            }
        }
        let _ = writeln!(out, "files:");
        for f in &self.files {
            let _ = writeln!(out, "  {}", f.display());
        }
        out
    }
}
