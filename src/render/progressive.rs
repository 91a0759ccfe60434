//! Progressive rendering on a worker thread, for the viewer.
//!
//! The caller (the UI thread) never waits on the renderer: it posts a
//! [`ViewRequest`] — the whole description of what should be on screen — into
//! a latest-wins mailbox, and reads the latest [`Snapshot`] the worker
//! published. The worker adds one sample per pixel per pass over all cores
//! and decides what a new request costs:
//!
//! * a change of radiance (scene, light mode or radius, BRDF, camera, size,
//!   seed, bounces) **restarts**; a change of what the lights are built from
//!   (the scene, the light mode, radius, selection and sampling, the
//!   sources' qualities: [`LightTable::same_lights`]) rebuilds the lights and
//!   the BVH first. On a restart the film is cleared, a quick preview at a
//!   quarter of the resolution (one continuation per first hit) is published
//!   first, then the splitting pilot chooses the continuations, then
//!   full-resolution passes run; the pass under way is cancelled between
//!   tiles so the restart is prompt;
//! * a change of the visible terms does **not** restart: each term has its own
//!   accumulator and sample count; hidden terms are no longer computed but keep
//!   their samples, and a term switched on accumulates from where it was;
//! * pause and "stop at N spp" only start or stop the passes;
//! * asking for each term's image (the four-up layout) only publishes again.
//!
//! The worker knows nothing of the GUI: it calls a `repaint` closure after
//! each publication. It renders on rayon's global pool (all cores), or on a
//! pool of its own when given a thread count, so that two workers can share
//! the machine equally (the viewer's equal-time comparison). On a web page
//! without Web Workers ([`threads::ONE_THREAD`]) there is no worker thread:
//! the page calls [`ProgressiveRenderer::run_between_frames`] each frame,
//! which does the same work a few tiles at a time.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, Weak};
use std::time::Duration;

use crate::course::{RenderSettings, Term, TermSet};
use crate::geometry::camera::CameraRays;
use crate::platform::threads::{self, Job};
use crate::platform::time::Instant;
use crate::render::film::Film;
use crate::render::{Pass, PassBuffer, Until};
use crate::scene::{Camera, Scene};
use crate::transport::context::RenderContext;
use crate::transport::continuations::Continuations;
use crate::transport::counts::RayCounts;
use crate::transport::lights::LightTable;
use crate::transport::splitting::choose_continuations;

/// A scene as the viewer holds it, compared by identity: two requests show
/// the same scene when they hold the same `Arc` (comparing the triangles
/// would cost more than a frame).
#[derive(Clone, Debug)]
pub struct SharedScene(pub Arc<Scene>);

impl PartialEq for SharedScene {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl From<Arc<Scene>> for SharedScene {
    fn from(scene: Arc<Scene>) -> Self {
        Self(scene)
    }
}

impl std::ops::Deref for SharedScene {
    type Target = Arc<Scene>;
    fn deref(&self) -> &Arc<Scene> {
        &self.0
    }
}

/// Everything that decides what the viewer shows: two equal requests show
/// the same thing.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewRequest {
    pub scene: SharedScene,
    /// `terms` are the visible terms.
    pub settings: RenderSettings,
    pub camera: Camera,
    pub paused: bool,
    /// Stop adding samples once every visible term has this many per pixel.
    pub stop_at_spp: Option<u32>,
    /// Publish each visible term's image too (`Snapshot::term_images`),
    /// for the four-up layout.
    pub term_images: bool,
    /// A new value restarts the film even when nothing else changed: a
    /// lesson step opens on a film of its own, with the continuations the
    /// pilot chooses for its terms, as `lumiere render` renders the step.
    pub film: u64,
}

/// What an image shows: which scene, from where, with which settings.
#[derive(Clone, Debug)]
pub struct ImageSource {
    /// The scene rendered (weak: an image does not keep an old scene alive).
    pub scene: Weak<Scene>,
    pub camera: Camera,
    /// The settings rendered with; `terms` are the terms the image sums.
    pub settings: RenderSettings,
}

