//! The integral itself: a term's integrand over the directions around a
//! point p, as an image of the hemisphere Ω⁺ in p's shading frame.
//!
//! ```text
//! L1(p, ωo) = ∫_Ω⁺ L_e(q, −ω) f_r(p, ω → ωo) cos θ dω      (+ the point lights' Diracs)
//! L2(p, ωo) = ∫_Ω⁺ L_direct(q, −ω) f_r(p, ω → ωo) cos θ dω
//! ```
//!
//! with q the point p sees along ω. L_e(q, −ω) is zero outside the
//! sources' domains Ω_s and where an occluder hides them (the shadow is a
//! hole in Ω_s); L_direct(q, −ω) is the direct lighting q sends back to p,
//! which is zero where q is a source that reflects nothing: L2 lives on
//! Ω = Ω⁺ − Ω_S. In general term k at p is term k − 1 arriving along ω,
//! times f_r cos θ: each direction is traced as the estimators trace it
//! ([`crate::transport::trace`]).
//!
//! **The projection** is Lambert's azimuthal equal-area map of Ω⁺ onto the
//! unit disk: the point (x, y), r² = x² + y² ≤ 1, is the direction
//!
//! ```text
//! ω = (x √(2 − r²), y √(2 − r²), 1 − r²)      (shading frame, z the normal)
//! ```
//!
//! so the zenith is the centre, the horizon the rim, and equal areas of the
//! disk are equal solid angles: dω = 2 dx dy (the disk's area π maps to
//! Ω⁺'s 2π). Every pixel of the map is then the same solid angle, the
//! quadrature of the integral is a plain sum, and the size of a source on
//! the map is its size in the integral. Azimuths are kept, and the map is
//! the view from p out along its normal, as a fisheye photograph taken
//! there: y up (the scene's +Y in the tangent plane; on a floor or a
//! ceiling, the side away from the viewer), x to the right, rows from
//! y = +1 at the top.

use glam::{Vec2, Vec3};
use rayon::prelude::*;

use crate::course::color::luminance;
use crate::course::{Sampler, Term, TermSet};
use crate::geometry::accel::Hit;
use crate::geometry::{Frame, Ray};
use crate::transport::brdf::Brdf;
use crate::transport::context::RenderContext;
use crate::transport::counts::RayCounts;
use crate::transport::light::Light;
use crate::transport::sampler::{SampleStream, dim};
use crate::transport::surface::SurfacePoint;
use crate::transport::trace;

/// dω / dx dy of the equal-area map: the unit disk's area π is Ω⁺'s 2π.
pub const SOLID_ANGLE_PER_AREA: f32 = 2.0;

/// The direction of the disk point (`x`, `y`), in the shading frame
/// (z the normal); `None` outside the unit disk.
pub fn disk_to_direction(point: Vec2) -> Option<Vec3> {
    let r2 = point.length_squared();
    if r2 > 1.0 {
        return None;
    }
    let s = (2.0 - r2).max(0.0).sqrt();
    Some(Vec3::new(point.x * s, point.y * s, 1.0 - r2))
}

/// The disk point of the direction `w` (unit, z ≥ 0 in the shading frame):
/// the inverse of [`disk_to_direction`].
pub fn direction_to_disk(w: Vec3) -> Vec2 {
    // r² = 1 − cos θ, and (x, y) along w's azimuth
    let r = (1.0 - w.z.clamp(0.0, 1.0)).sqrt();
    let horizontal = Vec2::new(w.x, w.y).normalize_or_zero();
    horizontal * r
}

