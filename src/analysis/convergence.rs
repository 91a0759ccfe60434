//! Convergence of estimators: error against a reference as samples and time grow.
//!
//! An unbiased estimator of per-pixel variance σ² averaged over N samples has
//!
//! ```text
//! MSE(N) = σ²/N   ⇒   log RMSE = log σ − ½ log N,    log relMSE = c − log N
//! ```
//!
//! so on log-log axes RMSE falls on a line of slope −1/2 and relMSE on a line
//! of slope −1, against N and against the time t ∝ N. Two estimators differ by
//! the height of their lines; the time-independent figure that ranks them is
//!
//! ```text
//! efficiency = 1 / (relMSE × t)        (higher is better)
//! ```
//!
//! constant along a 1/N line: an estimator twice as efficient reaches the same
//! error in half the time. A curve keeps one point per power of two of N
//! (1, 2, 4, …) plus the latest one, so a long run stays a few dozen points.

use crate::analysis::metrics::ImageError;
use crate::course::Choice;
use crate::course::{
    Adaptive, IndirectSampling, LightSampling, LightSelection, MisHeuristic, RenderSettings,
    Sampler,
};

/// The choices of a [`RenderSettings`] that make an estimator, not the image it
/// converges to. The seed is not among them: it only draws another noise.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct EstimatorKey {
    pub light_sampling: LightSampling,
    pub mis_heuristic: MisHeuristic,
    pub indirect_sampling: IndirectSampling,
    pub light_samples: u32,
    pub indirect_samples: u32,
    pub auto_indirect_samples: bool,
    pub light_selection: LightSelection,
    pub sampler: Sampler,
    pub adaptive: Option<Adaptive>,
}

impl EstimatorKey {
    pub fn of(settings: &RenderSettings) -> Self {
        Self {
            light_sampling: settings.light_sampling,
            mis_heuristic: settings.mis_heuristic,
            indirect_sampling: settings.indirect_sampling,
            light_samples: settings.light_samples,
            indirect_samples: settings.indirect_samples,
            auto_indirect_samples: settings.auto_indirect_samples,
            light_selection: settings.light_selection,
            sampler: settings.sampler,
            adaptive: settings.adaptive,
        }
    }

    /// Writes this estimator's choices into `settings`, leaving the rest.
    pub fn apply_to(&self, settings: &mut RenderSettings) {
        settings.light_sampling = self.light_sampling;
        settings.mis_heuristic = self.mis_heuristic;
        settings.indirect_sampling = self.indirect_sampling;
        settings.light_samples = self.light_samples;
        settings.indirect_samples = self.indirect_samples;
        settings.auto_indirect_samples = self.auto_indirect_samples;
        settings.light_selection = self.light_selection;
        settings.sampler = self.sampler;
        settings.adaptive = self.adaptive;
    }

    /// Short name: light sampling · indirect sampling · sampler, then what
    /// differs from the defaults ("mis·brdf·sobol·auto split", "area·cosine·independent·4 light").
    pub fn label(&self) -> String {
        let defaults = RenderSettings::default();
        let mut light = self.light_sampling.label().to_string();
        if self.light_sampling == LightSampling::Mis && self.mis_heuristic != defaults.mis_heuristic
        {
            light = format!("{light}({})", self.mis_heuristic.label());
        }
        let mut parts = vec![
            light,
            self.indirect_sampling.label().to_string(),
            self.sampler.label().to_string(),
        ];
        if self.light_samples != 1 {
            parts.push(format!("{} light", self.light_samples));
        }
        if self.auto_indirect_samples {
            parts.push("auto split".into());
        } else if self.indirect_samples != 1 {
            parts.push(format!("{} indirect", self.indirect_samples));
        }
        if self.light_selection != defaults.light_selection {
            parts.push(format!("{} pick", self.light_selection.label()));
        }
        if let Some(adaptive) = &self.adaptive {
            parts.push(format!("adaptive {}%", 100.0 * adaptive.threshold));
        }
        parts.join("·")
    }
}

/// The error of an image at some point of its render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorPoint {
    pub samples_per_pixel: u32,
    /// Render time since the start of the run.
    pub seconds: f64,
    pub error: ImageError,
}

impl ErrorPoint {
    /// 1 / (relMSE × seconds); `None` while either is zero.
    pub fn efficiency(&self) -> Option<f64> {
        let cost = self.error.relmse * self.seconds;
        (cost > 0.0).then(|| 1.0 / cost)
    }
}

/// Which render a measurement comes from: a worker and its restart.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RunId {
    pub renderer: u64,
    pub restart: u64,
}

/// The error of one estimator along its latest run.
#[derive(Clone, Debug)]
pub struct Curve {
    pub key: EstimatorKey,
    pub run: RunId,
    /// One point per power of two of the sample count, in order.
    kept: Vec<ErrorPoint>,
    /// The last point measured, if after the last kept one.
    latest: Option<ErrorPoint>,
}

impl Curve {
    pub fn new(key: EstimatorKey, run: RunId) -> Self {
        Self {
            key,
            run,
            kept: Vec::new(),
            latest: None,
        }
    }

