//! The viewer in a headless egui harness (wgpu), for the viewer tests:
//! the app, a wait on its worker, and photographs of its window.
#![allow(dead_code)]

use std::time::{Duration, Instant};

use eframe::egui;
use egui_kittest::Harness;
use lumiere::RenderSettings;
use lumiere::app::{LumiereApp, ViewOptions};
use lumiere::render::progressive::Snapshot;

/// The viewer on the Cornell box, rendering a 64×48 image.
pub fn harness() -> Harness<'static, LumiereApp> {
    harness_with_film(64, 48)
}

/// The viewer on the Cornell box, rendering a `width`×`height` image, in a
/// window tall enough for the whole side panel (a widget scrolled out of
/// view has no node to click).
pub fn harness_with_film(width: u32, height: u32) -> Harness<'static, LumiereApp> {
    harness_with_window(width, height, [1100.0, 1300.0])
}

/// The viewer on the Cornell box, rendering a `width`×`height` image, in a
/// window of `size` points.
pub fn harness_with_window(
    width: u32,
    height: u32,
    size: [f32; 2],
) -> Harness<'static, LumiereApp> {
    let options = ViewOptions {
        settings: RenderSettings {
            width,
            height,
            ..RenderSettings::default()
        },
        ..ViewOptions::default()
    };
    let mut harness = Harness::builder()
        .with_size(size)
        .wgpu()
        .build_eframe(|cc| LumiereApp::new(cc, options).expect("the Cornell box loads"));
    harness.run_steps(2);
    harness
}

/// Steps the UI until the worker's snapshot satisfies `done` (60 s at most).
pub fn wait_for(
    harness: &mut Harness<'static, LumiereApp>,
    what: &str,
    done: impl Fn(&Snapshot) -> bool,
) -> Snapshot {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        harness.step();
        let snapshot = harness.state().snapshot();
        // the film's guard zeroes NaN, infinite and negative samples: its count shows them
        assert_eq!(
            snapshot.rays.invalid_samples, 0,
            "the render worker dropped invalid samples"
        );
        if done(&snapshot) {
            return (*snapshot).clone();
        }
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The window as rendered now, and where the image is in it (pixels).
pub struct WindowShot {
    pub window: image::RgbaImage,
    pub image_rect: egui::Rect,
    /// The film's size: the image shows `film_width`×`film_height` pixels.
    pub film_width: u32,
    pub film_height: u32,
}

impl WindowShot {
    pub fn take(harness: &mut Harness<'static, LumiereApp>) -> Self {
        let ppp = harness.ctx.pixels_per_point();
        let app = harness.state();
        let image_rect = app.image_rect().expect("the image is drawn") * ppp;
        let (film_width, film_height) = (app.state.settings.width, app.state.settings.height);
        let window = harness.render().expect("the harness renders");
        Self {
            window,
            image_rect,
            film_width,
            film_height,
        }
    }

    /// The colour on screen at the centre of film pixel (`x`, `y`).
    pub fn colour_at(&self, x: u32, y: u32) -> [u8; 3] {
        let rect = self.image_rect;
        let point = rect.min
            + egui::vec2(
                (x as f32 + 0.5) / self.film_width as f32 * rect.width(),
                (y as f32 + 0.5) / self.film_height as f32 * rect.height(),
            );
        let p = self.window.get_pixel(point.x as u32, point.y as u32);
        [p[0], p[1], p[2]]
    }

    /// The colour on screen of every film pixel, rows from the top.
    pub fn film_colours(&self) -> Vec<[u8; 3]> {
        (0..self.film_height)
            .flat_map(|y| (0..self.film_width).map(move |x| (x, y)))
            .map(|(x, y)| self.colour_at(x, y))
            .collect()
    }
}
