//! How load, build, memory and tracing scale with triangles, pixels and threads.
//!
//! The procedural scene is a UV sphere of about N triangles over a floor,
//! under a quad light: N changes only the sphere's tessellation, so the
//! image (and the number of rays per sample) stays the same and Mrays/s
//! shows the cost of depth in the BVH alone. The same scene, written as a
//! glTF file with its binary buffer ([`write_gltf`]), is loaded through the
//! real loader to time the whole path from disk.
//!
//! Memory is the heap growth counted by the binary's global allocator
//! ([`super::memory`]) over load + build: the peak (transient buffers
//! included) and what stays held by the scene, its BVH and its lights, each
//! divided by the triangle count. Without the counting allocator (in the
//! tests) the memory columns are empty.

use std::fmt;
use std::path::Path;
use std::sync::Arc;

use glam::Vec3;
use serde::Serialize;
use serde_json::json;

use crate::course::RenderSettings;
use crate::platform::time::Instant;
use crate::render::{Budget, render};
use crate::scene::{Material, Scene, builtin, gltf};
use crate::transport::splitting::choose_continuations;
use crate::{Film, RenderContext};

use super::csv::{Decimals, csv_text};
use super::memory::{MemoryUse, measure};
use super::throughput::{fastest_replay, recorded_rays};
use super::{BenchError, Progress, thread_pool};

/// What a scaling row varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// Triangles of the procedural scene, built in memory.
    Triangles,
    /// Triangles of the procedural scene, loaded from a glTF file.
    GltfTriangles,
    /// Pixels of the bench scene.
    Resolution,
    /// Worker threads on the bench scene.
    Threads,
}

impl Axis {
    pub fn label(self) -> &'static str {
        match self {
            Axis::Triangles => "triangles",
            Axis::GltfTriangles => "gltf-triangles",
            Axis::Resolution => "resolution",
            Axis::Threads => "threads",
        }
    }
}

impl fmt::Display for Axis {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.label())
    }
}

/// What the scaling section measures.
#[derive(Clone, Debug)]
pub struct ScalingBench {
    /// Triangle counts of the procedural scene.
    pub triangle_counts: Vec<u64>,
    /// Triangles of the glTF file (0: no glTF row).
    pub gltf_triangles: u64,
    /// Square image sizes for the resolution rows.
    pub resolutions: Vec<u32>,
    /// Thread counts for the thread rows.
    pub thread_counts: Vec<usize>,
    /// Size of the images of the triangle rows.
    pub triangle_image_size: u32,
    /// Samples per pixel of every timed render.
    pub spp: u32,
    /// Timed runs of each triangle row's render and replay; the fastest counts.
    pub repeats: u32,
    /// Terms, light sampling, … of every render (size replaced per row).
    pub settings: RenderSettings,
}

/// One measured configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalingRow {
    pub axis: Axis,
    pub triangles: u64,
    pub width: u32,
    pub height: u32,
    pub threads: usize,
    /// Generating or parsing the scene.
    pub load_seconds: f64,
    /// Lights and BVH.
    pub build_seconds: f64,
    pub memory: Option<MemoryUse>,
    pub spp: u32,
    pub render_seconds: f64,
    pub rays: u64,
    /// The same rays traced again by the BVH alone (the throughput
    /// section's replay), for the triangle rows.
    pub traversal_seconds: Option<f64>,
}

impl ScalingRow {
    pub fn mrays_per_second(&self) -> f64 {
        self.rays as f64 / self.render_seconds.max(1e-12) / 1e6
    }

    /// Renderer rays/s ÷ traversal rays/s of the same rays, if replayed.
    pub fn traversal_ratio(&self) -> Option<f64> {
        self.traversal_seconds
            .map(|t| t / self.render_seconds.max(1e-12))
    }

    pub fn seconds_per_spp(&self) -> f64 {
        self.render_seconds / self.spp.max(1) as f64
    }

    /// (peak, retained) heap bytes per triangle.
    pub fn bytes_per_triangle(&self) -> Option<(f64, f64)> {
        let m = self.memory?;
        let n = self.triangles.max(1) as f64;
        Some((m.peak_bytes as f64 / n, m.retained_bytes as f64 / n))
    }
}

