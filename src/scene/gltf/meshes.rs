//! Mesh primitives: their vertices read and placed in world space (normals by
//! the inverse transpose, windings reversed by mirroring transforms), their
//! triangles assembled from lists, strips and fans, within the scene's limits
//! on size and coordinates.

use std::sync::OnceLock;

use glam::{Affine3A, Mat3, Vec2, Vec3};
use gltf::Document;
use gltf::accessor::{Accessor, DataType, Dimensions};
use gltf::mesh::{Mode, Semantic};

use super::accessors::{is_vec3_of_float, layout_name, read_accessor};
use super::build::SceneBuilder;
use super::nodes::scene_roots;
use super::{Loaded, label};
use crate::platform::memory::memory_ceiling;
use crate::scene::{Object, Triangle, append_vertex_attribute};

/// Largest number of triangles, and of vertices, in a loaded scene (instancing
/// lets a small file describe more geometry than memory holds).
const MAX_SCENE_ELEMENTS: usize = 1 << 26;

/// Heap bytes a triangle takes at the peak of loading a scene and building
/// its BVH: `lumiere bench` measures 296 for a file of positions only, one
/// vertex per triangle (docs/benchmarks.md); an unindexed mesh with normals
/// and two UV sets adds 3 × 28 bytes of vertex data. Rounded up.
const PEAK_BYTES_PER_TRIANGLE: u64 = 512;

/// The most triangles a scene may have, and why: [`MAX_SCENE_ELEMENTS`], and
/// no more than fit with their BVH in the memory a film may take
/// ([`memory_ceiling`]), so that instancing a mesh many times is refused with
/// a message rather than by the allocator.
fn scene_triangle_limit() -> (usize, String) {
    static LIMIT: OnceLock<(usize, String)> = OnceLock::new();
    LIMIT.get_or_init(compute_scene_triangle_limit).clone()
}

fn compute_scene_triangle_limit() -> (usize, String) {
    let (ceiling, reason) = memory_ceiling();
    let by_memory = ceiling / PEAK_BYTES_PER_TRIANGLE;
    if by_memory >= MAX_SCENE_ELEMENTS as u64 {
        return (MAX_SCENE_ELEMENTS, "the loader's limit".to_string());
    }
    let gib = ceiling as f64 / (1u64 << 30) as f64;
    (
        by_memory as usize,
        format!(
            "about {PEAK_BYTES_PER_TRIANGLE} bytes each with the BVH; the limit is {gib:.1} GiB, {reason}"
        ),
    )
}

/// Largest world-space coordinate of a vertex, in metres (about seven light
/// hours): beyond it the BVH builder's surface areas, times triangle counts,
/// overflow f32 and its partitioning fails.
const MAX_COORDINATE: f32 = 1e12;

/// Where a mesh instance goes: its world transform and what derives from it.
struct Placement {
    world: Affine3A,
    /// Inverse transpose of the linear part, scaled to avoid overflow (normals are renormalized).
    normal_matrix: Mat3,
    /// The transform mirrors (negative determinant): triangle windings are reversed.
    mirrored: bool,
}

impl Placement {
    fn new(world: Affine3A) -> Self {
        let linear = world.matrix3.as_dmat3();
        let inverse_transpose = linear.inverse().transpose();
        let largest = inverse_transpose
            .to_cols_array()
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        Self {
            world,
            normal_matrix: (inverse_transpose * (1.0 / largest)).as_mat3(),
            mirrored: linear.determinant() < 0.0,
        }
    }
}

/// One primitive's vertex attributes, in its mesh's local space.
struct PrimitiveVertices {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uv0: Option<Vec<Vec2>>,
    uv1: Option<Vec<Vec2>>,
}

