/* The model in a Web Worker: the native FMU's model core compiled to WebAssembly
   (fmu/native/heli_wasm.c), driven as an FMI co-simulation master drives the FMU, at a fixed
   RK4 step h, in real time (or a chosen time scale, or as fast as it can), decoupled from the
   page's frames. With stability augmentation on, the hover-hold controller (its FMU's C, also
   WebAssembly: fmu/controller_wasm.c) runs beside it as in the co-simulation: both step, then
   the helicopter's fuselage outputs go to the controller's inputs and its four pitch outputs
   to the helicopter's inputs.

   Each step k (from t_k = k h) holds its inputs: the pilot's controls (or an input table's
   values at t_k, interpolated as heli simulate --inputs does), plus with the controller on its
   outputs and the pilot's deflection from the design's trim. The inputs held over every step
   are recorded (a row where they change) and written as heli simulate's --inputs table.

   The hinge angles after every step are kept (history), and with the controller on also its
   inputs (the helicopter's fuselage outputs) and outputs after every step.

   Messages in: init, start, run, pause, until, scale, pilot, table, sas, inputs, history, bench.
   Messages out: ready, frame, stopped, inputs, history, error. */
"use strict";

var C = null;        /* the page's configuration (window.__flyData.config) */
var M = null;        /* the model's exports */
var H = null;        /* the controller's exports (null: none) */
var memory = null, hmemory = null;
var S = null;        /* the flight */
var wasiText = "";

/* -- WebAssembly ------------------------------------------------------------------------------ */

function bytesOf(b64) {
  var text = atob(b64), bytes = new Uint8Array(text.length);
  for (var i = 0; i < text.length; i++) bytes[i] = text.charCodeAt(i);
  return bytes;
}

/* The WASI calls the modules import: fd_write (the core's messages on stderr go to the console),
   fd_close and fd_seek (never reached). */
function wasi(getMemory) {
  return {
    fd_write: function (fd, iovs, n, written) {
      var view = new DataView(getMemory().buffer), total = 0, text = "";
      for (var i = 0; i < n; i++) {
        var p = view.getUint32(iovs + 8 * i, true), len = view.getUint32(iovs + 8 * i + 4, true);
        text += new TextDecoder().decode(new Uint8Array(getMemory().buffer, p, len));
        total += len;
      }
      view.setUint32(written, total, true);
      wasiText += text;
      if (wasiText.indexOf("\n") >= 0) { console.warn(wasiText.trim()); wasiText = ""; }
      return 0;
    },
    fd_close: function () { return 0; },
    fd_seek: function () { return 70; }, /* ESPIPE */
    proc_exit: function (code) { throw new Error("the model exited with status " + code); }
  };
}

function instantiate(b64, getMemory) {
  return WebAssembly.instantiate(bytesOf(b64), {wasi_snapshot_preview1: wasi(getMemory)}).then(function (r) {
    if (r.instance.exports._initialize) r.instance.exports._initialize();
    return r.instance.exports;
  });
}

function cString(mem, p) {
  var bytes = new Uint8Array(mem.buffer), q = p;
  while (bytes[q]) q++;
  return new TextDecoder().decode(bytes.subarray(p, q));
}

function buffer() { return new Float64Array(memory.buffer, M.hw_buffer(), M.hw_buffer_size()); }

function setText(text) {
  var bytes = new TextEncoder().encode(text), at = M.hw_text();
  new Uint8Array(memory.buffer).set(bytes, at);
  new Uint8Array(memory.buffer)[at + bytes.length] = 0;
}

function message() { return cString(memory, M.hw_message()); }

function check(status, what) {
  if (status > 1) throw new Error(what + ": " + (message() || "status " + status));
  return status;
}

/* Values of the value references vrs (an array) now. */
function values(vrs) {
  var b = buffer();
  for (var i = 0; i < vrs.length; i++) b[i] = vrs[i];
  check(M.hw_get(vrs.length), "reading the outputs");
  return Array.prototype.slice.call(buffer(), 0, vrs.length);
}

/* -- the flight -------------------------------------------------------------------------------- */

function clamp(v, low, high) { return Math.min(Math.max(v, low), high); }

/* A fresh flight from start s (index into C.starts) with the initial forward speed `speed`
   (m/s, null: the start's own). */
