//! The fast path tracer: one walk per sample that files every contribution
//! under its term; the lecture integrator (`lecture.rs`) is its oracle.
//!
//! A path leaves the camera; after k reflections it carries the throughput
//! β = Π f cos θ / pdf. Light reaches the camera along it in three ways,
//! each filed under the term of its number of reflections:
//!
//! * **emission hit**: the k-th segment lands on an emitter,
//!   β · L_e · w under L_k (L0: the emitter seen directly, w = 1);
//! * **light sample** at the vertex of the (k+1)-th reflection:
//!   β · f · L_i · cos θ / pdf_light · w_light under L_{k+1};
//! * **gathered direction** drawn there (by the BRDF or uniformly) that
//!   lands on an emitter: β · f · L_e · cos θ / pdf_gather · w_gather.
//!
//! For an extended light the two weights sum to one, so it is counted once:
//!
//! | `light_sampling` | w_light | w_gather |
//! |---|---|---|
//! | `area`, `solid-angle` | 1 | 0 |
//! | `brdf`, `hemisphere` | 0 | 1 |
//! | `mis` | h(pdf_light, n·pdf_brdf) | h(n·pdf_brdf, pdf_light) |
//!
//! h is the balance or power heuristic, n the BRDF samples per light sample
//! (the M continuations of a split first hit double as gathered directions:
//! Veach's multi-sample MIS). Dirac lights keep w_light = 1; a mirror or
//! glass has no light sample and its continuation's emission hit keeps
//! w = 1. A refraction counts as a reflection: it raises the term by one.
//!
//! The continuation is drawn uniformly, by cosine or by the BRDF
//! (`indirect_sampling`); at the first hit the path splits into M
//! continuations, each with β / M (`indirect_samples`, or the pilot's count
//! per region: `splitting.rs`). Russian roulette (`roulette.rs`) decides
//! from the segment reaching the fifth vertex on (it touches L4 and beyond
//! only), on the sample's throughput M β so that splitting does not shorten
//! the continuations. Work no selected term needs is skipped and counted
//! (`tally.rs`). `docs/light-transport.md` gives the details.
//!
//! ## Where each term is computed
//!
//! Every contribution goes through [`Walk::file_under`], under the term of
//! the vertex that reflected it last: each [`Vertex`] knows its term once
//! (`Vertex::term`: L1 at the first hit p, **L2 at q**, the second vertex,
//! L3+ beyond). The path loop, [`Walk::camera_path`] then
//! [`Walk::path_from`], reads as the lecture's `radiance_by_term`:
//!
//! | term | in the lecture integrator | here |
//! |---|---|---|
//! | L0 | `l[0] = emission(…)` | the camera ray's `follow(ray, Term::L0, …)` in `camera_path` |
//! | L1 | `l[1] = direct_lighting(p)` | `direct_lighting(p, …)` in `camera_path`, and what p's continuations hit |
//! | L2 | `l[2] = weight · direct_lighting(q)` | `direct_lighting(&x, …)` in `path_from` at its first vertex x = q, and what q's continuation hits |
//! | L3+ | `beyond_two_reflections` | the same lines of `path_from` at the later vertices |

use glam::Vec3;

use crate::course::TermRadiance;
use crate::course::{IndirectSampling, LightSampling, MisHeuristic, Term, TermSet};
use crate::geometry::Frame;
use crate::geometry::Ray;
use crate::geometry::accel::{Accel, Hit, Query};
use crate::transport::brdf::{Brdf, BrdfSample};
use crate::transport::context::RenderContext;
use crate::transport::counts::{ContinuationSplit, RayCounts};
use crate::transport::path_log::{PathLog, SegmentKind};
use crate::transport::roulette;
use crate::transport::sampler::{SampleStream, dim};
use crate::transport::surface::{SurfacePoint, leaves_on_its_side};
use crate::transport::tally::Tally;
use crate::transport::warps::{
    UNIFORM_HEMISPHERE_PDF, balance_heuristic, cosine_hemisphere, cosine_hemisphere_pdf,
    power_heuristic, uniform_hemisphere,
};

