//! Capturing a reference: the image errors are measured against.
//!
//! A reference is the same scene, camera and settings rendered to M samples
//! per pixel with a seed of its own, so that its noise is independent of the
//! image x_N measured against it. Then, per pixel of variance σ²,
//!
//! ```text
//! E[(x_N − r_M)²] = σ²/N + σ²/M
//! ```
//!
//! and a reference of M ≫ N samples adds only σ²/M to the measured MSE (with
//! the image's own seed it would share its first samples and the error would
//! vanish at N = M).
//!
//! What a reference is valid for is everything that decides the radiance —
//! scene, camera, size, terms, light mode, BRDF, bounces — and not the
//! estimator (light and indirect sampling, their counts, light selection,
//! sampler, seed): every unbiased estimator converges to the same image.

use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::{Arc, Weak};

use crate::analysis::convergence::EstimatorKey;
use crate::analysis::metrics::ReferenceImage;
use crate::course::RenderSettings;
use crate::platform::threads::{self, Job};
use crate::render::film::Film;
use crate::render::progressive::ImageSource;
use crate::render::{Budget, render_cancellable};
use crate::scene::{Camera, Scene};
use crate::transport::context::RenderContext;
use crate::transport::splitting::choose_continuations;

/// The seed a reference of an image of seed `seed` is rendered with.
pub fn reference_seed(seed: u64) -> u64 {
    // a bijection (odd multiplier) that sends neighbouring seeds far apart
    (seed ^ 0x5eed_5eed_5eed_5eed).wrapping_mul(0x9e37_79b9_7f4a_7c15)
}

/// `settings` with the estimator's choices and the seed set to their
/// defaults: two settings with equal radiance settings converge to one image.
pub fn radiance_settings(settings: &RenderSettings) -> RenderSettings {
    let defaults = RenderSettings::default();
    let mut radiance = settings.clone();
    EstimatorKey::of(&defaults).apply_to(&mut radiance);
    radiance.seed = defaults.seed;
    radiance
}

/// What a reference is valid for: scene, camera and radiance settings.
#[derive(Clone, Debug)]
pub struct ReferenceKey {
    scene: Weak<Scene>,
    camera: Camera,
    settings: RenderSettings,
}

impl ReferenceKey {
    pub fn new(scene: &Arc<Scene>, camera: &Camera, settings: &RenderSettings) -> Self {
        Self {
            scene: Arc::downgrade(scene),
            camera: camera.clone(),
            settings: radiance_settings(settings),
        }
    }

    /// Whether an image of `scene` seen by `camera` with `settings` converges
    /// to this reference (the same scene object, not merely an equal one).
    pub fn matches(&self, scene: &Weak<Scene>, camera: &Camera, settings: &RenderSettings) -> bool {
        Weak::ptr_eq(&self.scene, scene)
            && self.camera == *camera
            && self.settings == radiance_settings(settings)
    }

    /// [`matches`](Self::matches) for a published image.
    pub fn matches_source(&self, source: &ImageSource) -> bool {
        self.matches(&source.scene, &source.camera, &source.settings)
    }
}

/// A reference to render: the image `settings` describe, at `samples_per_pixel`.
#[derive(Clone, Debug)]
pub struct ReferenceJob {
    pub scene: Arc<Scene>,
    pub camera: Camera,
    /// The image's settings, its seed replaced by [`reference_seed`].
    pub settings: RenderSettings,
    pub samples_per_pixel: u32,
}

impl ReferenceJob {
    /// The reference of the image `settings` describe.
    pub fn new(
        scene: Arc<Scene>,
        camera: Camera,
        settings: &RenderSettings,
        samples_per_pixel: u32,
    ) -> Self {
        Self {
            scene,
            camera,
            settings: RenderSettings {
                seed: reference_seed(settings.seed),
                ..settings.clone()
            },
            samples_per_pixel: samples_per_pixel.max(1),
        }
    }

    /// What the reference will be valid for.
    pub fn key(&self) -> ReferenceKey {
        ReferenceKey::new(&self.scene, &self.camera, &self.settings)
    }

    /// Renders the reference on the calling thread (rayon's current pool),
    /// calling `progress` with the samples per pixel done after each pass;
    /// `None` if `cancel` was set before the end.
    pub fn run(
        &self,
        cancel: &AtomicBool,
        mut progress: impl FnMut(u32),
    ) -> Option<ReferenceImage> {
        let settings = &self.settings;
        let mut context = RenderContext::with_camera(
            Arc::clone(&self.scene),
            settings.clone(),
            Some(&self.camera),
        );
        choose_continuations(&mut context);
        let mut film = Film::new(settings.width, settings.height);
        render_cancellable(
            &context,
            &mut film,
            Budget::Samples(self.samples_per_pixel),
            cancel,
            |stats| progress(stats.samples_per_pixel),
        )?;
        Some(ReferenceImage {
            width: settings.width,
            height: settings.height,
            radiance: film.radiance(settings.terms),
            label: format!(
                "{} spp, {}",
                self.samples_per_pixel,
                EstimatorKey::of(settings).label()
            ),
        })
    }
}

/// A reference rendering on a thread of its own; dropping it cancels it.
pub struct ReferenceCapture {
    key: ReferenceKey,
    target: u32,
    done: Arc<AtomicU32>,
    cancel: Arc<AtomicBool>,
    thread: Option<Job<Option<ReferenceImage>>>,
}

impl ReferenceCapture {
    /// Starts `job`; `repaint` is called after each pass and at the end.
    pub fn spawn(job: ReferenceJob, repaint: impl Fn() + Send + 'static) -> Self {
        let done = Arc::new(AtomicU32::new(0));
        let cancel = Arc::new(AtomicBool::new(false));
        let (key, target) = (job.key(), job.samples_per_pixel);
        let (thread_done, thread_cancel) = (Arc::clone(&done), Arc::clone(&cancel));
        let thread = threads::spawn("lumiere reference", move || {
            let image = job.run(&thread_cancel, |spp| {
                thread_done.store(spp, Ordering::Relaxed);
                repaint();
            });
            repaint();
            image
        });
        Self {
            key,
            target,
            done,
            cancel,
            thread: Some(thread),
        }
    }

    /// Samples per pixel done and to do.
    pub fn progress(&self) -> (u32, u32) {
        (self.done.load(Ordering::Relaxed), self.target)
    }

    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    pub fn is_finished(&self) -> bool {
        self.thread.as_ref().is_none_or(|t| t.is_finished())
    }

    /// Waits for the end: the reference and what it is valid for, `None` if
    /// cancelled.
    pub fn join(mut self) -> Option<(ReferenceImage, ReferenceKey)> {
        let image = self.thread.take()?.join()??;
        Some((image, self.key.clone()))
    }
}

impl Drop for ReferenceCapture {
    fn drop(&mut self) {
        self.cancel();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}