function start(s, speed) {
  var st = C.starts[s], n = C.inputs.length;
  check(M.hw_open(), "creating the model");
  setText(C.scene);
  check(M.hw_set_string(C.vr.scene), "setting the scene");
  if (C.vr.initial_state >= 0) { setText("scene"); check(M.hw_set_string(C.vr.initial_state), "setting the start"); }
  for (var r = 0; r < C.scene_reals.length; r++)  /* the scene's own start values (not the family's primary's) */
    check(M.hw_set_real(C.scene_reals[r][0], C.scene_reals[r][1]), "setting the scene's start values");
  for (var i = 0; i < n; i++) check(M.hw_set_real(C.inputs[i].vr, st.controls[i]), "setting " + C.inputs[i].name);
  check(M.hw_start(), "initialising the model");
  var x = buffer();
  for (var j = 0; j < st.x0.length; j++) x[j] = st.x0[j];
  if (speed !== null && st.fs) for (var a = 0; a < 3; a++) x[st.fs.v[a]] = st.fs.direction[a] * speed;
  check(M.hw_load(), "loading the start");
  S = {start: s, speed: speed, k: 0, running: false, scale: S ? S.scale : 1, max: S ? S.max : false,
       until: null, pilot: st.controls.slice(), applied: st.controls.slice(), table: S ? S.table : null, sas: "off",
       sasOut: null, sasOffset: null, rows: [], hinges: [], stopped: null, samples: [],
       lastPost: 0, anchor: null, rate: [], behind: false, factor: null, flight: []};
  record(0, S.applied);
  keepHinges();
}

function time(k) { return k * C.h; }

/* -- inputs -------------------------------------------------------------------------------------- */

/* An input table's values at t: linear between rows, the later row at a jump, held after the last
   (mbs.inputs.InputTable.at). */
function tableAt(table, t) {
  var T = table.time, n = T.length, x = t * (1 + 1e-12) + 1e-15, lo = 0, hi = n;
  while (lo < hi) { var mid = (lo + hi) >> 1; if (T[mid] <= x) lo = mid + 1; else hi = mid; }
  var i = Math.min(Math.max(lo - 1, 0), n - 1), j = Math.min(i + 1, n - 1), span = T[j] - T[i];
  var w = span > 0 ? clamp((t - T[i]) / span, 0, 1) : 0;
  return table.values[i].map(function (v, c) { return v + w * (table.values[j][c] - v); });
}

/* The pilot's controls held over step k: the pilot's, or the input table's for its columns. */
function pilotAt(k) {
  var u = S.pilot.slice();
  if (S.table) {
    var row = tableAt(S.table, time(k));
    S.table.columns.forEach(function (c, i) { if (c >= 0) u[c] = row[i]; });
  }
  return u;
}

/* The model's inputs over step k: the pilot's, or the controller's plus the pilot's deflection
   from the design's trim, within the inputs' ranges. */
function inputsAt(k) {
  var u = pilotAt(k);
  if (S.sasOut) {
    var D = C.controller;
    u = u.map(function (v, i) {
      var o = D.output_of[i];
      return o < 0 ? v : S.sasOut[o] + (v - D.trim_out[o]);
    });
  }
  return u.map(function (v, i) { return clamp(v, C.inputs[i].low, C.inputs[i].high); });
}

function apply(u) {
  for (var i = 0; i < u.length; i++) {
    if (u[i] !== S.applied[i]) check(M.hw_set_real(C.inputs[i].vr, u[i]), "setting " + C.inputs[i].name);
  }
  if (changed(u, S.applied)) record(S.k, u);
  S.applied = u;
}

function changed(a, b) {
  for (var i = 0; i < a.length; i++) if (a[i] !== b[i]) return true;
  return false;
}

/* A row of the recorded inputs: from step k on, the inputs u. */
function record(k, u) {
  var last = S.rows[S.rows.length - 1];
  if (last && last.k === k) last.u = u.slice();
  else S.rows.push({k: k, u: u.slice()});
}

/* The recorded inputs as heli simulate's --inputs table: a row at each step where they change;
   a change after a stretch of equal inputs is a jump (its time written twice). Times are k h and
   values shortest round-trip decimals: the table's values at every step start are the ones held. */
function inputsCsv() {
  var lines = ["time," + C.inputs.map(function (q) { return q.name; }).join(",")];
  var line = function (k, u) { lines.push([time(k)].concat(u).map(String).join(",")); };
  S.rows.forEach(function (r, i) {
    var prev = S.rows[i - 1];
    if (prev && prev.k < r.k - 1) line(r.k, prev.u);
    line(r.k, r.u);
  });
  return lines.join("\n") + "\n";
}

/* -- stability augmentation --------------------------------------------------------------------- */

/* Switch the controller: "off", "attitude" (attitude hold: the controller sees no velocity or
   position error) or "hover" (hover hold: position and heading held where engaged). */
