//! Textures: linear RGB texels, looked up with bilinear filtering.
//!
//! Texels are stored already decoded (sRGB colour textures are turned into
//! linear values once, at load), so a lookup is four reads and a lerp.
//! Texel centres sit at half-integers: `uv = ((i + ½)/w, (j + ½)/h)` reads
//! texel (i, j) exactly; `v` grows downwards as in glTF.

use glam::{Vec2, Vec3};

pub use crate::course::color::{linear_to_srgb, srgb_to_linear};

/// How coordinates outside [0, 1] fold back in (glTF sampler wrap modes).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum WrapMode {
    #[default]
    Repeat,
    MirroredRepeat,
    ClampToEdge,
}

impl WrapMode {
    /// Maps an integer texel index into `0..size`.
    fn fold(self, i: i64, size: u32) -> u32 {
        let n = size as i64;
        match self {
            WrapMode::Repeat => i.rem_euclid(n) as u32,
            WrapMode::ClampToEdge => i.clamp(0, n - 1) as u32,
            WrapMode::MirroredRepeat => {
                let period = i.rem_euclid(2 * n);
                (if period < n {
                    period
                } else {
                    2 * n - 1 - period
                }) as u32
            }
        }
    }
}

/// A decoded texture: `width × height` linear RGB texels, row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub texels: Vec<Vec3>,
    pub wrap_s: WrapMode,
    pub wrap_t: WrapMode,
}

/// A material's use of a texture: which one, and which UV set it reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureRef {
    pub texture: u32,
    /// 0 or 1 (`TEXCOORD_0` or `TEXCOORD_1`).
    pub uv_set: u32,
}

impl Texture {
    /// A texture of one colour (handy for tests).
    pub fn constant(value: Vec3) -> Self {
        Self {
            name: "constant".into(),
            width: 1,
            height: 1,
            texels: vec![value],
            wrap_s: WrapMode::Repeat,
            wrap_t: WrapMode::Repeat,
        }
    }

    fn texel(&self, i: i64, j: i64) -> Vec3 {
        let x = self.wrap_s.fold(i, self.width);
        let y = self.wrap_t.fold(j, self.height);
        self.texels[(y * self.width + x) as usize]
    }

    /// Bilinearly filtered value at `uv`. Non-finite coordinates read texel (0, 0).
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        if self.texels.is_empty() {
            return Vec3::ZERO;
        }
        let uv = if uv.is_finite() { uv } else { Vec2::ZERO };
        // keep the coordinate in a range where f32 → i64 is exact enough
        let x = (uv.x as f64).rem_euclid(1024.0) * self.width as f64 - 0.5;
        let y = (uv.y as f64).rem_euclid(1024.0) * self.height as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = ((x - x0) as f32, (y - y0) as f32);
        let (i, j) = (x0 as i64, y0 as i64);
        let top = self.texel(i, j).lerp(self.texel(i + 1, j), fx);
        let bottom = self.texel(i, j + 1).lerp(self.texel(i + 1, j + 1), fx);
        top.lerp(bottom, fy)
    }

    /// Mean of all texels (used to estimate an emissive texture's power).
    pub fn mean(&self) -> Vec3 {
        if self.texels.is_empty() {
            return Vec3::ZERO;
        }
        let sum = self
            .texels
            .iter()
            .fold(glam::DVec3::ZERO, |acc, t| acc + t.as_dvec3());
        (sum / self.texels.len() as f64).as_vec3()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_modes_fold_indices() {
        assert_eq!(WrapMode::Repeat.fold(-1, 4), 3);
        assert_eq!(WrapMode::Repeat.fold(5, 4), 1);
        assert_eq!(WrapMode::ClampToEdge.fold(-3, 4), 0);
        assert_eq!(WrapMode::ClampToEdge.fold(9, 4), 3);
        assert_eq!(WrapMode::MirroredRepeat.fold(4, 4), 3);
        assert_eq!(WrapMode::MirroredRepeat.fold(-1, 4), 0);
    }

    #[test]
    fn bilinear_reads_texel_centres_and_midpoints() {
        let t = Texture {
            name: "t".into(),
            width: 2,
            height: 1,
            texels: vec![Vec3::ZERO, Vec3::ONE],
            wrap_s: WrapMode::ClampToEdge,
            wrap_t: WrapMode::ClampToEdge,
        };
        assert_eq!(t.sample(Vec2::new(0.25, 0.5)), Vec3::ZERO);
        assert_eq!(t.sample(Vec2::new(0.75, 0.5)), Vec3::ONE);
        assert!((t.sample(Vec2::new(0.5, 0.5)) - Vec3::splat(0.5)).length() < 1e-6);
    }
}
