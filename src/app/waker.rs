//! Waking the viewer when a background result is ready.
//!
//! On the desktop the thread asks egui for a repaint. In the browser egui's
//! repaint reads the page's clock, which a Web Worker does not have, so no
//! worker may call it there: a worker announces its result
//! (`platform::threads::announce`, which a finished job does too), and a
//! timer on the page's thread looks every 40 ms and asks for a frame only
//! when something was announced ([`install`]); an idle page draws nothing.

use eframe::egui;

/// How often the page looks for announced results in the browser.
#[cfg(target_arch = "wasm32")]
const LOOK_EVERY_MS: i32 = 40;

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
        #[cfg(target_arch = "wasm32")]
        crate::platform::threads::announce();
    }
}

/// Once, at start: in the browser, the page's timer that turns announced
/// results into frames.
pub fn install(ctx: &egui::Context) {
    #[cfg(target_arch = "wasm32")]
    {
        use wasm_bindgen::JsCast;
        let ctx = ctx.clone();
        let look = wasm_bindgen::closure::Closure::<dyn FnMut()>::new(move || {
            if crate::platform::threads::take_news() {
                ctx.request_repaint();
            }
        });
        if let Some(window) = web_sys::window() {
            let _ = window.set_interval_with_callback_and_timeout_and_arguments_0(
                look.as_ref().unchecked_ref(),
                LOOK_EVERY_MS,
            );
        }
        // the timer lives as long as the page
        look.forget();
    }
    #[cfg(not(target_arch = "wasm32"))]
    let _ = ctx;
}