/// Where the integral is taken: at p, the first hit of a pixel's centre
/// ray, or one bounce further, at q, the second vertex of a drawn path —
/// the lecture's nested integral, ∫_Ωp … ∫_Ωq:
///
/// ```text
/// L2(p, ωo) = ∫_Ωp L1(q, −ω) f_r(p, ω → ωo) cos θ dω,
/// L1(q, −ω) = ∫_Ωq L_e(r, −ω') f_r(q, ω' → −ω) cos θ' dω'
/// ```
///
/// so the integral of L1 at q is the L_i(p, ω) of L2's integrand at p
/// along the bounce.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Vertex {
    /// p: the first hit of the pixel's centre ray.
    #[default]
    FirstHit,
    /// q: where `bounce`, a continuation leaving p, lands first; ωo at q
    /// points back along it, to p.
    Second { bounce: Ray },
}

impl Vertex {
    /// The ray whose first hit is the vertex, for pixel (`x`, `y`).
    pub fn ray(self, context: &RenderContext, (x, y): (u32, u32)) -> Ray {
        match self {
            Vertex::FirstHit => context.camera.generate(x, y, Vec2::splat(0.5)),
            Vertex::Second { bounce } => bounce,
        }
    }

    /// Its name in the formulas: p or q.
    pub fn name(self) -> &'static str {
        match self {
            Vertex::FirstHit => "p",
            Vertex::Second { .. } => "q",
        }
    }
}

/// The point p a ray sees, where the integral is taken: its surface, its
/// BRDF and its shading frame on the viewer's side.
pub struct ShadingPoint {
    pub point: SurfacePoint,
    pub brdf: Brdf,
    /// Shading frame, z on the side of the viewer.
    pub frame: Frame,
    /// Geometric normal on that side.
    pub ng: Vec3,
    /// Towards the viewer, in the frame.
    pub wo_local: Vec3,
}

impl ShadingPoint {
    /// The surface `ray` hits first, if it is a triangle (a sphere light
    /// only emits).
    pub fn seen(context: &RenderContext, ray: &Ray) -> Option<Self> {
        let Some(Hit::Triangle { triangle, b, .. }) = context.accel.closest_hit(ray) else {
            return None;
        };
        let point = SurfacePoint::new(&context.scene, triangle, b);
        let wo = -ray.direction;
        let brdf = point.brdf(&context.scene, &context.settings, wo);
        let (shading, ng) = point.frame_towards(wo);
        let frame = view_frame(shading, wo);
        Some(Self {
            point,
            brdf,
            frame,
            ng,
            wo_local: frame.to_local(wo),
        })
    }

    /// f_r(p, ω → ωo) cos θ for the direction `w_local` of the frame:
    /// zero below the surface, geometric or shading.
    fn reflected(&self, w_local: Vec3) -> Vec3 {
        if !self.is_above(w_local) {
            return Vec3::ZERO;
        }
        self.brdf.eval(self.wo_local, w_local) * w_local.z
    }

    /// Whether `w_local` leaves p above both its shading and geometric surfaces.
    fn is_above(&self, w_local: Vec3) -> bool {
        w_local.z > 0.0 && self.frame.to_world(w_local).dot(self.ng) > 0.0
    }
}

/// The frame of the view from p out along its normal `shading.z`: y the
/// scene's up (+Y) in the tangent plane, or, on a floor or a ceiling, the
/// side away from the viewer (`wo`); x to the right, z × y. (The BRDFs are
/// isotropic: the integral does not depend on the tangents.)
fn view_frame(shading: Frame, wo: Vec3) -> Frame {
    let z = shading.z;
    let along_plane = |v: Vec3| v - z * z.dot(v);
    let mut up = along_plane(Vec3::Y);
    if up.length() < 0.1 {
        up = -along_plane(wo);
    }
    let y = up.try_normalize().unwrap_or(shading.y);
    Frame {
        x: z.cross(y),
        y,
        z,
    }
}

/// A point light's direction: the integrand of L1 is a Dirac there, its
/// integral the light's contribution L_e f_r cos θ / d² (zero if hidden).
#[derive(Clone, Debug)]
pub struct DiracDirection {
    /// In the shading frame.
    pub direction: Vec3,
    /// Where it falls on the map.
    pub disk: Vec2,
    /// Its contribution to the term (W/m²/sr), zero when occluded.
    pub radiance: Vec3,
    pub occluded: bool,
    /// Its source's name.
    pub name: String,
}

