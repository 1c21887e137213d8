/* The pilot's controls of the flight page: keyboard, on-screen sliders and cyclic stick, and a
   gamepad through the browser's Gamepad API.

   Each input (collective, cyclics, pedals: the model's pitch inputs in rad) is its trim (where
   the control rests) plus a deflection. The cyclic and the pedals spring back to their trim
   when let go (keys released, stick or gamepad centred); "trim release" makes the present
   deflection the new trim, as a force-trim release does. The collective stays where it is put.
   A slider sets its input's trim. Keys: W/S collective up/down, arrows cyclic (up: stick
   forward, nose down), A/D pedals (left/right), T trim release. A cyclic or pedal deflects at most
   config.stick_reach of its input's range from the trim. Gamepad (standard mapping):
   right stick cyclic, left stick sideways pedals and up/down collective, button A trim release.

   window.__pilot: values() (rad, in the order of config.inputs), update(dt) once a frame (the
   keys' and the gamepad's deflections, dt in s), reset(trims), release(), set(i, value),
   gamepad() (the connected gamepad's id or null). */
(function () {
  "use strict";
  var D = window.__flyData.config, inputs = D.inputs, n = inputs.length;
  var trim = inputs.map(function () { return 0; }), deflection = inputs.map(function () { return 0; });
  var stick = inputs.map(function () { return 0; }), keys = {}, pad = null, padButton = false;
  var DEFLECT_S = 0.6, COLLECTIVE_S = 4.0, DEAD = 0.08;
  var role = {};
  inputs.forEach(function (q, i) { if (q.role) role[q.role] = i; });
  var BINDINGS = [
    {role: "collective", up: ["w", "W", "PageUp"], down: ["s", "S", "PageDown"], spring: false},
    {role: "longitudinal", up: ["ArrowUp"], down: ["ArrowDown"], spring: true},
    {role: "lateral", up: ["ArrowRight"], down: ["ArrowLeft"], spring: true},
    {role: "pedals", up: ["d", "D"], down: ["a", "A"], spring: true}
  ];

  function clamp(v, lo, hi) { return Math.min(Math.max(v, lo), hi); }
  function span(i) { return inputs[i].high - inputs[i].low; }
  /* Largest deflection from the trim: a part of the input's range (config.stick_reach). */
  function reach(i) { return D.stick_reach * span(i); }

  function values() {
    return trim.map(function (v, i) { return clamp(v + deflection[i] + stick[i], inputs[i].low, inputs[i].high); });
  }

  function reset(trims) {
    trim = trims.slice();
    deflection = inputs.map(function () { return 0; });
    stick = inputs.map(function () { return 0; });
    show();
  }

  function release() {
    var v = values();
    trim = v;
    deflection = inputs.map(function () { return 0; });
    stick = inputs.map(function () { return 0; });
    show();
  }

  function set(i, value) {
    trim[i] = clamp(value, inputs[i].low, inputs[i].high);
    deflection[i] = 0;
    stick[i] = 0;
    show();
  }

  function pressed(list) { return list.some(function (k) { return keys[k]; }); }

  /* Move toward `goal` by at most `rate * dt`. */
  function toward(v, goal, step) { return v < goal ? Math.min(v + step, goal) : Math.max(v - step, goal); }

  function keyboard(dt) {
    BINDINGS.forEach(function (b) {
      var i = role[b.role];
      if (i === undefined) return;
      var dir = (pressed(b.up) ? 1 : 0) - (pressed(b.down) ? 1 : 0), sign = inputs[i].sign || 1;
      if (!b.spring) {
        if (dir) trim[i] = clamp(trim[i] + sign * dir * span(i) / COLLECTIVE_S * dt, inputs[i].low, inputs[i].high);
        return;
      }
      deflection[i] = toward(deflection[i], sign * dir * reach(i), reach(i) / DEFLECT_S * dt);
    });
  }

  function axis(v) { return Math.abs(v) < DEAD ? 0 : (v - Math.sign(v) * DEAD) / (1 - DEAD); }

  function gamepad(dt) {
    var all = navigator.getGamepads ? navigator.getGamepads() : [], g = null;
    for (var k = 0; all && k < all.length; k++) if (all[k] && all[k].connected !== false) { g = all[k]; break; }
    pad = g ? g.id : null;
    if (!g || !g.axes || g.axes.length < 4) return;
    var a = g.axes.map(axis), deflect = {lateral: a[2], longitudinal: -a[3], pedals: a[0]};
    Object.keys(deflect).forEach(function (r) {
      var i = role[r];
      if (i !== undefined) stick[i] = (inputs[i].sign || 1) * deflect[r] * reach(i);
    });
    var c = role.collective;
    if (c !== undefined && a[1]) trim[c] = clamp(trim[c] - (inputs[c].sign || 1) * a[1] * span(c) / COLLECTIVE_S * dt,
                                               inputs[c].low, inputs[c].high);
    var b = g.buttons && g.buttons[0] && (g.buttons[0].pressed || g.buttons[0].value > 0.5);
    if (b && !padButton) release();
    padButton = !!b;
  }

  function update(dt) {
    keyboard(dt);
    gamepad(dt);
    show();
  }

  /* -- on screen --------------------------------------------------------------------------------- */
  var sliders = [], outputs = [], dragging = -1;

  function degrees(v) { return (v * 180 / Math.PI).toFixed(2) + "\u00b0"; }

  function show() {
    var v = values();
    sliders.forEach(function (s, i) { if (i !== dragging) s.value = String(v[i]); outputs[i].textContent = degrees(v[i]); });
    var dot = document.getElementById("stick-dot"), lat = role.lateral, lon = role.longitudinal;
    if (dot && lat !== undefined && lon !== undefined) {
      var x = (deflection[lat] + stick[lat]) / reach(lat) * (inputs[lat].sign || 1);
      var y = (deflection[lon] + stick[lon]) / reach(lon) * (inputs[lon].sign || 1);
      dot.style.left = (50 + 45 * clamp(x, -1, 1)) + "%";
      dot.style.top = (50 - 45 * clamp(y, -1, 1)) + "%";
    }
  }

  function build() {
    var box = document.getElementById("pilot");
    inputs.forEach(function (q, i) {
      var label = document.createElement("label"), s = document.createElement("input"), o = document.createElement("output");
      label.className = "pilot";
      label.title = q.name + " (rad; shown in degrees)" + (q.keys ? ": " + q.keys : "");
      s.type = "range"; s.min = String(q.low); s.max = String(q.high); s.step = "any"; s.id = "input-" + q.name;
      s.setAttribute("aria-label", q.name);
      s.addEventListener("input", function () { dragging = i; set(i, parseFloat(s.value)); });
      s.addEventListener("change", function () { dragging = -1; show(); });
      label.appendChild(document.createTextNode(q.label + " "));
      label.appendChild(o);
      label.appendChild(s);
      box.appendChild(label);
      sliders.push(s); outputs.push(o);
    });
    stickPad();
  }

  function stickPad() {
    var el = document.getElementById("stick"), lat = role.lateral, lon = role.longitudinal;
    if (!el) return;
    if (lat === undefined || lon === undefined) { el.style.display = "none"; return; }
    var move = function (e) {
      var r = el.getBoundingClientRect();
      var x = clamp((e.clientX - r.left) / r.width * 2 - 1, -1, 1), y = clamp(1 - (e.clientY - r.top) / r.height * 2, -1, 1);
      stick[lat] = (inputs[lat].sign || 1) * x * reach(lat);
      stick[lon] = (inputs[lon].sign || 1) * y * reach(lon);
      show();
    };
    el.addEventListener("pointerdown", function (e) { el.setPointerCapture(e.pointerId); move(e); });
    el.addEventListener("pointermove", function (e) { if (el.hasPointerCapture(e.pointerId)) move(e); });
    el.addEventListener("pointerup", function () { stick[lat] = 0; stick[lon] = 0; show(); });
  }

  document.addEventListener("keydown", function (e) {
    if (/^(INPUT|SELECT|TEXTAREA)$/.test(e.target.tagName) && e.target.type !== "range") return;
    if (e.key === "t" || e.key === "T") { release(); return; }
    if (BINDINGS.some(function (b) { return b.up.indexOf(e.key) >= 0 || b.down.indexOf(e.key) >= 0; })) {
      keys[e.key] = true;
      e.preventDefault();
    }
  });
  document.addEventListener("keyup", function (e) { keys[e.key] = false; });
  window.addEventListener("blur", function () { keys = {}; });

  build();
  window.__pilot = {values: values, update: update, reset: reset, release: release, set: set,
                    gamepad: function () { return pad; },
                    state: function () { return {trim: trim.slice(), deflection: deflection.slice(), stick: stick.slice()}; }};
})();
