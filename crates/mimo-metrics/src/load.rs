//! Loading the scorer's inputs: the truth, tracks and dwells tables of a run, checked column by
//! column (see the crate docs, "Errors"), into the structures the per-run scoring walks.

use crate::MetricsError;
use crate::dwell_sums::{DWELL_SLICE_ROWS, DwellSums};
use crate::read::{Check, Col, col as rcol, read_file};
use crate::track_metrics::{TargetTruth, TrackLife, TrackState, TruthSample};
use glam::DVec3;
use mimo_core::records::{DwellColumns, DwellRow, TrackColumns, TrackRow, TrackStatus, TruthColumns, TruthRow};
use mimo_core::table_rules::track_row_order;
use mimo_store::rows::TableRow;
use mimo_store::table_chunks::TableChunks;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::path::PathBuf;

/// The run tables' column names (from their declarations in `mimo_core::records`).
const T: TruthColumns = TruthRow::COLUMNS;
const D: DwellColumns = DwellRow::COLUMNS;
const K: TrackColumns = TrackRow::COLUMNS;

/// `out` extended with the points of three checked float64 columns of a batch.
fn extend3(out: &mut Vec<DVec3>, b: &mimo_store::rows::Batch<'_>, names: [&str; 3]) -> Result<(), MetricsError> {
    let (x, y, z) = (b.f64_values(names[0])?, b.f64_values(names[1])?, b.f64_values(names[2])?);
    out.extend(x.iter().zip(y).zip(z).map(|((&x, &y), &z)| DVec3::new(x, y, z)));
    Ok(())
}

/// Truth grouped by run and target.
pub(crate) struct Truth {
    pub(crate) runs: Vec<u32>,
    pub(crate) target_names: Vec<String>,
    pub(crate) per_run: BTreeMap<u32, Vec<TargetTruth>>,
    pub(crate) t_end: BTreeMap<u32, f64>,
}

pub(crate) fn load_truth(paths: &[PathBuf]) -> Result<Truth, MetricsError> {
    some_files(TruthRow::TABLE, paths)?;
    let (mut run, mut t, mut p, mut v, mut alt) = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());

    // Each row's target, first as its index in order of first appearance: the name that followed
    // the row's predecessor's target last time is tried first (the truth is written time by time,
    // its targets in the same order each time), the names' map only when that guess fails.
    let mut seen: Vec<String> = Vec::new();
    let mut seen_index: HashMap<String, usize> = HashMap::new();
    let mut successor: Vec<usize> = Vec::new();
    let mut prev: Option<usize> = None;
    let mut target_of_row = Vec::new();
    for path in paths {
        let mut chunks = open_rows::<TruthRow>(path)?;
        let n = chunks.num_rows();
        run.reserve(n);
        t.reserve(n);
        alt.reserve(n);
        p.reserve(n);
        v.reserve(n);
        target_of_row.reserve(n);
        while let Some(batch) = chunks.next_batch()? {
            let b = chunks.view(&batch);
            let target = b.utf8(T.target)?;
            run.extend_from_slice(b.u32_values(T.run)?);
            t.extend_from_slice(b.f64_values(T.t_s)?);
            alt.extend_from_slice(b.f64_values(T.alt_m)?);
            extend3(&mut p, &b, [T.x_m, T.y_m, T.z_m])?;
            extend3(&mut v, &b, [T.vx_mps, T.vy_mps, T.vz_mps])?;
            for i in 0..b.num_rows() {
                let s = target.value(i);
                let guess = prev.map(|p| successor[p]).filter(|&g| seen.get(g).is_some_and(|n| n == s));
                let target = match guess.or_else(|| seen_index.get(s).copied()) {
                    Some(target) => target,
                    None => {
                        seen_index.insert(s.to_string(), seen.len());
                        seen.push(s.to_string());
                        successor.push(usize::MAX);
                        seen.len() - 1
                    }
                };
                if let Some(p) = prev {
                    successor[p] = target;
                }
                prev = Some(target);
                target_of_row.push(target);
            }
        }
    }
    // A target's index is its rank among the names, so that the rows sort by it as by name.
    let mut by_name: Vec<usize> = (0..seen.len()).collect();
    by_name.sort_by(|&a, &b| seen[a].cmp(&seen[b]));
    let mut rank = vec![0; seen.len()];
    for (r, &i) in by_name.iter().enumerate() {
        rank[i] = r;
    }
    for t in &mut target_of_row {
        *t = rank[*t];
    }
    let target_names: Vec<String> = by_name.iter().map(|&i| seen[i].clone()).collect();

    // The rows by run, target and time (docs/design.md §6: a target's samples in time order).
    let mut per_run: BTreeMap<u32, Vec<TargetTruth>> = BTreeMap::new();
    let mut t_end: BTreeMap<u32, f64> = BTreeMap::new();
    let mut current: Option<(u32, usize)> = None;
    for i in crate::row_order::stable_order(&run, &target_of_row, &t, None) {
        let key = (run[i], target_of_row[i]);
        let list = per_run.entry(run[i]).or_default();
        if current != Some(key) {
            list.push(TargetTruth { target: target_of_row[i], samples: Vec::new() });
            current = Some(key);
        }
        if let Some(tt) = list.last_mut() {
            tt.samples.push(TruthSample { t: t[i], p: p[i], v: v[i], alt: alt[i] });
        }
        let e = t_end.entry(run[i]).or_insert(f64::NEG_INFINITY);
        *e = e.max(t[i]);
    }
    Ok(Truth { runs: per_run.keys().copied().collect(), target_names, per_run, t_end })
}