/// The splitting pilot's sample along camera ray `ray`: two continuations
/// at the first hit, whatever the settings say, and what each brought; unguarded.
pub(crate) fn pilot_radiance(
    context: &RenderContext,
    ray: Ray,
    stream: &SampleStream,
    counts: &mut RayCounts,
) -> (TermRadiance, ContinuationSplit) {
    let mut split = ContinuationSplit::default();
    let tally = Tally::new(counts, None, Some(&mut split), context.escape_length);
    let radiance = Walk::new(context, tally, context.settings.terms).camera_path(ray, stream, 2);
    (radiance, split)
}

/// [`radiance`] for the settings' terms, appending every ray to `log`.
pub(crate) fn logged_radiance(
    context: &RenderContext,
    ray: Ray,
    stream: &SampleStream,
    splits: u32,
    counts: &mut RayCounts,
    log: &mut PathLog,
) -> TermRadiance {
    let tally = Tally::new(counts, Some(log), None, context.escape_length);
    Walk::new(context, tally, context.settings.terms).camera_path(ray, stream, splits)
}

/// The fast integrator's radiance along camera ray `ray` (unit direction),
/// for the terms of `terms` (within the settings'), with `splits`
/// continuations at the first hit; unguarded.
pub(crate) fn radiance(
    context: &RenderContext,
    ray: Ray,
    stream: &SampleStream,
    terms: TermSet,
    splits: u32,
    counts: &mut RayCounts,
) -> TermRadiance {
    let tally = Tally::new(counts, None, None, context.escape_length);
    Walk::new(context, tally, terms).camera_path(ray, stream, splits)
}

/// A distribution of directions on the hemisphere of a vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Directions {
    /// The BRDF's own sampling routine.
    Brdf,
    Uniform,
    Cosine,
}

/// How an emission hit is weighted (the `w` of the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
enum EmissionWeight {
    /// Seen from the camera, after a mirror, or found by `brdf`/`hemisphere` gathering.
    One,
    /// Light sampling estimates it: the hit adds nothing.
    Zero,
    /// Found by a direction of density `pdf` drawn at `from`, against light sampling.
    Mis { from: Vec3, pdf: f32 },
}

/// How direct lighting is estimated at one vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Gather {
    /// No gathered direction.
    None,
    /// Directions traced for this purpose only, as many as the light samples.
    Separate,
    /// The vertex's `directions` continuations are its gathered directions
    /// (one light sample against `directions` BRDF samples, each of weight
    /// 1/`directions`).
    Continuation { directions: u32 },
}

impl Gather {
    /// BRDF samples per light sample at the vertex: the n_brdf / n_light
    /// of multi-sample MIS (Veach), whose weights compare n_light·pdf_light
    /// with n_brdf·pdf_brdf.
    #[inline(always)]
    fn directions_per_light_sample(self) -> f32 {
        match self {
            Gather::Continuation { directions } => directions as f32,
            Gather::None | Gather::Separate => 1.0,
        }
    }
}

/// A surface point where the path reflects.
struct Vertex {
    point: SurfacePoint,
    brdf: Brdf,
    frame: Frame,
    /// Geometric normal on the side the path arrives from.
    ng: Vec3,
    wo_local: Vec3,
    /// Reflections before this one: 0 at the first hit p, 1 at q, …
    index: u32,
    /// The term of the light this vertex reflects towards the camera, its
    /// (index + 1)-th reflection: L1 at p, L2 at q, L3+ beyond. Its direct
    /// lighting and what its continuation hits are filed under it.
    term: Term,
}

/// The state of one sample: the context it reads, its bookkeeping (counters,
/// log, the pilot's measurement: [`Tally`]), and the radiance filed so far
/// under each term. Its small steps are inlined into the path loop
/// (`#[inline(always)]`): split apart, the per-vertex calls and moves cost
/// the defaults several percent.
struct Walk<'a> {
    context: &'a RenderContext,
    tally: Tally<'a>,
    radiance: TermRadiance,
    /// The terms computed (the settings', or fewer for adaptive sampling).
    terms: TermSet,
    /// The last reflection those terms need ([`TermSet::last_reflection`]).
    last_reflection: u32,
    /// Light samples per vertex ([`crate::transport::lights::LightTable::samples_per_vertex`]).
    light_samples: u32,
    can_hit_lights: bool,
    /// The continuations of the first hit this path is one of: its
    /// throughput carries 1/M, which Russian roulette must not read as a
    /// path that brings little.
    splits: f32,
}

