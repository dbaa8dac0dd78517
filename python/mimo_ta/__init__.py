"""mimo_ta: write a test article for the ``mimo`` radar-tracking benchmark in Python.

The protocol (docs/ta-protocol.md) as message types, a base class with ``on_start`` /
``on_dwell`` / ``on_wake`` / ``on_finish``, the frames (``geo``), the bistatic (R_B, u, v)
measurement model (``measurement``), the radar equation for sizing dwells (``radar``), track
covariances mimo accepts (``covariance``) and a tracks-table writer (``tracks_table``).
Needs numpy only.
"""

from .article import TestArticle
from .covariance import CovarianceError, checked_covariance, track_cov21
from .messages import (DEFAULT_SEARCH_BANDS, PROTOCOL_VERSION, AzSector, DwellReport, DwellRequest, GeoPoint,
                       Measurement, PartReport, Primitive, ProtocolError, SearchBand, SearchOrder, SearchPlan, ShipInfo,
                       StartInfo, StopLocalTracking, Subscription, TrackRow, TxOrder, WakeAt, from_upper_triangle,
                       upper_triangle)
from .tracks_table import tracks_columns, write_tracks_table

__version__ = "0.1.0"

__all__ = [
    "CovarianceError", "DEFAULT_SEARCH_BANDS", "PROTOCOL_VERSION", "AzSector", "SearchBand", "SearchOrder", "SearchPlan",
    "DwellReport", "DwellRequest", "GeoPoint", "Measurement", "PartReport", "Primitive",
    "ProtocolError", "ShipInfo", "StartInfo", "StopLocalTracking", "Subscription", "TestArticle", "TrackRow",
    "TxOrder", "WakeAt", "checked_covariance", "from_upper_triangle", "track_cov21", "tracks_columns",
    "upper_triangle", "write_tracks_table",
]
