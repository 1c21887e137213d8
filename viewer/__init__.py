"""Browser viewer of the rotor tree (meshcat): animated, self-contained HTML and a live mode.

Public API::

    from viewer import build_scene, motion, export_html, LiveViewer
    export_html(sim_or_results_folder, "viewer.html")          # one offline HTML file
    with LiveViewer(system) as live:                            # meshcat server on 127.0.0.1
        live.show(x, t)                                         # stream a pose

See ``docs/viewer.md``.
"""
from __future__ import annotations

from viewer.motion import Motion, Recording, as_recording, from_results, from_simulation, motion
from viewer.scene import Scene, build_scene


def export_html(source, path, **options):
    """Write one self-contained HTML animation; see :func:`viewer.export.export_html`."""
    from viewer.export import export_html as _export

    return _export(source, path, **options)


def __getattr__(name):
    if name == "LiveViewer":
        from viewer.live import LiveViewer

        return LiveViewer
    raise AttributeError(name)


__all__ = ["LiveViewer", "Motion", "Recording", "Scene", "as_recording", "build_scene", "export_html",
           "from_results", "from_simulation", "motion"]
