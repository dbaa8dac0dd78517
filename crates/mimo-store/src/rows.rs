//! Conversion between the row records of `mimo-core` and Arrow record batches.
//!
//! Every table implements [`TableRow`]. Writing builds one Arrow array per column in the order of
//! the table's [`TableSpec`]; reading checks that every column exists with the expected type and
//! that floating-point values are finite, naming the file and column when they are not.

use crate::StoreError;
use crate::schema::{self, TableSpec};
use arrow::array::{
    Array, ArrayRef, BooleanArray, FixedSizeListArray, Float64Array, Int64Array, RecordBatch, StringArray, UInt8Array,
    UInt32Array, UInt64Array,
};
use arrow::datatypes::{Field, SchemaRef};
use mimo_core::ids::RadarId;
use mimo_core::records::*;
use std::path::Path;
use std::sync::Arc;

/// A record type stored as one table.
pub trait TableRow: Sized + crate::invariants::RowInvariants {
    /// The table's schema spec.
    const SPEC: TableSpec;
    /// One Arrow array per column, in spec order.
    fn to_columns(rows: &[Self]) -> Vec<ArrayRef>;
    /// Rows from a batch already checked against the spec.
    fn from_batch(b: &Batch<'_>) -> Result<Vec<Self>, StoreError>;
}

/// Build a record batch of rows.
pub fn to_batch<R: TableRow>(rows: &[R]) -> Result<RecordBatch, StoreError> {
    let schema: SchemaRef = Arc::new(R::SPEC.arrow_schema());
    RecordBatch::try_new(schema, R::to_columns(rows)).map_err(|e| StoreError::Arrow(e.to_string()))
}

/// A record batch being read, with the file it came from for error messages.
pub struct Batch<'a> {
    /// The record batch read.
    pub batch: &'a RecordBatch,
    /// The file it was read from, named in errors.
    pub file: &'a Path,
    /// The table the batch was checked against.
    pub spec: &'static TableSpec,
}

impl<'a> Batch<'a> {
    /// Check every spec column is present with the right type and keeps its rule
    /// ([`crate::checked`]), and every row is the file's run; rows are numbered from 0.
    pub fn check(batch: &'a RecordBatch, file: &'a Path, spec: &'static TableSpec) -> Result<Batch<'a>, StoreError> {
        Self::check_from(batch, file, spec, 0)
    }

    /// [`Batch::check`] of a batch whose first row is row `first_row` of the file.
    pub fn check_from(
        batch: &'a RecordBatch,
        file: &'a Path,
        spec: &'static TableSpec,
        first_row: usize,
    ) -> Result<Batch<'a>, StoreError> {
        crate::checked::check_types(file, &batch.schema(), spec)?;
        Self::check_values(batch, file, spec, first_row)
    }

