//! Camera rays: pixel (x, y) plus a point in the pixel → a ray in world space.
//!
//! The image plane sits at z = −1 in camera space, +Y up, +X right; the
//! vertical field of view comes from the camera, the aspect from the image
//! size. Pixel (0, 0) is the top-left one; a sample `u ∈ [0,1)²` inside the
//! pixel gives the box filter.
//!
//! The inverse, for drawing rays over the image: a world point p goes to
//! camera space q = camera_from_world · p and lands on the film at
//!
//! ```text
//! perspective    x = W/2 · (1 + q.x / (−q.z · half_width)),   y = H/2 · (1 − q.y / (−q.z · half_height))
//! orthographic   x = W/2 · (1 + q.x / half_width),            y = H/2 · (1 − q.y / half_height)
//! ```
//!
//! Only points in front of the camera (q.z < 0) have an image, so a segment is
//! first clipped to the half-space in front of a near plane.

use glam::{Affine3A, Vec2, Vec3};

use crate::geometry::Ray;
use crate::scene::{Camera, Projection};

/// A camera bound to an image size.
#[derive(Clone, Debug)]
pub struct CameraRays {
    world_from_camera: Affine3A,
    projection: Projection,
    /// Half-extent of the image plane at distance 1 (perspective) or in metres (orthographic).
    half_height: f32,
    half_width: f32,
    width: u32,
    height: u32,
}

impl CameraRays {
    pub fn new(camera: &Camera, width: u32, height: u32) -> Self {
        let half_height = match camera.projection {
            Projection::Perspective { yfov } => (0.5 * yfov).tan(),
            Projection::Orthographic { half_height } => half_height,
        };
        Self {
            world_from_camera: camera.world_from_camera,
            projection: camera.projection,
            half_height,
            half_width: half_height * width as f32 / height as f32,
            width,
            height,
        }
    }

    /// The film's size in pixels.
    pub fn film_size(&self) -> Vec2 {
        Vec2::new(self.width as f32, self.height as f32)
    }

    /// The film point (in pixels from the top-left corner) of camera-space point `q`, q.z < 0.
    fn film_point(&self, q: Vec3) -> Vec2 {
        let depth = match self.projection {
            Projection::Perspective { .. } => -q.z,
            Projection::Orthographic { .. } => 1.0,
        };
        Vec2::new(
            0.5 * self.width as f32 * (1.0 + q.x / (depth * self.half_width)),
            0.5 * self.height as f32 * (1.0 - q.y / (depth * self.half_height)),
        )
    }

    /// The film image of the world segment `from`–`to` (film points in
    /// pixels, possibly outside the image), or `None` if it lies wholly
    /// behind the camera.
    ///
    /// The near plane sits at a small fraction of the segment's deepest point,
    /// so a ray leaving the eye keeps its direction on the film (a camera ray
    /// projects to the point of its pixel).
    pub fn project_segment(&self, from: Vec3, to: Vec3) -> Option<(Vec2, Vec2)> {
        let camera_from_world = self.world_from_camera.inverse();
        let (mut a, mut b) = (
            camera_from_world.transform_point3(from),
            camera_from_world.transform_point3(to),
        );
        let near = 1e-4 * a.z.abs().max(b.z.abs()).max(f32::MIN_POSITIVE);
        if a.z > -near && b.z > -near {
            return None;
        }
        // move the end behind the near plane onto it
        let clip = |inside: Vec3, outside: Vec3| {
            let t = (-near - inside.z) / (outside.z - inside.z);
            inside + (outside - inside) * t
        };
        if a.z > -near {
            a = clip(b, a);
        } else if b.z > -near {
            b = clip(a, b);
        }
        Some((self.film_point(a), self.film_point(b)))
    }

    /// The ray through point `u` of pixel (`x`, `y`); its direction is unit length.
    pub fn generate(&self, x: u32, y: u32, u: Vec2) -> Ray {
        let ndc_x = 2.0 * (x as f32 + u.x) / self.width as f32 - 1.0;
        let ndc_y = 1.0 - 2.0 * (y as f32 + u.y) / self.height as f32;
        let plane = Vec3::new(ndc_x * self.half_width, ndc_y * self.half_height, -1.0);
        let (origin, direction) = match self.projection {
            Projection::Perspective { .. } => (Vec3::ZERO, plane),
            Projection::Orthographic { .. } => (Vec3::new(plane.x, plane.y, 0.0), -Vec3::Z),
        };
        Ray::new(
            self.world_from_camera.transform_point3(origin),
            self.world_from_camera
                .transform_vector3(direction)
                .normalize(),
            f32::INFINITY,
        )
    }
}
