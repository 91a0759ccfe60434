//! Textures: each image's encoded bytes found (buffer view, data URI or file),
//! its declared size checked against limits before decoding, then decoded once
//! to linear RGB texels with its sampler's wrap modes.

use std::borrow::Cow;
use std::io::Cursor;

use glam::Vec3;
use gltf::buffer::Data as BufferData;
use image::DynamicImage;

use super::build::SceneBuilder;
use super::{Loaded, label};
use crate::scene::texture::srgb_to_linear;
use crate::scene::{Texture, WrapMode};

/// Largest texture width or height accepted.
const MAX_TEXTURE_SIDE: u32 = 16384;

/// Largest number of texels in a texture (8192 × 4096; 384 MiB as linear RGB f32).
const MAX_TEXTURE_TEXELS: u64 = 1 << 25;

/// Texels an encoded image may declare per byte of its encoding: deflate
/// expands at most about 1032:1, and a 1-bit PNG packs 8 pixels in a byte.
/// A header declaring more is lying about the data that follows.
const MAX_TEXELS_PER_ENCODED_BYTE: u64 = 8 * 1032;

/// Texels any encoded image may declare, however small its encoding.
const MIN_TEXEL_ALLOWANCE: u64 = 1 << 16;

fn wrap_mode(mode: gltf::texture::WrappingMode) -> WrapMode {
    match mode {
        gltf::texture::WrappingMode::Repeat => WrapMode::Repeat,
        gltf::texture::WrappingMode::MirroredRepeat => WrapMode::MirroredRepeat,
        gltf::texture::WrappingMode::ClampToEdge => WrapMode::ClampToEdge,
    }
}

/// Decodes a PNG or JPEG (or any format the `image` crate was built with),
/// trusting the bytes' signature over the declared MIME type. The size the
/// header declares is checked before any texel is allocated.
fn decode_image(encoded: &[u8], mime_type: Option<&str>) -> Loaded<DynamicImage> {
    let (width, height) = image_reader(encoded, mime_type)?
        .into_dimensions()
        .map_err(|e| format!("cannot read the header: {e}"))?;
    check_image_size(width, height, encoded.len())?;
    let mut reader = image_reader(encoded, mime_type)?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    // four channels of 32-bit floats is the widest pixel the decoder produces
    limits.max_alloc = Some(MAX_TEXTURE_TEXELS * 16);
    reader.limits(limits);
    let image = reader.decode().map_err(|e| format!("cannot decode: {e}"))?;
    if image.width() == 0 || image.height() == 0 {
        return Err("image is empty".into());
    }
    Ok(image)
}

fn image_reader<'a>(
    encoded: &'a [u8],
    mime_type: Option<&str>,
) -> Loaded<image::ImageReader<Cursor<&'a [u8]>>> {
    let mut reader = image::ImageReader::new(Cursor::new(encoded));
    if let Some(format) = mime_type.and_then(image::ImageFormat::from_mime_type) {
        reader.set_format(format);
    }
    reader
        .with_guessed_format()
        .map_err(|e| format!("cannot read: {e}"))
}

/// Refuses a declared image size that is empty, too large, or more than
/// `encoded_len` bytes of any encoding can describe.
fn check_image_size(width: u32, height: u32, encoded_len: usize) -> Loaded<()> {
    let texels = u64::from(width) * u64::from(height);
    if texels == 0 {
        return Err(format!("image is empty ({width}×{height})"));
    }
    if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE || texels > MAX_TEXTURE_TEXELS {
        return Err(format!(
            "{width}×{height} texels is above the limit ({MAX_TEXTURE_SIDE} per side, \
             {MAX_TEXTURE_TEXELS} in all)"
        ));
    }
    let allowance = (encoded_len as u64)
        .saturating_mul(MAX_TEXELS_PER_ENCODED_BYTE)
        .max(MIN_TEXEL_ALLOWANCE);
    if texels > allowance {
        return Err(format!(
            "the header declares {width}×{height} texels, more than {encoded_len} bytes \
             of encoded data can hold"
        ));
    }
    Ok(())
}

