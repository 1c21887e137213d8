/* Plot of an exported page (plain SVG): one panel per group of window.__viewerData.plot
   (pitch inputs, flap, lag, teeter ... in deg) against time, in s on the bottom axis and in
   main-rotor revolutions on the top axis, legends above the panels, a cursor at the player's
   time. Click or drag on the plot to seek (to the nearest key). window.__plot.cursor(t) moves the cursor;
   the svg's data-t0/-t1/-x0/-x1 give its time axis in viewBox units. */
(function () {
  "use strict";
  var NS = "http://www.w3.org/2000/svg";
  var D = window.__viewerData, P = D.plot, decode = window.__viewerDecode;
  var t = decode(P.t), t0 = t[0], t1 = t[t.length - 1];
  var W = 480, L = 50, R = 12, TOP = 30, HEAD = 34, BOTTOM = 34, CHAR = 5.2;
  var svg = document.getElementById("plot");
  var panels = P.panels.map(function (p) {
    return {title: p.title, series: p.series.map(function (s) { return {name: s.name, color: s.color, v: decode(s.values)}; })};
  });
  /* Panel height: all panels in the plot's box if they fit at 70 or more, at most 130. */
  var box = svg.parentElement, aspect = box.clientHeight / Math.max(box.clientWidth, 1);
  var H = Math.max(70, Math.min(130, (aspect * W - TOP - BOTTOM) / Math.max(panels.length, 1) - HEAD));
  var bottom = TOP + panels.length * (HEAD + H);

  function X(time) { return L + (t1 > t0 ? (time - t0) / (t1 - t0) : 0) * (W - L - R); }

  function add(name, attrs, text) {
    var e = document.createElementNS(NS, name);
    Object.keys(attrs).forEach(function (k) { e.setAttribute(k, attrs[k]); });
    if (text !== undefined) e.textContent = text;
    svg.appendChild(e);
    return e;
  }

  /* About `count` round tick values covering [lo, hi]. */
  function ticks(lo, hi, count) {
    var raw = (hi - lo) / count, mag = Math.pow(10, Math.floor(Math.log10(raw))), out = [];
    var step = [1, 2, 5, 10].map(function (m) { return m * mag; }).find(function (s) { return s >= raw; });
    for (var v = Math.ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step) out.push(Math.abs(v) < 1e-12 * step ? 0 : v);
    return {values: out, digits: Math.max(0, -Math.floor(Math.log10(step) + 1e-9))};
  }

  function range(series) {
    var lo = Infinity, hi = -Infinity;
    series.forEach(function (s) { for (var k = 0; k < s.v.length; k++) { lo = Math.min(lo, s.v[k]); hi = Math.max(hi, s.v[k]); } });
    var pad = hi - lo > 1e-9 * Math.max(1, Math.abs(hi)) ? 0.06 * (hi - lo) : Math.max(0.05 * Math.abs(hi), 0.01);
    return [lo - pad, hi + pad];
  }

  /* Legend names: the common ".flap"-like suffix is left out (blade1, blade2 ...). */
  function labels(series) {
    var tails = series.map(function (s) { return s.name.indexOf(".") > 0 ? s.name.slice(s.name.indexOf(".")) : null; });
    var common = tails[0] !== null && tails.every(function (x) { return x === tails[0]; });
    return series.map(function (s) { return common ? s.name.slice(0, s.name.length - tails[0].length) : s.name; });
  }

  function legend(p, y) {
    add("text", {x: L, y: y - 20, "font-size": 11, "font-weight": "bold"}, p.title);
    var x = L, names = labels(p.series);
    p.series.forEach(function (s, k) {
      add("line", {x1: x, x2: x + 12, y1: y - 7, y2: y - 7, stroke: s.color, "stroke-width": 2.5});
      add("text", {x: x + 15, y: y - 3, "font-size": 10}, names[k]);
      x += 16 + CHAR * names[k].length + 8;
    });
  }

  function panel(p, y) {
    legend(p, y);
    var yr = range(p.series), Y = function (v) { return y + H - (v - yr[0]) / (yr[1] - yr[0]) * H; };
    var tk = ticks(yr[0], yr[1], 4);
    tk.values.forEach(function (v) {
      add("line", {x1: L, x2: W - R, y1: Y(v), y2: Y(v), stroke: "#e4e4e4"});
      add("text", {x: L - 4, y: Y(v) + 3, "font-size": 9, "text-anchor": "end"}, v.toFixed(tk.digits));
    });
    revolutionLines(y);
    p.series.forEach(function (s) {
      var pts = [];
      for (var k = 0; k < s.v.length; k++) pts.push(X(t[k]).toFixed(2) + "," + Y(s.v[k]).toFixed(2));
      add("polyline", {points: pts.join(" "), fill: "none", stroke: s.color, "stroke-width": 1.1, "data-name": s.name});
    });
    add("rect", {x: L, y: y, width: W - L - R, height: H, fill: "none", stroke: "#888"});
  }

  function revolutionLines(y) {
    if (!D.revolution || (t1 - t0) / D.revolution > 60) return;
    for (var r = Math.ceil(t0 / D.revolution); r * D.revolution <= t1; r++) {
      add("line", {x1: X(r * D.revolution), x2: X(r * D.revolution), y1: y, y2: y + H, stroke: "#d0d8e8", "stroke-dasharray": "3,3"});
    }
  }

  function axes() {
    var ts = ticks(t0, t1, 6);
    ts.values.forEach(function (v) {
      add("line", {x1: X(v), x2: X(v), y1: bottom, y2: bottom + 4, stroke: "#888"});
      add("text", {x: X(v), y: bottom + 15, "font-size": 9, "text-anchor": "middle"}, v.toFixed(ts.digits));
    });
    add("text", {x: (L + W - R) / 2, y: bottom + 29, "font-size": 10, "text-anchor": "middle"}, "time (s)");
    if (!D.revolution) return;
    var rs = ticks(t0 / D.revolution, t1 / D.revolution, 6);
    rs.values.forEach(function (r) {
      add("text", {x: X(r * D.revolution), y: 12, "font-size": 9, "text-anchor": "middle"}, r.toFixed(rs.digits));
    });
    add("text", {x: W - R, y: 24, "font-size": 9, "text-anchor": "end", fill: "#555"}, "main-rotor revolutions");
  }

  svg.setAttribute("viewBox", "0 0 " + W + " " + (bottom + BOTTOM));
  panels.forEach(function (p, k) { panel(p, TOP + HEAD + k * (HEAD + H)); });
  axes();
  var cursor = add("line", {id: "plot-cursor", x1: L, x2: L, y1: TOP + HEAD - 4, y2: bottom, stroke: "#e00000", "stroke-width": 1.2});
  svg.dataset.t0 = String(t0);
  svg.dataset.t1 = String(t1);
  svg.dataset.x0 = String(L);
  svg.dataset.x1 = String(W - R);

  function timeAt(evt) {
    var pt = svg.createSVGPoint();
    pt.x = evt.clientX;
    pt.y = evt.clientY;
    var x = pt.matrixTransform(svg.getScreenCTM().inverse()).x;
    return t0 + (x - L) / (W - L - R) * (t1 - t0);
  }
  var dragging = false;
  svg.addEventListener("pointerdown", function (e) { dragging = true; window.__player.seekKey(timeAt(e)); });
  svg.addEventListener("pointermove", function (e) { if (dragging) window.__player.seekKey(timeAt(e)); });
  window.addEventListener("pointerup", function () { dragging = false; });

  window.__plot = {
    x: X,
    cursor: function (time) {
      var x = String(X(time));
      cursor.setAttribute("x1", x);
      cursor.setAttribute("x2", x);
    }
  };
})();
