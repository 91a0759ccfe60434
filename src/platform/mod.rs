//! What differs between the desktop and the browser, behind small named
//! seams; everything else is the same code on both.
//!
//! | seam | desktop | browser (`wasm32`) |
//! |---|---|---|
//! | [`time`] | the system's monotonic clock | the page's `performance.now()` |
//! | [`memory`] | `MemTotal` of /proc/meminfo | the same fallback ceiling |
//! | [`threads`] | OS threads; rayon pools of any size | Web Workers: rayon's one pool (`wasm-bindgen-rayon`), and background jobs on it |
//!
//! Files, downloads and the settings' storage are the viewer's
//! (`app::files`); the core reads and writes no file in the browser.

pub mod memory;
pub mod threads;
pub mod time;
