//! Error against time: how long an estimator takes to reach a given error.
//!
//! One progressive render per estimator, measured at N = 1, 2, 4, … samples
//! per pixel against a reference of M ≫ N samples (its own seed, see
//! [`crate::analysis::capture`]): wall time of the passes so far, RMSE and relMSE
//! ([`crate::analysis::metrics`]). For an unbiased estimator relMSE ≈ c/N, so on a
//! log-log plot against time each curve is a line of slope −1 and the better
//! estimator is the lower line. The figure of merit is the time to reach
//! relMSE ≤ τ, interpolated linearly in (log t, log relMSE) between the two
//! measured points that straddle τ ([`time_to_relmse`]).
//!
//! A curve still above the lowest τ at the last sample count goes on
//! doubling its samples up to `extend_spp` ([`next_extended_count`]), so
//! that a slow estimator gets a time to 10⁻³, not only a bound; the peer's
//! script is given the same rule. The limit stays well below the
//! reference's sample count, whose own error would otherwise be measured.
//!
//! The reference is cached in the output folder under a name that hashes
//! what decides the radiance (scene file, size, terms, lights, BRDF,
//! bounces) and its sample count, so a change of any of them renders a new
//! one; a reference's own noise adds its variance to every measured MSE.
//! The reference is therefore rendered with the least noisy estimator
//! lumiere has, whatever the curves use: Sobol numbers and the splitting
//! pilot's continuations per first hit, given the rays of `--reference-spp`
//! samples with one continuation ([`reference_plan`]). On a scene whose
//! continuations are noisy (a point light over a Cornell box) the default
//! estimator's 4096 spp left the reference a relMSE near 4·10⁻³, and no curve
//! could reach 10⁻³.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::analysis::capture::{radiance_settings, reference_seed};
use crate::analysis::metrics::{ReferenceImage, image_error};
use crate::course::Choice;
use crate::course::{Adaptive, LightSampling, RenderSettings, Sampler};
use crate::platform::time::Instant;
use crate::render::display::DisplaySettings;
use crate::render::export::{load_exr, save_image};
use crate::render::{Budget, render};
use crate::scene::{Scene, builtin};
use crate::transport::continuations::Continuations;
use crate::transport::splitting::choose_indirect_samples;
use crate::{Film, RenderContext};

use super::csv::ErrorRow;
use super::{BenchError, Progress};

/// The renderer name of lumiere's rows.
pub const LUMIERE: &str = "lumiere";

/// The relMSE thresholds of the figure of merit.
pub const RELMSE_THRESHOLDS: [f64; 2] = [1e-2, 1e-3];

/// One curve: a direct-lighting strategy with a sampler, uniform or adaptive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Estimator {
    pub light_sampling: LightSampling,
    pub sampler: Sampler,
    /// Adaptive sampling, whose spp column counts passes (not samples traced).
    pub adaptive: Option<Adaptive>,
    /// Continuations per first hit chosen by the splitting pilot, whose
    /// time the curve includes; otherwise the settings' count.
    pub auto_split: bool,
}

impl Estimator {
    /// `strategy/sampler`, then `/adaptive T`, then `/auto split`: the CSV's `estimator` column.
    pub fn label(&self) -> String {
        let mut label = format!("{}/{}", self.light_sampling.label(), self.sampler.label());
        if let Some(adaptive) = &self.adaptive {
            label += &format!("/adaptive {}", adaptive.threshold);
        }
        if self.auto_split {
            label += "/auto split";
        }
        label
    }

    /// Each of `estimators` with the settings' continuations, then with
    /// the pilot's choice.
    pub fn with_auto_split(estimators: &[Estimator]) -> Vec<Estimator> {
        estimators
            .iter()
            .flat_map(|&e| [false, true].map(|auto_split| Estimator { auto_split, ..e }))
            .collect()
    }

    /// Every strategy with every sampler; each twice with `adaptive`, uniform then adaptive.
    pub fn all_pairs(
        strategies: &[LightSampling],
        samplers: &[Sampler],
        adaptive: Option<Adaptive>,
    ) -> Vec<Estimator> {
        let modes = [None, adaptive];
        let modes = &modes[..if adaptive.is_some() { 2 } else { 1 }];
        strategies
            .iter()
            .flat_map(|&light_sampling| {
                samplers.iter().flat_map(move |&sampler| {
                    modes.iter().map(move |&adaptive| Estimator {
                        light_sampling,
                        sampler,
                        adaptive,
                        auto_split: false,
                    })
                })
            })
            .collect()
    }
}

