//! Rays per second of the whole renderer against the BVH traversal alone.
//!
//! The renderer's rays per second count every ray it traces (camera, shadow,
//! continuation, gathered) over the wall time of full passes: sampling,
//! shading, BRDFs, film accumulation and traversal. To see how much of that
//! is traversal, the same passes are rendered once more with the path log on
//! ([`crate::transport::sample_pixel_logged`]), which keeps every ray as traced
//! (origin, direction, t_max, the sphere a shadow ray aims at), and those
//! exact rays are traced again through the same [`Accel`], with the query
//! the renderer used ([`Query`]): closest hit for camera rays and
//! continuations that go on, any hit (`occluded`) for shadow rays, the
//! emitter search for rays that only look for a light (gathered directions,
//! a path's last segment); same threads, same order.
//!
//! ratio = renderer rays/s ÷ replay rays/s: 1 would mean all the time is
//! traversal; the rest is the cost of everything else per ray.
//!
//! A scene small enough for its triangles to be tested in blocks
//! (`accel/blocks.rs`) skips the BVH: the replay then measures those block
//! tests, and the same rays are replayed once more through obvhs's CWBVH
//! traversal ([`Accel::bvh_only`]), the yardstick of the target: the row
//! `cwbvh`, and `Throughput::bvh_ratio`.

use std::time::Duration;

use rayon::prelude::*;
use serde::Serialize;

use crate::geometry::Ray;
use crate::geometry::accel::{Accel, Query};
use crate::platform::time::Instant;
use crate::render::{Budget, render, sample_stream};
use crate::transport::counts::RayCounts;
use crate::transport::path_log::{PathLog, PathSegment, SegmentKind};
use crate::transport::sample_pixel_logged;
use crate::{Film, RenderContext};

use super::csv::{Decimals, csv_text};

/// The kinds of rays the renderer traces, as counted by [`RayCounts`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayKind {
    Camera,
    Shadow,
    Bounce,
    Gather,
}

impl RayKind {
    pub const ALL: [RayKind; 4] = [
        RayKind::Camera,
        RayKind::Shadow,
        RayKind::Bounce,
        RayKind::Gather,
    ];

    pub fn label(self) -> &'static str {
        match self {
            RayKind::Camera => "camera",
            RayKind::Shadow => "shadow",
            RayKind::Bounce => "bounce",
            RayKind::Gather => "gather",
        }
    }

    pub fn of(kind: SegmentKind) -> Self {
        match kind {
            SegmentKind::Camera => RayKind::Camera,
            SegmentKind::Shadow { .. } => RayKind::Shadow,
            SegmentKind::Bounce { .. } => RayKind::Bounce,
            SegmentKind::Gather { .. } => RayKind::Gather,
        }
    }

    fn count(self, counts: &RayCounts) -> u64 {
        match self {
            RayKind::Camera => counts.camera,
            RayKind::Shadow => counts.shadow,
            RayKind::Bounce => counts.bounce,
            RayKind::Gather => counts.gather,
        }
    }
}

/// A ray as the renderer traced it, with its query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecordedRay {
    pub ray: Ray,
    pub kind: RayKind,
    pub query: Query,
    /// For shadow rays: the sphere light aimed at, which does not block.
    pub target_sphere: Option<u32>,
}

impl RecordedRay {
    pub fn of(segment: &PathSegment) -> Self {
        let target_sphere = match segment.kind {
            SegmentKind::Shadow { target_sphere, .. } => target_sphere,
            _ => None,
        };
        Self {
            ray: segment.ray,
            kind: RayKind::of(segment.kind),
            query: segment.query,
            target_sphere,
        }
    }
}

/// Every ray segment of passes `0..passes` of `context`, pixel by pixel in the renderer's order.
pub fn record_segments(context: &RenderContext, passes: u32) -> Vec<PathSegment> {
    let (width, height) = (context.settings.width, context.settings.height);
    let pixels = width as usize * height as usize;
    (0..passes)
        .flat_map(|pass| {
            let logs: Vec<PathLog> = (0..pixels)
                .into_par_iter()
                .map(|index| {
                    let (x, y) = (
                        (index % width as usize) as u32,
                        (index / width as usize) as u32,
                    );
                    let stream = sample_stream(&context.settings, index as u64, pass);
                    let mut log = PathLog::default();
                    sample_pixel_logged(
                        context,
                        x,
                        y,
                        &stream,
                        &mut RayCounts::default(),
                        &mut log,
                    );
                    log
                })
                .collect();
            logs.into_iter().flat_map(|log| log.segments)
        })
        .collect()
}

