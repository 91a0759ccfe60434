//! Mouse work in the viewport and edits of the scene: orbit / pan / dolly
//! of the camera, picking an object by casting a ray through the clicked
//! pixel, and per-object and per-light edits (copy-on-write of the scene, so
//! the worker's copy is never touched while it renders).

use std::sync::Arc;

use eframe::egui;
use glam::{Affine3A, Quat, Vec2, Vec3};

use super::LumiereApp;
use super::probe_view::ImageMapping;
use crate::course::{LightMode, RenderSettings};
use crate::geometry::accel::{Accel, Hit};
use crate::geometry::camera::CameraRays;
use crate::scene::{BrdfModel, Camera, Material, PunctualKind, Scene};

/// Radians per point of mouse drag.
const ORBIT_SPEED: f32 = 0.008;

/// The point the camera orbits around, kept between drags.
#[derive(Clone, Copy, Debug, Default)]
pub struct Orbit {
    pub target: Option<Vec3>,
}

fn position(camera: &Camera) -> Vec3 {
    camera.world_from_camera.translation.into()
}

fn forward(camera: &Camera) -> Vec3 {
    camera
        .world_from_camera
        .transform_vector3(-Vec3::Z)
        .normalize()
}

/// A camera at `eye` looking at `target`, +Y up, with the projection of `like`.
fn looking_at(like: &Camera, eye: Vec3, target: Vec3) -> Camera {
    let forward = (target - eye).normalize_or(-Vec3::Z);
    let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
    let up = right.cross(forward);
    Camera {
        world_from_camera: Affine3A::from_cols(
            right.into(),
            up.into(),
            (-forward).into(),
            eye.into(),
        ),
        ..like.clone()
    }
}

impl Orbit {
    /// The orbit centre: kept, or the scene's centre projected on the view axis.
    fn target(&mut self, camera: &Camera, scene: &Scene) -> Vec3 {
        *self.target.get_or_insert_with(|| {
            let eye = position(camera);
            let distance = (scene.bounds().center() - eye).dot(forward(camera));
            eye + forward(camera) * distance.max(1e-3 * scene.bounds().diagonal().max(1e-3))
        })
    }

    /// Turns the camera around the target by a drag of `delta` points.
    pub fn orbit(&mut self, camera: &Camera, scene: &Scene, delta: egui::Vec2) -> Camera {
        let target = self.target(camera, scene);
        let offset = position(camera) - target;
        let right = camera
            .world_from_camera
            .transform_vector3(Vec3::X)
            .normalize();
        let yaw = Quat::from_axis_angle(Vec3::Y, -delta.x * ORBIT_SPEED);
        let pitch = Quat::from_axis_angle(right, -delta.y * ORBIT_SPEED);
        let turned = yaw * pitch * offset;
        // stop short of the poles, where "up" is undefined
        let offset = if turned.normalize().y.abs() < 0.98 {
            turned
        } else {
            yaw * offset
        };
        looking_at(camera, target + offset, target)
    }

    /// Slides camera and target sideways by a drag of `delta` points in a view `height` points tall.
    pub fn pan(
        &mut self,
        camera: &Camera,
        scene: &Scene,
        delta: egui::Vec2,
        height: f32,
    ) -> Camera {
        let target = self.target(camera, scene);
        let distance = (position(camera) - target).length();
        let scale = 2.0 * distance * 0.4 / height.max(1.0);
        let right = camera
            .world_from_camera
            .transform_vector3(Vec3::X)
            .normalize();
        let up = camera
            .world_from_camera
            .transform_vector3(Vec3::Y)
            .normalize();
        let shift = (-delta.x * right + delta.y * up) * scale;
        self.target = Some(target + shift);
        Camera {
            world_from_camera: Affine3A::from_translation(shift) * camera.world_from_camera,
            ..camera.clone()
        }
    }

    /// Moves the camera towards the target (positive `amount`) or away.
    pub fn dolly(&mut self, camera: &Camera, scene: &Scene, amount: f32) -> Camera {
        let target = self.target(camera, scene);
        let factor = (-amount * 0.002).exp();
        looking_at(
            camera,
            target + (position(camera) - target) * factor,
            target,
        )
    }
}