/// Texels as linear RGB, rows top first; 8- and 16-bit values are sRGB-decoded
/// when `srgb`, float values are taken as linear. Alpha is dropped, grey replicated.
fn linear_texels(image: &DynamicImage, srgb: bool) -> Loaded<Vec<Vec3>> {
    let unorm8 = |v: u8| f32::from(v) / 255.0;
    let unorm16 = |v: u16| f32::from(v) / 65535.0;
    let float = |v: f32| if v.is_finite() { v } else { 0.0 };
    Ok(match image {
        DynamicImage::ImageLuma8(i) => to_texels(i.as_raw(), 1, unorm8, srgb),
        DynamicImage::ImageLumaA8(i) => to_texels(i.as_raw(), 2, unorm8, srgb),
        DynamicImage::ImageRgb8(i) => to_texels(i.as_raw(), 3, unorm8, srgb),
        DynamicImage::ImageRgba8(i) => to_texels(i.as_raw(), 4, unorm8, srgb),
        DynamicImage::ImageLuma16(i) => to_texels(i.as_raw(), 1, unorm16, srgb),
        DynamicImage::ImageLumaA16(i) => to_texels(i.as_raw(), 2, unorm16, srgb),
        DynamicImage::ImageRgb16(i) => to_texels(i.as_raw(), 3, unorm16, srgb),
        DynamicImage::ImageRgba16(i) => to_texels(i.as_raw(), 4, unorm16, srgb),
        DynamicImage::ImageRgb32F(i) => to_texels(i.as_raw(), 3, float, false),
        DynamicImage::ImageRgba32F(i) => to_texels(i.as_raw(), 4, float, false),
        other => return Err(format!("unsupported pixel format {:?}", other.color())),
    })
}

fn to_texels<T: Copy>(
    raw: &[T],
    channels: usize,
    to_unit: impl Fn(T) -> f32,
    srgb: bool,
) -> Vec<Vec3> {
    raw.chunks_exact(channels)
        .map(|pixel| {
            let rgb = if channels >= 3 {
                Vec3::new(to_unit(pixel[0]), to_unit(pixel[1]), to_unit(pixel[2]))
            } else {
                Vec3::splat(to_unit(pixel[0]))
            };
            if srgb { rgb.map(srgb_to_linear) } else { rgb }
        })
        .collect()
}

impl<'f> SceneBuilder<'f> {
    /// The scene id of a glTF texture, decoding its image on first use (as an
    /// sRGB colour texture: base colour and emission are the only ones read).
    pub(super) fn texture_id(&mut self, texture: &gltf::Texture<'f>) -> Loaded<u32> {
        if let Some(&id) = self.texture_ids.get(&texture.index()) {
            return Ok(id);
        }
        let image = texture.source();
        let image_label = label("image", image.index(), image.name());
        let decoded = self
            .load_image(image.index())
            .map_err(|problem| format!("{image_label}: {problem}"))?;
        let texels =
            linear_texels(&decoded, true).map_err(|problem| format!("{image_label}: {problem}"))?;
        let sampler = texture.sampler();
        let name = texture
            .name()
            .or(image.name())
            .map_or_else(|| format!("texture {}", texture.index()), String::from);
        self.scene.textures.push(Texture {
            name,
            width: decoded.width(),
            height: decoded.height(),
            texels,
            wrap_s: wrap_mode(sampler.wrap_s()),
            wrap_t: wrap_mode(sampler.wrap_t()),
        });
        let id = (self.scene.textures.len() - 1) as u32;
        self.texture_ids.insert(texture.index(), id);
        Ok(id)
    }

    /// Finds an image's encoded bytes (buffer view, data URI or file) and decodes them.
    fn load_image(&self, index: usize) -> Loaded<DynamicImage> {
        let json = &self.document.as_json().images[index];
        let mime_type = json.mime_type.as_ref().map(|m| m.0.as_str());
        let encoded: Cow<[u8]> = match (&json.buffer_view, &json.uri) {
            (Some(view), _) => {
                let view = self
                    .document
                    .views()
                    .nth(view.value())
                    .ok_or("bufferView does not exist")?;
                let buffer = &self.buffers[view.buffer().index()];
                Cow::Borrowed(&buffer[view.offset()..view.offset() + view.length()])
            }
            (None, Some(uri)) => {
                let source = gltf::buffer::Source::Uri(uri);
                let data = BufferData::from_source(source, self.base_dir)
                    .map_err(|e| format!("cannot read \"{}\": {e}", short_uri(uri)))?;
                Cow::Owned(data.0)
            }
            (None, None) => return Err("has neither a uri nor a bufferView".into()),
        };
        decode_image(&encoded, mime_type)
    }
}

/// A URI for messages: data URIs are cut after their header.
fn short_uri(uri: &str) -> &str {
    if uri.starts_with("data:") {
        uri.split(',').next().unwrap_or(uri)
    } else {
        uri
    }
}
