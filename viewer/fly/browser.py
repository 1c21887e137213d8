"""Debian's Chromium for ``heli bench fly`` (never a downloaded browser), with the flags the
browser tests use: WebGL through ANGLE on SwiftShader, no GPU, no network services."""
from __future__ import annotations

import os
import shutil

ARGS = ["--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader", "--use-angle=swiftshader",
        "--disable-quic", "--no-first-run", "--disable-background-networking", "--disable-component-update",
        "--disable-sync", "--disable-dev-shm-usage"]


def chromium() -> str:
    """Debian's Chromium (or ``$MBS_CHROMIUM``); RuntimeError saying how to install it."""
    candidate = os.environ.get("MBS_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
    if not (os.path.isfile(candidate) and os.access(candidate, os.X_OK)):
        raise RuntimeError("this benchmark runs the page in Chromium, which is not installed "
                           "(Debian: apt-get install chromium)")
    return candidate