function engage(mode) {
  S.sas = mode;
  if (mode === "off" || !H) { S.sasOut = null; return; }
  if (H.hh_open(1.0) !== 0) throw new Error("the hover-hold controller: " + cString(hmemory, H.hh_message()));
  var y = values(C.controller.input_vrs);
  S.sasOffset = y.map(function (v, i) { return C.controller.offset[i] ? v - C.controller.trim_in[i] : 0; });
  feedController(y);
  S.sasOut = controllerOutputs();
}

function feedController(y) {
  var D = C.controller, b = new Float64Array(hmemory.buffer, H.hh_buffer(), D.input_vrs.length);
  for (var i = 0; i < y.length; i++) {
    b[i] = S.sas === "attitude" && D.velocity_or_position[i] ? D.trim_in[i] : y[i] - S.sasOffset[i];
  }
  if (H.hh_set_inputs() !== 0) throw new Error("the hover-hold controller: " + cString(hmemory, H.hh_message()));
}

function controllerOutputs() {
  var n = C.controller.trim_out.length, m = C.controller.input_vrs.length;
  if (H.hh_get_outputs() !== 0) throw new Error("the hover-hold controller: " + cString(hmemory, H.hh_message()));
  return Array.prototype.slice.call(new Float64Array(hmemory.buffer, H.hh_buffer(), m + n), m);
}

/* -- stepping ------------------------------------------------------------------------------------ */

function keepHinges() {
  if (S.hinges.length >= C.history_limit) return;
  M.hw_state();
  var b = buffer(), row = new Float64Array(C.hinge.length);
  for (var i = 0; i < C.hinge.length; i++) row[i] = b[C.hinge[i]];
  S.hinges.push(row);
}

/* One step; false when the model refused it (S.stopped says why). */
function step() {
  var t = time(S.k);
  apply(inputsAt(S.k));
  var status = M.hw_step(t, C.h);
  if (status > 1) {
    S.stopped = message() || "the step from t = " + t + " s failed (status " + status + ")";
    S.running = false;
    return false;
  }
  if (S.sasOut) {
    if (H.hh_step(t, C.h) !== 0) throw new Error("the hover-hold controller: " + cString(hmemory, H.hh_message()));
    var y = values(C.controller.input_vrs);
    feedController(y);
    S.sasOut = controllerOutputs();
    if (S.flight.length < C.history_limit) S.flight.push({k: S.k + 1, y: y, u: S.sasOut});
  }
  S.k += 1;
  keepHinges();
  if (S.k % C.chart_every === 0) sample();
  return true;
}

/* A chart sample at the current step: time, the chart values, the blade tips. */
function sample() {
  var v = values(C.chart_vrs);
  S.samples.push({t: time(S.k), v: v, tips: tips(), u: S.applied.slice()});
}

/* The blade tips (m) in their trace frames, x y z per blade. */
function tips() {
  var n = poses(), b = buffer(), out = [];
  C.tips.forEach(function (tip) {
    var p = pose(b, tip.body), q = tip.frame >= 0 ? pose(b, tip.frame) : null;
    var w = [0, 1, 2].map(function (i) {
      return p.o[i] + p.R[3 * i] * tip.point[0] + p.R[3 * i + 1] * tip.point[1] + p.R[3 * i + 2] * tip.point[2];
    });
    if (q) w = [0, 1, 2].map(function (j) {
      return q.R[j] * (w[0] - q.o[0]) + q.R[3 + j] * (w[1] - q.o[1]) + q.R[6 + j] * (w[2] - q.o[2]);
    });
    out.push(w[0], w[1], w[2]);
  });
  return out;
}

/* Evaluate the body poses into the buffer; their number of values. */
function poses() {
  var n = M.hw_poses();
  if (n < 0) throw new Error("the body poses could not be evaluated at t = " + time(S.k) + " s");
  return n;
}

function pose(b, i) {
  return {o: [b[12 * i], b[12 * i + 1], b[12 * i + 2]], R: Array.prototype.slice.call(b, 12 * i + 3, 12 * i + 12)};
}

/* -- the loop: real time (or the scale), as fast as it can (max), or until a time --------------------- */

var SLICE_MS = 20;
var channel = new MessageChannel();
channel.port1.onmessage = loop;

function schedule(delay) {
  if (delay > 0) setTimeout(loop, delay); else channel.port2.postMessage(0);
}