/// Refuses, before any geometry is read, a scene whose placed meshes draw
/// more triangles than [`scene_triangle_limit`] (a small file can place a
/// large mesh many times).
pub(super) fn check_scene_size(document: &Document) -> Loaded<()> {
    let mut reached = vec![false; document.nodes().len()];
    let mut pending = scene_roots(document);
    let mut triangles: u64 = 0;
    while let Some(node) = pending.pop() {
        // the walk reports nodes reached twice; here they are counted once
        if std::mem::replace(&mut reached[node.index()], true) {
            continue;
        }
        if let Some(mesh) = node.mesh() {
            triangles += mesh.primitives().map(|p| drawn_triangles(&p)).sum::<u64>();
        }
        pending.extend(node.children());
    }
    let (limit, why) = scene_triangle_limit();
    if triangles > limit as u64 {
        return Err(format!(
            "the scene places {triangles} triangles, more than {limit} ({why})"
        ));
    }
    Ok(())
}

/// How many triangles a primitive draws, from its index (or vertex) count.
fn drawn_triangles(primitive: &gltf::Primitive) -> u64 {
    let count = primitive
        .indices()
        .or_else(|| primitive.get(&Semantic::Positions))
        .map_or(0, |accessor| accessor.count() as u64);
    match primitive.mode() {
        Mode::Triangles => count / 3,
        Mode::TriangleStrip | Mode::TriangleFan => count.saturating_sub(2),
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => 0,
    }
}

fn draws_triangles(mode: Mode) -> bool {
    matches!(
        mode,
        Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
    )
}

/// Vertex corners of the triangles a primitive of a triangle mode draws, and
/// how many indices were left over (not enough for a last triangle).
fn assemble_triangles(mode: Mode, indices: &[u32]) -> (Vec<[u32; 3]>, usize) {
    let n = indices.len();
    // strips and fans use every index once they have three
    let strip_left_over = if n < 3 { n } else { 0 };
    match mode {
        Mode::Triangles => {
            let triangles = indices
                .chunks_exact(3)
                .map(|c| [c[0], c[1], c[2]])
                .collect();
            (triangles, n % 3)
        }
        // the specification's strip: triangle i is (i, i+1+i%2, i+2-i%2)
        Mode::TriangleStrip => {
            let triangles = (0..n.saturating_sub(2))
                .map(|i| {
                    let odd = i % 2;
                    [indices[i], indices[i + 1 + odd], indices[i + 2 - odd]]
                })
                .collect();
            (triangles, strip_left_over)
        }
        // the specification's fan: triangle i is (i+1, i+2, 0)
        Mode::TriangleFan => {
            let triangles = (0..n.saturating_sub(2))
                .map(|i| [indices[i + 1], indices[i + 2], indices[0]])
                .collect();
            (triangles, strip_left_over)
        }
        Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip => (Vec::new(), n),
    }
}

/// Whether the vertex normals of triangle (a, b, c) all lie along its face
/// normal (either way, to 10⁻⁶ in cosine): a flat face, whose shading normal
/// is the face normal, so nothing is interpolated per hit. Degenerate
/// triangles have no face normal and keep their vertex normals.
fn normals_are_the_face_normal(a: Vec3, b: Vec3, c: Vec3, normals: [Vec3; 3]) -> bool {
    let face = (b - a).cross(c - a).normalize_or_zero();
    face != Vec3::ZERO && normals.iter().all(|n| n.dot(face).abs() >= 1.0 - 1e-6)
}

fn is_degenerate(a: Vec3, b: Vec3, c: Vec3) -> bool {
    (b - a).cross(c - a).length_squared() == 0.0
}

fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Points => "POINTS",
        Mode::Lines => "LINES",
        Mode::LineLoop => "LINE_LOOP",
        Mode::LineStrip => "LINE_STRIP",
        Mode::Triangles => "TRIANGLES",
        Mode::TriangleStrip => "TRIANGLE_STRIP",
        Mode::TriangleFan => "TRIANGLE_FAN",
    }
}

impl<'f> SceneBuilder<'f> {
    pub(super) fn add_mesh_instance(
        &mut self,
        node: &gltf::Node,
        mesh: &gltf::Mesh<'f>,
        world: &Affine3A,
    ) -> Loaded<()> {
        self.placed_meshes[mesh.index()] = true;
        let placement = Placement::new(*world);
        let object_name = node
            .name()
            .or(mesh.name())
            .map_or_else(|| format!("mesh {}", mesh.index()), String::from);
        for primitive in mesh.primitives() {
            let primitive_label = format!(
                "{} primitive {}",
                label("mesh", mesh.index(), mesh.name()),
                primitive.index()
            );
            self.add_primitive(&primitive, &placement, &object_name, &primitive_label)?;
        }
        Ok(())
    }

