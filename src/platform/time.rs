//! A monotonic clock: `std::time::Instant` on the desktop, the page's
//! `performance.now()` in the browser, where std's clock is missing
//! (the `web-time` crate, which re-exports std's on the desktop).

pub use web_time::Instant;
