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
//! per region: `splitting.rs`). Russian roulette starts after the fourth
//! reflection, on the sample's throughput M β so that splitting does not
//! shorten the continuations. Work no selected term needs is skipped and
//! counted (`tally.rs`). `docs/light-transport.md` gives the details.

use glam::Vec3;

use crate::course::TermRadiance;
use crate::course::{IndirectSampling, LightSampling, MisHeuristic, Term, TermSet};
use crate::geometry::Frame;
use crate::geometry::Ray;
use crate::geometry::accel::{Accel, Hit, Query};
use crate::transport::brdf::{Brdf, BrdfSample};
use crate::transport::context::RenderContext;
use crate::transport::counts::RayCounts;
use crate::transport::path_log::{PathLog, SegmentKind};
use crate::transport::sampler::{SampleStream, dim};
use crate::transport::surface::{SurfacePoint, leaves_on_its_side};
use crate::transport::tally::Tally;
use crate::transport::warps::{
    UNIFORM_HEMISPHERE_PDF, balance_heuristic, cosine_hemisphere, cosine_hemisphere_pdf,
    power_heuristic, uniform_hemisphere,
};

/// The reflections after which Russian roulette may end a path: from the
/// fourth on, so that it only touches L3+ and never its largest part, the
/// third reflection's (its light samples and what the continuation after
/// it hits), where the roulette's weights 1/q would add the most noise.
pub const ROULETTE_FROM_REFLECTION: u32 = 4;

/// What the continuations of one pilot sample brought (`transport::pilot_sample`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContinuationSplit {
    /// The radiance of each of the two continuations, summed over the
    /// terms and unweighted (what it would bring alone, M = 1).
    pub continuations: [Vec3; 2],
    /// `RayCounts::total` once the first vertex's light samples are traced,
    /// then once the continuations are: the rays of each part, by difference
    /// with the count before the sample.
    pub first_rays: u64,
    pub continuation_rays: u64,
}

/// The splitting pilot's sample along camera ray `ray`: two continuations
/// at the first hit, whatever the settings say, and what each brought; unguarded.
pub(crate) fn pilot_radiance(
    context: &RenderContext,
    ray: Ray,
    stream: &SampleStream,
    counts: &mut RayCounts,
) -> (TermRadiance, ContinuationSplit) {
    let mut split = ContinuationSplit::default();
    let radiance = Walk::new(context, counts, None).split_path(ray, stream, 2, Some(&mut split));
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
    Walk::new(context, counts, Some(log)).camera_path(ray, stream, splits)
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
    let mut walk = Walk::new(context, counts, None);
    walk.restrict_terms(terms);
    walk.camera_path(ray, stream, splits)
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
    /// Reflections before this one (0: the first hit).
    index: u32,
}

/// The state of one sample: the context it reads, its bookkeeping (counters
/// and log), and the radiance gathered so far. Its small steps are inlined
/// into the path loop (`#[inline(always)]`): split apart, the per-vertex
/// calls and moves cost the defaults several percent.
struct Walk<'a> {
    context: &'a RenderContext,
    tally: Tally<'a>,
    radiance: TermRadiance,
    terms: TermSet,
    last_reflection: u32,
    can_hit_lights: bool,
    /// The continuations of the first hit this path is one of: its
    /// throughput carries 1/M, which Russian roulette must not read as a
    /// path that brings little.
    splits: f32,
}

impl<'a> Walk<'a> {
    fn new(
        context: &'a RenderContext,
        counts: &'a mut RayCounts,
        log: Option<&'a mut PathLog>,
    ) -> Self {
        let settings = &context.settings;
        let terms = settings.terms;
        Self {
            context,
            tally: Tally::new(counts, log, context.escape_length),
            radiance: [Vec3::ZERO; Term::COUNT],
            terms,
            last_reflection: terms
                .max_reflections()
                .unwrap_or(0)
                .min(settings.max_bounces),
            can_hit_lights: context.lights.has_hittable_lights(),
            splits: 1.0,
        }
    }

    /// Computes only the terms of `terms` (within the settings' terms).
    fn restrict_terms(&mut self, terms: TermSet) {
        let settings = &self.context.settings;
        self.terms = terms.intersection(settings.terms);
        self.last_reflection = self
            .terms
            .max_reflections()
            .unwrap_or(0)
            .min(settings.max_bounces);
    }

    /// The whole sample: the camera segment, then the first vertex and its
    /// `splits` continuations.
    fn camera_path(self, ray: Ray, stream: &SampleStream, splits: u32) -> TermRadiance {
        self.split_path(ray, stream, splits, None)
    }

    /// [`Walk::camera_path`] with `splits` continuations at the first hit,
    /// telling `split` (if given) what each continuation brought.
    #[inline(always)]
    fn split_path(
        mut self,
        ray: Ray,
        stream: &SampleStream,
        splits: u32,
        mut split: Option<&mut ContinuationSplit>,
    ) -> TermRadiance {
        self.tally.camera_ray(lowest_selected(self.terms, 0));
        let first = self.follow(ray, 0, Vec3::ONE, EmissionWeight::One, SegmentKind::Camera);
        let Some(first) = &first else {
            if let Some(split) = split {
                split.first_rays = self.tally.rays_so_far();
                split.continuation_rays = split.first_rays;
            }
            return self.radiance;
        };
        let gather = self.gather_plan(first, splits);
        self.direct_lighting(first, Vec3::ONE, stream, gather);
        if let Some(split) = split.as_deref_mut() {
            split.first_rays = self.tally.rays_so_far();
        }
        self.splits = splits as f32;
        for m in 0..splits {
            let before = self.radiance;
            let stream = stream.split(m, splits);
            let mut throughput = Vec3::splat(1.0 / splits as f32);
            if let Some(vertex) = self.continuation(first, &mut throughput, &stream, gather) {
                self.rest_of_path(vertex, throughput, &stream);
            }
            if let Some(split) = split.as_deref_mut()
                && let Some(slot) = split.continuations.get_mut(m as usize)
            {
                let added = self.radiance.iter().zip(&before).map(|(a, b)| *a - *b);
                *slot = added.sum::<Vec3>() * splits as f32;
            }
        }
        if let Some(split) = split {
            split.continuation_rays = self.tally.rays_so_far();
        }
        self.radiance
    }

