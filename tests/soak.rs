//! A soak of the viewer's render worker: thousands of random setting
//! changes, as fast as a lecturer's clicker or a student's fiddling sends
//! them, never block the caller, never make an invalid sample, never stop
//! the worker following the last request, and never grow memory.

use std::sync::Arc;
use std::time::{Duration, Instant};

use lumiere::course::{
    Adaptive, IndirectSampling, Integrator, LightSampling, Sampler, SourceQuality,
};
use lumiere::render::progressive::{ProgressiveRenderer, Snapshot, ViewRequest};
use lumiere::scene::{Scene, builtin};
use lumiere::transport::sources;
use lumiere::{BrdfOverride, LightMode, RenderSettings, Term, TermSet};
use strum::IntoEnumIterator;

/// Random setting changes the soak sends.
const CHANGES: usize = 3000;
/// A call that takes this long is stuck, not slow (the call only posts the request).
const STUCK: Duration = Duration::from_secs(2);

/// xorshift64*: the soak's own numbers, fixed by its seed.
struct Numbers(u64);

impl Numbers {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    fn pick<T: Clone>(&mut self, choices: &[T]) -> T {
        choices[self.below(choices.len())].clone()
    }

    fn chance(&mut self, one_in: usize) -> bool {
        self.below(one_in) == 0
    }
}

/// Resident memory of this process in bytes (Linux's /proc/self/statm).
fn resident_bytes() -> u64 {
    let statm = std::fs::read_to_string("/proc/self/statm").unwrap();
    let pages: u64 = statm.split_whitespace().nth(1).unwrap().parse().unwrap();
    pages * 4096
}

/// Random settings a viewer could send for `scene`.
fn random_settings(numbers: &mut Numbers, scene: &Scene) -> RenderSettings {
    let mut terms = TermSet::NONE;
    for term in TermSet::ALL.iter() {
        if numbers.chance(2) {
            terms = terms.with(term, true);
        }
    }
    if terms.is_empty() {
        terms = TermSet::only(Term::L1);
    }
    let mut settings = RenderSettings {
        width: 16 + numbers.below(80) as u32,
        height: 12 + numbers.below(60) as u32,
        terms,
        light_mode: numbers.pick(&LightMode::iter().collect::<Vec<_>>()),
        brdf: numbers.pick(&BrdfOverride::iter().collect::<Vec<_>>()),
        integrator: numbers.pick(&Integrator::iter().collect::<Vec<_>>()),
        light_sampling: numbers.pick(&LightSampling::iter().collect::<Vec<_>>()),
        indirect_sampling: numbers.pick(&IndirectSampling::iter().collect::<Vec<_>>()),
        sampler: numbers.pick(&Sampler::iter().collect::<Vec<_>>()),
        light_samples: 1 + numbers.below(3) as u32,
        indirect_samples: 1 + numbers.below(3) as u32,
        auto_indirect_samples: numbers.chance(8),
        max_bounces: 1 + numbers.below(8) as u32,
        seed: numbers.next() % 4,
        ..RenderSettings::default()
    };
    if numbers.chance(6) {
        settings.adaptive = Some(Adaptive {
            threshold: 0.05,
            ..Adaptive::default()
        });
    }
    if numbers.chance(4) {
        for key in sources::sources(scene) {
            let name = key.name(scene);
            if settings.sources.iter().any(|q| q.name == name) {
                continue;
            }
            settings.sources.push(if numbers.chance(4) {
                SourceQuality::off(name)
            } else {
                SourceQuality::samples(name, 1 + numbers.below(4) as u32)
            });
        }
    }
    settings.validate().unwrap();
    settings
}

/// Polls the worker until `done` holds (fails after 120 s rather than hang).
fn wait_for(renderer: &ProgressiveRenderer, what: &str, done: impl Fn(&Snapshot) -> bool) {
    let deadline = Instant::now() + Duration::from_secs(120);
    while !done(&renderer.snapshot()) {
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn thousands_of_random_setting_changes_never_block_crash_or_grow_memory() {
    let scenes: Vec<Arc<Scene>> = builtin::SCENES
        .iter()
        .map(|s| Arc::new(builtin::load(s.name).unwrap()))
        .collect();
    let first = ViewRequest {
        scene: Arc::clone(&scenes[0]).into(),
        camera: scenes[0].default_camera(),
        settings: RenderSettings {
            width: 32,
            height: 24,
            ..RenderSettings::default()
        },
        paused: false,
        stop_at_spp: None,
        term_images: false,
        film: 0,
    };
    let renderer = ProgressiveRenderer::spawn_with_threads(first, Some(2), || {});
    let mut numbers = Numbers(0x9e37_79b9_7f4a_7c15);
    let mut resident = Vec::new();
    let mut invalid = 0;
    let mut passes_seen = 0u64;
    for change in 0..CHANGES {
        let scene = numbers.pick(&scenes);
        let request = ViewRequest {
            camera: scene.default_camera(),
            settings: random_settings(&mut numbers, &scene),
            scene: scene.into(),
            paused: numbers.chance(10),
            stop_at_spp: numbers.chance(3).then(|| 1 + numbers.below(4) as u32),
            // the four-up's images of each term, now and then
            term_images: numbers.chance(3),
            // a lesson step opened, now and then
            film: numbers.below(2) as u64,
        };
        let start = Instant::now();
        renderer.request(request);
        let snapshot = renderer.snapshot();
        assert!(
            start.elapsed() < STUCK,
            "change {change}: the request blocked for {:?}",
            start.elapsed()
        );
        invalid += snapshot.rays.invalid_samples;
        passes_seen = passes_seen.max(snapshot.generation);
        // a key repeats every 30 ms or so; some changes come at once
        if numbers.chance(2) {
            std::thread::sleep(Duration::from_millis(numbers.below(4) as u64));
        }
        if change % 500 == 499 {
            resident.push(resident_bytes());
        }
    }
    // the worker still follows: the last request reaches the image
    let scene = Arc::clone(&scenes[1]);
    let last = RenderSettings {
        width: 40,
        height: 30,
        terms: TermSet::ALL,
        sources: vec![SourceQuality::samples("light", 2)],
        ..RenderSettings::default()
    };
    renderer.request(ViewRequest {
        camera: scene.default_camera(),
        settings: last.clone(),
        scene: scene.into(),
        paused: false,
        stop_at_spp: None,
        term_images: true,
        film: 0,
    });
    wait_for(&renderer, "the last request's image", |s| {
        s.source
            .as_ref()
            .is_some_and(|source| source.settings == last)
            && s.samples_per_pixel() >= 4
    });
    assert_eq!(invalid, 0, "invalid samples during the soak");
    assert!(
        passes_seen > 100,
        "the worker published only {passes_seen} images"
    );
    // memory: after the first 500 changes (allocator pools, caches) the
    // resident size stays flat (7 MB here); a film or a context kept per
    // change (≥ 10 kB each, 2500 changes) would add more than the allowance
    let (settled, end) = (resident[0], *resident.last().unwrap());
    let allowance = 16 << 20;
    assert!(
        end <= settled + allowance,
        "resident memory grew from {} MB to {} MB over {CHANGES} changes ({:?})",
        settled >> 20,
        end >> 20,
        resident.iter().map(|r| r >> 20).collect::<Vec<_>>()
    );
}