/// The integrand of terms over Ω⁺ at a point (their sum), on a
/// `size`×`size` image of the equal-area disk.
pub struct IntegrandMap {
    pub terms: TermSet,
    pub size: u32,
    /// Mean integrand over each pixel (W/m²/sr per sr), rows from the top;
    /// zero outside the disk.
    pub values: Vec<Vec3>,
    /// Its factors apart, over the same pixels (means of the same
    /// directions): L_i (W/m²/sr, the terms arriving), f_r (1/sr), cos θ.
    pub incident: Vec<Vec3>,
    pub brdf: Vec<Vec3>,
    pub cosine: Vec<f32>,
    /// Directions traced per pixel.
    pub directions_per_pixel: u32,
    /// The point lights, for L1: Diracs, not part of `values`.
    pub diracs: Vec<DiracDirection>,
    /// The integral of `values` (W/m²/sr), and the standard error of its
    /// luminance.
    pub integral: Vec3,
    pub integral_standard_error: f64,
}

impl IntegrandMap {
    /// The term's value at p: the map's integral plus the Diracs.
    pub fn quadrature(&self) -> Vec3 {
        self.integral + self.diracs.iter().map(|d| d.radiance).sum::<Vec3>()
    }

    /// The luminance of `factor` over each pixel.
    pub fn layer(&self, factor: Factor) -> Vec<f32> {
        match factor {
            Factor::Integrand => self.values.iter().map(|&v| luminance(v)).collect(),
            Factor::Incident => self.incident.iter().map(|&v| luminance(v)).collect(),
            Factor::Brdf => self.brdf.iter().map(|&v| luminance(v)).collect(),
            Factor::Cosine => self.cosine.clone(),
        }
    }

    /// The disk point of pixel (`column`, `row`) + `offset` (in pixels).
    pub fn disk_point(size: u32, column: u32, row: u32, offset: Vec2) -> Vec2 {
        let pixel = 2.0 / size as f32;
        Vec2::new(
            -1.0 + (column as f32 + offset.x) * pixel,
            1.0 - (row as f32 + offset.y) * pixel,
        )
    }
}

/// The integrand, or one of its factors apart.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Factor {
    /// L_i(p, ω) f_r(p, ω → ωo) cos θ: what the term integrates.
    #[default]
    Integrand,
    /// L_i(p, ω): the radiance arriving (for L2, L_direct(q, −ω)).
    Incident,
    /// f_r(p, ω → ωo).
    Brdf,
    /// cos θ.
    Cosine,
}

impl Factor {
    pub const ALL: [Factor; 4] = [
        Factor::Integrand,
        Factor::Incident,
        Factor::Brdf,
        Factor::Cosine,
    ];

    /// Its unit, as the colour bar states it.
    pub fn unit(self) -> &'static str {
        match self {
            Factor::Integrand => "W/m²/sr per sr",
            Factor::Incident => "W/m²/sr",
            Factor::Brdf => "1/sr",
            Factor::Cosine => "no unit",
        }
    }
}

/// Why a map cannot be drawn.
#[derive(Debug, PartialEq, thiserror::Error)]
pub enum HemisphereError {
    #[error("the ray meets no surface: there is no point p to integrate at")]
    NoSurface,
    #[error("L0 is the emission p sends, not an integral over directions: choose L1, L2 or L3+")]
    NotAnIntegral,
    #[error(
        "the BRDF at p is a Dirac (a mirror or glass): its integrand is one direction, not a map"
    )]
    DiracBrdf,
    /// The estimators compute only the settings' terms.
    #[error("the render context leaves out {0}, which the map traces along each direction")]
    TermsLeftOut(TermSet),
}

