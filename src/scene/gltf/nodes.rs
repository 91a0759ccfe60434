//! The node graph: checked to be a forest, then walked from the scene's roots
//! composing TRS and matrix transforms, each node's mesh, camera and light
//! added in world space.

use glam::{Affine3A, Mat4, Quat, Vec3, Vec4};
use gltf::Document;
use gltf::scene::Transform;

use super::build::SceneBuilder;
use super::{Loaded, label};

/// Refuses node graphs that are not forests: a node listed as the child of
/// two nodes, or a cycle (which would make a naive walk recurse forever).
pub(super) fn check_node_graph(document: &Document) -> Loaded<()> {
    let nodes = &document.as_json().nodes;
    let node_label = |i: usize| label("node", i, nodes[i].name.as_deref());
    let mut parents: Vec<Option<usize>> = vec![None; nodes.len()];
    for (parent, node) in nodes.iter().enumerate() {
        for child in node.children.iter().flatten().map(|c| c.value()) {
            if let Some(first) = parents[child] {
                return Err(if first == parent {
                    format!(
                        "{} lists {} twice as a child",
                        node_label(parent),
                        node_label(child)
                    )
                } else {
                    format!(
                        "{} is a child of both {} and {} (a node may have only one parent)",
                        node_label(child),
                        node_label(first),
                        node_label(parent)
                    )
                });
            }
            parents[child] = Some(parent);
        }
    }
    if let Some(cycle) = find_parent_cycle(&parents) {
        let names: Vec<String> = cycle.into_iter().map(node_label).collect();
        return Err(format!("node cycle: {}", names.join(" → ")));
    }
    Ok(())
}

/// With at most one parent per node, a cycle is a chain of parents that comes
/// back to itself. Returns it from parent to child, closed (first = last).
fn find_parent_cycle(parents: &[Option<usize>]) -> Option<Vec<usize>> {
    #[derive(Clone, Copy, PartialEq)]
    enum State {
        Unseen,
        OnChain,
        Done,
    }
    let mut states = vec![State::Unseen; parents.len()];
    for start in 0..parents.len() {
        let mut chain = Vec::new();
        let mut at = Some(start);
        while let Some(node) = at {
            match states[node] {
                State::Done => break,
                State::OnChain => {
                    let begin = chain.iter().position(|&n| n == node).unwrap_or(0);
                    let mut cycle: Vec<usize> = chain[begin..].to_vec();
                    cycle.push(node);
                    cycle.reverse();
                    return Some(cycle);
                }
                State::Unseen => {
                    states[node] = State::OnChain;
                    chain.push(node);
                    at = parents[node];
                }
            }
        }
        for node in chain {
            states[node] = State::Done;
        }
    }
    None
}

/// The nodes the walk starts from: the default scene's, else the first
/// scene's, else (a file without scenes) every node without a parent.
pub(super) fn scene_roots(document: &Document) -> Vec<gltf::Node<'_>> {
    if let Some(scene) = document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        return scene.nodes().collect();
    }
    let mut has_parent = vec![false; document.nodes().len()];
    for child in document.nodes().flat_map(|node| node.children()) {
        has_parent[child.index()] = true;
    }
    document
        .nodes()
        .filter(|node| !has_parent[node.index()])
        .collect()
}

/// An affine transform from a glTF (column-major) matrix.
fn affine_from_matrix(columns: [[f32; 4]; 4]) -> Loaded<Affine3A> {
    let matrix = Mat4::from_cols_array_2d(&columns);
    if !matrix.is_finite() {
        return Err("matrix is not finite".into());
    }
    let last_row = matrix.row(3);
    if (last_row - Vec4::W).abs().max_element() > 1e-6 {
        return Err(format!(
            "matrix is not affine (its last row is {last_row}, not 0 0 0 1)"
        ));
    }
    Ok(Affine3A::from_mat4(matrix))
}

