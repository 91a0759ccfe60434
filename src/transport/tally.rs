//! The fast integrator's bookkeeping, kept out of its path loop: what a
//! sample counts (rays by kind and by term, work skipped, rays that left
//! the scene) and, when asked, the log of every ray it traced and the
//! splitting pilot's measurement. The path loop makes one call per event;
//! these observe the path, none changes it.

use glam::Vec3;

use crate::course::Term;
use crate::course::TermRadiance;
use crate::geometry::Ray;
use crate::geometry::accel::{Accel, Query};
use crate::transport::counts::{ContinuationSplit, RayCounts};
use crate::transport::path_log::{PathLog, PathSegment, SegmentKind};

/// The counters and the log one sample writes.
pub(crate) struct Tally<'a> {
    counts: &'a mut RayCounts,
    log: Option<&'a mut PathLog>,
    /// The splitting pilot's measurement, if this sample is the pilot's.
    pilot: Option<&'a mut ContinuationSplit>,
    /// The rays traced once the first vertex was lit (the pilot's).
    first_rays: Option<u64>,
    /// How far the log draws a ray that left the scene.
    escape_length: f32,
}

impl<'a> Tally<'a> {
    /// The bookkeeping of a sample that adds to `counts`, logs its rays
    /// to `log` and tells `pilot` what its continuations brought, if given.
    pub fn new(
        counts: &'a mut RayCounts,
        log: Option<&'a mut PathLog>,
        pilot: Option<&'a mut ContinuationSplit>,
        escape_length: f32,
    ) -> Self {
        Self {
            counts,
            log,
            pilot,
            first_rays: None,
            escape_length,
        }
    }

    // ── the splitting pilot's measurement

    /// The first vertex's direct lighting is done: the pilot's first part ends.
    #[inline(always)]
    pub fn first_vertex_lit(&mut self) {
        if self.pilot.is_some() {
            self.first_rays = Some(self.counts.total());
        }
    }

    /// Continuation `m` of `splits` is done, the sample's radiance going
    /// from `before` to `after`: the pilot keeps what it brought, summed
    /// over the terms and unweighted (M times what was filed).
    #[inline(always)]
    pub fn continuation_brought(
        &mut self,
        m: u32,
        splits: u32,
        before: &TermRadiance,
        after: &TermRadiance,
    ) {
        if let Some(pilot) = self.pilot.as_deref_mut()
            && let Some(slot) = pilot.continuations.get_mut(m as usize)
        {
            let added = after.iter().zip(before).map(|(a, b)| *a - *b);
            *slot = added.sum::<Vec3>() * splits as f32;
        }
    }

    /// The sample is done: the pilot's continuations end here (and its
    /// first part too if the camera ray found no vertex).
    #[inline(always)]
    pub fn sample_done(&mut self) {
        let rays = self.counts.total();
        if let Some(pilot) = self.pilot.as_deref_mut() {
            pilot.first_rays = self.first_rays.unwrap_or(rays);
            pilot.continuation_rays = rays;
        }
    }

    // ── rays traced, each under the index of the lowest term it serves

    #[inline(always)]
    pub fn camera_ray(&mut self, serves: usize) {
        self.counts.camera += 1;
        self.counts.per_term[serves] += 1;
    }

    #[inline(always)]
    pub fn bounce(&mut self, serves: usize) {
        self.counts.bounce += 1;
        self.counts.per_term[serves] += 1;
    }

    #[inline(always)]
    pub fn gathered_direction(&mut self, term: Term) {
        self.counts.gather += 1;
        self.counts.per_term[term.index()] += 1;
    }

    /// A shadow ray traced towards a light, and its segment in the log.
    #[inline(always)]
    pub fn shadow_ray(
        &mut self,
        ray: &Ray,
        occluded: bool,
        target_sphere: Option<u32>,
        term: Term,
        added: Vec3,
        weight: f32,
    ) {
        self.counts.shadow += 1;
        self.counts.per_term[term.index()] += 1;
        let kind = SegmentKind::Shadow {
            occluded,
            target_sphere,
        };
        let to = ray.at(ray.t_max);
        self.segment(ray, to, kind, Query::Occlusion, term, added, Some(weight));
    }

    // ── work skipped

    /// A light sample behind the surface, or that carried nothing: no shadow ray.
    #[inline(always)]
    pub fn no_shadow_ray(&mut self) {
        self.counts.skipped.shadow_rays += 1;
    }

    /// A vertex's direct lighting not estimated, counted when the settings
    /// leave its term out (not when adaptive sampling does).
    #[inline(always)]
    pub fn no_direct_lighting(&mut self, settings_off: bool) {
        self.counts.skipped.direct_lighting += u64::from(settings_off);
    }

    /// `count` directions not gathered: no light can be hit.
    #[inline(always)]
    pub fn no_gathered_directions(&mut self, count: u32) {
        self.counts.skipped.gathered += u64::from(count);
    }

    /// A continuation not traced: no selected term needs it.
    #[inline(always)]
    pub fn no_continuation(&mut self) {
        self.counts.skipped.continuations += 1;
    }

    #[inline(always)]
    pub fn ended_by_roulette(&mut self) {
        self.counts.skipped.roulette += 1;
    }

    /// A search for a light, which searched the whole scene or not.
    #[inline(always)]
    pub fn light_search(&mut self, scene_searched: bool) {
        self.counts.skipped.scene_searches += u64::from(!scene_searched);
    }

    // ── the log

    /// Whether the sample's rays are logged.
    #[inline(always)]
    pub fn is_logging(&self) -> bool {
        self.log.is_some()
    }

    /// One traced ray, from its origin to `to`, that added `radiance` to
    /// `term`, any emission it met counted with `weight` (None: not counted).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub fn segment(
        &mut self,
        ray: &Ray,
        to: Vec3,
        kind: SegmentKind,
        query: Query,
        term: Term,
        radiance: Vec3,
        weight: Option<f32>,
    ) {
        if let Some(log) = self.log.as_deref_mut() {
            log.segments.push(PathSegment {
                from: ray.origin,
                ray: *ray,
                to,
                kind,
                query,
                term,
                radiance,
                weight,
            });
        }
    }

    /// A closest-hit ray that left the scene (it added nothing).
    #[cold]
    pub fn escaped(&mut self, ray: &Ray, kind: SegmentKind, term: Term, weight: Option<f32>) {
        self.counts.escaped += 1;
        if self.log.is_some() {
            let to = self.escape_point(ray);
            self.segment(ray, to, kind, Query::ClosestHit, term, Vec3::ZERO, weight);
        }
    }

    /// Logs a ray that looked for a light, which met emission `le` and
    /// added `added`. Where it stops comes from a closest-hit search in
    /// `accel`, made for the log only.
    #[cold]
    pub fn light_search_segment(
        &mut self,
        accel: &Accel,
        ray: &Ray,
        kind: SegmentKind,
        term: Term,
        (le, weight): (Vec3, Option<f32>),
        added: Vec3,
    ) {
        let to = match accel.closest_hit(ray) {
            Some(hit) => ray.at(hit.t()),
            None => self.escape_point(ray),
        };
        let kind = match kind {
            SegmentKind::Gather { .. } => SegmentKind::Gather {
                hit_light: le.max_element() > 0.0,
            },
            other => other,
        };
        self.segment(ray, to, kind, Query::VisibleEmitter, term, added, weight);
    }

    /// Where the drawing of a ray that left the scene stops: one scene diagonal away.
    fn escape_point(&self, ray: &Ray) -> Vec3 {
        ray.origin + ray.direction.normalize_or_zero() * self.escape_length
    }
}
