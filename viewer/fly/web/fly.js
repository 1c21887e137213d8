/* The flight page's main thread: starts the model's Web Worker (worker.js, from the page's own
   text: no file, no server), sends it the pilot's controls, and draws what it sends back: the
   body poses into the meshcat scene (each node relative to its parent, the world moved so that
   the fuselage stays at the centre), the readout (time, revolutions, azimuth), the charts and
   the tip-path plane, and the flight's state (running, behind real time, stopped with the
   model's message).

   window.__fly: the page's API, also what the tests drive: ready, frame (the last), run(),
   pause(), until(t) (run to time t and pause), scale(s) (s: a time scale, or "max"),
   sas(mode), start(i, speed), reset(), table(csvText, name) (fly an input table), inputsCsv()
   and history() (promises: the recorded inputs as heli simulate's --inputs table, the hinge
   angles of every step), on(type, fn). */
(function () {
  "use strict";
  var data = window.__flyData, C = data.config;
  var el = function (id) { return document.getElementById(id); };
  var listeners = {}, pending = {}, state = {ready: false, frame: null, error: null, firstFrameMs: null};
  var THREE = MeshCat.THREE;

  function on(type, fn) { (listeners[type] = listeners[type] || []).push(fn); }
  function emit(type, d) { (listeners[type] || []).forEach(function (fn) { fn(d); }); }

  var worker = new Worker(URL.createObjectURL(new Blob([el("worker-source").textContent], {type: "text/javascript"})));
  worker.onmessage = function (ev) {
    var d = ev.data;
    if (d.type === "frame") frame(d);
    else if (d.type === "ready") { state.ready = true; lastPilot = null; emit("ready", d); }
    else if (d.type === "error") { state.error = d.message; banner(d.message, "error"); emit("error", d); }
    else if (pending[d.type]) { pending[d.type].forEach(function (r) { r(d); }); pending[d.type] = []; }
  };
  function ask(type, extra) {
    return new Promise(function (resolve) {
      (pending[type] = pending[type] || []).push(resolve);
      worker.postMessage(Object.assign({type: type}, extra || {}));
    });
  }
  function send(type, extra) { worker.postMessage(Object.assign({type: type}, extra || {})); }

  /* -- the 3D view ------------------------------------------------------------------------------ */
  function node(path) { return viewer.scene_tree.find(path.split("/").filter(Boolean)).object; }
  var nodes = C.bodies.map(function (b) { return node(b.path); }), world = node(C.world);
  var matrix = new THREE.Matrix4();

  function poseOf(p, i) { return {o: [p[12 * i], p[12 * i + 1], p[12 * i + 2]], R: p.subarray(12 * i + 3, 12 * i + 12)}; }

  /* Each body's node: its pose relative to its parent's (R_p^T R, R_p^T (o - o_p)). */
  function place(p) {
    C.bodies.forEach(function (b, i) {
      var a = poseOf(p, i), R = a.R, o = a.o;
      if (b.parent >= 0) {
        var q = poseOf(p, b.parent), Q = q.R, d = [o[0] - q.o[0], o[1] - q.o[1], o[2] - q.o[2]], M = [];
        for (var r = 0; r < 3; r++) for (var c = 0; c < 3; c++) M.push(Q[r] * R[c] + Q[3 + r] * R[3 + c] + Q[6 + r] * R[6 + c]);
        o = [0, 1, 2].map(function (r) { return Q[r] * d[0] + Q[3 + r] * d[1] + Q[6 + r] * d[2]; });
        R = M;
      }
      matrix.set(R[0], R[1], R[2], o[0], R[3], R[4], R[5], o[1], R[6], R[7], R[8], o[2], 0, 0, 0, 1);
      nodes[i].position.set(o[0], o[1], o[2]);
      nodes[i].quaternion.setFromRotationMatrix(matrix);
    });
    if (C.follow >= 0) world.position.set(-p[12 * C.follow], -p[12 * C.follow + 1], -p[12 * C.follow + 2]);
    viewer.set_dirty();
  }

  /* -- the readout and the state -------------------------------------------------------------------- */
  function banner(text, kind) {
    var b = el("banner");
    b.textContent = text || "";
    b.className = kind || "";
    b.style.display = text ? "block" : "none";
  }

  function readout(d) {
    var r = d.readout, text = "t = " + d.t.toFixed(3) + " s   rev " + (d.t / C.revolution).toFixed(2);
    C.readout.forEach(function (q, i) {
      var v = r[i] * (q.scale || 1);
      if (q.modulo) v = ((v % q.modulo) + q.modulo) % q.modulo;
      text += (i === 1 ? "\n" : "   ") + q.label + " " + v.toFixed(q.digits) + q.unit;
    });
    el("readout").textContent = text;
    var s = el("status");
    s.className = d.behind ? "behind" : "";
    var mode = d.max ? "as fast as it can" : "time scale \u00d7" + d.scale;
    var rate = d.factor !== null && d.running ? ", running at \u00d7" + d.factor.toPrecision(3) + " real time" : "";
    s.textContent = (d.running ? mode + rate : "paused") + (d.behind ? ": this computer cannot keep up with \u00d7" +
                    d.scale + " (the flight runs slower than the chosen time scale)" : "");
    el("run").textContent = d.running ? "\u275a\u275a pause" : "\u25b6 fly";
    if (d.stopped) banner("The simulation stopped: " + d.stopped + " (reset to fly again)", "error");
    el("rows").textContent = d.rows + (d.rows === 1 ? " input row" : " input rows");
    el("table-drop").style.display = d.table ? "" : "none";
  }

  function frame(d) {
    if (state.firstFrameMs === null) state.firstFrameMs = performance.now(); /* ms since the page's navigation */
    state.frame = d;
    place(d.poses);
    readout(d);
    window.__charts.add(d.samples);
    emit("frame", d);
  }

  /* -- controls ----------------------------------------------------------------------------------- */
  var lastPilot = null;
  function pilotTick(dt) {
    window.__pilot.update(dt);
    var v = window.__pilot.values();
    if (!lastPilot || v.some(function (x, i) { return x !== lastPilot[i]; })) { send("pilot", {values: v}); lastPilot = v; }
  }

  var lastWall = null;
  function tick(now) {
    requestAnimationFrame(tick);
    var dt = lastWall === null ? 0 : Math.min(0.1, (now - lastWall) / 1000);
    lastWall = now;
    pilotTick(dt);
    window.__charts.frame();
    var pad = window.__pilot.gamepad();
    el("gamepad").textContent = pad ? "gamepad: " + pad : "no gamepad (connect one and press a button)";
  }

  function start(i, speed) {
    var st = C.starts[i];
    window.__pilot.reset(st.controls);
    lastPilot = null;
    window.__charts.clear();
    banner(C.note, C.note ? "note" : "");
    send("start", {start: i, speed: speed === undefined || speed === null || isNaN(speed) ? null : speed});
    send("pilot", {values: window.__pilot.values()});
    if (C.controller && el("sas").value !== "off") send("sas", {mode: el("sas").value}); /* stays as switched */
  }

  function setScale(value) {
    if (value === "max") send("scale", {max: true});
    else send("scale", {max: false, scale: parseFloat(value)});
  }

  /* -- input tables (heli simulate's --inputs CSV) --------------------------------------------------- */
  function parseTable(text, name) {
    var lines = text.split(/\r?\n/).filter(function (l) { return l.trim(); });
    var head = lines[0].split(",").map(function (s) { return s.trim(); });
    if (head[0] !== "time") throw new Error(name + ": the first column must be 'time' (s)");
    var names = C.inputs.map(function (q) { return q.name; });
    var columns = head.slice(1).map(function (h) { return names.indexOf(h); });
    var unknown = head.slice(1).filter(function (h, i) { return columns[i] < 0; });
    if (unknown.length) throw new Error(name + ": " + unknown.join(", ") + " is not an input of this page (" + names.join(", ") + ")");
    var time = [], values = [];
    lines.slice(1).forEach(function (l, k) {
      var f = l.split(",").map(Number);
      if (f.length !== head.length || f.some(function (x) { return !isFinite(x); })) {
        throw new Error(name + ": line " + (k + 2) + " is not " + head.length + " numbers");
      }
      time.push(f[0]); values.push(f.slice(1));
    });
    return {name: name, time: time, values: values, columns: columns};
  }

  function table(text, name) {
    var t = parseTable(text, name || "table");
    send("table", {table: t});
    return t;
  }

  function download(name, text) {
    var a = document.createElement("a");
    a.href = URL.createObjectURL(new Blob([text], {type: "text/csv"}));
    a.download = name;
    document.body.appendChild(a);
    a.click();
    a.remove();
  }

  function setup() {
    C.starts.forEach(function (s, i) {
      var o = document.createElement("option");
      o.value = String(i); o.textContent = s.label;
      el("start").appendChild(o);
    });
    C.scales.forEach(function (s) {
      var o = document.createElement("option");
      o.value = String(s); o.textContent = s === "max" ? "as fast as it can" : "\u00d7" + s + (s === 1 ? " (real time)" : "");
      o.selected = s === 1;
      el("scale").appendChild(o);
    });
    var restart = function () { start(parseInt(el("start").value, 10), el("speed").value === "" ? null : parseFloat(el("speed").value)); };
    el("start").addEventListener("change", function () { el("speed").value = ""; restart(); });
    el("reset").addEventListener("click", restart);
    el("speed").addEventListener("change", restart);
    el("run").addEventListener("click", function () { send(state.frame && state.frame.running ? "pause" : "run"); });
    el("scale").addEventListener("change", function () { setScale(el("scale").value); });
    el("sas").addEventListener("change", function () { send("sas", {mode: el("sas").value}); });
    el("sas").disabled = !C.controller;
    el("sas").title = C.controller ? C.controller.note : C.no_controller;
    el("trim").addEventListener("click", function () { window.__pilot.release(); });
    el("revolution").addEventListener("click", function () {
      var t = state.frame ? state.frame.t : 0;
      send("until", {t: (Math.floor(t / C.revolution + 1e-9) + 1) * C.revolution});
    });
    el("record").addEventListener("click", function () {
      ask("inputs").then(function (d) { download(C.inputs_file, d.csv); });
    });
    el("table-drop").addEventListener("click", function () {
      send("table", {table: null});
      el("table-file").value = "";
      banner("", "");
    });
    el("table-file").addEventListener("change", function () {
      var f = el("table-file").files[0];
      if (!f) return;
      f.text().then(function (text) {
        try { table(text, f.name); banner("flying the inputs of " + f.name + " at their times from t = 0 (reset flies them again)", "note"); }
        catch (e) { banner(String(e.message), "error"); }
      });
    });
    document.addEventListener("keydown", function (e) {
      if (/^(INPUT|SELECT|TEXTAREA|BUTTON)$/.test(e.target.tagName) && e.target.type !== "range") return;
      if (e.key === " ") { el("run").click(); e.preventDefault(); }
      if (e.key === "r" || e.key === "R") restart();
    });
    var pane = el("meshcat-pane"), resize = viewer.set_3d_pane_size.bind(viewer);
    viewer.set_3d_pane_size = function (w, h) {
      resize(w === undefined ? pane.offsetWidth : w, h === undefined ? pane.offsetHeight : h);
    };
    viewer.set_3d_pane_size();
    banner(C.note, C.note ? "note" : "");
  }

  setup();
  window.__pilot.reset(C.starts[0].controls);
  worker.postMessage({type: "init", config: C, model: el("model-wasm").textContent.trim(),
                      controller: C.controller ? el("controller-wasm").textContent.trim() : null});
  requestAnimationFrame(tick);

  window.__fly = {
    state: state, on: on,
    run: function () { send("run"); }, pause: function () { send("pause"); },
    until: function (t) { send("until", {t: t}); },
    scale: setScale,
    sas: function (mode) { el("sas").value = mode; send("sas", {mode: mode}); },
    start: start, reset: function () { el("reset").click(); },
    table: table,
    inputsCsv: function () { return ask("inputs"); },
    bench: function (steps) { return ask("bench", {steps: steps}); },
    history: function () { return ask("history"); }
  };
})();
