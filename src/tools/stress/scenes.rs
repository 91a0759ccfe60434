//! The generated scenes: furnaces (closed emitting spheres, plain or cut
//! into slivers), a closed box for the mirror corridor, a point light in a
//! sphere, a plane lit at grazing incidence, lights on and through a floor.
//! Each comes with its camera; what a case expects of it is in `cases`.

use glam::{Affine3A, Vec3};

use crate::scene::builtin::{closed_box, uv_sphere};
use crate::scene::{Camera, Material, Projection, PunctualKind, PunctualLight, Scene};

/// A camera at `position` looking along `forward` (world +Y up unless `forward` is vertical).
fn look(position: Vec3, forward: Vec3, yfov: f32) -> Camera {
    let forward = forward.normalize();
    let up_hint = if forward.y.abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    };
    let right = forward.cross(up_hint).normalize();
    let up = right.cross(forward);
    Camera {
        name: "stress".into(),
        world_from_camera: Affine3A::from_cols(
            right.into(),
            up.into(),
            (-forward).into(),
            position.into(),
        ),
        projection: Projection::Perspective { yfov },
    }
}

/// A furnace: a closed sphere of `radius` at `centre`, of `material` (its
/// emission is the furnace's E), `segments × rings`, seen from its centre.
pub(super) fn furnace_scene(
    radius: f32,
    centre: Vec3,
    material: Material,
    segments: u32,
    rings: u32,
) -> Scene {
    let mut scene = Scene {
        name: "furnace".into(),
        ..Scene::default()
    };
    let material = scene.add_material(material);
    let (positions, triangles) = uv_sphere(centre, radius, segments, rings, true);
    scene.add_mesh("sphere", material, &positions, &triangles);
    scene
        .cameras
        .push(look(centre, Vec3::new(0.3, -0.2, -1.0), 1.2));
    scene
}

/// A reflecting emitter: albedo `albedo`, emission `emission` (grey).
pub(super) fn glowing_wall(albedo: f32, emission: f32) -> Material {
    Material {
        emission: Vec3::splat(emission),
        ..Material::lambert("wall", Vec3::splat(albedo))
    }
}

/// Adds zero-area triangles on the sphere: repeated vertices, and three
/// points of one edge (its ends and its midpoint).
pub(super) fn add_zero_area_triangles(scene: &mut Scene) {
    let material = scene.triangles[0].material;
    let edges: Vec<(Vec3, Vec3)> = scene
        .triangles
        .iter()
        .step_by(7)
        .map(|t| {
            let [a, b, _] = t.vertices;
            (scene.positions[a as usize], scene.positions[b as usize])
        })
        .collect();
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for (k, (a, b)) in edges.into_iter().enumerate() {
        let base = positions.len() as u32;
        positions.extend([a, b, 0.5 * (a + b)]);
        triangles.push(if k % 2 == 0 {
            [base, base, base + 1]
        } else {
            [base, base + 2, base + 1]
        });
    }
    scene.add_mesh("zero-area", material, &positions, &triangles);
}

/// A closed box `size` (x, y, z) of `material` from the origin, seen from
/// near one end looking down +z.
pub(super) fn corridor_scene(size: Vec3, material: Material) -> Scene {
    let mut scene = Scene {
        name: "corridor".into(),
        ..Scene::default()
    };
    let material = scene.add_material(material);
    // wound facing out: the case's material is double-sided
    let (corners, triangles) = closed_box(Vec3::ZERO, size, false);
    scene.add_mesh("corridor", material, &corners, &triangles);
    scene.cameras.push(look(
        Vec3::new(0.5 * size.x, 0.5 * size.y, 0.3),
        Vec3::new(0.05, 0.03, 1.0),
        0.9,
    ));
    scene
}

