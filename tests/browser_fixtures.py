"""Headless Chromium (Debian's package, never a downloaded browser) driven by Playwright.

The fixtures ``browser`` (one for the session) and ``page`` are registered for every test module by
``tests/conftest.py`` (``pytest_plugins``); import the helpers (``open_viewer``, ``pixels``, ...).
Without Chromium or Playwright the tests skip with the reason, except when
``MBS_REQUIRE_BROWSER=1`` (set by ``.ci/run``): then they fail.
"""
from __future__ import annotations

import base64
import io
import os
import shutil

import numpy as np
import pytest

# WebGL through ANGLE on SwiftShader (software Vulkan): no GPU needed.
ARGS = ["--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader", "--use-angle=swiftshader",
        "--disable-quic", "--no-first-run", "--disable-background-networking", "--disable-component-update",
        "--disable-sync", "--disable-dev-shm-usage"]
VIEWPORT = {"width": 1000, "height": 640}

# Page helpers. mcNode walks the scene tree without creating nodes (scene_tree.find would).
# mcSeek(t): pause an exported page's player and show simulated time t (s).
HELPERS = """
window.mcNode = p => { let n = viewer.scene_tree;
  for (const s of p.split('/').filter(Boolean)) { n = n.children[s]; if (!n) return null; } return n; };
window.mcLocal = p => { const n = mcNode(p); if (!n) return null; n.object.updateMatrix();
  return Array.from(n.object.matrix.elements); };
window.mcSeek = t => { __player.pause(); __player.seek(t); viewer.render(); };
window.mcPixels = () => { viewer.render(); return viewer.renderer.domElement.toDataURL('image/png'); };
true;
"""


def chromium_path() -> str | None:
    """Debian's Chromium (or ``$MBS_CHROMIUM``), if installed."""
    candidate = os.environ.get("MBS_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
    return candidate if os.path.isfile(candidate) and os.access(candidate, os.X_OK) else None


def _unavailable(reason: str):
    if os.environ.get("MBS_REQUIRE_BROWSER") == "1":
        pytest.fail(f"browser tests are required (MBS_REQUIRE_BROWSER=1) but {reason}")
    pytest.skip(reason)


@pytest.fixture(scope="session")
def browser():
    executable = chromium_path()
    if executable is None:
        _unavailable("Chromium is not installed (Debian: apt-get install chromium)")
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        _unavailable("the playwright Python package is not installed (pip install -e '.[test]')")
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=executable, headless=True, args=ARGS, timeout=30000)
        yield b
        b.close()


@pytest.fixture
def page(browser):
    context = browser.new_context(viewport=VIEWPORT)
    pg = context.new_page()
    pg.set_default_timeout(20000)
    pg.errors = []
    pg.on("pageerror", lambda e: pg.errors.append(str(e)))
    yield pg
    context.close()


def open_viewer(page, url: str, ready: str = "window.__viewerReady === true"):
    """Load ``url``, wait (bounded) until ``ready`` holds, install the helpers."""
    page.goto(url)
    page.wait_for_function(ready, timeout=20000)
    page.evaluate(HELPERS)
    return page


def pixels(page) -> np.ndarray:
    """The canvas as RGB (h, w, 3) uint8, composited onto white."""
    from PIL import Image

    url = page.evaluate("mcPixels()")
    img = Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1]))).convert("RGBA")
    white = Image.new("RGBA", img.size, (255, 255, 255, 255))
    return np.asarray(Image.alpha_composite(white, img).convert("RGB"))


def count_color(rgb: np.ndarray, color: int, tol: int = 12) -> int:
    """Pixels within ``tol`` of ``color`` (0xrrggbb) in every channel."""
    target = np.array([(color >> 16) & 255, (color >> 8) & 255, color & 255])
    return int(np.all(np.abs(rgb.astype(int) - target) <= tol, axis=-1).sum())
