//! Scene files the user drops on the viewer. On the desktop a dropped file
//! has a path, loaded as any scene file (a `.gltf` finds its buffers beside
//! it). In the browser a page sees only the file's bytes, read
//! asynchronously, then loaded from memory: a `.glb`, or a `.gltf` whose
//! buffers and images are embedded.

use std::sync::{Arc, Mutex};

use eframe::egui;

use crate::scene::Scene;

/// What a drop brought.
pub enum DroppedScene {
    /// A file on disk, by path.
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    Path(String),
    /// A file read into memory (in the browser) and loaded, or why not.
    #[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
    Loaded(String, Result<Box<Scene>, String>),
}

/// A file's name and its bytes, or why the browser could not read them.
#[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
type ReadFile = (String, Result<Vec<u8>, String>);

/// Files dropped on the viewer, and those still being read.
#[derive(Default)]
pub struct Dropped {
    /// A file's name and bytes once the browser has read them.
    #[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
    inbox: Arc<Mutex<Option<ReadFile>>>,
}

impl Dropped {
    /// The scene dropped, once it is ready (called every frame).
    pub fn take(&mut self, ctx: &egui::Context) -> Option<DroppedScene> {
        let file = ctx.input(|i| i.raw.dropped_files.first().cloned());
        #[cfg(not(target_arch = "wasm32"))]
        {
            let path = file?.path().to_string_lossy().into_owned();
            (!path.is_empty()).then_some(DroppedScene::Path(path))
        }
        #[cfg(target_arch = "wasm32")]
        {
            use crate::platform::threads::lock;
            if let Some(file) = file {
                let inbox = Arc::clone(&self.inbox);
                let name = file.path().to_string_lossy().into_owned();
                wasm_bindgen_futures::spawn_local(async move {
                    let bytes = file.bytes_async().await;
                    *lock(&inbox) = Some((name, bytes));
                });
            }
            let (name, bytes) = lock(&self.inbox).take()?;
            let scene = bytes.and_then(|bytes| {
                crate::scene::gltf::load_slice(&bytes, &name, None)
                    .map(Box::new)
                    .map_err(|e| e.to_string())
            });
            Some(DroppedScene::Loaded(name, scene))
        }
    }
}
