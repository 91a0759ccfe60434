//! Files in and out of the viewer: the seam between the desktop and the
//! browser for file access.
//!
//! * **In.** A scene file the user drops on the viewer, or (in the browser)
//!   picks with Ctrl+O. On the desktop a dropped file has a path, loaded as
//!   any scene file (a `.gltf` finds its buffers beside it). A page sees
//!   only the file's bytes, read asynchronously, then loaded from memory: a
//!   `.glb`, or a `.gltf` whose buffers and images are embedded.
//! * **Out.** An export writes its files through an [`Outbox`]: into a
//!   folder on the desktop; in the browser it keeps them, and the page's
//!   thread hands them to the browser as downloads once the export is
//!   finished ([`deliver`]): a download must start on the page's thread,
//!   and an export runs on a worker.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use eframe::egui;

use super::LumiereApp;
use crate::scene::Scene;

/// Whether the viewer reads files by their paths: on the desktop; a page
/// sees only the files the user drops or picks, so fields that take a
/// path are not shown there.
pub const READS_PATHS: bool = cfg!(not(target_arch = "wasm32"));

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

/// Files dropped on the viewer or picked, and those still being read.
#[derive(Default)]
pub struct Dropped {
    /// A file's name and bytes once the browser has read them.
    #[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
    inbox: Arc<Mutex<Option<ReadFile>>>,
}

impl Dropped {
    /// The scene dropped or picked, once it is ready (called every frame).
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
                    crate::platform::threads::announce();
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

    /// In the browser, opens its file picker for a `.gltf`/`.glb`; the file
    /// chosen arrives through [`Dropped::take`] as a dropped one does.
    /// Browsers open a picker only shortly after a click or a key press.
    pub fn pick(&self) {
        #[cfg(target_arch = "wasm32")]
        if let Err(e) = web::pick(Arc::clone(&self.inbox)) {
            web_sys::console::error_1(&e);
        }
    }
}

/// Each frame: opens the scene dropped or picked, once read; an error
/// (which names the file) goes to the status bar.
pub fn open_dropped(app: &mut LumiereApp, ctx: &egui::Context) {
    match app.dropped.take(ctx) {
        Some(DroppedScene::Path(path)) => app.load_scene(&path),
        Some(DroppedScene::Loaded(name, Ok(scene))) => app.show_scene(&name, *scene),
        Some(DroppedScene::Loaded(_, Err(e))) => app.message = Some(format!("error: {e}")),
        None => {}
    }
}

/// Each frame: the exports finished, delivered ([`deliver`]); the status
/// bar says where they went, or why not.
pub fn collect_exports(app: &mut LumiereApp) {
    let (finished, running): (Vec<_>, Vec<_>) =
        app.exports.drain(..).partition(|h| h.is_finished());
    app.exports = running;
    for handle in finished {
        app.message = Some(match handle.join() {
            Some(Ok(saved)) => deliver(saved),
            Some(Err(e)) => format!("error: {e}"),
            None => "error: the export failed".into(),
        });
    }
}

/// A file an export made, for the browser to download.
#[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
pub struct Download {
    pub name: String,
    pub bytes: Vec<u8>,
}

/// What a finished export says, and in the browser the files it made.
pub struct Saved {
    pub message: String,
    #[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
    pub downloads: Vec<Download>,
}

/// Where an export's files go: a folder on the desktop; in the browser,
/// memory, until [`deliver`] hands them over as downloads.
pub struct Outbox {
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    folder: PathBuf,
    downloads: Vec<Download>,
    written: Vec<String>,
}

impl Outbox {
    /// Files in `folder`, made if missing (in the browser: the downloads).
    pub fn new(folder: &Path) -> Result<Self, String> {
        #[cfg(not(target_arch = "wasm32"))]
        std::fs::create_dir_all(folder).map_err(|e| format!("{}: {e}", folder.display()))?;
        Ok(Self {
            folder: folder.to_path_buf(),
            downloads: Vec::new(),
            written: Vec::new(),
        })
    }

    /// A name `prefix-…` for a set of files, whose first is `…{suffix}`:
    /// on the desktop `prefix-NNN` with the first NNN whose file is not in
    /// the folder yet; in the browser, which cannot see the downloads,
    /// `prefix-YYYYMMDD-HHMMSS` of the local time (with `-2`, `-3`… for a
    /// second file in the same second).
    pub fn free_stem(&self, prefix: &str, suffix: &str) -> String {
        #[cfg(not(target_arch = "wasm32"))]
        {
            (1..)
                .map(|n| format!("{prefix}-{n:03}"))
                .find(|stem| !self.folder.join(format!("{stem}{suffix}")).exists())
                .expect("some number is free")
        }
        #[cfg(target_arch = "wasm32")]
        {
            let _ = suffix;
            web::timestamped_stem(prefix)
        }
    }