impl<'a> Walk<'a> {
    /// A sample computing the terms of `terms` within the settings' terms.
    fn new(context: &'a RenderContext, tally: Tally<'a>, terms: TermSet) -> Self {
        let settings = &context.settings;
        let terms = terms.intersection(settings.terms);
        Self {
            context,
            tally,
            radiance: [Vec3::ZERO; Term::COUNT],
            terms,
            last_reflection: terms.last_reflection(settings.max_bounces),
            light_samples: context.lights.samples_per_vertex(settings),
            can_hit_lights: context.lights.has_hittable_lights(),
            splits: 1.0,
        }
    }

    /// Adds `radiance` to the sample's term `term`: every contribution of
    /// the walk is filed here.
    #[inline(always)]
    fn file_under(&mut self, term: Term, radiance: Vec3) {
        self.radiance[term.index()] += radiance;
    }

    /// The whole sample, in the order of the lecture's `radiance_by_term`:
    /// the camera ray and L0; direct lighting at p, L1; then along each of
    /// p's `splits` continuations, the rest of the path ([`Walk::path_from`]:
    /// L2 at q, L3+ beyond).
    #[inline(always)]
    fn camera_path(mut self, ray: Ray, stream: &SampleStream, splits: u32) -> TermRadiance {
        // ── L0: the emission of the point p the camera sees
        self.tally.camera_ray(lowest_selected(self.terms, 0));
        let first = self.follow(
            ray,
            Term::L0,
            0,
            Vec3::ONE,
            EmissionWeight::One,
            SegmentKind::Camera,
        );
        let Some(p) = &first else {
            return self.finish();
        };

        // ── L1: direct lighting at p (p.term is L1)
        let gather = self.gather_plan(p, splits);
        self.direct_lighting(p, Vec3::ONE, stream, gather);
        self.tally.first_vertex_lit();

        // ── L2, L3+: M continuations from p, each with throughput 1/M
        self.splits = splits as f32;
        for m in 0..splits {
            let before = self.radiance;
            let stream = stream.split(m, splits);
            self.path_from(p, Vec3::splat(1.0 / splits as f32), &stream, gather);
            self.tally
                .continuation_brought(m, splits, &before, &self.radiance);
        }
        self.finish()
    }

    /// The path after vertex `x` (direct lighting at `x` done, `gather` its
    /// plan), going on with throughput β = `throughput`: at each step the
    /// continuation from x (what it hits is filed under x's term; Russian
    /// roulette), then the direct lighting of the vertex it reaches: **L2 at
    /// q**, the second vertex, L3+ beyond.
    #[inline(always)]
    fn path_from(
        &mut self,
        x: &Vertex,
        mut throughput: Vec3,
        stream: &SampleStream,
        gather: Gather,
    ) {
        let Some(mut x) = self.continuation(x, &mut throughput, stream, gather) else {
            return;
        };
        loop {
            // ── direct lighting at x, filed under x.term: L2 at q, L3+ beyond
            let gather = self.gather_plan(&x, 1);
            self.direct_lighting(&x, throughput, stream, gather);
            // ── the continuation from x, and roulette
            match self.continuation(&x, &mut throughput, stream, gather) {
                Some(next) => x = next,
                None => return,
            }
        }
    }

    /// The radiance of the sample, per term, once its bookkeeping is closed.
    #[inline(always)]
    fn finish(mut self) -> TermRadiance {
        self.tally.sample_done();
        self.radiance
    }

