//! Where everything lives in a run directory and a study directory (docs/design.md §2, §9): the
//! one place that joins a table, a score table or a study file onto a path. Other crates ask a
//! [`RunDir`], a [`ScoreDir`] or a [`StudyDir`] for a path and never spell a file name; a test
//! (`crates/mimo-cli/tests/layout_owner.rs`) fails if they do.
//!
//! ```text
//! RUN/manifest.json                written last: a directory without it is not a finished run
//! RUN/TABLE/run-0000.parquet       one file per table and Monte Carlo run
//! RUN/.items/run-0000.json         a study cell's record of each finished item
//! RUN/score/summary.json, RUN/score/NAME.parquet, RUN/score/charts/
//! STUDY/study.json, plan.toml, runs/CELL/, shards/, results.parquet, costs.parquet,
//! STUDY/summary.parquet, challenge.parquet, challenge_ratios.parquet, charts/, report.md
//! ```

use crate::manifest::MANIFEST_FILE;
use crate::run_file_name;
use crate::schema::TableSpec;
use std::path::{Path, PathBuf};

/// A run directory (a `mimo simulate` or `mimo track` output, or a study cell).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunDir {
    root: PathBuf,
}

impl RunDir {
    /// The run directory at `root`.
    pub fn new(root: impl Into<PathBuf>) -> RunDir {
        RunDir { root: root.into() }
    }

    /// The directory itself.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// `RUN/manifest.json`.
    pub fn manifest(&self) -> PathBuf {
        self.root.join(MANIFEST_FILE)
    }

    /// `RUN/TABLE/`: every run's file of a table.
    pub fn table_dir(&self, table: &str) -> PathBuf {
        self.root.join(table)
    }

    /// `RUN/TABLE/run-K.parquet`.
    pub fn table_file(&self, table: &str, run: u32) -> PathBuf {
        self.root.join(RunDir::table_file_rel(table, run))
    }

    /// `TABLE/run-K.parquet`, relative to the run directory (as the manifest lists it).
    pub fn table_file_rel(table: &str, run: u32) -> String {
        format!("{table}/{}", run_file_name(run))
    }

    /// A file the manifest lists (`TableFile::file`, relative to the run directory).
    pub fn listed(&self, rel: &str) -> PathBuf {
        self.root.join(rel)
    }

    /// Whether `name` is the name of a table's run file (`run-K.parquet`).
    pub fn is_run_file_name(name: &str) -> bool {
        name.strip_prefix("run-")
            .and_then(|r| r.strip_suffix(".parquet"))
            .is_some_and(|k| !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit()))
    }

    /// `RUN/.items/run-K.json`: a study cell's record of item `run`.
    pub fn item_record(&self, run: u32) -> PathBuf {
        self.root.join(".items").join(format!("run-{run:04}.json"))
    }

    /// `RUN/score/`.
    pub fn score(&self) -> ScoreDir {
        ScoreDir::new(self.root.join("score"))
    }
}

/// A score directory (`RUN/score/`, or a staging directory that will become one).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScoreDir {
    root: PathBuf,
}

impl ScoreDir {
    /// The score directory at `root`.
    pub fn new(root: impl Into<PathBuf>) -> ScoreDir {
        ScoreDir { root: root.into() }
    }

    /// The directory itself.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// `score/summary.json`.
    pub fn summary(&self) -> PathBuf {
        self.root.join("summary.json")
    }

    /// `score/NAME.parquet` of a score table ([`crate::score_schema::score_file_name`]).
    pub fn table(&self, spec: &TableSpec) -> PathBuf {
        self.root.join(crate::score_schema::score_file_name(spec))
    }

    /// `score/charts/`.
    pub fn charts(&self) -> PathBuf {
        self.root.join("charts")
    }
}

/// A study directory (docs/studies.md).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StudyDir {
    root: PathBuf,
}

/// The mark file of a study directory.
pub const STUDY_FILE: &str = "study.json";

impl StudyDir {
    /// The study directory at `root`.
    pub fn new(root: impl Into<PathBuf>) -> StudyDir {
        StudyDir { root: root.into() }
    }

    /// The directory itself.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// `STUDY/study.json`, the mark.
    pub fn mark(&self) -> PathBuf {
        self.root.join(STUDY_FILE)
    }

    /// `STUDY/plan.toml`, a copy of the plan.
    pub fn plan(&self) -> PathBuf {
        self.root.join("plan.toml")
    }

    /// `STUDY/runs/`: the cells.
    pub fn runs(&self) -> PathBuf {
        self.root.join("runs")
    }

    /// The run directory of a cell, `rel` its hive-style path under `runs/`.
    pub fn cell(&self, rel: &Path) -> RunDir {
        RunDir::new(self.runs().join(rel))
    }

    /// `STUDY/shards/`: one log per shard.
    pub fn shards(&self) -> PathBuf {
        self.root.join("shards")
    }

    /// `STUDY/NAME.parquet` of a study table (`results`, `costs`, `summary`, `challenge`, …).
    pub fn table(&self, spec: &TableSpec) -> PathBuf {
        self.root.join(format!("{}.parquet", spec.name.trim_start_matches("study_")))
    }

    /// `STUDY/charts/`.
    pub fn charts(&self) -> PathBuf {
        self.root.join("charts")
    }

    /// `STUDY/report.md`.
    pub fn report(&self) -> PathBuf {
        self.root.join("report.md")
    }

    /// `STUDY/report.html`, the study as one offline page.
    pub fn report_html(&self) -> PathBuf {
        self.root.join("report.html")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_follow_the_documented_layout() {
        let r = RunDir::new("out/s7");
        assert_eq!(r.manifest(), Path::new("out/s7/manifest.json"));
        assert_eq!(r.table_file("tracks", 12), Path::new("out/s7/tracks/run-0012.parquet"));
        assert_eq!(RunDir::table_file_rel("truth", 0), "truth/run-0000.parquet");
        assert_eq!(r.score().summary(), Path::new("out/s7/score/summary.json"));
        assert_eq!(r.item_record(3), Path::new("out/s7/.items/run-0003.json"));
        assert!(RunDir::is_run_file_name("run-0003.parquet") && !RunDir::is_run_file_name("run-.parquet"));
        let s = StudyDir::new("st");
        assert_eq!(
            s.cell(Path::new("method=a/scenario=7")).manifest(),
            Path::new("st/runs/method=a/scenario=7/manifest.json")
        );
        assert_eq!(s.mark(), Path::new("st/study.json"));
    }
}