    /// Writes the file `name` (a name, not a path).
    pub fn write(&mut self, name: &str, bytes: Vec<u8>) -> Result<(), String> {
        #[cfg(not(target_arch = "wasm32"))]
        {
            let path = self.folder.join(name);
            std::fs::write(&path, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
        }
        #[cfg(target_arch = "wasm32")]
        self.downloads.push(Download {
            name: name.into(),
            bytes,
        });
        self.written.push(name.into());
        Ok(())
    }

    /// The export is written: "saved …" naming the first file, with
    /// `detail` after it.
    pub fn finish(self, detail: &str) -> Saved {
        let first = self.written.first().cloned().unwrap_or_default();
        #[cfg(not(target_arch = "wasm32"))]
        let message = format!("saved {}{detail}", self.folder.join(first).display());
        #[cfg(target_arch = "wasm32")]
        let message = match self.written.len() {
            0 | 1 => format!("downloaded {first}{detail}"),
            n => format!("downloaded {first}{detail} and {} more files", n - 1),
        };
        Saved {
            message,
            downloads: self.downloads,
        }
    }
}

/// On the page's thread, once an export is finished: hands its files to
/// the browser as downloads; the line for the status bar.
pub fn deliver(saved: Saved) -> String {
    #[cfg(target_arch = "wasm32")]
    for file in &saved.downloads {
        if let Err(e) = web::download(&file.name, &file.bytes) {
            return format!(
                "error: {}: the browser refused the download: {e:?}",
                file.name
            );
        }
    }
    saved.message
}

/// The browser's side: its file picker, downloads and clock.
#[cfg(target_arch = "wasm32")]
mod web {
    use std::sync::{Arc, Mutex};

    use wasm_bindgen::JsCast;
    use wasm_bindgen::prelude::*;

    use super::ReadFile;
    use crate::platform::threads::lock;

    fn document() -> Result<web_sys::Document, JsValue> {
        web_sys::window()
            .and_then(|w| w.document())
            .ok_or_else(|| "no document".into())
    }

    /// An `<input type="file">`, clicked; its file's bytes go to `inbox`.
    pub fn pick(inbox: Arc<Mutex<Option<ReadFile>>>) -> Result<(), JsValue> {
        let input: web_sys::HtmlInputElement = document()?.create_element("input")?.dyn_into()?;
        input.set_type("file");
        input.set_accept(".gltf,.glb,model/gltf+json,model/gltf-binary");
        let chosen = input.clone();
        let on_change = Closure::once_into_js(move || {
            let Some(file) = chosen.files().and_then(|files| files.get(0)) else {
                return;
            };
            wasm_bindgen_futures::spawn_local(async move {
                let name = file.name();
                let bytes = wasm_bindgen_futures::JsFuture::from(file.array_buffer())
                    .await
                    .map(|buffer| js_sys::Uint8Array::new(&buffer).to_vec())
                    .map_err(|e| format!("{name}: cannot read the file: {e:?}"));
                *lock(&inbox) = Some((name, bytes));
                crate::platform::threads::announce();
            });
        });
        input.set_onchange(Some(on_change.unchecked_ref()));
        input.click();
        Ok(())
    }

    /// Starts the download of `bytes` as the file `name`: a link to a blob
    /// of them, clicked.
    pub fn download(name: &str, bytes: &[u8]) -> Result<(), JsValue> {
        // a copy: a blob may not view the module's shared memory
        let array = js_sys::Uint8Array::new_with_length(bytes.len() as u32);
        array.copy_from(bytes);
        let options = web_sys::BlobPropertyBag::new();
        options.set_type(media_type(name));
        let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(
            &js_sys::Array::of1(&array),
            &options,
        )?;
        let url = web_sys::Url::create_object_url_with_blob(&blob)?;
        let link: web_sys::HtmlAnchorElement = document()?.create_element("a")?.dyn_into()?;
        link.set_href(&url);
        link.set_download(name);
        link.click();
        // the browser has read the blob's address once the click is handled
        let revoke = Closure::once_into_js(move || {
            let _ = web_sys::Url::revoke_object_url(&url);
        });
        web_sys::window()
            .ok_or("no window")?
            .set_timeout_with_callback_and_timeout_and_arguments_0(
                revoke.unchecked_ref(),
                60_000,
            )?;
        Ok(())
    }

    fn media_type(name: &str) -> &'static str {
        match name.rsplit('.').next() {
            Some("png") => "image/png",
            Some("exr") => "image/x-exr",
            Some("json") => "application/json",
            _ => "application/octet-stream",
        }
    }

    /// `prefix-YYYYMMDD-HHMMSS` in local time, `-2`, `-3`… appended when
    /// the same second was already used.
    pub fn timestamped_stem(prefix: &str) -> String {
        static LAST: Mutex<(String, u32)> = Mutex::new((String::new(), 0));
        let now = js_sys::Date::new_0();
        let stem = format!(
            "{prefix}-{:04}{:02}{:02}-{:02}{:02}{:02}",
            now.get_full_year(),
            now.get_month() + 1,
            now.get_date(),
            now.get_hours(),
            now.get_minutes(),
            now.get_seconds()
        );
        let mut last = lock(&LAST);
        if last.0 == stem {
            last.1 += 1;
            format!("{stem}-{}", last.1)
        } else {
            *last = (stem.clone(), 1);
            stem
        }
    }
}
