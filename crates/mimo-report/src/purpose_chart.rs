//! `energy_by_purpose`: the energy emitted per scoring interval, summed over radars and averaged
//! over runs, stacked by purpose (docs/design.md §6, "Usage by purpose"): background search at the
//! bottom, then the test article's confirmation looks at real objects and at false alarms, and
//! its track looks on objects and on nothing.

use crate::draw::{Area, Panel, TimeChart};
use crate::{Chart, ReportError, WIDTH, ma_half, save, subtitle};
use mimo_metrics::{Purpose, Score};
use plotters::style::RGBColor;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Colours: search grey, true looks in blues and greens, false ones in warm colours.
fn color(p: Purpose) -> RGBColor {
    match p {
        Purpose::Search => RGBColor(170, 170, 170),
        Purpose::ConfirmTrue => RGBColor(86, 180, 233),
        Purpose::ConfirmFalse => RGBColor(230, 159, 0),
        Purpose::Track => RGBColor(0, 114, 178),
        Purpose::TrackFalse => RGBColor(213, 94, 0),
    }
}

fn label(p: Purpose) -> &'static str {
    match p {
        Purpose::Search => "search",
        Purpose::ConfirmTrue => "confirm, object in beam",
        Purpose::ConfirmFalse => "confirm, no object (false alarm)",
        Purpose::Track => "track / MIMO, object in beam",
        Purpose::TrackFalse => "track / MIMO, no object",
    }
}

/// Mean over runs of each interval's energy summed over radars, per purpose: `(t_mid_s, [J; 5])`.
fn per_interval(score: &Score) -> Vec<(f64, [f64; 5])> {
    let mut sums: BTreeMap<u32, (f64, [f64; 5], BTreeSet<u32>)> = BTreeMap::new();
    for r in &score.usage_by_purpose {
        let Some(p) = Purpose::ALL.iter().position(|p| p.name() == r.purpose) else { continue };
        let e = sums.entry(r.interval).or_insert_with(|| (0.5 * (r.t_start_s + r.t_end_s), [0.0; 5], BTreeSet::new()));
        e.1[p] += r.energy_j;
        e.2.insert(r.run);
    }
    sums.into_values()
        .map(|(t, mut e, runs)| {
            let n = runs.len().max(1) as f64;
            e.iter_mut().for_each(|v| *v /= n);
            (t, e)
        })
        .collect()
}

/// Each purpose of `purposes`' moving average (the raw per-interval values jump with every look),
/// stacked in that order, labelled with its total per run.
fn stacked(rows: &[(f64, [f64; 5])], purposes: &[Purpose], half: usize) -> Vec<Area> {
    let mut stack = vec![0.0; rows.len()];
    let mut areas = Vec::new();
    for &p in purposes {
        let raw: Vec<(f64, Option<f64>)> = rows.iter().map(|(t, e)| (*t, Some(e[p.index()]))).collect();
        let mut points = Vec::with_capacity(rows.len());
        for (s, (t, v)) in stack.iter_mut().zip(crate::moving_average(&raw, half)) {
            *s += v.unwrap_or(0.0);
            points.push((t, *s));
        }
        let total: f64 = rows.iter().map(|(_, e)| e[p.index()]).sum();
        // kJ to one decimal, or J when that would read 0.
        let amount = if total >= 50.0 {
            format!("{} kJ", crate::draw::fmt_num((total / 100.0).round() / 10.0))
        } else {
            format!("{} J", crate::draw::fmt_num(total.round()))
        };
        let name = format!("{} ({amount} per run)", label(p));
        areas.push(Area { label: name, color: color(p), points });
    }
    areas
}

/// Draw `energy_by_purpose.png` and `.svg` into `dir`: all radars' energy stacked by purpose,
/// and below it the test article's looks alone (search left out), at their own scale.
pub(crate) fn render(score: &Score, dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), ReportError> {
    let rows = per_interval(score);
    let half = ma_half(rows.len());
    let dt = score.options.interval_s;
    let y_label = format!("energy per {} s interval (J)", crate::draw::fmt_num(dt));
    let panel = |title: &str, purposes: &[Purpose]| Panel {
        title: Some(title.to_string()),
        y_label: y_label.clone(),
        lines: vec![],
        areas: stacked(&rows, purposes, half),
        y_range: None,
    };
    let window = crate::draw::fmt_num((2 * half + 1) as f64 * dt);
    let c = Chart::Time(TimeChart {
        title: format!("Emitted energy per scoring interval by purpose, all radars {}", subtitle(score)),
        x_label: format!("time since scenario start (s); each purpose a {window} s moving average, stacked"),
        panels: vec![
            panel("all dwells", &Purpose::ALL),
            panel("confirmation and track looks alone (search left out)", &Purpose::ALL[1..]),
        ],
        columns: 1,
    });
    save(&c, dir, "energy_by_purpose", (WIDTH, 2 * crate::HEIGHT - 120), out)
}