/// Handles the viewport's mouse input for the image drawn at `mapping`.
pub fn viewport_input(app: &mut LumiereApp, response: &egui::Response, mapping: &ImageMapping) {
    let rect = mapping.rect;
    let scene = Arc::clone(&app.scene);
    let shift = response.ctx.input(|i| i.modifiers.shift);
    if shift && app.zoom.scale.is_some() && response.dragged() {
        app.zoom.pan += response.drag_delta();
    } else if response.dragged_by(egui::PointerButton::Primary) {
        app.camera = app.orbit.orbit(&app.camera, &scene, response.drag_delta());
    } else if response.dragged_by(egui::PointerButton::Secondary)
        || response.dragged_by(egui::PointerButton::Middle)
    {
        app.camera = app
            .orbit
            .pan(&app.camera, &scene, response.drag_delta(), rect.height());
    }
    if response.hovered() {
        let scroll = response.ctx.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            app.camera = app.orbit.dolly(&app.camera, &scene, scroll);
        }
    }
    if response.clicked()
        && let Some(pointer) = response.interact_pointer_pos()
        && rect.contains(pointer)
    {
        let command = response.ctx.input(|i| i.modifiers.command);
        if app.probe_tool || command {
            if let Some((x, y)) = mapping.screen_to_pixel(pointer) {
                app.probe.pick(x, y);
            }
        } else {
            let uv = (pointer - rect.min) / rect.size();
            app.selected = app.pick(Vec2::new(uv.x, uv.y));
        }
    }
}

impl LumiereApp {
    /// The object under image coordinates `uv` ∈ [0,1]² (top-left origin).
    pub fn pick(&mut self, uv: Vec2) -> Option<u32> {
        let scene = Arc::clone(&self.scene);
        let fresh = self
            .picking
            .as_ref()
            .is_some_and(|(s, _)| Arc::ptr_eq(s, &scene));
        if !fresh {
            // all triangles, whatever the light mode: emitters can be selected too
            self.picking = Some((
                Arc::clone(&scene),
                Accel::build(&scene, |_| true, Vec::new()),
            ));
        }
        let (_, accel) = self.picking.as_ref()?;
        let settings = &self.state.settings;
        let rays = CameraRays::new(&self.camera, settings.width, settings.height);
        let pixel = uv * Vec2::new(settings.width as f32, settings.height as f32);
        let x = (pixel.x as u32).min(settings.width - 1);
        let y = (pixel.y as u32).min(settings.height - 1);
        let ray = rays.generate(x, y, pixel.fract());
        match accel.closest_hit(&ray)? {
            Hit::Triangle { triangle, .. } => Some(scene.object_of_triangle(triangle)),
            Hit::Sphere { .. } => None,
        }
    }

    /// The material of `object`, made its own first (a copy if other objects share it).
    pub fn own_material(&mut self, object: u32) -> &mut Material {
        Arc::make_mut(&mut self.scene).own_material(object)
    }
}

/// The course's model of a material, as metallic-roughness parameters and
/// the glass share (the index of refraction stays the material's).
pub fn set_model(material: &mut Material, model: BrdfModel) {
    let (metallic, roughness, transmission) = match model {
        BrdfModel::Lambert => (0.0, 1.0, 0.0),
        BrdfModel::Mirror => (1.0, 0.0, 0.0),
        // invert n = 2/α² − 2 with α = roughness²
        BrdfModel::Phong { exponent } => (0.0, (2.0 / (exponent + 2.0)).sqrt().sqrt(), 0.0),
        BrdfModel::Glass => (0.0, 0.0, 1.0),
    };
    material.metallic = metallic;
    material.roughness = roughness;
    material.transmission = transmission;
}

/// What glass does, and to which term its light goes.
pub const GLASS_TOOLTIP: &str = "Smooth glass: Fresnel reflection and Snell refraction, tinted by \
the colour. Each refraction is an interaction like a reflection: a light seen through a glass \
block is L2, a caustic on the floor under it L3. Glass cannot sample a light: its direct \
lighting comes from its one direction.";

