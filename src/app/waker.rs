//! Waking the viewer from a background thread when a result is ready.
//!
//! On the desktop the thread asks egui for a repaint. In the browser egui's
//! repaint reads the page's clock, which a Web Worker does not have, so no
//! thread may call it there: the page repaints on its own every 40 ms
//! instead ([`poll`]), which is when a new result shows.

use eframe::egui;

/// How often the page looks for new results in the browser.
#[cfg(target_arch = "wasm32")]
const POLL: std::time::Duration = std::time::Duration::from_millis(40);

/// Wakes the viewer; cheap to clone and send to any thread.
#[derive(Clone)]
pub struct Waker(#[cfg_attr(target_arch = "wasm32", allow(dead_code))] egui::Context);

impl Waker {
    pub fn new(ctx: &egui::Context) -> Self {
        Self(ctx.clone())
    }

    /// Asks for a frame, which will show what the thread just finished.
    pub fn wake(&self) {
        #[cfg(not(target_arch = "wasm32"))]
        self.0.request_repaint();
    }
}

/// Called every frame: in the browser, asks for the next one 40 ms later.
pub fn poll(ctx: &egui::Context) {
    #[cfg(target_arch = "wasm32")]
    ctx.request_repaint_after(POLL);
    #[cfg(not(target_arch = "wasm32"))]
    let _ = ctx;
}
