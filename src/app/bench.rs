//! `lumiere view --bench`: the viewer measures itself in a real window.
//!
//! It alternates the BRDF override (a change of radiance: the worker restarts)
//! and times each toggle until the frame that draws the new preview, then
//! waits for two full-resolution passes before the next toggle. Meanwhile it
//! records how long each UI frame takes to build (`ui()` on the UI thread) and
//! the interval between frames. When done it prints the figures and closes.

use std::time::Duration;

use crate::course::BrdfOverride;
use crate::platform::time::Instant;
use crate::render::progressive::Snapshot;

/// Toggles measured per run.
const TOGGLES: usize = 12;

#[derive(Default)]
pub struct Bench {
    /// When the last toggle was posted, and the generation then on screen.
    pending: Option<(Instant, u64)>,
    latencies: Vec<Duration>,
    frame_times: Vec<Duration>,
    frame_intervals: Vec<Duration>,
    last_frame: Option<Instant>,
}

/// What the bench asks of the app this frame.
pub enum BenchStep {
    Wait,
    /// Toggle the BRDF override to this value, then call `posted`.
    Toggle(BrdfOverride),
    Finished(String),
}

impl Bench {
    /// Call at the start of a frame.
    pub fn frame_started(&mut self, now: Instant) {
        if let Some(last) = self.last_frame.replace(now) {
            self.frame_intervals.push(now - last);
        }
    }

    /// Call at the end of a frame with the time `ui()` took, while rendering.
    pub fn frame_built(&mut self, took: Duration) {
        self.frame_times.push(took);
    }

    pub fn step(&mut self, snapshot: &Snapshot, current: BrdfOverride) -> BenchStep {
        if let Some((sent, generation)) = self.pending {
            if snapshot.preview && snapshot.generation > generation {
                self.latencies.push(sent.elapsed());
                self.pending = None;
            }
            return BenchStep::Wait;
        }
        if snapshot.preview || snapshot.samples_per_pixel() < 2 {
            return BenchStep::Wait;
        }
        if self.latencies.len() >= TOGGLES {
            return BenchStep::Finished(self.report());
        }
        BenchStep::Toggle(if current == BrdfOverride::Mirror {
            BrdfOverride::Authored
        } else {
            BrdfOverride::Mirror
        })
    }

    /// Call right after the toggled request was posted to the worker.
    pub fn posted(&mut self, generation_on_screen: u64) {
        self.pending = Some((Instant::now(), generation_on_screen));
    }

    fn report(&self) -> String {
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        let stats = |values: &[Duration]| {
            let mut sorted: Vec<f64> = values.iter().map(|&d| ms(d)).collect();
            sorted.sort_by(f64::total_cmp);
            let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
            format!(
                "median {:.1} ms, p95 {:.1} ms, max {:.1} ms ({} samples)",
                at(0.5),
                at(0.95),
                at(1.0),
                sorted.len()
            )
        };
        format!(
            "toggle to preview on screen: {}\nUI frame build time: {}\nframe interval: {}",
            stats(&self.latencies),
            stats(&self.frame_times),
            stats(&self.frame_intervals)
        )
    }
}