/// Traces one recorded ray with the renderer's query; true if it hit (or was blocked).
#[inline]
pub fn replay_one(accel: &Accel, recorded: &RecordedRay) -> bool {
    match recorded.query {
        Query::Occlusion => accel.occluded(&recorded.ray, recorded.target_sphere),
        Query::ClosestHit => accel.closest_hit(&recorded.ray).is_some(),
        Query::VisibleEmitter => accel.visible_emitter(&recorded.ray).is_some(),
    }
}

/// Traces `rays` on the current rayon pool; returns how many hit (or were blocked).
pub fn replay(accel: &Accel, rays: &[RecordedRay]) -> u64 {
    rays.par_chunks(1024)
        .map(|chunk| chunk.iter().filter(|r| replay_one(accel, r)).count() as u64)
        .sum()
}

/// Whether tracing `segment`'s ray again reproduces what the renderer
/// logged: the same verdict for shadow rays; for the others the same hit
/// point (or a miss), and for a light search an emitter there or none.
pub fn replay_matches(context: &RenderContext, segment: &PathSegment) -> bool {
    let ray = &segment.ray;
    if let SegmentKind::Shadow {
        occluded,
        target_sphere,
    } = segment.kind
    {
        return context.accel.occluded(ray, target_sphere) == occluded;
    }
    let ends_where_logged = match context.accel.closest_hit(ray) {
        Some(hit) => ray.at(hit.t()) == segment.to,
        None => {
            segment.to == ray.origin + ray.direction.normalize_or_zero() * context.escape_length
        }
    };
    let emitter_where_logged = match segment.query {
        Query::VisibleEmitter => context
            .accel
            .visible_emitter(ray)
            .is_none_or(|hit| ray.at(hit.t()) == segment.to),
        _ => true,
    };
    ends_where_logged && emitter_where_logged
}

/// One line of the throughput table.
#[derive(Clone, Debug, PartialEq)]
pub struct ThroughputRow {
    /// `renderer` (full passes), `traversal` (the replay) or `cwbvh` (the
    /// replay through the CWBVH, for a scene whose queries test blocks).
    pub measure: String,
    /// `all` or one [`RayKind`] label.
    pub rays_of: String,
    pub rays: u64,
    pub seconds: f64,
}

impl ThroughputRow {
    pub fn mrays_per_second(&self) -> f64 {
        self.rays as f64 / self.seconds.max(1e-12) / 1e6
    }
}

/// The header of the throughput CSV, in order.
pub const THROUGHPUT_COLUMNS: [&str; 5] =
    ["measure", "rays_of", "rays", "seconds", "mrays_per_second"];

/// One line of the throughput CSV: a [`ThroughputRow`] and its rate.
#[derive(Serialize)]
struct ThroughputRecord<'a> {
    measure: &'a str,
    rays_of: &'a str,
    rays: u64,
    seconds: Decimals<6>,
    mrays_per_second: Decimals<3>,
}

/// The throughput CSV text.
pub fn throughput_csv(rows: &[ThroughputRow]) -> String {
    csv_text(
        &THROUGHPUT_COLUMNS,
        rows.iter().map(|r| ThroughputRecord {
            measure: &r.measure,
            rays_of: &r.rays_of,
            rays: r.rays,
            seconds: Decimals(r.seconds),
            mrays_per_second: Decimals(r.mrays_per_second()),
        }),
    )
}

/// The result of the throughput section.
#[derive(Clone, Debug, PartialEq)]
pub struct Throughput {
    pub rows: Vec<ThroughputRow>,
    /// Rays of the renderer by kind (for the summary).
    pub renderer_rays: RayCounts,
    /// Renderer rays/s ÷ traversal rays/s, all rays.
    pub ratio: f64,
    /// Renderer rays/s ÷ CWBVH traversal rays/s, when the renderer's
    /// queries test blocks instead (else `ratio` is that already).
    pub bvh_ratio: Option<f64>,
}