    fn add_primitive(
        &mut self,
        primitive: &gltf::Primitive<'f>,
        placement: &Placement,
        object_name: &str,
        primitive_label: &str,
    ) -> Loaded<()> {
        let mode = primitive.mode();
        if !draws_triangles(mode) {
            self.warn(format!(
                "{primitive_label}: mode {} is not supported (triangles only); skipped",
                mode_name(mode)
            ));
            return Ok(());
        }
        if primitive.morph_targets().next().is_some() {
            self.warn(format!("{primitive_label}: morph targets ignored"));
        }
        let vertices = self.read_vertices(primitive, primitive_label)?;
        let indices = self.read_indices(primitive, vertices.positions.len(), primitive_label)?;
        let (triangles, left_over) = assemble_triangles(mode, &indices);
        if left_over > 0 {
            self.warn(format!(
                "{primitive_label}: {left_over} trailing index(es) do not make a whole triangle; ignored"
            ));
        }
        if triangles.is_empty() {
            self.warn(format!("{primitive_label}: no triangle; skipped"));
            return Ok(());
        }
        let (max_triangles, why) = scene_triangle_limit();
        if self.scene.triangles.len() + triangles.len() > max_triangles {
            return Err(format!(
                "{primitive_label}: the scene would have more than {max_triangles} triangles ({why})"
            ));
        }
        let material = self.material_id(primitive.material())?;
        let (first_vertex, smooth_vertices) =
            self.append_vertices(&vertices, placement, primitive_label)?;
        let first_triangle = self.scene.triangles.len() as u32;
        for corners in &triangles {
            let corners = if placement.mirrored {
                [corners[0], corners[2], corners[1]]
            } else {
                *corners
            };
            self.append_triangle(corners, first_vertex, &smooth_vertices, material);
        }
        self.scene.objects.push(Object {
            name: object_name.to_string(),
            material,
            triangles: first_triangle..self.scene.triangles.len() as u32,
        });
        Ok(())
    }

    fn read_vertices(
        &mut self,
        primitive: &gltf::Primitive,
        primitive_label: &str,
    ) -> Loaded<PrimitiveVertices> {
        let positions = primitive
            .get(&Semantic::Positions)
            .ok_or_else(|| format!("{primitive_label}: no POSITION attribute"))?;
        if !is_vec3_of_float(&positions) {
            return Err(format!(
                "{primitive_label}: POSITION accessor {} is {}, not VEC3 of FLOAT",
                positions.index(),
                layout_name(&positions)
            ));
        }
        let positions: Vec<Vec3> = read_accessor::<[f32; 3]>(&positions, self.buffers)?
            .into_iter()
            .map(Vec3::from)
            .collect();
        let count = positions.len();
        Ok(PrimitiveVertices {
            normals: self.read_normals(primitive, count, primitive_label)?,
            uv0: self.read_tex_coords(primitive, 0, count, primitive_label)?,
            uv1: self.read_tex_coords(primitive, 1, count, primitive_label)?,
            positions,
        })
    }

    fn read_normals(
        &mut self,
        primitive: &gltf::Primitive,
        count: usize,
        primitive_label: &str,
    ) -> Loaded<Option<Vec<Vec3>>> {
        let Some(accessor) = primitive.get(&Semantic::Normals) else {
            return Ok(None);
        };
        if !is_vec3_of_float(&accessor) {
            self.warn(format!(
                "{primitive_label}: NORMAL accessor {} is {}, not VEC3 of FLOAT; normals ignored",
                accessor.index(),
                layout_name(&accessor)
            ));
            return Ok(None);
        }
        check_attribute_count(&accessor, count, "NORMAL", primitive_label)?;
        let normals: Vec<Vec3> = read_accessor::<[f32; 3]>(&accessor, self.buffers)?
            .into_iter()
            .map(Vec3::from)
            .collect();
        check_finite(&normals, |n| n.is_finite(), "NORMAL", primitive_label)?;
        Ok(Some(normals))
    }

