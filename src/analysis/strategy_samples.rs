//! Where the estimator puts its samples at p: the directions the render's
//! own samples of a pixel take from its first hit, read from their path
//! logs (the same random streams as the film's), each with its strategy,
//! its value and its MIS weight; the running estimate as N grows; and
//! each strategy's density over the hemisphere, to lay over the map.
//!
//! For L1 the samples are the light samples (a shadow ray towards a point
//! drawn on a light: *light* strategy) and the directions drawn by the
//! BRDF or uniformly that look for a light (*directions* strategy); with
//! MIS each carries its weight, and the two kinds of a sample sum to its
//! value. For L2 and beyond they are p's continuations, each with the
//! radiance its path brought to the term.

use glam::{Vec2, Vec3, Vec3A};

use crate::course::color::luminance;
use crate::course::{IndirectSampling, LightSampling, Term, TermSet};
use crate::geometry::accel::{Hit, intersect_sphere};
use crate::geometry::{Ray, ShearedRay};
use crate::render::sample_stream;
use crate::transport::context::RenderContext;
use crate::transport::counts::RayCounts;
use crate::transport::light::{Light, cone_of};
use crate::transport::path_log::SegmentKind;
use crate::transport::surface::SurfacePoint;
use crate::transport::warps::{UNIFORM_HEMISPHERE_PDF, cosine_hemisphere_pdf, uniform_cone_pdf};
use crate::transport::{sample_pixel_logged, trace_logged};

use super::domains::lights_along;
use super::hemisphere::{IntegrandMap, ShadingPoint, Vertex, direction_to_disk, disk_to_direction};

/// How a sample's direction was drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// A point drawn on a light (next-event estimation).
    Light,
    /// A direction drawn on the hemisphere (by the BRDF, by cos θ or uniformly).
    Directions,
}

/// One direction a sample took from p.
#[derive(Clone, Copy, Debug)]
pub struct DrawnSample {
    /// The sample (pass) it belongs to.
    pub pass: u32,
    /// In p's frame, and on the map.
    pub direction: Vec3,
    pub disk: Vec2,
    pub strategy: Strategy,
    /// What it added to the term's sample (weighted, W/m²/sr).
    pub value: Vec3,
    /// Its MIS weight (1 without MIS).
    pub weight: f32,
    /// Whether it reached a light (a shadow ray unblocked, a direction that met one).
    pub reached_light: bool,
}

/// The samples of a pixel at its first hit, for one term.
#[derive(Clone, Debug)]
pub struct DrawnSamples {
    pub term: Term,
    pub samples: Vec<DrawnSample>,
    /// The term's value of each sample, pass by pass (what the film adds).
    pub per_pass: Vec<Vec3>,
    /// How each strategy draws here, in words (`None`: not used).
    pub light: Option<&'static str>,
    pub directions: Option<&'static str>,
}

/// The mean of the first `n` samples and its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunningEstimate {
    pub n: u32,
    pub mean: f64,
    pub standard_error: f64,
}

impl DrawnSamples {
    /// The term's mean over all the samples.
    pub fn mean(&self) -> Vec3 {
        self.per_pass.iter().sum::<Vec3>() / self.per_pass.len().max(1) as f32
    }

    /// The samples of the first `n` passes.
    pub fn first(&self, n: u32) -> impl Iterator<Item = &DrawnSample> {
        self.samples.iter().filter(move |s| s.pass < n)
    }

    /// The luminance of the estimate after 1, 2, 4, … samples, with its
    /// standard error (from the samples' own variance).
    pub fn running_estimate(&self) -> Vec<RunningEstimate> {
        let mut estimates = Vec::new();
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        let mut next = 1usize;
        for (k, value) in self.per_pass.iter().enumerate() {
            let y = luminance(*value) as f64;
            (sum, sum2) = (sum + y, sum2 + y * y);
            let n = k + 1;
            if n == next || n == self.per_pass.len() {
                let mean = sum / n as f64;
                let variance = if n > 1 {
                    ((sum2 - n as f64 * mean * mean) / (n as f64 - 1.0)).max(0.0)
                } else {
                    0.0
                };
                estimates.push(RunningEstimate {
                    n: n as u32,
                    mean,
                    standard_error: (variance / n as f64).sqrt(),
                });
                next *= 2;
            }
        }
        estimates.dedup_by_key(|e| e.n);
        estimates
    }
}

