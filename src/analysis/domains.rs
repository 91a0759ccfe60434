//! The sources' domains Ω_s on the map of the hemisphere at p: the
//! directions from p that meet source s, whether or not something hides
//! it. L1 integrates over Σ Ω_s, where an occluder makes a hole (the
//! shadow); L2 over Ω = Ω⁺ − Ω_S, the rest (`hemisphere.rs`).

use glam::Vec2;

use crate::geometry::accel::Hit;
use crate::transport::context::RenderContext;
use crate::transport::surface::SurfacePoint;

use super::hemisphere::{IntegrandMap, ShadingPoint, disk_to_direction};

/// Surfaces a domain ray goes through, at most, looking for a source
/// behind the occluders.
const MOST_OCCLUDERS: u32 = 64;

/// Which source each pixel of a `size`×`size` map of the hemisphere looks
/// at (through its centre), and whether it sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct SourceDomains {
    pub size: u32,
    /// Per pixel, rows from the top: the index in `names` of the first
    /// source along the direction, ignoring what is in front of it.
    pub source: Vec<Option<u16>>,
    /// Per pixel: the source is the first surface the direction meets.
    pub visible: Vec<bool>,
    /// The sources met, by the names the user knows them by.
    pub names: Vec<String>,
}

impl SourceDomains {
    /// The outline of each domain, in disk coordinates (x right, y up): the
    /// pixel edges between a pixel of Ω_s and one that is not.
    pub fn outline(&self) -> Vec<(Vec2, Vec2)> {
        let size = self.size;
        let at = |column: u32, row: u32| self.source[(row * size + column) as usize];
        let corner =
            |column: u32, row: u32| IntegrandMap::disk_point(size, column, row, Vec2::ZERO);
        let mut edges = Vec::new();
        for row in 0..size {
            for column in 0..size {
                let here = at(column, row);
                if column + 1 < size && at(column + 1, row) != here {
                    edges.push((corner(column + 1, row), corner(column + 1, row + 1)));
                }
                if row + 1 < size && at(column, row + 1) != here {
                    edges.push((corner(column, row + 1), corner(column + 1, row + 1)));
                }
            }
        }
        edges
    }

    /// Where to write each source's name: beside its domain, and the
    /// domain's share of the hemisphere.
    pub fn labels(&self) -> Vec<DomainLabel> {
        // per source: the sum of its pixel centres, their count, the lowest y
        let mut sums = vec![(Vec2::ZERO, 0u32, f32::INFINITY); self.names.len()];
        for (i, source) in self.source.iter().enumerate() {
            if let Some(s) = source {
                let (column, row) = (i as u32 % self.size, i as u32 / self.size);
                let centre = IntegrandMap::disk_point(self.size, column, row, Vec2::splat(0.5));
                let sum = &mut sums[*s as usize];
                *sum = (sum.0 + centre, sum.1 + 1, sum.2.min(centre.y));
            }
        }
        // the disk's π·size²/4 pixels are Ω⁺'s 2π sr
        let disk_pixels = std::f32::consts::PI / 4.0 * (self.size * self.size) as f32;
        let half_pixel = 1.0 / self.size as f32;
        self.names
            .iter()
            .zip(sums)
            .filter(|(_, (_, n, _))| *n > 0)
            .map(|(name, (sum, n, lowest))| DomainLabel {
                name: name.clone(),
                centre: sum / n as f32,
                below: Vec2::new(sum.x / n as f32, lowest - half_pixel),
                share: n as f32 / disk_pixels,
            })
            .collect()
    }
}

/// A source's name on the map.
#[derive(Clone, Debug, PartialEq)]
pub struct DomainLabel {
    pub name: String,
    /// The centroid of its domain, in disk coordinates.
    pub centre: Vec2,
    /// Under the domain's lowest pixel, where the name does not hide it.
    pub below: Vec2,
    /// Its fraction of Ω⁺'s 2π sr.
    pub share: f32,
}