    /// The values of the spec's columns the batch holds (a projection: types already checked
    /// when the file was opened) checked against their rules, and `run` against the file's run;
    /// the batch's first row is row `first_row` of the file.
    pub fn check_values(
        batch: &'a RecordBatch,
        file: &'a Path,
        spec: &'static TableSpec,
        first_row: usize,
    ) -> Result<Batch<'a>, StoreError> {
        check_values_of(batch, file, spec, first_row)?;
        Ok(Batch { batch, file, spec })
    }

    /// [`Batch::check_values`] of a batch of rows picked from the file: batch row `i` is file
    /// row `file_rows[i]`, named in the error.
    pub fn check_values_at(
        batch: &'a RecordBatch,
        file: &'a Path,
        spec: &'static TableSpec,
        file_rows: &[usize],
    ) -> Result<Batch<'a>, StoreError> {
        if check_values_of(batch, file, spec, 0).is_err() {
            // Row by row, to name the file row of the first value that breaks a rule.
            for (i, &row) in file_rows.iter().enumerate().take(batch.num_rows()) {
                check_values_of(&batch.slice(i, 1), file, spec, row)?;
            }
            check_values_of(batch, file, spec, 0)?;
        }
        Ok(Batch { batch, file, spec })
    }

    fn col(&self, name: &str) -> &ArrayRef {
        // Presence was checked in `check`; a spec column name is always there.
        let idx = self.batch.schema().index_of(name).unwrap_or(0);
        self.batch.column(idx)
    }

    fn bad(&self, column: &str, why: impl Into<String>) -> StoreError {
        StoreError::BadColumn { file: self.file.to_path_buf(), column: column.to_string(), why: why.into() }
    }

    fn nonnull<T>(&self, name: &str, arr: &dyn Array, f: impl Fn(usize) -> T) -> Result<Vec<T>, StoreError> {
        if arr.null_count() > 0 {
            return Err(self.bad(name, "has null values"));
        }
        Ok((0..arr.len()).map(f).collect())
    }

    /// The values of a non-nullable float64 column. Errors ([`StoreError::BadColumn`]) when it is
    /// not float64, holds a null or a NaN or ∞.
    pub fn f64(&self, name: &str) -> Result<Vec<f64>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<Float64Array>().ok_or_else(|| self.bad(name, "is not float64"))?;
        let v = self.nonnull(name, a, |i| a.value(i))?;
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(self.bad(name, format!("has a non-finite value ({}) at row {i}", v[i])));
        }
        Ok(v)
    }

    /// The values of a non-nullable uint32 column. Errors ([`StoreError::BadColumn`]) when it is not
    /// uint32 or holds a null.
    pub fn u32(&self, name: &str) -> Result<Vec<u32>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<UInt32Array>().ok_or_else(|| self.bad(name, "is not uint32"))?;
        self.nonnull(name, a, |i| a.value(i))
    }

    /// The values of a non-nullable uint64 column. Errors ([`StoreError::BadColumn`]) when it is not
    /// uint64 or holds a null.
    pub fn u64(&self, name: &str) -> Result<Vec<u64>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<UInt64Array>().ok_or_else(|| self.bad(name, "is not uint64"))?;
        self.nonnull(name, a, |i| a.value(i))
    }

    /// The values of a nullable uint64 column, `None` for a null. Errors ([`StoreError::BadColumn`])
    /// when it is not uint64.
    pub fn opt_u64(&self, name: &str) -> Result<Vec<Option<u64>>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<UInt64Array>().ok_or_else(|| self.bad(name, "is not uint64"))?;
        Ok((0..a.len()).map(|i| if a.is_null(i) { None } else { Some(a.value(i)) }).collect())
    }

    /// The values of a non-nullable int64 column. Errors ([`StoreError::BadColumn`]) when it is not
    /// int64 or holds a null.
    pub fn i64(&self, name: &str) -> Result<Vec<i64>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<Int64Array>().ok_or_else(|| self.bad(name, "is not int64"))?;
        self.nonnull(name, a, |i| a.value(i))
    }

    /// The values of a non-nullable uint8 column. Errors ([`StoreError::BadColumn`]) when it is not
    /// uint8 or holds a null.
    pub fn u8(&self, name: &str) -> Result<Vec<u8>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<UInt8Array>().ok_or_else(|| self.bad(name, "is not uint8"))?;
        self.nonnull(name, a, |i| a.value(i))
    }

    /// The values of a non-nullable boolean column. Errors ([`StoreError::BadColumn`]) when it is not
    /// boolean or holds a null.
    pub fn bool(&self, name: &str) -> Result<Vec<bool>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<BooleanArray>().ok_or_else(|| self.bad(name, "is not bool"))?;
        self.nonnull(name, a, |i| a.value(i))
    }

    /// The values of a non-nullable utf8 column. Errors ([`StoreError::BadColumn`]) when it is not
    /// utf8 or holds a null.
    pub fn str(&self, name: &str) -> Result<Vec<String>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<StringArray>().ok_or_else(|| self.bad(name, "is not utf8"))?;
        self.nonnull(name, a, |i| a.value(i).to_string())
    }

    /// The values of a nullable utf8 column, `None` for a null. Errors ([`StoreError::BadColumn`])
    /// when it is not utf8.
    pub fn opt_str(&self, name: &str) -> Result<Vec<Option<String>>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<StringArray>().ok_or_else(|| self.bad(name, "is not utf8"))?;
        Ok((0..a.len()).map(|i| if a.is_null(i) { None } else { Some(a.value(i).to_string()) }).collect())
    }

    /// A utf8 column of radar ids (`R1`…), parsed. Errors ([`StoreError::BadColumn`]) on a null or
    /// a value that is not a radar id, naming the row.
    pub fn radar(&self, name: &str) -> Result<Vec<RadarId>, StoreError> {
        self.parse_each(name, RadarId::parse, "a radar id like R1")
    }

    /// A utf8 column of categories parsed by `parse`; `what` lists the accepted values for the
    /// error ([`StoreError::BadColumn`], naming the row) raised on a null or any other value.
    pub fn parsed<T>(&self, name: &str, parse: fn(&str) -> Option<T>, what: &str) -> Result<Vec<T>, StoreError> {
        self.parse_each(name, parse, &format!("one of {what}"))
    }

    /// Parse every value of a non-nullable utf8 column in place (no string is copied); `what`
    /// completes "row i: 'x' is not …".
    fn parse_each<T>(&self, name: &str, parse: impl Fn(&str) -> Option<T>, what: &str) -> Result<Vec<T>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<StringArray>().ok_or_else(|| self.bad(name, "is not utf8"))?;
        if a.null_count() > 0 {
            return Err(self.bad(name, "has null values"));
        }
        (0..a.len())
            .map(|i| {
                let s = a.value(i);
                parse(s).ok_or_else(|| self.bad(name, format!("row {i}: '{s}' is not {what}")))
            })
            .collect()
    }

    /// A non-nullable `fixed_size_list<float64, 21>` column: per row, the upper triangle of the
    /// 6×6 covariance, row-major. Errors ([`StoreError::BadColumn`]) when it has another type,
    /// holds a null or a NaN or ∞.
    pub fn cov21(&self, name: &str) -> Result<Vec<[f64; 21]>, StoreError> {
        let a = self.col(name);
        let a = a
            .as_any()
            .downcast_ref::<FixedSizeListArray>()
            .ok_or_else(|| self.bad(name, "is not a fixed-size list"))?;
        if a.null_count() > 0 {
            return Err(self.bad(name, "has null values"));
        }
        let vals = a.values();
        let vals =
            vals.as_any().downcast_ref::<Float64Array>().ok_or_else(|| self.bad(name, "items are not float64"))?;
        let mut out = Vec::with_capacity(a.len());
        for i in 0..a.len() {
            let mut c = [0.0; 21];
            for (k, ck) in c.iter_mut().enumerate() {
                *ck = vals.value(i * 21 + k);
                if !ck.is_finite() {
                    return Err(self.bad(name, format!("has a non-finite value at row {i}")));
                }
            }
            out.push(c);
        }
        Ok(out)
    }
}

