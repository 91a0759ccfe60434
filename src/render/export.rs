//! Image export: linear EXR (radiance as is) and display-referred PNG.
//!
//! Exposure, tonemap and the sRGB transfer are applied here and at display
//! only, never inside the estimator: PNG value = sRGB(tonemap(L · 2^EV)). The
//! viewer's blit shader (`src/app/blit.wgsl`) applies the same formulas.

use std::path::Path;

use glam::Vec3;
use image::{ImageBuffer, Rgb};

use crate::course::color::linear_to_srgb;
use crate::render::display::DisplaySettings;

/// Image file formats lumiere writes, chosen by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// Linear RGB radiance, 32-bit float.
    Exr,
    /// Exposure, then sRGB, 8 bits per channel.
    Png,
}

impl ImageFormat {
    /// The format of `path` by its extension (case-insensitive).
    pub fn from_path(path: &Path) -> Option<Self> {
        let extension = path.extension()?.to_str()?.to_ascii_lowercase();
        match extension.as_str() {
            "exr" => Some(ImageFormat::Exr),
            "png" => Some(ImageFormat::Png),
            _ => None,
        }
    }
}

/// An image that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{}: {problem}", path.display())]
pub struct ExportError {
    pub path: std::path::PathBuf,
    pub problem: String,
}

/// 8-bit sRGB of radiance `pixels` as displayed with `display`.
pub fn to_srgb8(pixels: &[Vec3], display: DisplaySettings) -> Vec<u8> {
    let scale = display.exposure.exp2();
    pixels
        .iter()
        .flat_map(|p| (*p * scale).to_array())
        .map(|c| (linear_to_srgb(display.tonemap.apply(c)) * 255.0 + 0.5) as u8)
        .collect()
}

/// Writes `pixels` (row-major from the top, linear radiance) to `path`,
/// in the format its extension names (`display` applies to PNG only).
pub fn save_image(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Vec3],
    display: DisplaySettings,
) -> Result<(), ExportError> {
    let fail = |problem: String| ExportError {
        path: path.to_path_buf(),
        problem,
    };
    let format = ImageFormat::from_path(path).ok_or_else(|| {
        fail("unknown image format: the file name must end in .exr or .png".into())
    })?;
    let bytes = encode_image(format, width, height, pixels, display).map_err(fail)?;
    std::fs::write(path, bytes).map_err(|e| fail(format!("cannot write: {e}")))
}

/// The bytes of the file [`save_image`] writes, for a download.
pub fn encode_image(
    format: ImageFormat,
    width: u32,
    height: u32,
    pixels: &[Vec3],
    display: DisplaySettings,
) -> Result<Vec<u8>, String> {
    let mismatch = || "image size mismatch".to_string();
    let mut bytes = std::io::Cursor::new(Vec::new());
    let result = match format {
        ImageFormat::Exr => {
            let data: Vec<f32> = pixels.iter().flat_map(|p| p.to_array()).collect();
            let image: ImageBuffer<Rgb<f32>, _> =
                ImageBuffer::from_raw(width, height, data).ok_or_else(mismatch)?;
            image.write_to(&mut bytes, image::ImageFormat::OpenExr)
        }
        ImageFormat::Png => {
            return encode_png(width, height, &to_srgb8(pixels, display)).ok_or_else(mismatch);
        }
    };
    result.map_err(|e| e.to_string())?;
    Ok(bytes.into_inner())
}

/// 8-bit sRGB pixels (RGB, row-major from the top) as a PNG file's bytes;
/// `None` if their number is not `width`×`height`.
pub fn encode_png(width: u32, height: u32, srgb: &[u8]) -> Option<Vec<u8>> {
    let image: ImageBuffer<Rgb<u8>, _> = ImageBuffer::from_raw(width, height, srgb)?;
    let mut bytes = std::io::Cursor::new(Vec::new());
    image
        .write_to(&mut bytes, image::ImageFormat::Png)
        .expect("a PNG encodes in memory");
    Some(bytes.into_inner())
}

/// Reads an EXR written by [`save_image`] back as linear RGB.
pub fn load_exr(path: &Path) -> Result<(u32, u32, Vec<Vec3>), ExportError> {
    let image = image::open(path).map_err(|e| ExportError {
        path: path.to_path_buf(),
        problem: e.to_string(),
    })?;
    let rgb = image.to_rgb32f();
    let pixels = rgb.pixels().map(|p| Vec3::from_array(p.0)).collect();
    Ok((rgb.width(), rgb.height(), pixels))
}