/// What the error section measures.
#[derive(Clone, Debug)]
pub struct ErrorBench {
    /// `cornell` or a glTF path, as given on the command line.
    pub scene: String,
    /// Size, terms and every other setting; the estimators replace light sampling and sampler.
    pub settings: RenderSettings,
    pub estimators: Vec<Estimator>,
    /// The last sample count (the counts are 1, 2, 4, … up to it).
    pub max_spp: u32,
    /// A curve above the lowest threshold at `max_spp` doubles its samples
    /// until it reaches it or would pass this count (≤ `max_spp`: never).
    pub extend_spp: u32,
    /// Samples per pixel of a rendered reference.
    pub reference_spp: u32,
    /// A reference EXR to use instead of rendering one.
    pub reference: Option<PathBuf>,
}

/// 1, 2, 4, … below `max_spp`, then `max_spp`.
pub fn sample_counts(max_spp: u32) -> Vec<u32> {
    let mut counts: Vec<u32> = (0..32)
        .map(|k| 1u32 << k)
        .take_while(|&n| n < max_spp)
        .collect();
    counts.push(max_spp.max(1));
    counts
}

/// The lowest relMSE threshold, the one a curve is extended to reach.
pub fn lowest_threshold() -> f64 {
    RELMSE_THRESHOLDS.into_iter().fold(f64::INFINITY, f64::min)
}

/// The sample count after `done` of a curve past its planned counts:
/// twice `done` while its relMSE is above the lowest threshold and the
/// doubled count is within `limit`; `None` once it has reached the
/// threshold or the limit.
pub fn next_extended_count(done: u32, relmse: f64, limit: u32) -> Option<u32> {
    let next = done.checked_mul(2)?;
    (relmse > lowest_threshold() && next <= limit).then_some(next)
}

/// The first time a curve of (seconds, relMSE) points, in order of growing
/// spp, reaches relMSE ≤ `threshold`: the first point's time if it is
/// already there, else log-log interpolation between the last point above
/// and the first at or below; `None` if no point reaches it.
pub fn time_to_relmse(points: &[(f64, f64)], threshold: f64) -> Option<f64> {
    let first = points.first()?;
    if first.1 <= threshold {
        return Some(first.0);
    }
    points.windows(2).find_map(|pair| {
        let ((t0, e0), (t1, e1)) = (pair[0], pair[1]);
        if !(e0 > threshold && e1 <= threshold) {
            return None;
        }
        if t0 <= 0.0 || e1 <= 0.0 {
            return Some(t1);
        }
        let s = (threshold.ln() - e0.ln()) / (e1.ln() - e0.ln());
        Some((t0.ln() + s * (t1.ln() - t0.ln())).exp())
    })
}

/// The times of one curve (renderer, estimator) to each of [`RELMSE_THRESHOLDS`].
#[derive(Clone, Debug, PartialEq)]
pub struct CurveSummary {
    pub renderer: String,
    pub estimator: String,
    pub last_spp: u32,
    pub last_relmse: f64,
    /// The time of the last point's render.
    pub last_seconds: f64,
    /// One per threshold, in the order of [`RELMSE_THRESHOLDS`].
    pub seconds_to: [Option<f64>; 2],
}

/// One curve's time to a relMSE threshold divided by another's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TimeRatio {
    /// Both reached the threshold.
    Measured(f64),
    /// Only the first did: the other's time is longer than its last render,
    /// so the ratio is below this.
    Below(f64),
    /// Only the other did: the ratio is above this.
    Above(f64),
    /// Neither did.
    Unknown,
}

impl TimeRatio {
    /// `ours`' time to threshold number `index` ÷ `theirs'`.
    pub fn of(ours: &CurveSummary, theirs: &CurveSummary, index: usize) -> Self {
        match (ours.seconds_to[index], theirs.seconds_to[index]) {
            (Some(a), Some(b)) if b > 0.0 => Self::Measured(a / b),
            (Some(a), None) if theirs.last_seconds > 0.0 => Self::Below(a / theirs.last_seconds),
            (None, Some(b)) if b > 0.0 => Self::Above(ours.last_seconds / b),
            _ => Self::Unknown,
        }
    }
}