/// The values of the spec's columns that `batch` holds against their rules, and `run` against the
/// file's run.
fn check_values_of(batch: &RecordBatch, file: &Path, spec: &TableSpec, first_row: usize) -> Result<(), StoreError> {
    for c in spec.columns {
        if let Some(array) = batch.column_by_name(c.name) {
            crate::checked::check_array(file, c, array.as_ref(), first_row)?;
            if c.name == "run" {
                crate::checked::check_file_run(file, array.as_ref(), first_row)?;
            }
        }
    }
    Ok(())
}

fn f64s<R>(rows: &[R], f: impl Fn(&R) -> f64) -> ArrayRef {
    Arc::new(Float64Array::from_iter_values(rows.iter().map(f)))
}
fn u32s<R>(rows: &[R], f: impl Fn(&R) -> u32) -> ArrayRef {
    Arc::new(UInt32Array::from_iter_values(rows.iter().map(f)))
}
fn u64s<R>(rows: &[R], f: impl Fn(&R) -> u64) -> ArrayRef {
    Arc::new(UInt64Array::from_iter_values(rows.iter().map(f)))
}
fn i64s<R>(rows: &[R], f: impl Fn(&R) -> i64) -> ArrayRef {
    Arc::new(Int64Array::from_iter_values(rows.iter().map(f)))
}
fn u8s<R>(rows: &[R], f: impl Fn(&R) -> u8) -> ArrayRef {
    Arc::new(UInt8Array::from_iter_values(rows.iter().map(f)))
}
fn bools<R>(rows: &[R], f: impl Fn(&R) -> bool) -> ArrayRef {
    Arc::new(BooleanArray::from_iter(rows.iter().map(|r| Some(f(r)))))
}
fn strs<'a, R>(rows: &'a [R], f: impl Fn(&'a R) -> &'a str) -> ArrayRef {
    str_column(rows, f)
}
/// A column of fixed labels (no string made per row).
fn labels<R>(rows: &[R], f: impl Fn(&R) -> &'static str) -> ArrayRef {
    str_column(rows, f)
}
/// A column of radar ids, each id's text made once.
fn radars<R>(rows: &[R], f: impl Fn(&R) -> RadarId) -> ArrayRef {
    let mut names: Vec<Option<String>> = Vec::new();
    for r in rows {
        let i = f(r).index();
        if names.len() <= i {
            names.resize(i + 1, None);
        }
        names[i].get_or_insert_with(|| f(r).to_string());
    }
    str_column(rows, |r| names[f(r).index()].as_deref().unwrap_or_default())
}
/// A non-null utf8 column.
fn str_column<'a, R, S: AsRef<str>>(rows: &'a [R], f: impl Fn(&'a R) -> S) -> ArrayRef {
    Arc::new(StringArray::from_iter_values(rows.iter().map(f)))
}
fn opt_strs<R>(rows: &[R], f: impl Fn(&R) -> Option<&str>) -> ArrayRef {
    Arc::new(StringArray::from_iter(rows.iter().map(f)))
}

