//! The path tracer: one loop that files every contribution under its term.
//!
//! A path leaves the camera; after k reflections it carries the throughput
//! β = Π f cos / pdf. Light reaches the camera along it in two ways, each
//! filed under the term of its number of reflections (`Term::of_reflections`):
//!
//! * **emission hit** — the path's (k)th segment lands on an emitter:
//!   β · L_e · w_brdf, filed under L_k (k = 0 is L0, the emitter seen directly);
//! * **next-event estimation** — at the vertex of the (k+1)th reflection a
//!   light is sampled: β · f · L_i · cos θ / pdf_light · w_light, under L_{k+1}.
//!
//! Both estimate the same integral; w_brdf and w_light are the power-heuristic
//! MIS weights (they sum to one), so emission is counted once. A Dirac BRDF
//! (mirror) cannot sample a light: its emission hits keep weight 1. A Dirac
//! light (point, spot, directional) cannot be hit: its light samples keep
//! weight 1.
//!
//! Work the selected terms do not need is skipped: no light sample at a
//! vertex whose term is off (`--terms L2` traces no shadow ray at the first
//! hit), no vertex beyond the last term needed (`--terms L0` traces camera
//! rays only), no continuation ray whose only use would be to hit an emitter
//! when the scene has no area light, and no shadow ray for a light behind the
//! surface. Russian roulette starts after the third reflection (it only
//! touches L3+), and `max_bounces` caps the reflections.

use std::sync::Arc;

use glam::Vec3;

use crate::accel::{Accel, Hit};
use crate::camera::CameraRays;
use crate::geometry::Ray;
use crate::lights::LightTable;
use crate::sampling::{SampleStream, dim, power_heuristic};
use crate::scene::Scene;
use crate::settings::{RenderSettings, Term, TermSet};
use crate::shading::SurfacePoint;

/// Radiance of one sample, per term.
pub type TermRadiance = [Vec3; Term::COUNT];

/// Rays traced, by kind and by the lowest selected term each serves: the
/// shadow ray at the k-th reflection serves L_k; a ray leaving the camera
/// (k = 0) or the k-th reflection serves L_k and every later term.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    pub camera: u64,
    pub shadow: u64,
    pub bounce: u64,
    pub per_term: [u64; Term::COUNT],
}

impl RayCounts {
    pub fn total(&self) -> u64 {
        self.camera + self.shadow + self.bounce
    }

    pub fn add(&mut self, other: &RayCounts) {
        self.camera += other.camera;
        self.shadow += other.shadow;
        self.bounce += other.bounce;
        for (mine, theirs) in self.per_term.iter_mut().zip(other.per_term) {
            *mine += theirs;
        }
    }
}

/// Everything a sample needs: the scene, its acceleration structure, its
/// lights and the settings they were built for.
pub struct RenderContext {
    pub scene: Arc<Scene>,
    pub accel: Accel,
    pub lights: LightTable,
    pub settings: RenderSettings,
    pub camera: CameraRays,
}

impl RenderContext {
    /// Builds the lights and the BVH of `scene` for `settings`, with the scene's default camera.
    pub fn new(scene: impl Into<Arc<Scene>>, settings: RenderSettings) -> Self {
        let scene = scene.into();
        let lights = LightTable::build(&scene, &settings);
        let hidden = &lights.hidden_triangles;
        let accel = Accel::build(&scene, |t| !hidden[t as usize], lights.spheres.clone());
        let camera = CameraRays::new(&scene.default_camera(), settings.width, settings.height);
        Self {
            scene,
            accel,
            lights,
            settings,
            camera,
        }
    }

    /// One sample of pixel (`x`, `y`): its radiance per term.
    pub fn sample_pixel(
        &self,
        x: u32,
        y: u32,
        stream: &SampleStream,
        counts: &mut RayCounts,
    ) -> TermRadiance {
        let ray = self.camera.generate(x, y, stream.uniform2(dim::PIXEL));
        self.trace(ray, stream, counts)
    }

