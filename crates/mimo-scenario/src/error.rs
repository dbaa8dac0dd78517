//! The one error type of this crate.

use thiserror::Error;

/// Everything that can go wrong while loading, validating or flying a scenario.
///
/// Every message is one line and names the file (and where the parser knows it, the line and
/// column), the field, and what was expected, so the CLI can print it after `error:` as is.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ScenarioError {
    /// `load_standard(n)` with an `n` outside the standard set.
    #[error(
        "unknown standard scenario {number}: expected a number from 1 to {max} \
         (or the path of a scenario TOML file)"
    )]
    UnknownScenario {
        /// The number asked for.
        number: u32,
        /// The highest standard scenario number (the set is 1 to `max`).
        max: u32,
    },

    /// A scenario file (or one it includes) could not be read.
    #[error("{file}: cannot read scenario file: {message}")]
    Io {
        /// The path of the file that could not be read.
        file: String,
        /// The operating system's message (and, for an include, the file that included it).
        message: String,
    },

    /// The file is not valid TOML.
    #[error("{file}:{line}:{column}: TOML syntax error: {message}")]
    Syntax {
        /// The file, as its path, `builtin:NAME` or the name given to `load_str`.
        file: String,
        /// Line of the error in `file`, 1-based.
        line: usize,
        /// Column of the error in `line`, 1-based (in characters).
        column: usize,
        /// The TOML parser's message, on one line.
        message: String,
    },

    /// A key the scenario format does not know (typos are never silently ignored).
    #[error("{file}:{line}:{column}: {message}")]
    UnknownField {
        /// The file, as its path, `builtin:NAME` or the name given to `load_str`.
        file: String,
        /// Line of the error in `file`, 1-based.
        line: usize,
        /// Column of the error in `line`, 1-based (in characters).
        column: usize,
        /// The offending key.
        field: String,
        /// The parser's message, which lists the keys allowed there.
        message: String,
    },

    /// Valid TOML of the wrong shape: a wrong type, a missing field, an unknown variant.
    #[error("{file}:{line}:{column}: {message}")]
    Schema {
        /// The file, as its path, `builtin:NAME` or the name given to `load_str`.
        file: String,
        /// Line of the error in `file`, 1-based.
        line: usize,
        /// Column of the error in `line`, 1-based (in characters).
        column: usize,
        /// The parser's message: what was found and what was expected.
        message: String,
    },

    /// A value that parses but is impossible or inconsistent (latitude 95°, negative speed, no
    /// targets, an unknown target id, overlapping manoeuvres, …).
    #[error("{file}: {field}: expected {expected}")]
    Invalid {
        /// The file (path, `builtin:NAME` or the name given to `load_str`), or "scenario `NAME`"
        /// when `Scenario::validate` checks a scenario that was not read from a file.
        file: String,
        /// Dotted path of the field, e.g. `ships[1].lat_deg`.
        field: String,
        /// What a valid value would be, e.g. `a longitude between -180 and 180 degrees, got 190`.
        expected: String,
    },

    /// An `include` entry that cannot be followed (missing built-in, cycle).
    #[error("{file}: include `{include}`: {reason}")]
    Include {
        /// The file holding the `include` entry.
        file: String,
        /// The `include` entry as written.
        include: String,
        /// Why it cannot be followed.
        reason: String,
    },

    /// A trajectory leaves its aircraft type's flight envelope (speed or acceleration), found
    /// when the trajectories are built.
    #[error("target {target} leaves its flight envelope at t = {t_s:.2} s: {what}")]
    Envelope {
        /// Id of the target.
        target: String,
        /// Time of the first step outside the envelope (s since scenario start).
        t_s: f64,
        /// What is out of bounds, with the value and the limits.
        what: String,
    },
}

impl ScenarioError {
    pub(crate) fn invalid(file: &str, field: impl Into<String>, expected: impl Into<String>) -> ScenarioError {
        ScenarioError::Invalid { file: file.to_string(), field: field.into(), expected: expected.into() }
    }
}

/// 1-based line and column of a byte offset in `text`.
pub(crate) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let offset = offset.min(text.len());
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before.get(line_start..).map_or(0, |s| s.chars().count()) + 1;
    (line, column)
}

/// Turn a `toml` deserialization error into one of our variants. `syntax` says whether the error
/// came from parsing the document (grammar) or from mapping it onto the scenario format.
pub(crate) fn from_toml(file: &str, text: &str, err: &toml::de::Error, syntax: bool) -> ScenarioError {
    let (line, column) = err.span().map_or((1, 1), |s| line_column(text, s.start));
    let message = one_line(err.message());
    let file = file.to_string();
    if syntax {
        return ScenarioError::Syntax { file, line, column, message };
    }
    // Name the key the error sits at (`duration_s: invalid type: …`), not just its place.
    let at = err.span().and_then(|s| crate::toml_path::key_path_at(text, s.start));
    let with_key = |m: String| at.as_ref().map_or(m.clone(), |k| format!("{k}: {m}"));
    if let Some(rest) = message.strip_prefix("unknown field `") {
        let field = rest.split('`').next().unwrap_or_default().to_string();
        return ScenarioError::UnknownField { file, line, column, field, message: with_key(message) };
    }
    ScenarioError::Schema { file, line, column, message: with_key(message) }
}

/// Collapse a possibly multi-line message onto one line.
pub(crate) fn one_line(s: &str) -> String {
    s.lines().map(str::trim).filter(|l| !l.is_empty()).collect::<Vec<_>>().join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_and_column_are_one_based() {
        let t = "a = 1\nbb = 2\n";
        assert_eq!(line_column(t, 0), (1, 1));
        assert_eq!(line_column(t, 6), (2, 1));
        assert_eq!(line_column(t, 8), (2, 3));
        assert_eq!(line_column(t, 1000), (3, 1));
    }
}