impl TableRow for TruthRow {
    const SPEC: TableSpec = schema::TRUTH;
    fn to_columns(rows: &[Self]) -> Vec<ArrayRef> {
        vec![
            u32s(rows, |r| r.run),
            f64s(rows, |r| r.t_s),
            strs(rows, |r| r.target.as_str()),
            f64s(rows, |r| r.x_m),
            f64s(rows, |r| r.y_m),
            f64s(rows, |r| r.z_m),
            f64s(rows, |r| r.vx_mps),
            f64s(rows, |r| r.vy_mps),
            f64s(rows, |r| r.vz_mps),
            f64s(rows, |r| r.lat_deg),
            f64s(rows, |r| r.lon_deg),
            f64s(rows, |r| r.alt_m),
            f64s(rows, |r| r.rcs_m2),
        ]
    }
    fn from_batch(b: &Batch<'_>) -> Result<Vec<Self>, StoreError> {
        let (run, t, target) = (b.u32("run")?, b.f64("t_s")?, b.str("target")?);
        let (x, y, z) = (b.f64("x_m")?, b.f64("y_m")?, b.f64("z_m")?);
        let (vx, vy, vz) = (b.f64("vx_mps")?, b.f64("vy_mps")?, b.f64("vz_mps")?);
        let (lat, lon, alt, rcs) = (b.f64("lat_deg")?, b.f64("lon_deg")?, b.f64("alt_m")?, b.f64("rcs_m2")?);
        Ok((0..run.len())
            .map(|i| TruthRow {
                run: run[i],
                t_s: t[i],
                target: target[i].clone(),
                x_m: x[i],
                y_m: y[i],
                z_m: z[i],
                vx_mps: vx[i],
                vy_mps: vy[i],
                vz_mps: vz[i],
                lat_deg: lat[i],
                lon_deg: lon[i],
                alt_m: alt[i],
                rcs_m2: rcs[i],
            })
            .collect())
    }
}