impl std::fmt::Display for TimeRatio {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Measured(r) => write!(f, "{r:.2}"),
            Self::Below(r) => write!(f, "< {r:.2}"),
            Self::Above(r) => write!(f, "> {r:.2}"),
            Self::Unknown => write!(f, "n/a"),
        }
    }
}

/// The curves of `rows`, grouped by (renderer, estimator) in order of first appearance.
pub fn curves(rows: &[ErrorRow]) -> Vec<(String, String, Vec<ErrorRow>)> {
    let mut curves: Vec<(String, String, Vec<ErrorRow>)> = Vec::new();
    for row in rows {
        match curves
            .iter_mut()
            .find(|(r, e, _)| *r == row.renderer && *e == row.estimator)
        {
            Some((_, _, points)) => points.push(row.clone()),
            None => curves.push((
                row.renderer.clone(),
                row.estimator.clone(),
                vec![row.clone()],
            )),
        }
    }
    for (_, _, points) in &mut curves {
        points.sort_by_key(|p| p.spp);
    }
    curves
}

/// The figure of merit of every curve of `rows`.
pub fn summarize(rows: &[ErrorRow]) -> Vec<CurveSummary> {
    curves(rows)
        .into_iter()
        .map(|(renderer, estimator, points)| {
            let xy: Vec<(f64, f64)> = points.iter().map(|p| (p.seconds, p.relmse)).collect();
            let last = points.last().expect("a curve has a point");
            CurveSummary {
                renderer,
                estimator,
                last_spp: last.spp,
                last_relmse: last.relmse,
                last_seconds: last.seconds,
                seconds_to: RELMSE_THRESHOLDS.map(|t| time_to_relmse(&xy, t)),
            }
        })
        .collect()
}

/// What identifies the scene's content: the built-in name, or a file's path, size and modification time.
fn scene_identity(scene: &str) -> String {
    if builtin::is_builtin(scene) {
        return format!("builtin:{scene}");
    }
    let metadata = std::fs::metadata(scene).ok();
    let size = metadata.as_ref().map_or(0, |m| m.len());
    let modified = metadata
        .and_then(|m| m.modified().ok())
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |d| d.as_nanos());
    let path = std::fs::canonicalize(scene).unwrap_or_else(|_| PathBuf::from(scene));
    format!("file:{}:{size}:{modified}", path.display())
}

