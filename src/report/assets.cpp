/// @file assets.cpp
/// Inline CSS and JavaScript of the report page. The x-y renderer follows figure.cpp's SVG
/// layout (panel 340 x 220 px, margins 64/14/26/42); both draw the same figure model.

#include "detail/assets.hpp"

namespace manta::report::detail {

const char* const report_css = R"CSS(
body{font-family:Helvetica,Arial,sans-serif;margin:0;color:#222;background:#f6f6f4;line-height:1.4}
header{background:#1d3557;color:#fff;padding:14px 28px}
figure.cp{margin:10px 0 18px 0}figure.cp svg{max-width:100%;height:auto;background:#fff;border:1px solid #ddd}
figure.cp figcaption{font-size:13px;color:#555}
header h1{margin:0 0 4px 0;font-size:22px}
header p{margin:0;font-size:13px;opacity:.9}
nav{padding:8px 28px;background:#e9ecef;font-size:14px;position:sticky;top:0;z-index:5}
nav a{margin-right:16px;color:#1d3557;text-decoration:none}
main{padding:0 28px 40px 28px;max-width:1120px}
section{background:#fff;margin:18px 0;padding:12px 20px 18px 20px;border:1px solid #ddd;border-radius:4px}
h2{font-size:19px;margin:6px 0 10px 0;color:#1d3557}
h3{font-size:15px;margin:16px 0 6px 0}
table.num{border-collapse:collapse;font-size:13px;margin:6px 0}
table.num th,table.num td{border:1px solid #ccc;padding:3px 8px;text-align:right}
table.num th{background:#f0f0f0}
table.num td.k,table.num th.k{text-align:left}
.note{font-size:13px;color:#555}
.missing{color:#8a5a00}
#errors{background:#fdd;border:1px solid #c00;padding:8px 28px;color:#900}
.plot{position:relative;margin:8px 0}
.plot>svg{max-width:100%;height:auto}
.plot svg text{font-family:Helvetica,Arial,sans-serif;fill:#222}
.plot .tick{font-size:11px}.plot .label{font-size:12px}.plot .ptitle{font-size:12px;font-weight:bold}
.plot .title{font-size:15px;font-weight:bold}.plot .legend{font-size:12px}
.readout{position:absolute;pointer-events:none;background:rgba(255,255,255,.93);border:1px solid #888;
 font-size:12px;padding:3px 6px;white-space:pre;display:none}
.tools{font-size:12px;margin:2px 0}
.tools button,.tools select{font-size:12px}
.drawing svg{max-width:100%;height:auto}
.wide{overflow-x:auto}
.drawing svg text{font-family:Helvetica,Arial,sans-serif;font-size:12px;fill:#222}
.path3d svg{cursor:grab;background:#fff;border:1px solid #ddd}
)CSS";

const char* const report_js = R"JS(
(function () {
  'use strict';
  var nErrors = 0;
  function fail(msg) {
    nErrors += 1;
    document.body.setAttribute('data-errors', String(nErrors));
    var box = document.getElementById('errors');
    box.hidden = false;
    var d = document.createElement('div');
    d.textContent = msg;
    box.appendChild(d);
  }
  window.addEventListener('error', function (ev) {
    fail('script error: ' + ev.message + ' (' + ev.filename + ':' + ev.lineno + ')');
  });
  var NS = 'http://www.w3.org/2000/svg';
  var L = {pw: 340, ph: 220, ml: 64, mr: 14, mt: 26, mb: 42, title: 30, legend: 20};
  var DATA = JSON.parse(document.getElementById('manta-data').textContent);

  function el(tag, attrs, parent) {
    var e = document.createElementNS(NS, tag);
    for (var k in attrs) if (Object.prototype.hasOwnProperty.call(attrs, k)) e.setAttribute(k, attrs[k]);
    if (parent) parent.appendChild(e);
    return e;
  }
  function txt(parent, x, y, s, cls, anchor) {
    var t = el('text', {x: x, y: y, 'class': cls || '', 'text-anchor': anchor || 'start'}, parent);
    t.textContent = s;
    return t;
  }
  function niceTicks(lo, hi, target) {
    var out = [];
    if (!(hi > lo) || !isFinite(lo) || !isFinite(hi)) return out;
    var raw = (hi - lo) / (target || 5), mag = Math.pow(10, Math.floor(Math.log10(raw))), r = raw / mag;
    var step = (r < 1.5 ? 1 : r < 3.5 ? 2 : r < 7.5 ? 5 : 10) * mag;
    for (var v = Math.ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step)
      out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
    return out;
  }
  function tickText(v, step) {
    if (Math.abs(v) < step * 1e-9) v = 0;
    var mag = Math.max(Math.abs(v), step);
    if (mag >= 1e6 || step < 1e-4) return v === 0 ? '0' : Number(v.toPrecision(3)).toExponential();
    var d = Math.max(0, Math.floor(-Math.floor(Math.log10(step) + 1e-9)));
    return v.toFixed(d);
  }
  function fmtValue(v) {
    if (!isFinite(v)) return String(v);
    var a = Math.abs(v);
    return (a !== 0 && (a < 1e-3 || a >= 1e6)) ? v.toExponential(3) : String(+v.toPrecision(5));
  }
  function Range() { this.lo = Infinity; this.hi = -Infinity; }
  Range.prototype.add = function (v) { if (isFinite(v)) { if (v < this.lo) this.lo = v; if (v > this.hi) this.hi = v; } };
  Range.prototype.finish = function (pad) {
    if (!(this.lo <= this.hi)) { this.lo = 0; this.hi = 1; }
    if (this.hi - this.lo <= 1e-12 * Math.max(1, Math.abs(this.hi))) {
      var d0 = Math.max(Math.abs(this.hi) * 0.1, 1e-6); this.lo -= d0; this.hi += d0;
    }
    var d = (this.hi - this.lo) * pad; this.lo -= d; this.hi += d;
  };
  function points(xs, ys, X, Y) {
    var s = [];
    for (var i = 0; i < xs.length; i++) s.push(X(xs[i]).toFixed(2) + ',' + Y(ys[i]).toFixed(2));
    return s.join(' ');
  }
  function nearestIndex(xs, x) {
    var best = 0, bd = Infinity;
    for (var i = 0; i < xs.length; i++) { var d = Math.abs(xs[i] - x); if (d < bd) { bd = d; best = i; } }
    return best;
  }
  function legendEntries(fig) {
    var out = [];
    fig.panels.forEach(function (p) {
      p.series.forEach(function (s) {
        if (s.legend !== false && !out.some(function (o) { return o.name === s.name && o.colour === s.colour && o.style === s.style; })) out.push(s);
      });
    });
    return out;
  }
  function drawPanel(svg, p, ox, oy, container, uid) {
    var x0 = ox + L.ml, x1 = ox + L.pw - L.mr, y0 = oy + L.mt, y1 = oy + L.ph - L.mb;
    var rx = new Range(), ry = new Range();
    p.series.forEach(function (s) {
      s.x.forEach(function (v) { rx.add(v); });
      s.y.forEach(function (v) { ry.add(v); });
      if (s.y_upper) s.y_upper.forEach(function (v) { ry.add(v); });
    });
    rx.finish(0); ry.finish(0.06);
    var X = function (v) { return x0 + (v - rx.lo) / (rx.hi - rx.lo) * (x1 - x0); };
    var Y = function (v) { return y1 - (v - ry.lo) / (ry.hi - ry.lo) * (y1 - y0); };
    el('rect', {x: x0, y: y0, width: x1 - x0, height: y1 - y0, fill: '#fff', stroke: '#999'}, svg);
    p.shades.forEach(function (sh) {
      var a = X(Math.min(Math.max(sh.x0, rx.lo), rx.hi)), b = X(Math.min(Math.max(sh.x1, rx.lo), rx.hi));
      var r = el('rect', {x: a, y: y0, width: Math.max(b - a, 1), height: y1 - y0, fill: '#ffb000', 'fill-opacity': 0.28}, svg);
      el('title', {}, r).textContent = sh.label;
    });
    var xt = niceTicks(rx.lo, rx.hi, 5), yt = niceTicks(ry.lo, ry.hi, 5);
    var xs = xt.length > 1 ? xt[1] - xt[0] : 1, ys = yt.length > 1 ? yt[1] - yt[0] : 1;
    xt.forEach(function (v) {
      el('line', {x1: X(v), y1: y0, x2: X(v), y2: y1, stroke: '#e4e4e4'}, svg);
      txt(svg, X(v), y1 + 14, tickText(v, xs), 'tick', 'middle');
    });
    yt.forEach(function (v) {
      el('line', {x1: x0, y1: Y(v), x2: x1, y2: Y(v), stroke: '#e4e4e4'}, svg);
      txt(svg, x0 - 4, Y(v) + 4, tickText(v, ys), 'tick', 'end');
    });
    var clip = el('clipPath', {id: uid}, svg);
    el('rect', {x: x0, y: y0, width: x1 - x0, height: y1 - y0}, clip);
    var g = el('g', {'clip-path': 'url(#' + uid + ')'}, svg);
    p.series.forEach(function (s) {
      if (s.style === 'band') {
        var up = points(s.x, s.y_upper, X, Y);
        var lo = points(s.x.slice().reverse(), s.y.slice().reverse(), X, Y);
        el('polygon', {points: up + ' ' + lo, fill: s.colour, 'fill-opacity': s.opacity || 0.2, stroke: 'none'}, g);
      } else if (s.style === 'markers') {
        for (var i = 0; i < s.x.length; i++)
          el('circle', {cx: X(s.x[i]), cy: Y(s.y[i]), r: 3, fill: 'none', stroke: s.colour, 'stroke-width': 1.2}, g);
      } else if (s.style === 'squares') {
        for (var j = 0; j < s.x.length; j++)
          el('rect', {x: X(s.x[j]) - 3, y: Y(s.y[j]) - 3, width: 6, height: 6, fill: 'none', stroke: s.colour, 'stroke-width': 1.2}, g);
      } else {
        var a = {points: points(s.x, s.y, X, Y), fill: 'none', stroke: s.colour, 'stroke-width': 1.6};
        if (s.style === 'dashed') a['stroke-dasharray'] = '5,4';
        el('polyline', a, g);
      }
    });
    txt(svg, (x0 + x1) / 2, y1 + 32, p.x, 'label', 'middle');
    var yl = txt(svg, 0, 0, p.y, 'label', 'middle');
    yl.setAttribute('transform', 'translate(' + (ox + 14) + ',' + ((y0 + y1) / 2) + ') rotate(-90)');
    txt(svg, (x0 + x1) / 2, oy + 17, p.title, 'ptitle', 'middle');
    // Hover readout: a cursor line and the value of every series at the nearest sample.
    var cursor = el('line', {x1: 0, y1: y0, x2: 0, y2: y1, stroke: '#444', 'stroke-dasharray': '2,2', visibility: 'hidden'}, svg);
    var hit = el('rect', {x: x0, y: y0, width: x1 - x0, height: y1 - y0, fill: 'transparent'}, svg);
    var box = container.querySelector('.readout');
    hit.addEventListener('mousemove', function (ev) {
      var r = svg.getBoundingClientRect(), vb = svg.viewBox.baseVal;
      var sx = (ev.clientX - r.left) * vb.width / r.width;
      var xv = rx.lo + (sx - x0) / (x1 - x0) * (rx.hi - rx.lo);
      cursor.setAttribute('x1', sx); cursor.setAttribute('x2', sx); cursor.setAttribute('visibility', 'visible');
      var lines = [p.x + ' = ' + fmtValue(xv)];
      p.series.forEach(function (s) {
        if (!s.x.length) return;
        var i = nearestIndex(s.x, xv);
        var v = s.style === 'band' ? fmtValue(s.y[i]) + ' .. ' + fmtValue(s.y_upper[i]) : fmtValue(s.y[i]);
        lines.push(s.name + ': ' + v);
      });
      box.textContent = lines.join('\n');
      box.style.display = 'block';
      var cr = container.getBoundingClientRect();
      box.style.left = (ev.clientX - cr.left + container.scrollLeft + 14) + 'px';
      box.style.top = (ev.clientY - cr.top + 10) + 'px';
    });
    hit.addEventListener('mouseleave', function () { box.style.display = 'none'; cursor.setAttribute('visibility', 'hidden'); });
  }
  function addDownload(container, svg, name) {
    var tools = document.createElement('div');
    tools.className = 'tools';
    var b = document.createElement('button');
    b.textContent = 'save SVG';
    b.addEventListener('click', function () {
      var blob = new Blob([new XMLSerializer().serializeToString(svg)], {type: 'image/svg+xml'});
      var a = document.createElement('a');
      a.href = URL.createObjectURL(blob); a.download = name + '.svg'; a.click();
    });
    tools.appendChild(b);
    container.appendChild(tools);
  }
  function drawFigure(container, fig) {
    container.innerHTML = '';
    var cols = Math.max(1, Math.min(fig.columns, fig.panels.length));
    var rows = Math.ceil(fig.panels.length / cols), width = cols * L.pw;
    var svg = el('svg', {xmlns: NS});
    txt(svg, 10, 20, fig.title, 'title');
    var lx = 10, ly = L.title + 14, entries = legendEntries(fig);
    entries.forEach(function (s) {
      var w = 34 + 7 * s.name.length;
      if (lx + w > width && lx > 10) { lx = 10; ly += L.legend; }
      if (s.style === 'band') el('rect', {x: lx, y: ly - 9, width: 22, height: 10, fill: s.colour, 'fill-opacity': Math.min(1, (s.opacity || 0.2) + 0.05)}, svg);
      else if (s.style === 'markers') el('circle', {cx: lx + 11, cy: ly - 4, r: 3, fill: 'none', stroke: s.colour, 'stroke-width': 1.2}, svg);
      else if (s.style === 'squares') el('rect', {x: lx + 8, y: ly - 7, width: 6, height: 6, fill: 'none', stroke: s.colour, 'stroke-width': 1.2}, svg);
      else {
        var a = {x1: lx, y1: ly - 4, x2: lx + 22, y2: ly - 4, stroke: s.colour, 'stroke-width': 2};
        if (s.style === 'dashed') a['stroke-dasharray'] = '5,4';
        el('line', a, svg);
      }
      txt(svg, lx + 27, ly, s.name, 'legend');
      lx += w;
    });
    var top = entries.length ? ly + 10 : L.title, height = top + rows * L.ph;
    svg.setAttribute('width', width); svg.setAttribute('height', height);
    svg.setAttribute('viewBox', '0 0 ' + width + ' ' + height);
    var box = document.createElement('div'); box.className = 'readout';
    container.appendChild(svg); container.appendChild(box);
    fig.panels.forEach(function (p, i) {
      drawPanel(svg, p, (i % cols) * L.pw, top + Math.floor(i / cols) * L.ph, container, fig.id + '-clip-' + i);
    });
    addDownload(container, svg, fig.id);
    container.setAttribute('data-rendered', String(fig.panels.length));
  }

  // ---- 3-D flight path: orthographic view, drag to rotate, wheel to zoom.
  function drawPath(container, P) {
    var W = 760, H = 560, view = {az: -60, el: 25, zoom: 1};
    container.innerHTML = '';
    var svg = el('svg', {xmlns: NS, width: W, height: H, viewBox: '0 0 ' + W + ' ' + H}, container);
    var n = P.t.length, re = new Range(), rn = new Range(), rh = new Range();
    for (var i = 0; i < n; i++) { re.add(P.east[i]); rn.add(P.north[i]); rh.add(P.altitude[i]); }
    re.finish(0.05); rn.finish(0.05); rh.finish(0.05);
    var largest = Math.max(re.hi - re.lo, rn.hi - rn.lo, rh.hi - rh.lo);
    [re, rn, rh].forEach(function (r) {
      var grow = Math.max(0, 0.4 * largest - (r.hi - r.lo)) / 2; r.lo -= grow; r.hi += grow;
    });
    var ce = (re.lo + re.hi) / 2, cn = (rn.lo + rn.hi) / 2, ch = (rh.lo + rh.hi) / 2;
    var extent = Math.max(re.hi - re.lo, rn.hi - rn.lo, rh.hi - rh.lo);
    function proj(e, nn, a) {
      var az = view.az * Math.PI / 180, elv = view.el * Math.PI / 180;
      var s = 0.75 * Math.min(W, H) / extent * view.zoom;
      var x1 = Math.cos(az) * (e - ce) + Math.sin(az) * (nn - cn);
      var y1 = -Math.sin(az) * (e - ce) + Math.cos(az) * (nn - cn);
      var sy = Math.sin(elv) * y1 + Math.cos(elv) * (a - ch);
      return [W / 2 + s * x1, H / 2 + 20 - s * sy];
    }
    function line(g, a, b, attrs) {
      attrs.x1 = a[0]; attrs.y1 = a[1]; attrs.x2 = b[0]; attrs.y2 = b[1];
      return el('line', attrs, g);
    }
    var g = el('g', {}, svg);
    function redraw() {
      while (g.firstChild) g.removeChild(g.firstChild);
      txt(g, 10, 20, P.title, 'title');
      // Box edges on the ground and three axes with ticks in metres.
      var c = [[re.lo, rn.lo], [re.hi, rn.lo], [re.hi, rn.hi], [re.lo, rn.hi]];
      for (var k = 0; k < 4; k++)
        line(g, proj(c[k][0], c[k][1], rh.lo), proj(c[(k + 1) % 4][0], c[(k + 1) % 4][1], rh.lo), {stroke: '#ccc'});
      var axes = [[re, 'east [m]'], [rn, 'north [m]'], [rh, 'altitude [m]']];
      axes.forEach(function (ax, k) {
        var r = ax[0];
        var at = function (v) { return proj(k === 0 ? v : re.lo, k === 1 ? v : rn.lo, k === 2 ? v : rh.lo); };
        line(g, at(r.lo), at(r.hi), {stroke: '#555'});
        niceTicks(r.lo, r.hi, 4).forEach(function (v) {
          var q = at(v);
          el('circle', {cx: q[0], cy: q[1], r: 1.5, fill: '#555'}, g);
          txt(g, q[0] + [6, -4, -6][k], q[1] + [12, 14, 4][k], v.toFixed(0), 'tick', k === 0 ? 'start' : 'end');
        });
        var e = at(r.hi);
        txt(g, e[0] + 6, e[1] - 4, ax[1], 'label');
      });
      var track = [], path = [];
      for (var i = 0; i < n; i++) {
        var a = proj(P.east[i], P.north[i], rh.lo), b = proj(P.east[i], P.north[i], P.altitude[i]);
        track.push(a[0].toFixed(1) + ',' + a[1].toFixed(1)); path.push(b[0].toFixed(1) + ',' + b[1].toFixed(1));
      }
      el('polyline', {points: track.join(' '), fill: 'none', stroke: '#bbb', 'stroke-dasharray': '3,3'}, g);
      el('polyline', {points: path.join(' '), fill: 'none', stroke: P.colour, 'stroke-width': 2}, g);
      P.glyphs.forEach(function (i) {
        var cf = Math.cos(P.phi[i]), sf = Math.sin(P.phi[i]), ct = Math.cos(P.theta[i]), st = Math.sin(P.theta[i]);
        var cp = Math.cos(P.psi[i]), sp = Math.sin(P.psi[i]);
        var R = [[ct * cp, sf * st * cp - cf * sp, cf * st * cp + sf * sp],
                 [ct * sp, sf * st * sp + cf * cp, cf * st * sp - sf * cp],
                 [-st, sf * ct, cf * ct]];
        var k = P.glyph_scale;
        var earth = function (bx, by, bz) {
          var nn = R[0][0] * bx + R[0][1] * by + R[0][2] * bz;
          var e = R[1][0] * bx + R[1][1] * by + R[1][2] * bz;
          var d = R[2][0] * bx + R[2][1] * by + R[2][2] * bz;
          return proj(P.east[i] + k * e, P.north[i] + k * nn, P.altitude[i] - k * d);
        };
        P.segments.forEach(function (s) {
          line(g, earth(s[0], s[1], s[2]), earth(s[3], s[4], s[5]), {stroke: '#333', 'stroke-width': 0.8});
        });
      });
      var s0 = proj(P.east[0], P.north[0], P.altitude[0]);
      el('circle', {cx: s0[0], cy: s0[1], r: 4, fill: '#2ca02c'}, g);
      txt(g, s0[0] + 6, s0[1] + 4, 'start', 'legend');
      txt(g, 10, H - 10, 'aircraft drawn ' + P.glyph_scale + ':1; dashed: ground track; drag to rotate, wheel to zoom (azimuth ' +
          view.az.toFixed(0) + ' deg, elevation ' + view.el.toFixed(0) + ' deg)', 'legend');
    }
    redraw();
    var drag = null;
    svg.addEventListener('mousedown', function (ev) { drag = [ev.clientX, ev.clientY]; ev.preventDefault(); });
    window.addEventListener('mouseup', function () { drag = null; });
    window.addEventListener('mousemove', function (ev) {
      if (!drag) return;
      view.az -= (ev.clientX - drag[0]) * 0.5;
      view.el = Math.max(-89, Math.min(89, view.el + (ev.clientY - drag[1]) * 0.5));
      drag = [ev.clientX, ev.clientY];
      redraw();
    });
    svg.addEventListener('wheel', function (ev) {
      ev.preventDefault();
      view.zoom = Math.max(0.2, Math.min(20, view.zoom * Math.exp(-ev.deltaY * 0.001)));
      redraw();
    }, {passive: false});
    var tools = document.createElement('div');
    tools.className = 'tools';
    var reset = document.createElement('button');
    reset.textContent = 'reset view';
    reset.addEventListener('click', function () { view = {az: -60, el: 25, zoom: 1}; redraw(); });
    tools.appendChild(reset);
    container.appendChild(tools);
    addDownload(container, svg, P.id);
    container.setAttribute('data-rendered', String(n));
  }

  // Each plot on its own: one that fails is reported and the others are still drawn.
  function guarded(what, f) {
    try { f(); } catch (e) { fail(what + ': ' + (e && e.stack ? e.stack : e)); }
  }
  function renderAll() {
    document.querySelectorAll('.plot[data-figure]').forEach(function (c) {
      var id = c.getAttribute('data-figure'), f = DATA.figures[id];
      if (!f) { fail('figure ' + id + ' has no data'); return; }
      guarded('figure ' + id, function () { drawFigure(c, f); });
    });
    document.querySelectorAll('.plot[data-path]').forEach(function (c) {
      var id = c.getAttribute('data-path'), p = DATA.paths[id];
      if (!p) { fail('path ' + id + ' has no data'); return; }
      guarded('path ' + id, function () { drawPath(c, p); });
    });
    document.querySelectorAll('select[data-group]').forEach(function (s) {
      s.addEventListener('change', function () {
        var c = document.getElementById(s.getAttribute('data-group'));
        c.setAttribute('data-figure', s.value);
        guarded('figure ' + s.value, function () { drawFigure(c, DATA.figures[s.value]); });
      });
    });
  }
  try { renderAll(); } catch (e) { fail('script error: ' + (e && e.stack ? e.stack : e)); }
  var plots = document.querySelectorAll('.plot');
  var done = document.querySelectorAll('.plot[data-rendered]');
  document.body.setAttribute('data-plots-total', String(plots.length));
  document.body.setAttribute('data-plots-rendered', String(done.length));
})();
)JS";

}  // namespace manta::report::detail
