// Blit of the film's radiance to the screen: exposure, tonemap, sRGB.
// The same formulas as `Tonemap::apply` and `color::linear_to_srgb` (PNG export).
// A false-colour image (noise views) is already display colour: only sRGB.

struct Params {
    // 2^exposure
    scale: f32,
    // 0 none (clamp), 1 Reinhard, 2 ACES (Narkowicz)
    tonemap: u32,
    // 1 when the target is not an sRGB format and the shader must encode
    encode_srgb: u32,
    // 1 for a false-colour image: no exposure, no tonemap
    false_colour: u32,
};

@group(0) @binding(0) var image: texture_2d<f32>;
@group(0) @binding(1) var<uniform> params: Params;

struct VertexOut {
    @builtin(position) position: vec4<f32>,
    // 0..1 across the image rectangle, v downwards
    @location(0) uv: vec2<f32>,
};

// One triangle that covers the viewport (the paint callback's rectangle).
@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> VertexOut {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    var out: VertexOut;
    out.position = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
    out.uv = uv;
    return out;
}

fn tonemap(c: f32) -> f32 {
    let x = max(c, 0.0);
    var mapped = x;
    if params.tonemap == 1u {
        mapped = x / (1.0 + x);
    } else if params.tonemap == 2u {
        mapped = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
    }
    return clamp(mapped, 0.0, 1.0);
}

fn srgb(c: f32) -> f32 {
    if c <= 0.0031308 {
        return c * 12.92;
    }
    return 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let size = vec2<f32>(textureDimensions(image));
    // nearest neighbour: each film pixel is a crisp square when zoomed
    let texel = vec2<i32>(clamp(floor(in.uv * size), vec2<f32>(0.0), size - 1.0));
    let texel_value = textureLoad(image, texel, 0).rgb;
    var color = clamp(texel_value, vec3<f32>(0.0), vec3<f32>(1.0));
    if params.false_colour == 0u {
        let radiance = texel_value * params.scale;
        color = vec3<f32>(tonemap(radiance.r), tonemap(radiance.g), tonemap(radiance.b));
    }
    if params.encode_srgb == 1u {
        color = vec3<f32>(srgb(color.r), srgb(color.g), srgb(color.b));
    }
    return vec4<f32>(color, 1.0);
}