pub(crate) fn load_tracks(
    paths: &[PathBuf],
    runs: &BTreeSet<u32>,
) -> Result<BTreeMap<u32, Vec<TrackLife>>, MetricsError> {
    some_files(TrackRow::TABLE, paths)?;
    let (mut run, mut id, mut t, mut p, mut v) = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut status, mut rank) = (Vec::new(), Vec::new());
    for path in paths {
        let mut chunks = open_rows::<TrackRow>(path)?;
        let n = chunks.num_rows();
        run.reserve(n);
        id.reserve(n);
        t.reserve(n);
        p.reserve(n);
        v.reserve(n);
        status.reserve(n);
        rank.reserve(n);
        let mut first_row = 0;
        while let Some(batch) = chunks.next_batch()? {
            let b = chunks.view(&batch);
            let runs_here = b.u32_values(K.run)?;
            // A track of a run the truth does not hold has nothing to be scored against.
            if let Some(i) = runs_here.iter().position(|r| !runs.contains(r)) {
                return Err(not_a_truth_run(path, first_row + i, runs_here[i], runs));
            }
            first_row += b.num_rows();
            run.extend_from_slice(runs_here);
            id.extend_from_slice(b.u64_values(K.track_id)?);
            t.extend_from_slice(b.f64_values(K.t_s)?);
            extend3(&mut p, &b, [K.x_m, K.y_m, K.z_m])?;
            extend3(&mut v, &b, [K.vx_mps, K.vy_mps, K.vz_mps])?;
            let n_updates = b.u32_values(K.n_updates)?;
            // Labels the checked read accepted; a run of equal labels is parsed once.
            let mut last: Option<(&str, TrackStatus)> = None;
            for (i, s) in b.utf8(K.status)?.iter().enumerate() {
                let s = s.unwrap_or_default();
                let parsed = match last {
                    Some((name, parsed)) if name == s => parsed,
                    _ => TrackStatus::parse(s).ok_or_else(|| MetricsError::Internal {
                        context: "reading tracks",
                        detail: format!("status '{s}' passed the checked read"),
                    })?,
                };
                last = Some((s, parsed));
                status.push(parsed);
                rank.push(track_row_order(n_updates[i], parsed == TrackStatus::Deleted));
            }
        }
    }
    let (run, id, t) = (&run[..], &id[..], &t[..]);

    // The rows by run, track, time and rank at one time (the table's order, whatever the files'
    // row order: rows it cannot order were refused by `check_tracks`).
    let mut out: BTreeMap<u32, Vec<TrackLife>> = BTreeMap::new();
    let mut current: Option<(u32, u64)> = None;
    let mut ended = false;
    for i in crate::row_order::stable_order(run, id, t, Some(&rank)) {
        let key = (run[i], id[i]);
        let list = out.entry(run[i]).or_default();
        if current != Some(key) {
            list.push(TrackLife { id: id[i], t_confirm: f64::INFINITY, t_delete: f64::INFINITY, states: Vec::new() });
            current = Some(key);
            ended = false;
        }
        let Some(tr) = list.last_mut() else { continue };
        if ended {
            continue;
        }
        match status[i] {
            TrackStatus::Deleted => {
                tr.t_delete = t[i];
                ended = true;
            }
            TrackStatus::Confirmed => {
                if !tr.t_confirm.is_finite() {
                    tr.t_confirm = t[i];
                }
                tr.states.push(TrackState { t: t[i], p: p[i], v: v[i] });
            }
            _ => tr.states.push(TrackState { t: t[i], p: p[i], v: v[i] }),
        }
    }
    Ok(out)
}