/// What the worker last finished: the image of the visible terms and its statistics.
#[derive(Clone, Debug, Default)]
pub struct Snapshot {
    /// Increases with every publication.
    pub generation: u64,
    /// Number of restarts so far (a term toggle must not add one).
    pub restarts: u64,
    pub width: u32,
    pub height: u32,
    /// A low-resolution preview published right after a restart.
    pub preview: bool,
    /// Linear RGBA radiance (A = 1) of the visible terms, rows from the top.
    pub radiance: Vec<[f32; 4]>,
    /// The visible terms this image sums.
    pub terms: TermSet,
    /// When the request asks for them: each visible term's image alone
    /// (linear RGBA, same size), by [`Term::index`]; `radiance` is their sum.
    pub term_images: [Option<Vec<[f32; 4]>>; Term::COUNT],
    /// Samples per pixel of each term.
    pub term_samples: [u32; Term::COUNT],
    /// Time spent rendering since the restart.
    pub elapsed: Duration,
    /// Rays traced since the restart.
    pub rays: RayCounts,
    /// Pixel samples added since the restart.
    pub pixel_samples: u64,
    /// Continuations per first hit the samples take (the pilot's choice,
    /// region by region, with `auto_indirect_samples`).
    pub continuations: Continuations,
    /// No more passes will run until the request changes (paused or reached the stop).
    pub idle: bool,
    /// What the image shows (`None` before the first publication).
    pub source: Option<ImageSource>,
}

impl Snapshot {
    /// The fewest samples per pixel among the visible terms.
    pub fn samples_per_pixel(&self) -> u32 {
        self.terms
            .iter()
            .map(|t| self.term_samples[t.index()])
            .min()
            .unwrap_or(0)
    }

    pub fn samples_per_second(&self) -> f64 {
        self.pixel_samples as f64 / self.elapsed.as_secs_f64().max(1e-9)
    }

    pub fn mrays_per_second(&self) -> f64 {
        self.rays.total() as f64 / self.elapsed.as_secs_f64().max(1e-9) / 1e6
    }
}

#[derive(Default)]
struct Mailbox {
    request: Option<ViewRequest>,
    quit: bool,
}

struct Shared {
    mailbox: Mutex<Mailbox>,
    wake: Condvar,
    /// Set when a request arrives: the pass under way gives up.
    cancel: AtomicBool,
    snapshot: Mutex<Arc<Snapshot>>,
    /// The film being accumulated (a new one after each restart), for export.
    film: Mutex<Option<Arc<Mutex<Film>>>>,
}

/// The handle of a render worker thread; dropping it stops the thread.
pub struct ProgressiveRenderer {
    shared: Arc<Shared>,
    thread: Option<Job<()>>,
    /// On a page with one thread, the worker the page runs between frames.
    between_frames: Option<Mutex<Worker>>,
}

fn lock<T>(mutex: &Mutex<T>) -> MutexGuard<'_, T> {
    // a panic elsewhere must not take the viewer down with a poisoned lock
    threads::lock(mutex)
}

impl ProgressiveRenderer {
    /// Starts the worker on `request`; `repaint` is called after each publication.
    pub fn spawn(request: ViewRequest, repaint: impl Fn() + Send + 'static) -> Self {
        Self::spawn_with_threads(request, None, repaint)
    }

    /// [`spawn`](Self::spawn) on a pool of `threads` threads of its own
    /// (`None`: rayon's global pool, all cores).
    pub fn spawn_with_threads(
        request: ViewRequest,
        threads: Option<usize>,
        repaint: impl Fn() + Send + 'static,
    ) -> Self {
        if threads::ONE_THREAD {
            return Self::between_frames(request, repaint);
        }
        let shared = Self::shared(request);
        let worker = Worker::new(Arc::clone(&shared), Box::new(repaint));
        let thread = threads::spawn("lumiere render", move || {
            let pool = threads.and_then(|threads| threads::pool(threads, "lumiere render"));
            threads::install(pool.as_ref(), || worker.run());
        });
        Self {
            shared,
            thread: Some(thread),
            between_frames: None,
        }
    }

    /// The worker without a thread of its own, for a page with one thread
    /// ([`threads::ONE_THREAD`], where [`spawn`](Self::spawn) gives this):
    /// it renders only in [`run_between_frames`](Self::run_between_frames).
    pub fn between_frames(request: ViewRequest, repaint: impl Fn() + Send + 'static) -> Self {
        let shared = Self::shared(request);
        let worker = Worker::new(Arc::clone(&shared), Box::new(repaint));
        Self {
            shared,
            thread: None,
            between_frames: Some(Mutex::new(worker)),
        }
    }

