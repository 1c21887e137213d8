/* Live strip charts and the tip-path-plane view of the flight page (canvas).

   Charts: one panel per entry of config.charts (hinge angles of each blade, attitude, speed,
   rotor thrust, the pilot's controls), scrolling over the last `span` revolutions or seconds of
   simulated time. Tip-path plane: the blade tips of the last revolution in their hub's parent
   frame (body axes, z down), seen from the side (x forward, z up) and from behind (y right, z up),
   the vertical scale stretched; the plane fitted to them gives its forward and lateral tilt
   (front down and right down positive). window.__charts: add(samples), clear(), draw(), tpp() (the last fit). */
(function () {
  "use strict";
  var D = window.__flyData.config;
  var canvas = document.getElementById("charts"), tppCanvas = document.getElementById("tpp");
  var samples = [], dirty = true, fit = null;
  var PANEL_H = 92, HEAD = 16, LEFT = 46, RIGHT = 8, DEG = 180 / Math.PI, TPP_H = 150;
  var keep = Math.max.apply(null, D.charts.map(function (p) { return spanOf(p); }));

  function spanOf(p) { return p.revs ? p.revs * D.revolution : p.seconds; }

  function add(list) {
    if (!list.length) return;
    Array.prototype.push.apply(samples, list);
    var t = samples[samples.length - 1].t, i = 0;
    while (i < samples.length && samples[i].t < t - keep) i++;
    if (i > 0) samples.splice(0, i);
    dirty = true;
  }

  function clear() { samples = []; fit = null; dirty = true; }

  function size(c, h) {
    var w = c.parentElement.clientWidth || 400, r = window.devicePixelRatio || 1;
    if (c.width !== Math.round(w * r) || c.height !== Math.round(h * r)) {
      c.width = Math.round(w * r); c.height = Math.round(h * r);
      c.style.height = h + "px";
    }
    var g = c.getContext("2d");
    g.setTransform(r, 0, 0, r, 0, 0);
    return {g: g, w: w, h: h};
  }

  function niceRange(lo, hi) {
    if (!(hi > lo)) { var m = Math.max(Math.abs(lo) * 0.05, 0.01); return [lo - m, hi + m]; }
    var pad = 0.08 * (hi - lo);
    return [lo - pad, hi + pad];
  }

  function value(s, series, panel) {
    var v = series.input !== undefined ? s.u[series.input] : s.v[series.index];
    return v * (panel.scale || 1);
  }

  function panel(c, p, top, t1) {
    var g = c.g, span = spanOf(p), t0 = t1 - span, w = c.w - LEFT - RIGHT, lo = Infinity, hi = -Infinity;
    var shown = samples.filter(function (s) { return s.t >= t0; });
    shown.forEach(function (s) { p.series.forEach(function (q) { var v = value(s, q, p); lo = Math.min(lo, v); hi = Math.max(hi, v); }); });
    if (!shown.length) { lo = -1; hi = 1; }
    var r = niceRange(lo, hi), y0 = top + HEAD, h = PANEL_H - HEAD - 4;
    var Y = function (v) { return y0 + h - (v - r[0]) / (r[1] - r[0]) * h; };
    var X = function (t) { return LEFT + (t - t0) / span * w; };
    g.fillStyle = "#222"; g.font = "bold 11px sans-serif"; g.fillText(p.title, LEFT, top + 11);
    var x = LEFT + g.measureText(p.title).width + 10;
    g.font = "10px sans-serif";
    p.series.forEach(function (q) {
      g.fillStyle = q.color; g.fillRect(x, top + 5, 10, 3); x += 13;
      g.fillStyle = "#333"; g.fillText(q.label, x, top + 11); x += g.measureText(q.label).width + 8;
    });
    g.strokeStyle = "#ccc"; g.lineWidth = 1; g.strokeRect(LEFT, y0, w, h);
    g.fillStyle = "#555"; g.fillText(r[1].toPrecision(3), 2, y0 + 9); g.fillText(r[0].toPrecision(3), 2, y0 + h);
    p.series.forEach(function (q) {
      g.strokeStyle = q.color; g.lineWidth = 1.3; g.beginPath();
      shown.forEach(function (s, i) { var px = X(s.t), py = Y(value(s, q, p)); if (i) g.lineTo(px, py); else g.moveTo(px, py); });
      g.stroke();
    });
  }

  /* Panels as high as the side bar allows beside the tip-path plane (60 to 92 px). */
  function panelHeight() {
    var room = (canvas.parentElement.clientHeight || 700) - TPP_H - 40;
    return Math.max(60, Math.min(92, Math.floor(room / Math.max(D.charts.length, 1))));
  }

  function drawCharts() {
    PANEL_H = panelHeight();
    var c = size(canvas, D.charts.length * PANEL_H + 14), t1 = samples.length ? samples[samples.length - 1].t : 0;
    c.g.clearRect(0, 0, c.w, c.h);
    D.charts.forEach(function (p, i) { panel(c, p, i * PANEL_H, t1); });
    c.g.fillStyle = "#555"; c.g.font = "10px sans-serif";
    c.g.fillText("t = " + t1.toFixed(2) + " s (right edge)", LEFT, c.h - 3);
  }

  /* Least-squares plane z = a + b x + c y through the points (x, y, z). */
  function plane(points) {
    var S = [[0, 0, 0], [0, 0, 0], [0, 0, 0]], r = [0, 0, 0];
    points.forEach(function (p) {
      var f = [1, p[0], p[1]];
      for (var i = 0; i < 3; i++) { r[i] += f[i] * p[2]; for (var j = 0; j < 3; j++) S[i][j] += f[i] * f[j]; }
    });
    var det = function (m) {
      return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
        m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    var d = det(S);
    if (!(Math.abs(d) > 1e-12)) return null;
    return [0, 1, 2].map(function (k) { return det(S.map(function (row, i) { var m = row.slice(); m[k] = r[i]; return m; })) / d; });
  }

  function drawTpp() {
    var c = size(tppCanvas, TPP_H), g = c.g, n = D.tips.length, t1 = samples.length ? samples[samples.length - 1].t : 0;
    g.clearRect(0, 0, c.w, c.h);
    var last = samples.filter(function (s) { return s.t > t1 - D.revolution && s.tips.length; });
    var pts = [];
    last.forEach(function (s) { for (var b = 0; b < n; b++) pts.push([s.tips[3 * b], s.tips[3 * b + 1], s.tips[3 * b + 2], b]); });
    if (!pts.length) return;
    var cx = 0, cy = 0, cz = 0;
    pts.forEach(function (p) { cx += p[0]; cy += p[1]; cz += p[2]; });
    cx /= pts.length; cy /= pts.length; cz /= pts.length;
    var R = Math.max.apply(null, pts.map(function (p) { return Math.hypot(p[0] - cx, p[1] - cy); })) || 1;
    var stretch = D.tpp_stretch, half = c.w / 2, h = c.h - 20, mid = 10 + h / 2;
    var views = [{title: "side (x forward, z up)", a: 0, x0: 0}, {title: "from behind (y right, z up)", a: 1, x0: half}];
    views.forEach(function (v) {
      g.fillStyle = "#222"; g.font = "11px sans-serif"; g.fillText(v.title, v.x0 + 6, 12);
      g.strokeStyle = "#ddd"; g.beginPath(); g.moveTo(v.x0 + 6, mid); g.lineTo(v.x0 + half - 6, mid); g.stroke();
      var X = function (p) { return v.x0 + half / 2 + (p[v.a] - (v.a ? cy : cx)) / R * (half / 2 - 10); };
      var Y = function (p) { return mid + (p[2] - cz) / R * stretch * (half / 2 - 10); }; /* z down in the frame */
      for (var b = 0; b < n; b++) {
        g.fillStyle = D.tips[b].color;
        pts.forEach(function (p) { if (p[3] === b) g.fillRect(X(p) - 1, Y(p) - 1, 2.4, 2.4); });
      }
    });
    var f = plane(pts);
    fit = f ? {forward_deg: Math.atan(f[1]) * DEG, lateral_deg: Math.atan(f[2]) * DEG} : null;
    g.fillStyle = "#333"; g.font = "11px sans-serif";
    g.fillText("vertical \u00d7" + stretch + (fit ? "   plane tilt: forward " + fit.forward_deg.toFixed(2) + "\u00b0, right " +
               fit.lateral_deg.toFixed(2) + "\u00b0 (side down +)" : ""), 6, c.h - 4);
  }

  function draw() {
    if (!dirty) return;
    dirty = false;
    drawCharts();
    drawTpp();
  }

  window.__charts = {add: add, clear: clear, draw: function () { dirty = true; draw(); }, frame: draw,
                     tpp: function () { return fit; }, samples: function () { return samples.length; }};
})();
