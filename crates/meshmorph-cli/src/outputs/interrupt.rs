//! Signals that would end the process (SIGINT, SIGTERM, SIGHUP, SIGQUIT,
//! SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGXCPU): an interrupted run
//! removes what it staged and the folders it created, then exits with
//! status 128 + the signal's number, as shells report a process the signal
//! ended (130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP, 131 for
//! SIGQUIT). SIGXFSZ (a file past `ulimit -f`) does not end the run: the
//! write fails with "File too large" and the run fails as on a full disk,
//! removing what it staged.
//!
//! Writers hold [`writing`] (a shared lock) while they write one file; the
//! handler first marks the run interrupted, so that no new write starts,
//! then takes the lock exclusively (waiting for the writes in progress to
//! finish or fail, which leaves no temporary file of theirs behind),
//! removes the staged files and exits. The commit holds the lock
//! exclusively, so an interrupt never cuts it in half.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Mutex, RwLock, RwLockReadGuard, RwLockWriteGuard};

use anyhow::{bail, Result};

static INTERRUPTED: AtomicBool = AtomicBool::new(false);
/// Every output of the run is in place (see [`committed`]).
static COMMITTED: AtomicBool = AtomicBool::new(false);
static AS_JSON: AtomicBool = AtomicBool::new(false);
static GATE: RwLock<()> = RwLock::new(());
static PENDING: Mutex<Option<Cleanup>> = Mutex::new(None);
static ABANDONING: AtomicBool = AtomicBool::new(false);

/// What a run must undo if it does not commit.
#[derive(Clone, Debug, Default)]
pub(super) struct Cleanup {
    /// Staged files (they may not exist yet).
    pub staged: Vec<PathBuf>,
    /// Staged folders (hidden, made by the run), removed with what they hold.
    pub folders: Vec<PathBuf>,
}

impl Cleanup {
    pub fn run(&self) {
        let mut dirs: Vec<&std::path::Path> = Vec::new();
        for p in &self.staged {
            let _ = std::fs::remove_file(p);
            if let Some(dir) = p.parent().filter(|d| !dirs.contains(d)) {
                dirs.push(dir);
            }
        }
        // What a writer of this process was writing there when the run was
        // abandoned (out of memory: no unwinding removes it).
        for dir in dirs {
            // A file named without a folder is in the current one.
            let dir = if dir.as_os_str().is_empty() {
                std::path::Path::new(".")
            } else {
                dir
            };
            meshmorph::io::remove_own_temporaries(dir);
        }
        for dir in &self.folders {
            // Not followed if it is a link: only the link goes.
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}

/// Installs the handler (once; later calls do nothing).
pub fn install() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // Without a handler (it cannot be installed) the default action
        // still stops the run; staged files would then remain, so say so.
        if let Err(e) = listen() {
            tell!("warning: cannot catch Ctrl-C ({e}): an interrupted run may leave its hidden unfinished files behind, which the next run into the folder removes");
        }
    });
}

/// Calls [`on_interrupt`] from a thread of its own when a signal comes.
#[cfg(unix)]
fn listen() -> std::io::Result<()> {
    use signal_hook::consts::{
        SIGALRM, SIGHUP, SIGINT, SIGQUIT, SIGTERM, SIGUSR1, SIGUSR2, SIGVTALRM, SIGXCPU, SIGXFSZ,
    };
    // Caught and ignored: the write past the limit then fails as an error.
    signal_hook::flag::register(SIGXFSZ, std::sync::Arc::new(AtomicBool::new(false)))?;
    let mut signals = signal_hook::iterator::Signals::new([
        SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGXCPU,
    ])?;
    std::thread::Builder::new()
        .name("interrupt".into())
        .spawn(move || {
            if let Some(signal) = signals.forever().next() {
                on_interrupt(128 + signal);
            }
        })?;
    Ok(())
}

/// Calls [`on_interrupt`] from a thread of its own on Ctrl-C (or Ctrl-Break
/// or the console closing): the status of SIGINT.
#[cfg(not(unix))]
fn listen() -> Result<(), ctrlc::Error> {
    ctrlc::set_handler(|| on_interrupt(130))
}

