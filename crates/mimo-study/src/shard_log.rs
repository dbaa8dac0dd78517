//! What each shard of a study did: `DIR/shards/shard-K-of-N.json`, written when shard `K/N`
//! starts and again when it stops, so that `--status` can tell a shard that finished from one
//! that never started, stopped on an error, or was killed (started, never stopped) — and so
//! that the study knows its shard count without being told. The file is informative only: what
//! is done is what has an item record (`crate::record`).

use crate::grid::Shard;
use mimo_store::layout::StudyDir;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// One shard's last known state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardState {
    /// The shard (0-based).
    pub k: usize,
    /// Number of shards.
    pub n: usize,
    /// The machine it ran on.
    pub host: String,
    /// Its process id there.
    pub pid: u32,
    /// When it started (seconds since 1970, UTC).
    pub started_unix_s: u64,
    /// When it stopped, if it did.
    pub stopped_unix_s: Option<u64>,
    /// Items it ran (when stopped).
    pub ran: usize,
    /// Items of those whose method failed (when stopped).
    pub failed: usize,
    /// The system fault that stopped it, if any.
    pub error: Option<String>,
}

/// Seconds since 1970.
pub fn now_unix_s() -> u64 {
    std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs())
}

/// This machine's name.
pub fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "unknown".into())
}

/// The file of shard `s` in the study directory `out`.
pub fn shard_path(out: &Path, s: Shard) -> PathBuf {
    StudyDir::new(out).shards().join(format!("shard-{}-of-{}.json", s.k, s.n))
}

impl ShardState {
    /// The state of shard `s` starting now in this process.
    pub fn starting(s: Shard) -> ShardState {
        ShardState {
            k: s.k,
            n: s.n,
            host: host_name(),
            pid: std::process::id(),
            started_unix_s: now_unix_s(),
            stopped_unix_s: None,
            ran: 0,
            failed: 0,
            error: None,
        }
    }

    /// Write it (temporary file, then rename).
    pub fn write(&self, out: &Path) -> std::io::Result<()> {
        let path = shard_path(out, Shard { k: self.k, n: self.n });
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        let tmp = path.with_extension(format!("json.tmp-{}", std::process::id()));
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        std::fs::write(&tmp, text + "\n")?;
        std::fs::rename(&tmp, &path)
    }
}

/// Every readable shard file of the study `out` (files that do not parse are skipped: they are
/// informative only).
pub fn read_all(out: &Path) -> Vec<ShardState> {
    let Ok(entries) = std::fs::read_dir(StudyDir::new(out).shards()) else { return Vec::new() };
    let mut all: Vec<ShardState> = entries
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".json"))
        .filter_map(|e| std::fs::read_to_string(e.path()).ok())
        .filter_map(|t| serde_json::from_str(&t).ok())
        .collect();
    all.sort_by_key(|s: &ShardState| (s.n, s.k));
    all
}

/// The shard count of the latest split of `out` (the `N` of the shard that started last).
pub fn latest_n(states: &[ShardState]) -> Option<usize> {
    states.iter().max_by_key(|s| (s.started_unix_s, s.n)).map(|s| s.n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn states_round_trip_and_the_latest_split_wins() {
        let tmp = tempfile::tempdir().expect("tmp");
        assert!(read_all(tmp.path()).is_empty());
        let mut a = ShardState::starting(Shard { k: 1, n: 4 });
        a.started_unix_s = 100;
        a.write(tmp.path()).expect("write");
        let mut b = ShardState::starting(Shard { k: 0, n: 3 });
        b.started_unix_s = 200;
        b.stopped_unix_s = Some(260);
        b.ran = 5;
        b.write(tmp.path()).expect("write");
        std::fs::write(StudyDir::new(tmp.path()).shards().join("junk.json"), "{").expect("junk");
        let all = read_all(tmp.path());
        assert_eq!(all, vec![b.clone(), a]);
        assert_eq!(latest_n(&all), Some(3));
        assert!(shard_path(tmp.path(), Shard { k: 0, n: 3 }).is_file());
    }
}