    fn shared(request: ViewRequest) -> Arc<Shared> {
        Arc::new(Shared {
            mailbox: Mutex::new(Mailbox {
                request: Some(request),
                quit: false,
            }),
            wake: Condvar::new(),
            cancel: AtomicBool::new(false),
            snapshot: Mutex::new(Arc::new(Snapshot::default())),
            film: Mutex::new(None),
        })
    }

    /// Without a thread of its own ([`between_frames`](Self::between_frames)), the worker's
    /// work until `budget` has passed (at least one step): the latest
    /// request, then the preview, the pilot or tiles of the next pass. True
    /// while work remains (the page asks for another frame). A worker with
    /// a thread of its own renders there, and this does nothing.
    pub fn run_between_frames(&self, budget: Duration) -> bool {
        let Some(worker) = &self.between_frames else {
            return false;
        };
        let mut worker = lock(worker);
        let deadline = Instant::now() + budget;
        while worker.work(Some(deadline)) {
            if Instant::now() >= deadline {
                return true;
            }
        }
        false
    }

    /// Replaces what should be rendered (the latest request wins).
    pub fn request(&self, request: ViewRequest) {
        lock(&self.shared.mailbox).request = Some(request);
        self.shared.cancel.store(true, Ordering::Relaxed);
        self.shared.wake.notify_one();
    }

    /// The latest published snapshot.
    pub fn snapshot(&self) -> Arc<Snapshot> {
        Arc::clone(&lock(&self.shared.snapshot))
    }

    /// The film being accumulated. The worker holds its lock during a pass:
    /// read it from another thread than the UI's (export does).
    pub fn film(&self) -> Option<Arc<Mutex<Film>>> {
        lock(&self.shared.film).clone()
    }
}

