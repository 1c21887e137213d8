"""The slave's entry points never raise: a refused value (:class:`BadValue`) or any other exception
is logged with status error, naming the FMI call (:func:`entry_point`)."""
from __future__ import annotations

import functools
import traceback


class BadValue(ValueError):
    """A value that the FMU refuses; the message names the variable and the value."""


def _fallback(value, args):
    return value(*args) if callable(value) else value


def entry_point(call: str, fallback=None):
    """Decorator of an FMI entry point: nothing escapes it. A refused value (BadValue) is
    logged with status error as ``"<call>: <message>"``, any other exception with its
    traceback; then ``fallback`` (or ``fallback(*args)`` if callable) is returned."""
    def wrap(fn):
        @functools.wraps(fn)
        def guarded(self, *args):
            try:
                if getattr(self, "_broken", None):
                    self._report(f"{call}: instance unusable: {self._broken}")
                    return _fallback(fallback, args)
                return fn(self, *args)
            except BadValue as exc:
                self._report(f"{call}: {exc}")
            except Exception as exc:
                self._report(f"{call} failed: {type(exc).__name__}: {exc}\n{traceback.format_exc()}")
            return _fallback(fallback, args)
        return guarded
    return wrap
