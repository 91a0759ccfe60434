//! Panics inside the `gltf` crate (a malformed file reaching one of its
//! assertions) turned into errors, without printing them.

use std::cell::Cell;
use std::panic::{self, AssertUnwindSafe};
use std::sync::Once;

use super::Loaded;

thread_local! {
    /// Whether a panic on this thread is expected to be caught by `catch_panics`.
    static QUIET_PANICS: Cell<bool> = const { Cell::new(false) };
}

/// Runs `load`, turning a panic inside it (a malformed file reaching an
/// assertion in the gltf crate) into a problem, without printing the panic.
pub(super) fn catch_panics<T>(load: impl FnOnce() -> Loaded<T>) -> Loaded<T> {
    install_quiet_panic_hook();
    let was_quiet = QUIET_PANICS.replace(true);
    let outcome = panic::catch_unwind(AssertUnwindSafe(load));
    QUIET_PANICS.set(was_quiet);
    outcome.unwrap_or_else(|payload| {
        Err(format!(
            "malformed file (the glTF reader failed: {})",
            panic_message(payload.as_ref())
        ))
    })
}

/// Wraps the process's panic hook, once, so that panics on a thread inside
/// `catch_panics` print nothing; panics elsewhere reach the previous hook.
fn install_quiet_panic_hook() {
    static INSTALL: Once = Once::new();
    INSTALL.call_once(|| {
        let previous = panic::take_hook();
        panic::set_hook(Box::new(move |info| {
            if !QUIET_PANICS.try_with(Cell::get).unwrap_or(false) {
                previous(info);
            }
        }));
    });
}

fn panic_message(payload: &(dyn std::any::Any + Send)) -> &str {
    if let Some(text) = payload.downcast_ref::<&str>() {
        text
    } else if let Some(text) = payload.downcast_ref::<String>() {
        text
    } else {
        "unknown panic"
    }
}
