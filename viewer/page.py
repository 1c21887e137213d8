"""The HTML text of an exported page: meshcat's viewer script, the scene commands (base64
msgpack, run synchronously on load), the data document, and the page's own scripts
(``web/player.js``, ``web/plot.js``) and style (``web/page.css``), all inline: one file,
no server, no network.

Layout: the 3D view with the plot beside it (below it on narrow windows), and a bar of
controls underneath: play/pause, time slider, readout (time, revolutions, main-rotor
azimuth), playback speed and the follow-fuselage camera.
"""
from __future__ import annotations

import base64
import html
import json
from pathlib import Path

WEB = Path(__file__).with_name("web")


def asset(name: str) -> str:
    """A file of ``viewer/web`` (script or style), safe to inline in a ``<script>`` or ``<style>``."""
    return (WEB / name).read_text(encoding="utf-8").replace("</", "<\\/")


def viewer_script() -> str:
    """meshcat's bundled viewer (three.js r132 and helpers), minified."""
    from viewer.scene import meshcat

    text = (Path(meshcat().viewer_assets_path()) / "dist" / "main.min.js").read_text(encoding="utf-8")
    return text.replace("</script", "<\\/script")


def notice() -> str:
    """Names and licences of the inlined third-party code (from meshcat's licence list)."""
    from viewer.scene import meshcat

    listing = Path(meshcat().viewer_assets_path()) / "dist" / "main.min.js.THIRD_PARTY_LICENSES.json"
    try:
        items = json.loads(listing.read_text())
        names = ", ".join(f"{i['name']} {i['version']} ({i['license']})" for i in items)
    except (OSError, ValueError, KeyError):
        names = "three.js and helpers"
    return (f"Contains the MeshCat viewer of meshcat-python 0.3.2 (MIT licence), bundling {names}; "
            "the licence texts ship with the meshcat Python package (viewer/dist).")


CONTROLS = """<div id="controls">
<button id="play" type="button" title="play / pause (space bar)">play</button>
<input id="time" type="range" step="any" aria-label="time (s)" title="time (arrow keys: one key back or on)">
<span id="readout"></span>
<label>speed <select id="speed" title="playback speed relative to real time"></select></label>
<label id="follow-label" title="keep the fuselage at the centre of the view">
<input id="follow" type="checkbox"> follow fuselage</label>
</div>"""


def head(title: str, style: str) -> str:
    """The page's start up to its body: the title, the inlined code's notice, the ``style`` sheet."""
    return f"""<!DOCTYPE html>
<html>
<head>
<meta charset="utf-8">
<title>{html.escape(title)}</title>
<!-- {html.escape(notice()).replace("--", "- -")} -->
<style>
{style}
</style>
</head>"""


def scene_scripts(packed: list[bytes], setup: str) -> str:
    """meshcat's viewer script, then the script that makes ``viewer`` in ``#meshcat-pane``, runs
    ``setup`` (JavaScript) and the ``packed`` scene commands, synchronously."""
    cmds = ",\n".join(json.dumps(base64.b64encode(b).decode("ascii")) for b in packed)
    return f"""<script>
{viewer_script()}
</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
{setup}
(function () {{
  var commands = [
{cmds}
  ];
  for (var i = 0; i < commands.length; i++) {{
    var text = atob(commands[i]);
    var bytes = new Uint8Array(text.length);
    for (var j = 0; j < text.length; j++) bytes[j] = text.charCodeAt(j);
    viewer.handle_command_bytearray(bytes);
  }}
}})();
</script>"""


def html_page(packed: list[bytes], info: dict, doc: dict, title: str, label: str) -> str:
    """The page: ``packed`` meshcat commands, ``info`` (``window.__viewerInfo``), ``doc`` the
    data document (``window.__viewerData``, see :mod:`viewer.pack`)."""
    data = json.dumps(doc, separators=(",", ":")).replace("</", "<\\/")
    setup = (f"window.__viewerInfo = {json.dumps(info)};\n"
             'window.__viewerData = JSON.parse(document.getElementById("viewer-data").textContent);')
    return f"""{head(title, asset("page.css"))}
<body>
<div id="app">
<div id="main">
<div id="view"><div id="meshcat-pane"></div><div id="viewer-label">{html.escape(label)}</div></div>
<div id="side"><svg id="plot" role="img" aria-label="hinge angles and inputs against time"></svg></div>
</div>
{CONTROLS}
</div>
<script id="viewer-data" type="application/json">{data}</script>
{scene_scripts(packed, setup)}
<script>
{asset("player.js")}
</script>
<script>
{asset("plot.js")}
</script>
<script>
window.__player.start();
window.__viewerReady = true;
</script>
</body>
</html>
"""
