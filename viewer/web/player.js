/* Player of an exported page. Sets the meshcat scene's node transforms from the keyframes of
   window.__viewerData at the player's time t (s of the simulation), the body nodes' and the
   hub-load arrows' (which also have a scale): positions and scales linear and
   quaternions spherical-linear between keys (the mapping of viewer/animation.py, local_at and
   world_at). Controls: play/pause (space bar), time slider (arrow keys: one key back or on),
   playback speed, follow-fuselage camera; the readout shows t, revolutions and the main-rotor
   azimuth. Playing runs through the times between keys; the slider and the plot seek to the
   nearest key, where the poses are the simulation's own. window.__player exposes seek(t),
   seekKey(t), play(), pause() and the state. */
(function () {
  "use strict";
  var D = window.__viewerData;
  var SLERP_LINEAR_ABOVE = 0.9995;
  var SPEEDS = [0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2];

  function decode(a) {
    var text = atob(a.b64), bytes = new Uint8Array(text.length);
    for (var j = 0; j < text.length; j++) bytes[j] = text.charCodeAt(j);
    return a.dtype === "f8" ? new Float64Array(bytes.buffer) : new Float32Array(bytes.buffer);
  }
  window.__viewerDecode = decode;

  function node(path) { return viewer.scene_tree.find(path.split("/").filter(Boolean)).object; }

  var T = decode(D.t), K = T.length, T0 = T[0], T1 = T[K - 1];
  var nodes = D.nodes.concat(D.arrows || []).map(function (n) {
    return {object: node(n.path), position: decode(n.position), quaternion: decode(n.quaternion),
            scale: n.scale ? decode(n.scale) : null};
  });
  var world = node(D.world);
  var follow = D.follow ? decode(D.follow) : null;
  var azimuth = D.azimuth ? decode(D.azimuth) : null;
  var traces = D.traces.map(node);
  var el = function (id) { return document.getElementById(id); };
  var button = el("play"), slider = el("time"), readout = el("readout"), speed = el("speed"), followBox = el("follow");
  var state = {time: T0, playing: false, speed: D.speed, follow: D.camera === "follow"};

  /* Key index i and weight w with t = (1 - w) T[i] + w T[i + 1]; t clamped to the keys. */
  function locate(t) {
    if (K < 2) return [0, 0];
    t = Math.min(Math.max(t, T0), T1);
    var lo = 0, hi = K - 1;
    while (hi - lo > 1) {
      var mid = (lo + hi) >> 1;
      if (T[mid] <= t) lo = mid; else hi = mid;
    }
    return [lo, (t - T[lo]) / (T[lo + 1] - T[lo])];
  }

  /* Row i of a track (n values per key, or one constant row) moved by w towards row i + 1. */
  function lerp(v, n, i, w) {
    var out = new Array(n);
    if (v.length === n || w === 0) {
      var r = v.length === n ? 0 : i * n;
      for (var k = 0; k < n; k++) out[k] = v[r + k];
      return out;
    }
    for (var m = 0; m < n; m++) out[m] = (1 - w) * v[i * n + m] + w * v[(i + 1) * n + m];
    return out;
  }

  function slerp(q, i, w) {
    if (q.length === 4 || w === 0) return lerp(q, 4, i, 0);
    var a = lerp(q, 4, i, 0), b = lerp(q, 4, i + 1, 0);
    var d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3], out = new Array(4), k;
    if (d < 0) { for (k = 0; k < 4; k++) b[k] = -b[k]; d = -d; }
    if (d > SLERP_LINEAR_ABOVE) {
      for (k = 0; k < 4; k++) out[k] = a[k] + w * (b[k] - a[k]);
      var norm = Math.hypot(out[0], out[1], out[2], out[3]);
      return out.map(function (x) { return x / norm; });
    }
    var theta = Math.acos(d), s = Math.sin(theta);
    for (k = 0; k < 4; k++) out[k] = (Math.sin((1 - w) * theta) * a[k] + Math.sin(w * theta) * b[k]) / s;
    return out;
  }

  function azimuthDeg(i, w) {
    var a = lerp(azimuth, 1, i, w)[0] * 180 / Math.PI;
    return (Math.round((((a % 360) + 360) % 360) * 10) / 10) % 360;
  }

  function show(t, i, w) {
    var text = "t = " + t.toFixed(4) + " s";
    if (D.revolution) text += "   rev " + (t / D.revolution).toFixed(3);
    if (azimuth) text += "   azimuth " + azimuthDeg(i, w).toFixed(1) + "\u00b0";
    readout.textContent = text;
    slider.value = String(t);
    if (window.__plot) window.__plot.cursor(t);
  }

  /* Show the scene at time t (s). */
  function seek(t) {
    t = Math.min(Math.max(t, T0), T1);
    var iw = locate(t), i = iw[0], w = iw[1];
    nodes.forEach(function (n) {
      var p = lerp(n.position, 3, i, w), q = slerp(n.quaternion, i, w);
      n.object.position.set(p[0], p[1], p[2]);
      n.object.quaternion.set(q[0], q[1], q[2], q[3]);
      if (n.scale) {
        var s = lerp(n.scale, 3, i, w);
        n.object.scale.set(s[0], s[1], s[2]);
      }
    });
    if (follow) {
      var f = state.follow ? lerp(follow, 3, i, w) : lerp(follow, 3, 0, 0);
      world.position.set(-f[0], -f[1], -f[2]);
    }
    var from = D.revolution ? locate(t - D.revolution)[0] : 0, upto = i + (w > 0 ? 2 : 1);
    traces.forEach(function (line) { line.geometry.setDrawRange(from, upto - from); });
    state.time = t;
    show(t, i, w);
    viewer.set_dirty();
  }

  /* Show the key nearest to time t (s). */
  function seekKey(t) {
    var iw = locate(t);
    seek(T[iw[1] < 0.5 ? iw[0] : Math.min(iw[0] + 1, K - 1)]);
  }

  function setPlaying(on) {
    state.playing = on;
    button.textContent = on ? "\u275a\u275a pause" : "\u25b6 play";
    button.setAttribute("aria-pressed", String(on));
  }

  /* One key back (-1) or on (+1) from the current time. */
  function step(direction) {
    var iw = locate(state.time), i = iw[0], w = iw[1];
    var k = direction > 0 ? i + 1 : (w > 0 ? i : i - 1);
    seek(T[Math.min(Math.max(k, 0), K - 1)]);
  }

  var last = null;
  function frame(now) {
    requestAnimationFrame(frame);
    if (!state.playing) { last = null; return; }
    if (last !== null && T1 > T0) {
      var t = state.time + (now - last) / 1000 * state.speed;
      seek(t > T1 ? T0 + (t - T1) % (T1 - T0) : t);
    }
    last = now;
  }

  function setupSpeed() {
    var speeds = SPEEDS.indexOf(D.speed) < 0 ? SPEEDS.concat([D.speed]).sort(function (a, b) { return a - b; }) : SPEEDS;
    speeds.forEach(function (s) {
      var o = document.createElement("option");
      o.value = String(s);
      o.textContent = "\u00d7" + Number(s.toPrecision(3)) + (s === 1 ? " (real time)" : "");
      o.selected = s === D.speed;
      speed.appendChild(o);
    });
    speed.addEventListener("change", function () { state.speed = parseFloat(speed.value); });
  }

  function setupControls() {
    slider.min = String(T0);
    slider.max = String(T1);
    slider.addEventListener("input", function () { seekKey(parseFloat(slider.value)); });
    button.addEventListener("click", function () { setPlaying(!state.playing); });
    setupSpeed();
    followBox.checked = state.follow;
    el("follow-label").style.display = follow ? "" : "none";
    followBox.addEventListener("change", function () { state.follow = followBox.checked; seek(state.time); });
    document.addEventListener("keydown", function (e) {
      if (/^(INPUT|SELECT|BUTTON)$/.test(e.target.tagName)) return;
      if (e.key === " ") { setPlaying(!state.playing); e.preventDefault(); }
      if (e.key === "ArrowRight" || e.key === "ArrowLeft") { step(e.key === "ArrowRight" ? 1 : -1); e.preventDefault(); }
    });
  }

  /* The 3D pane fills its box (meshcat sizes it to the window height otherwise). */
  var pane = document.getElementById("meshcat-pane"), resize = viewer.set_3d_pane_size.bind(viewer);
  viewer.set_3d_pane_size = function (w, h) {
    resize(w === undefined ? pane.offsetWidth : w, h === undefined ? pane.offsetHeight : h);
  };

  window.__player = {
    seek: seek, seekKey: seekKey, locate: locate, step: step,
    play: function () { setPlaying(true); },
    pause: function () { setPlaying(false); },
    state: function () { return {time: state.time, playing: state.playing, speed: state.speed, follow: state.follow}; },
    start: function () {
      setupControls();
      viewer.set_3d_pane_size();
      seek(T0);
      setPlaying(D.autoplay !== false);
      requestAnimationFrame(frame);
    }
  };
})();
