//! Values quoted in error lines, bounded (docs/design.md §7): a bad value may be megabytes long
//! (a label column holding a whole document, a test article's runaway reply), and an error line
//! shows at most a prefix of it and says where it was cut.

/// The most bytes of a value an error line quotes.
pub const QUOTE_MAX_BYTES: usize = 80;

/// The longest prefix of `s` of at most `max` bytes that ends on a character boundary.
fn prefix(s: &str, max: usize) -> &str {
    let mut end = max.min(s.len());
    while !s.is_char_boundary(end) {
        end -= 1;
    }
    &s[..end]
}

/// `'value'`, or for a value longer than [`QUOTE_MAX_BYTES`] its prefix and where it was cut:
/// `'abc…' (cut after 80 of 52428800 bytes)`. Control characters are shown escaped, so the
/// quote stays on one line.
pub fn quoted(s: &str) -> String {
    let shown = prefix(s, QUOTE_MAX_BYTES);
    let escaped: String =
        shown.chars().flat_map(|c| if c.is_control() { c.escape_default().collect() } else { vec![c] }).collect();
    if shown.len() == s.len() {
        format!("'{escaped}'")
    } else {
        format!("'{escaped}…' (cut after {} of {} bytes)", shown.len(), s.len())
    }
}

/// A whole message (which may embed a value, e.g. a parser's) cut to at most `max` bytes, with
/// where it was cut.
pub fn bounded(s: &str, max: usize) -> String {
    let shown = prefix(s, max);
    if shown.len() == s.len() {
        s.to_string()
    } else {
        format!("{shown}… (cut after {} of {} bytes)", shown.len(), s.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_values_whole_long_ones_cut_and_said() {
        assert_eq!(quoted("bogus"), "'bogus'");
        let long = "x".repeat(50 * 1024 * 1024);
        let q = quoted(&long);
        assert!(q.len() < 200, "{} bytes", q.len());
        assert!(q.ends_with("…' (cut after 80 of 52428800 bytes)"), "{q}");
        // A cut never splits a character; a newline stays on the line.
        let accents = "é".repeat(100);
        assert!(quoted(&accents).contains("cut after 80 of 200 bytes"));
        assert_eq!(quoted("a\nb"), "'a\\nb'");
        assert_eq!(bounded("short", 10), "short");
        assert_eq!(bounded("0123456789abc", 10), "0123456789… (cut after 10 of 13 bytes)");
    }
}