/// The header of the scaling CSV, in order.
pub const SCALING_COLUMNS: [&str; 13] = [
    "axis",
    "triangles",
    "width",
    "height",
    "threads",
    "load_seconds",
    "build_seconds",
    "peak_bytes_per_triangle",
    "retained_bytes_per_triangle",
    "spp",
    "seconds_per_spp",
    "mrays_per_second",
    "renderer_over_traversal",
];

/// One line of the scaling CSV: a [`ScalingRow`] with its derived figures.
#[derive(Serialize)]
struct ScalingRecord {
    axis: &'static str,
    triangles: u64,
    width: u32,
    height: u32,
    threads: usize,
    load_seconds: Decimals<6>,
    build_seconds: Decimals<6>,
    peak_bytes_per_triangle: Option<Decimals<1>>,
    retained_bytes_per_triangle: Option<Decimals<1>>,
    spp: u32,
    seconds_per_spp: Decimals<6>,
    mrays_per_second: Decimals<3>,
    renderer_over_traversal: Option<Decimals<3>>,
}

impl From<&ScalingRow> for ScalingRecord {
    fn from(r: &ScalingRow) -> Self {
        let bytes = r.bytes_per_triangle();
        Self {
            axis: r.axis.label(),
            triangles: r.triangles,
            width: r.width,
            height: r.height,
            threads: r.threads,
            load_seconds: Decimals(r.load_seconds),
            build_seconds: Decimals(r.build_seconds),
            peak_bytes_per_triangle: bytes.map(|(peak, _)| Decimals(peak)),
            retained_bytes_per_triangle: bytes.map(|(_, retained)| Decimals(retained)),
            spp: r.spp,
            seconds_per_spp: Decimals(r.seconds_per_spp()),
            mrays_per_second: Decimals(r.mrays_per_second()),
            renderer_over_traversal: r.traversal_ratio().map(Decimals),
        }
    }
}

/// The scaling CSV text (memory columns empty when not measured, the
/// traversal ratio empty when the rays were not replayed).
pub fn scaling_csv(rows: &[ScalingRow]) -> String {
    csv_text(&SCALING_COLUMNS, rows.iter().map(ScalingRecord::from))
}

/// The procedural scene: a sphere of about `triangles` triangles on a floor, under a quad light.
pub fn procedural_scene(triangles: u64) -> Scene {
    let mut scene = Scene {
        name: format!("sphere of {triangles} triangles"),
        ..Scene::default()
    };
    // a UV sphere of r rings and 2r segments has 4r² − 4r triangles
    let rings = ((triangles as f64 / 4.0).sqrt().ceil() as u32).max(2);
    let (positions, sphere) =
        builtin::uv_sphere(Vec3::new(0.0, 1.0, 0.0), 1.0, 2 * rings, rings, false);
    let grey = scene.add_material(Material::lambert("grey", Vec3::splat(0.6)));
    scene.add_mesh("sphere", grey, &positions, &sphere);
    let quad = |y: f32, half: f32, facing_down: bool| {
        let corners = [
            Vec3::new(-half, y, -half),
            Vec3::new(half, y, -half),
            Vec3::new(half, y, half),
            Vec3::new(-half, y, half),
        ];
        let triangles = if facing_down {
            vec![[0, 1, 2], [0, 2, 3]]
        } else {
            vec![[0, 2, 1], [0, 3, 2]]
        };
        (corners, triangles)
    };
    let (floor, floor_triangles) = quad(0.0, 4.0, false);
    scene.add_mesh("floor", grey, &floor, &floor_triangles);
    let light = scene.add_material(Material::emitter("light", Vec3::splat(8.0)));
    let (lamp, lamp_triangles) = quad(3.5, 0.75, true);
    scene.add_mesh("light", light, &lamp, &lamp_triangles);
    scene
}