    /// Traces `ray`, the segment that reaches the path's vertex number
    /// `reflections` (0: from the camera), files under `term` (L0 from the
    /// camera, else the term of the vertex it leaves) the emission it meets
    /// with `weight`, and returns the vertex it reaches if the path may
    /// reflect there.
    #[inline(always)]
    fn follow(
        &mut self,
        ray: Ray,
        term: Term,
        reflections: u32,
        throughput: Vec3,
        weight: EmissionWeight,
        kind: SegmentKind,
    ) -> Option<Vertex> {
        let counted = weight != EmissionWeight::Zero && self.terms.contains(term);
        let Some(hit) = self.accel().closest_hit(&ray) else {
            self.tally.escaped(&ray, kind, term, counted.then_some(0.0));
            return None;
        };
        let (mut emitted, mut counted_weight) = (Vec3::ZERO, 0.0);
        let vertex = match hit {
            // sphere lights are pure emitters: the path ends here
            Hit::Sphere { sphere, .. } => {
                if counted {
                    let (le, w) = self.sphere_emission(sphere, ray.direction, weight);
                    (emitted, counted_weight) = (throughput * le * w, w);
                }
                None
            }
            Hit::Triangle { triangle, b, .. } => {
                let point = SurfacePoint::new(&self.context.scene, triangle, b);
                let wo = -ray.direction;
                if counted {
                    let (le, w) = self.triangle_emission(&point, wo, weight);
                    (emitted, counted_weight) = (throughput * le * w, w);
                }
                self.vertex(point, wo, reflections)
            }
        };
        self.file_under(term, emitted);
        self.tally.segment(
            &ray,
            ray.at(hit.t()),
            kind,
            Query::ClosestHit,
            term,
            emitted,
            counted.then_some(counted_weight),
        );
        vertex
    }

    /// Traces `ray`, a segment that only looks for a light (the path ends
    /// where it lands), and files under `term` the emission it finds,
    /// weighted by `weight` and scaled by `scale` (the throughput times, for
    /// a gathered direction, its f cos θ / pdf).
    #[inline(always)]
    fn find_emitter(
        &mut self,
        ray: &Ray,
        scale: Vec3,
        weight: EmissionWeight,
        kind: SegmentKind,
        term: Term,
    ) {
        let search = self.accel().search_emitters(ray);
        self.tally.light_search(search.scene_searched);
        let (le, w) = match search.hit {
            None => (Vec3::ZERO, 0.0),
            Some(Hit::Sphere { sphere, .. }) => self.sphere_emission(sphere, ray.direction, weight),
            Some(Hit::Triangle { triangle, b, .. }) => {
                if self.context.lights.light_of_triangle(triangle).is_some() {
                    let point = SurfacePoint::new(&self.context.scene, triangle, b);
                    self.triangle_emission(&point, -ray.direction, weight)
                } else {
                    (Vec3::ZERO, 0.0)
                }
            }
        };
        let added = scale * le * w;
        self.file_under(term, added);
        if self.tally.is_logging() {
            let accel = self.accel();
            let counted = (weight != EmissionWeight::Zero).then_some(w);
            self.tally
                .light_search_segment(accel, ray, kind, term, (le, counted), added);
        }
    }

    /// The vertex at `point` reached along -`wo` after `reflections`
    /// reflections, if a reflection there can serve a selected term.
    #[inline(always)]
    fn vertex(&self, point: SurfacePoint, wo: Vec3, reflections: u32) -> Option<Vertex> {
        if reflections >= self.last_reflection {
            return None;
        }
        let brdf = point.brdf(&self.context.scene, &self.context.settings, wo);
        if brdf.is_black() {
            return None;
        }
        let (frame, ng) = point.frame_towards(wo);
        Some(Vertex {
            point,
            brdf,
            frame,
            ng,
            wo_local: frame.to_local(wo),
            index: reflections,
            term: Term::of_reflections(reflections + 1),
        })
    }

    /// Whether and how directions are gathered at `vertex`, which has `continuations`.
    #[inline(always)]
    fn gather_plan(&self, vertex: &Vertex, continuations: u32) -> Gather {
        let settings = &self.context.settings;
        let wanted = !vertex.brdf.is_delta()
            && self.terms.contains(vertex.term)
            && gather_directions(settings.light_sampling).is_some();
        // M > 1 continuations double as gathered directions only where
        // they are traced anyway, to serve a later term
        let traced_anyway = vertex.index + 1 < self.last_reflection;
        if !(wanted && self.can_hit_lights) {
            Gather::None
        } else if self.light_samples <= 1
            && (continuations == 1 || traced_anyway)
            && gather_directions(settings.light_sampling)
                == Some(self.continuation_directions(&vertex.brdf))
        {
            Gather::Continuation {
                directions: continuations,
            }
        } else {
            Gather::Separate
        }
    }

