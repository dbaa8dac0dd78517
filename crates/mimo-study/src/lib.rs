//! # mimo-study
//!
//! Studies compare methods side by side: a plan ([`plan::Plan`]) names methods (test articles
//! and their configurations), scenarios, stress axes and Monte Carlo runs; the grid
//! ([`grid`]) makes every (method, scenario, stress point) a cell, each an ordinary run
//! directory in a hive-style path, and every (cell, run) an item that any machine can run
//! (`--shard K/N`). Results, costs and a summary with confidence intervals are Parquet tables;
//! charts and a report page show energy against completeness, compute against accuracy and
//! where each method fails (docs/studies.md); `report.html` shows them in one offline page
//! ([`report_page`]), from which any run can be re-created on its own ([`rerun`]).

#![warn(missing_docs)]

pub mod beams;
pub mod bootstrap;
pub mod challenge;
pub mod challenge_report;
pub mod challenge_table;
pub mod charts;
pub mod cpu;
pub mod estimate;
pub mod execute;
pub mod failure_point;
pub mod failure_report;
pub mod failure_table;
pub mod frontier;
pub mod frontier_energy;
pub mod frontier_steps;
pub mod grid;
pub mod guard;
pub mod inflight;
pub mod item;
pub mod kfu;
pub mod merge;
pub mod method_sweep;
pub mod page_data;
pub mod page_tables;
pub mod paired;
pub mod plan;
mod plan_check;
mod plan_toml;
pub mod prepare;
pub mod record;
pub mod refine;
pub mod report;
pub mod report_page;
pub mod rerun;
pub mod run_usage;
pub mod runner;
pub mod shard_log;
pub mod status;
pub mod study_dir;
pub mod tables;
pub mod timed;

pub use plan::{Plan, PlanError};
pub use runner::{Options, Outcome, StudyError, run_study};
