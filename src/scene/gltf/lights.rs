//! `KHR_lights_punctual` point, spot and directional lights: `color × intensity`
//! taken as is (no photometric conversion), placed by their node's transform.

use std::f32::consts::FRAC_PI_2;

use glam::{Affine3A, Vec3};

use super::build::SceneBuilder;
use super::{Loaded, label};
use crate::scene::{PunctualKind, PunctualLight};

/// `color × intensity`, refused if negative or not finite.
fn light_intensity(light: &gltf::khr_lights_punctual::Light) -> Loaded<Vec3> {
    let color = Vec3::from(light.color());
    let strength = light.intensity();
    if !strength.is_finite() || strength < 0.0 {
        return Err(format!(
            "intensity {strength} must be finite and non-negative"
        ));
    }
    if !color.is_finite() || color.min_element() < 0.0 {
        return Err(format!("color {color} must be finite and non-negative"));
    }
    let intensity = color * strength;
    if !intensity.is_finite() {
        return Err(format!("intensity {color} × {strength} overflows"));
    }
    Ok(intensity)
}

impl SceneBuilder<'_> {
    pub(super) fn add_light(
        &mut self,
        node: &gltf::Node,
        light: &gltf::khr_lights_punctual::Light,
        world: &Affine3A,
    ) -> Loaded<()> {
        let light_label = label("light", light.index(), light.name());
        let intensity =
            light_intensity(light).map_err(|problem| format!("{light_label}: {problem}"))?;
        let kind = match light.kind() {
            gltf::khr_lights_punctual::Kind::Point => PunctualKind::Point,
            gltf::khr_lights_punctual::Kind::Directional => PunctualKind::Directional,
            gltf::khr_lights_punctual::Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => self.spot_cone(inner_cone_angle, outer_cone_angle, &light_label)?,
        };
        let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
        if direction == Vec3::ZERO {
            return Err(format!(
                "{light_label}: its node's −Z axis has no direction"
            ));
        }
        let name = light
            .name()
            .or(node.name())
            .map_or_else(|| format!("light {}", light.index()), String::from);
        self.scene.lights.push(PunctualLight {
            name,
            kind,
            position: world.translation.into(),
            direction,
            intensity,
        });
        Ok(())
    }

    /// Requires 0 ≤ inner < outer ≤ π/2; an inner angle not below the outer
    /// one is moved just below it, with a warning.
    fn spot_cone(&mut self, inner: f32, outer: f32, light_label: &str) -> Loaded<PunctualKind> {
        if !(outer > 0.0 && outer <= FRAC_PI_2) {
            return Err(format!(
                "{light_label}: outerConeAngle {outer} must lie in (0, π/2]"
            ));
        }
        if !inner.is_finite() || inner < 0.0 {
            return Err(format!(
                "{light_label}: innerConeAngle {inner} must be finite and non-negative"
            ));
        }
        let inner = if inner >= outer {
            self.warn(format!(
                "{light_label}: innerConeAngle {inner} is not below outerConeAngle {outer}; moved just below it"
            ));
            outer.next_down()
        } else {
            inner
        };
        Ok(PunctualKind::Spot {
            inner_cone_angle: inner,
            outer_cone_angle: outer,
        })
    }
}
