//! The lecture's estimator, written as the slides write it.
//!
//! The light reaching the camera from the point p it sees, towards ωo, is
//! split by the number of reflections it underwent:
//!
//! ```text
//! L = L0 + L1 + L2 + L3+
//! L0(p, ωo) = L_e(p, ωo)                                           emission
//! L1(p, ωo) = Σ_s ∫_Ωs L_e(q, −ω) f_r(p, ω → ωo) cos θ dω          direct lighting
//! L2(p, ωo) = ∫_Ω L_i(p, ω) f_r(p, ω → ωo) cos θ dω,
//!             with L_i(p, ω) ≈ L_direct(q, −ω), q seen from p along ω    indirect lighting
//! L3+       = the same step repeated: q reflects the direct lighting of a further point, …
//! ```
//!
//! Each integral is estimated by Monte Carlo with one sample: a point drawn
//! on a source for L1, a direction drawn by the BRDF for L2 and beyond. The
//! directions of L2 that hit a source bring nothing: that light was counted
//! in L1. A refraction through glass is an interaction like a reflection:
//! a light seen through a glass block is L2 (two refractions). This is the integrator to read against the course, and the oracle
//! the fast integrator (`transport/fast.rs`) is tested against; it has no
//! multiple importance sampling, splitting, counters or logs.

use glam::{Vec2, Vec3};

use crate::course::TermRadiance;
use crate::course::{Term, TermSet};
use crate::geometry::accel::Hit;
use crate::geometry::{Frame, Ray};
use crate::transport::brdf::Brdf;
use crate::transport::context::RenderContext;
use crate::transport::roulette;
use crate::transport::sampler::{SampleStream, dim};
use crate::transport::sources::SourceBudget;
use crate::transport::surface::{SurfacePoint, leaves_on_its_side};

/// The radiance arriving along `camera_ray` (unit direction), per term; the
/// terms outside `terms` are zero.
pub fn radiance(
    context: &RenderContext,
    camera_ray: &Ray,
    stream: &SampleStream,
    terms: TermSet,
) -> TermRadiance {
    let mut l = radiance_by_term(context, camera_ray, stream, terms);
    for term in Term::ALL {
        if !terms.contains(term) {
            l[term.index()] = Vec3::ZERO;
        }
    }
    l
}

/// Every term up to the deepest one of `terms`.
fn radiance_by_term(
    context: &RenderContext,
    camera_ray: &Ray,
    stream: &SampleStream,
    terms: TermSet,
) -> TermRadiance {
    let mut l = [Vec3::ZERO; Term::COUNT];
    let reflections = terms.last_reflection(context.settings.max_bounces);

    // ── L0 = L_e(p, ωo): the emission of the point p the camera sees
    let Some(hit) = context.accel.closest_hit(camera_ray) else {
        return l;
    };
    l[0] = emission(context, &hit, camera_ray);
    if reflections < 1 {
        return l;
    }
    let Some(p) = Surface::seen(context, &hit, camera_ray) else {
        return l;
    };

    // ── L1 = Σ_s ∫_Ωs L_e(q, −ω) f_r(p, ω → ωo) cos θ dω: direct lighting at p
    l[1] = direct_lighting(context, &p, stream, 0);
    if reflections < 2 {
        return l;
    }

    // ── L2 = ∫_Ω L_i(p, ω) f_r(p, ω → ωo) cos θ dω, L_i(p, ω) ≈ L_direct(q, −ω):
    // one direction ω drawn by the BRDF (weight f_r cos θ / pdf), q the point it sees
    let Some((q, weight)) = bounce(context, &p, stream, 0) else {
        return l;
    };
    l[2] = weight * direct_lighting(context, &q, stream, 1);

    // ── L3+: the same step, repeated from q
    l[3] = beyond_two_reflections(context, q, weight, stream, reflections);
    l
}

