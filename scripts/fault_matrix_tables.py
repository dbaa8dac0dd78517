#!/usr/bin/env python3
"""Damage one table file of a mimo run in a chosen way (scripts/fault_matrix.sh).

    python3 scripts/fault_matrix_tables.py FILE FAULT

Each FAULT is one thing a hand-edited, foreign or corrupted table may get wrong; the file is
rewritten in place with pyarrow. Prints "n/a" (and changes nothing) when the fault does not
apply to this table (a variance fault on a table without variances).
"""

import math
import sys

import pyarrow as pa
import pyarrow.parquet as pq

PATH, FAULT = sys.argv[1], sys.argv[2]
t = pq.read_table(PATH)
meta = dict(t.schema.metadata or {})
TABLE = meta.get(b"mimo.table", b"?").decode()
# A float column every table carries a finite value in, and its variance columns.
VALUE = {"tracks": "x_m", "truth": "x_m", "measurements": "range_m", "primitives": "range_m", "dwells": "energy_j"}
VARS = {"measurements": "var_range_m2", "primitives": "var_u"}


def with_meta(tab, m):
    return tab.replace_schema_metadata(m)


def set_value(tab, col, row, value):
    arr = tab.column(col).to_pylist()
    if not arr:
        return None
    arr[row] = value
    i = tab.schema.get_field_index(col)
    return tab.set_column(i, tab.schema.field(i), pa.array(arr, type=tab.schema.field(i).type))


def cast(tab, col, typ):
    i = tab.schema.get_field_index(col)
    f = pa.field(col, typ, nullable=tab.schema.field(i).nullable)
    return with_meta(tab.set_column(i, f, tab.column(col).cast(typ)), meta)


def set_cov(tab, cov_of):
    if "cov" not in tab.column_names or tab.num_rows == 0:
        return None
    covs = tab.column("cov").to_pylist()
    covs[0] = cov_of(covs[0])
    n = len(covs[0])
    i = tab.schema.get_field_index("cov")
    typ = pa.list_(pa.field("item", pa.float64(), nullable=False), n)
    others = [c if len(c) == n else (c + [0.0] * n)[:n] for c in covs]
    return with_meta(tab.set_column(i, pa.field("cov", typ), pa.array(others, type=typ)), meta)


def upper(cov):
    """The 6x6 matrix of a 21-value upper triangle (row-major)."""
    m = [[0.0] * 6 for _ in range(6)]
    k = 0
    for i in range(6):
        for j in range(i, 6):
            m[i][j] = m[j][i] = cov[k]
            k += 1
    return m


def non_psd(cov):
    m = upper(cov)
    big = 10.0 * math.sqrt(abs(m[0][0] * m[1][1]) + 1.0)
    out = list(cov)
    out[1] = big  # (0, 1): |c01| > sqrt(c00 c11)
    return out


def with_smallest_eigenvalue(ratio):
    """A covariance like the row's, its smallest eigenvalue set to ``ratio`` times its largest
    (docs/design.md §7: -1e-6 is repaired and counted, -1e-2 refused with the eigenvalue named)."""
    import numpy as np

    def change(cov):
        m = np.array(upper(cov))
        lam, vec = np.linalg.eigh(m)
        lam[0] = ratio * lam[-1]
        out = (vec * lam) @ vec.T
        return np.asarray(out)[np.triu_indices(6)].tolist()

    return change