/// Writes `scene`'s triangles and materials (base colour, emission) as
/// `path` (glTF JSON) and `path` with extension `.bin` (its buffer): one
/// mesh primitive per material, flat-shaded, no camera.
pub fn write_gltf(scene: &Scene, path: &Path) -> Result<(), BenchError> {
    let bin_path = path.with_extension("bin");
    let bin_name = bin_path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let mut buffer: Vec<u8> =
        Vec::with_capacity(scene.positions.len() * 12 + scene.triangles.len() * 12);
    let (mut min, mut max) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for p in &scene.positions {
        min = min.min(*p);
        max = max.max(*p);
        for c in p.to_array() {
            buffer.extend_from_slice(&c.to_le_bytes());
        }
    }
    let positions_length = buffer.len();
    let mut views = vec![
        json!({"buffer": 0, "byteOffset": 0, "byteLength": positions_length, "target": 34962}),
    ];
    let mut accessors = vec![json!({
        "bufferView": 0, "componentType": 5126, "count": scene.positions.len(), "type": "VEC3",
        "min": min.to_array(), "max": max.to_array()
    })];
    let mut primitives = Vec::new();
    for material in 0..scene.materials.len() as u32 {
        let offset = buffer.len();
        let mut count = 0;
        for t in scene.triangles.iter().filter(|t| t.material == material) {
            for v in t.vertices {
                buffer.extend_from_slice(&v.to_le_bytes());
            }
            count += 3;
        }
        if count == 0 {
            continue;
        }
        views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": buffer.len() - offset, "target": 34963}));
        accessors.push(json!({"bufferView": views.len() - 1, "componentType": 5125, "count": count, "type": "SCALAR"}));
        primitives.push(json!({"attributes": {"POSITION": 0}, "indices": accessors.len() - 1, "material": material}));
    }
    let materials: Vec<_> = scene
        .materials
        .iter()
        .map(|m| {
            let strength = m.emission.max_element().max(1.0);
            let mut material = json!({
                "name": m.name,
                "pbrMetallicRoughness": {
                    "baseColorFactor": [m.base_color.x, m.base_color.y, m.base_color.z, 1.0],
                    "metallicFactor": m.metallic, "roughnessFactor": m.roughness
                },
                "emissiveFactor": (m.emission / strength).to_array(),
            });
            if strength > 1.0 {
                material["extensions"] =
                    json!({"KHR_materials_emissive_strength": {"emissiveStrength": strength}});
            }
            material
        })
        .collect();
    let document = json!({
        "asset": {"version": "2.0", "generator": "lumiere bench"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": primitives}],
        "materials": materials,
        "buffers": [{"uri": bin_name, "byteLength": buffer.len()}],
        "bufferViews": views,
        "accessors": accessors,
    });
    std::fs::write(&bin_path, &buffer)
        .map_err(|e| BenchError::file(&bin_path, format!("cannot write: {e}")))?;
    let text = serde_json::to_string(&document).map_err(|e| BenchError::file(path, e))?;
    std::fs::write(path, text).map_err(|e| BenchError::file(path, format!("cannot write: {e}")))
}

/// Renders `spp` passes of `context`: (seconds, rays).
fn time_render(context: &RenderContext, spp: u32) -> (f64, u64) {
    let mut film = Film::new(context.settings.width, context.settings.height);
    let stats = render(context, &mut film, Budget::Samples(spp), |_| {});
    (stats.elapsed.as_secs_f64(), stats.rays.total())
}

/// The fastest of `repeats` [`time_render`]s.
fn fastest_render(context: &RenderContext, spp: u32, repeats: u32) -> (f64, u64) {
    (0..repeats.max(1))
        .map(|_| time_render(context, spp))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap_or_default()
}

fn sized(settings: &RenderSettings, width: u32, height: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        ..settings.clone()
    }
}

/// Loads (with `load`) and builds a scene, timing both and measuring the
/// heap, then renders it at the triangle rows' size.
fn triangle_row(
    bench: &ScalingBench,
    axis: Axis,
    load: impl FnOnce() -> Result<Scene, BenchError>,
) -> Result<ScalingRow, BenchError> {
    let size = bench.triangle_image_size;
    let settings = sized(&bench.settings, size, size);
    let (built, memory) = measure(|| -> Result<_, BenchError> {
        let start = Instant::now();
        let scene = load()?;
        let loaded = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let mut context = RenderContext::new(Arc::new(scene), settings.clone());
        choose_continuations(&mut context);
        Ok((context, loaded, start.elapsed().as_secs_f64()))
    });
    let (context, load_seconds, build_seconds) = built?;
    let (render_seconds, rays) = fastest_render(&context, bench.spp, bench.repeats);
    let replayed = recorded_rays(&context, bench.spp);
    let traversal_seconds = fastest_replay(&context.accel, &replayed, bench.repeats).as_secs_f64();
    Ok(ScalingRow {
        axis,
        triangles: context.scene.triangles.len() as u64,
        width: size,
        height: size,
        threads: rayon::current_num_threads(),
        load_seconds,
        build_seconds,
        memory,
        spp: bench.spp,
        render_seconds,
        rays,
        traversal_seconds: Some(traversal_seconds),
    })
}

