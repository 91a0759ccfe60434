//! Light sources and their sampling (next-event estimation).
//!
//! Direct lighting at p from a source s, in solid angle:
//!
//! ```text
//! L_direct(p, ωo) = ∫ L_e(q, −ω) f_r(p, ω → ωo) |cos θ| dω
//! ```
//!
//! is estimated by drawing one light with probability P_sel (alias table:
//! `light_selection power`, P_sel ∝ emitted power; `uniform`, P_sel = 1/n
//! over the n lights that emit) and one point or direction on it; a
//! [`LightSample`] carries the incident radiance `L_i` and the solid-angle
//! density `pdf` (selection included), so the estimate is
//! `f_r · L_i · cos θ / pdf`. Point, spot and directional lights are Diracs:
//! `L_i` is I/d² (or E) and `pdf` is the selection probability alone.
//!
//! | light | sampled | L_i | pdf (solid angle) |
//! |---|---|---|---|
//! | emissive triangle, `area` | uniform point q on the triangle | L_e(q, −ω) | P_sel · d² / (A · cos θ_q) |
//! | emissive triangle, `solid-angle` | uniform direction in the Ω it subtends (Arvo) | L_e(q, −ω) | P_sel / Ω |
//! | sphere (radius r) | cone of directions it subtends | I(−ω) / (π r²) | P_sel / (2π (1 − cos θ_max)) |
//! | point, spot | — | I(−ω) / d² | P_sel (Dirac) |
//! | cosine point (area light collapsed) | — | L_e A max(0, n·(−ω)) / d² | P_sel (Dirac) |
//! | directional | — | E | P_sel (Dirac) |
//!
//! Solid-angle sampling falls back to area sampling where Ω is outside
//! [`SOLID_ANGLE_RANGE`] (tiny: rounding; near 2π: the point is almost on
//! the triangle's plane). MIS asks for the density of a point found by a
//! ray ([`LightTable::pdf_triangle`], [`LightTable::sphere_emission`]): it is
//! the density of whichever routine the table uses at that point, so the
//! weights of the two strategies sum to one.
//!
//! The course's swap keeps power: an area light of radiance L_e and area A
//! (Φ = π A L_e) becomes a point at its centroid with intensity
//! I(ω) = L_e A max(0, n·ω); a point light of intensity I (Φ = 4π I) becomes a
//! sphere of radius r with radiance I / (π r²). A spot light keeps its cone:
//! the sphere's radiance towards ω is I(ω) / (π r²).

use glam::{Vec2, Vec3};
use std::f32::consts::PI;

use crate::course::color::luminance;
use crate::course::{LightMode, LightSampling, LightSelection, RenderSettings};
use crate::geometry::accel::Sphere;
use crate::geometry::{Ray, offset_ray_origin};
use crate::scene::{NO_ID, PunctualKind, Scene};
use crate::transport::light::{
    Cone, Light, LightSample, SHADOW_EPSILON, SOLID_ANGLE_RANGE, TriangleSampling, cone_of,
    light_point_sample, sample_sphere, sample_triangle_solid_angle, triangle_solid_angle,
};
use crate::transport::sources::{SourceBudget, SourceKey};
use crate::transport::surface::{SurfacePoint, geometric_normal};
use crate::transport::warps::{AliasTable, uniform_cone_pdf, uniform_triangle};

/// Lights up to which one number both picks a light and places the sample
/// on it: the choice takes log₂ n of the number's 24 bits, leaving at least
/// 16 for the position.
pub const SHARED_SELECTION_LIGHTS: usize = 256;

/// The lights of a scene under one light mode, with their selection table.
#[derive(Clone, Debug, Default)]
pub struct LightTable {
    pub lights: Vec<Light>,
    /// Selection probabilities (by power, or uniform over the lights that emit).
    selection: AliasTable,
    pub triangle_sampling: TriangleSampling,
    /// Whether some selectable light is a Dirac (point, spot, directional).
    has_delta_lights: bool,
    /// Whether some selectable light can be hit by a ray (triangle or sphere).
    has_hittable_lights: bool,
    /// (scene triangle, light index) of each triangle light, sorted by
    /// triangle: a lookup costs a binary search over the emitters, not four
    /// bytes for every triangle of the scene.
    triangle_light: Vec<(u32, u32)>,
    /// Light index of each accel sphere.
    sphere_light: Vec<u32>,
    /// Scene triangles that stop being geometry (emitters collapsed to
    /// points), one flag per scene triangle; empty when none is hidden.
    hidden_triangles: Vec<bool>,
    pub spheres: Vec<Sphere>,
    /// The source of each light, as the user names it.
    sources: Vec<SourceKey>,
    /// With a quality for each source: which source each light sample draws from.
    budget: Option<SourceBudget>,
}

