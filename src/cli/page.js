/* layerfit report: the page's script (embedded by the Makefile).
 *
 * Reads the data from the JSON script element #lf-data and
 * builds the page: a fit's tables and figures, or a batch's heat maps,
 * histograms, results table and the curve of a clicked pixel.  Text from
 * the data is only ever set through textContent (el() below), never as
 * markup.  No network, no other file. */
'use strict';
(function () {
var D = JSON.parse(document.getElementById('lf-data').textContent);
var PAL = ['#1b6ca8', '#c0392b', '#27ae60', '#8e44ad', '#d35400', '#2c3e50', '#16a085', '#7f8c8d'];
var main = document.getElementById('page');

/* ---- helpers ---------------------------------------------------------- */
function el(tag, attrs, kids) {
  var e = document.createElement(tag), k;
  for (k in attrs || {}) {
    if (k === 'text') e.textContent = attrs[k];
    else if (k === 'cls') e.className = attrs[k];
    else if (k.slice(0, 2) === 'on') e.addEventListener(k.slice(2), attrs[k]);
    else e.setAttribute(k, attrs[k]);
  }
  (kids || []).forEach(function (c) {
    if (c != null) e.appendChild(typeof c === 'string' ? document.createTextNode(c) : c);
  });
  return e;
}
function fin(x) { return typeof x === 'number' && isFinite(x); }
var PREF = [[1e9, 'G'], [1e6, 'M'], [1e3, 'k'], [1, ''], [1e-3, 'm'], [1e-6, 'µ'], [1e-9, 'n'],
            [1e-12, 'p'], [1e-15, 'f']];
function prefixFor(x) {
  var a = Math.abs(x), i;
  for (i = 0; i < PREF.length - 1; i++) if (a >= PREF[i][0] * 0.9995) return PREF[i];
  return PREF[PREF.length - 1];
}
/* x with unit in SI prefixes: "12.3 nN"; J/m² as mJ/m² */
function human(x, unit, digits) {
  if (!fin(x)) return '–';
  if (x === 0) return '0 ' + unit;
  var p = prefixFor(x);
  return (x / p[0]).toPrecision(digits || 4).replace(/\.?0+(e|$)/, '$1') + ' ' + p[1] + unit;
}
function num(x, d) { return fin(x) ? (+x.toPrecision(d || 4)).toString() : '–'; }
function basename(s) { s = String(s == null ? '' : s); var i = s.lastIndexOf('/'); return i < 0 ? s : s.slice(i + 1); }
/* a long name shortened, the whole on hover */
function nameCell(s) { return el('span', { cls: 'name', title: String(s), text: basename(s) }); }
function td(x, cls) { return el('td', cls ? { cls: cls, text: x } : { text: x }); }
function tdn(x) { return el('td', { cls: x === '–' ? 'na' : 'num', text: x }); }
function section(id, title) {
  var s = el('section', { id: id }, [el('h2', { text: title })]);
  main.appendChild(s);
  return s;
}
function niceTicks(lo, hi, n) {
  if (!(hi > lo)) return [lo];
  var step = Math.pow(10, Math.floor(Math.log10((hi - lo) / n))), f = (hi - lo) / n / step, t = [], v;
  step *= f > 5 ? 10 : f > 2 ? 5 : f > 1 ? 2 : 1;
  for (v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) t.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  return t;
}
function tickText(v) { return (+v.toPrecision(6)).toString(); }

/* ---- one curve's points, decoded --------------------------------------- */
/* plot: quantized points of cli/page.c; z0, F0: offsets (SI) or null.
 * Returns depths as indentation delta = z - z0 in nm (z in nm when z0 is
 * not known) and forces F - F0 in the unit fu (N per unit). */
function decode(plot, z0, F0) {
  var q = plot.q, z = plot.z, f = plot.f, r = plot.r, i, o = {};
  function dz(v) { return z[0] + (z[1] - z[0]) * v / q; }
  function df(v) { return f[0] + (f[1] - f[0]) * v / q; }
  var zs = fin(z0) ? z0 : 0, fs = fin(F0) ? F0 : 0;
  var fmax = Math.max(Math.abs(f[0] - fs), Math.abs(f[1] - fs));
  var p = prefixFor(fmax || 1);
  o.fu = p[0]; o.fname = p[1] + 'N'; o.indent = fin(z0);
  function X(zz) { return (zz - zs) * 1e9; }
  function Y(ff) { return (ff - fs) / o.fu; }
  o.pts = []; o.res = [];
  for (i = 0; i < plot.pz.length; i++) {
    var x = X(dz(plot.pz[i])), y = Y(df(plot.pf[i]));
    o.pts.push([x, y]);
    if (plot.pr[i] >= 0) o.res.push([x, (r[0] + (r[1] - r[0]) * plot.pr[i] / q) / o.fu]);
  }
  o.model = [[], [], []];
  if (plot.mz) {
    var nm = plot.mf.length;
    for (i = 0; i < nm; i++) {
      var c = +plot.mc[i], pt = [X(plot.mz[0] + (plot.mz[1] - plot.mz[0]) * i / (nm - 1)), Y(df(plot.mf[i]))];
      /* runs of a class share their end points so that the parts join */
      o.model[c].push(pt);
      if (i + 1 < nm && +plot.mc[i + 1] !== c) {
        o.model[c].push(null);
        o.model[+plot.mc[i + 1]].push(pt);
      }
    }
  }
  /* the segments the fit left out (lf_segment: 0 retract, 1 approach, 2 hold) */
  o.other = [[], [], [], []];
  if (plot.o) {
    var P = plot.o;
    for (i = 0; i < P.pz.length; i++)
      o.other[+P.s[i]].push([X(P.z[0] + (P.z[1] - P.z[0]) * P.pz[i] / P.q), Y(P.f[0] + (P.f[1] - P.f[0]) * P.pf[i] / P.q)]);
  }
  o.po = plot.po ? [X(plot.po[0]), Y(plot.po[1])] : null;
  var lo = null;    /* the lowest force of the fitted segment, window or not */
  o.pts.concat(o.other[3]).forEach(function (p) { if (!lo || p[1] < lo[1]) lo = p; });
  o.lowest = lo;
  o.n = plot.n; o.shown = plot.pz.length;
  return o;
}

/* ---- a chart on a canvas: data panel over a residual panel ----------------
 * spec: {series: [{name, pts, color, kind: 'pts'|'line', dash, width}],
 *        marks: [{name, pt, color, shape}], res: [[x, y]] or null,
 *        xlabel, ylabel, rlabel, bad: text drawn across the figure} */
function Chart(host, spec) {
  var self = this, wrap = el('div', { cls: 'fig' + (spec.bad ? ' noconv' : '') });
  var tools = el('div', { cls: 'tools' });
  var canvas = el('canvas', { style: 'height:' + (spec.res ? 440 : 340) + 'px' });
  var tip = el('div', { cls: 'tip' });
  this.spec = spec; this.canvas = canvas; this.hidden = {};
  var named = {};
  spec.series.concat(spec.marks || [], spec.lines || []).forEach(function (s) {
    if ((!s.pts && !s.pt && s.x == null && s.y == null) || named[s.name]) return;
    named[s.name] = 1;
    var box = el('input', { type: 'checkbox', 'data-series': s.name });
    box.checked = true;
    box.addEventListener('change', function () { self.hidden[s.name] = !box.checked; self.draw(); });
    tools.appendChild(el('label', {}, [box, el('span', { cls: 'swatch', style: 'background:' + s.color }),
                                       s.name]));
  });
  ['zoom in', 'zoom out', 'reset'].forEach(function (w) {
    tools.appendChild(el('button', { type: 'button', 'data-zoom': w, text: w, onclick: function () {
      if (w === 'reset') self.reset(); else self.zoom(w === 'zoom in' ? 0.5 : 2, null, null);
    } }));
  });
  tools.appendChild(el('span', { cls: 'hint', text: 'wheel: zoom depth (shift: force), drag: pan, double-click: reset' }));
  wrap.appendChild(tools);
  wrap.appendChild(canvas);
  wrap.appendChild(tip);
  host.appendChild(wrap);
  this.wrap = wrap; this.tip = tip;
  this.reset();
  var drag = null;
  canvas.addEventListener('wheel', function (e) {
    e.preventDefault();
    var p = self.toData(e), f = e.deltaY < 0 ? 0.8 : 1.25;
    if (e.shiftKey) self.zoomY(f, p ? p[1] : null); else self.zoom(f, p ? p[0] : null, null);
  }, { passive: false });
  canvas.addEventListener('mousedown', function (e) { drag = [e.clientX, e.clientY, self.x0, self.x1, self.y0, self.y1]; });
  window.addEventListener('mouseup', function () { drag = null; });
  canvas.addEventListener('mousemove', function (e) {
    if (drag) {
      var L = self.layout(), dx = (e.clientX - drag[0]) / L.w * (drag[3] - drag[2]);
      var dy = (e.clientY - drag[1]) / L.h * (drag[5] - drag[4]);
      self.x0 = drag[2] - dx; self.x1 = drag[3] - dx; self.y0 = drag[4] + dy; self.y1 = drag[5] + dy;
      self.draw();
    } else self.hover(e);
  });
  canvas.addEventListener('mouseleave', function () { tip.style.display = 'none'; });
  canvas.addEventListener('dblclick', function () { self.reset(); });
  window.addEventListener('resize', function () { self.draw(); });
}
Chart.prototype.visible = function (s) { return !this.hidden[s.name]; };
Chart.prototype.reset = function () {
  var xs = [], ys = [], rs = [], sp = this.spec, self = this;
  sp.series.forEach(function (s) {
    if (!self.visible(s) || s.context) return;    /* the view opens on what was fitted */
    s.pts.forEach(function (p) { if (p) { xs.push(p[0]); ys.push(p[1]); } });
  });
  (sp.marks || []).forEach(function (m) { if (m.pt) { xs.push(m.pt[0]); ys.push(m.pt[1]); } });
  (sp.res || []).forEach(function (p) { rs.push(p[1]); });
  function span(a) {
    var lo = Math.min.apply(null, a), hi = Math.max.apply(null, a), pad;
    if (!a.length) return [0, 1];
    pad = (hi - lo) * 0.04 || Math.abs(lo) * 0.1 || 1;
    return [lo - pad, hi + pad];
  }
  var X = span(xs), Y = span(ys), R = span(rs.length ? rs : [0]);
  this.x0 = X[0]; this.x1 = X[1]; this.y0 = Y[0]; this.y1 = Y[1];
  var m = Math.max(Math.abs(R[0]), Math.abs(R[1]));
  this.r0 = -m; this.r1 = m;
  this.draw();
};
Chart.prototype.zoom = function (f, at) {
  var c = at == null ? (this.x0 + this.x1) / 2 : at;
  this.x0 = c - (c - this.x0) * f; this.x1 = c + (this.x1 - c) * f;
  this.draw();
};
Chart.prototype.zoomY = function (f, at) {
  var c = at == null ? (this.y0 + this.y1) / 2 : at;
  this.y0 = c - (c - this.y0) * f; this.y1 = c + (this.y1 - c) * f;
  this.draw();
};
Chart.prototype.layout = function () {
  var W = this.canvas.clientWidth || 800, H = this.canvas.clientHeight || this.canvas.height;
  var L = { W: W, H: H, l: 70, r: 12, t: 10 };
  L.w = W - L.l - L.r;
  if (this.spec.res) { L.h = (H - 50) * 0.7; L.rt = L.t + L.h + 8; L.rh = H - 40 - L.rt; }
  else L.h = H - 40 - L.t;
  return L;
};
Chart.prototype.toData = function (e) {
  var b = this.canvas.getBoundingClientRect(), L = this.layout();
  var px = e.clientX - b.left - L.l, py = e.clientY - b.top - L.t;
  if (px < 0 || px > L.w) return null;
  return [this.x0 + px / L.w * (this.x1 - this.x0), this.y1 - py / L.h * (this.y1 - this.y0)];
};
Chart.prototype.draw = function () {
  var cv = this.canvas, dpr = window.devicePixelRatio || 1, L = this.layout(), sp = this.spec, self = this;
  cv.width = Math.round(L.W * dpr); cv.height = Math.round(L.H * dpr);
  var g = cv.getContext('2d');
  g.setTransform(dpr, 0, 0, dpr, 0, 0);
  g.clearRect(0, 0, L.W, L.H);
  g.font = '11px Helvetica,Arial,sans-serif';
  var x0 = this.x0, x1 = this.x1;
  function sx(x) { return L.l + (x - x0) / (x1 - x0) * L.w; }
  function panel(top, h, y0, y1, label, draw, xlab) {
    function sy(y) { return top + (y1 - y) / (y1 - y0) * h; }
    g.save();
    g.strokeStyle = '#bbb'; g.fillStyle = '#333';
    g.strokeRect(L.l, top, L.w, h);
    g.textAlign = 'right'; g.textBaseline = 'middle';
    niceTicks(y0, y1, Math.max(2, h / 45)).forEach(function (t) {
      g.fillText(tickText(t), L.l - 4, sy(t));
      g.strokeStyle = '#eee'; g.beginPath(); g.moveTo(L.l, sy(t)); g.lineTo(L.l + L.w, sy(t)); g.stroke();
    });
    if (xlab) {
      g.textAlign = 'center'; g.textBaseline = 'top';
      niceTicks(x0, x1, Math.max(2, L.w / 90)).forEach(function (t) { g.fillText(tickText(t), sx(t), top + h + 3); });
      g.fillText(xlab, L.l + L.w / 2, top + h + 17);
    }
    g.save(); g.translate(12, top + h / 2); g.rotate(-Math.PI / 2); g.textAlign = 'center';
    g.fillText(label, 0, 0); g.restore();
    g.beginPath(); g.rect(L.l, top, L.w, h); g.clip();
    draw(sy);
    g.restore();
  }
  panel(L.t, L.h, this.y0, this.y1, sp.ylabel, function (sy) {
    sp.series.forEach(function (s) {
      if (!self.visible(s)) return;
      g.strokeStyle = g.fillStyle = s.color;
      if (s.kind === 'line') {
        g.lineWidth = s.width || 2; g.setLineDash(s.dash || []);
        g.beginPath();
        var on = false;
        s.pts.forEach(function (p) {
          if (!p) { on = false; return; }
          if (on) g.lineTo(sx(p[0]), sy(p[1])); else g.moveTo(sx(p[0]), sy(p[1]));
          on = true;
        });
        g.stroke(); g.setLineDash([]);
      } else {
        s.pts.forEach(function (p) { g.fillRect(sx(p[0]) - 1.5, sy(p[1]) - 1.5, 3, 3); });
      }
    });
    (sp.marks || []).forEach(function (m) {
      if (!m.pt || !self.visible(m)) return;
      var X = sx(m.pt[0]), Y = sy(m.pt[1]);
      g.strokeStyle = m.color; g.lineWidth = 2; g.beginPath();
      if (m.shape === 'x') { g.moveTo(X - 6, Y - 6); g.lineTo(X + 6, Y + 6); g.moveTo(X - 6, Y + 6); g.lineTo(X + 6, Y - 6); }
      else g.arc(X, Y, 6, 0, 2 * Math.PI);
      g.stroke();
      g.setLineDash([3, 3]); g.lineWidth = 1; g.beginPath(); g.moveTo(X, L.t); g.lineTo(X, L.t + L.h); g.stroke();
      g.setLineDash([]);
    });
    /* lines across the figure: the fit window's ends */
    (sp.lines || []).forEach(function (ln) {
      if (!self.visible(ln)) return;
      g.strokeStyle = ln.color; g.lineWidth = 1.5; g.setLineDash([8, 4]); g.beginPath();
      if (ln.x != null) { g.moveTo(sx(ln.x), L.t); g.lineTo(sx(ln.x), L.t + L.h); }
      else { g.moveTo(L.l, sy(ln.y)); g.lineTo(L.l + L.w, sy(ln.y)); }
      g.stroke(); g.setLineDash([]);
    });
    if (sp.bad) {
      g.fillStyle = 'rgba(176,58,46,0.85)'; g.font = 'bold 15px Helvetica,Arial,sans-serif';
      g.textAlign = 'center'; g.textBaseline = 'top';
      g.fillText(sp.bad, L.l + L.w / 2, L.t + 8);
    }
  }, sp.res ? null : sp.xlabel);
  if (sp.res) {
    panel(L.rt, L.rh, this.r0, this.r1, sp.rlabel, function (sy) {
      g.strokeStyle = '#666'; g.setLineDash([2, 3]); g.beginPath(); g.moveTo(L.l, sy(0)); g.lineTo(L.l + L.w, sy(0)); g.stroke();
      g.setLineDash([]); g.fillStyle = PAL[0];
      sp.res.forEach(function (p) { g.fillRect(sx(p[0]) - 1.5, sy(p[1]) - 1.5, 3, 3); });
    }, sp.xlabel);
  }
};
Chart.prototype.hover = function (e) {
  var p = this.toData(e), best = null, bd = Infinity, self = this, L = this.layout();
  if (!p) { this.tip.style.display = 'none'; return; }
  var kx = L.w / (this.x1 - this.x0), ky = L.h / (this.y1 - this.y0);
  this.spec.series.forEach(function (s) {
    if (!self.visible(s)) return;
    s.pts.forEach(function (q) {
      if (!q) return;
      var d = Math.pow((q[0] - p[0]) * kx, 2) + Math.pow((q[1] - p[1]) * ky, 2);
      if (d < bd) { bd = d; best = [s, q]; }
    });
  });
  if (!best || bd > 400) { this.tip.style.display = 'none'; return; }
  this.tip.textContent = best[0].name + ': ' + num(best[1][0], 5) + ' nm, ' + num(best[1][1], 5) + ' ' + this.spec.funit;
  var b = this.canvas.getBoundingClientRect(), w = this.wrap.getBoundingClientRect();
  this.tip.style.left = (e.clientX - w.left + 12) + 'px';
  this.tip.style.top = (e.clientY - w.top + 12) + 'px';
  this.tip.style.display = 'block';
  void b;
};

/* The figure of one curve: data, model (stable solid, unstable dashed,
 * out of contact dotted), pull-off of the model and the lowest measured
 * force, residuals below on the same depth axis. */
function curveChart(host, plot, z0, F0, bad, info) {
  var o = decode(plot, z0, F0), lines = [], W = info && info.window;
  /* the fit window (where the report gives one): its ends on the depth
   * and force axes, as placed on this curve */
  if (W) {
    [W.depth_lo_m, W.depth_hi_m].forEach(function (v) { if (fin(v)) lines.push({ name: 'fit window', x: (v - z0) * 1e9, color: '#16a085' }); });
    [W.force_lo_N, W.force_hi_N].forEach(function (v) { if (fin(v)) lines.push({ name: 'fit window', y: (v - F0) / o.fu, color: '#16a085' }); });
  }
  var spec = {
    series: [
      { name: 'approach (not fitted)', pts: o.other[1], color: '#c8c8c8', kind: 'pts', context: true },
      { name: 'hold (not fitted)', pts: o.other[2], color: '#e0d8c8', kind: 'pts', context: true },
      { name: 'retract (not fitted)', pts: o.other[0], color: '#c8c8c8', kind: 'pts', context: true },
      { name: 'outside the fit window', pts: o.other[3], color: '#9ec9e2', kind: 'pts', context: true },
      { name: 'data', pts: o.pts, color: PAL[0], kind: 'pts' },
      { name: 'model, stable', pts: o.model[1], color: PAL[1], kind: 'line' },
      { name: 'model, unstable', pts: o.model[2], color: PAL[1], kind: 'line', dash: [6, 4] },
      { name: 'model, out of contact', pts: o.model[0], color: '#777', kind: 'line', dash: [2, 3], width: 1.5 }
    ],
    marks: [
      { name: 'pull-off (model)', pt: o.po, color: '#8e44ad' },
      { name: info && fin(info.adhesion) ? 'measured adhesion ' + human(info.adhesion, 'N') : 'lowest force (measured)', pt: o.lowest, color: '#d35400', shape: 'x' }
    ],
    lines: lines,
    res: o.res,
    xlabel: o.indent ? 'indentation δ = z − z0 (nm)' : 'depth z (nm; contact point not determined)',
    ylabel: (fin(F0) ? 'force − F0' : 'force') + ' (' + o.fname + ')',
    rlabel: 'residual (' + o.fname + ')', funit: o.fname, bad: bad
  };
  spec.series = spec.series.filter(function (s) { return s.pts.length; });
  var c = new Chart(host, spec);
  host.appendChild(el('div', { cls: 'hint', style: 'font-size:.8em;color:#555',
    text: o.shown < o.n ? o.shown + ' of ' + o.n + ' points drawn (every point near contact and pull-off; the envelope elsewhere)'
                        : o.n + ' points' }));
  return c;
}

/* warnings grouped by kind (the text with its numbers taken out), each
 * once with a count and the curves it concerns */
function groupedWarnings(list) {
  var groups = {}, order = [];
  list.forEach(function (w) {
    var key = w.text.replace(/[-+]?\d[\d.eE+-]*/g, '#');
    if (!groups[key]) { groups[key] = { first: w.text, n: 0, where: [] }; order.push(key); }
    groups[key].n++;
    if (w.curve) groups[key].where.push(w.curve);
  });
  return order.map(function (k) { return groups[k]; });
}
function warningList(list, cls) {
  var ul = el('ul');
  groupedWarnings(list).forEach(function (g) {
    var li = el('li', { cls: cls }, [g.n > 1 ? el('span', { cls: 'count', text: '×' + g.n }) : null, g.first]);
    if (g.where.length) li.appendChild(el('span', { style: 'color:#666', text: ' (curve' + (g.where.length > 1 ? 's ' : ' ') + g.where.join(', ') + ')' }));
    ul.appendChild(li);
  });
  return ul;
}

/* the selected curve, 1-based, from the address (#curve=N) */
function hashCurve() {
  var m = /curve=(\d+)/.exec(location.hash);
  return m ? +m[1] : 0;
}

/* ======================================================================
 * A single or joint fit
 * ==================================================================== */
function fitPage() {
  var R = D.result, F = R.fit, C = R.curves, prov = R.provenance || {};
  document.title = 'layerfit fit: ' + C.length + ' curve' + (C.length === 1 ? '' : 's');
  document.getElementById('version').textContent = 'layerfit ' + prov.layerfit + ' · model ' + F.model +
    ' · method ' + F.method + ' · ' + C.length + ' curve' + (C.length === 1 ? '' : 's');
  /* the tables are the library's (lf_fit_result_html); here they get
   * long names shortened, the offsets' correlations folded, the warnings
   * grouped and the curves' rows a click */
  /* the file names of a table's second column, shortened */
  function shorten(t) {
    Array.prototype.forEach.call(t ? t.rows : [], function (tr, i) {
      if (i === 0) return;
      var name = tr.cells[1].textContent;
      tr.cells[1].textContent = '';
      tr.cells[1].appendChild(nameCell(name));
    });
  }
  var ct = document.getElementById('curve-table');
  shorten(ct);
  shorten(document.getElementById('observed-table'));
  Array.prototype.forEach.call(ct.querySelectorAll('tr'), function (tr, i) {
    if (i === 0) return;
    tr.className = 'pick';
    tr.setAttribute('data-curve', i);
    tr.addEventListener('click', function () { location.hash = 'curve=' + i; });
  });
  var cor = document.getElementById('correlation-table');
  if (cor) {
    var heads = Array.prototype.map.call(cor.rows[0].cells, function (c) { return c.textContent; });
    var off = heads.map(function (h) { return /\[/.test(h); }), noff = off.filter(Boolean).length;
    var folded = true;
    function fold() {
      Array.prototype.forEach.call(cor.rows, function (tr, i) {
        tr.hidden = folded && i > 0 && off[i];
        Array.prototype.forEach.call(tr.cells, function (c, j) { c.hidden = folded && off[j]; });
      });
      tog.textContent = folded ? 'show the per-curve offsets (' + noff + ')' : 'the material parameters only';
    }
    var tog = el('button', { type: 'button', id: 'correlation-offsets', onclick: function () { folded = !folded; fold(); } });
    if (noff) { cor.parentNode.parentNode.appendChild(tog); fold(); }
  }
  var wl = document.querySelector('#warnings ul');
  if (wl) {
    var items = Array.prototype.map.call(wl.querySelectorAll('li'), function (li) {
      var m = /^curve (\d+): ([\s\S]*)$/.exec(li.textContent);
      return m ? { text: m[2], curve: +m[1] } : { text: li.textContent };
    });
    wl.parentNode.replaceChild(warningList(items, 'warn'), wl);
  }

  /* every curve on shared axes, then the one chosen */
  var s = document.getElementById('figures');
  s.appendChild(el('h3', { text: 'All curves: indentation δ = z − z0' }));
  var series = [], fu = 0, fname = 'N';
  D.plots.forEach(function (p) { if (p && p.q) { var o = decode(p, p.z0, p.F0); if (o.fu > fu) { fu = o.fu; fname = o.fname; } } });
  D.plots.forEach(function (p, j) {
    if (!p || !p.q) return;
    var o = decode(p, p.z0, p.F0), k = o.fu / fu;
    function sc(a) { return a.map(function (q) { return q && [q[0], q[1] * k]; }); }
    var col = PAL[j % PAL.length];
    series.push({ name: (j + 1) + ': ' + basename(C[j].file), pts: sc(o.pts), color: col, kind: 'pts' });
    series.push({ name: (j + 1) + ': model', pts: sc(o.model[1].concat([null], o.model[2])), color: col, kind: 'line', width: 1.5 });
  });
  var ov = el('div', { id: 'overview' });
  s.appendChild(ov);
  var bad = F.converged ? null : 'did not converge: ' + F.stop_reason;
  new Chart(ov, { series: series, marks: [], res: null, xlabel: 'indentation δ (nm)', ylabel: 'force − F0 (' + fname + ')', funit: fname, bad: bad });
  var panel = el('div', { id: 'curve-panel' });
  s.appendChild(panel);
  function show() {
    var n = hashCurve() || 1;
    if (n > C.length) n = 1;
    panel.textContent = '';
    Array.prototype.forEach.call(ct.querySelectorAll('tr[data-curve]'), function (tr) { tr.className = 'pick' + (+tr.getAttribute('data-curve') === n ? ' sel' : ''); });
    var c = C[n - 1], row = ct.querySelector('tr[data-curve="' + n + '"]');
    panel.appendChild(el('h3', {}, ['Curve ' + n + ': ', el('span', { id: 'curve-file', title: String(c.file), text: basename(c.file) })]));
    /* its numbers: its row of the curve table */
    var nt = el('table', { id: 'curve-numbers' }, [ct.rows[0].cloneNode(true), row.cloneNode(true)]);
    nt.rows[1].className = '';
    panel.appendChild(el('div', { cls: 'wide' }, [nt]));
    if (D.plots[n - 1] && D.plots[n - 1].q)
      curveChart(panel, D.plots[n - 1], D.plots[n - 1].z0, D.plots[n - 1].F0, bad, { window: c.window, adhesion: c.adhesion_force_N });
    else panel.appendChild(el('p', { cls: 'note', text: 'The model could not be drawn for this curve.' }));
  }
  window.addEventListener('hashchange', show);
  show();

  s = section('provenance', 'Provenance');
  var pt = el('table', { id: 'input-table' }, [el('tr', {}, [el('th', { text: 'input' }), el('th', { text: 'SHA-256' })])]);
  (prov.inputs || []).forEach(function (i) { pt.appendChild(el('tr', {}, [el('td', {}, [nameCell(i.file)]), el('td', {}, [el('code', { text: i.sha256 || '' })])])); });
  s.appendChild(el('div', { cls: 'wide' }, [pt]));
}

/* ======================================================================
 * Many fits: heat maps, histograms, the results, the curve of a pixel
 * ==================================================================== */
var QUANT = [
  { key: 'w_J_m2', label: 'w (work of adhesion)', unit: 'J/m²' },
  { key: 'Estar_Pa', label: 'E* (effective modulus)', unit: 'Pa' },
  { key: 'nu', label: 'ν (Poisson’s ratio)', unit: '' },
  { key: 'chi2_dof', label: 'χ²/dof', unit: '' },
  { key: 'adhesion_force_N', label: 'adhesion force (measured)', unit: 'N' },
  { key: 'P_po_N', label: 'pull-off force (model)', unit: 'N' }
];
var STATUS_COL = { ok: [39, 174, 96], misfit: [230, 126, 34], noconv: [192, 57, 43], error: [120, 120, 120] };
var VIR = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
function viridis(t) {
  t = Math.max(0, Math.min(1, t)) * (VIR.length - 1);
  var i = Math.min(VIR.length - 2, Math.floor(t)), f = t - i, a = VIR[i], b = VIR[i + 1];
  return [a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f, a[2] + (b[2] - a[2]) * f];
}
/* a quantity's value: with its unit in SI prefixes, a bare number without one */
function qtext(v, q, d) { return q.unit ? human(v, q.unit, d) : num(v, d || 4); }
function csvCell(v) {
  var s = v == null ? '' : String(v);
  return /[",\n\r]/.test(s) ? '"' + s.replace(/"/g, '""') + '"' : s;
}

function mapPage() {
  var cols = D.columns, rows = D.rows, N = rows.length, ci = {};
  cols.forEach(function (c, i) { ci[c] = i; });
  function get(r, k) { return ci[k] == null ? null : rows[r][ci[k]]; }
  var excluded = new Uint8Array(N), pass = new Uint8Array(N), sel = 0;
  document.title = 'layerfit map: ' + N + ' fits';
  var counts = {};
  for (var r = 0; r < N; r++) { var st = get(r, 'status'); counts[st] = (counts[st] || 0) + 1; }
  var ver = document.getElementById('version');
  ver.textContent += ' · ' + N + ' fits: ' + Object.keys(counts).map(function (k) { return counts[k] + ' ' + k; }).join(', ');
  ver.after(el('p', {}, ['Results: ', el('span', { id: 'results-file', text: D.results })]));
  var quants = QUANT.filter(function (q) {
    if (ci[q.key] == null) return false;
    for (var r = 0; r < N; r++) if (fin(get(r, q.key))) return true;
    return false;
  });

  /* controls: filter, colour scale, selection */
  var ctl = el('div', { cls: 'controls', id: 'controls' });
  var fStatus = el('select', { id: 'filter-status' }, [el('option', { value: '', text: 'any status' })].concat(Object.keys(counts).map(function (k) { return el('option', { value: k, text: k + ' (' + counts[k] + ')' }); })));
  var fQ = el('select', { id: 'filter-quantity' }, quants.map(function (q) { return el('option', { value: q.key, text: q.label }); }));
  var fMin = el('input', { type: 'number', id: 'filter-min', step: 'any', placeholder: 'min (SI)' });
  var fMax = el('input', { type: 'number', id: 'filter-max', step: 'any', placeholder: 'max (SI)' });
  var shared = el('input', { type: 'checkbox', id: 'shared-scale' });
  shared.checked = true;
  var nsel = el('span', { id: 'kept-count' });
  var link = el('a', { id: 'export-plan', href: '#', download: 'kept-plan.csv', text: 'export the kept curves as a plan' });
  ctl.appendChild(el('label', {}, ['status ', fStatus]));
  ctl.appendChild(el('label', {}, [fQ, ' from ', fMin, ' to ', fMax]));
  ctl.appendChild(el('label', { title: 'one colour scale for every map of a quantity (several map files in one batch)' }, [shared, ' shared colour scale']));
  ctl.appendChild(el('button', { type: 'button', id: 'exclude-filtered-out', text: 'exclude what the filter hides', onclick: function () {
    for (var r = 0; r < N; r++) if (!pass[r]) excluded[r] = 1;
    refresh();
  } }));
  ctl.appendChild(el('button', { type: 'button', id: 'clear-exclusions', text: 'keep all', onclick: function () { excluded.fill(0); refresh(); } }));
  ctl.appendChild(nsel);
  ctl.appendChild(link);
  main.appendChild(ctl);
  [fStatus, fQ, fMin, fMax, shared].forEach(function (e) { e.addEventListener('change', refresh); e.addEventListener('input', refresh); });

  var panel = el('div', { id: 'curve-panel' });
  panel.hidden = true;
  main.appendChild(panel);
  var mapsSec = section('maps', 'Maps');
  var mapsBox = el('div', { cls: 'maps' });
  mapsSec.appendChild(mapsBox);
  var histSec = section('histograms', 'Histograms (the fits the filter shows, status ok)');
  var histBox = el('div', { cls: 'hists' });
  histSec.appendChild(histBox);
  var tabSec = section('results', 'Results');
  var pager = el('div', { cls: 'pager' }), tableBox = el('div', { cls: 'wide' });
  tabSec.appendChild(pager);
  tabSec.appendChild(tableBox);

  /* the maps, pixels at
   * grid_i, grid_j where every row gives them, else at distinct x, y */
  var groups = {}, gorder = [];
  for (r = 0; r < N; r++) {
    /* a file of many curves (FILE#N) is a map of its own; files of one
     * curve make one map together */
    var f = String(get(r, 'file') || ''), g = /#\d+$/.test(f) ? f.replace(/#\d+$/, '') : 'curve files', x = get(r, 'x_m'), y = get(r, 'y_m');
    if (!fin(x) || !fin(y)) continue;
    if (!groups[g]) { groups[g] = { name: g, rows: [] }; gorder.push(g); }
    groups[g].rows.push(r);
  }
  gorder.forEach(function (k) {
    var G = groups[k], useGrid = G.rows.every(function (r) { return fin(get(r, 'grid_i')) && fin(get(r, 'grid_j')); });
    function axis(key) {
      var v = G.rows.map(function (r) { return get(r, key); }).sort(function (a, b) { return a - b; }), u = [];
      v.forEach(function (a) { if (!u.length || a - u[u.length - 1] > 1e-9 * Math.max(Math.abs(a), 1e-12)) u.push(a); });
      return u;
    }
    function index(u, a) { var lo = 0, hi = u.length; while (hi - lo > 1) { var m = (lo + hi) >> 1; if (u[m] <= a * (1 + 1e-9) + 1e-21) lo = m; else hi = m; } return lo; }
    var ux = useGrid ? null : axis('x_m'), uy = useGrid ? null : axis('y_m');
    G.cell = G.rows.map(function (r) {
      return useGrid ? [get(r, 'grid_i'), get(r, 'grid_j')] : [index(ux, get(r, 'x_m')), index(uy, get(r, 'y_m'))];
    });
    G.at = {};      /* "i,j" -> the row there */
    G.cell.forEach(function (c, t) { G.at[c[0] + ',' + c[1]] = G.rows[t]; });
    G.nx = 1 + Math.max.apply(null, G.cell.map(function (c) { return c[0]; }));
    G.ny = 1 + Math.max.apply(null, G.cell.map(function (c) { return c[1]; }));
  });
  var maps = [];
  gorder.forEach(function (k, gi) {
    var G = groups[k];
    quants.concat([{ key: 'status', label: 'status', unit: '' }]).forEach(function (q) {
      var box = el('div', { cls: 'map' });
      var cv = el('canvas', { id: 'heatmap-' + q.key + (gi ? '-' + gi : ''), 'data-nx': G.nx, 'data-ny': G.ny, width: G.nx, height: G.ny });
      var bar = el('canvas', { cls: 'bar', width: 200, height: 1 });
      var scale = el('div', { cls: 'scale' });
      box.appendChild(el('h3', {}, [q.label + ' · ', nameCell(G.name)]));
      box.appendChild(cv);
      if (q.key !== 'status') { box.appendChild(bar); box.appendChild(scale); }
      else box.appendChild(el('div', { cls: 'scale' }, Object.keys(STATUS_COL).map(function (s) { return el('span', {}, [el('span', { cls: 'swatch', style: 'background:rgb(' + STATUS_COL[s] + ')' }), s]); })));
      mapsBox.appendChild(box);
      cv.style.aspectRatio = G.nx + ' / ' + G.ny;
      function rowAt(e) {
        var b = cv.getBoundingClientRect(), i = Math.floor((e.clientX - b.left) / b.width * G.nx), j = G.ny - 1 - Math.floor((e.clientY - b.top) / b.height * G.ny);
        return G.at[i + ',' + j];
      }
      cv.addEventListener('click', function (e) { var r = rowAt(e); if (r != null) location.hash = 'curve=' + (r + 1); });
      /* the pixel's fit and value under the pointer */
      cv.addEventListener('mousemove', function (e) {
        var r = rowAt(e), v = r == null ? null : get(r, q.key);
        cv.title = r == null ? '' : 'fit ' + (r + 1) + ' (' + get(r, 'status') + '): ' + (q.key === 'status' ? v : typeof v === 'number' ? qtext(v, q) : '–');
      });
      maps.push({ G: G, q: q, cv: cv, bar: bar, scale: scale });
    });
  });
  if (!gorder.length) mapsBox.appendChild(el('p', { text: 'No fit states a position (x_m, y_m): no map to draw.' }));

  function range(q, rowsOf) {
    var v = [];
    rowsOf.forEach(function (r) { var a = get(r, q.key); if (fin(a) && pass[r] && get(r, 'status') === 'ok') v.push(a); });
    v.sort(function (a, b) { return a - b; });
    if (!v.length) return null;
    /* 1st to 99th percentile: one wild fit does not flatten the map */
    return [v[Math.floor(0.01 * (v.length - 1))], v[Math.ceil(0.99 * (v.length - 1))]];
  }
  function drawMaps() {
    var sharedR = {};
    if (shared.checked) quants.forEach(function (q) {
      var all = []; gorder.forEach(function (k) { all = all.concat(groups[k].rows); });
      sharedR[q.key] = range(q, all);
    });
    maps.forEach(function (m) {
      var G = m.G, q = m.q, g = m.cv.getContext('2d'), img = g.createImageData(G.nx, G.ny), d = img.data;
      var R = q.key === 'status' ? null : shared.checked ? sharedR[q.key] : range(q, G.rows);
      for (var t = 0; t < G.rows.length; t++) {
        var r = G.rows[t], c = G.cell[t], o = 4 * ((G.ny - 1 - c[1]) * G.nx + c[0]), rgb = null, v = get(r, q.key);
        if (q.key === 'status') rgb = STATUS_COL[v] || [0, 0, 0];
        else if (fin(v) && R && get(r, 'status') === 'ok') rgb = viridis(R[1] > R[0] ? (v - R[0]) / (R[1] - R[0]) : 0.5);
        if (!rgb) continue;
        d[o] = rgb[0]; d[o + 1] = rgb[1]; d[o + 2] = rgb[2];
        d[o + 3] = excluded[r] ? 40 : pass[r] ? 255 : 90;
        if (r + 1 === sel) { d[o] = 255; d[o + 1] = 0; d[o + 2] = 255; d[o + 3] = 255; }
      }
      g.putImageData(img, 0, 0);
      if (q.key !== 'status') {
        var bg = m.bar.getContext('2d'), bi = bg.createImageData(200, 1);
        for (var i = 0; i < 200; i++) { var c2 = viridis(i / 199); bi.data.set([c2[0], c2[1], c2[2], 255], 4 * i); }
        bg.putImageData(bi, 0, 0);
        m.scale.textContent = '';
        m.scale.appendChild(el('span', { text: R ? qtext(R[0], q) : '–' }));
        m.scale.appendChild(el('span', { text: R ? qtext(R[1], q) : '–' }));
      }
    });
  }

  /* histograms of the shown, ok fits with their median and quartiles */
  function drawHists() {
    histBox.textContent = '';
    quants.forEach(function (q) {
      var v = [];
      for (var r = 0; r < N; r++) { var a = get(r, q.key); if (fin(a) && pass[r] && !excluded[r] && get(r, 'status') === 'ok') v.push(a); }
      v.sort(function (a, b) { return a - b; });
      var box = el('div', { cls: 'hist', id: 'hist-' + q.key }), cv = el('canvas', { height: 120 });
      box.appendChild(el('b', { text: q.label }));
      box.appendChild(cv);
      histBox.appendChild(box);
      if (!v.length) { box.appendChild(el('div', { text: 'no value' })); return; }
      function at(p) { var x = p * (v.length - 1), i = Math.floor(x); return i + 1 < v.length ? v[i] + (v[i + 1] - v[i]) * (x - i) : v[i]; }
      var lo = v.length < 200 ? v[0] : at(0.005), hi = v.length < 200 ? v[v.length - 1] : at(0.995), nb = Math.min(40, Math.max(5, Math.round(Math.sqrt(v.length)))), h = new Array(nb).fill(0), out = 0;
      v.forEach(function (a) { if (a < lo || a > hi) { out++; return; } h[Math.min(nb - 1, Math.floor((a - lo) / ((hi - lo) || 1) * nb))]++; });
      var W = cv.clientWidth || 290, H = 120, dpr = window.devicePixelRatio || 1, g = cv.getContext('2d'), mx = Math.max.apply(null, h);
      cv.width = W * dpr; cv.height = H * dpr; g.setTransform(dpr, 0, 0, dpr, 0, 0);
      g.fillStyle = PAL[0];
      h.forEach(function (c, i) { var bh = c / mx * (H - 20); g.fillRect(i * W / nb + 0.5, H - 14 - bh, W / nb - 1, bh); });
      [[at(0.5), '#c0392b'], [at(0.25), '#888'], [at(0.75), '#888']].forEach(function (m) {
        if (!(hi > lo)) return;
        var X = (m[0] - lo) / (hi - lo) * W; g.strokeStyle = m[1]; g.beginPath(); g.moveTo(X, 0); g.lineTo(X, H - 14); g.stroke();
      });
      g.fillStyle = '#333'; g.font = '10px sans-serif'; g.textAlign = 'left'; g.fillText(qtext(lo, q, 3), 0, H - 2);
      g.textAlign = 'right'; g.fillText(qtext(hi, q, 3), W, H - 2);
      box.appendChild(el('div', { text: v.length + ' fits · median ' + qtext(at(0.5), q) + ' · quartiles ' + qtext(at(0.25), q) + ' – ' + qtext(at(0.75), q) +
        ' · spread (IQR/median) ' + (at(0.5) ? num(100 * (at(0.75) - at(0.25)) / Math.abs(at(0.5)), 2) + ' %' : '–') + (out ? ' · ' + out + ' outside the axis' : '') }));
    });
  }

  /* the batch's population summary (RESULTS.summary.json): every fit, and
   * each sample, as the batch computed it (not the filter's) */
  function summaryTable() {
    var S = null;
    try { S = D.summary ? JSON.parse(D.summary) : null; } catch (e) { S = null; }
    if (!S || !S.all) return;
    var sec = section('population', 'Population summary (the batch’s, of every fit)');
    var UNITS = { w: 'J/m²', Estar: 'Pa', nu: '' };
    var t = el('table', { id: 'population-summary' }, [el('tr', {}, ['fits', 'parameter', 'n', 'median (quartiles)', 'population mean (95 %)',
      'spot-to-spot SD (95 %)', 'I²', 'p (same everywhere)'].map(function (h) { return el('th', { text: h }); }))]);
    [['all', S.all]].concat((S.groups || []).map(function (g) { return [g.sample || g.name || 'sample', g]; })).forEach(function (g) {
      var H = g[1].heterogeneity || g[1], P = H.parameters || {};
      Object.keys(UNITS).forEach(function (k) {
        var e = P[k], u = UNITS[k];
        if (!e || !e.n) return;
        function v(x) { return u ? human(x, u) : num(x, 4); }
        function ci(a) { return a && fin(a[0]) && fin(a[1]) ? ' (' + v(a[0]) + ' – ' + v(a[1]) + ')' : ''; }
        t.appendChild(el('tr', {}, [td(g[0]), td(k === 'Estar' ? 'E*' : k), tdn(String(e.n)),
          tdn(v(e.median) + ' (' + v(e.q1) + ' – ' + v(e.q3) + ')'),
          tdn(fin(e.population_mean) ? v(e.population_mean) + ci(e.population_ci95) : (e.why_not_determined || '–')),
          tdn(fin(e.tau_rel) ? num(100 * e.tau_rel, 2) + ' %' + (e.tau_rel_ci95 && fin(e.tau_rel_ci95[1]) ? ' (' + num(100 * e.tau_rel_ci95[0], 2) + ' – ' + num(100 * e.tau_rel_ci95[1], 2) + ' %)' : '') : '–'),
          tdn(fin(e.I2) ? num(100 * e.I2, 3) + ' %' : '–'), tdn(fin(e.p_homogeneous) ? (e.p_homogeneous < 1e-16 ? '< 1e-16' : num(e.p_homogeneous, 2)) : '–')]));
      });
    });
    sec.appendChild(el('div', { cls: 'wide' }, [t]));
    histSec.after(sec);
  }
  summaryTable();

  /* the results, a page at a time */
  var page = 0, PER = 100, shownCols = ['fit', 'status', 'file', 'sample', 'w_J_m2', 'Estar_Pa', 'nu', 'chi2_dof', 'adhesion_force_N', 'P_po_N', 'message'].filter(function (c) { return ci[c] != null; });
  var UNIT = { w_J_m2: 'J/m²', Estar_Pa: 'Pa', adhesion_force_N: 'N', P_po_N: 'N' };
  function passing() { var a = []; for (var r = 0; r < N; r++) if (pass[r]) a.push(r); return a; }
  function drawTable() {
    var list = passing(), pages = Math.max(1, Math.ceil(list.length / PER));
    if (page >= pages) page = pages - 1;
    pager.textContent = '';
    pager.appendChild(el('button', { type: 'button', text: '◀', onclick: function () { if (page > 0) { page--; drawTable(); } } }));
    pager.appendChild(el('span', { text: ' rows ' + (list.length ? page * PER + 1 : 0) + '–' + Math.min(list.length, (page + 1) * PER) + ' of ' + list.length + ' shown (' + N + ' fits) ' }));
    pager.appendChild(el('button', { type: 'button', text: '▶', onclick: function () { if (page + 1 < pages) { page++; drawTable(); } } }));
    var t = el('table', { id: 'results-table' }, [el('tr', {}, [el('th', { text: 'keep' })].concat(shownCols.map(function (c) { return el('th', { text: c }); })))]);
    list.slice(page * PER, (page + 1) * PER).forEach(function (r) {
      var box = el('input', { type: 'checkbox', 'data-row': r + 1 });
      box.checked = !excluded[r];
      box.addEventListener('click', function (e) { e.stopPropagation(); excluded[r] = box.checked ? 0 : 1; refresh(); });
      var tr = el('tr', { cls: 'pick' + (r + 1 === sel ? ' sel' : '') + (excluded[r] ? ' excluded' : ''), 'data-row': r + 1,
                          onclick: function () { location.hash = 'curve=' + (r + 1); } }, [el('td', {}, [box])]);
      shownCols.forEach(function (c) {
        var v = get(r, c);
        if (c === 'file' || c === 'message') tr.appendChild(el('td', {}, [c === 'file' ? nameCell(v) : el('span', { cls: 'name', title: String(v || ''), text: String(v || '') })]));
        else if (typeof v === 'number') tr.appendChild(tdn(UNIT[c] ? human(v, UNIT[c]) : num(v, 5)));
        else tr.appendChild(td(v == null ? '–' : String(v), c === 'status' && v !== 'ok' ? 'fail' : null));
      });
      t.appendChild(tr);
    });
    tableBox.textContent = '';
    tableBox.appendChild(t);
  }

  /* the selection: a plan of the kept curves (every curve of a kept fit;
   * the plan's rows where the report holds them, else file and sample) */
  function exportPlan() {
    var withPlan = D.fits.some(function (f) { return f && f.p; }), lines = [];
    lines.push(withPlan ? 'file,index,sample,k,R_m,b_m,interface,nu,segment' : 'file,sample');
    for (var r = 0; r < N; r++) {
      if (excluded[r]) continue;
      var f = D.fits[r];
      if (withPlan && f && f.p) f.p.forEach(function (p) { lines.push(p.map(function (v) { return csvCell(v == null ? '' : v); }).join(',')); });
      else if (!withPlan) lines.push([csvCell(get(r, 'file')), csvCell(get(r, 'sample'))].join(','));
    }
    var old = link.getAttribute('href');
    if (old && old.slice(0, 5) === 'blob:') URL.revokeObjectURL(old);
    link.setAttribute('href', URL.createObjectURL(new Blob([lines.join('\n') + '\n'], { type: 'text/csv' })));
    link.setAttribute('data-rows', String(lines.length - 1));
  }

  function showCurve() {
    sel = hashCurve();
    if (!(sel >= 1 && sel <= N)) { sel = 0; panel.hidden = true; return; }
    var r = sel - 1, f = D.fits[r], st = get(r, 'status');
    panel.hidden = false;
    panel.textContent = '';
    panel.appendChild(el('h3', {}, ['Fit ' + sel + ' (' + st + '): ', el('span', { id: 'curve-file', title: String(get(r, 'file')), text: basename(get(r, 'file')) })]));
    var nums = el('table', { id: 'curve-numbers' }), tr1 = el('tr'), tr2 = el('tr');
    cols.forEach(function (c) {
      var v = get(r, c);
      if (c === 'file' || c === 'message' || v == null || v === '') return;
      tr1.appendChild(el('th', { text: c }));
      tr2.appendChild(typeof v === 'number' ? tdn(UNIT[c] ? human(v, UNIT[c]) : num(v, 5)) : td(String(v)));
    });
    nums.appendChild(tr1); nums.appendChild(tr2);
    panel.appendChild(el('div', { cls: 'wide' }, [nums]));
    if (get(r, 'message')) panel.appendChild(el('p', { cls: st === 'ok' ? 'note' : 'bad', id: 'curve-message', text: get(r, 'message') }));
    var keep = el('input', { type: 'checkbox', id: 'curve-keep' });
    keep.checked = !excluded[r];
    keep.addEventListener('change', function () { excluded[r] = keep.checked ? 0 : 1; refresh(); });
    panel.appendChild(el('label', {}, [keep, ' keep this fit in the exported plan']));
    panel.appendChild(el('button', { type: 'button', text: 'close', style: 'margin-left:1em', onclick: function () { history.back(); } }));
    if (f && f.note) panel.appendChild(el('p', { cls: 'note', id: 'curve-note', text: f.note }));
    if (f && f.c && f.c.length) {
      f.c.forEach(function (p, j) {
        if (!p.q) return;
        if (f.c.length > 1) panel.appendChild(el('div', { text: 'curve ' + (j + 1) + ': ' + basename(f.p[j][0]) }));
        curveChart(panel, p, p.z0, p.F0, st === 'noconv' ? 'did not converge' : st === 'misfit' ? 'the model does not describe this curve' : null,
                   { adhesion: f.c.length === 1 ? get(r, 'adhesion_force_N') : null });
      });
    } else if (!(f && f.note)) panel.appendChild(el('p', { cls: 'note', text: 'No curve to draw: the fit failed before a result.' }));
    drawMaps();
    drawTable();
  }

  function refresh() {
    var st = fStatus.value, q = fQ.value, lo = parseFloat(fMin.value), hi = parseFloat(fMax.value), kept = 0;
    for (var r = 0; r < N; r++) {
      var ok = !st || get(r, 'status') === st, v = get(r, q);
      if (ok && isFinite(lo)) ok = fin(v) && v >= lo;
      if (ok && isFinite(hi)) ok = fin(v) && v <= hi;
      pass[r] = ok ? 1 : 0;
      kept += !excluded[r];
    }
    nsel.textContent = kept + ' of ' + N + ' fits kept';
    drawMaps(); drawHists(); drawTable(); exportPlan();
    var k = document.getElementById('curve-keep');
    if (k && sel) k.checked = !excluded[sel - 1];
  }
  window.addEventListener('hashchange', showCurve);
  refresh();
  showCurve();
}

if (D.kind === 'fit') fitPage(); else mapPage();
document.body.setAttribute('data-ready', '1');
})();
