//! The usage sums of a dwells file read whole by the checked reader (`crate::read`), for the
//! checked read that names a broken rule ([`crate::load`]): the columns of its [`Frame`] parsed
//! into the rows the one pass takes ([`crate::dwell_sums::Rows`]), each label parsed once per run
//! of equal strings.

use crate::dwell_sums::{FilePass, Rows};
use crate::frame::Frame;
use arrow::array::Array;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellColumns, DwellKind, DwellRow, Requester, Role};

/// The dwells table's column names (from its declaration).
const D: DwellColumns = DwellRow::COLUMNS;

/// A utf8 column's values parsed by `parse` into `out`; `None` on a null or a string `parse`
/// refuses.
fn parsed<T: Copy>(df: &Frame, name: &str, out: &mut Vec<T>, mut parse: impl FnMut(&str) -> Option<T>) -> Option<()> {
    let strings = df.strs(name).ok()?;
    if strings.null_count() > 0 {
        return None;
    }
    out.clear();
    let mut last: Option<(&str, T)> = None;
    for s in strings.iter().flatten() {
        let value = match last {
            Some((l, v)) if l == s => v,
            _ => parse(s)?,
        };
        last = Some((s, value));
        out.push(value);
    }
    Some(())
}

/// A float column's values into `out`; `None` on a null.
fn f64s_of(df: &Frame, name: &str, out: &mut Vec<f64>) -> Option<()> {
    if df.column(name).ok()?.null_count() > 0 {
        return None;
    }
    out.clear();
    out.extend_from_slice(df.f64s(name).ok()?);
    Some(())
}

/// The rows of `df` (a whole dwells file) checked and added to `pass`; the radars named in
/// `bufs.radar_names`, in order of first appearance.
pub(crate) fn frame_rows(pass: &mut FilePass<'_>, df: &Frame, bufs: &mut Buffers) -> Option<()> {
    if df.column(D.run).ok()?.null_count() > 0 {
        return None;
    }
    bufs.run.clear();
    bufs.run.extend_from_slice(df.u32s(D.run).ok()?);
    let names = &mut bufs.radar_names;
    parsed(df, D.radar, &mut bufs.radar, |s| {
        let id = RadarId::parse(s)?;
        let name = id.to_string();
        let i = match names.iter().position(|n| *n == name) {
            Some(i) => i,
            None => {
                names.push(name);
                names.len() - 1
            }
        };
        u8::try_from(i).ok()
    })?;
    parsed(df, D.role, &mut bufs.role, Role::parse)?;
    parsed(df, D.kind, &mut bufs.kind, DwellKind::parse)?;
    parsed(df, D.requested_by, &mut bufs.by, Requester::parse)?;
    f64s_of(df, D.t_s, &mut bufs.t_s)?;
    f64s_of(df, D.duration_s, &mut bufs.duration_s)?;
    f64s_of(df, D.energy_j, &mut bufs.energy_j)?;
    pass.rows(&Rows {
        run: &bufs.run,
        radar: &bufs.radar,
        role: &bufs.role,
        requested_by: &bufs.by,
        t_s: &bufs.t_s,
        duration_s: &bufs.duration_s,
        energy_j: &bufs.energy_j,
    })
}

/// The columns of a file, and the radars named.
#[derive(Default)]
pub(crate) struct Buffers {
    pub(crate) radar_names: Vec<String>,
    run: Vec<u32>,
    radar: Vec<u8>,
    role: Vec<Role>,
    kind: Vec<DwellKind>,
    by: Vec<Requester>,
    t_s: Vec<f64>,
    duration_s: Vec<f64>,
    energy_j: Vec<f64>,
}