function loop() {
  if (!S || !S.running || S.looping) return;
  S.looping = true;
  var now = performance.now(), end = now + SLICE_MS, k0 = S.k, wait = 0;
  try {
    if (S.until !== null) {
      while (S.running && time(S.k) < S.until - 1e-12 && performance.now() < end) step();
      if (time(S.k) >= S.until - 1e-12) { S.running = false; S.until = null; }
    } else if (S.max) {
      while (S.running && performance.now() < end) step();
    } else {
      if (!S.anchor) S.anchor = {t: time(S.k), wall: now};
      var target = S.anchor.t + (now - S.anchor.wall) / 1000 * S.scale;
      while (S.running && time(S.k) < target && performance.now() < end) step();
      var lag = target - time(S.k);
      if (lag > 0.25 * S.scale) S.anchor = {t: time(S.k), wall: performance.now()}; /* give up the lost time */
      if (lag <= 0) wait = Math.max(1, Math.min(10, -lag / S.scale * 1000));
    }
  } catch (e) {
    S.running = false;
    S.stopped = String(e.message || e);
  }
  rate(now, k0);
  S.looping = false;
  post();
  if (S.running) schedule(wait);
}

/* The achieved real-time factor over the last second (s simulated per s of wall time). */
function rate(now, k0) {
  S.rate.push({wall: performance.now(), t: time(S.k), dk: S.k - k0});
  while (S.rate.length > 2 && S.rate[S.rate.length - 1].wall - S.rate[0].wall > 1000) S.rate.shift();
  var a = S.rate[0], b = S.rate[S.rate.length - 1];
  S.factor = b.wall > a.wall ? (b.t - a.t) / ((b.wall - a.wall) / 1000) : null;
  S.behind = !S.max && S.until === null && S.running && b.wall - a.wall > 500 && S.factor < 0.9 * S.scale;
}

/* A frame for the page: the poses, the readout, the chart samples since the last frame. */
function post(force) {
  var now = performance.now();
  if (!force && S.running && now - S.lastPost < 15) return;
  S.lastPost = now;
  var p = new Float64Array(buffer().subarray(0, poses()));
  var readout = values(C.readout_vrs);
  self.postMessage({type: "frame", t: time(S.k), k: S.k, poses: p, readout: readout, samples: S.samples,
                    running: S.running, stopped: S.stopped, behind: S.behind, factor: S.factor, scale: S.scale,
                    max: S.max, sas: S.sas, applied: S.applied, pilot: S.pilot, table: S.table ? S.table.name : null,
                    rows: S.rows.length}, [p.buffer]);
  S.samples = [];
}

/* -- messages ------------------------------------------------------------------------------------ */

function run(on) {
  if (S.stopped) on = false;
  S.running = on;
  S.anchor = null;
  S.rate = [];
  if (on) schedule(0); else post(true);
}

var handlers = {
  init: function (d) {
    C = d.config;
    var loads = [instantiate(d.model, function () { return memory; }).then(function (e) { M = e; memory = e.memory; })];
    if (d.controller) loads.push(instantiate(d.controller, function () { return hmemory; }).then(function (e) {
      H = e; hmemory = e.memory;
    }));
    Promise.all(loads).then(function () {
      start(0, null);
      self.postMessage({type: "ready"});
      post(true);
    }).catch(fail);
  },
  start: function (d) { start(d.start, d.speed === undefined ? null : d.speed); if (d.table) S.table = d.table; post(true); },
  run: function () { run(true); },
  pause: function () { run(false); },
  until: function (d) { S.until = d.t; run(true); },
  scale: function (d) { S.max = d.max; if (!d.max) S.scale = d.scale; S.anchor = null; S.rate = []; },
  pilot: function (d) { S.pilot = d.values.slice(); if (!S.running) post(true); },
  table: function (d) { S.table = d.table; post(true); },
  sas: function (d) { engage(d.mode); post(true); },
  inputs: function () { self.postMessage({type: "inputs", csv: inputsCsv(), steps: S.k}); },
  /* The benchmark: `steps` steps of the model core in one call (hw_run), then the flight restarts. */
  bench: function (d) {
    run(false);
    var t0 = performance.now(), status = M.hw_run(d.steps, C.h), ms = performance.now() - t0;
    start(S.start, S.speed);
    self.postMessage({type: "bench", us_per_step: ms * 1000 / d.steps, status: status});
  },
  history: function () {
    self.postMessage({type: "history", h: C.h, steps: S.hinges.length, names: C.hinge_names,
                      values: S.hinges.map(function (r) { return Array.prototype.slice.call(r); }),
                      flight: S.flight});
  }
};

function fail(e) { self.postMessage({type: "error", message: String(e && e.message || e)}); }

self.onmessage = function (ev) {
  try {
    if (ev.data.type !== "init" && !S) return; /* before the model is ready: the page sends again on "ready" */
    handlers[ev.data.type](ev.data);
  } catch (e) {
    fail(e);
  }
};