/// One file of a run table read with the store's reader of its checked rows
/// ([`mimo_store::table_chunks`]). Its errors are the store's, worded as `mimo plot` and
/// `mimo track` word them for the same file; only a missing file is a missing table.
pub(crate) struct TableRows<R: TableRow>(TableChunks<R>);

impl<R: TableRow> TableRows<R> {
    /// The file's rows, from its footer.
    pub(crate) fn num_rows(&self) -> usize {
        self.0.num_rows()
    }

    /// The next checked batch ([`TableChunks::next_batch`]); `None` after the last.
    pub(crate) fn next_batch(&mut self) -> Result<Option<arrow::array::RecordBatch>, MetricsError> {
        self.0.next_batch().map_err(in_table::<R>)
    }

    /// A batch of this file with its typed accessors.
    pub(crate) fn view<'a>(&'a self, batch: &'a arrow::array::RecordBatch) -> mimo_store::rows::Batch<'a> {
        self.0.view(batch)
    }
}

/// A store error of `R`'s table, a missing file named as a missing table.
fn in_table<R: TableRow>(e: mimo_store::StoreError) -> MetricsError {
    match e {
        mimo_store::StoreError::Missing { path } => {
            MetricsError::MissingTable { table: R::SPEC.name, path, detail: "file does not exist".into() }
        }
        e => e.into(),
    }
}

/// A table given no file is missing.
fn some_files(table: &'static str, paths: &[PathBuf]) -> Result<(), MetricsError> {
    if paths.is_empty() {
        return Err(MetricsError::MissingTable {
            table,
            path: PathBuf::from(table),
            detail: "no Parquet files given".into(),
        });
    }
    Ok(())
}

/// Open one file of a run table ([`TableRows`]).
pub(crate) fn open_rows<R: TableRow>(path: &std::path::Path) -> Result<TableRows<R>, MetricsError> {
    TableChunks::<R>::open(path).map(TableRows).map_err(in_table::<R>)
}

/// The error of a tracks row whose run the truth does not hold.
fn not_a_truth_run(path: &std::path::Path, row: usize, run: u32, runs: &BTreeSet<u32>) -> MetricsError {
    let list: Vec<String> = runs.iter().take(8).map(|r| r.to_string()).collect();
    let more = if runs.len() > 8 { ", …" } else { "" };
    MetricsError::InvalidValue {
        table: TrackRow::TABLE,
        path: path.to_path_buf(),
        column: K.run,
        row,
        value: run.to_string(),
        expected: format!("a run present in the truth table ({}{more})", list.join(", ")),
    }
}

/// The error of a score given no dwells file.
pub(crate) fn no_dwells() -> MetricsError {
    MetricsError::MissingTable {
        table: DwellRow::TABLE,
        path: PathBuf::from(DwellRow::TABLE),
        detail: "no Parquet files given".into(),
    }
}

/// The columns of the dwells table that the usage figures need (their checks from the table's
/// spec; `run` also among the truth's runs).
fn dwell_cols(runs: &BTreeSet<u32>) -> [Col<'_>; 8] {
    let any = |name| rcol(name, Check::Any);
    [
        rcol(D.run, Check::RunIn(runs)),
        any(D.radar),
        any(D.role),
        any(D.kind),
        any(D.requested_by),
        any(D.t_s),
        any(D.duration_s),
        any(D.energy_j),
    ]
}

/// One dwells file read, checked and reduced to its usage sums and the radars it names, in one
/// pass ([`crate::dwell_file::file_sums`]). When any check fails the whole file is read with
/// every check, whose error names the row and rule.
pub(crate) fn dwell_file_sums(
    path: &std::path::Path,
    runs: &BTreeSet<u32>,
    interval_s: f64,
) -> Result<DwellSums, MetricsError> {
    let n_rows = crate::read::file_rows(DwellRow::TABLE, path)?;
    let of_file = runs_of_file(path, runs);
    let runs_here = of_file.as_ref().unwrap_or(runs);
    if n_rows > 0
        && let Some(sums) = crate::dwell_file::file_sums(path, runs_here, interval_s, DWELL_SLICE_ROWS)
    {
        return Ok(sums);
    }
    dwell_file_sums_whole(path, runs, interval_s)
}