def fault(tab):
    if FAULT == "meta_other_table":
        return with_meta(tab, {**meta, b"mimo.table": b"truth" if TABLE != "truth" else b"tracks"})
    if FAULT == "meta_version_99":
        return with_meta(tab, {**meta, b"mimo.schema_version": b"99"})
    if FAULT == "meta_none":
        return with_meta(tab, {})
    if FAULT == "t_float32":
        return cast(tab, "t_s", pa.float32())
    if FAULT == "run_int64":
        return cast(tab, "run", pa.int64())
    if FAULT == "run_other":
        return set_value(tab, "run", 0, 5)
    if FAULT == "run_all_other":
        i = tab.schema.get_field_index("run")
        return tab.set_column(i, tab.schema.field(i), pa.array([1] * tab.num_rows, type=pa.uint32()))
    if FAULT in ("nan", "inf", "neg_inf"):
        v = {"nan": math.nan, "inf": math.inf, "neg_inf": -math.inf}[FAULT]
        return set_value(tab, VALUE[TABLE], 0, v)
    if FAULT == "t_nan":
        return set_value(tab, "t_s", 0, math.nan)
    if FAULT == "t_negative":
        return set_value(tab, "t_s", 0, -5.0)
    if FAULT == "t_beyond":
        return set_value(tab, "t_s", tab.num_rows - 1 if tab.num_rows else 0, 1.0e9)
    if FAULT in ("var_negative", "var_zero", "var_nan"):
        v = {"var_negative": -1.0, "var_zero": 0.0, "var_nan": math.nan}[FAULT]
        if TABLE in VARS:
            return set_value(tab, VARS[TABLE], 0, v)
        if TABLE == "tracks":
            return set_cov(tab, lambda c: [v] + c[1:])
        return None
    if FAULT == "cov_nonpsd":
        return set_cov(tab, non_psd)
    if FAULT == "cov_near_psd":
        return set_cov(tab, with_smallest_eigenvalue(-1e-6))
    if FAULT == "cov_far_psd":
        return set_cov(tab, with_smallest_eigenvalue(-1e-2))
    if FAULT == "label_50mb":
        col = {"tracks": "status", "dwells": "kind", "measurements": "rx", "primitives": "rx"}.get(TABLE)
        return set_value(tab, col, 0, "x" * (50 * 1024 * 1024)) if col else None
    if FAULT == "cov_len20":
        return set_cov(tab, lambda c: c[:20])
    if FAULT == "cov_zero":
        return set_cov(tab, lambda c: [0.0] * 21)
    if FAULT == "drop_t":
        return tab.drop(["t_s"])
    if FAULT == "extra_column":
        return with_meta(tab.append_column("mine", pa.array([0] * tab.num_rows, type=pa.int32())), meta)
    if FAULT == "nulls":
        col = VALUE[TABLE]
        i = tab.schema.get_field_index(col)
        arr = tab.column(col).to_pylist()
        if not arr:
            return None
        arr[0] = None
        return tab.set_column(i, pa.field(col, pa.float64(), nullable=True), pa.array(arr, type=pa.float64()))
    if FAULT == "bad_label":
        col = {"tracks": "status", "dwells": "kind", "truth": "target"}.get(TABLE)
        return set_value(tab, col, 0, "bogus") if col else None
    if FAULT == "reversed":
        return tab.take(pa.array(list(range(tab.num_rows - 1, -1, -1))))
    if FAULT == "dup_key_other_state":
        if TABLE != "tracks" or tab.num_rows < 2:
            return None
        row = tab.slice(0, 1)
        i = row.schema.get_field_index("x_m")
        row = row.set_column(i, row.schema.field(i), pa.array([row.column("x_m")[0].as_py() + 500.0]))
        return pa.concat_tables([tab.slice(0, 1), row, tab.slice(1)])
    if FAULT == "empty_table":
        return tab.slice(0, 0)
    raise SystemExit(f"unknown fault {FAULT}")


if FAULT == "truncated":
    data = open(PATH, "rb").read()
    open(PATH, "wb").write(data[: len(data) // 2])
elif FAULT == "zero_bytes":
    open(PATH, "wb").close()
elif FAULT == "not_parquet":
    open(PATH, "w").write("run,t_s\n0,1.0\n")
else:
    out = fault(t)
    if out is None:
        print("n/a")
        sys.exit(0)
    pq.write_table(out, PATH)
