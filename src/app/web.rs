//! The viewer in a web page: what the page's script (`assets/web/main.js`)
//! calls, and the page's address read as the viewer's options.
//!
//! `?lesson=simulation-notions&step=3&lang=fr` opens a lesson on a step
//! (counted from 1, as the viewer shows it); `?scene=cornell-glass` a
//! built-in scene; `&spp=8` stops at 8 samples per pixel and says so on
//! the console (what the page's test waits for). A cross-origin-isolated
//! page loads the module built with `web-threads` and starts rayon's pool
//! of Web Workers (`init_thread_pool`) before [`start`]; any other page
//! loads the one-thread module, which renders between frames.

use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;

use eframe::egui;

use super::{LumiereApp, ViewOptions};
use crate::lesson::{Lang, Lesson};

#[cfg(feature = "web-threads")]
pub use wasm_bindgen_rayon::init_thread_pool;

/// Opens the viewer on the canvas `canvas_id`; an error is the page's to show.
#[wasm_bindgen]
pub async fn start(canvas_id: String) -> Result<(), JsValue> {
    let window = web_sys::window().ok_or("no window")?;
    let canvas = window
        .document()
        .ok_or("no document")?
        .get_element_by_id(&canvas_id)
        .ok_or_else(|| format!("no element #{canvas_id}"))?
        .dyn_into::<web_sys::HtmlCanvasElement>()?;
    let query = window.location().search().unwrap_or_default();
    let options = options_from_query(&query).map_err(JsValue::from)?;
    eframe::WebRunner::new()
        .start(
            canvas,
            eframe::WebOptions::default(),
            Box::new(move |cc| Ok(Box::new(LumiereApp::new(cc, options)?))),
        )
        .await
}

/// The first frame with an image: says on the console how long after the
/// page was opened (the time a student waits before the viewer answers).
pub fn report_first_image(snapshot: &crate::render::progressive::Snapshot) {
    use std::sync::atomic::{AtomicBool, Ordering};
    static REPORTED: AtomicBool = AtomicBool::new(false);
    if snapshot.radiance.is_empty() || REPORTED.swap(true, Ordering::Relaxed) {
        return;
    }
    let since_opened = web_sys::window()
        .and_then(|w| w.performance())
        .map_or(0.0, |p| p.now() / 1000.0);
    let line = format!("lumiere: first image {since_opened:.2} s after the page was opened");
    web_sys::console::log_1(&line.into());
}

/// A scripted page (`?spp=N`) has its image: the line a test waits for,
/// with where the image is in the page's pixels.
pub fn report_reached(snapshot: &crate::render::progressive::Snapshot, image: Option<egui::Rect>) {
    let mut line = format!(
        "lumiere: reached {} samples per pixel in {:.2} s, {:.3} M samples/s",
        snapshot.samples_per_pixel(),
        snapshot.elapsed.as_secs_f64(),
        snapshot.samples_per_second() / 1e6
    );
    if let Some(r) = image {
        line += &format!(
            "; image at {:.0} {:.0} size {:.0} {:.0}",
            r.min.x,
            r.min.y,
            r.width(),
            r.height()
        );
    }
    web_sys::console::log_1(&line.into());
}

/// The viewer's options from the page's query string (`?key=value&…`).
pub fn options_from_query(query: &str) -> Result<ViewOptions, String> {
    let mut options = ViewOptions {
        restore: true,
        ..ViewOptions::default()
    };
    let mut step = None;
    for pair in query
        .trim_start_matches('?')
        .split('&')
        .filter(|p| !p.is_empty())
    {
        let (key, value) = pair.split_once('=').unwrap_or((pair, ""));
        let value = percent_encoding::percent_decode_str(value)
            .decode_utf8_lossy()
            .into_owned();
        match key {
            "scene" => options.scene = value,
            "lesson" => options.lesson = Some(Lesson::load(&value).map_err(|e| e.to_string())?),
            "step" => {
                let n: usize = value
                    .parse()
                    .map_err(|_| format!("step={value}: not a step number"))?;
                step = Some(n.max(1) - 1);
            }
            // the stop of a scripted run, which the page reports on its console
            "spp" => {
                let n: u32 = value
                    .parse()
                    .map_err(|_| format!("spp={value}: not a number of samples"))?;
                options.exit_after_spp = Some(n.max(1));
            }
            "lang" => {
                options.lang = match value.as_str() {
                    "fr" => Lang::Fr,
                    "en" => Lang::En,
                    _ => return Err(format!("lang={value}: fr or en")),
                }
            }
            _ => {}
        }
    }
    options.step = step.unwrap_or(0);
    Ok(options)
}
