//! Work in the background: a job on a thread of its own, and a rayon pool
//! of a given size.
//!
//! On the desktop a job is an OS thread. In the browser a thread is a Web
//! Worker, and only rayon's global pool has them (`wasm-bindgen-rayon`
//! starts it from the page): a job runs on that pool, which the page makes
//! one worker larger than the renders need, and a pool of a given size is
//! the global one. The page's own thread may never block, so a job's
//! [`Job::join`] there gives its result only once it is finished.

#[cfg(target_arch = "wasm32")]
use std::sync::{Arc, Mutex};

/// A web page without Web Workers (built without the `web-threads`
/// feature, for a page that is not cross-origin isolated): a job runs at
/// once, on the page's thread, and the viewer renders between frames
/// (`ProgressiveRenderer::run_between_frames`).
pub const ONE_THREAD: bool = cfg!(all(target_arch = "wasm32", not(feature = "web-threads")));

/// Set when background work has a result to show (in the browser).
#[cfg(target_arch = "wasm32")]
static NEWS: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Says, from any thread, that background work has a result to show. In
/// the browser only the page's thread may ask for a frame, and it asks
/// when [`take_news`] says so; on the desktop callers ask egui
/// themselves, and this does nothing.
pub fn announce() {
    #[cfg(target_arch = "wasm32")]
    NEWS.store(true, std::sync::atomic::Ordering::Release);
}

/// Whether anything was announced since the last call (always false on
/// the desktop).
pub fn take_news() -> bool {
    #[cfg(target_arch = "wasm32")]
    {
        NEWS.swap(false, std::sync::atomic::Ordering::AcqRel)
    }
    #[cfg(not(target_arch = "wasm32"))]
    false
}

/// Work running in the background, whose result is taken once.
pub struct Job<T> {
    #[cfg(not(target_arch = "wasm32"))]
    handle: std::thread::JoinHandle<T>,
    #[cfg(target_arch = "wasm32")]
    result: Arc<Mutex<Option<T>>>,
    #[cfg(target_arch = "wasm32")]
    finished: Arc<std::sync::atomic::AtomicBool>,
}

/// Starts `work` in the background; `name` names its thread on the desktop.
pub fn spawn<T: Send + 'static>(name: &str, work: impl FnOnce() -> T + Send + 'static) -> Job<T> {
    #[cfg(not(target_arch = "wasm32"))]
    {
        let handle = std::thread::Builder::new()
            .name(name.into())
            .spawn(work)
            .unwrap_or_else(|e| panic!("cannot start the thread {name}: {e}"));
        Job { handle }
    }
    #[cfg(target_arch = "wasm32")]
    {
        let _ = name;
        let result = Arc::new(Mutex::new(None));
        let finished = Arc::new(std::sync::atomic::AtomicBool::new(false));
        let (slot, done) = (Arc::clone(&result), Arc::clone(&finished));
        let run = move || {
            let value = work();
            *slot.lock().unwrap_or_else(|p| p.into_inner()) = Some(value);
            done.store(true, std::sync::atomic::Ordering::Release);
            announce();
        };
        #[cfg(feature = "web-threads")]
        rayon::spawn(run);
        #[cfg(not(feature = "web-threads"))]
        run();
        Job { result, finished }
    }
}

impl<T> Job<T> {
    /// Whether the work has returned.
    pub fn is_finished(&self) -> bool {
        #[cfg(not(target_arch = "wasm32"))]
        {
            self.handle.is_finished()
        }
        #[cfg(target_arch = "wasm32")]
        {
            self.finished.load(std::sync::atomic::Ordering::Acquire)
        }
    }

    /// The work's result: waits for it on the desktop; in the browser,
    /// `None` until it is finished (the page may not wait). `None` too if
    /// the work panicked.
    pub fn join(self) -> Option<T> {
        #[cfg(not(target_arch = "wasm32"))]
        {
            self.handle.join().ok()
        }
        #[cfg(target_arch = "wasm32")]
        {
            self.result.lock().unwrap_or_else(|p| p.into_inner()).take()
        }
    }
}

/// A rayon pool of `threads` threads, to run work with `install`; `None`
/// where it cannot be made (in the browser: the global pool serves).
pub fn pool(threads: usize, name: &'static str) -> Option<rayon::ThreadPool> {
    #[cfg(not(target_arch = "wasm32"))]
    {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads.max(1))
            .thread_name(move |i| format!("{name} {i}"))
            .build()
            .ok()
    }
    #[cfg(target_arch = "wasm32")]
    {
        let _ = (threads, name);
        None
    }
}

/// Runs `work` on `pool`, or on the global pool without one.
pub fn install<T: Send>(pool: Option<&rayon::ThreadPool>, work: impl FnOnce() -> T + Send) -> T {
    match pool {
        Some(pool) => pool.install(work),
        None => work(),
    }
}

/// Threads the machine offers (at least 1).
pub fn available() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Locks `mutex`, ignoring a poisoning panic (the data is plain values).
/// In the browser the page's own thread may not wait (`Atomics.wait` is
/// refused there), so it spins until the lock is free; locks are held
/// for moments, never across a render pass, where the page takes them.
pub fn lock<T>(mutex: &std::sync::Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    #[cfg(target_arch = "wasm32")]
    loop {
        match mutex.try_lock() {
            Ok(guard) => return guard,
            Err(std::sync::TryLockError::Poisoned(poisoned)) => return poisoned.into_inner(),
            Err(std::sync::TryLockError::WouldBlock) => std::hint::spin_loop(),
        }
    }
    #[cfg(not(target_arch = "wasm32"))]
    mutex
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner())
}
