// mimo study: the report page's logic. Data (D) are gathered by crates/mimo-study/src/page_data.rs
// from the study's tables (docs/studies.md, "The page").
(function () {
  'use strict';
  var MARKS = window.__mimo.marks;
  MARKS.plotly_loaded_ms = performance.now();
  var D = JSON.parse(document.getElementById('mimo-data').textContent);
  MARKS.data_parsed_ms = performance.now();
  var R = D.required;
  var CONFIG = { displaylogo: false, responsive: true };
  var PALETTE = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#8c564b', '#e377c2', '#17becf', '#7f7f7f', '#bcbd22'];
  var FIGURES = {
    completeness: 'completeness', energy_per_object_j: 'energy / object (J)', energy_search_j: 'search (J)',
    energy_confirm_true_j: 'confirm true (J)', energy_confirm_false_j: 'confirm false (J)', energy_track_j: 'track (J)',
    energy_track_false_j: 'track false (J)', breaks: 'breaks', switches: 'switches', first_track_mean_s: 'first track mean (s)',
    first_track_max_s: 'first track worst (s)', never_tracked: 'never tracked'
  };
  function $(id) { return document.getElementById(id); }
  function esc(s) {
    return String(s).replace(/[&<>"]/g, function (c) { return { '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;' }[c]; });
  }
  function fmt(v) {
    if (v === null || v === undefined || !isFinite(v)) return '–';
    var a = Math.abs(v);
    if (a >= 1000) return v.toFixed(0);
    if (a >= 100) return v.toFixed(1);
    if (a === 0) return '0';
    return String(Number(v.toPrecision(4)));
  }
  function withCi(t) { return t[1] !== null && t[2] !== null ? fmt(t[0]) + ' (' + fmt(t[1]) + '–' + fmt(t[2]) + ')' : fmt(t[0]); }
  function unique(xs) { var out = []; xs.forEach(function (x) { if (out.indexOf(x) < 0) out.push(x); }); return out; }
  // A word for a POSIX shell, as crates/mimo-study/src/rerun.rs quotes it.
  function quote(s) { return /^[A-Za-z0-9_.\/=@:,+%-]+$/.test(s) ? s : "'" + s.replace(/'/g, "'\\''") + "'"; }
  function command(cell, run) {
    var out = D.rerun_root + '/' + cell.rel + '/run-' + run;
    return 'mimo study ' + quote(D.plan) + ' --rerun ' + quote(cell.rel) + ' --run ' + run + ' --out ' + quote(out) +
      ' && mimo plot ' + quote(out) + ' --run ' + run + ' --out ' + quote(out + '.html');
  }
  function options(sel, values) { sel.innerHTML = values.map(function (v) { return '<option>' + esc(v) + '</option>'; }).join(''); }

  var families = unique(D.cells.map(function (c) { return c.f; }));
  var colour = {};
  families.forEach(function (f, i) { colour[f] = PALETTE[i % PALETTE.length]; });
  var enabled = {};
  families.forEach(function (f) { enabled[f] = true; });
  var scenarios = unique(D.cells.map(function (c) { return c.sc; }));
  var S = { sc: scenarios[0], pt: null, scale: 'log', axis: D.axes.length ? D.axes[0].name : null, ssc: scenarios[0] };

  $('subtitle').textContent = 'plan ' + D.plan + ' · seed ' + D.seed + ' · ' + D.runs + ' Monte Carlo run(s) per cell · ' +
    D.cells.length + ' cells · required completeness ' + (100 * R) + ' %';
  $('notes').innerHTML = D.notes.map(function (n) { return '<li>' + esc(n) + '</li>'; }).join('');

  // ---- the frontier ----
  // The energy the frontiers are built on: the total (search and test article) or the test article's part.
  var TA_BASIS = D.energy === 'test_article';
  var E_WORD = TA_BASIS ? 'TA energy / object ' : 'energy / object ';
  function pointsOf(sc) { return unique(D.cells.filter(function (c) { return c.sc === sc; }).map(function (c) { return c.pt; })); }
  function errBar(t) {
    var ok = t[0] !== null && t[1] !== null && t[2] !== null;
    return { plus: ok ? Math.max(0, t[2] - t[0]) : 0, minus: ok ? Math.max(0, t[0] - t[1]) : 0 };
  }
  function hoverCell(c) {
    return '<b>' + esc(c.m) + '</b><br>scenario ' + esc(c.sc) + (c.pt !== '—' ? ' · ' + esc(c.pt) : '') +
      '<br>completeness ' + withCi(c.c) + '<br>' + E_WORD + withCi(c.e) + ' J' +
      '<br>' + c.n + ' runs' + (c.failed ? ', ' + c.failed + ' failed' : '') +
      (c.front === true ? '<br>on the frontier' : c.front === false ? '<br>off the frontier' : '') + '<br><i>click: list its runs</i>';
  }
  function frontierTraces() {
    var here = D.cells.map(function (c, i) { return [c, i]; }).filter(function (x) { return x[0].sc === S.sc && x[0].pt === S.pt; });
    var traces = [], why = [];
    var fams = unique(here.map(function (x) { return x[0].f; }));
    var curves = 0;
    fams.forEach(function (f) {
      var pts = here.filter(function (x) { return x[0].f === f && x[0].c[0] !== null && x[0].e[0] !== null; });
      var all = here.filter(function (x) { return x[0].f === f; });
      if (all.length > 1) curves++;
      if (!enabled[f]) return;
      if (pts.length < all.length) why.push(f + ': ' + (all.length - pts.length) + ' point(s) without a completed run are not drawn');
      var conv = all[0][0].arch === 'conventional';
      var ex = pts.map(function (x) { return errBar(x[0].e); }), ey = pts.map(function (x) { return errBar(x[0].c); });
      traces.push({
        type: 'scatter', mode: 'markers', name: f + (all[0][0].arch ? ' (' + all[0][0].arch + ')' : ''), legendgroup: f,
        x: pts.map(function (x) { return x[0].e[0]; }), y: pts.map(function (x) { return x[0].c[0]; }),
        customdata: pts.map(function (x) { return x[1]; }), text: pts.map(function (x) { return hoverCell(x[0]); }),
        hovertemplate: '%{text}<extra></extra>',
        marker: { color: colour[f], size: pts.map(function (x) { return x[0].front === false ? 6 : 10; }), symbol: conv ? 'square' : 'circle' },
        error_x: { type: 'data', symmetric: false, array: ex.map(function (b) { return b.plus; }), arrayminus: ex.map(function (b) { return b.minus; }), thickness: 1, width: 2, color: colour[f] },
        error_y: { type: 'data', symmetric: false, array: ey.map(function (b) { return b.plus; }), arrayminus: ey.map(function (b) { return b.minus; }), thickness: 1, width: 2, color: colour[f] }
      });
      var front = pts.filter(function (x) { return x[0].front === true; }).sort(function (a, b) { return a[0].e[0] - b[0].e[0]; });
      if (front.length > 1) {
        traces.push({
          type: 'scatter', mode: 'lines', name: f + ' frontier', legendgroup: f, showlegend: false, hoverinfo: 'skip',
          x: front.map(function (x) { return x[0].e[0]; }), y: front.map(function (x) { return x[0].c[0]; }),
          line: { color: colour[f], dash: conv ? 'dash' : 'solid', width: 2 }
        });
      }
      D.crossings.filter(function (k) { return k.f === f && k.sc === S.sc && k.pt === S.pt; }).forEach(function (k) {
        if (k.e98[0] === null) {
          if (all.length > 1 || k.reason) why.push(f + ': no crossing of ' + (100 * R) + ' %' + (k.reason ? ' — ' + k.reason : ''));
          return;
        }
        var lo = k.e98[1], hi = k.e98[2];
        traces.push({
          type: 'scatter', mode: 'markers', name: f + ' crossing', legendgroup: f, showlegend: false,
          x: [k.e98[0]], y: [R], marker: { color: colour[f], size: 13, symbol: 'triangle-up', line: { color: '#000', width: 1 } },
          error_x: { type: 'data', symmetric: false, array: [hi !== null ? hi - k.e98[0] : 0], arrayminus: [lo !== null ? k.e98[0] - lo : 0], thickness: 2, width: 6, color: colour[f] },
          text: ['<b>' + esc(f) + ' crosses ' + (100 * R) + ' %</b><br>' + E_WORD + fmt(k.e98[0]) + ' J (' +
            (lo !== null ? fmt(lo) : '…') + '–' + (hi !== null ? fmt(hi) : '…') + ')<br>between ' + esc(k.bracket[0] || '–') +
            ' and ' + esc(k.bracket[1] || '–')],
          hovertemplate: '%{text}<extra></extra>'
        });
      });
    });
    if (D.cells.length === 1) why.unshift('The study has one point: there is no frontier to draw, only that point.');
    else if (here.length && curves === 0) {
      why.unshift('No frontier here: every method is one point (no method of the plan sweeps a knob), so there is no curve to cross ' +
        (100 * R) + ' % — sweep a knob (docs/studies.md, "Sweeping a method") to get a frontier.');
    }
    return { traces: traces, why: why };
  }
  function frontierLayout() {
    return {
      margin: { l: 60, r: 20, t: 30, b: 50 },
      xaxis: { title: { text: TA_BASIS ? 'test-article energy per scorable object (J), background search left out' : 'total energy per scorable object (J), every transmit dwell' }, type: S.scale },
      yaxis: { title: { text: 'mean track completeness' } },
      legend: { orientation: 'h', y: -0.18 },
      hovermode: 'closest',
      shapes: [{ type: 'line', xref: 'paper', x0: 0, x1: 1, y0: R, y1: R, line: { color: '#c00', width: 1, dash: 'dot' } }],
      annotations: [{ xref: 'paper', x: 1, y: R, xanchor: 'right', yanchor: 'bottom', text: (100 * R) + ' %', showarrow: false, font: { color: '#c00' } }]
    };
  }
  function drawFrontier() {
    var f = frontierTraces();
    $('f-why').textContent = f.why.join(' · ');
    return Plotly.react('frontier', f.traces, frontierLayout(), CONFIG);
  }
  function frontierControls() {
    options($('f-scenario'), scenarios);
    $('f-scenario').value = S.sc;
    var pts = pointsOf(S.sc);
    options($('f-point'), pts);
    if (pts.indexOf(S.pt) < 0) S.pt = pts[0];
    $('f-point').value = S.pt;
    $('f-point-label').style.display = pts.length > 1 ? '' : 'none';
  }
  function methodToggles() {
    $('f-methods').innerHTML = 'methods ' + families.map(function (f, i) {
      return '<label><input type="checkbox" data-family="' + i + '" checked><span style="color:' + colour[f] + '">■</span> ' + esc(f) + '</label>';
    }).join(' ');
    Array.prototype.forEach.call($('f-methods').querySelectorAll('input'), function (box) {
      box.addEventListener('change', function () { enabled[families[Number(box.dataset.family)]] = box.checked; drawFrontier(); });
    });
  }

  // ---- the runs of a point ----
  function sortable(table) {
    var ths = table.querySelectorAll('th');
    Array.prototype.forEach.call(ths, function (th, col) {
      th.addEventListener('click', function () {
        var asc = !th.classList.contains('asc');
        Array.prototype.forEach.call(ths, function (t) { t.classList.remove('asc', 'desc'); });
        th.classList.add(asc ? 'asc' : 'desc');
        var body = table.tBodies[0], rows = Array.prototype.slice.call(body.rows);
        var key = function (r) { return r.cells[col] ? r.cells[col].textContent.trim() : ''; };
        var num = function (s) { var m = /^[-+]?(\d+\.?\d*|\.\d+)(e[-+]?\d+)?/i.exec(s.replace(/^[^\d.+-]+/, '')); return m ? Number(m[0]) : NaN; };
        var numeric = rows.every(function (r) { var k = key(r); return k === '' || k === '–' || !isNaN(num(k)); });
        rows.sort(function (a, b) {
          var x = key(a), y = key(b), c;
          if (numeric) {
            var p = num(x), q = num(y);
            if (isNaN(p) && isNaN(q)) c = 0; else if (isNaN(p)) return 1; else if (isNaN(q)) return -1; else c = p - q;
          } else c = x.localeCompare(y, undefined, { numeric: true });
          return asc ? c : -c;
        });
        rows.forEach(function (r) { body.appendChild(r); });
      });
    });
  }
  function showRuns(ci) {
    var c = D.cells[ci];
    if (!c) return;
    var head = ['run'].concat(D.figures.map(function (f) { return FIGURES[f] || f; })).concat(['failure', 'command: re-create the run and open it in mimo plot']);
    var rows = c.runs.map(function (r) {
      var cells = ['<td class="num">' + r[0] + '</td>'];
      for (var k = 1; k <= D.figures.length; k++) cells.push('<td class="num">' + fmt(r[k]) + '</td>');
      cells.push('<td>' + esc(r[D.figures.length + 1] || '') + '</td>');
      cells.push('<td><code class="cmd">' + esc(command(c, r[0])) + '</code></td>');
      return '<tr data-run="' + r[0] + '">' + cells.join('') + '</tr>';
    });
    $('runs').innerHTML = '<p><b>' + esc(c.m) + '</b> (family ' + esc(c.f) + (c.arch ? ', ' + esc(c.arch) : '') + ') · scenario ' +
      esc(c.sc) + (c.pt !== '—' ? ' · ' + esc(c.pt) : '') + ' · cell <code>' + esc(c.rel) + '</code><br>completeness ' + withCi(c.c) +
      ' · ' + E_WORD + withCi(c.e) + ' J · ' + c.n + ' runs' + (c.failed ? ', ' + c.failed + ' failed' : '') +
      '. Energies by purpose are the run\'s totals over every radar; each command re-runs the run with the study\'s plan, seed and cell and keeps its tables.</p>' +
      '<div class="wrap"><table id="runs-table"><thead><tr>' + head.map(function (h) { return '<th>' + esc(h) + '</th>'; }).join('') +
      '</tr></thead><tbody>' + rows.join('') + '</tbody></table></div>';
    sortable($('runs-table'));
    $('runs-box').scrollIntoView({ block: 'nearest' });
  }

  // ---- failure points along each stress axis ----
  function atBaseline(c, axis) {
    return D.axes.every(function (a) { return a.name === axis || c.ax[a.name] === undefined || c.ax[a.name] === a.baseline; });
  }
  function failureTraces() {
    var A = D.axes.filter(function (a) { return a.name === S.axis; })[0];
    var traces = [], why = [];
    if (!A) return { traces: traces, why: ['This plan sweeps no stress axis: there are no failure-point curves (docs/studies.md, "Where each method fails").'], log: false };
    var here = D.cells.map(function (c, i) { return [c, i]; }).filter(function (x) {
      var c = x[0];
      return c.sc === S.ssc && c.ax[A.name] !== undefined && (c.sw === A.name || (c.sw === null && atBaseline(c, A.name)));
    });
    var methods = unique(here.map(function (x) { return x[0].m; }));
    methods.forEach(function (m, k) {
      var pts = here.filter(function (x) { return x[0].m === m && x[0].c[0] !== null; }).sort(function (a, b) { return a[0].ax[A.name] - b[0].ax[A.name]; });
      if (!pts.length) return;
      var col = colour[pts[0][0].f] || PALETTE[k % PALETTE.length];
      var ey = pts.map(function (x) { return errBar(x[0].c); });
      traces.push({
        type: 'scatter', mode: 'lines+markers', name: m, legendgroup: m,
        x: pts.map(function (x) { return x[0].ax[A.name]; }), y: pts.map(function (x) { return x[0].c[0]; }),
        customdata: pts.map(function (x) { return x[1]; }), text: pts.map(function (x) { return hoverCell(x[0]); }),
        hovertemplate: '%{text}<extra></extra>', line: { color: col, dash: k % 2 ? 'dash' : 'solid' }, marker: { color: col, size: 7 },
        error_y: { type: 'data', symmetric: false, array: ey.map(function (b) { return b.plus; }), arrayminus: ey.map(function (b) { return b.minus; }), thickness: 1, width: 2, color: col }
      });
      D.failures.filter(function (f) { return f.m === m && f.sc === S.ssc && f.axis === A.name; }).forEach(function (f) {
        if (f.status === 'crosses' && f.fp[0] !== null) {
          var lo = f.fp[1], hi = f.fp[2];
          traces.push({
            type: 'scatter', mode: 'markers', name: m + ' failure point', legendgroup: m, showlegend: false,
            x: [f.fp[0]], y: [R - 0.01 * (k + 1)], marker: { color: col, size: 11, symbol: 'diamond', line: { color: '#000', width: 1 } },
            error_x: { type: 'data', symmetric: false, array: [hi !== null ? Math.abs(hi - f.fp[0]) : 0], arrayminus: [lo !== null ? Math.abs(f.fp[0] - lo) : 0], thickness: 2, width: 5, color: col },
            text: ['<b>' + esc(m) + '</b> fails at ' + esc(A.name) + ' = ' + fmt(f.fp[0]) + ' (' + (lo !== null ? fmt(lo) : '…') + '–' +
              (hi !== null ? fmt(hi) : '…') + ', ' + esc(f.interval || '') + ')'],
            hovertemplate: '%{text}<extra></extra>'
          });
        } else if (f.status === 'holds') why.push(m + ': holds over the range (to ' + fmt(f.range[1]) + ')');
        else if (f.status === 'fails_at_baseline') why.push(m + ': fails at the baseline (' + fmt(f.range[0]) + ')');
      });
    });
    if (!traces.length) why.unshift('No cell varies ' + A.name + ' on scenario ' + S.ssc + '.');
    return { traces: traces, why: why, log: A.log, label: A.label };
  }
  function drawFailure() {
    var f = failureTraces();
    $('s-why').textContent = f.why.join(' · ');
    $('failure').style.display = f.traces.length ? '' : 'none';
    if (!f.traces.length) return Promise.resolve();
    return Plotly.react('failure', f.traces, {
      margin: { l: 60, r: 20, t: 30, b: 50 }, hovermode: 'closest',
      xaxis: { title: { text: f.label || '' }, type: f.log ? 'log' : 'linear' },
      yaxis: { title: { text: 'mean track completeness' } }, legend: { orientation: 'h', y: -0.18 },
      shapes: [{ type: 'line', xref: 'paper', x0: 0, x1: 1, y0: R, y1: R, line: { color: '#c00', width: 1, dash: 'dot' } }]
    }, CONFIG);
  }
  function failureControls() {
    options($('s-axis'), D.axes.map(function (a) { return a.name; }));
    options($('s-scenario'), scenarios);
    if (S.axis) $('s-axis').value = S.axis;
    $('s-scenario').value = S.ssc;
  }

  // ---- the tables of report.md ----
  function mdTables() {
    $('md-tables').innerHTML = D.tables.map(function (t, i) {
      return '<h3>' + esc(t.section) + '</h3><div class="wrap"><table class="md" id="md-' + i + '"><thead><tr>' +
        t.head.map(function (h) { return '<th>' + esc(h) + '</th>'; }).join('') + '</tr></thead><tbody>' +
        t.rows.map(function (r) {
          return '<tr>' + r.map(function (c) { return '<td' + (/^[-+]?\d/.test(c) ? ' class="num"' : '') + '>' + esc(c) + '</td>'; }).join('') + '</tr>';
        }).join('') + '</tbody></table></div>';
    }).join('') || '<p>report.md has no table.</p>';
    Array.prototype.forEach.call(document.querySelectorAll('table.md'), sortable);
  }

  // ---- self-test (report.html#selftest): draw, click a point, list its runs, toggle, sort ----
  function selftest() {
    var v = { ok: false, checks: {} }, out = $('selftest');
    var finish = function () {
      v.errors = window.__mimo.errors; v.network = window.__mimo.network; v.marks = MARKS;
      v.frontier_why = $('f-why').textContent; v.stress_why = $('s-why').textContent;
      v.ok = Object.keys(v.checks).every(function (k) { return v.checks[k]; }) && !v.errors.length && !v.network.length;
      out.textContent = 'MIMO-SELFTEST ' + JSON.stringify(v);
    };
    try {
      var gd = $('frontier');
      var pointTrace = gd.data.filter(function (t) { return t.customdata && t.customdata.length; })[0];
      v.checks.frontier_points_drawn = !!pointTrace && gd.querySelectorAll('.scatterlayer .point').length > 0;
      v.frontier_line_drawn = gd.data.some(function (t) { return t.mode === 'lines'; });
      v.checks.required_line = gd.layout.shapes.some(function (s) { return s.y0 === R; });
      var idx = pointTrace ? pointTrace.customdata[0] : -1;
      gd.emit('plotly_click', { points: [{ customdata: idx, data: pointTrace, curveNumber: gd.data.indexOf(pointTrace), pointNumber: 0 }] });
      var rows = document.querySelectorAll('#runs-table tbody tr');
      v.runs_listed = rows.length;
      v.checks.click_lists_runs = idx >= 0 && rows.length === D.cells[idx].runs.length;
      var cmd = document.querySelector('#runs-table code.cmd');
      v.command = cmd ? cmd.textContent : null;
      v.cell = idx >= 0 ? D.cells[idx].rel : null;
      v.checks.command_shown = !!v.command && v.command.indexOf(' --rerun ') > 0 && v.command.indexOf('mimo plot ') > 0;
      var box = $('f-methods').querySelector('input');
      var before = gd.data.length;
      box.checked = false; box.dispatchEvent(new Event('change'));
      setTimeout(function () {
        try {
          v.checks.toggle_hides_a_family = gd.data.length < before;
          box.checked = true; box.dispatchEvent(new Event('change'));
          var lin = document.querySelector('input[name=f-scale][value=linear]');
          lin.checked = true; lin.dispatchEvent(new Event('change'));
          setTimeout(function () {
            try {
              v.checks.toggle_restores = gd.data.length === before;
              v.checks.linear_energy = gd.layout.xaxis.type === 'linear';
              var th = document.querySelector('#runs-table th');
              th.click(); th.click();
              v.checks.runs_sortable = th.classList.contains('desc');
              v.checks.report_tables = document.querySelectorAll('table.md').length === D.tables.length;
              v.checks.failure_curves = !D.axes.length || $('failure').data === undefined || $('failure').data.length > 0;
            } catch (e) { window.__mimo.errors.push('selftest: ' + e); }
            finish();
          }, 300);
        } catch (e) { window.__mimo.errors.push('selftest: ' + e); finish(); }
      }, 300);
    } catch (e) { window.__mimo.errors.push('selftest: ' + e); finish(); }
  }

  // ---- start ----
  var frames2 = function () {
    return new Promise(function (r) { requestAnimationFrame(function () { requestAnimationFrame(r); }); setTimeout(r, 5000); });
  };
  frontierControls();
  methodToggles();
  $('f-scenario').addEventListener('change', function () { S.sc = this.value; frontierControls(); drawFrontier(); });
  $('f-point').addEventListener('change', function () { S.pt = this.value; drawFrontier(); });
  Array.prototype.forEach.call(document.querySelectorAll('input[name=f-scale]'), function (r) {
    r.addEventListener('change', function () { if (r.checked) { S.scale = r.value; drawFrontier(); } });
  });
  var hash = {};
  location.hash.replace(/^#/, '').split('&').forEach(function (kv) { var p = kv.split('='); if (p[0]) hash[p[0]] = p.length > 1 ? decodeURIComponent(p[1]) : true; });
  if (hash.scenario && scenarios.indexOf(hash.scenario) >= 0) { S.sc = hash.scenario; frontierControls(); }
  drawFrontier().then(function () {
    $('frontier').on('plotly_click', function (ev) {
      var p = ev && ev.points && ev.points[0];
      if (p && p.customdata !== undefined && p.customdata !== null && p.customdata >= 0) showRuns(p.customdata);
    });
    MARKS.frontier_ms = performance.now();
    return frames2();
  }).then(function () {
    MARKS.first_render_ms = performance.now();
    failureControls();
    $('s-axis').addEventListener('change', function () { S.axis = this.value; drawFailure(); });
    $('s-scenario').addEventListener('change', function () { S.ssc = this.value; drawFailure(); });
    return drawFailure();
  }).then(function () {
    var fd = $('failure');
    if (fd.on) fd.on('plotly_click', function (ev) { var p = ev && ev.points && ev.points[0]; if (p && p.customdata >= 0) showRuns(p.customdata); });
    mdTables();
    return frames2();
  }).then(function () {
    MARKS.all_drawn_ms = performance.now();
    document.body.dataset.marks = JSON.stringify(MARKS);
    document.body.dataset.ready = '1';
    if (hash.selftest) selftest();
  }).catch(function (e) { window.__mimo.errors.push('start: ' + e); if (hash.selftest) selftest(); });
})();