/// 64-bit FNV-1a: a stable hash for cache file names (std's hasher may change between releases).
fn fnv1a(text: &str) -> u64 {
    text.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The cached reference's file name for `scene`, `settings` and `spp`.
pub fn reference_file_name(scene: &str, settings: &RenderSettings, spp: u32) -> String {
    let radiance = serde_json::to_string(&radiance_settings(settings)).unwrap_or_default();
    let key = format!(
        "{}|{radiance}|{spp}|{REFERENCE_METHOD}",
        scene_identity(scene)
    );
    format!("reference-{:016x}.exr", fnv1a(&key))
}

/// How the reference is rendered (part of its cache key): see [`reference_plan`].
const REFERENCE_METHOD: &str = "sobol, auto split, rays of the spp with one continuation";

/// The context and sample count of the reference for `settings`' radiance
/// and a budget of `spp` samples: Sobol numbers (the reference's own seed)
/// with the pilot's continuations per first hit, M, and as many samples as
/// cost the rays of `spp` samples with one, C₁ + C₂ rays each: spp · (C₁ +
/// C₂) / (C₁ + M C₂), at the nearest power of two (where Sobol's points fill
/// their strata).
pub fn reference_plan(
    scene: &Arc<Scene>,
    settings: &RenderSettings,
    spp: u32,
) -> (RenderContext, u32) {
    let mut reference_settings = radiance_settings(settings);
    reference_settings.seed = reference_seed(settings.seed);
    reference_settings.sampler = Sampler::Sobol;
    let mut context = RenderContext::new(scene.clone(), reference_settings);
    let choice = choose_indirect_samples(&context);
    context.continuations = choice.continuations();
    let mean = context.continuations.mean();
    if mean <= 1.0 {
        return (context, spp);
    }
    let cost = |m: f64| choice.first_rays + m * choice.continuation_rays;
    let samples = (spp as f64 * cost(1.0) / cost(mean)).max(1.0);
    let power_of_two = 2f64.powi(samples.log2().round() as i32) as u32;
    (context, power_of_two.clamp(1, spp.max(1)))
}

/// The reference of `bench`: its `--reference` file, the cached one in
/// `folder`, or a new render (then saved there). Returns it with its path.
pub fn reference(
    bench: &ErrorBench,
    scene: &Arc<Scene>,
    folder: &Path,
    progress: &dyn Progress,
) -> Result<(ReferenceImage, PathBuf), BenchError> {
    let settings = &bench.settings;
    let given = bench.reference.is_some();
    let path = bench.reference.clone().unwrap_or_else(|| {
        folder.join(reference_file_name(
            &bench.scene,
            settings,
            bench.reference_spp,
        ))
    });
    if given || path.exists() {
        let (width, height, radiance) = load_exr(&path)?;
        if (width, height) != (settings.width, settings.height) {
            return Err(BenchError::file(
                &path,
                format!(
                    "the reference is {width}×{height}, the bench renders {}×{} (set --width/--height to match)",
                    settings.width, settings.height
                ),
            ));
        }
        let name = path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        // a cached reference was rendered as `reference_plan` says
        let label = if given {
            name
        } else {
            format!("{name}, cached")
        };
        return Ok((
            ReferenceImage {
                width,
                height,
                radiance,
                label,
            },
            path,
        ));
    }
    progress.message("reference: pilot");
    let (context, spp) = reference_plan(scene, settings, bench.reference_spp);
    let mut film = Film::new(settings.width, settings.height);
    render(&context, &mut film, Budget::Samples(spp), |s| {
        progress.message(&format!(
            "reference: {}/{}",
            s.samples_per_pixel,
            reference_label(spp, &context.continuations)
        ))
    });
    let radiance = film.radiance(settings.terms);
    save_image(
        &path,
        settings.width,
        settings.height,
        &radiance,
        DisplaySettings::default(),
    )?;
    let image = ReferenceImage {
        width: settings.width,
        height: settings.height,
        radiance,
        label: reference_label(spp, &context.continuations),
    };
    Ok((image, path))
}

/// How a reference of `spp` samples with `continuations` per first hit was rendered.
fn reference_label(spp: u32, continuations: &Continuations) -> String {
    match continuations.label().as_str() {
        "1" => format!("{spp} spp, Sobol"),
        m => format!("{spp} spp, Sobol, {m} continuations per first hit"),
    }
}

/// Renders every estimator of `bench` progressively to its sample counts,
/// measuring time and error against `reference` after each.
pub fn measure_curves(
    bench: &ErrorBench,
    scene: &Arc<Scene>,
    reference: &ReferenceImage,
    progress: &dyn Progress,
) -> Vec<ErrorRow> {
    let counts = sample_counts(bench.max_spp);
    let mut rows = Vec::new();
    for estimator in &bench.estimators {
        let mut settings = bench.settings.clone();
        settings.light_sampling = estimator.light_sampling;
        settings.sampler = estimator.sampler;
        settings.adaptive = estimator.adaptive;
        settings.auto_indirect_samples = false;
        let mut context = RenderContext::new(scene.clone(), settings.clone());
        let (mut done, mut seconds) = (0, 0.0);
        let mut label = estimator.label();
        if estimator.auto_split {
            progress.message(&format!("error: {label}, pilot"));
            // the pilot is part of the render: its time counts
            let start = Instant::now();
            let choice = choose_indirect_samples(&context);
            seconds += start.elapsed().as_secs_f64();
            context.continuations = choice.continuations();
            label += &format!(" ×{}", context.continuations.label());
        }
        let mut film = Film::new(settings.width, settings.height);
        let mut planned = counts.iter().copied();
        let mut next = planned.next();
        while let Some(spp) = next {
            progress.message(&format!("error: {label} at {spp} spp"));
            let stats = render(&context, &mut film, Budget::Samples(spp - done), |_| {});
            done = spp;
            seconds += stats.elapsed.as_secs_f64();
            // measured outside the timed passes
            let error = image_error(&film.radiance(settings.terms), &reference.radiance)
                .expect("film and reference have the same size");
            rows.push(ErrorRow {
                renderer: LUMIERE.into(),
                estimator: label.clone(),
                spp,
                seconds,
                rmse: error.rmse,
                relmse: error.relmse,
            });
            next = planned
                .next()
                .or_else(|| next_extended_count(done, error.relmse, bench.extend_spp));
        }
    }
    rows
}
