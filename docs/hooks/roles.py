"""Griffe extension for the API reference: the docstrings' Sphinx roles (``:func:`name```,
``:mod:`~pkg.mod```) shown as inline code, since the docstrings are read as Markdown."""
from __future__ import annotations

import re

import griffe

ROLE = re.compile(r":(?:mod|func|class|meth|attr|data|obj|exc|const):`~?([^`]+)`")


def _plain(match: re.Match) -> str:
    target = match.group(1)
    return f"`{target}`"


class SphinxRolesAsCode(griffe.Extension):
    """Rewrite each object's docstring once, when griffe has loaded it."""

    def on_instance(self, *, obj: griffe.Object, **kwargs) -> None:
        if obj.docstring is not None:
            obj.docstring.value = ROLE.sub(_plain, obj.docstring.value)