impl TableRow for DwellRow {
    const SPEC: TableSpec = schema::DWELLS;
    fn to_columns(rows: &[Self]) -> Vec<ArrayRef> {
        vec![
            u32s(rows, |r| r.run),
            u64s(rows, |r| r.dwell_id),
            u64s(rows, |r| r.group_id),
            radars(rows, |r| r.radar),
            labels(rows, |r| r.role.as_str()),
            labels(rows, |r| r.kind.as_str()),
            labels(rows, |r| r.requested_by.as_str()),
            f64s(rows, |r| r.t_s),
            f64s(rows, |r| r.duration_s),
            f64s(rows, |r| r.pulse_width_s),
            u32s(rows, |r| r.n_pulses),
            f64s(rows, |r| r.peak_power_w),
            f64s(rows, |r| r.energy_j),
            u32s(rows, |r| r.waveform),
            u8s(rows, |r| r.face),
            f64s(rows, |r| r.beam_u),
            f64s(rows, |r| r.beam_v),
            f64s(rows, |r| r.aim_x_m),
            f64s(rows, |r| r.aim_y_m),
            f64s(rows, |r| r.aim_z_m),
        ]
    }
    fn from_batch(b: &Batch<'_>) -> Result<Vec<Self>, StoreError> {
        let (run, id, gid, radar) = (b.u32("run")?, b.u64("dwell_id")?, b.u64("group_id")?, b.radar("radar")?);
        let role = b.parsed("role", Role::parse, "tx, rx, txrx")?;
        let kind = b.parsed("kind", DwellKind::parse, "search, confirm, track, mimo")?;
        let req = b.parsed("requested_by", Requester::parse, "radar, ta")?;
        let (t, dur, pw, np) = (b.f64("t_s")?, b.f64("duration_s")?, b.f64("pulse_width_s")?, b.u32("n_pulses")?);
        let (pp, e, wf, face) = (b.f64("peak_power_w")?, b.f64("energy_j")?, b.u32("waveform")?, b.u8("face")?);
        let (bu, bv) = (b.f64("beam_u")?, b.f64("beam_v")?);
        let (ax, ay, az) = (b.f64("aim_x_m")?, b.f64("aim_y_m")?, b.f64("aim_z_m")?);
        Ok((0..run.len())
            .map(|i| DwellRow {
                run: run[i],
                dwell_id: id[i],
                group_id: gid[i],
                radar: radar[i],
                role: role[i],
                kind: kind[i],
                requested_by: req[i],
                t_s: t[i],
                duration_s: dur[i],
                pulse_width_s: pw[i],
                n_pulses: np[i],
                peak_power_w: pp[i],
                energy_j: e[i],
                waveform: wf[i],
                face: face[i],
                beam_u: bu[i],
                beam_v: bv[i],
                aim_x_m: ax[i],
                aim_y_m: ay[i],
                aim_z_m: az[i],
            })
            .collect())
    }
}

impl TableRow for VoltageRow {
    const SPEC: TableSpec = schema::VOLTAGES;
    fn to_columns(rows: &[Self]) -> Vec<ArrayRef> {
        vec![
            u32s(rows, |r| r.run),
            u64s(rows, |r| r.dwell_id),
            radars(rows, |r| r.rx),
            radars(rows, |r| r.tx),
            i64s(rows, |r| r.range_cell),
            f64s(rows, |r| r.range_m),
            f64s(rows, |r| r.sum_i),
            f64s(rows, |r| r.sum_q),
            f64s(rows, |r| r.az_i),
            f64s(rows, |r| r.az_q),
            f64s(rows, |r| r.el_i),
            f64s(rows, |r| r.el_q),
        ]
    }
    fn from_batch(b: &Batch<'_>) -> Result<Vec<Self>, StoreError> {
        let (run, id, rx, tx) = (b.u32("run")?, b.u64("dwell_id")?, b.radar("rx")?, b.radar("tx")?);
        let (cell, r) = (b.i64("range_cell")?, b.f64("range_m")?);
        let (si, sq, ai, aq, ei, eq) =
            (b.f64("sum_i")?, b.f64("sum_q")?, b.f64("az_i")?, b.f64("az_q")?, b.f64("el_i")?, b.f64("el_q")?);
        Ok((0..run.len())
            .map(|i| VoltageRow {
                run: run[i],
                dwell_id: id[i],
                rx: rx[i],
                tx: tx[i],
                range_cell: cell[i],
                range_m: r[i],
                sum_i: si[i],
                sum_q: sq[i],
                az_i: ai[i],
                az_q: aq[i],
                el_i: ei[i],
                el_q: eq[i],
            })
            .collect())
    }
}