/// With `json`, an interrupt also prints its message as a JSON error on
/// stdout (see [`crate::output::print_json_error`]).
pub fn interrupted_as_json(json: bool) {
    AS_JSON.store(json, Ordering::SeqCst);
}

fn on_interrupt(status: i32) {
    INTERRUPTED.store(true, Ordering::SeqCst);
    let _exclusive = GATE.write().unwrap_or_else(|e| e.into_inner());
    let pending = PENDING.lock().unwrap_or_else(|e| e.into_inner()).take();
    stop(&format!("interrupted: {}", undo(pending)), status);
}

/// Ends the run at once on a failure that cannot be returned (a failed
/// allocation): no new write starts, the staged files and created folders
/// are removed, `message` is said and the process exits with status 1.
/// The interrupt's hold is not taken: the failing thread may be writing.
pub fn abandon(message: &str) -> ! {
    // Threads failing together (the frames are drawn on every core): the
    // first removes the staged files and ends the process; the others wait
    // for it, instead of finding nothing left to undo and ending the
    // process while the first is still removing.
    if ABANDONING.swap(true, Ordering::SeqCst) {
        loop {
            std::thread::park();
        }
    }
    INTERRUPTED.store(true, Ordering::SeqCst);
    let pending = match PENDING.try_lock() {
        Ok(mut p) => p.take(),
        Err(std::sync::TryLockError::Poisoned(e)) => e.into_inner().take(),
        Err(std::sync::TryLockError::WouldBlock) => None,
    };
    let said = format!("error: {message}; {}", undo(pending.clone()));
    tell!("{said}");
    if AS_JSON.load(Ordering::SeqCst) {
        crate::output::print_json_error(&said, 1);
    }
    // A writer that had started before the run was marked may have made
    // its temporary file since: removed again just before the end.
    if let Some(cleanup) = pending {
        cleanup.run();
    }
    std::process::exit(1);
}

/// Removes what `pending` staged; says what became of the run's outputs.
fn undo(pending: Option<Cleanup>) -> &'static str {
    match pending {
        Some(cleanup) => {
            cleanup.run();
            "this run's outputs were removed (none had been moved into place)"
        }
        None if COMMITTED.load(Ordering::SeqCst) => {
            "every output of this run had been moved into place: they are all written"
        }
        None => "no output of the current run was written",
    }
}

/// Says `message` (also as JSON with `--json`) and exits with `status`.
fn stop(message: &str, status: i32) -> ! {
    tell!("{message}");
    if AS_JSON.load(Ordering::SeqCst) {
        crate::output::print_json_error(message, status);
    }
    std::process::exit(status);
}

/// A shared hold on writing one file; refused once the run is interrupted.
pub(super) fn writing() -> Result<RwLockReadGuard<'static, ()>> {
    let guard = GATE.read().unwrap_or_else(|e| e.into_inner());
    if INTERRUPTED.load(Ordering::SeqCst) {
        bail!("interrupted");
    }
    Ok(guard)
}

/// An exclusive hold, for the commit; refused once the run is interrupted.
pub(super) fn exclusive() -> Result<RwLockWriteGuard<'static, ()>> {
    let guard = GATE.write().unwrap_or_else(|e| e.into_inner());
    if INTERRUPTED.load(Ordering::SeqCst) {
        bail!("interrupted");
    }
    Ok(guard)
}

/// Registers what an interrupt must undo (replacing an earlier run's).
pub(super) fn arm(cleanup: Cleanup) {
    *PENDING.lock().unwrap_or_else(|e| e.into_inner()) = Some(cleanup);
}

/// Every output is in place: nothing to undo, and an interrupt says so.
pub(super) fn committed() {
    COMMITTED.store(true, Ordering::SeqCst);
    disarm();
}

/// Nothing left to undo: committed, or already cleaned up.
pub(super) fn disarm() {
    *PENDING.lock().unwrap_or_else(|e| e.into_inner()) = None;
}
