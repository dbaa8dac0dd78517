//! `parent` links of `mimo track` outputs (docs/design.md §2): a re-tracked run holds tracks (and
//! re-formed measurements) only, and reads truth and dwells through its manifest's `parent`.
//!
//! * The link is stored **relative to the child's own directory** (`../s7`) and resolved from
//!   there, so a pair of runs can be moved or scored from any working directory. An absolute
//!   link (written by hand) is used as it is.
//! * The link is **checked** ([`ParentCheck`]): the parent's scenario name, seed and a hash of its
//!   `manifest.json` must be those recorded when the child was made; a parent replaced or swapped
//!   since is refused rather than silently scored against.
//! * Chains are followed with a record of the directories seen, so a cycle (a run that is its own
//!   parent, or two runs that name each other) is an error, not unbounded recursion.

use crate::StoreError;
use crate::manifest::{MANIFEST_FILE, Manifest, ParentCheck};
use std::path::{Component, Path, PathBuf};

/// FNV-1a (64-bit) of a run's `manifest.json`, as 16 hex digits. It tells a replaced parent
/// from the one a child was made from; it is not meant to resist deliberate forgery.
pub fn manifest_hash(run_dir: &Path) -> Result<String, StoreError> {
    let path = run_dir.join(MANIFEST_FILE);
    let bytes = std::fs::read(&path).map_err(crate::io_err(&path))?;
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    Ok(format!("{h:016x}"))
}

/// `p` made absolute, with every existing part of it canonical (symbolic links and `..`
/// resolved), whether or not `p` itself exists yet.
pub fn resolve(p: &Path) -> PathBuf {
    if let Ok(c) = p.canonicalize() {
        return c;
    }
    match (p.parent(), p.file_name()) {
        (Some(parent), Some(name)) => {
            let parent = if parent.as_os_str().is_empty() { Path::new(".") } else { parent };
            resolve(parent).join(name)
        }
        _ => std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf()),
    }
}

/// The path of `to` relative to the directory `from` (both absolute and resolved).
fn relative(from: &Path, to: &Path) -> PathBuf {
    let f: Vec<Component<'_>> = from.components().collect();
    let t: Vec<Component<'_>> = to.components().collect();
    let common = f.iter().zip(&t).take_while(|(a, b)| a == b).count();
    let mut out = PathBuf::new();
    for _ in common..f.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c.as_os_str());
    }
    if out.as_os_str().is_empty() { PathBuf::from(".") } else { out }
}

/// Refuse an output that is the input, lies inside it, or holds it: writing it (or replacing it
/// with `--force`) would destroy the input.
pub fn check_output_apart(input: &Path, out: &Path) -> Result<(), StoreError> {
    let (i, o) = (resolve(input), resolve(out));
    let why = if o == i {
        "is the input run directory"
    } else if o.starts_with(&i) {
        "lies inside the input run directory"
    } else if i.starts_with(&o) {
        "holds the input run directory"
    } else {
        return Ok(());
    };
    Err(StoreError::Refused {
        path: out.to_path_buf(),
        why: format!("{why} {}; choose an output outside it", input.display()),
    })
}

/// The `parent` link and its check for a child to be written at `child` from the run `parent`.
pub fn link(child: &Path, parent: &Path, parent_manifest: &Manifest) -> Result<(String, ParentCheck), StoreError> {
    let rel = relative(&resolve(child), &resolve(parent));
    let check = ParentCheck {
        scenario: parent_manifest.scenario.name.clone(),
        seed: parent_manifest.seed,
        manifest_fnv1a64: manifest_hash(parent)?,
    };
    Ok((rel.to_string_lossy().to_string(), check))
}

/// Most links a chain may have (a re-track of a re-track …); far more than any real use.
pub const MAX_CHAIN: usize = 64;

/// Follow `parent` links from `run_dir` (whose manifest is `m`) to the run that holds truth and
/// dwells: `run_dir` itself when it has no parent.
pub fn source_dir(run_dir: &Path, m: &Manifest) -> Result<PathBuf, StoreError> {
    let mut dir = run_dir.to_path_buf();
    let mut manifest = m.clone();
    let mut seen = vec![resolve(&dir)];
    loop {
        let Some(parent) = manifest.parent.clone() else { return Ok(dir) };
        let file = dir.join(MANIFEST_FILE);
        let bad = |why: String| StoreError::BadManifest { file: file.clone(), field: "parent".into(), why };
        let next = dir.join(&parent);
        if !next.join(MANIFEST_FILE).is_file() {
            return Err(bad(format!(
                "run directory '{parent}' (resolved from this run's directory to {}) not found or not a finished run \
                 (expected the run this one was tracked from)",
                next.display()
            )));
        }
        let key = resolve(&next);
        if seen.contains(&key) {
            let chain: Vec<String> = seen.iter().chain([&key]).map(|p| p.display().to_string()).collect();
            return Err(bad(format!("'parent' links form a cycle: {}", chain.join(" -> "))));
        }
        if seen.len() > MAX_CHAIN {
            return Err(bad(format!("more than {MAX_CHAIN} 'parent' links in a chain")));
        }
        seen.push(key);
        let pm = Manifest::read(&next)?;
        if let Some(check) = &manifest.parent_check {
            if pm.scenario.name != check.scenario || pm.seed != check.seed {
                return Err(bad(format!(
                    "'{parent}' holds scenario '{}' seed {}, but this run was tracked from scenario '{}' seed {}",
                    pm.scenario.name, pm.seed, check.scenario, check.seed
                )));
            }
            let h = manifest_hash(&next)?;
            if h != check.manifest_fnv1a64 {
                return Err(bad(format!(
                    "'{parent}' was replaced since this run was tracked from it (its manifest hash is {h}, recorded {}); \
                     re-run `mimo track` on it",
                    check.manifest_fnv1a64
                )));
            }
        }
        dir = next;
        manifest = pm;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relative_paths() {
        assert_eq!(relative(Path::new("/x/t"), Path::new("/x/r")), PathBuf::from("../r"));
        assert_eq!(relative(Path::new("/x/a/t"), Path::new("/y/r")), PathBuf::from("../../../y/r"));
        assert_eq!(relative(Path::new("/x/t"), Path::new("/x/t/r")), PathBuf::from("r"));
    }

    #[test]
    fn outputs_apart_from_the_input() {
        let tmp = tempfile::tempdir().expect("tmp");
        let r = tmp.path().join("r");
        std::fs::create_dir(&r).expect("mkdir");
        assert!(check_output_apart(&r, &r).is_err());
        assert!(check_output_apart(&r, &r.join("sub/x")).is_err());
        assert!(check_output_apart(&r, tmp.path()).is_err());
        assert!(check_output_apart(&r, &tmp.path().join("r2")).is_ok());
        assert!(check_output_apart(&r, &r.join("../r")).is_err());
    }
}