/// The first `passes` samples of pixel (`x`, `y`) at `vertex`, drawn with
/// `context` (its settings, continuations and random streams), seen from
/// p, the vertex's point: the directions they take from their first hit
/// for `term` (L1, L2 or L3+).
///
/// At the first hit they are the film's own samples: a sample's first hit
/// lies within the pixel's footprint around p. At a second vertex q they
/// are samples of the estimator started along the bounce p → q (the
/// pixel's streams, pass by pass): each estimates the term at q, sent
/// back to p.
pub fn drawn_samples(
    context: &RenderContext,
    p: &ShadingPoint,
    (x, y): (u32, u32),
    vertex: Vertex,
    term: Term,
    passes: u32,
) -> DrawnSamples {
    let settings = &context.settings;
    let pixel = y as u64 * settings.width as u64 + x as u64;
    let mut samples = Vec::new();
    let mut per_pass = Vec::with_capacity(passes as usize);
    for pass in 0..passes {
        let stream = sample_stream(settings, pixel, pass);
        let mut log = crate::transport::path_log::PathLog::default();
        let counts = &mut RayCounts::default();
        let radiance = match vertex {
            Vertex::FirstHit => sample_pixel_logged(context, x, y, &stream, counts, &mut log),
            Vertex::Second { bounce } => trace_logged(context, bounce, &stream, counts, &mut log),
        };
        per_pass.push(radiance[term.index()]);
        let mut add = |direction: Vec3, strategy, value, weight, reached_light| {
            let local = p.frame.to_local(direction.normalize());
            if local.z > 0.0 {
                samples.push(DrawnSample {
                    pass,
                    direction: local,
                    disk: direction_to_disk(local),
                    strategy,
                    value,
                    weight,
                    reached_light,
                });
            }
        };
        if term == Term::L1 {
            for segment in log.segments.iter().filter(|s| s.term == Term::L1) {
                let Some(weight) = segment.weight else {
                    continue; // a continuation whose emission another strategy counts
                };
                let (strategy, reached) = match segment.kind {
                    SegmentKind::Camera => continue,
                    SegmentKind::Shadow { occluded, .. } => (Strategy::Light, !occluded),
                    SegmentKind::Gather { hit_light } => (Strategy::Directions, hit_light),
                    SegmentKind::Bounce { .. } => {
                        (Strategy::Directions, segment.radiance.max_element() > 0.0)
                    }
                };
                add(
                    segment.ray.direction,
                    strategy,
                    segment.radiance,
                    weight,
                    reached,
                );
            }
        } else {
            // p's continuations (their ray is filed under L1, the term of
            // the vertex they leave), each with what its path brought to `term`
            let mut current: Option<(Vec3, Vec3)> = None;
            for segment in &log.segments {
                let leaves_p =
                    matches!(segment.kind, SegmentKind::Bounce { .. }) && segment.term == Term::L1;
                if leaves_p {
                    if let Some((direction, value)) = current.take() {
                        add(
                            direction,
                            Strategy::Directions,
                            value,
                            1.0,
                            value.max_element() > 0.0,
                        );
                    }
                    current = Some((segment.ray.direction, Vec3::ZERO));
                } else if segment.term == term
                    && let Some((_, value)) = current.as_mut()
                {
                    *value += segment.radiance;
                }
            }
            if let Some((direction, value)) = current {
                add(
                    direction,
                    Strategy::Directions,
                    value,
                    1.0,
                    value.max_element() > 0.0,
                );
            }
        }
    }
    let (light, directions) = strategies(context, term);
    DrawnSamples {
        term,
        samples,
        per_pass,
        light,
        directions,
    }
}

/// How each strategy draws for `term` under the context's settings.
pub fn strategies(
    context: &RenderContext,
    term: Term,
) -> (Option<&'static str>, Option<&'static str>) {
    let settings = &context.settings;
    if term != Term::L1 {
        let directions = match settings.indirect_sampling {
            IndirectSampling::Uniform => "uniform on the hemisphere",
            IndirectSampling::Cosine => "by cos θ",
            IndirectSampling::Brdf => "by the BRDF",
        };
        return (None, Some(directions));
    }
    match settings.light_sampling {
        LightSampling::Area => (Some("points on the lights, by area"), None),
        LightSampling::SolidAngle => (Some("by the lights' solid angle"), None),
        LightSampling::Brdf => (None, Some("by the BRDF")),
        LightSampling::Hemisphere => (None, Some("uniform on the hemisphere")),
        LightSampling::Mis => (Some("points on the lights, by area"), Some("by the BRDF")),
    }
}

