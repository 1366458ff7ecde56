//! Where the work runs: the module's own thread pool, rebuilt in a process
//! forked from the one that built it, and long calls that stop between
//! frames when Python has a signal to handle (Ctrl-C).
//!
//! rayon's global pool does not survive `fork` (its threads stay in the
//! parent, and a child's first parallel call waits for them forever), and
//! `multiprocessing` forks by default on Linux. Every parallel call of the
//! library runs inside [`pool`], which is built again when the process id
//! is not the one that built it; the library's `par_iter` and
//! `rayon::join` then use it. Calls that the library runs on one thread
//! (`at`, `apply`, `solve`) need no pool.

use std::sync::atomic::{AtomicBool, AtomicPtr, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use pyo3::prelude::*;

use crate::MeshmorphError;

/// The pool and the process that built it.
struct Slot {
    pid: u32,
    pool: rayon::ThreadPool,
}

/// This process's [`Slot`], or one inherited through `fork` (or null).
/// Slots are never freed: one inherited from a parent is left as it is
/// (its threads are not in this process, and dropping it would wait on
/// locks they may have held).
static POOL: AtomicPtr<Slot> = AtomicPtr::new(std::ptr::null_mut());

/// How often a long call checks for signals.
const SIGNAL_CHECK: Duration = Duration::from_millis(20);

/// The thread pool of this process: as many threads as rayon's default
/// (`RAYON_NUM_THREADS`, else one a core), one when no more can start.
fn pool() -> PyResult<&'static rayon::ThreadPool> {
    let pid = std::process::id();
    let seen = POOL.load(Ordering::Acquire);
    // SAFETY: a non-null `POOL` points at a leaked `Slot`, never freed.
    if let Some(slot) = unsafe { seen.as_ref() } {
        if slot.pid == pid {
            return Ok(&slot.pool);
        }
    }
    let build = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|k| format!("meshmorph-{k}"))
            .build()
    };
    let pool = build(0)
        .or_else(|_| build(1))
        .map_err(|e| MeshmorphError::new_err(format!("could not start threads: {e}")))?;
    let slot: &'static mut Slot = Box::leak(Box::new(Slot { pid, pool }));
    match POOL.compare_exchange(seen, slot, Ordering::AcqRel, Ordering::Acquire) {
        Ok(_) => Ok(&slot.pool),
        Err(other) => {
            // Another thread of this process built one first: use that,
            // and end this one's threads.
            // SAFETY: `slot` was leaked above and never published.
            drop(unsafe { Box::from_raw(slot as *mut Slot) });
            // SAFETY: as above, a published slot is never freed.
            Ok(unsafe { &(*other).pool })
        }
    }
}

/// `f` in the pool, the GIL released.
pub fn run<R: Send>(py: Python<'_>, f: impl FnOnce() -> R + Send) -> PyResult<R> {
    let pool = pool()?;
    Ok(py.detach(|| pool.install(f)))
}

/// Set when a long call is to stop: work checks it between frames.
pub struct Stop(AtomicBool);

impl Stop {
    pub fn is_set(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// `f` in the pool, the GIL released, while this thread checks for signals
/// every few milliseconds (taking the GIL for the check): when a handler
/// raises (KeyboardInterrupt for Ctrl-C), `f` is told to stop through its
/// [`Stop`], and once it has returned the exception is raised and what it
/// made is dropped.
pub fn run_stoppable<R: Send>(py: Python<'_>, f: impl FnOnce(&Stop) -> R + Send) -> PyResult<R> {
    let stop = Stop(AtomicBool::new(false));
    if rayon::current_thread_index().is_some() {
        // Called from the pool's own threads (a progress callback): no
        // signal reaches them, and waiting here would hold a thread the
        // work needs.
        return Ok(py.detach(|| f(&stop)));
    }
    let pool = pool()?;
    py.detach(|| {
        let mut interrupted: Option<PyErr> = None;
        let mut result = None;
        pool.in_place_scope(|scope| {
            let (sender, receiver) = mpsc::channel();
            let stop = &stop;
            scope.spawn(move |_| {
                // The receiver waits for this, or has gone with a panic.
                let _ = sender.send(f(stop));
            });
            loop {
                match receiver.recv_timeout(SIGNAL_CHECK) {
                    Ok(r) => {
                        result = Some(r);
                        break;
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) if interrupted.is_none() => {
                        if let Err(e) = Python::attach(|py| py.check_signals()) {
                            interrupted = Some(e);
                            stop.0.store(true, Ordering::Relaxed);
                        }
                    }
                    Err(mpsc::RecvTimeoutError::Timeout) => {}
                    // `f` panicked: the scope raises it.
                    Err(mpsc::RecvTimeoutError::Disconnected) => break,
                }
            }
        });
        match (interrupted, result) {
            (Some(e), _) => Err(e),
            (None, Some(r)) => Ok(r),
            (None, None) => unreachable!("the scope re-raises a panic of the work"),
        }
    })
}
