//! SIGINT and SIGTERM (docs/design.md §7), one handler for every command: kill the process test
//! articles still running, each with its process group (they no longer see the terminal's Ctrl-C,
//! docs/decisions/0325-test-article-process-group.md), remove the staging
//! directories, temporary files and lock files this process is writing (registered by
//! `mimo_store::output`), say so on one `error:` line, and exit with 130 (128 + SIGINT, the
//! shell's convention for an interrupted command). Killed harder (SIGKILL, power loss), a
//! process leaves its staging behind; the next writer of the same output removes it.
//!
//! The handler runs on its own thread while the command's threads go on: writes into a staging
//! directory it has removed fail, and the command returns an error. [`settle`] keeps that error
//! from being reported (and the process from ending with status 1 while the handler is still
//! removing files): once interrupted, the handler alone ends the process.

use std::sync::atomic::{AtomicBool, Ordering};

/// Set by the handler before it removes anything.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// Install the handler once per process (later calls, e.g. from in-process tests, do nothing).
pub fn install() -> Result<(), String> {
    static INSTALLED: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    INSTALLED
        .get_or_init(|| {
            ctrlc::set_handler(|| {
                INTERRUPTED.store(true, Ordering::SeqCst);
                mimo_ta::process::kill_live_groups();
                mimo_store::output::remove_pending();
                eprintln!("error: interrupted; partial output removed");
                std::process::exit(130);
            })
            .map_err(|e| e.to_string())
        })
        .clone()
}

/// After a command has returned: if it was interrupted, wait for the handler, which removes the
/// partial output and ends the process with status 130. Returns at once otherwise.
pub fn settle() {
    while INTERRUPTED.load(Ordering::SeqCst) {
        std::thread::park_timeout(std::time::Duration::from_millis(100));
    }
}