    /// Radiance arriving along `ray` (unit direction), per term.
    pub fn trace(
        &self,
        mut ray: Ray,
        stream: &SampleStream,
        counts: &mut RayCounts,
    ) -> TermRadiance {
        let settings = &self.settings;
        let terms = settings.terms;
        let last_reflection = terms
            .max_reflections()
            .unwrap_or(0)
            .min(settings.max_bounces);
        let can_hit_lights = self.lights.has_hittable_lights();
        let mut radiance = [Vec3::ZERO; Term::COUNT];
        let mut throughput = Vec3::ONE;
        let mut reflections = 0u32;
        // the previous vertex, for the MIS weight of emission hits
        let mut previous: Option<(Vec3, f32, bool)> = None; // (position, brdf pdf, delta)
        counts.camera += 1;
        counts.per_term[lowest_selected(terms, 0)] += 1;

        while let Some(hit) = self.accel.closest_hit(&ray) {
            let term = Term::of_reflections(reflections).index();
            let wo = -ray.direction;

            // ── emission hit ────────────────────────────────────────────
            let point = match hit {
                Hit::Sphere { sphere, .. } => {
                    // sphere lights are pure emitters: the path ends here
                    if terms.contains_reflections(reflections) {
                        let from = previous.map_or(ray.origin, |p| p.0);
                        let (le, light_pdf) =
                            self.lights.sphere_emission(sphere, from, ray.direction);
                        let weight = previous.map_or(1.0, |(_, pdf, delta)| {
                            mis_brdf_weight(pdf, delta, light_pdf)
                        });
                        radiance[term] += throughput * le * weight;
                    }
                    break;
                }
                Hit::Triangle { triangle, b, .. } => {
                    let point = SurfacePoint::new(&self.scene, triangle, b);
                    if terms.contains_reflections(reflections) {
                        let le = point.emitted(&self.scene, wo);
                        if le.max_element() > 0.0 {
                            let weight = previous.map_or(1.0, |(from, pdf, delta)| {
                                let light_pdf =
                                    self.lights
                                        .pdf_triangle(&self.scene, from, triangle, &point);
                                mis_brdf_weight(pdf, delta, light_pdf)
                            });
                            radiance[term] += throughput * le * weight;
                        }
                    }
                    point
                }
            };
            if reflections >= last_reflection {
                break;
            }

            // ── reflection number `next` at this vertex ──────────────────
            let next = reflections + 1;
            let next_term = Term::of_reflections(next).index();
            let base = dim::vertex_base(reflections);
            let brdf = point.brdf(&self.scene, settings);
            if brdf.is_black() {
                break;
            }
            let (frame, ng) = point.frame_towards(wo);
            let wo_local = frame.to_local(wo);

            // ── light sampling (next-event estimation) ──────────────────
            let sample_lights = terms.contains_reflections(next) && !brdf.is_delta();
            if sample_lights {
                let light = self.lights.sample(
                    &self.scene,
                    &point,
                    stream.uniform(base + dim::LIGHT_SELECT),
                    stream.uniform2(base + dim::LIGHT_POSITION),
                );
                if let Some(light) = light {
                    let wi_local = frame.to_local(light.wi);
                    let f_cos = brdf.eval(wo_local, wi_local) * wi_local.z;
                    let contribution = throughput * f_cos * light.radiance / light.pdf;
                    // a light behind the surface (or a zero BRDF) gets no shadow ray
                    if contribution.max_element() > 0.0 && light.wi.dot(ng) > 0.0 {
                        counts.shadow += 1;
                        counts.per_term[next_term] += 1;
                        if !self.accel.occluded(&light.shadow_ray, light.target_sphere) {
                            let weight = if light.delta {
                                1.0
                            } else {
                                power_heuristic(light.pdf, brdf.pdf(wo_local, wi_local))
                            };
                            radiance[next_term] += contribution * weight;
                        }
                    }
                }
            }

            // ── BRDF sampling: the next segment ─────────────────────────
            // past the last term, a continuation only serves to hit an emitter
            if next >= last_reflection && !(terms.contains_reflections(next) && can_hit_lights) {
                break;
            }
            let Some(sample) = brdf.sample(
                wo_local,
                stream.uniform(base + dim::BRDF_LOBE),
                stream.uniform2(base + dim::BRDF_DIRECTION),
            ) else {
                break;
            };
            let wi = frame.to_world(sample.wi).normalize();
            if wi.dot(ng) <= 0.0 {
                break; // below the geometric surface: shading-normal artefact
            }
            throughput *= sample.weight;
            previous = Some((point.p, sample.pdf, sample.delta));
            reflections = next;

            // russian roulette after the third reflection
            if reflections >= 3 {
                let survival = throughput.max_element().min(0.95);
                if stream.uniform(base + dim::RUSSIAN_ROULETTE) >= survival {
                    break;
                }
                throughput /= survival;
            }
            ray = point.spawn_ray(wi);
            counts.bounce += 1;
            counts.per_term[lowest_selected(terms, reflections)] += 1;
        }
        radiance
    }
}

/// Index of the first selected term with `reflections` reflections or more.
fn lowest_selected(terms: TermSet, reflections: u32) -> usize {
    let from = Term::of_reflections(reflections);
    terms.iter().find(|&t| t >= from).unwrap_or(from).index()
}

/// MIS weight of an emission hit reached by BRDF sampling with density `brdf_pdf`.
fn mis_brdf_weight(brdf_pdf: f32, delta: bool, light_pdf: f32) -> f32 {
    if delta {
        1.0
    } else {
        power_heuristic(brdf_pdf, light_pdf)
    }
}