/// L3+ = Σ_{k ≥ 3} β_k L_direct(x_k): the path goes on from `q` (the second
/// reflection, reached with throughput `throughput`), each bounce multiplying
/// the throughput β by f_r cos θ / pdf, each point adding its direct lighting.
fn beyond_two_reflections(
    context: &RenderContext,
    q: Surface,
    throughput: Vec3,
    stream: &SampleStream,
    reflections: u32,
) -> Vec3 {
    let (mut x, mut beta) = (q, throughput);
    let mut radiance = Vec3::ZERO;
    for k in 2..reflections {
        let Some((next, weight)) = bounce(context, &x, stream, k - 1) else {
            break;
        };
        beta *= weight;
        // Russian roulette: go on with probability q and divide by q, which
        // keeps the mean and ends paths that carry little (`roulette.rs`)
        if k >= roulette::LECTURE_FIRST_SEGMENT {
            let survival = roulette::survival(beta);
            let u = stream.uniform(dim::vertex_base(k) + dim::RUSSIAN_ROULETTE);
            if u >= survival {
                break;
            }
            beta /= survival;
        }
        radiance += beta * direct_lighting(context, &next, stream, k);
        x = next;
    }
    radiance
}

/// A point where light reflects: its surface, its BRDF, and the directions
/// around it in the shading frame.
struct Surface {
    point: SurfacePoint,
    brdf: Brdf,
    /// Shading frame, its z on the side the light leaves towards.
    frame: Frame,
    /// Geometric normal on that side.
    ng: Vec3,
    /// Direction towards the viewer (or the previous point), local frame.
    wo_local: Vec3,
}

impl Surface {
    /// The reflecting surface `ray` hit, if it reflects anything (a sphere
    /// light is a pure emitter; a black material reflects nothing).
    fn seen(context: &RenderContext, hit: &Hit, ray: &Ray) -> Option<Surface> {
        let Hit::Triangle { triangle, b, .. } = *hit else {
            return None;
        };
        let point = SurfacePoint::new(&context.scene, triangle, b);
        let wo = -ray.direction;
        let brdf = point.brdf(&context.scene, &context.settings, wo);
        if brdf.is_black() {
            return None;
        }
        let (frame, ng) = point.frame_towards(wo);
        Some(Surface {
            point,
            brdf,
            frame,
            ng,
            wo_local: frame.to_local(wo),
        })
    }
}

/// L_e(q, ωo): the radiance the point `hit` emits back along `ray`.
fn emission(context: &RenderContext, hit: &Hit, ray: &Ray) -> Vec3 {
    match *hit {
        Hit::Sphere { sphere, .. } => {
            let (radiance, _pdf) =
                context
                    .lights
                    .sphere_emission(sphere, ray.origin, ray.direction);
            radiance
        }
        Hit::Triangle { triangle, b, .. } => {
            SurfacePoint::new(&context.scene, triangle, b).emitted(&context.scene, -ray.direction)
        }
    }
}

/// L_direct(x, ωo) = Σ_s ∫_Ωs L_e f_r cos θ dω at `x`, the point after
/// `vertex` earlier reflections.
///
/// A mirror or glass cannot sample a source (its f_r is a Dirac): it
/// passes on the light it sees in its one direction (glass draws
/// reflection or refraction). Elsewhere the sum over the sources is
/// estimated by one source s drawn with probability P(s), proportional to
/// its power: E[x_s / P(s)] = Σ_s x_s, for any number of sources; or, with
/// a quality for each source, by each source's own samples.
fn direct_lighting(
    context: &RenderContext,
    x: &Surface,
    stream: &SampleStream,
    vertex: u32,
) -> Vec3 {
    let base = dim::vertex_base(vertex);
    if x.brdf.is_delta() {
        return light_seen_through_dirac(context, x, stream.uniform2(base + dim::LIGHT_POSITION));
    }
    if let Some(budget) = context.lights.budget() {
        return quality_for_each_source(context, x, stream, base, budget);
    }
    let Some((source, probability)) = context
        .lights
        .pick(stream.uniform(base + dim::LIGHT_SELECT))
    else {
        return Vec3::ZERO; // no source
    };
    let u = stream.uniform2(base + dim::LIGHT_POSITION);
    light_from_source(context, x, source, u) / probability
}

