//! The page: one self-contained HTML file with plotly.js (the gl3d partial bundle, MIT, shipped
//! in `assets/`), the view's data as JSON and the page's script. Nothing is fetched when the
//! page is viewed; its content security policy forbids any connection.

use crate::view::View;

/// plotly.js 4.1.1, gl3d partial bundle (scatter, scatter3d, mesh3d, …), minified (MIT).
pub const PLOTLY_JS: &str = include_str!("../assets/plotly-gl3d.min.js");
/// plotly.js licence, repeated in the page.
pub const PLOTLY_LICENSE: &str = include_str!("../assets/LICENSE-plotly.js");
const TEMPLATE: &str = include_str!("../assets/view.html");
/// V8's magic comment asking for every function of a script to be compiled eagerly.
const COMPILE_HINT: &str = "//# allFunctionsCalledOnLoad";
const VIEW_JS: &str = include_str!("../assets/view.js");

/// Escape text for an HTML text node.
fn escape_text(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// JSON safe inside a `<script>` element: `</` never appears.
fn script_json(json: &str) -> String {
    json.replace("</", "<\\/")
}

/// Columns only the click panel and the selection's ellipsoid read. They go into a second
/// data element that the page parses on the first click, not at opening (about half the data).
pub const DETAIL_COLUMNS: [(&str, &[&str]); 3] = [
    ("tracks", &["v", "ax", "n", "truth", "tk"]),
    ("meas", &["id", "ax", "trk", "hint", "merged"]),
    ("beams", &["gid", "np", "e"]),
];

/// Split the view's JSON into what the page draws from and the click details
/// ([`DETAIL_COLUMNS`] and the truth velocities, as `truth: [v, …]` in target order).
pub fn split_view(view: &View) -> Result<(serde_json::Value, serde_json::Value), serde_json::Error> {
    use serde_json::{Map, Value};
    let mut main = serde_json::to_value(view)?;
    let mut detail = Map::new();
    for (table, cols) in DETAIL_COLUMNS {
        let mut d = Map::new();
        if let Some(t) = main.get_mut(table).and_then(Value::as_object_mut) {
            for c in cols {
                if let Some(v) = t.remove(*c) {
                    d.insert((*c).to_string(), v);
                }
            }
        }
        detail.insert(table.to_string(), Value::Object(d));
    }
    let truth_v: Vec<Value> = main
        .get_mut("truth")
        .and_then(Value::as_array_mut)
        .map(|a| a.iter_mut().filter_map(|p| p.as_object_mut().and_then(|o| o.remove("v"))).collect())
        .unwrap_or_default();
    detail.insert("truth".to_string(), Value::Array(truth_v));
    Ok((main, Value::Object(detail)))
}

/// Render the page of a view.
pub fn render(view: &View) -> Result<String, serde_json::Error> {
    let (main, detail) = split_view(view)?;
    let data = script_json(&serde_json::to_string(&main)?);
    let detail = script_json(&serde_json::to_string(&detail)?);
    let title = escape_text(&format!("mimo plot — {} run {}", view.meta.scenario, view.meta.run));
    // V8's explicit compile hint (a plain comment to other engines), first in the script: every
    // function of plotly.js is compiled with the script instead of at its first call, which
    // shortened plotly.js's load by about a quarter in Chromium (docs/decisions/0017-run-viewer-opening-cuts.md).
    let licence = format!("{COMPILE_HINT}\n/*! plotly.js licence:\n{}*/\n", PLOTLY_LICENSE.replace("*/", "* /"));
    // Replace the script placeholders last, so nothing inside plotly.js or the data is touched.
    let page = TEMPLATE.replace("__TITLE__", &title);
    let page = page.replacen("/*__VIEWJS__*/", VIEW_JS, 1);
    let page = page.replacen("__DETAIL__", &detail, 1);
    let page = page.replacen("__DATA__", &data, 1);
    let (head, tail) = page.split_once("/*__PLOTLY__*/").unwrap_or((page.as_str(), ""));
    let mut out = String::with_capacity(head.len() + licence.len() + PLOTLY_JS.len() + tail.len());
    out.push_str(head);
    out.push_str(&licence);
    out.push_str(PLOTLY_JS);
    out.push_str(tail);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn embedded_scripts_cannot_close_their_element() {
        assert!(!PLOTLY_JS.contains("</script"));
        assert!(!VIEW_JS.contains("</script"));
        assert_eq!(script_json(r#"{"a":"</script>"}"#), r#"{"a":"<\/script>"}"#);
        assert_eq!(TEMPLATE.matches("__DATA__").count(), 1);
        assert_eq!(TEMPLATE.matches("__DETAIL__").count(), 1);
        assert_eq!(TEMPLATE.matches("/*__PLOTLY__*/").count(), 1);
        assert_eq!(TEMPLATE.matches("/*__VIEWJS__*/").count(), 1);
    }
}