impl TableRow for PrimitiveRow {
    const SPEC: TableSpec = schema::PRIMITIVES;
    fn to_columns(rows: &[Self]) -> Vec<ArrayRef> {
        vec![
            u32s(rows, |r| r.run),
            u64s(rows, |r| r.dwell_id),
            f64s(rows, |r| r.t_s),
            radars(rows, |r| r.rx),
            radars(rows, |r| r.tx),
            u8s(rows, |r| r.rx_face),
            i64s(rows, |r| r.range_cell),
            f64s(rows, |r| r.range_m),
            f64s(rows, |r| r.u),
            f64s(rows, |r| r.v),
            f64s(rows, |r| r.snr_db),
            f64s(rows, |r| r.eta_q),
            bools(rows, |r| r.merged),
            f64s(rows, |r| r.beam_u),
            f64s(rows, |r| r.beam_v),
            f64s(rows, |r| r.var_range_m2),
            f64s(rows, |r| r.var_u),
            f64s(rows, |r| r.var_v),
            opt_strs(rows, |r| r.target_hint.as_deref()),
        ]
    }
    fn from_batch(b: &Batch<'_>) -> Result<Vec<Self>, StoreError> {
        let (run, id, t, rx, tx) = (b.u32("run")?, b.u64("dwell_id")?, b.f64("t_s")?, b.radar("rx")?, b.radar("tx")?);
        let (face, cell, r, u, v) =
            (b.u8("rx_face")?, b.i64("range_cell")?, b.f64("range_m")?, b.f64("u")?, b.f64("v")?);
        let (snr, eq, merged) = (b.f64("snr_db")?, b.f64("eta_q")?, b.bool("merged")?);
        let (bu, bv) = (b.f64("beam_u")?, b.f64("beam_v")?);
        let (vr, vu, vv) = (b.f64("var_range_m2")?, b.f64("var_u")?, b.f64("var_v")?);
        let hint = b.opt_str("target_hint")?;
        Ok((0..run.len())
            .map(|i| PrimitiveRow {
                run: run[i],
                dwell_id: id[i],
                t_s: t[i],
                rx: rx[i],
                tx: tx[i],
                rx_face: face[i],
                range_cell: cell[i],
                range_m: r[i],
                u: u[i],
                v: v[i],
                snr_db: snr[i],
                eta_q: eq[i],
                merged: merged[i],
                beam_u: bu[i],
                beam_v: bv[i],
                var_range_m2: vr[i],
                var_u: vu[i],
                var_v: vv[i],
                target_hint: hint[i].clone(),
            })
            .collect())
    }
}

