"""Write a tracks table from Python that ``mimo score`` reads (docs/design.md §3, §7).

For a tracker run outside ``mimo`` (Stone Soup over a recording's measurements, say): give the
rows (:class:`mimo_ta.TrackRow` objects or dicts of the same fields, ``cov`` a 6x6 matrix or its
21-number upper triangle) and get the table's columns with every covariance symmetrised and,
where rounding left it slightly indefinite, repaired as ``mimo`` would
(:mod:`mimo_ta.covariance`), so that the file scores without hand-cleaning:

* :func:`tracks_columns` -- the columns as plain lists (no dependency beyond numpy: hand them to
  polars or pyarrow) and how many covariances were repaired;
* :func:`write_tracks_table` -- ``RUN/tracks/run-NNNN.parquet`` with the exact column types and
  the ``mimo.table`` / ``mimo.schema_version`` metadata mimo checks (needs pyarrow).

A covariance beyond the bound raises :class:`mimo_ta.covariance.CovarianceError` naming the row.
"""

from __future__ import annotations

from .covariance import CovarianceError, checked_covariance, track_cov21

#: The tracks table's columns, in order (``schemas/tracks.json``).
TRACK_COLUMNS = ("run", "t_s", "track_id", "status", "x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps", "cov",
                 "n_updates", "last_meas_id")
#: The table layout version the files carry (``mimo.schema_version``).
SCHEMA_VERSION = 1


def _field(row, name):
    return row[name] if isinstance(row, dict) else getattr(row, name)


def tracks_columns(rows, run: int) -> tuple:
    """``(columns, repaired)``: the tracks table of run ``run`` as a dict of lists in
    :data:`TRACK_COLUMNS` order, and the number of rows whose covariance was repaired."""
    cols = {c: [] for c in TRACK_COLUMNS}
    repaired = 0
    for i, r in enumerate(rows):
        try:
            repaired += int(checked_covariance(_field(r, "cov"))[1])
            cov = track_cov21(_field(r, "cov"))
        except CovarianceError as e:
            raise CovarianceError(f"row {i} (track {_field(r, 'track_id')} at t = {_field(r, 't_s')} s): {e}") from e
        cols["run"].append(int(run))
        for c in TRACK_COLUMNS[1:]:
            if c == "cov":
                cols[c].append(cov)
            elif c in ("track_id", "n_updates"):
                cols[c].append(int(_field(r, c)))
            elif c == "status":
                cols[c].append(str(_field(r, c)))
            elif c == "last_meas_id":
                v = _field(r, c) if not isinstance(r, dict) else r.get(c)
                cols[c].append(None if v is None else int(v))
            else:
                cols[c].append(float(_field(r, c)))
    return cols, repaired


def write_tracks_table(path, rows, run: int) -> int:
    """Write run ``run``'s tracks table to ``path`` (``OUT/tracks/run-NNNN.parquet``) with
    pyarrow; returns the number of covariances repaired."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    cols, repaired = tracks_columns(rows, run)
    cov_type = pa.list_(pa.field("item", pa.float64(), nullable=False), 21)
    schema = pa.schema([
        pa.field("run", pa.uint32(), nullable=False),
        pa.field("t_s", pa.float64(), nullable=False),
        pa.field("track_id", pa.uint64(), nullable=False),
        pa.field("status", pa.utf8(), nullable=False),
        *[pa.field(c, pa.float64(), nullable=False) for c in ("x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps")],
        pa.field("cov", cov_type, nullable=False),
        pa.field("n_updates", pa.uint32(), nullable=False),
        pa.field("last_meas_id", pa.uint64(), nullable=True),
    ], metadata={"mimo.table": "tracks", "mimo.schema_version": str(SCHEMA_VERSION)})
    table = pa.table({c: pa.array(cols[c], type=schema.field(c).type) for c in TRACK_COLUMNS}, schema=schema)
    pq.write_table(table, str(path))
    return repaired
