// mimo plot: the page's logic. Data (D) are built by crates/mimo-plot (see its docs); positions
// are whole metres in a local ENU frame at the scenario centre (docs/model.md §1.2).
(function () {
  'use strict';
  var MARKS = window.__mimo.marks;
  MARKS.plotly_loaded_ms = performance.now();
  var D = JSON.parse(document.getElementById('mimo-data').textContent);
  MARKS.data_parsed_ms = performance.now();
  // Click details (ellipsoid axes, velocities, ids, …: about half the data) are parsed on the
  // first selection, not at opening (crates/mimo-plot/src/html.rs, DETAIL_COLUMNS).
  var detailed = false;
  function details() {
    if (detailed) return;
    detailed = true;
    var X = JSON.parse(document.getElementById('mimo-detail').textContent);
    ['tracks', 'meas', 'beams'].forEach(function (k) { Object.keys(X[k]).forEach(function (c) { D[k][c] = X[k][c]; }); });
    X.truth.forEach(function (v, i) { D.truth[i].v = v; });
  }
  var F = D.frame, R = F.enu_from_ecef, O = F.origin_ecef_m;
  var KIND_COLORS = ['#9e9e9e', '#ff7f0e', '#2ca02c', '#9467bd'];
  var RADAR_COLORS = ['#d62728', '#1f77b4', '#2ca02c', '#8c564b', '#e377c2', '#17becf', '#bcbd22', '#7f7f7f'];
  var TRACK_COLORS = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2', '#17becf', '#bcbd22', '#393b79'];
  var SHIP_FACE_HALF_M = 4000, FACE_OFFSET_M = 5000, BORESIGHT_M = 12000;

  var S = {
    t: D.meta.from_s, trail: 30, playing: false, speed: 5, sel: null, mode: 'region', vex: 5,
    layers: { earth: true, coast: true, ships: true, faces: true, truth: true, tracks: true, meas: true, beams: true },
    radarsOn: D.radars.map(function () { return true; }),
    kindsOn: D.meta.kinds.map(function () { return true; }),
    sig1: true, sig3: true
  };

  // ---- frames (docs/model.md §1.1, §1.2) ----
  function toEcef(x, y, z) { // ECEF = o + Rᵀ p
    return [O[0] + R[0] * x + R[3] * y + R[6] * z, O[1] + R[1] * x + R[4] * y + R[7] * z, O[2] + R[2] * x + R[5] * y + R[8] * z];
  }
  function geodetic(p) { // WGS-84, iterative (docs/model.md §1.1)
    var a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
    var x = p[0], y = p[1], z = p[2], r = Math.hypot(x, y), lon = Math.atan2(y, x);
    var lat = Math.atan2(z, r * (1 - e2)), h = 0;
    for (var i = 0; i < 8; i++) {
      var s = Math.sin(lat), N = a / Math.sqrt(1 - e2 * s * s);
      h = r / Math.cos(lat) - N;
      lat = Math.atan2(z, r * (1 - e2 * N / (N + h)));
    }
    return [lat * 180 / Math.PI, lon * 180 / Math.PI, h];
  }
  window.__mimo.toEcef = toEcef; window.__mimo.geodetic = geodetic;

  // ---- helpers ----
  function lowerBound(a, x) { var lo = 0, hi = a.length; while (lo < hi) { var m = (lo + hi) >> 1; if (a[m] < x) lo = m + 1; else hi = m; } return lo; }
  function upperBound(a, x) { var lo = 0, hi = a.length; while (lo < hi) { var m = (lo + hi) >> 1; if (a[m] <= x) lo = m + 1; else hi = m; } return lo; }
  function pt(arr, i) { return [arr[3 * i], arr[3 * i + 1], arr[3 * i + 2]]; }
  function fmt(x, d) { return x === null || x === undefined ? 'n/a' : Number(x).toFixed(d); }
  function radarNames(mask) { var o = []; D.radars.forEach(function (r, i) { if (mask & (1 << i)) o.push(r.id); }); return o; }
  function radarsVisible(mask) { for (var i = 0; i < D.radars.length; i++) if ((mask & (1 << i)) && S.radarsOn[i]) return true; return false; }
  function trackColor(id) { return TRACK_COLORS[id % TRACK_COLORS.length]; }
  function interp(ts, ps, t) { // linear interpolation of a sampled path
    var n = ts.length; if (!n) return null;
    var j = upperBound(ts, t);
    if (j <= 0) return t < ts[0] ? null : pt(ps, 0);
    if (j >= n) return pt(ps, n - 1);
    var a = ts[j - 1], b = ts[j], w = b > a ? (t - a) / (b - a) : 0, p = pt(ps, j - 1), q = pt(ps, j);
    return [p[0] + w * (q[0] - p[0]), p[1] + w * (q[1] - p[1]), p[2] + w * (q[2] - p[2])];
  }
  function shipAt(i, t) { var r = D.radars[i]; return interp(r.t, r.p, t); }

  // ---- the scene's traces ----
  // Every object at time t goes into three scatter3d traces: one of solid lines, one of dotted
  // lines (per-vertex colours, null breaks) and one of markers (per-point symbol, size and
  // colour; customdata [layer, index] for the click panel). plotly builds WebGL programs per
  // trace, and linking them is most of a page's opening time under software WebGL, so the
  // scene has few traces (docs/decisions/0014-run-viewer-few-traces.md). Labels are scene annotations.
  var COAST = (function () { // coastlines as one broken polyline (static)
    var x = [], y = [], z = [], s = D.coast.starts.concat([D.coast.p.length / 3]);
    for (var l = 0; l + 1 < s.length; l++) {
      for (var n = s[l]; n < s[l + 1]; n++) { x.push(D.coast.p[3 * n]); y.push(D.coast.p[3 * n + 1]); z.push(D.coast.p[3 * n + 2]); }
      x.push(null); y.push(null); z.push(null);
    }
    return { x: x, y: y, z: z };
  })();
  function graticule(g) { var o = { x: [], y: [], z: [] }; for (var n = 0; n < g.p.length / 3; n++) { var b = g.starts.indexOf(n) > 0; if (b) { o.x.push(null); o.y.push(null); o.z.push(null); } o.x.push(g.p[3 * n]); o.y.push(g.p[3 * n + 1]); o.z.push(g.p[3 * n + 2]); } return o; }
  var GRID = { region: graticule(D.region.graticule), globe: null }; // the globe's on first use
  // The region view's coastlines: the parts within the region graticule's extent (and a point
  // beyond it, so lines reach its edge). Outlines elsewhere lie outside every region box, and
  // each vertex costs time when the scene is first drawn.
  var COAST_REGION = (function () {
    var g = GRID.region, lo = [Infinity, Infinity], hi = [-Infinity, -Infinity], o = { x: [], y: [], z: [] };
    g.x.forEach(function (x, n) { if (x === null) return; lo[0] = Math.min(lo[0], x); hi[0] = Math.max(hi[0], x); lo[1] = Math.min(lo[1], g.y[n]); hi[1] = Math.max(hi[1], g.y[n]); });
    var inside = function (n) { return COAST.x[n] !== null && COAST.x[n] >= lo[0] && COAST.x[n] <= hi[0] && COAST.y[n] >= lo[1] && COAST.y[n] <= hi[1]; };
    var open = false;
    for (var n = 0; n < COAST.x.length; n++) {
      if (COAST.x[n] !== null && (inside(n) || (n > 0 && inside(n - 1)) || (n + 1 < COAST.x.length && inside(n + 1)))) {
        o.x.push(COAST.x[n]); o.y.push(COAST.y[n]); o.z.push(COAST.z[n]); open = true;
      } else if (open) { o.x.push(null); o.y.push(null); o.z.push(null); open = false; }
    }
    return o;
  })();
  function lines(name, dash, width) {
    return { type: 'scatter3d', mode: 'lines', name: name, x: [], y: [], z: [], line: { color: [], width: width, dash: dash },
      hoverinfo: 'skip', showlegend: false, meta: 'lines' };
  }
  function addLine(tr, pts, color) { // one polyline, then a break
    pts.forEach(function (p) { tr.x.push(p[0]); tr.y.push(p[1]); tr.z.push(p[2]); tr.line.color.push(color); });
    tr.x.push(null); tr.y.push(null); tr.z.push(null); tr.line.color.push(color);
  }
  function addStatic(tr, s, color) {
    for (var n = 0; n < s.x.length; n++) { tr.x.push(s.x[n]); tr.y.push(s.y[n]); tr.z.push(s.z[n]); tr.line.color.push(color); }
    tr.x.push(null); tr.y.push(null); tr.z.push(null); tr.line.color.push(color);
  }
  // Markers are opaque (plotly's default opacity for per-point sizes is 0.7): a translucent
  // point cloud is drawn in gl-plot3d's transparent pass, with a shader program of its own
  // linked at the first frame (docs/decisions/0017-run-viewer-opening-cuts.md).
  function markers() {
    return { type: 'scatter3d', mode: 'markers', name: 'objects', x: [], y: [], z: [], customdata: [], text: [],
      marker: { symbol: [], size: [], color: [], opacity: 1, line: { width: 0 } }, hoverinfo: 'text', showlegend: false, meta: 'objects' };
  }
  function addMark(tr, p, cd, symbol, size, color, text) {
    tr.x.push(p[0]); tr.y.push(p[1]); tr.z.push(p[2]); tr.customdata.push(cd);
    tr.marker.symbol.push(symbol); tr.marker.size.push(size); tr.marker.color.push(color); tr.text.push(text);
  }
  function label(p, text, color, yshift) {
    return { x: p[0], y: p[1], z: p[2], text: text, showarrow: false, yshift: yshift, font: { size: 11, color: color } };
  }

  // The earth (graticule and coastlines) is one static trace, built again only when the view
  // mode or its layers change: the slider passes the same object, and its WebGL buffers are not
  // uploaded again (see keepStatic below).
  var STATIC = null, staticKey = '';
  function staticTrace() {
    var key = S.mode + S.layers.earth + S.layers.coast;
    if (STATIC && key === staticKey) return STATIC;
    var tr = lines('earth', 'solid', 2);
    if (S.mode === 'globe' && !GRID.globe) GRID.globe = graticule(D.globe);
    if (S.layers.earth) addStatic(tr, GRID[S.mode], '#9dbbd1');
    if (S.layers.coast) addStatic(tr, S.mode === 'region' ? COAST_REGION : COAST, '#4a4a4a');
    // Two lone vertices (not drawn: a line needs two) span the whole earth and 200 km above
    // it. plotly scales every trace by the bounds of all the scene's data (scene.dataScale), so
    // with these the scale never depends on the moving objects and the earth's buffers stay valid.
    addStatic(tr, { x: [-7e6], y: [-7e6], z: [-13e6] }, '#fff');
    addStatic(tr, { x: [7e6], y: [7e6], z: [2e5] }, '#fff');
    tr.uid = 'earth'; tr.meta = 'earth ' + key;
    STATIC = tr; staticKey = key;
    return tr;
  }
  // plotly's gl3d scene updates every trace on every render (scene.plot calls update() on each),
  // which would upload the earth's buffers again at each slider step. The earth's WebGL object
  // skips an update when its input trace and the scene's scale are those of its last upload
  // (axis ranges are not part of it: the scene clips to them when it draws).
  window.__mimo.staticUploads = 0;
  function keepStatic() {
    var sc = gd._fullLayout && gd._fullLayout.scene && gd._fullLayout.scene._scene;
    var obj = sc && sc.traces && sc.traces.earth;
    if (!obj || obj.__mimoKeep) return;
    window.__mimo.staticUploads++; // created by plotly: uploaded once
    var update = obj.update, last = { input: obj.data && obj.data._input, scale: String(sc.dataScale) };
    obj.__mimoKeep = true;
    obj.update = function (data) {
      var now = { input: data._input, scale: String(sc.dataScale) };
      if (now.input === last.input && now.scale === last.scale) { this.data = data; return; }
      last = now; window.__mimo.staticUploads++;
      return update.call(this, data);
    };
  }

  function build(t) {
    var t0 = t - S.trail, solid = lines('solid lines', 'solid', 3), dotted = lines('dotted lines', 'dot', 3), mk = markers(), labels = [];
    solid.uid = 'solid'; dotted.uid = 'dotted'; mk.uid = 'objects';
    // Ships and faces.
    D.radars.forEach(function (r, i) {
      if (!S.radarsOn[i] || !S.layers.ships) return;
      var c = RADAR_COLORS[i % RADAR_COLORS.length], p = shipAt(i, t);
      if (!p) return;
      addMark(mk, p, ['ship', i], 'square', 9, c, 'radar ' + r.id);
      labels.push(label(p, r.id, c, 14));
      if (!S.layers.faces) return;
      r.faces.forEach(function (a) {
        var xh = [a[0], a[1], a[2]], yh = [a[3], a[4], a[5]], n = [a[6], a[7], a[8]];
        var cen = [0, 1, 2].map(function (k) { return p[k] + FACE_OFFSET_M * n[k]; });
        var corner = function (sx, sy) { return [0, 1, 2].map(function (k) { return cen[k] + SHIP_FACE_HALF_M * (sx * xh[k] + sy * yh[k]); }); };
        addLine(solid, [corner(-1, -1), corner(1, -1), corner(1, 1), corner(-1, 1), corner(-1, -1)], c);
        addLine(solid, [cen, [0, 1, 2].map(function (k) { return cen[k] + BORESIGHT_M * n[k]; })], c);
      });
    });
    // Truth: trails and current positions.
    if (S.layers.truth) D.truth.forEach(function (p, ti) {
      var a = lowerBound(p.t, t0), b = upperBound(p.t, t), trail = [];
      for (var n = a; n < b; n++) trail.push(pt(p.p, n));
      var now = interp(p.t, p.p, t);
      if (now && t <= p.t[p.t.length - 1]) {
        trail.push(now);
        addMark(mk, now, ['truth', ti, Math.max(b - 1, 0)], 'circle', 6, '#222', 'truth ' + p.id);
        labels.push(label(now, p.id, '#222', -12));
      }
      if (trail.length > 1) addLine(solid, trail, '#222');
    });
    // Tracks: dotted while tentative, solid once confirmed, × where deleted; coloured by id.
    var T = D.tracks, ta = lowerBound(T.t, t0), tb = upperBound(T.t, t), per = new Map(), i;
    if (S.layers.tracks) {
      for (i = ta; i < tb; i++) { var id = T.id[i]; if (!per.has(id)) per.set(id, []); per.get(id).push(i); }
      per.forEach(function (rows, id) {
        var c = trackColor(id), prev = null;
        rows.forEach(function (r) {
          if (prev !== null) addLine(T.st[r] === 0 ? dotted : solid, [pt(T.p, prev), pt(T.p, r)], c);
          addMark(mk, pt(T.p, r), ['track', r], 'circle', 3.5, c, 'track ' + id);
          prev = r;
        });
        var last = rows[rows.length - 1];
        if (T.st[last] === 2) addMark(mk, pt(T.p, last), ['track', last], 'x', 7, c, 'track ' + id + ' deleted');
        else addMark(mk, pt(T.p, last), ['track', last], 'circle', 6, c, 'track ' + id + ' (' + D.meta.statuses[T.st[last]] + ')');
      });
    }
    // Measurements: monostatic circles, bistatic diamonds; coloured by receiving radar.
    var M = D.meas, ma = lowerBound(M.t, t0), mb = upperBound(M.t, t);
    if (S.layers.meas) for (i = ma; i < mb; i++) {
      if (!S.kindsOn[M.kind[i]] || !(S.radarsOn[M.tx[i]] || S.radarsOn[M.rx[i]])) continue;
      var bist = M.tx[i] !== M.rx[i];
      addMark(mk, pt(M.p, i), ['meas', i], bist ? 'diamond' : 'circle', bist ? 5 : 4, RADAR_COLORS[M.rx[i] % RADAR_COLORS.length],
        (bist ? D.radars[M.tx[i]].id + '→' + D.radars[M.rx[i]].id : D.radars[M.rx[i]].id) + ' ' + fmt(M.snr[i], 1) + ' dB');
    }
    // Beam points of the test article's dwells, coloured by kind.
    var B = D.beams, ba = lowerBound(B.t, t0), bb = upperBound(B.t, t);
    if (S.layers.beams) for (i = ba; i < bb; i++) {
      if (!S.kindsOn[B.kind[i]] || !radarsVisible(B.tx[i] | B.rx[i])) continue;
      addMark(mk, pt(B.p, i), ['beam', i], 'square-open', 4.5, KIND_COLORS[B.kind[i]], D.meta.kinds[B.kind[i]] + ' dwell');
    }
    // Selection: sensor lines and a ring; its ellipsoids are the only meshes.
    var info = selectionInfo(), out = [staticTrace(), solid, dotted, mk];
    if (info) {
      sensorLines(info).forEach(function (l) { addLine(l.role === 'tx' ? solid : dotted, [l.from, l.to], l.role === 'tx' ? '#d62728' : '#1f77b4'); });
      addMark(mk, info.p, ['none', -1], 'circle-open', 10, '#000', 'selected');
      if (info.ax) {
        if (S.sig3) out.push(ellipsoid(info.p, info.ax, 3, '#ff9800', 0.25, '3σ'));
        if (S.sig1) out.push(ellipsoid(info.p, info.ax, 1, '#e65100', 0.6, '1σ'));
      }
    }
    S.labels = labels;
    return out;
  }

  // ---- selection ----
  function ellipsoid(c, ax, k, color, opacity, name) {
    var x = [], y = [], z = [], I = [], J = [], K = [], nu = 16, nv = 10;
    for (var a = 0; a <= nv; a++) {
      var th = Math.PI * a / nv;
      for (var b = 0; b < nu; b++) {
        var ph = 2 * Math.PI * b / nu, e = [Math.sin(th) * Math.cos(ph), Math.sin(th) * Math.sin(ph), Math.cos(th)];
        x.push(c[0] + k * (e[0] * ax[0] + e[1] * ax[3] + e[2] * ax[6]));
        y.push(c[1] + k * (e[0] * ax[1] + e[1] * ax[4] + e[2] * ax[7]));
        z.push(c[2] + k * (e[0] * ax[2] + e[1] * ax[5] + e[2] * ax[8]));
      }
    }
    for (a = 0; a < nv; a++) for (b = 0; b < nu; b++) {
      var p0 = a * nu + b, p1 = a * nu + (b + 1) % nu, q0 = p0 + nu, q1 = p1 + nu;
      I.push(p0, p1); J.push(p1, q1); K.push(q0, q0);
    }
    return { type: 'mesh3d', uid: name, name: name, x: x, y: y, z: z, i: I, j: J, k: K, color: color, opacity: opacity, hoverinfo: 'skip', showlegend: false, meta: 'ellipsoid' };
  }
  function selectionInfo() { // position, axes, time, transmitters and receivers of the selection
    var s = S.sel; if (!s) return null;
    details();
    if (s.layer === 'meas') { var M = D.meas; return { p: pt(M.p, s.i), ax: M.ax.slice(9 * s.i, 9 * s.i + 9), t: M.t[s.i], tx: 1 << M.tx[s.i], rx: 1 << M.rx[s.i] }; }
    if (s.layer === 'beam') { var B = D.beams; return { p: pt(B.p, s.i), ax: null, t: B.t[s.i], tx: B.tx[s.i], rx: B.rx[s.i] }; }
    if (s.layer === 'track') { var T = D.tracks; return { p: pt(T.p, s.i), ax: T.ax.slice(9 * s.i, 9 * s.i + 9), t: T.t[s.i], tx: 0, rx: 0 }; }
    if (s.layer === 'truth') { var P = D.truth[s.i[0]]; return { p: pt(P.p, s.i[1]), ax: null, t: P.t[s.i[1]], tx: 0, rx: 0 }; }
    if (s.layer === 'ship') { return { p: shipAt(s.i, S.t), ax: null, t: S.t, tx: 0, rx: 0 }; }
    return null;
  }
  // Sensor lines of a selection: a solid line from each transmitter, a dotted one from each
  // receiver, each from the ship's position at the object's time.
  function sensorLines(info) {
    var out = [];
    D.radars.forEach(function (r, i) {
      var q = shipAt(i, info.t); if (!q) return;
      if (info.tx & (1 << i)) out.push({ radar: r.id, role: 'tx', from: q, to: info.p });
      if (info.rx & (1 << i)) out.push({ radar: r.id, role: 'rx', from: q, to: info.p });
    });
    return out;
  }

  function row(k, v) { return '<tr><td>' + k + '</td><td>' + v + '</td></tr>'; }
  function posRows(p) {
    var e = toEcef(p[0], p[1], p[2]), g = geodetic(e);
    return row('lat, lon', fmt(g[0], 5) + '°, ' + fmt(g[1], 5) + '°') + row('alt', fmt(g[2], 0) + ' m') +
      row('ECEF', fmt(e[0], 0) + ', ' + fmt(e[1], 0) + ', ' + fmt(e[2], 0) + ' m') + row('ENU (plot)', p.join(', ') + ' m');
  }
  function axRows(ax) {
    var L = [0, 3, 6].map(function (o) { return Math.hypot(ax[o], ax[o + 1], ax[o + 2]); });
    return row('1σ semi-axes', L.map(function (x) { return fmt(x, 1); }).join(', ') + ' m');
  }
  function renderPanel() {
    var s = S.sel, h = '', body = document.getElementById('infobody');
    if (!s) { body.innerHTML = 'Click a truth, track, measurement, beam or ship.'; body.dataset.layer = ''; return; }
    details();
    if (s.layer === 'meas') {
      var M = D.meas, i = s.i, bist = M.tx[i] !== M.rx[i];
      h = row('object', (bist ? 'bistatic' : 'monostatic') + ' measurement ' + M.id[i]) + row('time', fmt(M.t[i], 3) + ' s') + posRows(pt(M.p, i)) +
        row('SNR', fmt(M.snr[i], 1) + ' dB') + row('dwell kind', D.meta.kinds[M.kind[i]]) +
        row('transmitter', D.radars[M.tx[i]].id) + row('receiver', D.radars[M.rx[i]].id) +
        row('track', M.trk[i] >= 0 ? 'updated track ' + M.trk[i] : 'none') +
        row('truth (hint)', M.hint[i] >= 0 ? D.targets[M.hint[i]] : 'false alarm') + row('merged', M.merged[i] ? 'yes' : 'no') + axRows(M.ax.slice(9 * i, 9 * i + 9));
    } else if (s.layer === 'beam') {
      var B = D.beams; i = s.i;
      h = row('object', D.meta.kinds[B.kind[i]] + ' dwell (group ' + B.gid[i] + ')') + row('time', fmt(B.t[i], 3) + ' s (start)') + posRows(pt(B.p, i)) +
        row('dwell kind', D.meta.kinds[B.kind[i]]) + row('transmitters', radarNames(B.tx[i]).join(', ')) + row('receivers', radarNames(B.rx[i]).join(', ')) +
        row('pulses', B.np[i]) + row('energy', fmt(B.e[i], 1) + ' J');
    } else if (s.layer === 'track') {
      var T = D.tracks; i = s.i;
      h = row('object', 'track ' + T.id[i] + ' (' + D.meta.statuses[T.st[i]] + ')') + row('time', fmt(T.t[i], 3) + ' s') + posRows(pt(T.p, i)) +
        row('velocity', pt(T.v, i).join(', ') + ' m/s (ENU)') + row('updates', T.n[i]) +
        row('assigned truth', (T.truth[i] >= 0 ? D.targets[T.truth[i]] : 'none') + ' at scoring time ' + fmt(T.tk[i], 1) + ' s') + axRows(T.ax.slice(9 * i, 9 * i + 9));
    } else if (s.layer === 'truth') {
      var P = D.truth[s.i[0]]; i = s.i[1];
      h = row('object', 'truth ' + P.id) + row('time', fmt(P.t[i], 3) + ' s') + posRows(pt(P.p, i)) + row('velocity', pt(P.v, i).join(', ') + ' m/s (ENU)');
    } else if (s.layer === 'ship') {
      h = row('object', 'radar ' + D.radars[s.i].id + ' (' + D.radars[s.i].faces.length + ' faces)') + row('time', fmt(S.t, 1) + ' s') + posRows(shipAt(s.i, S.t).map(Math.round));
    }
    body.innerHTML = '<table>' + h + '</table>';
    body.dataset.layer = s.layer;
  }

  // ---- drawing ----
  var gd = document.getElementById('scene'), mg = document.getElementById('metrics');
  // Picking on demand. gl-plot3d draws every trace a second time, with pick shaders into an
  // off-screen buffer, at every change of the scene (each slider step and the first frame), so
  // that a hover or click can be looked up. Under software WebGL the first such pass costs
  // compiling its shaders' draw routines. Draws with a pick program (its fragment shader reads
  // pickId or pickGroup) are skipped while the pointer is outside the scene; when it enters, the
  // pick buffers are drawn at once, before any click can read them (docs/decisions/0017-run-viewer-opening-cuts.md).
  var PICK = { on: false };
  [window.WebGLRenderingContext, window.WebGL2RenderingContext].forEach(function (C) {
    if (!C) return;
    var P = C.prototype, link = P.linkProgram, use = P.useProgram, drawA = P.drawArrays, drawE = P.drawElements;
    P.linkProgram = function (prog) {
      try {
        prog.__mimoPick = this.getAttachedShaders(prog).some(function (sh) {
          return this.getShaderParameter(sh, this.SHADER_TYPE) === this.FRAGMENT_SHADER && /\bpick(Id|Group)\b/.test(this.getShaderSource(sh) || '');
        }, this);
      } catch (e) { /* not a program we can read: drawn as usual */ }
      return link.call(this, prog);
    };
    P.useProgram = function (prog) { this.__mimoProg = prog; return use.call(this, prog); };
    P.drawArrays = function () { if (!PICK.on && this.__mimoProg && this.__mimoProg.__mimoPick) return; return drawA.apply(this, arguments); };
    P.drawElements = function () { if (!PICK.on && this.__mimoProg && this.__mimoProg.__mimoPick) return; return drawE.apply(this, arguments); };
  });
  function picking(on) {
    if (PICK.on === on) return;
    PICK.on = on;
    var sc = on && gd._fullLayout && gd._fullLayout.scene && gd._fullLayout.scene._scene;
    if (!sc || !sc.glplot) return;
    sc.glplot.objects.forEach(function (o) { o.dirty = true; }); // the next redraw draws the pick buffers
    sc.glplot.redraw();
  }
  gd.addEventListener('pointerenter', function () { picking(true); });
  gd.addEventListener('pointermove', function () { picking(true); });
  gd.addEventListener('pointerleave', function () { picking(false); });
  // Framing (crates/mimo-plot/src/framing.rs): the region view shows a box that holds the ships
  // and targets at t. The box is kept while the box of t's step lies inside it and is not much
  // smaller (70 % of its width), so most slider steps do not rescale the scene; otherwise the
  // new box holds this step and the next five (a minute), squared in plan.
  function stepBox(k) { var F = D.framing; k = Math.min(F.lo.length - 1, Math.max(0, k)); return [F.lo[k], F.hi[k]]; }
  function boxInside(b, c) { for (var a = 0; a < 3; a++) if (b[0][a] < c[0][a] || b[1][a] > c[1][a]) return false; return true; }
  function frameAt(t) {
    var F = D.framing, k = Math.floor((t - F.t0_s) / F.step_s), b = stepBox(k);
    if (S.box && boxInside(b, S.box) && (b[1][0] - b[0][0]) > 0.7 * (S.box[1][0] - S.box[0][0])) return;
    var lo = b[0].slice(), hi = b[1].slice();
    for (var j = 1; j <= 5; j++) { var n = stepBox(k + j); for (var a = 0; a < 3; a++) { lo[a] = Math.min(lo[a], n[0][a]); hi[a] = Math.max(hi[a], n[1][a]); } }
    var half = Math.max(hi[0] - lo[0], hi[1] - lo[1]) / 2, cx = (lo[0] + hi[0]) / 2, cy = (lo[1] + hi[1]) / 2;
    S.box = [[Math.floor(cx - half), Math.floor(cy - half), lo[2]], [Math.ceil(cx + half), Math.ceil(cy + half), hi[2]]];
    S.reframes = (S.reframes || 0) + 1;
  }
  window.__mimo.frameAt = frameAt;
  function sceneLayout() {
    frameAt(S.t);
    var lo = S.box[0], hi = S.box[1], sc;
    // No axis box, ticks or titles: an ENU-metre box says little on a globe, and tick text is
    // costly to draw (text vectorised per label).
    // The axes are "visible" with no ticks and empty titles rather than hidden: plotly leaves a
    // hidden axis with gl-axes3d's default ticks (−3…3) and titles "x", "y", whose text is
    // vectorised again at every render although nothing is drawn (docs/decisions/0017-run-viewer-opening-cuts.md).
    var NOTICKS = { showticklabels: false, ticks: '', tickmode: 'array', tickvals: [], ticktext: [], showgrid: false, showline: false,
      zeroline: false, showspikes: false, showaxeslabels: false, title: { text: '' } };
    var ax = function (r) { return Object.assign({ visible: true, range: r, showbackground: false }, NOTICKS); };
    if (S.mode === 'region') {
      var w = hi[0] - lo[0];
      sc = { xaxis: ax([lo[0], hi[0]]), yaxis: ax([lo[1], hi[1]]), zaxis: ax([lo[2], hi[2]]),
        aspectmode: 'manual', aspectratio: { x: 1, y: (hi[1] - lo[1]) / w, z: Math.max(0.05, S.vex * (hi[2] - lo[2]) / w) },
        camera: { eye: { x: -0.45, y: -0.8, z: 0.55 }, center: { x: 0, y: 0, z: -0.1 } } }; // frames the box of ships and targets
      // The sea, under the graticule: the scene's background colour (a clear of the canvas), not
      // the up axis's floor, whose faces cost a few hundred ms of software WebGL in the first frame.
      if (S.layers.earth) sc.bgcolor = '#e3eef7';
    } else {
      sc = { xaxis: ax([-6.5e6, 6.5e6]), yaxis: ax([-6.5e6, 6.5e6]), zaxis: ax([-12.8e6, 2e5]),
        aspectmode: 'data', camera: { eye: { x: 0, y: -0.25, z: 0.9 }, center: { x: 0, y: 0, z: 0 } } };
    }
    sc.annotations = S.labels || [];
    return { scene: sc, margin: { l: 0, r: 0, t: 0, b: 0 }, height: gd.clientHeight, uirevision: S.mode + S.vex, showlegend: false, paper_bgcolor: '#fff' };
  }
  // Renders run one at a time; a draw() asked for while one is queued joins it (its promise
  // resolves after a render that saw every change made before it started).
  // No mode bar (its buttons are SVG drawn at opening; the scene keeps mouse rotate/zoom/pan),
  // and no 'responsive' (its relayout on resize); a window resize relayouts both plots once.
  var CONFIG = { displaylogo: false, displayModeBar: false, responsive: false };
  var resizeTimer = null;
  window.addEventListener('resize', function () {
    clearTimeout(resizeTimer);
    resizeTimer = setTimeout(function () { Plotly.Plots.resize(gd); Plotly.Plots.resize(mg); }, 150);
  });
  var running = Promise.resolve(), queued = null, inflight = 0, rendered = 0;
  function draw() {
    if (queued) return queued;
    inflight++;
    var p = running.then(function () {
      queued = null;
      return Plotly.react(gd, build(S.t), sceneLayout(), CONFIG);
    }).then(function () {
      keepStatic();
      inflight--; rendered++;
      document.getElementById('tlabel').textContent = 't = ' + S.t.toFixed(1) + ' s';
      if (!mg._fullLayout) return null; // the metrics panel is not drawn yet (it shows S.t when it is)
      return Plotly.relayout(mg, { 'shapes[0].x0': S.t, 'shapes[0].x1': S.t });
    });
    queued = p;
    running = p.catch(function (e) { inflight = 0; window.__mimo.errors.push('draw: ' + e); });
    return p;
  }
  function setTime(t) {
    S.t = Math.min(D.meta.to_s, Math.max(D.meta.from_s, t));
    document.getElementById('time').value = S.t;
    return draw();
  }
  function select(layer, i) { S.sel = { layer: layer, i: i }; renderPanel(); return draw(); }
  window.__mimo.select = select; window.__mimo.setTime = setTime; window.__mimo.state = S;
  window.__mimo.selectionInfo = selectionInfo; window.__mimo.sensorLines = function () { var i = selectionInfo(); return i ? sensorLines(i) : []; };

  function metricsPlot() {
    var m = D.metrics;
    var traces = [
      { x: m.t, y: m.completeness, name: 'completeness', type: 'scatter', mode: 'lines', line: { color: '#1f77b4' }, connectgaps: false },
      { x: m.t, y: m.energy_j, name: 'energy per interval (J)', type: 'scatter', mode: 'lines', yaxis: 'y2', line: { color: '#ff7f0e', width: 1 } },
      { x: m.t, y: m.ta_energy_j, name: 'TA energy per interval (J)', type: 'scatter', mode: 'lines', yaxis: 'y2', line: { color: '#2ca02c', width: 1 } }
    ];
    var layout = {
      margin: { l: 50, r: 60, t: 24, b: 36 }, height: mg.clientHeight, hovermode: 'x', showlegend: true, legend: { orientation: 'h', y: 1.18 },
      xaxis: { title: { text: 'scoring time (s)' }, range: [D.meta.from_s, D.meta.to_s] },
      yaxis: { title: { text: 'completeness' }, range: [0, 1.05] },
      yaxis2: { title: { text: 'J' }, overlaying: 'y', side: 'right', rangemode: 'tozero' },
      shapes: [{ type: 'line', xref: 'x', yref: 'paper', x0: S.t, x1: S.t, y0: 0, y1: 1, line: { color: '#d62728', width: 2 } },
        { type: 'line', xref: 'paper', yref: 'y', x0: 0, x1: 1, y0: 0.98, y1: 0.98, line: { color: '#888', width: 1, dash: 'dash' } }]
    };
    return Plotly.newPlot(mg, traces, layout, CONFIG).then(function () {
      mg.on('plotly_click', function (ev) { if (ev.points && ev.points.length) setTime(Number(ev.points[0].x)); });
    });
  }

  // ---- controls ----
  function checkbox(parent, label, checked, onchange, color) {
    var l = document.createElement('label'), c = document.createElement('input');
    c.type = 'checkbox'; c.checked = checked; c.addEventListener('change', function () { onchange(c.checked); draw(); });
    l.appendChild(c);
    if (color) { var s = document.createElement('span'); s.className = 'sw'; s.style.background = color; l.appendChild(s); }
    l.appendChild(document.createTextNode(label)); parent.appendChild(l); return c;
  }
  function controls() {
    var names = { earth: 'earth', coast: 'coastlines', ships: 'ships', faces: 'faces', truth: 'truth', tracks: 'tracks', meas: 'measurements', beams: 'beams' };
    var lay = document.getElementById('layers');
    Object.keys(names).forEach(function (k) { checkbox(lay, names[k], S.layers[k], function (v) { S.layers[k] = v; }).id = 'layer-' + k; });
    var rd = document.getElementById('radars');
    D.radars.forEach(function (r, i) { checkbox(rd, r.id, true, function (v) { S.radarsOn[i] = v; }, RADAR_COLORS[i % RADAR_COLORS.length]).id = 'radar-' + r.id; });
    var kd = document.getElementById('kinds');
    D.meta.kinds.forEach(function (k, i) { checkbox(kd, k, true, function (v) { S.kindsOn[i] = v; }, KIND_COLORS[i]).id = 'kind-' + k; });
    document.getElementById('sig1').addEventListener('change', function (e) { S.sig1 = e.target.checked; draw(); });
    document.getElementById('sig3').addEventListener('change', function (e) { S.sig3 = e.target.checked; draw(); });
    var slider = document.getElementById('time');
    slider.min = D.meta.from_s; slider.max = D.meta.to_s; slider.value = S.t;
    slider.addEventListener('input', function () { setTime(Number(slider.value)); });
    document.getElementById('trail').addEventListener('change', function (e) { S.trail = Number(e.target.value); draw(); });
    document.getElementById('speed').addEventListener('change', function (e) { S.speed = Number(e.target.value); });
    document.getElementById('mode').addEventListener('change', function (e) { S.mode = e.target.value; draw(); });
    document.getElementById('vex').addEventListener('change', function (e) { S.vex = Number(e.target.value); draw(); });
    // The scene has no mode bar (CONFIG): this button stands for its "reset camera".
    document.getElementById('recenter').addEventListener('click', function () {
      S.box = null;
      Plotly.relayout(gd, { 'scene.camera': sceneLayout().scene.camera }).then(draw);
    });
    var btn = document.getElementById('play'), last = null;
    // Play: every 40 ms, once the last render is done, time moves on by speed × the wall time
    // since the previous step (a timer, not animation frames, which headless browsers may hold).
    var gen = 0;
    function tick(g) {
      if (!S.playing || g !== gen) return;
      var now = performance.now();
      if (inflight === 0) {
        if (last !== null) {
          var nt = S.t + S.speed * (now - last) / 1000;
          if (nt >= D.meta.to_s) { S.playing = false; btn.textContent = '▶ play'; }
          setTime(nt);
        }
        last = now;
      }
      setTimeout(function () { tick(g); }, 40);
    }
    btn.addEventListener('click', function () {
      S.playing = !S.playing; btn.textContent = S.playing ? '❚❚ pause' : '▶ play'; last = null; gen++;
      if (S.playing) tick(gen);
    });
    gd.on('plotly_click', function (ev) {
      var p = ev.points && ev.points[0]; if (!p) return;
      var cd = p.customdata; if (!Array.isArray(cd)) return;
      if (cd[0] === 'truth') select('truth', [cd[1], cd[2]]);
      else if (['meas', 'beam', 'track', 'ship'].indexOf(cd[0]) >= 0) select(cd[0], cd[1]);
    });
    var legend = document.getElementById('legend');
    legend.innerHTML = '<h3>Legend</h3>truth: black line, ● now · tracks: coloured by id, ⋯ tentative, — confirmed, × deleted · ' +
      'measurements: ● monostatic, ◆ bistatic, coloured by receiver · beams: □ by kind · selection: red — transmitter, blue ⋯ receiver, orange 1σ/3σ ellipsoid';
    document.getElementById('subtitle').textContent = ' run ' + D.meta.run + ' of ' + D.meta.run_dir + ' · ' + D.meta.tracker +
      ' · ' + D.meta.from_s + '–' + D.meta.to_s + ' s · metrics: ' + D.metrics.source;
    var dl = document.getElementById('dropped');
    D.meta.dropped.forEach(function (s) { var li = document.createElement('li'); li.textContent = s; dl.appendChild(li); });
  }

  // ---- self-test (view.html#selftest): click a measurement, ellipsoids, toggles, linked
  // panel, play/pause, slider; report ----
  function clickBox(id) { document.getElementById(id).click(); return draw(); }
  function selftest() {
    var v = { ok: false, checks: {} }, out = document.getElementById('selftest');
    function finish() {
      v.errors = window.__mimo.errors; v.network = window.__mimo.network;
      v.ok = Object.keys(v.checks).every(function (k) { return v.checks[k] === true; }) && !v.errors.length && !v.network.length;
      out.textContent = 'MIMO-SELFTEST ' + JSON.stringify(v);
    }
    try {
      v.first_render_ms = window.__mimo.firstRenderMs;
      v.marks = MARKS;
      var M = D.meas, target = -1;
      for (var i = 0; i < M.t.length && target < 0; i++) if (M.tx[i] !== M.rx[i]) target = i;
      if (target < 0 && M.t.length) target = 0;
      v.checks.has_measurement = target >= 0;
      v.checks.scene_has_webgl = !!gd.querySelector('canvas');
      if (target < 0) { finish(); return; }
      setTime(M.t[target]).then(function () {
        // The click goes through plotly's own click event, as a user's does.
        var trace = gd.data.find(function (d) { return d.meta === 'objects'; }), k = -1;
        if (trace) trace.customdata.forEach(function (cd, j) { if (cd[0] === 'meas' && cd[1] === target) k = j; });
        v.checks.measurement_drawn = k >= 0;
        gd.emit('plotly_click', { points: [{ data: trace, pointNumber: k, customdata: k >= 0 ? trace.customdata[k] : undefined }] });
        return draw();
      }).then(function () {
        var body = document.getElementById('infobody');
        v.panel = body.innerText;
        v.checks.panel_filled = body.dataset.layer === 'meas' && /SNR/.test(v.panel) && /transmitter/.test(v.panel) && /lat, lon/.test(v.panel);
        var ls = window.__mimo.sensorLines();
        v.sensor_lines = ls.map(function (l) { return l.role + ':' + l.radar; });
        var want = ['tx:' + D.radars[M.tx[target]].id, 'rx:' + D.radars[M.rx[target]].id];
        v.checks.sensor_lines_join_the_radars = want.every(function (w) { return v.sensor_lines.indexOf(w) >= 0; });
        // Drawn: a red (transmit) segment in the solid trace and a blue (receive) one in the dotted.
        var colours = function (name) { var d = gd.data.find(function (x) { return x.name === name; }); return d ? d.line.color : []; };
        v.checks.sensor_lines_drawn = colours('solid lines').indexOf('#d62728') >= 0 && colours('dotted lines').indexOf('#1f77b4') >= 0;
        v.selected = { meas_id: M.id[target], t: M.t[target], enu: pt(M.p, target) };
        // The 1σ and 3σ ellipsoids are drawn; unticking 3σ leaves the 1σ one.
        var meshes = function () { return gd.data.filter(function (d) { return d.type === 'mesh3d'; }).map(function (d) { return d.name; }).sort().join(','); };
        v.ellipsoids = meshes();
        return clickBox('sig3').then(function () {
          v.checks.ellipsoids_1_and_3_sigma = v.ellipsoids === '1σ,3σ' && meshes() === '1σ';
          return clickBox('sig3');
        });
      }).then(function () {
        // Per-kind and per-radar toggles: untick, look at the drawn measurements, tick again.
        var drawn = function () { var d = gd.data.find(function (x) { return x.meta === 'objects'; }); return d.customdata.filter(function (c) { return c[0] === 'meas'; }).map(function (c) { return c[1]; }); };
        var all = drawn(), k0 = M.kind[target], r0 = M.rx[target];
        return clickBox('kind-' + D.meta.kinds[k0]).then(function () {
          var off = drawn();
          v.checks.kind_toggle_hides_its_measurements = all.indexOf(target) >= 0 && off.length < all.length && off.every(function (i) { return M.kind[i] !== k0; });
          return clickBox('kind-' + D.meta.kinds[k0]);
        }).then(function () { return clickBox('radar-' + D.radars[r0].id); }).then(function () {
          var off = drawn();
          v.checks.radar_toggle_hides_its_measurements = off.length < all.length && off.every(function (i) { return M.tx[i] !== r0 || M.rx[i] !== r0; });
          return clickBox('radar-' + D.radars[r0].id);
        }).then(function () { v.checks.toggles_restore = drawn().length === all.length; });
      }).then(function () {
        // The linked metrics panel: a click at a scoring time moves the 3-D view there.
        var tk = D.metrics.t[Math.floor(D.metrics.t.length / 2)];
        mg.emit('plotly_click', { points: [{ x: tk }] });
        return draw().then(function () { v.checks.metrics_click_moves_time = Math.abs(S.t - tk) < 1e-9; });
      }).then(function () {
        // Play for a moment, then pause: time moves on, then stands.
        var btn = document.getElementById('play'), t0 = S.t = D.meta.from_s;
        btn.click();
        return new Promise(function (r) { // until time has moved (at most 20 s)
          var waited = 0;
          (function poll() { if (S.t > t0 || waited >= 20000) r(); else { waited += 100; setTimeout(poll, 100); } })();
        }).then(function () {
          btn.click();
          var t1 = S.t;
          return draw().then(function () { return new Promise(function (r) { setTimeout(r, 500); }); }).then(function () {
            v.play = { from_s: t0, paused_at_s: t1, after_s: S.t };
            v.checks.play_then_pause = t1 > t0 && !S.playing && S.t === t1;
          });
        });
      }).then(function () {
        var truthNow = function () { var d = gd.data.find(function (x) { return x.meta === 'objects'; }); return JSON.stringify(d.x.filter(function (_, j) { return d.customdata[j][0] === 'truth'; })); };
        var truthBefore = truthNow();
        var slider = document.getElementById('time'), t2 = Math.min(D.meta.to_s, M.t[target] + 20);
        slider.value = t2;
        slider.dispatchEvent(new Event('input'));
        return draw().then(function () {
          var truthAfter = truthNow();
          v.checks.slider_moves_state = Math.abs(S.t - t2) < 0.11 && truthAfter !== truthBefore &&
            document.getElementById('tlabel').textContent.indexOf(t2.toFixed(1)) >= 0;
          v.renders = rendered;
          // Smoothness: twenty slider steps of 1 s, each timed from the slider's input event to
          // its render done. The earth is not uploaded again, and the framing box holds every
          // ship and every live target at each step.
          var k = 0, times = [], uploads = window.__mimo.staticUploads, reframes = S.reframes, framed = true;
          function holds() {
            var r = gd._fullLayout.scene, inR = function (p) { return ['xaxis', 'yaxis', 'zaxis'].every(function (a, j) { return p[j] >= r[a].range[0] && p[j] <= r[a].range[1]; }); };
            D.radars.forEach(function (x, i) { var p = shipAt(i, S.t); if (p && !inR(p)) framed = false; });
            D.truth.forEach(function (p) { if (S.t >= p.t[0] && S.t <= p.t[p.t.length - 1] && !inR(interp(p.t, p.p, S.t))) framed = false; });
          }
          function step() {
            if (k >= 20) {
              v.step_render_ms = times.reduce(function (a, b) { return a + b; }, 0) / times.length;
              v.step_worst_ms = Math.max.apply(null, times);
              v.step_ms = times.map(Math.round);
              v.reframes = S.reframes;
              v.earth_uploads = window.__mimo.staticUploads - uploads;
              v.reframes_in_steps = S.reframes - reframes;
              v.checks.earth_not_uploaded_on_slider_steps = v.earth_uploads === 0;
              v.checks.framing_holds_ships_and_targets = framed;
              finish(); return;
            }
            k++;
            var s0 = performance.now();
            slider.value = t2 - k;
            slider.dispatchEvent(new Event('input'));
            return draw().then(function () { times.push(performance.now() - s0); holds(); }).then(step);
          }
          return step();
        });
      }).catch(function (e) { window.__mimo.errors.push('selftest: ' + e); finish(); });
    } catch (e) { window.__mimo.errors.push('selftest: ' + e); finish(); }
  }

  // ---- start ----
  var hash = {};
  location.hash.replace(/^#/, '').split('&').forEach(function (kv) { var p = kv.split('='); if (p[0]) hash[p[0]] = p.length > 1 ? decodeURIComponent(p[1]) : true; });
  if (hash.t !== undefined && isFinite(Number(hash.t))) S.t = Math.min(D.meta.to_s, Math.max(D.meta.from_s, Number(hash.t)));
  if (hash.mode === 'globe') { S.mode = 'globe'; document.getElementById('mode').value = 'globe'; }
  // Marks (performance.now(), ms since navigation): data parsed, scene drawn, first render =
  // the scene on screen (two animation frames later, so its first WebGL frame is painted),
  // metrics panel drawn, and all_drawn = both on screen. The metrics panel and the controls
  // are made after the scene is painted, so the scene appears first.
  // scripts/plot_open_time.sh reads them.
  // Two animation frames, or 5 s if frames are held (headless Chromium under a virtual time
  // budget may not run them, and would then spend its budget before the self-test starts).
  var frames2 = function () {
    return new Promise(function (r) { requestAnimationFrame(function () { requestAnimationFrame(r); }); setTimeout(r, 5000); });
  };
  // The metrics panel is drawn when the browser is next idle after the scene's first frame (at
  // most 200 ms later), so it never delays the scene.
  var idle = function () {
    return new Promise(function (r) { if (window.requestIdleCallback) requestIdleCallback(function () { r(); }, { timeout: 200 }); else setTimeout(r, 0); });
  };
  Plotly.newPlot(gd, build(S.t), sceneLayout(), CONFIG).then(function () {
    keepStatic();
    MARKS.scene_ms = performance.now();
    document.getElementById('tlabel').textContent = 't = ' + S.t.toFixed(1) + ' s';
    return frames2();
  }).then(function () {
    window.__mimo.firstRenderMs = MARKS.first_render_ms = performance.now();
    controls();
    return idle().then(metricsPlot);
  }).then(function () {
    MARKS.metrics_ms = performance.now();
    return frames2();
  }).then(function () {
    document.getElementById('time').value = S.t;
    MARKS.all_drawn_ms = performance.now();
    document.body.dataset.marks = JSON.stringify(MARKS);
    document.body.dataset.ready = '1';
    if (hash.select === 'mimo') { // open with a bistatic measurement near t selected (for screenshots)
      var M = D.meas, best = -1;
      for (var i = lowerBound(M.t, S.t - S.trail); i < upperBound(M.t, S.t); i++) if (M.tx[i] !== M.rx[i]) best = i;
      if (best >= 0) select('meas', best);
    }
    if (hash.selftest) selftest();
  }).catch(function (e) { window.__mimo.errors.push('start: ' + e); });
})();