    // ── direct lighting ──────────────────────────────────────────────

    /// The direct lighting of `vertex`, filed under its term (L1 at p, L2
    /// at q, L3+ beyond): its light samples and its separately gathered
    /// directions.
    #[inline(always)]
    fn direct_lighting(
        &mut self,
        vertex: &Vertex,
        throughput: Vec3,
        stream: &SampleStream,
        gather: Gather,
    ) {
        if vertex.brdf.is_delta() {
            return;
        }
        if !self.terms.contains(vertex.term) {
            // counted when the settings leave the term out (not when adaptive sampling does)
            let settings_off = !self.context.settings.terms.contains(vertex.term);
            self.tally.no_direct_lighting(settings_off);
            return;
        }
        let settings = &self.context.settings;
        let count = self.light_samples;
        if !self.can_hit_lights && gather_directions(settings.light_sampling).is_some() {
            self.tally.no_gathered_directions(count);
        }
        let share = throughput / count as f32;
        let light_samples = match settings.light_sampling {
            LightSampling::Area | LightSampling::SolidAngle | LightSampling::Mis => true,
            // only the Dirac lights remain for light samples
            LightSampling::Brdf | LightSampling::Hemisphere => {
                self.context.lights.has_delta_lights()
            }
        };
        if light_samples {
            let directions = gather.directions_per_light_sample();
            for j in 0..count {
                self.light_sample(vertex, share, &stream.split(j, count), j, directions);
            }
        }
        if gather == Gather::Separate {
            for j in 0..count {
                self.gathered_direction(vertex, share, &stream.split(j, count));
            }
        }
    }

    /// Light sample `slot` (next-event estimation) at `vertex`, against
    /// `directions` gathered directions per light sample (MIS).
    #[inline(always)]
    fn light_sample(
        &mut self,
        vertex: &Vertex,
        throughput: Vec3,
        stream: &SampleStream,
        slot: u32,
        directions: f32,
    ) {
        let context = self.context;
        let settings = &context.settings;
        let base = dim::vertex_base(vertex.index);
        let Some((index, probability, u_position)) = context.lights.pick_with_position(
            stream.uniform2(base + dim::LIGHT_POSITION),
            slot,
            || stream.uniform(base + dim::LIGHT_SELECT),
        ) else {
            return;
        };
        let extended = !context.lights.lights[index].is_delta();
        if extended
            && matches!(
                settings.light_sampling,
                LightSampling::Brdf | LightSampling::Hemisphere
            )
        {
            return; // weight 0: gathering alone finds extended lights
        }
        let Some(light) = context.lights.sample_light(
            &context.scene,
            &vertex.point,
            index,
            probability,
            u_position,
        ) else {
            return;
        };
        let wi_local = vertex.frame.to_local(light.wi);
        let (f, brdf_pdf) = vertex.brdf.eval_and_pdf(vertex.wo_local, wi_local);
        let f_cos = f * wi_local.z;
        let contribution = throughput * f_cos * light.radiance / light.pdf;
        // a light behind the surface (or a zero BRDF) gets no shadow ray
        if contribution.max_element() <= 0.0 || light.wi.dot(vertex.ng) <= 0.0 {
            self.tally.no_shadow_ray();
            return;
        }
        let occluded = self
            .accel()
            .occluded(&light.shadow_ray, light.target_sphere);
        let weight = if light.delta || settings.light_sampling != LightSampling::Mis {
            1.0
        } else {
            self.mis(light.pdf, directions * brdf_pdf)
        };
        let mut added = Vec3::ZERO;
        if !occluded {
            added = contribution * weight;
            self.file_under(vertex.term, added);
        }
        let (ray, target_sphere) = (light.shadow_ray, light.target_sphere);
        self.tally
            .shadow_ray(&ray, occluded, target_sphere, vertex.term, added, weight);
    }

