//! Built-in scenes: the Cornell box (embedded glTF) and analytic test scenes
//! whose answers are known in closed form.

use std::path::Path;

use glam::{Affine3A, Vec3};

use super::{Camera, Material, Projection, PunctualKind, PunctualLight, Scene};
use crate::scene::error::SceneError;

/// The Cornell box from the published measurements, in metres.
pub const CORNELL_GLTF: &[u8] = include_bytes!("../../assets/cornell-box.gltf");

/// A scene built into lumiere (`assets/`), loadable by name.
pub struct BuiltinScene {
    pub name: &'static str,
    /// What it shows, in one line.
    pub description: &'static str,
    gltf: &'static [u8],
}

/// The scene library: the Cornell box and its variants, and one scene per
/// lesson (`assets/scenes/README.md` says how each was made and its licence).
pub const SCENES: [BuiltinScene; 9] = [
    BuiltinScene {
        name: "cornell",
        description: "the Cornell box: an area light in the ceiling, a red and a green wall, two white blocks",
        gltf: CORNELL_GLTF,
    },
    BuiltinScene {
        name: "cornell-point",
        description: "the Cornell box under a point light of the same power: hard shadows",
        gltf: include_bytes!("../../assets/scenes/cornell-point.gltf"),
    },
    BuiltinScene {
        name: "cornell-spot",
        description: "the Cornell box under a spot light pointing down: a cone of light",
        gltf: include_bytes!("../../assets/scenes/cornell-spot.gltf"),
    },
    BuiltinScene {
        name: "cornell-mirror",
        description: "the Cornell box with a mirror tall block",
        gltf: include_bytes!("../../assets/scenes/cornell-mirror.gltf"),
    },
    BuiltinScene {
        name: "cornell-glass",
        description: "the Cornell box with a clear glass tall block (η = 1.5): the box seen through it is L3, its caustic on the floor L3 and beyond",
        gltf: include_bytes!("../../assets/scenes/cornell-glass.gltf"),
    },
    BuiltinScene {
        name: "cornell-glossy",
        description: "the Cornell box with a glossy floor and a glossy metal block (Phong)",
        gltf: include_bytes!("../../assets/scenes/cornell-glossy.gltf"),
    },
    BuiltinScene {
        name: "veach-mis",
        description: "four glossy plates, sharp to rough, under four lights of equal power, small to large: light against BRDF sampling",
        gltf: include_bytes!("../../assets/scenes/veach-mis.gltf"),
    },
    BuiltinScene {
        name: "penumbra",
        description: "a cube on a post under a point light: a hard shadow, and a penumbra growing with the light's size with --lights area --light-radius R",
        gltf: include_bytes!("../../assets/scenes/penumbra.gltf"),
    },
    BuiltinScene {
        name: "indirect-room",
        description: "a room whose lamp lights no visible surface: L1 is black, L2 carries the picture",
        gltf: include_bytes!("../../assets/scenes/indirect-room.gltf"),
    },
];

impl BuiltinScene {
    /// The scene's glTF file, as built in.
    pub fn gltf(&self) -> &'static [u8] {
        self.gltf
    }
}

/// Whether `spec` names a built-in scene (rather than a file).
pub fn is_builtin(spec: &str) -> bool {
    SCENES.iter().any(|s| s.name == spec)
}

/// The built-in Cornell box.
pub fn cornell() -> Scene {
    super::gltf::load_slice(CORNELL_GLTF, "cornell", None).expect("the embedded Cornell box loads")
}

/// A scene by name (`cornell`, or another of [`SCENES`]) or by path to a
/// `.gltf`/`.glb` file.
pub fn load(spec: &str) -> Result<Scene, SceneError> {
    match SCENES.iter().find(|s| s.name == spec) {
        Some(builtin) => super::gltf::load_slice(builtin.gltf, builtin.name, None),
        None => super::gltf::load(Path::new(spec)),
    }
}