impl TableRow for MeasurementRow {
    const SPEC: TableSpec = schema::MEASUREMENTS;
    fn to_columns(rows: &[Self]) -> Vec<ArrayRef> {
        vec![
            u32s(rows, |r| r.run),
            u64s(rows, |r| r.meas_id),
            u64s(rows, |r| r.dwell_id),
            f64s(rows, |r| r.t_s),
            radars(rows, |r| r.rx),
            radars(rows, |r| r.tx),
            u8s(rows, |r| r.rx_face),
            f64s(rows, |r| r.range_m),
            f64s(rows, |r| r.u),
            f64s(rows, |r| r.v),
            f64s(rows, |r| r.snr_db),
            f64s(rows, |r| r.var_range_m2),
            f64s(rows, |r| r.var_u),
            f64s(rows, |r| r.var_v),
            u32s(rows, |r| r.n_primitives),
            bools(rows, |r| r.merged),
            opt_strs(rows, |r| r.target_hint.as_deref()),
        ]
    }
    fn from_batch(b: &Batch<'_>) -> Result<Vec<Self>, StoreError> {
        let (run, mid, id, t) = (b.u32("run")?, b.u64("meas_id")?, b.u64("dwell_id")?, b.f64("t_s")?);
        let (rx, tx, face) = (b.radar("rx")?, b.radar("tx")?, b.u8("rx_face")?);
        let (r, u, v, snr) = (b.f64("range_m")?, b.f64("u")?, b.f64("v")?, b.f64("snr_db")?);
        let (vr, vu, vv) = (b.f64("var_range_m2")?, b.f64("var_u")?, b.f64("var_v")?);
        let (np, merged, hint) = (b.u32("n_primitives")?, b.bool("merged")?, b.opt_str("target_hint")?);
        Ok((0..run.len())
            .map(|i| MeasurementRow {
                run: run[i],
                meas_id: mid[i],
                dwell_id: id[i],
                t_s: t[i],
                rx: rx[i],
                tx: tx[i],
                rx_face: face[i],
                range_m: r[i],
                u: u[i],
                v: v[i],
                snr_db: snr[i],
                var_range_m2: vr[i],
                var_u: vu[i],
                var_v: vv[i],
                n_primitives: np[i],
                merged: merged[i],
                target_hint: hint[i].clone(),
            })
            .collect())
    }
}

impl TableRow for TrackRow {
    const SPEC: TableSpec = schema::TRACKS;
    fn to_columns(rows: &[Self]) -> Vec<ArrayRef> {
        let values = Float64Array::from_iter_values(rows.iter().flat_map(|r| r.cov));
        let item = Arc::new(Field::new("item", arrow::datatypes::DataType::Float64, false));
        let cov = FixedSizeListArray::new(item, 21, Arc::new(values), None);
        vec![
            u32s(rows, |r| r.run),
            f64s(rows, |r| r.t_s),
            u64s(rows, |r| r.track_id),
            labels(rows, |r| r.status.as_str()),
            f64s(rows, |r| r.x_m),
            f64s(rows, |r| r.y_m),
            f64s(rows, |r| r.z_m),
            f64s(rows, |r| r.vx_mps),
            f64s(rows, |r| r.vy_mps),
            f64s(rows, |r| r.vz_mps),
            Arc::new(cov),
            u32s(rows, |r| r.n_updates),
            Arc::new(UInt64Array::from_iter(rows.iter().map(|r| r.last_meas_id))),
        ]
    }
    fn from_batch(b: &Batch<'_>) -> Result<Vec<Self>, StoreError> {
        let (run, t, id) = (b.u32("run")?, b.f64("t_s")?, b.u64("track_id")?);
        let status = b.parsed("status", TrackStatus::parse, "tentative, confirmed, deleted")?;
        let (x, y, z) = (b.f64("x_m")?, b.f64("y_m")?, b.f64("z_m")?);
        let (vx, vy, vz) = (b.f64("vx_mps")?, b.f64("vy_mps")?, b.f64("vz_mps")?);
        let (cov, nu, last) = (b.cov21("cov")?, b.u32("n_updates")?, b.opt_u64("last_meas_id")?);
        Ok((0..run.len())
            .map(|i| TrackRow {
                run: run[i],
                t_s: t[i],
                track_id: id[i],
                status: status[i],
                x_m: x[i],
                y_m: y[i],
                z_m: z[i],
                vx_mps: vx[i],
                vy_mps: vy[i],
                vz_mps: vz[i],
                cov: cov[i],
                n_updates: nu[i],
                last_meas_id: last[i],
            })
            .collect())
    }
}