/// A point light of intensity π R² at the centre of a closed sphere of
/// radius R at `centre` and albedo ½, its surface there `copies` times (the
/// third inside out), seen from halfway to the wall.
pub(super) fn point_in_sphere_scene(radius: f32, centre: Vec3, copies: usize) -> Scene {
    let mut scene = Scene {
        name: "point in sphere".into(),
        ..Scene::default()
    };
    let wall = scene.add_material(Material {
        double_sided: true,
        ..Material::lambert("wall", Vec3::splat(0.5))
    });
    for copy in 0..copies {
        let (positions, triangles) = uv_sphere(centre, radius, 256, 128, copy != 2);
        scene.add_mesh("sphere", wall, &positions, &triangles);
    }
    scene.lights.push(PunctualLight {
        name: "centre".into(),
        kind: PunctualKind::Point,
        position: centre,
        direction: -Vec3::Z,
        intensity: Vec3::splat(std::f32::consts::PI * radius * radius),
    });
    scene.cameras.push(look(
        centre + Vec3::new(0.5 * radius, 0.0, 0.0),
        Vec3::new(1.0, 0.2, 0.1),
        1.2,
    ));
    scene
}

/// The plane y = 0 (albedo 0.5), a directional light 89.9° from its normal
/// (irradiance E⊥ = 1000 W/m²), the camera 89.5° from it.
pub(super) fn grazing_scene() -> Scene {
    let mut scene = Scene {
        name: "grazing".into(),
        ..Scene::default()
    };
    let material = scene.add_material(Material::lambert("plane", Vec3::splat(0.5)));
    let size = 1e3;
    let corners = [
        Vec3::new(-size, 0.0, -size),
        Vec3::new(size, 0.0, -size),
        Vec3::new(size, 0.0, size),
        Vec3::new(-size, 0.0, size),
    ];
    scene.add_mesh("plane", material, &corners, &[[0, 2, 1], [0, 3, 2]]);
    let light_angle = 89.9f32.to_radians();
    scene.lights.push(PunctualLight {
        name: "sun".into(),
        kind: PunctualKind::Directional,
        position: Vec3::ZERO,
        direction: -Vec3::new(light_angle.sin(), light_angle.cos(), 0.0),
        intensity: Vec3::splat(1000.0),
    });
    let view_angle = 89.5f32.to_radians();
    scene.cameras.push(look(
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::new(0.0, -view_angle.cos(), -view_angle.sin()),
        0.02,
    ));
    scene
}

/// A floor (albedo 0.5); a point light on it (cos θ = 0 at every floor
/// point: L1 = 0), another 1 µm above, an emitting quad crossing the floor.
pub(super) fn light_on_surface_scene() -> Scene {
    let mut scene = Scene {
        name: "light on surface".into(),
        ..Scene::default()
    };
    let floor = scene.add_material(Material::lambert("floor", Vec3::splat(0.5)));
    let corners = [
        Vec3::new(-2.0, 0.0, -2.0),
        Vec3::new(2.0, 0.0, -2.0),
        Vec3::new(2.0, 0.0, 2.0),
        Vec3::new(-2.0, 0.0, 2.0),
    ];
    scene.add_mesh("floor", floor, &corners, &[[0, 2, 1], [0, 3, 2]]);
    let emitter = scene.add_material(Material {
        double_sided: true,
        ..Material::emitter("through the floor", Vec3::splat(5.0))
    });
    let quad = [
        Vec3::new(0.5, -0.5, -0.5),
        Vec3::new(0.5, -0.5, 0.5),
        Vec3::new(0.5, 0.5, 0.5),
        Vec3::new(0.5, 0.5, -0.5),
    ];
    scene.add_mesh("emitter", emitter, &quad, &[[0, 1, 2], [0, 2, 3]]);
    for (name, height) in [("on the floor", 0.0), ("1 um above", 1e-6)] {
        scene.lights.push(PunctualLight {
            name: name.into(),
            kind: PunctualKind::Point,
            position: Vec3::new(-0.5, height, 0.0),
            direction: -Vec3::Z,
            intensity: Vec3::splat(10.0),
        });
    }
    scene
        .cameras
        .push(look(Vec3::new(0.0, 3.0, 0.01), -Vec3::Y, 1.0));
    scene
}