/// The density (1/sr) with which `strategy` draws each pixel centre's
/// direction of a `size`×`size` map at p, for `term`: the light strategy's
/// through the light the direction meets (behind any occluder; a point
/// light has no density), the directions strategy's from its distribution.
pub fn strategy_density(
    context: &RenderContext,
    p: &ShadingPoint,
    term: Term,
    strategy: Strategy,
    size: u32,
) -> Vec<f32> {
    (0..size * size)
        .map(|i| {
            let centre = IntegrandMap::disk_point(size, i % size, i / size, Vec2::splat(0.5));
            disk_to_direction(centre).map_or(0.0, |w_local| {
                direction_density(context, p, term, strategy, w_local)
            })
        })
        .collect()
}

/// The density (1/sr) with which `strategy` draws the direction `w_local`
/// (p's frame, above the horizon) at p for `term`.
pub fn direction_density(
    context: &RenderContext,
    p: &ShadingPoint,
    term: Term,
    strategy: Strategy,
    w_local: Vec3,
) -> f32 {
    match strategy {
        Strategy::Directions => match directions_distribution(context, term) {
            IndirectSampling::Uniform => UNIFORM_HEMISPHERE_PDF,
            IndirectSampling::Cosine => cosine_hemisphere_pdf(w_local.z),
            IndirectSampling::Brdf => p.brdf.pdf(p.wo_local, w_local),
        },
        Strategy::Light => light_density(context, p, w_local),
    }
}

/// The distribution the directions strategy draws from for `term`: L1's
/// gathering draws by the BRDF (uniformly with hemisphere sampling), the
/// continuations by the indirect sampling chosen.
pub fn directions_distribution(context: &RenderContext, term: Term) -> IndirectSampling {
    let settings = &context.settings;
    if term == Term::L1 {
        match settings.light_sampling {
            LightSampling::Hemisphere => IndirectSampling::Uniform,
            _ => IndirectSampling::Brdf,
        }
    } else {
        settings.indirect_sampling
    }
}

/// Lights a density looks at one by one (more: through the scene's BVH).
const LIGHTS_TESTED_ONE_BY_ONE: usize = 64;

/// The light-sampling density of direction `w_local` at p: the sum over
/// the lights the direction meets, whatever stands in front of them (a
/// light sample is drawn whether or not it is hidden).
pub fn light_density(context: &RenderContext, p: &ShadingPoint, w_local: Vec3) -> f32 {
    let w = p.frame.to_world(w_local).normalize();
    let lights = &context.lights;
    if lights.lights.len() > LIGHTS_TESTED_ONE_BY_ONE {
        return lights_along(context, p.point.spawn_ray(w))
            .iter()
            .map(|behind| match (behind.hit, &behind.point) {
                (Hit::Sphere { sphere, .. }, _) => lights.sphere_emission(sphere, p.point.p, w).1,
                (Hit::Triangle { triangle, .. }, Some(point)) => {
                    lights.pdf_triangle(&context.scene, p.point.p, triangle, point)
                }
                _ => 0.0,
            })
            .sum();
    }
    // few lights: each intersected directly, cheaper than a walk through the scene
    let ray = ShearedRay::new(p.point.p.into(), w.into());
    let mut density = 0.0;
    for (index, light) in lights.lights.iter().enumerate() {
        match light {
            Light::Triangle {
                triangle, corners, ..
            } => {
                let [p0, p1, p2] = corners.map(Vec3A::from);
                if let Some(hit) = ray.intersect(f32::INFINITY, p0, p1, p2) {
                    let b = Vec3::new(hit.b0, hit.b1, hit.b2);
                    let point = SurfacePoint::new(&context.scene, *triangle, b);
                    density += lights.pdf_triangle(&context.scene, p.point.p, *triangle, &point);
                }
            }
            Light::Sphere { sphere, .. } => {
                let towards = Ray::new(p.point.p, w, f32::INFINITY);
                if intersect_sphere(&towards, sphere, f32::INFINITY).is_some()
                    && let Some((_, one_minus_cos)) = cone_of(sphere, p.point.p)
                {
                    density +=
                        lights.selection_probability(index) * uniform_cone_pdf(one_minus_cos);
                }
            }
            _ => {} // a Dirac: no density
        }
    }
    density
}

/// The terms the samples' context renders: the view's, and `term`.
pub fn sampled_terms(shown: TermSet, term: Term) -> TermSet {
    shown.with(term, true)
}
