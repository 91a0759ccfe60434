//! Materials: metallic-roughness factors and emission converted once per glTF
//! material, with the textures they refer to, and warnings for the parts not
//! read.

use glam::Vec3;

use super::build::SceneBuilder;
use super::{Loaded, label};
use crate::course::DEFAULT_IOR;
use crate::scene::{Material, TextureRef};

/// `emissiveFactor × KHR_materials_emissive_strength`, a radiance.
fn emission_radiance(material: &gltf::Material) -> Loaded<Vec3> {
    let factor = Vec3::from(material.emissive_factor());
    let strength = material.emissive_strength().unwrap_or(1.0);
    if !factor.is_finite() || factor.min_element() < 0.0 {
        return Err(format!(
            "emissiveFactor {factor} must be finite and non-negative"
        ));
    }
    if !strength.is_finite() || strength < 0.0 {
        return Err(format!(
            "emissiveStrength {strength} must be finite and non-negative"
        ));
    }
    let radiance = factor * strength;
    if !radiance.is_finite() {
        return Err(format!("emission {factor} × {strength} overflows"));
    }
    Ok(radiance)
}

impl<'f> SceneBuilder<'f> {
    /// The scene id of a glTF material, converting it on first use.
    pub(super) fn material_id(&mut self, material: gltf::Material<'f>) -> Loaded<u32> {
        let key = material.index();
        if let Some(&id) = self.material_ids.get(&key) {
            return Ok(id);
        }
        let converted = match key {
            None => Material::default(),
            Some(_) => self.convert_material(&material)?,
        };
        let id = self.scene.add_material(converted);
        self.material_ids.insert(key, id);
        Ok(id)
    }

    fn convert_material(&mut self, material: &gltf::Material<'f>) -> Loaded<Material> {
        let index = material.index().unwrap_or_default();
        let material_label = label("material", index, material.name());
        let pbr = material.pbr_metallic_roughness();
        let [red, green, blue, _alpha] = pbr.base_color_factor();
        let base_color = Vec3::new(
            self.unit_factor(red, "baseColorFactor", &material_label)?,
            self.unit_factor(green, "baseColorFactor", &material_label)?,
            self.unit_factor(blue, "baseColorFactor", &material_label)?,
        );
        let metallic =
            self.unit_factor(pbr.metallic_factor(), "metallicFactor", &material_label)?;
        let roughness =
            self.unit_factor(pbr.roughness_factor(), "roughnessFactor", &material_label)?;
        let emission = emission_radiance(material)
            .map_err(|problem| format!("{material_label}: {problem}"))?;
        let base_color_texture = match pbr.base_color_texture() {
            Some(info) => Some(self.texture_ref(&info, &material_label, "baseColorTexture")?),
            None => None,
        };
        let emission_texture = match material.emissive_texture() {
            Some(info) => Some(self.texture_ref(&info, &material_label, "emissiveTexture")?),
            None => None,
        };
        let transmission = match material.transmission() {
            Some(t) => self.unit_factor(
                t.transmission_factor(),
                "transmissionFactor",
                &material_label,
            )?,
            None => 0.0,
        };
        let ior = self.index_of_refraction(material, &material_label)?;
        self.warn_ignored_material_parts(material, &material_label, emission);
        if transmission > 0.0 && roughness > 0.0 {
            self.warn(format!(
                "{material_label}: rough transmission (roughnessFactor {roughness}) is rendered as smooth glass"
            ));
        }
        Ok(Material {
            name: material
                .name()
                .map_or_else(|| format!("material {index}"), String::from),
            base_color,
            base_color_texture,
            metallic,
            roughness,
            emission,
            emission_texture,
            double_sided: material.double_sided(),
            transmission,
            ior,
        })
    }

    /// `KHR_materials_ior`'s index of refraction (1.5 without it); refused
    /// if not finite, raised to 1 with a warning below it (glTF's 0, an
    /// index of refraction for metals, among them).
    fn index_of_refraction(
        &mut self,
        material: &gltf::Material<'f>,
        material_label: &str,
    ) -> Loaded<f32> {
        let Some(ior) = material.ior() else {
            return Ok(DEFAULT_IOR);
        };
        if !ior.is_finite() {
            return Err(format!("{material_label}: ior {ior} is not finite"));
        }
        if ior < 1.0 {
            self.warn(format!(
                "{material_label}: ior {ior} raised to 1 (an index of refraction is at least 1)"
            ));
            return Ok(1.0);
        }
        Ok(ior)
    }

    /// A factor clamped to [0, 1], with a warning if it was outside; refused if not finite.
    fn unit_factor(&mut self, value: f32, field: &str, material_label: &str) -> Loaded<f32> {
        if !value.is_finite() {
            return Err(format!("{material_label}: {field} {value} is not finite"));
        }
        let clamped = value.clamp(0.0, 1.0);
        if clamped != value {
            self.warn(format!(
                "{material_label}: {field} {value} clamped to [0, 1]"
            ));
        }
        Ok(clamped)
    }

    fn warn_ignored_material_parts(
        &mut self,
        material: &gltf::Material,
        material_label: &str,
        emission: Vec3,
    ) {
        if material
            .pbr_metallic_roughness()
            .metallic_roughness_texture()
            .is_some()
        {
            self.warn(format!(
                "{material_label}: metallicRoughnessTexture ignored; the metallic and roughness factors are used"
            ));
        }
        if let Some(transmission) = material.transmission()
            && transmission.transmission_texture().is_some()
        {
            self.warn(format!(
                "{material_label}: transmissionTexture ignored; the transmission factor is used"
            ));
        }
        if material.normal_texture().is_some() {
            self.warn(format!("{material_label}: normalTexture ignored"));
        }
        let alpha_mode = match material.alpha_mode() {
            gltf::material::AlphaMode::Opaque => None,
            gltf::material::AlphaMode::Mask => Some("MASK"),
            gltf::material::AlphaMode::Blend => Some("BLEND"),
        };
        if let Some(alpha_mode) = alpha_mode {
            self.warn(format!(
                "{material_label}: alphaMode {alpha_mode} ignored; the surface is opaque"
            ));
        }
        if material.emissive_texture().is_some() && emission == Vec3::ZERO {
            self.warn(format!(
                "{material_label}: emissiveTexture has no effect (the emission factor is zero)"
            ));
        }
    }

    fn texture_ref(
        &mut self,
        info: &gltf::texture::Info<'f>,
        material_label: &str,
        slot: &str,
    ) -> Loaded<TextureRef> {
        let uv_set = match info.tex_coord() {
            set @ (0 | 1) => set,
            set => {
                self.warn(format!(
                    "{material_label}: {slot} reads TEXCOORD_{set}; only sets 0 and 1 are loaded, set 0 used"
                ));
                0
            }
        };
        let texture = self.texture_id(&info.texture())?;
        Ok(TextureRef { texture, uv_set })
    }
}