    /// Adds a measurement: kept when it reaches a new power of two of the
    /// sample count, else it only replaces the latest point.
    pub fn record(&mut self, point: ErrorPoint) {
        let octave = |spp: u32| spp.max(1).ilog2();
        match self.kept.last() {
            Some(last) if point.samples_per_pixel <= last.samples_per_pixel => {}
            Some(last) if octave(point.samples_per_pixel) == octave(last.samples_per_pixel) => {
                self.latest = Some(point);
            }
            _ => {
                self.kept.push(point);
                self.latest = None;
            }
        }
    }

    /// The points in order of sample count: the kept ones and the latest.
    pub fn points(&self) -> impl Iterator<Item = &ErrorPoint> {
        self.kept.iter().chain(self.latest.as_ref())
    }

    pub fn latest(&self) -> Option<&ErrorPoint> {
        self.latest.as_ref().or(self.kept.last())
    }

    pub fn len(&self) -> usize {
        self.points().count()
    }

    pub fn is_empty(&self) -> bool {
        self.kept.is_empty()
    }
}

/// One curve per estimator tried, in the order first tried.
#[derive(Clone, Debug, Default)]
pub struct CurveSet {
    curves: Vec<Curve>,
}

impl CurveSet {
    /// Records `point` on the curve of `key`; a new run of the same estimator
    /// (a restart, another seed) replaces the curve's points.
    pub fn record(&mut self, key: EstimatorKey, run: RunId, point: ErrorPoint) {
        let index = match self.curves.iter().position(|c| c.key == key) {
            Some(index) => index,
            None => {
                self.curves.push(Curve::new(key, run));
                self.curves.len() - 1
            }
        };
        let curve = &mut self.curves[index];
        if curve.run != run {
            *curve = Curve::new(key, run);
        }
        curve.record(point);
    }

    pub fn get(&self, key: &EstimatorKey) -> Option<&Curve> {
        self.curves.iter().find(|c| c.key == *key)
    }

    pub fn iter(&self) -> impl Iterator<Item = &Curve> {
        self.curves.iter()
    }

    pub fn is_empty(&self) -> bool {
        self.curves.is_empty()
    }

    pub fn clear(&mut self) {
        self.curves.clear();
    }
}

/// Least-squares slope of log10 y against log10 x over the points with both
/// positive; `None` with fewer than two distinct x.
pub fn log_log_slope(points: impl IntoIterator<Item = (f64, f64)>) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .into_iter()
        .filter(|&(x, y)| x > 0.0 && y > 0.0)
        .map(|(x, y)| (x.log10(), y.log10()))
        .collect();
    let n = logs.len() as f64;
    let mean_x = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let mean_y = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    (logs.len() >= 2 && sxx > 1e-12).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(spp: u32) -> ErrorPoint {
        ErrorPoint {
            samples_per_pixel: spp,
            seconds: spp as f64 * 0.1,
            error: ImageError {
                rmse: 1.0 / (spp as f64).sqrt(),
                relmse: 1.0 / spp as f64,
            },
        }
    }

    #[test]
    fn curves_keep_powers_of_two_and_the_latest_point() {
        let key = EstimatorKey::of(&RenderSettings::default());
        let run = RunId {
            renderer: 0,
            restart: 1,
        };
        let mut curves = CurveSet::default();
        for spp in [1, 2, 3, 5, 6, 7, 9, 10] {
            curves.record(key, run, point(spp));
        }
        let spps: Vec<u32> = curves
            .get(&key)
            .unwrap()
            .points()
            .map(|p| p.samples_per_pixel)
            .collect();
        assert_eq!(spps, [1, 2, 5, 9, 10]);
        // a new run of the same estimator starts the curve over
        let rerun = RunId {
            renderer: 0,
            restart: 2,
        };
        curves.record(key, rerun, point(1));
        assert_eq!(curves.get(&key).unwrap().len(), 1);
        assert_eq!(curves.iter().count(), 1);
    }

    #[test]
    fn slope_and_efficiency_of_a_one_over_n_estimator() {
        let points: Vec<ErrorPoint> = [1, 4, 16, 64].map(point).into();
        let rmse = log_log_slope(
            points
                .iter()
                .map(|p| (p.samples_per_pixel as f64, p.error.rmse)),
        );
        assert!((rmse.unwrap() + 0.5).abs() < 1e-12);
        let relmse = log_log_slope(points.iter().map(|p| (p.seconds, p.error.relmse)));
        assert!((relmse.unwrap() + 1.0).abs() < 1e-12);
        // efficiency does not depend on how long the estimator ran
        assert!((points[0].efficiency().unwrap() - 10.0).abs() < 1e-9);
        assert!((points[3].efficiency().unwrap() - 10.0).abs() < 1e-9);
        assert_eq!(log_log_slope([(1.0, 1.0)]), None);
    }

    #[test]
    fn labels_name_the_strategies_and_what_differs_from_the_defaults() {
        let mut settings = RenderSettings::default();
        assert_eq!(
            EstimatorKey::of(&settings).label(),
            "mis·brdf·sobol·auto split"
        );
        settings.sampler = Sampler::Independent;
        settings.auto_indirect_samples = false;
        settings.light_samples = 4;
        settings.mis_heuristic = MisHeuristic::Balance;
        assert_eq!(
            EstimatorKey::of(&settings).label(),
            "mis(balance)·brdf·independent·4 light"
        );
    }
}
