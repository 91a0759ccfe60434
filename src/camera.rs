//! Camera rays: pixel (x, y) plus a point in the pixel → a ray in world space.
//!
//! The image plane sits at z = −1 in camera space, +Y up, +X right; the
//! vertical field of view comes from the camera, the aspect from the image
//! size. Pixel (0, 0) is the top-left one; a sample `u ∈ [0,1)²` inside the
//! pixel gives the box filter.

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
