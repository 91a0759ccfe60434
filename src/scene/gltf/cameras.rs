//! Cameras: perspective and orthographic projections, placed by their node's
//! transform with its scale and shear removed.

use std::f32::consts::PI;

use glam::{Affine3A, Mat3, Vec3};

use super::build::SceneBuilder;
use super::{Loaded, label};
use crate::scene::{Camera, Projection};

fn projection(camera: &gltf::Camera) -> Loaded<Projection> {
    match camera.projection() {
        gltf::camera::Projection::Perspective(perspective) => {
            let yfov = perspective.yfov();
            if yfov.is_finite() && yfov > 0.0 && yfov < PI {
                Ok(Projection::Perspective { yfov })
            } else {
                Err(format!("yfov {yfov} must be an angle between 0 and π"))
            }
        }
        gltf::camera::Projection::Orthographic(orthographic) => {
            let ymag = orthographic.ymag();
            if ymag.is_finite() && ymag != 0.0 {
                Ok(Projection::Orthographic {
                    half_height: ymag.abs(),
                })
            } else {
                Err(format!("ymag {ymag} must be finite and non-zero"))
            }
        }
    }
}

/// The rotation and translation of `world`, its scale and shear removed:
/// the camera keeps its viewing direction (−Z) and, as far as possible, its up (+Y).
fn rigid_part(world: &Affine3A) -> Affine3A {
    let back = Vec3::from(world.matrix3.z_axis).normalize();
    let up_axis = Vec3::from(world.matrix3.y_axis);
    let up = (up_axis - back * up_axis.dot(back)).normalize();
    let right = up.cross(back);
    Affine3A::from_mat3_translation(Mat3::from_cols(right, up, back), world.translation.into())
}

impl SceneBuilder<'_> {
    pub(super) fn add_camera(
        &mut self,
        node: &gltf::Node,
        camera: &gltf::Camera,
        world: &Affine3A,
        node_label: &str,
    ) -> Loaded<()> {
        let camera_label = label("camera", camera.index(), camera.name());
        let projection =
            projection(camera).map_err(|problem| format!("{camera_label}: {problem}"))?;
        if world.matrix3.determinant() < 0.0 {
            self.warn(format!(
                "{node_label}: the transform of {camera_label} mirrors; the mirroring is ignored"
            ));
        }
        let name = camera
            .name()
            .or(node.name())
            .map_or_else(|| format!("camera {}", camera.index()), String::from);
        self.scene.cameras.push(Camera {
            name,
            world_from_camera: rigid_part(world),
            projection,
        });
        Ok(())
    }
}