impl LightTable {
    /// The lights of `scene` as `settings.light_mode` asks.
    pub fn build(scene: &Scene, settings: &RenderSettings) -> Self {
        let mut table = LightTable::default();
        match settings.light_mode {
            LightMode::Point => table.add_collapsed_emitters(scene),
            _ => table.add_emissive_triangles(scene),
        }
        let radius = sphere_light_radius(scene, settings);
        table.add_punctual_lights(scene, settings.light_mode == LightMode::Area, radius);
        let scene_radius = 0.5 * scene.bounds().diagonal();
        let powers: Vec<f32> = table
            .lights
            .iter()
            .map(|l| power(scene, l, scene_radius))
            .collect();
        let weights: Vec<f32> = if settings.sources.is_empty() {
            match settings.light_selection {
                LightSelection::Power => powers,
                LightSelection::Uniform => powers.iter().map(|&p| f32::from(p > 0.0)).collect(),
            }
        } else {
            let (budget, weights) = SourceBudget::build(scene, settings, &table.sources, &powers);
            table.budget = Some(budget);
            weights
        };
        table.selection = AliasTable::new(&weights);
        table.triangle_sampling = match settings.light_sampling {
            LightSampling::SolidAngle => TriangleSampling::SolidAngle,
            _ => TriangleSampling::Area,
        };
        let selectable = |i: &usize| table.selection.pmf(*i) > 0.0;
        table.has_delta_lights = (0..table.lights.len())
            .filter(selectable)
            .any(|i| table.lights[i].is_delta());
        table.has_hittable_lights = (0..table.lights.len())
            .filter(selectable)
            .any(|i| !table.lights[i].is_delta());
        table
    }

    /// Whether [`LightTable::build`] gives the same table (and the same
    /// scene, sources switched off) for settings `a` and `b`.
    pub fn same_lights(a: &RenderSettings, b: &RenderSettings) -> bool {
        a.light_mode == b.light_mode
            && a.light_radius == b.light_radius
            && a.light_selection == b.light_selection
            && a.light_sampling == b.light_sampling
            && a.sources == b.sources
            && (a.sources.is_empty() || a.light_samples == b.light_samples)
    }

    fn push(&mut self, light: Light, source: SourceKey) -> u32 {
        self.lights.push(light);
        self.sources.push(source);
        (self.lights.len() - 1) as u32
    }

    fn add_emissive_triangles(&mut self, scene: &Scene) {
        for (i, tri) in scene.triangles.iter().enumerate() {
            if !scene.materials[tri.material as usize].is_emissive() {
                continue;
            }
            let area = triangle_area(scene, i as u32);
            if area > 0.0 {
                let material = &scene.materials[tri.material as usize];
                let corners = tri.vertices.map(|v| scene.positions[v as usize]);
                let light = self.push(
                    Light::Triangle {
                        triangle: i as u32,
                        area,
                        corners,
                        normal: geometric_normal(corners[0], corners[1], corners[2]),
                        uniform_radiance: material
                            .emission_texture
                            .is_none()
                            .then_some(material.emission),
                        double_sided: material.double_sided,
                    },
                    SourceKey::Emitter(tri.material),
                );
                // in increasing triangle order: the list stays sorted
                self.triangle_light.push((i as u32, light));
            }
        }
    }