    /// `TEXCOORD_<set>` as floats (normalized integers divided out); `None`
    /// when absent or unreadable (the scene then reads zeros).
    fn read_tex_coords(
        &mut self,
        primitive: &gltf::Primitive,
        set: u32,
        count: usize,
        primitive_label: &str,
    ) -> Loaded<Option<Vec<Vec2>>> {
        let Some(accessor) = primitive.get(&Semantic::TexCoords(set)) else {
            return Ok(None);
        };
        let name = format!("TEXCOORD_{set}");
        check_attribute_count(&accessor, count, &name, primitive_label)?;
        let buffers = self.buffers;
        let uvs: Vec<Vec2> = match (accessor.dimensions(), accessor.data_type()) {
            (Dimensions::Vec2, DataType::F32) => read_accessor::<[f32; 2]>(&accessor, buffers)?
                .into_iter()
                .map(Vec2::from)
                .collect(),
            (Dimensions::Vec2, DataType::U8) => read_accessor::<[u8; 2]>(&accessor, buffers)?
                .into_iter()
                .map(|[u, v]| Vec2::new(u.into(), v.into()) / 255.0)
                .collect(),
            (Dimensions::Vec2, DataType::U16) => read_accessor::<[u16; 2]>(&accessor, buffers)?
                .into_iter()
                .map(|[u, v]| Vec2::new(u.into(), v.into()) / 65535.0)
                .collect(),
            _ => {
                self.warn(format!(
                    "{primitive_label}: {name} accessor {} is {}, not VEC2 of FLOAT, \
                     UNSIGNED_BYTE or UNSIGNED_SHORT; zeros used",
                    accessor.index(),
                    layout_name(&accessor)
                ));
                return Ok(None);
            }
        };
        check_finite(&uvs, |uv| uv.is_finite(), &name, primitive_label)?;
        Ok(Some(uvs))
    }

    /// The primitive's indices (0, 1, 2, … without an index accessor), each
    /// checked against the vertex count.
    fn read_indices(
        &self,
        primitive: &gltf::Primitive,
        vertex_count: usize,
        primitive_label: &str,
    ) -> Loaded<Vec<u32>> {
        let Some(accessor) = primitive.indices() else {
            return Ok((0..vertex_count as u32).collect());
        };
        // the crate reaches `unreachable!()` for any other index layout
        let indices: Vec<u32> = match (accessor.dimensions(), accessor.data_type()) {
            (Dimensions::Scalar, DataType::U8) => {
                widen(read_accessor::<u8>(&accessor, self.buffers)?)
            }
            (Dimensions::Scalar, DataType::U16) => {
                widen(read_accessor::<u16>(&accessor, self.buffers)?)
            }
            (Dimensions::Scalar, DataType::U32) => read_accessor::<u32>(&accessor, self.buffers)?,
            _ => {
                return Err(format!(
                    "{primitive_label}: index accessor {} is {}; indices must be SCALAR of \
                     UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT",
                    accessor.index(),
                    layout_name(&accessor)
                ));
            }
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= vertex_count) {
            return Err(format!(
                "{primitive_label}: index {bad} out of range ({vertex_count} vertices)"
            ));
        }
        Ok(indices)
    }