/// Refuses world transforms that are not finite or flatten space (det ≈ 0,
/// relative to the lengths of the axes).
fn check_world_transform(world: &Affine3A) -> Loaded<()> {
    if !world.is_finite() {
        return Err("world transform is not finite".into());
    }
    let linear = world.matrix3.as_dmat3();
    let axes_volume = linear.x_axis.length() * linear.y_axis.length() * linear.z_axis.length();
    let determinant = linear.determinant();
    if axes_volume > 0.0 && determinant.abs() > 1e-9 * axes_volume {
        Ok(())
    } else {
        Err(format!(
            "world transform is singular (determinant {determinant:e}): it flattens space"
        ))
    }
}

impl<'f> SceneBuilder<'f> {
    /// Depth-first, parents before children, children in file order; each
    /// node is reached once (`check_node_graph` refused cycles and shared children).
    /// Walks the nodes of the document's scene from its roots.
    pub(super) fn walk_scene(&mut self) -> Loaded<()> {
        self.walk(scene_roots(self.document))
    }

    pub(super) fn walk(&mut self, roots: Vec<gltf::Node<'f>>) -> Loaded<()> {
        let mut reached = vec![false; self.document.nodes().len()];
        let mut pending: Vec<(gltf::Node<'f>, Affine3A)> = roots
            .into_iter()
            .rev()
            .map(|root| (root, Affine3A::IDENTITY))
            .collect();
        while let Some((node, parent_world)) = pending.pop() {
            let node_label = label("node", node.index(), node.name());
            if std::mem::replace(&mut reached[node.index()], true) {
                return Err(format!(
                    "{node_label} is reached twice from the scene's roots \
                     (listed twice, or a root that is also a child)"
                ));
            }
            let world = parent_world * self.local_transform(&node, &node_label)?;
            self.add_node_contents(&node, &world, &node_label)?;
            let children: Vec<gltf::Node<'f>> = node.children().collect();
            pending.extend(children.into_iter().rev().map(|child| (child, world)));
        }
        Ok(())
    }

    fn local_transform(&mut self, node: &gltf::Node, node_label: &str) -> Loaded<Affine3A> {
        match node.transform() {
            Transform::Matrix { matrix } => {
                affine_from_matrix(matrix).map_err(|problem| format!("{node_label}: {problem}"))
            }
            Transform::Decomposed {
                translation,
                rotation,
                scale,
            } => {
                let (translation, scale) = (Vec3::from(translation), Vec3::from(scale));
                let rotation = Quat::from_array(rotation);
                if !translation.is_finite() || !scale.is_finite() || !rotation.is_finite() {
                    return Err(format!(
                        "{node_label}: translation, rotation or scale is not finite"
                    ));
                }
                let rotation = self.unit_rotation(rotation, node_label)?;
                Ok(Affine3A::from_scale_rotation_translation(
                    scale,
                    rotation,
                    translation,
                ))
            }
        }
    }

    /// Normalizes a rotation quaternion, with a warning if it was far from unit length.
    fn unit_rotation(&mut self, rotation: Quat, node_label: &str) -> Loaded<Quat> {
        let length = rotation.length();
        if length < 1e-6 {
            return Err(format!("{node_label}: rotation is a zero quaternion"));
        }
        if (length - 1.0).abs() > 1e-3 {
            self.warn(format!(
                "{node_label}: rotation {rotation} is not a unit quaternion (length {length}); normalized"
            ));
        }
        Ok(rotation / length)
    }

    fn add_node_contents(
        &mut self,
        node: &gltf::Node<'f>,
        world: &Affine3A,
        node_label: &str,
    ) -> Loaded<()> {
        let (mesh, camera, light) = (node.mesh(), node.camera(), node.light());
        if mesh.is_none() && camera.is_none() && light.is_none() {
            return Ok(());
        }
        check_world_transform(world).map_err(|problem| format!("{node_label}: {problem}"))?;
        if let Some(mesh) = mesh {
            if node.skin().is_some() {
                self.warn(format!(
                    "{node_label}: skinning is not supported; the mesh is drawn unskinned"
                ));
            }
            self.add_mesh_instance(node, &mesh, world)?;
        }
        if let Some(camera) = camera {
            self.add_camera(node, &camera, world, node_label)?;
        }
        if let Some(light) = light {
            self.add_light(node, &light, world)?;
        }
        Ok(())
    }
}
