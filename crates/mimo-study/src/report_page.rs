//! `DIR/report.html`: the study as one self-contained, offline page (docs/studies.md, "The
//! page"; docs/decisions/0310-study-report-page.md). plotly.js is the run viewer's own bundle
//! (`mimo_plot::html::PLOTLY_JS`, which holds the 2-D scatter trace too), inlined with its
//! licence; the data are [`crate::page_data::PageData`] as JSON; the page's content security
//! policy forbids any connection. The page is made from the study's tables alone, so a merge and
//! `mimo study PLAN --out DIR --page` (a study directory holding only its tables, like the
//! shipped ones) write the same page.

use crate::page_data::{PageData, page_data};
use crate::page_tables::PageError;
use crate::plan::Plan;
use mimo_store::layout::StudyDir;
use std::path::{Path, PathBuf};

const TEMPLATE: &str = include_str!("../assets/report.html");
const REPORT_JS: &str = include_str!("../assets/report.js");

/// Escape text for an HTML text node.
fn escape_text(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// Render the page of the data.
pub fn render(data: &PageData) -> Result<String, serde_json::Error> {
    // JSON safe inside a `<script>` element: `</` never appears.
    let json = serde_json::to_string(data)?.replace("</", "<\\/");
    let licence = format!("/*! plotly.js licence:\n{}*/\n", mimo_plot::html::PLOTLY_LICENSE.replace("*/", "* /"));
    // The placeholders are replaced before plotly.js is put in, so nothing inside it is touched.
    let page = TEMPLATE.replace("__TITLE__", &escape_text(&format!("mimo study — {}", data.title)));
    let page = page.replacen("/*__REPORTJS__*/", REPORT_JS, 1);
    let page = page.replacen("__DATA__", &json, 1);
    let (head, tail) = page.split_once("/*__PLOTLY__*/").unwrap_or((page.as_str(), ""));
    let plotly = mimo_plot::html::PLOTLY_JS;
    let mut out = String::with_capacity(head.len() + licence.len() + plotly.len() + tail.len());
    out.push_str(head);
    out.push_str(&licence);
    out.push_str(plotly);
    out.push_str(tail);
    Ok(out)
}

/// Make the page of the study at `dir` (of `plan`, named `plan_arg` in the page's commands) and
/// write it to `DIR/report.html` atomically: a temporary file beside it, then a rename, so a
/// page is whole or absent. On any error nothing is written.
pub fn write_page(plan: &Plan, plan_arg: &str, dir: &Path) -> Result<PathBuf, PageError> {
    let data = page_data(plan, plan_arg, dir)?;
    let path = StudyDir::new(dir).report_html();
    let io = |e: std::io::Error| PageError::Io { path: path.clone(), why: e.to_string() };
    let page = render(&data).map_err(|e| io(std::io::Error::other(e)))?;
    let tmp = mimo_store::output::sibling(&path, "tmp")
        .map_err(|e| PageError::Io { path: path.clone(), why: e.to_string() })?;
    mimo_store::output::register(&tmp);
    let written = std::fs::write(&tmp, page).and_then(|()| std::fs::rename(&tmp, &path)).map_err(io);
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    mimo_store::output::unregister(&tmp);
    written.map(|()| path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_scripts_cannot_close_their_element() {
        assert!(!REPORT_JS.contains("</script"));
        for mark in ["__DATA__", "/*__PLOTLY__*/", "/*__REPORTJS__*/"] {
            assert_eq!(TEMPLATE.matches(mark).count(), 1, "{mark}");
        }
    }
}
