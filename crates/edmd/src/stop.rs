//! Ctrl-C, SIGTERM and SIGHUP as a flag: a front door installs the handler before any work
//! ([`install_ctrlc`]), and every long loop looks at [`stop_requested`] at least every tenth of
//! a second or so, then ends cleanly (temporary files removed, what was promised on a stop
//! written).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Result;

static STOP: AtomicBool = AtomicBool::new(false);
/// Set when the command has seen [`STOP`] (through [`stop_requested`]).
static NOTICED: AtomicBool = AtomicBool::new(false);
/// Set by [`stop_promptly`]: the command must end within [`STOP_GRACE`] of a signal.
static PROMPT: AtomicBool = AtomicBool::new(false);

/// How long a command that asked to stop promptly may take to notice a signal before the
/// program ends without it. Every loop of such a command looks at the flag at least every
/// tenth of a second or so; this covers the steps that cannot look (reading a large file,
/// building a large simulation, drawing one large frame). 800 ms leaves the program the rest
/// of the second it promises to end in.
pub const STOP_GRACE: std::time::Duration = std::time::Duration::from_millis(800);

/// Makes Ctrl-C (SIGINT), SIGTERM and SIGHUP ask the running command to stop: an experiment
/// then writes what it measured so far, `run` and `render` abandon the run and remove their
/// temporary files. A second signal removes the temporary files and ends the program at once
/// (exit status [`crate::INTERRUPTED_STATUS`]). Commands install it before any work, so that a
/// signal is never met by the default action, which would leave temporary files.
pub fn install_ctrlc() {
    let _ = ctrlc::set_handler(|| {
        if STOP.swap(true, Ordering::SeqCst) {
            end_now("interrupted again: stopped at once");
        }
        eprintln!("\nstopping (Ctrl-C again to quit at once)");
        if PROMPT.load(Ordering::SeqCst) {
            // The handler runs on its own thread; the deadline gets another so that a second
            // Ctrl-C is still heard at once.
            std::thread::spawn(|| {
                std::thread::sleep(STOP_GRACE);
                if !NOTICED.load(Ordering::SeqCst) {
                    end_now(
                        "interrupted in a step that cannot stop half-way: nothing more written",
                    );
                }
            });
        }
    });
}

/// Also makes the program end by itself (temporary files removed, exit status
/// [`crate::INTERRUPTED_STATUS`]) when the command has not noticed a stop request within
/// [`STOP_GRACE`]. For `run`, `render`, `soak` and the experiments, whose loops all look at the
/// flag; not for `edmd pack`, which stops at its next velocity rescaling to write a checkpoint
/// however long that takes.
pub fn stop_promptly() {
    PROMPT.store(true, Ordering::SeqCst);
}

/// Ends the program on a signal: temporary files and a folder this run created (if still
/// empty) removed, one line, exit status 130.
fn end_now(why: &str) -> ! {
    crate::output::remove_temporaries();
    remove_created_dirs();
    eprintln!("edmd: {why}");
    std::process::exit(crate::INTERRUPTED_STATUS.into());
}

/// True once Ctrl-C (SIGTERM, SIGHUP) has been pressed.
pub fn stop_requested() -> bool {
    let stop = STOP.load(Ordering::SeqCst);
    if stop {
        NOTICED.store(true, Ordering::SeqCst);
    }
    stop
}

/// Runs `work` on a thread of its own and waits for it, looking at the stop flag meanwhile:
/// `None` when a stop was requested first (the thread is left to the end of the program). For
/// the steps of an experiment that the engine runs in one call (generating and melting a large
/// fluid, building a large simulation), so that a signal there still lets the experiment write
/// the results of the steps before.
pub fn interruptible<T: Send + 'static>(
    work: impl FnOnce() -> T + Send + 'static,
) -> Result<Option<T>> {
    use std::sync::mpsc::RecvTimeoutError;
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::Builder::new()
        .spawn(move || {
            let _ = tx.send(work());
        })
        .map_err(|e| anyhow::anyhow!("cannot start a thread: {e}"))?;
    loop {
        if stop_requested() {
            return Ok(None);
        }
        match rx.recv_timeout(std::time::Duration::from_millis(20)) {
            Ok(x) => return Ok(Some(x)),
            Err(RecvTimeoutError::Timeout) => {}
            Err(RecvTimeoutError::Disconnected) => {
                anyhow::bail!("internal error: a step of the experiment ended without a result")
            }
        }
    }
}

/// The output folders this run created, the deepest first: removed again, each only if
/// empty, when the command fails or is stopped ([`remove_created_dirs`]).
static CREATED_DIRS: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Makes the folder `dir` and those above it that do not exist, remembering each one made,
/// so that a command that fails leaves none of them behind ([`remove_created_dirs`]).
pub fn create_dir_remembered(dir: &Path) -> std::io::Result<()> {
    let missing = crate::output::missing_folders(dir);
    // Remembered before they are made: a creation that fails half-way leaves some.
    if let Ok(mut c) = CREATED_DIRS.lock() {
        c.extend(missing);
    }
    std::fs::create_dir_all(dir)
}

/// Removes the folders [`create_dir_remembered`] made that are still empty, the deepest first.
pub fn remove_created_dirs() {
    if let Ok(mut c) = CREATED_DIRS.try_lock() {
        for d in c.drain(..) {
            let _ = std::fs::remove_dir(d);
        }
    }
}