/// A UV sphere of `rings × segments` quads (two triangles each, poles as fans),
/// counter-clockwise seen from outside, or from inside if `inward`.
pub fn uv_sphere(
    center: Vec3,
    radius: f32,
    segments: u32,
    rings: u32,
    inward: bool,
) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut positions = Vec::new();
    for ring in 0..=rings {
        let theta = std::f32::consts::PI * ring as f32 / rings as f32;
        for segment in 0..segments {
            let phi = std::f32::consts::TAU * segment as f32 / segments as f32;
            let (st, ct) = theta.sin_cos();
            let (sp, cp) = phi.sin_cos();
            // exact poles so that the fans close the mesh
            let st = if ring == 0 || ring == rings { 0.0 } else { st };
            positions.push(center + radius * Vec3::new(st * cp, ct, st * sp));
        }
    }
    let index = |ring: u32, segment: u32| ring * segments + segment % segments;
    let mut triangles = Vec::new();
    for ring in 0..rings {
        for segment in 0..segments {
            let (a, b) = (index(ring, segment), index(ring, segment + 1));
            let (c, d) = (index(ring + 1, segment), index(ring + 1, segment + 1));
            // outward winding: (a, b, c) seen from outside is counter-clockwise
            let mut quad = vec![];
            if ring != 0 {
                quad.push([a, b, d]);
            }
            if ring != rings - 1 {
                quad.push([a, d, c]);
            }
            for t in quad {
                triangles.push(if inward { [t[0], t[2], t[1]] } else { t });
            }
        }
    }
    (positions, triangles)
}

/// The axis-aligned box between `lo` and `hi`: its 8 corners and 12
/// triangles, counter-clockwise seen from outside, or from inside if
/// `inward`.
pub fn closed_box(lo: Vec3, hi: Vec3, inward: bool) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let corners: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 != 0 { hi.x } else { lo.x },
                if i & 2 != 0 { hi.y } else { lo.y },
                if i & 4 != 0 { hi.z } else { lo.z },
            )
        })
        .collect();
    // faces counter-clockwise seen from outside
    let quads = [
        [0, 2, 3, 1], // z = lo
        [4, 5, 7, 6], // z = hi
        [0, 4, 6, 2], // x = lo
        [1, 3, 7, 5], // x = hi
        [0, 1, 5, 4], // y = lo
        [2, 6, 7, 3], // y = hi
    ];
    let triangles = quads
        .iter()
        .map(|&[a, b, c, d]| if inward { [a, d, c, b] } else { [a, b, c, d] })
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    (corners, triangles)
}

/// The furnace: the camera at the centre of a closed unit sphere whose inner
/// surface is Lambertian of albedo `albedo` and emits radiance `emission`.
/// Every term has a closed form: L_k = albedoᵏ · emission.
pub fn furnace(albedo: f32, emission: f32) -> Scene {
    let mut scene = Scene {
        name: "furnace".into(),
        ..Scene::default()
    };
    let material = scene.add_material(Material {
        emission: Vec3::splat(emission),
        ..Material::lambert("furnace wall", Vec3::splat(albedo))
    });
    let (positions, triangles) = uv_sphere(Vec3::ZERO, 1.0, 48, 24, true);
    scene.add_mesh("sphere", material, &positions, &triangles);
    scene.cameras.push(Camera {
        name: "centre".into(),
        world_from_camera: Affine3A::IDENTITY,
        projection: Projection::Perspective { yfov: 1.2 },
    });
    scene
}

/// A point light of intensity `intensity` at the centre of a closed sphere of
/// radius `radius`, Lambertian of albedo `albedo`, seen from the centre.
/// L1 = albedo · I / (π R²) everywhere, and L2 = albedo · L1.
pub fn point_in_sphere(albedo: f32, intensity: f32, radius: f32) -> Scene {
    let mut scene = Scene {
        name: "point in sphere".into(),
        ..Scene::default()
    };
    let material = scene.add_material(Material::lambert("wall", Vec3::splat(albedo)));
    let (positions, triangles) = uv_sphere(Vec3::ZERO, radius, 256, 128, true);
    scene.add_mesh("sphere", material, &positions, &triangles);
    scene.lights.push(PunctualLight {
        name: "point".into(),
        kind: PunctualKind::Point,
        position: Vec3::ZERO,
        direction: -Vec3::Z,
        intensity: Vec3::splat(intensity),
    });
    scene.cameras.push(Camera {
        name: "centre".into(),
        world_from_camera: Affine3A::IDENTITY,
        projection: Projection::Perspective { yfov: 1.2 },
    });
    scene
}