    /// The path from `vertex` on: direct lighting and one continuation per vertex.
    #[inline]
    fn rest_of_path(&mut self, mut vertex: Vertex, mut throughput: Vec3, stream: &SampleStream) {
        loop {
            let gather = self.gather_plan(&vertex, 1);
            self.direct_lighting(&vertex, throughput, stream, gather);
            match self.continuation(&vertex, &mut throughput, stream, gather) {
                Some(next) => vertex = next,
                None => return,
            }
        }
    }

    /// Traces `ray` (the path's segment number `reflections`, 0 from the
    /// camera), files the emission it meets with `weight`, and returns the
    /// vertex it reaches if the path may reflect there.
    #[inline(always)]
    fn follow(
        &mut self,
        ray: Ray,
        reflections: u32,
        throughput: Vec3,
        weight: EmissionWeight,
        kind: SegmentKind,
    ) -> Option<Vertex> {
        let term = Term::of_reflections(reflections);
        let counted = weight != EmissionWeight::Zero && self.terms.contains(term);
        let Some(hit) = self.accel().closest_hit(&ray) else {
            self.tally.escaped(&ray, kind, term);
            return None;
        };
        let mut emitted = Vec3::ZERO;
        let vertex = match hit {
            // sphere lights are pure emitters: the path ends here
            Hit::Sphere { sphere, .. } => {
                if counted {
                    let (le, w) = self.sphere_emission(sphere, ray.direction, weight);
                    emitted = throughput * le * w;
                }
                None
            }
            Hit::Triangle { triangle, b, .. } => {
                let point = SurfacePoint::new(&self.context.scene, triangle, b);
                let wo = -ray.direction;
                if counted {
                    let (le, w) = self.triangle_emission(&point, wo, weight);
                    emitted = throughput * le * w;
                }
                self.vertex(point, wo, reflections)
            }
        };
        self.radiance[term.index()] += emitted;
        self.tally.segment(
            &ray,
            ray.at(hit.t()),
            kind,
            Query::ClosestHit,
            term,
            emitted,
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
        self.radiance[term.index()] += added;
        if self.tally.is_logging() {
            let accel = self.accel();
            self.tally
                .light_search_segment(accel, ray, kind, term, le, added);
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
        })
    }

    /// Whether and how directions are gathered at `vertex`, which has `continuations`.
    #[inline(always)]
    fn gather_plan(&mut self, vertex: &Vertex, continuations: u32) -> Gather {
        let settings = &self.context.settings;
        let wanted = !vertex.brdf.is_delta()
            && self.terms.contains_reflections(vertex.index + 1)
            && gather_directions(settings.light_sampling).is_some();
        if wanted && !self.can_hit_lights {
            self.tally.no_gathered_directions(
                self.context
                    .lights
                    .samples_per_vertex(&self.context.settings),
            );
        }
        // M > 1 continuations double as gathered directions only where
        // they are traced anyway, to serve a later term
        let traced_anyway = vertex.index + 1 < self.last_reflection;
        if !(wanted && self.can_hit_lights) {
            Gather::None
        } else if self
            .context
            .lights
            .samples_per_vertex(&self.context.settings)
            <= 1
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

    /// The light samples and separately gathered directions of `vertex`, filed under its next term.
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
        if !self.terms.contains_reflections(vertex.index + 1) {
            // counted when the settings leave the term out (not when adaptive sampling does)
            let settings_off = !self
                .context
                .settings
                .terms
                .contains_reflections(vertex.index + 1);
            self.tally.no_direct_lighting(settings_off);
            return;
        }
        let settings = &self.context.settings;
        let count = self
            .context
            .lights
            .samples_per_vertex(&self.context.settings);
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
        let term = Term::of_reflections(vertex.index + 1);
        let occluded = self
            .accel()
            .occluded(&light.shadow_ray, light.target_sphere);
        let mut added = Vec3::ZERO;
        if !occluded {
            let weight = if light.delta || settings.light_sampling != LightSampling::Mis {
                1.0
            } else {
                self.mis(light.pdf, directions * brdf_pdf)
            };
            added = contribution * weight;
            self.radiance[term.index()] += added;
        }
        let (ray, target_sphere) = (light.shadow_ray, light.target_sphere);
        self.tally
            .shadow_ray(&ray, occluded, target_sphere, term, added);
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
        let term = Term::of_reflections(vertex.index + 1);
        self.tally.gathered_direction(term);
        let ray = vertex.point.spawn_ray(wi);
        let weight = self.gather_weight(vertex, sample.pdf);
        let kind = SegmentKind::Gather { hit_light: false };
        self.find_emitter(&ray, throughput * sample.weight, weight, kind, term);
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
    /// the path goes on.
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
            && !(finds_lights && self.can_hit_lights && self.terms.contains_reflections(next))
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

        // russian roulette, on the throughput of the sample, not of one
        // of its M continuations
        if next >= ROULETTE_FROM_REFLECTION {
            let survival = (*throughput * self.splits).max_element().min(0.95);
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
            let term = Term::of_reflections(next);
            self.find_emitter(&ray, *throughput, weight, kind, term);
            return None;
        }
        self.follow(ray, next, *throughput, weight, kind)
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