    /// Light mode `point`: each emitter (object × material) becomes one cosine
    /// point at its area-weighted centroid if it is planar, else one per triangle.
    fn add_collapsed_emitters(&mut self, scene: &Scene) {
        let mut groups: std::collections::BTreeMap<(u32, u32), Vec<u32>> = Default::default();
        for (i, tri) in scene.triangles.iter().enumerate() {
            if scene.materials[tri.material as usize].is_emissive() {
                self.hidden_triangles.resize(scene.triangles.len(), false);
                self.hidden_triangles[i] = true;
                let object = scene.object_of_triangle(i as u32);
                groups
                    .entry((object, tri.material))
                    .or_default()
                    .push(i as u32);
            }
        }
        for ((_, material_index), triangles) in groups {
            let material = &scene.materials[material_index as usize];
            let radiance = material.emission
                * material
                    .emission_texture
                    .map_or(Vec3::ONE, |t| scene.textures[t.texture as usize].mean());
            let normal_of = |t: u32| SurfacePoint::new(scene, t, Vec3::splat(1.0 / 3.0)).ng;
            let n0 = normal_of(triangles[0]);
            let planar = triangles.iter().all(|&t| normal_of(t).dot(n0) > 1.0 - 1e-5);
            let parts: Vec<Vec<u32>> = if planar {
                vec![triangles]
            } else {
                triangles.into_iter().map(|t| vec![t]).collect()
            };
            for part in parts {
                let area: f32 = part.iter().map(|&t| triangle_area(scene, t)).sum();
                if area <= 0.0 {
                    continue;
                }
                let centroid = part
                    .iter()
                    .map(|&t| {
                        triangle_area(scene, t)
                            * SurfacePoint::new(scene, t, Vec3::splat(1.0 / 3.0)).p
                    })
                    .sum::<Vec3>()
                    / area;
                self.push(
                    Light::CosinePoint {
                        position: centroid,
                        normal: normal_of(part[0]),
                        radiance_area: radiance * area,
                        two_sided: material.double_sided,
                    },
                    SourceKey::Emitter(material_index),
                );
            }
        }
    }

    fn add_punctual_lights(&mut self, scene: &Scene, extended: bool, radius: f32) {
        for (index, light) in scene.lights.iter().enumerate() {
            let cone = match light.kind {
                PunctualKind::Spot {
                    inner_cone_angle,
                    outer_cone_angle,
                } => Some(Cone {
                    axis: light.direction,
                    cos_inner: inner_cone_angle.cos(),
                    cos_outer: outer_cone_angle.cos(),
                }),
                _ => None,
            };
            let new = match light.kind {
                PunctualKind::Directional => Light::Directional {
                    towards_light: -light.direction,
                    irradiance: light.intensity,
                },
                _ if extended => {
                    let sphere = Sphere {
                        center: light.position,
                        radius,
                        light: self.lights.len() as u32,
                    };
                    self.spheres.push(sphere);
                    self.sphere_light.push(sphere.light);
                    Light::Sphere {
                        sphere,
                        intensity: light.intensity,
                        cone,
                    }
                }
                _ => Light::Point {
                    position: light.position,
                    intensity: light.intensity,
                    cone,
                },
            };
            self.push(new, SourceKey::Light(index as u32));
        }
    }

    pub fn is_empty(&self) -> bool {
        self.selection.is_empty()
    }

    /// Whether some light can be hit by a ray (area or sphere lights).
    pub fn has_hittable_lights(&self) -> bool {
        self.has_hittable_lights
    }

    /// Whether some light is a Dirac (only light samples can find it).
    pub fn has_delta_lights(&self) -> bool {
        self.has_delta_lights
    }

    /// Probability that a light sample picks light `index`.
    pub fn selection_probability(&self, index: usize) -> f32 {
        self.selection.pmf(index)
    }

    /// Light index of scene triangle `triangle`, if it is an emitter of this table.
    pub fn light_of_triangle(&self, triangle: u32) -> Option<u32> {
        let found = self
            .triangle_light
            .binary_search_by_key(&triangle, |&(t, _)| t);
        found.ok().map(|at| self.triangle_light[at].1)
    }

    /// Light index of accel sphere `sphere`.
    pub fn light_of_sphere(&self, sphere: u32) -> u32 {
        self.sphere_light[sphere as usize]
    }

    /// The source light `light` belongs to, as the user names it.
    pub fn source_of(&self, light: usize) -> SourceKey {
        self.sources[light]
    }

    /// Whether scene triangle `triangle` stopped being geometry (an emitter
    /// collapsed to a point light).
    pub fn is_hidden(&self, triangle: u32) -> bool {
        self.hidden_triangles
            .get(triangle as usize)
            .copied()
            .unwrap_or(false)
    }

    /// Draws light at surface point `at` from the position pair `u` (and,
    /// with many lights, the selection number `u_select`), as
    /// [`LightTable::pick_with_position`] shares them out.
    pub fn sample(
        &self,
        scene: &Scene,
        at: &SurfacePoint,
        u_select: f32,
        u: Vec2,
    ) -> Option<LightSample> {
        let (index, probability, u) = self.pick_with_position(u, 0, || u_select)?;
        self.sample_light(scene, at, index, probability, u)
    }

    /// Picks a light from one uniform number: its index and probability.
    #[inline]
    pub fn pick(&self, u_select: f32) -> Option<(usize, f32)> {
        self.selection.sample(u_select)
    }