/// The lecture's "a quality for each source": each source s that is on
/// gets its own N_s samples, averaged, and the sources are summed:
/// Σ_s (1/N_s) Σ_k estimate_k. A source made of several lights (an
/// emitter's triangles) picks one, t, with probability P(t | s).
fn quality_for_each_source(
    context: &RenderContext,
    x: &Surface,
    stream: &SampleStream,
    base: u32,
    budget: &SourceBudget,
) -> Vec3 {
    let count = budget.samples_per_vertex();
    let mut radiance = Vec3::ZERO;
    for slot in 0..count {
        let u = stream
            .split(slot, count)
            .uniform2(base + dim::LIGHT_POSITION);
        let Some((light, probability, samples, u_x)) = budget.pick(slot, u.x) else {
            continue;
        };
        let estimate = light_from_source(context, x, light, Vec2::new(u_x, u.y)) / probability;
        radiance += estimate / samples as f32;
    }
    radiance
}

/// ∫_Ωs L_e(q, −ω) f_r(x, ω → ωo) cos θ dω for source `source`, from one
/// sample `u`:
/// * a point light (or spot, or the sun): no integral, L_e f_r cos θ / d²
///   (or E f_r cos θ), the light's one direction;
/// * an extended light (a triangle, a sphere): a point q drawn on it with
///   solid-angle density pdf, L_e(q) f_r cos θ / pdf.
///
/// Zero if q is hidden from x (the shadow ray is blocked).
fn light_from_source(context: &RenderContext, x: &Surface, source: usize, u: Vec2) -> Vec3 {
    let scene = &context.scene;
    // with probability 1: the pdf is the density on this source alone
    let Some(light) = context.lights.sample_light(scene, &x.point, source, 1.0, u) else {
        return Vec3::ZERO;
    };
    let wi_local = x.frame.to_local(light.wi);
    let cos_theta = wi_local.z;
    // a light behind the surface lights nothing
    if cos_theta <= 0.0 || light.wi.dot(x.ng) <= 0.0 {
        return Vec3::ZERO;
    }
    if context
        .accel
        .occluded(&light.shadow_ray, light.target_sphere)
    {
        return Vec3::ZERO;
    }
    let f = x.brdf.eval(x.wo_local, wi_local);
    light.radiance * f * cos_theta / light.pdf
}

/// The direct lighting of a mirror or glass: weight · L_e(q, −ω) for the
/// point q seen in the direction ω of its Dirac; glass picks reflection or
/// refraction with `u` (weight R for a mirror, 1 or T/η² for glass).
fn light_seen_through_dirac(context: &RenderContext, x: &Surface, u: Vec2) -> Vec3 {
    let Some(sample) = x.brdf.sample(x.wo_local, u) else {
        return Vec3::ZERO;
    };
    let wi = x.frame.to_world(sample.wi).normalize();
    if !leaves_on_its_side(wi, x.ng, sample.wi) {
        return Vec3::ZERO; // across the geometric surface
    }
    let ray = x.point.spawn_ray(wi);
    match context.accel.closest_hit(&ray) {
        Some(hit) => sample.weight * emission(context, &hit, &ray),
        None => Vec3::ZERO,
    }
}

/// One step of the path: a direction ω drawn at `x` by its BRDF, the point
/// it sees, and the step's weight f_r cos θ / pdf (for a mirror, R; for
/// glass, 1 reflected or T/η² refracted).
/// `None` if ω is below the surface, leaves the scene or meets a surface
/// that reflects nothing.
fn bounce(
    context: &RenderContext,
    x: &Surface,
    stream: &SampleStream,
    vertex: u32,
) -> Option<(Surface, Vec3)> {
    let u = stream.uniform2(dim::vertex_base(vertex) + dim::BRDF_DIRECTION);
    let sample = x.brdf.sample(x.wo_local, u)?;
    let wi = x.frame.to_world(sample.wi).normalize();
    if !leaves_on_its_side(wi, x.ng, sample.wi) {
        return None; // across the geometric surface: a shading-normal artefact
    }
    let ray = x.point.spawn_ray(wi);
    let hit = context.accel.closest_hit(&ray)?;
    let next = Surface::seen(context, &hit, &ray)?;
    Some((next, sample.weight))
}