/// The terms arriving along ω whose reflection at p is `terms`: term k at
/// p is term k − 1 arriving (L3+ is L2 and L3+ arriving).
pub fn arriving(terms: TermSet) -> TermSet {
    let mut arriving = TermSet::NONE;
    for (term, before) in [
        (Term::L1, Term::L0),
        (Term::L2, Term::L1),
        (Term::L3Plus, Term::L2),
        (Term::L3Plus, Term::L3Plus),
    ] {
        if terms.contains(term) {
            arriving = arriving.with(before, true);
        }
    }
    arriving
}

/// The integrand of `terms` (L1, L2, L3+, summed) at the point `ray`
/// sees (the context's settings must hold the terms arriving along ω:
/// [`arriving`]; `TermSet::ALL` does): `samples` jittered directions per pixel of a `size`×`size` map
/// (stratified on a √samples grid), each traced as the estimators trace
/// (random numbers from `seed`, the same whatever the number of threads).
pub fn integrand_map(
    context: &RenderContext,
    ray: &Ray,
    terms: TermSet,
    size: u32,
    samples: u32,
    seed: u64,
) -> Result<IntegrandMap, HemisphereError> {
    if terms.is_empty() || terms.contains(Term::L0) {
        return Err(HemisphereError::NotAnIntegral);
    }
    let p = ShadingPoint::seen(context, ray).ok_or(HemisphereError::NoSurface)?;
    if p.brdf.is_delta() {
        return Err(HemisphereError::DiracBrdf);
    }
    let arriving = arriving(terms);
    let left_out = arriving.difference(context.settings.terms);
    if !left_out.is_empty() {
        return Err(HemisphereError::TermsLeftOut(left_out));
    }
    let side = (samples.max(1) as f32).sqrt().ceil() as u32;
    let per_pixel = side * side;
    let pixel_area = (2.0 / size as f32).powi(2);
    // a pixel's solid angle: each pixel is a stratum of the quadrature
    let pixel_solid_angle = (pixel_area * SOLID_ANGLE_PER_AREA) as f64;
    let rows: Vec<(Vec<Factors>, Moments)> = (0..size)
        .into_par_iter()
        .map(|row| {
            let mut counts = RayCounts::default();
            let mut moments = Moments::default();
            let pixels = (0..size)
                .map(|column| {
                    let pixel = (row * size + column) as u64;
                    let (mut total, mut sum, mut sum2) = (Factors::default(), 0.0f64, 0.0f64);
                    for k in 0..per_pixel {
                        let stream =
                            SampleStream::with_sampler(Sampler::Independent, seed, pixel, k as u64);
                        let jitter = stream.uniform2(dim::PIXEL);
                        let cell = Vec2::new((k % side) as f32, (k / side) as f32);
                        let offset = (cell + jitter) / side as f32;
                        let disk = IntegrandMap::disk_point(size, column, row, offset);
                        let factors = disk_to_direction(disk).map_or(Factors::default(), |w| {
                            factors(context, &p, w, &stream, arriving, &mut counts)
                        });
                        let y = luminance(factors.integrand) as f64;
                        (sum, sum2) = (sum + y, sum2 + y * y);
                        total.add(&factors);
                    }
                    moments.add(sum, sum2, per_pixel, pixel_solid_angle);
                    total.scaled(1.0 / per_pixel as f32)
                })
                .collect();
            (pixels, moments)
        })
        .collect();
    let moments = rows
        .iter()
        .fold(Moments::default(), |a, (_, b)| a.merged(b));
    let pixels: Vec<Factors> = rows.into_iter().flat_map(|r| r.0).collect();
    let values: Vec<Vec3> = pixels.iter().map(|f| f.integrand).collect();
    let integral = values.iter().sum::<Vec3>() * pixel_area * SOLID_ANGLE_PER_AREA;
    let diracs = if terms.contains(Term::L1) {
        dirac_directions(context, &p)
    } else {
        Vec::new()
    };
    Ok(IntegrandMap {
        terms,
        size,
        values,
        incident: pixels.iter().map(|f| f.incident).collect(),
        brdf: pixels.iter().map(|f| f.brdf).collect(),
        cosine: pixels.iter().map(|f| f.cosine).collect(),
        directions_per_pixel: per_pixel,
        diracs,
        integral,
        integral_standard_error: moments.standard_error(),
    })
}

