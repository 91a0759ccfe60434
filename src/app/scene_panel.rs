//! The side panel's Scene group: the scene library with thumbnails, and a
//! scene file of one's own (a path on the desktop, the file picker in the
//! browser, or a file dropped on the window).

use eframe::egui;

use super::LumiereApp;

/// Ctrl+O: in the browser, its file picker; on the desktop, the Scene
/// group opened on its file field.
pub fn open_file(app: &mut LumiereApp) {
    if !super::files::READS_PATHS {
        app.dropped.pick();
    } else {
        app.open_file_requested = true;
    }
}

pub fn scene_ui(app: &mut LumiereApp, ui: &mut egui::Ui) {
    let open_file = std::mem::take(&mut app.open_file_requested);
    egui::CollapsingHeader::new("Scene")
        .default_open(false)
        .open(open_file.then_some(true))
        .show(ui, |ui| {
            ui.label(format!(
                "{}: {} triangles, {} lights",
                app.scene.name,
                app.scene.triangles.len(),
                app.scene.lights.len()
            ));
            let mut chosen = None;
            egui::CollapsingHeader::new("library")
                .default_open(true)
                .show(ui, |ui| {
                    for (index, scene) in crate::scene::builtin::SCENES.iter().enumerate() {
                        let current = app.scene_spec == scene.name;
                        if library_row(ui, &mut app.thumbnails, index, current) {
                            chosen = Some(scene.name);
                        }
                    }
                })
                .header_response
                .on_hover_text(
                    "The scene library: the Cornell box, its variants, one scene per lesson",
                );
            if let Some(name) = chosen {
                app.load_scene(name);
            }
            if !super::files::READS_PATHS {
                if ui
                    .button("Open a glTF file…")
                    .on_hover_text(
                        "Ctrl+O: a .glb, or a .gltf with its buffers embedded, from this computer",
                    )
                    .clicked()
                {
                    app.dropped.pick();
                }
            } else {
                file_field(app, ui, open_file);
            }
            ui.label(
                egui::RichText::new("or drop a .gltf/.glb file on the window")
                    .weak()
                    .small(),
            );
        });
}

/// A scene's path or built-in name, loaded on Enter or "Load".
fn file_field(app: &mut LumiereApp, ui: &mut egui::Ui, focus: bool) {
    ui.horizontal(|ui| {
        let label = ui.label("file");
        let field = ui
            .text_edit_singleline(&mut app.scene_field)
            .labelled_by(label.id)
            .on_hover_text("Ctrl+O: a .gltf or .glb file's path, or a built-in scene's name");
        if focus {
            field.request_focus();
        }
        let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        if ui.button("Load").clicked() || enter {
            let spec = app.scene_field.clone();
            app.load_scene(&spec);
        }
    });
}

/// One scene of the library: its thumbnail, its name and its description;
/// true when it was clicked.
fn library_row(
    ui: &mut egui::Ui,
    thumbnails: &mut super::thumbnails::Thumbnails,
    index: usize,
    current: bool,
) -> bool {
    let scene = &crate::scene::builtin::SCENES[index];
    let [width, height] = super::thumbnails::SIZE.map(|v| v as f32);
    ui.horizontal(|ui| {
        let picture = match thumbnails.get(ui.ctx(), index) {
            Some(texture) => ui.add(
                egui::Image::new((texture.id(), egui::vec2(width, height)))
                    .sense(egui::Sense::click()),
            ),
            None => ui.add_sized([width, height], egui::Spinner::new()),
        };
        ui.vertical(|ui| {
            let name = ui.selectable_label(current, egui::RichText::new(scene.name).strong());
            ui.add(egui::Label::new(egui::RichText::new(scene.description).small()).wrap());
            name.clicked() || picture.clicked()
        })
        .inner
    })
    .inner
}