    /// One direction gathered at `vertex` (traced on its own), counted if it finds a light.
    fn gathered_direction(&mut self, vertex: &Vertex, throughput: Vec3, stream: &SampleStream) {
        let Some(directions) = gather_directions(self.context.settings.light_sampling) else {
            return;
        };
        let base = dim::vertex_base(vertex.index);
        let Some(sample) = draw_direction(
            &vertex.brdf,
            vertex.wo_local,
            directions,
            stream,
            base + dim::GATHER_DIRECTION,
        ) else {
            return;
        };
        let wi = vertex.frame.to_world(sample.wi).normalize();
        if wi.dot(vertex.ng) <= 0.0 {
            return; // below the geometric surface: shading-normal artefact
        }
        self.tally.gathered_direction(vertex.term);
        let ray = vertex.point.spawn_ray(wi);
        let weight = self.gather_weight(vertex, sample.pdf);
        let kind = SegmentKind::Gather { hit_light: false };
        self.find_emitter(&ray, throughput * sample.weight, weight, kind, vertex.term);
    }

    /// The weight of an emission hit found by a gathered direction of density `pdf` at `vertex`.
    #[inline]
    fn gather_weight(&self, vertex: &Vertex, pdf: f32) -> EmissionWeight {
        match self.context.settings.light_sampling {
            LightSampling::Mis => EmissionWeight::Mis {
                from: vertex.point.p,
                pdf,
            },
            LightSampling::Brdf | LightSampling::Hemisphere => EmissionWeight::One,
            LightSampling::Area | LightSampling::SolidAngle => EmissionWeight::Zero,
        }
    }

    // ── continuation ─────────────────────────────────────────────────

    /// The distribution the continuation at a vertex of `brdf` is drawn from.
    #[inline(always)]
    fn continuation_directions(&self, brdf: &Brdf) -> Directions {
        if brdf.is_delta() {
            return Directions::Brdf;
        }
        match self.context.settings.indirect_sampling {
            IndirectSampling::Uniform => Directions::Uniform,
            IndirectSampling::Cosine => Directions::Cosine,
            IndirectSampling::Brdf => Directions::Brdf,
        }
    }

    /// Draws and traces the next reflection from `vertex`, updating
    /// `throughput` (β at `vertex`) to β at the next vertex: that vertex, if
    /// the path goes on. What the continuation hits is light `vertex`
    /// reflects: it is filed under `vertex.term`.
    #[inline(always)]
    fn continuation(
        &mut self,
        vertex: &Vertex,
        throughput: &mut Vec3,
        stream: &SampleStream,
        gather: Gather,
    ) -> Option<Vertex> {
        let next = vertex.index + 1;
        let delta = vertex.brdf.is_delta();
        // how the emission the continuation may hit is weighted (its pdf comes below)
        let finds_lights = delta || matches!(gather, Gather::Continuation { .. });
        // past the last term, a continuation only serves to hit an emitter
        if next >= self.last_reflection
            && !(finds_lights && self.can_hit_lights && self.terms.contains(vertex.term))
        {
            self.tally.no_continuation();
            return None;
        }
        let base = dim::vertex_base(vertex.index);
        let sample = draw_direction(
            &vertex.brdf,
            vertex.wo_local,
            self.continuation_directions(&vertex.brdf),
            stream,
            base + dim::BRDF_DIRECTION,
        )?;
        let wi = vertex.frame.to_world(sample.wi).normalize();
        if !leaves_on_its_side(wi, vertex.ng, sample.wi) {
            return None; // across the geometric surface: shading-normal artefact
        }
        let weight = if sample.delta {
            EmissionWeight::One
        } else if matches!(gather, Gather::Continuation { .. }) {
            self.gather_weight(vertex, gather.directions_per_light_sample() * sample.pdf)
        } else {
            EmissionWeight::Zero
        };
        *throughput *= sample.weight;

        // Russian roulette (`roulette.rs`), on the throughput of the
        // sample, not of one of its M continuations
        if next >= roulette::FAST_FIRST_SEGMENT {
            let survival = roulette::survival(*throughput * self.splits);
            if stream.uniform(base + dim::RUSSIAN_ROULETTE) >= survival {
                self.tally.ended_by_roulette();
                return None;
            }
            *throughput /= survival;
        }
        self.tally.bounce(lowest_selected(self.terms, next));
        let ray = vertex.point.spawn_ray(wi);
        let kind = SegmentKind::Bounce {
            refracted: sample.wi.z < 0.0,
        };
        if next >= self.last_reflection {
            // the path ends where this ray lands: it only looks for a light
            self.find_emitter(&ray, *throughput, weight, kind, vertex.term);
            return None;
        }
        self.follow(ray, vertex.term, next, *throughput, weight, kind)
    }