/// What the standard error of the quadrature is estimated from: each
/// pixel (solid angle A, k directions of luminance y) adds A ȳ to the
/// integral, with variance A² s²/k, s² the directions' sample variance
/// (an upper bound for directions stratified within the pixel). With one
/// direction per pixel, the directions are taken as independent over the
/// whole disk instead (a looser bound).
#[derive(Clone, Copy, Default)]
struct Moments {
    /// Σ A² s²/k over the pixels.
    stratified_variance: f64,
    /// Σ A y and Σ A² y² over the directions (for one direction per pixel).
    sum: f64,
    sum2: f64,
    directions: u64,
    per_pixel: u32,
}

impl Moments {
    fn add(&mut self, sum: f64, sum2: f64, k: u32, solid_angle: f64) {
        self.per_pixel = k;
        self.directions += k as u64;
        self.sum += sum * solid_angle;
        self.sum2 += sum2 * solid_angle * solid_angle;
        if k >= 2 {
            let n = k as f64;
            let mean = sum / n;
            let variance = ((sum2 - n * mean * mean) / (n - 1.0)).max(0.0);
            self.stratified_variance += solid_angle * solid_angle * variance / n;
        }
    }

    fn merged(self, other: &Moments) -> Moments {
        Moments {
            stratified_variance: self.stratified_variance + other.stratified_variance,
            sum: self.sum + other.sum,
            sum2: self.sum2 + other.sum2,
            directions: self.directions + other.directions,
            per_pixel: self.per_pixel.max(other.per_pixel),
        }
    }

    fn standard_error(&self) -> f64 {
        if self.per_pixel >= 2 {
            return self.stratified_variance.sqrt();
        }
        // one direction per pixel: X = N A y, N the pixels, estimates the
        // integral alone; the quadrature is the mean of the N values of X,
        // ΣX = N·sum, ΣX² = N²·sum2
        let n = self.directions.max(2) as f64;
        ((n * self.sum2 - self.sum * self.sum) / (n - 1.0))
            .max(0.0)
            .sqrt()
    }
}

/// The integrand at a direction and its factors (or their means over a pixel).
#[derive(Clone, Copy, Default)]
struct Factors {
    integrand: Vec3,
    incident: Vec3,
    brdf: Vec3,
    cosine: f32,
}

impl Factors {
    fn add(&mut self, other: &Factors) {
        self.integrand += other.integrand;
        self.incident += other.incident;
        self.brdf += other.brdf;
        self.cosine += other.cosine;
    }

    fn scaled(self, s: f32) -> Factors {
        Factors {
            integrand: self.integrand * s,
            incident: self.incident * s,
            brdf: self.brdf * s,
            cosine: self.cosine * s,
        }
    }
}

/// The integrand at direction `w_local`: the `arriving` terms along ω
/// (L_i), times f_r cos θ; each factor apart. Below the geometric surface
/// (a shading-normal artefact) every factor is zero.
fn factors(
    context: &RenderContext,
    p: &ShadingPoint,
    w_local: Vec3,
    stream: &SampleStream,
    arriving: TermSet,
    counts: &mut RayCounts,
) -> Factors {
    if !p.is_above(w_local) {
        return Factors::default();
    }
    let w = p.frame.to_world(w_local).normalize();
    let radiance = trace(context, p.point.spawn_ray(w), stream, arriving, counts);
    let incident: Vec3 = arriving.iter().map(|t| radiance[t.index()]).sum();
    let brdf = p.brdf.eval(p.wo_local, w_local);
    Factors {
        integrand: incident * brdf * w_local.z,
        incident,
        brdf,
        cosine: w_local.z,
    }
}