    /// Appends the primitive's vertices in world space; returns the id of the
    /// first one and, per vertex, whether it has a usable shading normal.
    fn append_vertices(
        &mut self,
        vertices: &PrimitiveVertices,
        placement: &Placement,
        primitive_label: &str,
    ) -> Loaded<(u32, Vec<bool>)> {
        let first = self.scene.positions.len();
        if first + vertices.positions.len() > MAX_SCENE_ELEMENTS {
            return Err(format!(
                "{primitive_label}: the scene would have more than {MAX_SCENE_ELEMENTS} vertices"
            ));
        }
        for (i, &local) in vertices.positions.iter().enumerate() {
            let world = placement.world.transform_point3(local);
            if !world.is_finite() {
                return Err(format!(
                    "{primitive_label}: vertex {i} position {local} is not finite in world space"
                ));
            }
            let extent = world.abs().max_element();
            if extent > MAX_COORDINATE {
                return Err(format!(
                    "{primitive_label}: vertex {i} has a world-space coordinate of {extent:.3e} m, \
                     beyond ±{MAX_COORDINATE:e} m"
                ));
            }
            self.scene.positions.push(world);
        }
        let count = vertices.positions.len();
        // a normal that vanishes (zero, or crushed by the transform) is no
        // shading normal: its vertex is not smooth and stores +Z
        let mut smooth = vec![false; count];
        let world_normals: Option<Vec<Vec3>> = vertices.normals.as_ref().map(|normals| {
            let world = |(i, &local): (usize, &Vec3)| {
                let n = (placement.normal_matrix * local).normalize_or_zero();
                smooth[i] = n != Vec3::ZERO;
                if smooth[i] { n } else { Vec3::Z }
            };
            normals.iter().enumerate().map(world).collect()
        });
        let scene = &mut self.scene;
        let normals = world_normals.as_deref();
        append_vertex_attribute(&mut scene.normals, normals, first, count, Vec3::Z);
        let (uv0, uv1) = (vertices.uv0.as_deref(), vertices.uv1.as_deref());
        append_vertex_attribute(&mut scene.uv0, uv0, first, count, Vec2::ZERO);
        append_vertex_attribute(&mut scene.uv1, uv1, first, count, Vec2::ZERO);
        Ok((first as u32, smooth))
    }

    fn append_triangle(
        &mut self,
        corners: [u32; 3],
        first_vertex: u32,
        smooth_vertices: &[bool],
        material: u32,
    ) {
        let vertices = corners.map(|corner| first_vertex + corner);
        let [a, b, c] = vertices.map(|v| self.scene.positions[v as usize]);
        if is_degenerate(a, b, c) {
            self.degenerate_triangles += 1;
        }
        let has_normals = corners
            .iter()
            .all(|&corner| smooth_vertices[corner as usize]);
        let smooth = has_normals && {
            let normals = vertices.map(|v| self.scene.normals[v as usize]);
            !normals_are_the_face_normal(a, b, c, normals)
        };
        self.scene.triangles.push(Triangle {
            vertices,
            material,
            smooth,
        });
    }
}

fn check_attribute_count(
    accessor: &Accessor,
    vertex_count: usize,
    attribute: &str,
    primitive_label: &str,
) -> Loaded<()> {
    if accessor.count() == vertex_count {
        Ok(())
    } else {
        Err(format!(
            "{primitive_label}: {attribute} has {} elements but POSITION has {vertex_count}",
            accessor.count()
        ))
    }
}

/// Refuses an attribute with a NaN or infinite component, naming the first such vertex.
fn check_finite<V: std::fmt::Display>(
    values: &[V],
    is_finite: impl Fn(&V) -> bool,
    attribute: &str,
    primitive_label: &str,
) -> Loaded<()> {
    match values.iter().position(|v| !is_finite(v)) {
        None => Ok(()),
        Some(i) => Err(format!(
            "{primitive_label}: vertex {i} {attribute} {} is not finite",
            values[i]
        )),
    }
}

fn widen<T: Into<u32>>(indices: Vec<T>) -> Vec<u32> {
    indices.into_iter().map(Into::into).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_normals_along_the_face_normal_make_a_flat_triangle() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        assert!(normals_are_the_face_normal(a, b, c, [Vec3::Z; 3]));
        // either way round: the shading frame faces the ray regardless
        assert!(normals_are_the_face_normal(a, b, c, [Vec3::NEG_Z; 3]));
        // a normal tilted by a degree is a curved surface's
        let tilted = Vec3::new(1f32.to_radians().sin(), 0.0, 1f32.to_radians().cos());
        assert!(!normals_are_the_face_normal(
            a,
            b,
            c,
            [Vec3::Z, tilted, Vec3::Z]
        ));
        // a degenerate triangle has no face normal to compare with
        assert!(!normals_are_the_face_normal(a, b, 2.0 * b, [Vec3::Z; 3]));
    }
}