/// The runs of `runs` a one-pass reader of `path` takes: a file of run K holds run K alone, so
/// those readers take that run only (any other leaves them to the checked read, which names the
/// row); `None` (all of `runs`) for a file not named by its run.
pub(crate) fn runs_of_file(path: &std::path::Path, runs: &BTreeSet<u32>) -> Option<BTreeSet<u32>> {
    let k = mimo_store::invariants::file_run(path)?;
    Some(runs.iter().copied().filter(|&r| r == k).collect())
}

/// [`dwell_file_sums`] in one checked read of the whole file (its sums in one slice).
fn dwell_file_sums_whole(
    path: &std::path::Path,
    runs: &BTreeSet<u32>,
    interval_s: f64,
) -> Result<DwellSums, MetricsError> {
    let df = read_file(DwellRow::TABLE, path, &dwell_cols(runs))?;
    crate::rules::check_dwells(path, &df)?;
    let mut pass = crate::dwell_sums::FilePass::new(runs, interval_s, df.height());
    let mut bufs = crate::dwell_read::Buffers::default();
    if crate::dwell_read::frame_rows(&mut pass, &df, &mut bufs).is_some() {
        return Ok(pass.finish(bufs.radar_names));
    }
    // Every check passed: only a time too far out for an interval number is left.
    let t = df.f64s(D.t_s)?;
    let row = t.iter().position(|t| t / interval_s >= 9.0e18).unwrap_or(0);
    Err(MetricsError::InvalidValue {
        table: DwellRow::TABLE,
        path: path.to_path_buf(),
        column: D.t_s,
        row,
        value: t.get(row).map(|t| t.to_string()).unwrap_or_default(),
        expected: "a time of fewer than 9e18 scoring intervals".into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::Frame;
    use mimo_store::testing::varied_dwell_rows;

    /// A dwells file of `n` rows: four radars in turn, every role, kind and requester, times
    /// increasing; with `back_at`, that row's time is set before its radar's previous row.
    fn dwells_file(dir: &std::path::Path, n: usize, back_at: Option<usize>, bad_role_at: Option<usize>) -> PathBuf {
        let mut t = Vec::with_capacity(n);
        for i in 0..n {
            t.push(0.013 * i as f64 + 0.004 * ((i * 7919) % 13) as f64 / 13.0);
        }
        if let Some(i) = back_at {
            t[i] = t[i - 4] - 0.001;
        }
        let rows = varied_dwell_rows(0, &t);
        // mimo's layout and metadata (the table's spec: required columns, plain pages, `t_s`
        // byte-stream-split, zstd), in row groups of 300 rows and pages of 100, so that every
        // reader of `crate::dwell_read` takes the file and crosses pages and row groups.
        use arrow::array::{ArrayRef, StringArray};
        use parquet::basic::{Compression, Encoding};
        use parquet::file::properties::WriterProperties;
        use std::sync::Arc;
        let mut batch = mimo_store::rows::to_batch(&rows).expect("batch");
        if let Some(bad) = bad_role_at {
            let roles: Vec<&str> =
                rows.iter().enumerate().map(|(i, r)| if i == bad { "bogus" } else { r.role.as_str() }).collect();
            let schema = batch.schema();
            let mut columns = batch.columns().to_vec();
            columns[schema.index_of("role").expect("role")] = Arc::new(StringArray::from(roles)) as ArrayRef;
            batch = arrow::array::RecordBatch::try_new(schema, columns).expect("batch");
        }
        let schema = batch.schema();
        let props = WriterProperties::builder()
            .set_compression(Compression::ZSTD(Default::default()))
            .set_dictionary_enabled(false)
            .set_max_row_group_row_count(Some(300))
            .set_data_page_row_count_limit(100)
            .set_write_batch_size(50)
            .set_column_encoding("t_s".into(), Encoding::BYTE_STREAM_SPLIT)
            .build();
        let path = dir.join("run-0000.parquet");
        let f = std::fs::File::create(&path).expect("create");
        let mut w = parquet::arrow::ArrowWriter::try_new(f, schema, Some(props)).expect("writer");
        w.write(&batch).expect("write");
        w.close().expect("close");
        path
    }

    /// The additions the one-pass sums promise, written the plain way: each slice of
    /// `slice_rows` rows grouped by (run, radar, interval) in order of first appearance, a
    /// group's transmit rows added in row order (a group of one row is its value), and the
    /// slices' sums of a group added in slice order.
    fn reference_sums(df: &Frame, interval_s: f64, slice_rows: usize) -> Vec<((u32, String, i64), [u64; 4])> {
        let (run, radar, role, by) = (
            df.u32s("run").expect("run"),
            df.strs("radar").expect("radar"),
            df.strs("role").expect("role"),
            df.strs("requested_by").expect("by"),
        );
        let (t, d, e) =
            (df.f64s("t_s").expect("t"), df.f64s("duration_s").expect("d"), df.f64s("energy_j").expect("e"));
        let mut order: Vec<(u32, String, i64)> = Vec::new();
        let mut total: HashMap<(u32, String, i64), [crate::mean::GroupMean; 4]> = HashMap::new();
        for first in (0..df.height()).step_by(slice_rows) {
            let mut slice_order: Vec<(u32, String, i64)> = Vec::new();
            let mut slice: HashMap<(u32, String, i64), [crate::mean::GroupMean; 4]> = HashMap::new();
            for i in first..(first + slice_rows).min(df.height()) {
                if role.value(i) == "rx" {
                    continue;
                }
                let key = (run[i], radar.value(i).to_string(), (t[i] / interval_s) as i64 + 1);
                let ta = by.value(i) == "ta";
                let g = slice.entry(key.clone()).or_insert_with(|| {
                    slice_order.push(key);
                    Default::default()
                });
                for (m, v) in g.iter_mut().zip([d[i], e[i], if ta { d[i] } else { 0.0 }, if ta { e[i] } else { 0.0 }]) {
                    m.push(Some(v));
                }
            }
            for key in slice_order {
                let part = slice[&key];
                let g = total.entry(key.clone()).or_insert_with(|| {
                    order.push(key);
                    Default::default()
                });
                for (m, p) in g.iter_mut().zip(part) {
                    m.push(Some(p.sum()));
                }
            }
        }
        order
            .into_iter()
            .map(|k| {
                let s = total[&k].map(|m| m.sum().to_bits());
                (k, s)
            })
            .collect()
    }

    /// The one-pass sums (from the pages and from the Arrow read, in slices of 1000 and 64 rows)
    /// are those of the plain additions to the bit: the same groups in the same order and the
    /// same radars.
    #[test]
    fn one_pass_sums_are_the_plain_additions() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dwells_file(dir.path(), 1000, None, None);
        let runs = BTreeSet::from([0u32]);
        let cols = dwell_cols(&runs);
        let df = read_file("dwells", &path, &cols).expect("read");
        let whole = reference_sums(&df, 1.0, 1000);
        let sliced = reference_sums(&df, 1.0, 64);
        assert!(whole.len() > 40, "{} groups", whole.len());
        // The sums do differ between the two ways of slicing (so the comparison below can fail).
        assert_ne!(whole, sliced);
        let radars_whole: BTreeSet<String> =
            df.strs("radar").expect("radar").iter().flatten().map(str::to_string).collect();
        for (reference, slice_rows) in [(&whole, 1000), (&sliced, 64)] {
            let sums = crate::dwell_file::file_sums(&path, &runs, 1.0, slice_rows);
            let sums = sums.expect("no broken rule, the file read");
            assert_eq!(sums.radars(), radars_whole);
            let got: Vec<((u32, String, i64), [u64; 4])> = sums
                .groups
                .iter()
                .zip(&sums.sums)
                .map(|(&(r, rad, k), s)| ((r, sums.radar_names[rad].clone(), k), s.value().map(f64::to_bits)))
                .collect();
            assert_eq!(&got, reference, "slices of {slice_rows} rows");
        }
        // The checked whole-file read gives the one-slice sums too.
        let all = dwell_file_sums_whole(&path, &runs, 1.0).expect("whole");
        let got: Vec<[u64; 4]> = all.sums.iter().map(|s| s.value().map(f64::to_bits)).collect();
        assert_eq!(got, whole.iter().map(|(_, s)| *s).collect::<Vec<_>>());
    }

    /// The store's own writer output takes the page decoder's fast path (`mimo_store::dwell_chunks`),
    /// across pages and row groups: a change of the writer's settings, or of the parquet crate,
    /// that turned the fast path off fails here.
    #[test]
    fn the_store_writer_output_takes_the_fast_path() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("run-0000.parquet");
        let n = mimo_store::ROW_GROUP_ROWS + mimo_store::PAGE_ROWS + 100;
        let t: Vec<f64> = (0..n).map(|i| 0.013 * i as f64).collect();
        mimo_store::write_table(&path, &varied_dwell_rows(0, &t)).expect("write");
        let runs = BTreeSet::from([0u32]);
        assert!(pages_only(&path), "the store's dwells file takes the fast path");
        let fast = crate::dwell_file::file_sums(&path, &runs, 1.0, DWELL_SLICE_ROWS).expect("pass");
        let whole = dwell_file_sums_whole(&path, &runs, 1.0).expect("checked read");
        assert_eq!(fast.groups, whole.groups);
        assert_eq!(fast.radars(), whole.radars());
    }

    /// Whether the dwells reader decodes every row of `path` from its pages.
    fn pages_only(path: &std::path::Path) -> bool {
        use mimo_store::dwell_chunks::{DwellChunk, DwellChunks, DwellField};
        let mut r = DwellChunks::open(path, &[DwellField::Run, DwellField::TS]).expect("open");
        let mut c = DwellChunk::default();
        while r.next_chunk(&mut c).expect("chunk") {}
        r.pages_only()
    }

    /// A dwells file written with other settings than the store's (dictionary pages, the
    /// Parquet writer's defaults) is not taken by the page decoder, and the Arrow reader gives
    /// its sums: the same, to the bit, as those of the store's own file of the same rows.
    #[test]
    fn other_writer_settings_are_read_by_the_slow_path() {
        let dir = tempfile::tempdir().expect("tempdir");
        let (ours, other) = (dir.path().join("a"), dir.path().join("b"));
        let n = mimo_store::ROW_GROUP_ROWS + 100;
        let rows = varied_dwell_rows(0, &(0..n).map(|i| 0.013 * i as f64).collect::<Vec<_>>());
        std::fs::create_dir_all(&ours).expect("dir");
        std::fs::create_dir_all(&other).expect("dir");
        let (ours, other) = (ours.join("run-0000.parquet"), other.join("run-0000.parquet"));
        mimo_store::write_table(&ours, &rows).expect("write");
        let batch = mimo_store::rows::to_batch(&rows).expect("batch");
        let props = parquet::file::properties::WriterProperties::builder().set_dictionary_enabled(true).build();
        let file = std::fs::File::create(&other).expect("create");
        let mut w = parquet::arrow::ArrowWriter::try_new(file, batch.schema(), Some(props)).expect("writer");
        w.write(&batch).expect("write");
        w.close().expect("close");
        let runs = BTreeSet::from([0u32]);
        assert!(!pages_only(&other), "not the store's layout");
        assert!(pages_only(&ours), "the store's layout");
        let bits = |s: &DwellSums| -> Vec<[u64; 4]> { s.sums.iter().map(|x| x.value().map(f64::to_bits)).collect() };
        let a = dwell_file_sums(&ours, &runs, 1.0).expect("ours");
        let b = dwell_file_sums(&other, &runs, 1.0).expect("other");
        assert!(a.groups.len() > 100, "{} groups", a.groups.len());
        assert_eq!((&a.groups, a.radars(), bits(&a)), (&b.groups, b.radars(), bits(&b)));
    }

    /// A time that runs backwards across a slice boundary is caught by the sliced pass, and the
    /// whole read then names it.
    #[test]
    fn a_time_out_of_order_across_slices_is_caught() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dwells_file(dir.path(), 1000, Some(128), None);
        let runs = BTreeSet::from([0u32]);
        assert!(crate::dwell_file::file_sums(&path, &runs, 1.0, 64).is_none());
        let err = dwell_file_sums(&path, &runs, 1.0).map(|_| ()).expect_err("out of order");
        assert!(matches!(err, MetricsError::BrokenRule { row: 128, .. }), "{err}");
    }

    /// A bad label in a file of mimo's layout: the one-pass readers give up, and the error is
    /// the checked read's, naming the column, row and value.
    #[test]
    fn a_bad_label_is_reported_by_the_checked_read() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dwells_file(dir.path(), 1000, None, Some(500));
        let runs = BTreeSet::from([0u32]);
        assert!(crate::dwell_file::file_sums(&path, &runs, 1.0, 64).is_none());
        let err = dwell_file_sums(&path, &runs, 1.0).map(|_| ()).expect_err("bad role");
        assert!(err.to_string().contains("column 'role' is 'bogus' at row 500"), "{err}");
        let whole = dwell_file_sums_whole(&path, &runs, 1.0).map(|_| ()).expect_err("bad role");
        assert_eq!(err.to_string(), whole.to_string());
    }
}