    /// Light samples per vertex: `settings.light_samples`, or with a
    /// quality for each source, N = Σ N_s (`transport::sources`).
    #[inline]
    pub fn samples_per_vertex(&self, settings: &RenderSettings) -> u32 {
        match &self.budget {
            Some(budget) => budget.samples_per_vertex().max(1),
            None => settings.light_samples.max(1),
        }
    }

    /// With a quality for each source, the source of each light sample.
    pub fn budget(&self) -> Option<&SourceBudget> {
        self.budget.as_ref()
    }

    /// Picks the light of light sample `slot` (of [`LightTable::samples_per_vertex`])
    /// and the pair that places the sample on it, from the pair `u`. With a
    /// quality for each source, the slot's source picks one of its lights
    /// with `u.x`, and the probability returned is N_s P(t | s) / N.
    /// Otherwise, with up to [`SHARED_SELECTION_LIGHTS`] lights, `u.x` picks
    /// the light and, remapped, places the sample with `u.y`, so a
    /// stratified pair stays stratified over all the emitters together
    /// (the two triangles of a quad light share its points, instead of
    /// splitting them by an unrelated number). With more lights the choice
    /// would leave too few bits of `u.x`, and `u_select` picks instead.
    #[inline(always)]
    pub fn pick_with_position(
        &self,
        u: Vec2,
        slot: u32,
        u_select: impl FnOnce() -> f32,
    ) -> Option<(usize, f32, Vec2)> {
        if let Some(budget) = &self.budget {
            let (index, probability, samples, x) = budget.pick(slot, u.x)?;
            let share = samples as f32 / budget.samples_per_vertex() as f32;
            return Some((index, probability * share, Vec2::new(x, u.y)));
        }
        if self.lights.len() <= SHARED_SELECTION_LIGHTS {
            let (index, probability, x) = self.selection.sample_remapped(u.x)?;
            Some((index, probability, Vec2::new(x, u.y)))
        } else {
            let (index, probability) = self.pick(u_select())?;
            Some((index, probability, u))
        }
    }

    /// Draws a point or direction of light `index`, picked with probability
    /// `probability`, seen from `at` (the returned pdf includes the probability).
    #[inline(always)]
    pub fn sample_light(
        &self,
        scene: &Scene,
        at: &SurfacePoint,
        index: usize,
        probability: f32,
        u: Vec2,
    ) -> Option<LightSample> {
        let mut sample = match self.lights[index] {
            Light::Triangle { triangle, .. } => match self.triangle_sampling {
                TriangleSampling::Area => {
                    let light = &self.lights[index];
                    light_point_sample(scene, at, light, uniform_triangle(u))?
                }
                TriangleSampling::SolidAngle => {
                    sample_triangle_solid_angle(scene, at, &self.lights[index], triangle, u)?
                }
            },
            Light::Point {
                position,
                intensity,
                cone,
            } => {
                let to_light = position - at.p;
                let wi = to_light.normalize_or_zero();
                let radiance =
                    Light::intensity_towards(intensity, &cone, -wi) / to_light.length_squared();
                delta_sample(at, wi, radiance, position)
            }
            Light::CosinePoint {
                position,
                normal,
                radiance_area,
                two_sided,
            } => {
                let to_light = position - at.p;
                let wi = to_light.normalize_or_zero();
                let cos = normal.dot(-wi);
                let cos = if two_sided { cos.abs() } else { cos.max(0.0) };
                delta_sample(
                    at,
                    wi,
                    radiance_area * cos / to_light.length_squared(),
                    position,
                )
            }
            Light::Directional {
                towards_light,
                irradiance,
            } => {
                let origin = offset_ray_origin(at.p, at.p_error, at.ng, towards_light);
                LightSample {
                    wi: towards_light,
                    radiance: irradiance,
                    pdf: 1.0,
                    delta: true,
                    shadow_ray: Ray::new(origin, towards_light, f32::INFINITY),
                    target_sphere: None,
                }
            }
            Light::Sphere {
                sphere,
                intensity,
                cone,
            } => sample_sphere(at, &sphere, intensity, &cone, u, self.sphere_index(index))?,
        };
        if !sample.radiance.is_finite() || sample.radiance.max_element() <= 0.0 {
            return None;
        }
        sample.pdf *= probability;
        Some(sample)
    }

