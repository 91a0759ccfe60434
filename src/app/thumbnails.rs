//! Thumbnails of the scene library, for the Scene group: each built-in
//! scene rendered small (L0+L1+L2, Sobol numbers) on a background thread
//! the first time the list is shown, so they always show the scenes as
//! they are.

use std::sync::mpsc::{Receiver, channel};

use eframe::egui;

use crate::course::{RenderSettings, Sampler};
use crate::platform::threads;
use crate::render::display::DisplaySettings;
use crate::render::export::to_srgb8;
use crate::render::film::Film;
use crate::render::{Budget, render};
use crate::scene::builtin::{self, SCENES};
use crate::transport::context::RenderContext;

/// A thumbnail's size in pixels (the scenes' cameras are 4:3).
pub const SIZE: [usize; 2] = [96, 72];
const SAMPLES_PER_PIXEL: u32 = 64;

/// The thumbnails rendered so far, one per built-in scene.
#[derive(Default)]
pub struct Thumbnails {
    textures: Vec<Option<egui::TextureHandle>>,
    arriving: Option<Receiver<(usize, egui::ColorImage)>>,
}

impl Thumbnails {
    /// Scene `index`'s thumbnail, once rendered; the first call starts the renders.
    pub fn get(&mut self, ctx: &egui::Context, index: usize) -> Option<&egui::TextureHandle> {
        if self.textures.is_empty() {
            self.textures = vec![None; SCENES.len()];
            self.arriving = Some(start(super::waker::Waker::new(ctx)));
        }
        if let Some(arriving) = &self.arriving {
            while let Ok((i, image)) = arriving.try_recv() {
                let name = format!("thumbnail of {}", SCENES[i].name);
                self.textures[i] = Some(ctx.load_texture(name, image, Default::default()));
            }
        }
        self.textures.get(index)?.as_ref()
    }

    /// How many thumbnails have arrived.
    pub fn ready(&self) -> usize {
        self.textures.iter().flatten().count()
    }
}

/// Renders every built-in scene's thumbnail on a thread of its own, one
/// after the other, sending each as it is done.
fn start(waker: super::waker::Waker) -> Receiver<(usize, egui::ColorImage)> {
    let (send, receive) = channel();
    // the job ends with the list; nobody waits for it
    let _job = threads::spawn("thumbnails", move || {
        for (index, scene) in SCENES.iter().enumerate() {
            let Some(image) = thumbnail(scene.name) else {
                continue;
            };
            if send.send((index, image)).is_err() {
                return; // the viewer is gone
            }
            waker.wake();
        }
    });
    receive
}

/// One scene's thumbnail, as the viewer would show it at its defaults.
pub fn thumbnail(name: &str) -> Option<egui::ColorImage> {
    let scene = builtin::load(name).ok()?;
    let settings = RenderSettings {
        width: SIZE[0] as u32,
        height: SIZE[1] as u32,
        sampler: Sampler::Sobol,
        ..RenderSettings::default()
    };
    let context = RenderContext::new(scene, settings.clone());
    let mut film = Film::new(settings.width, settings.height);
    // one thread: the viewer's own render keeps the cores
    let pool = threads::pool(1, "thumbnail");
    threads::install(pool.as_ref(), || {
        render(
            &context,
            &mut film,
            Budget::Samples(SAMPLES_PER_PIXEL),
            |_| {},
        )
    });
    let rgb = to_srgb8(&film.radiance(settings.terms), DisplaySettings::default());
    Some(egui::ColorImage::from_rgb(SIZE, &rgb))
}