/// The selected object's controls: its reflection model and colour.
pub fn selection_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    egui::CollapsingHeader::new("Selection")
        .default_open(true)
        .show(ui, |ui| {
            let Some(object) = app
                .selected
                .filter(|&o| (o as usize) < app.scene.objects.len())
            else {
                ui.label(
                    egui::RichText::new("click an object in the image to select it")
                        .weak()
                        .small(),
                );
                return;
            };
            let name = app.scene.objects[object as usize].name.clone();
            let material =
                &app.scene.materials[app.scene.objects[object as usize].material as usize];
            let model = material.brdf_model();
            let mut color = material.base_color.to_array();
            ui.label(format!("{name} ({})", material.name));
            let mut chosen = model;
            egui::ComboBox::from_label("model")
                .selected_text(match model {
                    BrdfModel::Lambert => "Lambert",
                    BrdfModel::Phong { .. } => "Phong",
                    BrdfModel::Mirror => "Mirror",
                    BrdfModel::Glass => "Glass",
                })
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut chosen, BrdfModel::Lambert, "Lambert");
                    ui.selectable_value(&mut chosen, BrdfModel::Phong { exponent: 32.0 }, "Phong");
                    ui.selectable_value(&mut chosen, BrdfModel::Mirror, "Mirror");
                    ui.selectable_value(&mut chosen, BrdfModel::Glass, "Glass")
                        .on_hover_text(GLASS_TOOLTIP);
                });
            let mut exponent = match model {
                BrdfModel::Phong { exponent } => exponent,
                _ => 32.0,
            };
            let exponent_changed = matches!(model, BrdfModel::Phong { .. })
                && ui
                    .add(
                        egui::Slider::new(&mut exponent, 1.0..=10_000.0)
                            .logarithmic(true)
                            .text("exponent"),
                    )
                    .changed();
            // glass, or a material partly glass: its share and index of refraction
            let (mut transmission, mut ior) = (material.transmission, material.ior);
            let glass_changed = material.glass_weight() > 0.0 && {
                let share = model != BrdfModel::Glass
                    && ui
                        .add(egui::Slider::new(&mut transmission, 0.0..=1.0).text("glass share"))
                        .on_hover_text(
                            "the share of the material that is glass (glTF transmissionFactor)",
                        )
                        .changed();
                let index = ui
                    .add(
                        egui::Slider::new(&mut ior, 1.0..=crate::course::MAX_IOR)
                            .text("η (index of refraction)"),
                    )
                    .on_hover_text("glass 1.5, water 1.33, diamond 2.42")
                    .changed();
                share || index
            };
            let color_changed = ui
                .horizontal(|ui| {
                    let label = ui.label("colour");
                    ui.color_edit_button_rgb(&mut color)
                        .labelled_by(label.id)
                        .changed()
                })
                .inner;
            if chosen != model {
                set_model(app.own_material(object), chosen);
            }
            if exponent_changed {
                set_model(app.own_material(object), BrdfModel::Phong { exponent });
            }
            if glass_changed {
                let material = app.own_material(object);
                material.transmission = transmission;
                material.ior = ior;
            }
            if color_changed {
                app.own_material(object).base_color = Vec3::from_array(color);
            }
        });
}