    fn sphere_index(&self, light: usize) -> u32 {
        self.sphere_light
            .iter()
            .position(|&l| l as usize == light)
            .map_or(NO_ID, |i| i as u32)
    }

    /// Solid-angle density with which [`LightTable::sample`] at `from` picks the
    /// point `hit` of emissive triangle `triangle` (0 if it is not a light).
    pub fn pdf_triangle(
        &self,
        scene: &Scene,
        from: Vec3,
        triangle: u32,
        hit: &SurfacePoint,
    ) -> f32 {
        let Some(light) = self.light_of_triangle(triangle) else {
            return 0.0;
        };
        let Light::Triangle { area, .. } = self.lights[light as usize] else {
            return 0.0;
        };
        let to_hit = hit.p - from;
        let distance2 = to_hit.length_squared();
        let cos = hit.ng.dot(-to_hit.normalize_or_zero());
        let material = &scene.materials[scene.triangles[triangle as usize].material as usize];
        let cos = if material.double_sided {
            cos.abs()
        } else {
            cos
        };
        if cos <= 0.0 {
            return 0.0;
        }
        let selection = self.selection.pmf(light as usize);
        if self.triangle_sampling == TriangleSampling::SolidAngle {
            let solid_angle = triangle_solid_angle(scene, triangle, from);
            if SOLID_ANGLE_RANGE.contains(&solid_angle) {
                return selection / solid_angle as f32;
            }
        }
        selection * distance2 / (cos * area)
    }

    /// Radiance leaving accel sphere `sphere` along unit `direction`, and the
    /// solid-angle density with which sampling at `from` picks that direction.
    pub fn sphere_emission(&self, sphere: u32, from: Vec3, direction: Vec3) -> (Vec3, f32) {
        let light = self.sphere_light[sphere as usize] as usize;
        let Light::Sphere {
            sphere,
            intensity,
            cone,
        } = self.lights[light]
        else {
            return (Vec3::ZERO, 0.0);
        };
        let radiance = Light::intensity_towards(intensity, &cone, direction)
            / (PI * sphere.radius * sphere.radius);
        let pdf = cone_of(&sphere, from)
            .map_or(0.0, |(_, one_minus_cos)| uniform_cone_pdf(one_minus_cos));
        (radiance, self.selection.pmf(light) * pdf)
    }
}

/// Radius of the sphere lights `--lights area` makes of point and spot
/// lights: `settings.light_radius`, or 2% of the scene's diagonal.
pub fn sphere_light_radius(scene: &Scene, settings: &RenderSettings) -> f32 {
    settings
        .light_radius
        .unwrap_or(0.02 * scene.bounds().diagonal().max(1e-6))
}

/// A Dirac light at `position` seen from `at`.
fn delta_sample(at: &SurfacePoint, wi: Vec3, radiance: Vec3, position: Vec3) -> LightSample {
    let origin = offset_ray_origin(at.p, at.p_error, at.ng, wi);
    LightSample {
        wi,
        radiance,
        pdf: 1.0,
        delta: true,
        shadow_ray: Ray::new(origin, position - origin, 1.0 - SHADOW_EPSILON),
        target_sphere: None,
    }
}

fn triangle_area(scene: &Scene, triangle: u32) -> f32 {
    let [p0, p1, p2] = scene.triangles[triangle as usize]
        .vertices
        .map(|v| scene.positions[v as usize]);
    0.5 * (p1 - p0).cross(p2 - p0).length()
}

/// Emitted power (luminance, W) used to choose between lights.
fn power(scene: &Scene, light: &Light, scene_radius: f32) -> f32 {
    let pi = PI;
    match *light {
        Light::Triangle { triangle, area, .. } => {
            let material = &scene.materials[scene.triangles[triangle as usize].material as usize];
            let texture_mean = material
                .emission_texture
                .map_or(Vec3::ONE, |t| scene.textures[t.texture as usize].mean());
            let sides = if material.double_sided { 2.0 } else { 1.0 };
            sides * pi * area * luminance(material.emission * texture_mean)
        }
        Light::Point {
            intensity, cone, ..
        }
        | Light::Sphere {
            intensity, cone, ..
        } => luminance(intensity) * cone.map_or(4.0 * pi, |c| c.solid_angle()),
        Light::CosinePoint {
            radiance_area,
            two_sided,
            ..
        } => (if two_sided { 2.0 } else { 1.0 }) * pi * luminance(radiance_area),
        Light::Directional { irradiance, .. } => {
            pi * scene_radius * scene_radius * luminance(irradiance)
        }
    }
}