impl Drop for ProgressiveRenderer {
    fn drop(&mut self) {
        lock(&self.shared.mailbox).quit = true;
        self.shared.cancel.store(true, Ordering::Relaxed);
        self.shared.wake.notify_one();
        // (in the browser the worker ends on its own: the page may not wait)
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// The continuations per first hit of the preview: the settings' count,
/// or one when the pilot chooses, so that the first picture does not wait
/// for the pilot.
fn preview_continuations(settings: &RenderSettings) -> Continuations {
    Continuations::uniform(if settings.auto_indirect_samples {
        1
    } else {
        settings.indirect_samples
    })
}

/// What a request asks for besides the settings, which the context owns.
struct View {
    scene: SharedScene,
    camera: Camera,
    paused: bool,
    stop_at_spp: Option<u32>,
    term_images: bool,
    film: u64,
}

/// `request` in two parts: its settings and the rest.
fn split(request: ViewRequest) -> (RenderSettings, View) {
    let ViewRequest {
        scene,
        settings,
        camera,
        paused,
        stop_at_spp,
        term_images,
        film,
    } = request;
    let view = View {
        scene,
        camera,
        paused,
        stop_at_spp,
        term_images,
        film,
    };
    (settings, view)
}

/// What the film has accumulated since the last restart.
struct Accumulation {
    film: Arc<Mutex<Film>>,
    next_sample: u32,
    needs_preview: bool,
    /// The continuations per first hit are still the preview's: the
    /// splitting pilot runs after the preview, before the first full pass.
    needs_pilot: bool,
    elapsed: Duration,
    rays: RayCounts,
    pixel_samples: u64,
    /// Adaptive sampling has stopped every pixel: the last pass traced nothing.
    converged: bool,
    /// The pass under way, some tiles done (cancelled by a request, or
    /// between frames on one thread).
    pass: Option<Pass>,
}

impl Accumulation {
    fn new(settings: &RenderSettings) -> Self {
        Self {
            film: Arc::new(Mutex::new(Film::new(settings.width, settings.height))),
            next_sample: 0,
            needs_preview: true,
            needs_pilot: true,
            elapsed: Duration::ZERO,
            rays: RayCounts::default(),
            pixel_samples: 0,
            converged: false,
            pass: None,
        }
    }
}

/// What the worker renders now; the context owns the settings.
struct Current {
    context: RenderContext,
    view: View,
    accumulation: Accumulation,
}

impl Current {
    /// Whether no pass is due, given the current film (locked by the caller).
    fn is_idle(&self, film: &Film) -> bool {
        let (view, accumulation) = (&self.view, &self.accumulation);
        let spp = self
            .context
            .settings
            .terms
            .iter()
            .map(|t| film.samples(t))
            .min()
            .unwrap_or(0);
        !accumulation.needs_preview
            && (view.paused || accumulation.converged || view.stop_at_spp.is_some_and(|n| spp >= n))
    }
}

/// The worker's state machine, the same with a thread of its own and
/// between a page's frames: [`Worker::work`] takes the latest request and
/// does one step.
struct Worker {
    shared: Arc<Shared>,
    repaint: Box<dyn Fn() + Send>,
    current: Option<Current>,
    buffer: PassBuffer,
    generation: u64,
    restarts: u64,
}

impl Worker {
    fn new(shared: Arc<Shared>, repaint: Box<dyn Fn() + Send>) -> Self {
        Self {
            shared,
            repaint,
            current: None,
            buffer: PassBuffer::default(),
            generation: 0,
            restarts: 0,
        }
    }

    /// On a thread of its own: works, and waits while there is nothing to do.
    fn run(mut self) {
        loop {
            {
                let mut mailbox = lock(&self.shared.mailbox);
                while !mailbox.quit && mailbox.request.is_none() && self.is_idle() {
                    mailbox = self
                        .shared
                        .wake
                        .wait(mailbox)
                        .unwrap_or_else(|poisoned| poisoned.into_inner());
                }
                if mailbox.quit {
                    return;
                }
            }
            self.work(None);
        }
    }

    /// Takes the latest request, then does one step (with a `deadline`:
    /// tiles of the pass until then). False if there was nothing to do.
    fn work(&mut self, deadline: Option<Instant>) -> bool {
        let request = {
            let mut mailbox = lock(&self.shared.mailbox);
            self.shared.cancel.store(false, Ordering::Relaxed);
            mailbox.request.take()
        };
        if let Some(request) = request {
            self.apply(request);
        }
        if self.is_idle() {
            return false;
        }
        self.step(deadline);
        true
    }

    fn is_idle(&self) -> bool {
        self.current
            .as_ref()
            .is_none_or(|current| current.is_idle(&lock(&current.accumulation.film)))
    }

    /// Takes a new request: rebuilds, restarts or only retargets the terms.
    fn apply(&mut self, request: ViewRequest) {
        let (settings, view) = split(request);
        let Some(current) = &mut self.current else {
            self.start(settings, view);
            return;
        };
        let old = &current.context.settings;
        let rebuild = current.view.scene != view.scene || !LightTable::same_lights(old, &settings);
        let restart = rebuild
            || current.view.camera != view.camera
            || current.view.film != view.film
            || RenderSettings {
                terms: settings.terms,
                ..old.clone()
            } != settings;
        if rebuild {
            self.start(settings, view);
        } else if restart {
            current.context.settings = settings;
            current.context.set_camera(&view.camera);
            current.view = view;
            self.restart();
        } else {
            // visible terms, pause, stop or the term images changed: no restart
            if current.context.settings.terms != settings.terms {
                // the tiles done hold the old terms' samples
                current.accumulation.pass = None;
            }
            current.context.settings.terms = settings.terms;
            current.accumulation.converged = false;
            current.view = view;
            self.publish_full();
        }
    }

    /// Builds lights and BVH for the request and starts from an empty film.
    fn start(&mut self, settings: RenderSettings, view: View) {
        let context =
            RenderContext::with_camera(Arc::clone(&view.scene), settings, Some(&view.camera));
        let accumulation = Accumulation::new(&context.settings);
        self.current = Some(Current {
            context,
            view,
            accumulation,
        });
        self.restart();
    }

    /// An empty film for the current context, the preview first.
    fn restart(&mut self) {
        let Some(current) = &mut self.current else {
            return;
        };
        current.context.continuations = preview_continuations(&current.context.settings);
        current.accumulation = Accumulation::new(&current.context.settings);
        *lock(&self.shared.film) = Some(Arc::clone(&current.accumulation.film));
        self.restarts += 1;
    }

    /// One unit of work: the preview after a restart, else one full pass
    /// (with a `deadline`: tiles of it until then).
    fn step(&mut self, deadline: Option<Instant>) {
        let Some(current) = &mut self.current else {
            return;
        };
        let start = Instant::now();
        if current.accumulation.needs_preview {
            let preview = Self::render_preview(current, &mut self.buffer, &self.shared.cancel);
            current.accumulation.elapsed += start.elapsed();
            current.accumulation.needs_preview = false;
            if let Some(film) = preview {
                self.publish(&film, true, false);
            }
            return;
        }
        let (context, accumulation) = (&mut current.context, &mut current.accumulation);
        if accumulation.needs_pilot {
            choose_continuations(context);
            accumulation.needs_pilot = false;
        }
        let mut film = lock(&accumulation.film);
        let pass = accumulation
            .pass
            .get_or_insert_with(|| Pass::new(context, &film, accumulation.next_sample));
        let until = Until {
            cancel: Some(&self.shared.cancel),
            deadline,
        };
        let counts = pass.render(context, &mut film, &mut self.buffer, &until);
        drop(film);
        accumulation.elapsed += start.elapsed();
        if let Some(counts) = counts {
            accumulation.pass = None;
            accumulation.rays.add(&counts);
            // one camera ray per sample traced (adaptive sampling traces fewer than the pixels)
            accumulation.pixel_samples += counts.camera;
            accumulation.converged = counts.camera == 0;
            accumulation.next_sample += 1;
            self.publish_full();
        }
    }

    /// One sample per pixel at a quarter of the resolution.
    fn render_preview(
        current: &mut Current,
        buffer: &mut PassBuffer,
        cancel: &AtomicBool,
    ) -> Option<Film> {
        let context = &mut current.context;
        let (width, height) = (
            context.settings.width.div_ceil(4),
            context.settings.height.div_ceil(4),
        );
        let full_camera = std::mem::replace(
            &mut context.camera,
            CameraRays::new(&current.view.camera, width, height),
        );
        let mut film = Film::new(width, height);
        let counts = Pass::new(context, &film, 0).render(
            context,
            &mut film,
            buffer,
            &Until::cancelled_by(cancel),
        );
        context.camera = full_camera;
        current.accumulation.rays.add(&counts?);
        Some(film)
    }

    fn publish_full(&mut self) {
        if let Some(current) = &self.current {
            let film = Arc::clone(&current.accumulation.film);
            let film = lock(&film);
            let idle = current.is_idle(&film);
            self.publish(&film, false, idle);
        }
    }

    fn publish(&mut self, film: &Film, preview: bool, idle: bool) {
        let Some(current) = &self.current else {
            return;
        };
        let (settings, view, accumulation) = (
            &current.context.settings,
            &current.view,
            &current.accumulation,
        );
        let terms = settings.terms;
        let rgba = |pixels: Vec<glam::Vec3>| -> Vec<[f32; 4]> {
            pixels
                .into_iter()
                .map(|p| p.extend(1.0).to_array())
                .collect()
        };
        let term_images = Term::ALL.map(|t| {
            (view.term_images && terms.contains(t)).then(|| rgba(film.radiance(TermSet::only(t))))
        });
        self.generation += 1;
        let snapshot = Snapshot {
            generation: self.generation,
            restarts: self.restarts,
            width: film.width,
            height: film.height,
            preview,
            radiance: rgba(film.radiance(terms)),
            terms,
            term_images,
            term_samples: Term::ALL.map(|t| if preview { 0 } else { film.samples(t) }),
            elapsed: accumulation.elapsed,
            rays: accumulation.rays,
            pixel_samples: accumulation.pixel_samples,
            continuations: current.context.continuations.clone(),
            idle,
            source: Some(ImageSource {
                scene: Arc::downgrade(&view.scene),
                camera: view.camera.clone(),
                settings: settings.clone(),
            }),
        };
        *lock(&self.shared.snapshot) = Arc::new(snapshot);
        (self.repaint)();
    }
}