/// Every row of `bench`: procedural triangle counts, the glTF file (written
/// into `folder`, removed after), then `scene` at each resolution and
/// thread count.
pub fn measure_scaling(
    bench: &ScalingBench,
    scene: &Arc<Scene>,
    folder: &Path,
    progress: &dyn Progress,
) -> Result<Vec<ScalingRow>, BenchError> {
    let mut rows = Vec::new();
    for &n in &bench.triangle_counts {
        progress.message(&format!("scaling: procedural scene of {n} triangles"));
        rows.push(triangle_row(bench, Axis::Triangles, || {
            Ok(procedural_scene(n))
        })?);
    }
    if bench.gltf_triangles > 0 {
        let n = bench.gltf_triangles;
        progress.message(&format!("scaling: writing a glTF of {n} triangles"));
        let path = folder.join(format!("scaling-{n}.gltf"));
        write_gltf(&procedural_scene(n), &path)?;
        progress.message(&format!("scaling: loading the glTF of {n} triangles"));
        let row = triangle_row(bench, Axis::GltfTriangles, || Ok(gltf::load(&path)?));
        // the files are large and rewritten at every run
        let _ = std::fs::remove_file(path.with_extension("bin"));
        let _ = std::fs::remove_file(&path);
        rows.push(row?);
    }
    let scene_row = |axis: Axis, size: u32, threads: usize| -> Result<ScalingRow, BenchError> {
        let pool = thread_pool(threads)?;
        let settings = sized(&bench.settings, size, size);
        let start = Instant::now();
        let mut context = RenderContext::new(scene.clone(), settings);
        choose_continuations(&mut context);
        let build_seconds = start.elapsed().as_secs_f64();
        let (render_seconds, rays) = pool.install(|| time_render(&context, bench.spp));
        Ok(ScalingRow {
            axis,
            triangles: scene.triangles.len() as u64,
            width: size,
            height: size,
            threads: pool.current_num_threads(),
            load_seconds: 0.0,
            build_seconds,
            memory: None,
            spp: bench.spp,
            render_seconds,
            rays,
            traversal_seconds: None,
        })
    };
    for &size in &bench.resolutions {
        progress.message(&format!("scaling: {size}×{size}"));
        rows.push(scene_row(
            Axis::Resolution,
            size,
            rayon::current_num_threads(),
        )?);
    }
    for &threads in &bench.thread_counts {
        progress.message(&format!("scaling: {threads} thread(s)"));
        let size = bench
            .resolutions
            .get(1)
            .or(bench.resolutions.first())
            .copied()
            .unwrap_or(256);
        rows.push(scene_row(Axis::Threads, size, threads)?);
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tools::bench::csv::field_names;

    #[test]
    fn scaling_rows_are_written_under_their_columns() {
        let row = ScalingRow {
            axis: Axis::GltfTriangles,
            triangles: 2000,
            width: 16,
            height: 24,
            threads: 2,
            load_seconds: 0.25,
            build_seconds: 0.125,
            memory: Some(MemoryUse {
                peak_bytes: 300_000,
                retained_bytes: 100_000,
            }),
            spp: 4,
            render_seconds: 0.5,
            rays: 1_000_000,
            traversal_seconds: Some(0.25),
        };
        let unmeasured = ScalingRow {
            axis: Axis::Threads,
            memory: None,
            traversal_seconds: None,
            ..row.clone()
        };
        let text = scaling_csv(&[row.clone(), unmeasured]);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], SCALING_COLUMNS.join(","));
        assert_eq!(
            lines[1],
            "gltf-triangles,2000,16,24,2,0.250000,0.125000,150.0,50.0,4,0.125000,2.000,0.500"
        );
        assert_eq!(
            lines[2],
            "threads,2000,16,24,2,0.250000,0.125000,,,4,0.125000,2.000,"
        );
        assert_eq!(lines.len(), 3);
        assert_eq!(field_names(ScalingRecord::from(&row)), lines[0]);
    }
}