/// The point lights (and lights collapsed to points, and the sun) seen
/// from p: each a direction with its contribution to L1.
fn dirac_directions(context: &RenderContext, p: &ShadingPoint) -> Vec<DiracDirection> {
    let lights = &context.lights;
    (0..lights.lights.len())
        .filter(|&index| {
            matches!(
                lights.lights[index],
                Light::Point { .. } | Light::CosinePoint { .. } | Light::Directional { .. }
            )
        })
        .filter_map(|index| {
            let sample =
                lights.sample_light(&context.scene, &p.point, index, 1.0, Vec2::splat(0.5))?;
            let direction = p.frame.to_local(sample.wi);
            let occluded = context
                .accel
                .occluded(&sample.shadow_ray, sample.target_sphere);
            let radiance = if occluded {
                Vec3::ZERO
            } else {
                sample.radiance * p.reflected(direction)
            };
            Some(DiracDirection {
                name: lights.source_of(index).name(&context.scene).to_owned(),
                direction,
                disk: direction_to_disk(direction),
                radiance,
                occluded,
            })
        })
        .collect()
}

/// Mean, and standard error of the luminance, of `terms` (summed) along
/// `ray`, over `samples` samples of the render's own estimator (the
/// film's sampler and seed, pixel `pixel`): what the quadrature of the map
/// is compared with.
pub fn estimator_mean(
    context: &RenderContext,
    ray: &Ray,
    terms: TermSet,
    pixel: u64,
    samples: u32,
) -> (Vec3, f64) {
    let settings = &context.settings;
    let mut counts = RayCounts::default();
    let (mut sum, mut sum_luminance, mut sum2) = (glam::DVec3::ZERO, 0.0f64, 0.0f64);
    for pass in 0..samples {
        let stream =
            SampleStream::with_sampler(settings.sampler, settings.seed, pixel, pass as u64);
        let by_term = trace(context, *ray, &stream, terms, &mut counts);
        let radiance: Vec3 = terms.iter().map(|t| by_term[t.index()]).sum();
        let y = luminance(radiance) as f64;
        sum += radiance.as_dvec3();
        sum_luminance += y;
        sum2 += y * y;
    }
    let n = samples.max(1) as f64;
    let mean = sum_luminance / n;
    let variance = (sum2 / n - mean * mean).max(0.0) * n / (n - 1.0).max(1.0);
    ((sum / n).as_vec3(), (variance / n).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map and its inverse agree, and equal areas are equal solid angles.
    #[test]
    fn the_map_is_an_equal_area_bijection() {
        for (x, y) in [(0.0, 0.0), (0.3, -0.4), (-0.7, 0.7), (0.999, 0.0)] {
            let point = Vec2::new(x, y);
            let w = disk_to_direction(point).unwrap();
            assert!((w.length() - 1.0).abs() < 1e-5, "{w}");
            assert!((direction_to_disk(w) - point).length() < 1e-4);
        }
        assert!(disk_to_direction(Vec2::new(0.8, 0.8)).is_none());
        // a cap of half-angle α (solid angle 2π(1 − cos α)) is a disk of
        // radius r, r² = 1 − cos α: area π r², times 2
        for alpha in [0.2f32, 0.9, 1.5] {
            let r = direction_to_disk(Vec3::new(alpha.sin(), 0.0, alpha.cos())).x;
            let cap = 2.0 * std::f32::consts::PI * (1.0 - alpha.cos());
            let disk = std::f32::consts::PI * r * r * SOLID_ANGLE_PER_AREA;
            assert!(
                (cap - disk).abs() < 1e-4 * cap,
                "α {alpha}: {cap} vs {disk}"
            );
        }
    }
}
