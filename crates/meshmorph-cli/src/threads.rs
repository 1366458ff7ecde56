//! The thread pool every parallel step runs on.

/// Starts rayon's global pool with a thread per core (or
/// `RAYON_NUM_THREADS`), or on the main
/// thread alone where that many threads cannot be started (a limit on
/// processes, `ulimit -u`): rayon would otherwise panic at its first
/// parallel call.
pub fn start_pool() {
    // As rayon's own default: RAYON_NUM_THREADS, else a thread per core.
    let wanted = std::env::var("RAYON_NUM_THREADS")
        .ok()
        .and_then(|n| n.parse::<usize>().ok())
        .filter(|&n| n > 0)
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    // rayon starts its pool once, and panics on later use if that failed:
    // the threads are tried first.
    let builder = if can_start_threads(wanted) {
        rayon::ThreadPoolBuilder::new().num_threads(wanted)
    } else {
        // The main thread is the pool's only one: no thread is started.
        rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .use_current_thread()
    };
    if let Err(e) = builder.build_global() {
        tell!("warning: cannot start the thread pool ({e})");
    }
}

/// Whether `count` threads can run at once: each is started and waits
/// until all are, then ends.
fn can_start_threads(count: usize) -> bool {
    let (release, wait) = std::sync::mpsc::channel::<()>();
    let wait = std::sync::Arc::new(std::sync::Mutex::new(wait));
    let mut started = Vec::with_capacity(count);
    for _ in 0..count {
        let wait = wait.clone();
        let spawned = std::thread::Builder::new().spawn(move || {
            // Returns when `release` is dropped.
            let _ = wait.lock().map(|w| w.recv());
        });
        match spawned {
            Ok(handle) => started.push(handle),
            Err(_) => break,
        }
    }
    let all = started.len() == count;
    drop(release);
    for handle in started {
        let _ = handle.join();
    }
    all
}
