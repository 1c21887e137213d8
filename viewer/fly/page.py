"""The HTML text of a flight page: meshcat's viewer script and the scene's commands (as the
viewer's pages, :mod:`viewer.page`), the model and the controller as base64 WebAssembly, the
worker's source as text (started from a Blob: no file, no server), the configuration document,
and the page's own scripts (``web/controls.js``, ``web/charts.js``, ``web/fly.js``) and style,
all inline: one file that works from ``file://`` with no network.
"""
from __future__ import annotations

import base64
import json
from pathlib import Path

from viewer.page import head, scene_scripts

WEB = Path(__file__).with_name("web")


def asset(name: str) -> str:
    """A file of ``viewer/fly/web``, safe inside a ``<script>`` or ``<style>`` element."""
    text = (WEB / name).read_text(encoding="utf-8")
    if "</" in text:
        raise ValueError(f"{name} contains '</', which would end its script element")
    return text


def _b64(module: bytes | None) -> str:
    return base64.b64encode(module).decode("ascii") if module else ""


BARS = """<div class="bar" id="flight">
<label title="the start: a periodic trim computed when the page was written">start <select id="start"></select></label>
<label title="initial forward speed (m/s) at the start's attitude, as the FMU's initial_forward_speed; empty: the start's own">
speed <input id="speed" type="number" step="any" placeholder="trim"> m/s</label>
<button id="run" type="button" title="fly / pause (space bar)">&#9654; fly</button>
<button id="reset" type="button" title="back to the start (R)">&#10226; reset</button>
<button id="revolution" type="button" title="fly to the end of the present revolution and pause">+1 rev</button>
<label title="simulated seconds per second">time <select id="scale"></select></label>
<label>SAS <select id="sas"><option value="off">off</option><option value="attitude">attitude hold</option>
<option value="hover">hover hold</option></select></label>
<button id="record" type="button" title="download the inputs flown since the start as heli simulate's --inputs table">
&#11015; inputs CSV</button> <span id="rows"></span>
<label title="fly the inputs of a table (heli simulate's --inputs CSV) from its times; reset flies it again">fly a table
<input id="table-file" type="file" accept=".csv,text/csv"></label>
<button id="table-drop" type="button" title="the pilot's controls again instead of the table's">drop the table</button>
</div>
<div class="bar" id="pilot">
<button id="trim" type="button" title="the present stick and pedal positions become the trim (T)">trim release</button>
<div id="stick" title="cyclic stick: drag (arrow keys)"><div id="stick-dot"></div></div>
</div>
<div class="bar"><span id="gamepad"></span><span id="help"></span></div>"""


def html_page(packed: list[bytes], data: dict, model: bytes, controller: bytes | None, title: str) -> str:
    """The page: ``packed`` meshcat commands, ``data`` (``window.__flyData``), the WebAssembly
    ``model`` and ``controller`` (None: none)."""
    doc = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    setup = 'window.__flyData = JSON.parse(document.getElementById("fly-data").textContent);'
    return f"""{head(title, asset("fly.css"))}
<body>
<div id="app">
<div id="main">
<div id="view"><div id="meshcat-pane"></div><div id="banner"></div><div id="readout"></div><div id="status"></div></div>
<div id="side"><canvas id="charts"></canvas><div id="tpp-label">tip-path plane over the last revolution, blade tips in
body axes</div><canvas id="tpp"></canvas></div>
</div>
{BARS}
</div>
<script id="worker-source" type="text/plain">
{asset("worker.js")}
</script>
<script id="model-wasm" type="text/plain">{_b64(model)}</script>
<script id="controller-wasm" type="text/plain">{_b64(controller)}</script>
<script id="fly-data" type="application/json">{doc}</script>
{scene_scripts(packed, setup)}
<script>
{asset("controls.js")}
</script>
<script>
{asset("charts.js")}
</script>
<script>
{asset("fly.js")}
</script>
<script>
window.__flyReady = true;
</script>
</body>
</html>
"""
