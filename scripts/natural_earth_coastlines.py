#!/usr/bin/env python3
"""Convert Natural Earth 110 m land outlines (TopoJSON from the npm package `world-atlas`, ISC)
into the compact coastline file embedded by `mimo plot` (crates/mimo-plot/assets/coastlines-110m.txt).

Run once, by hand, when the coastline data is to be refreshed:

    cd /tmp && npm pack world-atlas@2.0.2 && tar xzf world-atlas-2.0.2.tgz
    python3 scripts/natural_earth_coastlines.py /tmp/package/land-110m.json \
        crates/mimo-plot/assets/coastlines-110m.txt

Output: one polyline per line, `lon lat lon lat …` in hundredths of a degree (integers). The
110 m data is generalised to about 0.1°, so 0.01° loses nothing. Every arc of the land
topology is a piece of coastline; arcs are written once each (shared arcs are not repeated).
"""
import json
import sys


def main(src, dst):
    topo = json.load(open(src))
    sx, sy = topo["transform"]["scale"]
    tx, ty = topo["transform"]["translate"]
    lines = []
    points = 0
    for arc in topo["arcs"]:
        x = y = 0
        out = []
        for dx, dy in arc:  # quantized, delta-encoded (TopoJSON spec)
            x += dx
            y += dy
            lon = x * sx + tx
            lat = y * sy + ty
            q = (round(lon * 100), round(lat * 100))
            if not out or out[-1] != q:
                out.append(q)
        if len(out) >= 2:
            lines.append(" ".join(f"{a} {b}" for a, b in out))
            points += len(out)
    header = (
        "# Natural Earth 110 m land outlines (public domain, naturalearthdata.com), via world-atlas 2.0.2 "
        "land-110m.json (ISC). One polyline per line: lon lat pairs in 0.01 deg. "
        "Made by scripts/natural_earth_coastlines.py.\n"
    )
    with open(dst, "w") as f:
        f.write(header)
        f.write("\n".join(lines) + "\n")
    print(f"{len(lines)} polylines, {points} points -> {dst}")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