    // ── emission ─────────────────────────────────────────────────────

    /// Radiance leaving emissive `point` towards unit `wo`, and its weight.
    #[inline(always)]
    fn triangle_emission(
        &self,
        point: &SurfacePoint,
        wo: Vec3,
        weight: EmissionWeight,
    ) -> (Vec3, f32) {
        let scene = &self.context.scene;
        let le = point.emitted(scene, wo);
        let weight = match weight {
            _ if le.max_element() <= 0.0 => 0.0,
            EmissionWeight::One => 1.0,
            EmissionWeight::Zero => 0.0,
            EmissionWeight::Mis { from, pdf } => {
                let light_pdf =
                    self.context
                        .lights
                        .pdf_triangle(scene, from, point.triangle, point);
                self.mis(pdf, light_pdf)
            }
        };
        (le, weight)
    }

    /// Radiance leaving accel sphere `sphere` along unit `direction`, and its weight.
    fn sphere_emission(&self, sphere: u32, direction: Vec3, weight: EmissionWeight) -> (Vec3, f32) {
        let lights = &self.context.lights;
        match weight {
            EmissionWeight::Zero => (Vec3::ZERO, 0.0),
            // the density only matters to MIS: any origin will do
            EmissionWeight::One => (lights.sphere_emission(sphere, Vec3::ZERO, direction).0, 1.0),
            EmissionWeight::Mis { from, pdf } => {
                let (le, light_pdf) = lights.sphere_emission(sphere, from, direction);
                (le, self.mis(pdf, light_pdf))
            }
        }
    }

    /// The MIS weight of a strategy of density `pdf` against one of density `other`.
    #[inline]
    fn mis(&self, pdf: f32, other: f32) -> f32 {
        match self.context.settings.mis_heuristic {
            MisHeuristic::Balance => balance_heuristic(pdf, other),
            MisHeuristic::Power => power_heuristic(pdf, other),
        }
    }

    fn accel(&self) -> &'a Accel {
        &self.context.accel
    }
}

/// The distribution of the directions `strategy` gathers, if it gathers any.
fn gather_directions(strategy: LightSampling) -> Option<Directions> {
    match strategy {
        LightSampling::Brdf | LightSampling::Mis => Some(Directions::Brdf),
        LightSampling::Hemisphere => Some(Directions::Uniform),
        LightSampling::Area | LightSampling::SolidAngle => None,
    }
}

/// A direction (local frame) drawn from `directions` at a vertex of `brdf`
/// seen from `wo`, with f cos θ / pdf and its pdf; `None` if it reflects
/// nothing. The numbers come from `stream`'s direction pair (glass picks
/// its lobe with them; a mirror ignores them).
#[inline(always)]
fn draw_direction(
    brdf: &Brdf,
    wo: Vec3,
    directions: Directions,
    stream: &SampleStream,
    direction_dimension: u32,
) -> Option<BrdfSample> {
    let (wi, pdf) = match directions {
        Directions::Brdf => return brdf.sample(wo, stream.uniform2(direction_dimension)),
        Directions::Uniform => (
            uniform_hemisphere(stream.uniform2(direction_dimension)),
            UNIFORM_HEMISPHERE_PDF,
        ),
        Directions::Cosine => {
            let wi = cosine_hemisphere(stream.uniform2(direction_dimension));
            (wi, cosine_hemisphere_pdf(wi.z))
        }
    };
    let f = brdf.eval(wo, wi);
    if pdf <= 0.0 || f.max_element() <= 0.0 {
        return None;
    }
    Some(BrdfSample {
        wi,
        weight: f * wi.z / pdf,
        pdf,
        delta: false,
    })
}

/// Index of the first selected term with `reflections` reflections or more.
fn lowest_selected(terms: TermSet, reflections: u32) -> usize {
    let from = Term::of_reflections(reflections);
    terms.iter().find(|&t| t >= from).unwrap_or(from).index()
}
