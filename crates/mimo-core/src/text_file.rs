//! Reading a small text input (a scenario, an included file, a test article's configuration)
//! within a memory budget: only a regular file is opened, and only up to a size limit
//! (docs/design.md §7 "Bounds"). A device (`/dev/zero`), a FIFO (which would block until a
//! writer appears), a socket or a directory is refused before it is opened; a file larger than
//! the limit is refused from its length, and a file that grows while it is read is cut off at the
//! limit and refused too.

use std::io::Read;
use std::path::Path;
use thiserror::Error;

/// Largest text input `mimo` reads (scenario files, each include, test-article configuration
/// files): 1 MiB. The standard scenarios are under 4 KiB; parsing takes about 40 bytes of memory
/// per byte of TOML, so the limit keeps a parse under 50 MB.
pub const MAX_TEXT_FILE_BYTES: u64 = 1 << 20;

/// Why a text input was not read. The messages name no path: callers prefix the file.
#[derive(Debug, Error)]
pub enum TextFileError {
    /// Not a regular file (a FIFO, a device, a socket, a directory).
    #[error("not a regular file ({kind}); expected a text file")]
    NotRegular {
        /// What it is instead.
        kind: &'static str,
    },
    /// Larger than the limit.
    #[error("{bytes} bytes is above the limit of {limit} bytes for a text input")]
    TooLarge {
        /// Its size (or, for a file that grew while read, the limit plus one).
        bytes: u64,
        /// The limit.
        limit: u64,
    },
    /// Not UTF-8 text.
    #[error("not UTF-8 text")]
    NotUtf8,
    /// The operating system could not open or read it.
    #[error("{0}")]
    Io(#[from] std::io::Error),
}

impl TextFileError {
    /// Whether the input is at fault (a wrong kind of file, too large, not text) rather than the
    /// system (a read that failed).
    pub fn is_bad_input(&self) -> bool {
        match self {
            TextFileError::Io(e) => {
                matches!(e.kind(), std::io::ErrorKind::NotFound | std::io::ErrorKind::PermissionDenied)
            }
            _ => true,
        }
    }
}

fn kind_of(t: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "a FIFO";
        }
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() { "a directory" } else { "not a file" }
}

/// Read `path` (following symbolic links) as UTF-8 text of at most `max_bytes` bytes.
pub fn read_text_file(path: &Path, max_bytes: u64) -> Result<String, TextFileError> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(TextFileError::NotRegular { kind: kind_of(meta.file_type()) });
    }
    if meta.len() > max_bytes {
        return Err(TextFileError::TooLarge { bytes: meta.len(), limit: max_bytes });
    }
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    std::fs::File::open(path)?.take(max_bytes + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > max_bytes {
        return Err(TextFileError::TooLarge { bytes: max_bytes + 1, limit: max_bytes });
    }
    String::from_utf8(bytes).map_err(|_| TextFileError::NotUtf8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_small_file_is_read_whole() {
        let d = tempfile::tempdir().expect("tmp");
        let p = d.path().join("a.toml");
        std::fs::write(&p, "x = 1\n").expect("write");
        assert_eq!(read_text_file(&p, 6).expect("read"), "x = 1\n");
    }

    #[test]
    fn a_file_over_the_limit_is_refused_from_its_length() {
        let d = tempfile::tempdir().expect("tmp");
        let p = d.path().join("a.toml");
        std::fs::write(&p, "x = 1\n").expect("write");
        let e = read_text_file(&p, 5).expect_err("too large");
        assert!(matches!(e, TextFileError::TooLarge { bytes: 6, limit: 5 }), "{e}");
        assert!(e.is_bad_input());
    }

    #[test]
    fn a_directory_and_a_device_are_refused_unopened() {
        let d = tempfile::tempdir().expect("tmp");
        let e = read_text_file(d.path(), MAX_TEXT_FILE_BYTES).expect_err("dir");
        assert_eq!(e.to_string(), "not a regular file (a directory); expected a text file");
        #[cfg(unix)]
        {
            let e = read_text_file(Path::new("/dev/zero"), MAX_TEXT_FILE_BYTES).expect_err("device");
            assert_eq!(e.to_string(), "not a regular file (a character device); expected a text file");
        }
    }

    #[test]
    fn binary_and_missing_files_are_named_as_such() {
        let d = tempfile::tempdir().expect("tmp");
        let p = d.path().join("b");
        std::fs::write(&p, [0xff, 0xfe, 0x00]).expect("write");
        assert!(matches!(read_text_file(&p, 100), Err(TextFileError::NotUtf8)));
        let e = read_text_file(&d.path().join("missing"), 100).expect_err("missing");
        assert!(e.is_bad_input(), "{e}");
    }
}
