//! Any text to the scenario parser: a scenario or a one-line error naming the file, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        if let Err(e) = mimo_scenario::load_str(text, "fuzz.toml", None) {
            assert!(!e.to_string().contains('\n'));
        }
    }
});