/// The domains of the sources at `p`, on a `size`×`size` map.
pub fn source_domains(context: &RenderContext, p: &ShadingPoint, size: u32) -> SourceDomains {
    let mut names: Vec<String> = Vec::new();
    let mut source = Vec::with_capacity((size * size) as usize);
    let mut visible = Vec::with_capacity((size * size) as usize);
    for row in 0..size {
        for column in 0..size {
            let centre = IntegrandMap::disk_point(size, column, row, Vec2::splat(0.5));
            let found = disk_to_direction(centre).and_then(|w_local| {
                let w = p.frame.to_world(w_local).normalize();
                first_source(context, p.point.spawn_ray(w))
            });
            match found {
                Some((name, seen)) => {
                    let index = match names.iter().position(|n| *n == name) {
                        Some(index) => index,
                        None => {
                            names.push(name);
                            names.len() - 1
                        }
                    };
                    source.push(Some(index as u16));
                    visible.push(seen);
                }
                None => {
                    source.push(None);
                    visible.push(false);
                }
            }
        }
    }
    SourceDomains {
        size,
        source,
        visible,
        names,
    }
}

/// The name of the first source along `ray`, through any surface in front
/// of it, and whether it is the first surface met.
fn first_source(context: &RenderContext, ray: crate::geometry::Ray) -> Option<(String, bool)> {
    let behind = first_light(context, ray)?;
    let source = context.lights.source_of(behind.light as usize);
    Some((
        source.name(&context.scene).to_owned(),
        behind.occluders == 0,
    ))
}

/// The first light along a ray, whatever stands in front of it.
pub struct LightBehind {
    /// Its index in the light table.
    pub light: u32,
    pub hit: Hit,
    /// The point hit, on a triangle light.
    pub point: Option<SurfacePoint>,
    /// Surfaces the ray went through before it.
    pub occluders: u32,
}

/// The first light along `ray`, through at most [`MOST_OCCLUDERS`] surfaces.
pub fn first_light(context: &RenderContext, ray: crate::geometry::Ray) -> Option<LightBehind> {
    let mut first = None;
    walk_to_lights(context, ray, |light| {
        first = Some(light);
        false
    });
    first
}

/// Every light along `ray`, through at most [`MOST_OCCLUDERS`] surfaces,
/// nearest first; the walk ends at a sphere light (what lies behind it is
/// not looked for).
pub fn lights_along(context: &RenderContext, ray: crate::geometry::Ray) -> Vec<LightBehind> {
    let mut lights = Vec::new();
    walk_to_lights(context, ray, |light| {
        lights.push(light);
        true
    });
    lights
}

/// Walks along `ray` through surfaces, handing each light met to `visit`
/// until it returns false.
fn walk_to_lights(
    context: &RenderContext,
    mut ray: crate::geometry::Ray,
    mut visit: impl FnMut(LightBehind) -> bool,
) {
    let (scene, lights) = (&context.scene, &context.lights);
    let mut occluders = 0;
    for _ in 0..MOST_OCCLUDERS {
        let Some(hit) = context.accel.closest_hit(&ray) else {
            return;
        };
        match hit {
            Hit::Sphere { sphere, .. } => {
                let light = lights.light_of_sphere(sphere);
                visit(LightBehind {
                    light,
                    hit,
                    point: None,
                    occluders,
                });
                return;
            }
            Hit::Triangle { triangle, b, .. } => {
                let point = SurfacePoint::new(scene, triangle, b);
                ray = point.spawn_ray(ray.direction);
                // a light is handed over; an occluder is looked behind
                if let Some(light) = lights.light_of_triangle(triangle) {
                    let light = LightBehind {
                        light,
                        hit,
                        point: Some(point),
                        occluders,
                    };
                    if !visit(light) {
                        return;
                    }
                }
                occluders += 1;
            }
        }
    }
}