/// The rays of `passes` passes of `context` as [`record_segments`] logs them.
pub fn recorded_rays(context: &RenderContext, passes: u32) -> Vec<RecordedRay> {
    record_segments(context, passes)
        .iter()
        .map(RecordedRay::of)
        .collect()
}

/// The fastest of `repeats` replays of `rays` through `accel`.
pub fn fastest_replay(accel: &Accel, rays: &[RecordedRay], repeats: u32) -> Duration {
    (0..repeats.max(1))
        .map(|_| {
            let start = Instant::now();
            std::hint::black_box(replay(accel, std::hint::black_box(rays)));
            start.elapsed()
        })
        .min()
        .unwrap_or_default()
}

/// Times `passes` full passes of `context` and the replay of their rays,
/// each the fastest of `repeats` runs, on the current rayon pool.
pub fn measure(context: &RenderContext, passes: u32, repeats: u32) -> Throughput {
    let repeats = repeats.max(1);
    let mut renderer_time = Duration::MAX;
    let mut renderer_rays = RayCounts::default();
    for _ in 0..repeats {
        let mut film = Film::new(context.settings.width, context.settings.height);
        let stats = render(context, &mut film, Budget::Samples(passes), |_| {});
        renderer_time = renderer_time.min(stats.elapsed);
        renderer_rays = stats.rays;
    }
    let rays = recorded_rays(context, passes);
    let fastest = |rays: &[RecordedRay]| fastest_replay(&context.accel, rays, repeats);
    let traversal_time = fastest(&rays);
    let mut rows = vec![
        ThroughputRow {
            measure: "renderer".into(),
            rays_of: "all".into(),
            rays: renderer_rays.total(),
            seconds: renderer_time.as_secs_f64(),
        },
        ThroughputRow {
            measure: "traversal".into(),
            rays_of: "all".into(),
            rays: rays.len() as u64,
            seconds: traversal_time.as_secs_f64(),
        },
    ];
    for kind in RayKind::ALL {
        let of_kind: Vec<RecordedRay> = rays.iter().filter(|r| r.kind == kind).copied().collect();
        if of_kind.is_empty() {
            continue;
        }
        debug_assert_eq!(of_kind.len() as u64, kind.count(&renderer_rays));
        rows.push(ThroughputRow {
            measure: "traversal".into(),
            rays_of: kind.label().into(),
            rays: of_kind.len() as u64,
            seconds: fastest(&of_kind).as_secs_f64(),
        });
    }
    let renderer_rate = rows[0].mrays_per_second();
    let ratio = renderer_rate / rows[1].mrays_per_second().max(1e-12);
    let mut bvh_ratio = None;
    if context.accel.tests_in_blocks() {
        let bvh_only = context.accel.bvh_only();
        let row = ThroughputRow {
            measure: "cwbvh".into(),
            rays_of: "all".into(),
            rays: rays.len() as u64,
            seconds: fastest_replay(&bvh_only, &rays, repeats).as_secs_f64(),
        };
        bvh_ratio = Some(renderer_rate / row.mrays_per_second().max(1e-12));
        rows.push(row);
    }
    Throughput {
        rows,
        renderer_rays,
        ratio,
        bvh_ratio,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::bench::csv::field_names;

    #[test]
    fn throughput_rows_are_written_under_their_columns() {
        let row = ThroughputRow {
            measure: "renderer".into(),
            rays_of: "all".into(),
            rays: 3_000_000,
            seconds: 1.5,
        };
        let text = throughput_csv(std::slice::from_ref(&row));
        assert_eq!(
            text,
            "measure,rays_of,rays,seconds,mrays_per_second\nrenderer,all,3000000,1.500000,2.000\n"
        );
        let record = ThroughputRecord {
            measure: "",
            rays_of: "",
            rays: 0,
            seconds: Decimals(0.0),
            mrays_per_second: Decimals(0.0),
        };
        assert_eq!(field_names(record), THROUGHPUT_COLUMNS.join(","));
    }
}