/// Each light's strength in the unit of what it is in the current light
/// mode — a point light's intensity I (W/sr), a sphere light's or an
/// emitter's radiance Lₑ (W/m²/sr), an emitter collapsed to a point's peak
/// intensity — with its power Φ (W), which the modes keep.
pub fn light_power_ui(
    ui: &mut egui::Ui,
    settings: &RenderSettings,
    edited: &mut Arc<Scene>,
    areas: &mut EmitterAreas,
) {
    let scene = Arc::clone(edited);
    let mode = settings.light_mode;
    let radius = crate::transport::lights::sphere_light_radius(&scene, settings);
    let sphere_area = std::f32::consts::PI * radius * radius;
    for (i, light) in scene.lights.iter().enumerate() {
        let intensity = light.intensity.max_element();
        // what the light is in this mode, in its own unit, and its power Φ
        let (value, unit, per_intensity, power) = match light.kind {
            PunctualKind::Directional => (intensity, "E, W/m²", 1.0, None),
            kind => {
                let solid_angle = match kind {
                    PunctualKind::Spot {
                        inner_cone_angle,
                        outer_cone_angle,
                    } => {
                        2.0 * std::f32::consts::PI
                            * (1.0 - 0.5 * (inner_cone_angle.cos() + outer_cone_angle.cos()))
                    }
                    _ => 4.0 * std::f32::consts::PI,
                };
                let power = Some(intensity * solid_angle);
                if mode == LightMode::Area {
                    // a sphere of radius r: Lₑ = I / (π r²)
                    (
                        intensity / sphere_area,
                        "Lₑ, W/m²/sr",
                        1.0 / sphere_area,
                        power,
                    )
                } else {
                    (intensity, "I, W/sr", 1.0, power)
                }
            }
        };
        if let Some(value) = strength_field(ui, value, &light.name, unit, power) {
            let light = &mut Arc::make_mut(edited).lights[i];
            let colour = light.intensity / light.intensity.max_element().max(1e-12);
            let colour = if colour == Vec3::ZERO {
                Vec3::ONE
            } else {
                colour
            };
            light.intensity = colour * (value / per_intensity);
        }
    }
    let areas = areas.of(&scene).to_vec();
    for (i, material) in scene
        .materials
        .iter()
        .enumerate()
        .filter(|(_, m)| m.is_emissive())
    {
        let radiance = material.emission.max_element();
        let area = areas[i];
        // a Lambertian emitter of area A: Φ = π A Lₑ per emitting side
        let sides = if material.double_sided { 2.0 } else { 1.0 };
        let power = Some(std::f32::consts::PI * area * radiance * sides);
        let (value, unit, per_radiance) = if mode == LightMode::Point && area > 0.0 {
            // collapsed to a point: the cosine lobe's peak I = Lₑ A
            (radiance * area, "I, W/sr", area)
        } else {
            (radiance, "Lₑ, W/m²/sr", 1.0)
        };
        if let Some(value) = strength_field(ui, value, &material.name, unit, power) {
            let material = &mut Arc::make_mut(edited).materials[i];
            let colour = material.emission / material.emission.max_element();
            material.emission = colour * (value / per_radiance).max(1e-6);
        }
    }
}

/// The area of each material's triangles, kept for the scene it was
/// found for (the light panel reads it every frame).
#[derive(Default)]
pub struct EmitterAreas {
    /// The scene's address, and its areas by material.
    found: Option<(usize, Vec<f32>)>,
}

impl EmitterAreas {
    fn of(&mut self, scene: &Arc<Scene>) -> &[f32] {
        let key = Arc::as_ptr(scene) as usize;
        if self.found.as_ref().is_none_or(|(found, _)| *found != key) {
            self.found = Some((key, emitter_areas(scene)));
        }
        self.found.as_ref().map_or(&[], |(_, areas)| areas)
    }
}

/// The area of each material's triangles (zero for most): what an emissive
/// material's radiance is spread over.
fn emitter_areas(scene: &Scene) -> Vec<f32> {
    let mut areas = vec![0.0; scene.materials.len()];
    for triangle in &scene.triangles {
        if !scene.materials[triangle.material as usize].is_emissive() {
            continue;
        }
        let [a, b, c] = triangle.vertices.map(|v| scene.positions[v as usize]);
        areas[triangle.material as usize] += 0.5 * (b - a).cross(c - a).length();
    }
    areas
}

/// A light's strength in `unit`, with its power Φ beside it when it has
/// one; the new value when it was changed.
fn strength_field(
    ui: &mut egui::Ui,
    value: f32,
    name: &str,
    unit: &str,
    power: Option<f32>,
) -> Option<f32> {
    let mut value = value;
    let changed = power_field(ui, &mut value, &format!("{name} ({unit})"));
    if let Some(power) = power {
        ui.label(
            egui::RichText::new(format!("Φ = {power:.4} W"))
                .weak()
                .small(),
        );
    }
    changed.then_some(value)
}

/// A labelled number field for a light's strength; true when it changed.
fn power_field(ui: &mut egui::Ui, value: &mut f32, label: &str) -> bool {
    ui.horizontal(|ui| {
        let speed = (*value * 0.01).max(1e-3);
        let name = ui.label(label);
        ui.add(egui::DragValue::new(value).speed(speed).range(0.0..=1e9))
            .labelled_by(name.id)
            .changed()
    })
    .inner
}
