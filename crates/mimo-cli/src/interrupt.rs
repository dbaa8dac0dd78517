//! SIGINT and SIGTERM (docs/design.md §7): remove the staging directories and lock files this
//! process is writing (registered by `mimo_store::output`), say so on one `error:` line, and exit
//! with 130 (128 + SIGINT, the shell's convention for an interrupted command). Killed harder
//! (SIGKILL, power loss), a process leaves its staging behind; the next writer of the same output
//! removes it.

/// Install the handler once per process (later calls, e.g. from in-process tests, do nothing).
pub fn install() -> Result<(), String> {
    static INSTALLED: std::sync::OnceLock<Result<(), String>> = std::sync::OnceLock::new();
    INSTALLED
        .get_or_init(|| {
            ctrlc::set_handler(|| {
                mimo_store::output::remove_pending();
                eprintln!("error: interrupted; partial output removed");
                std::process::exit(130);
            })
            .map_err(|e| e.to_string())
        })
        .clone()
}
