"""The slave's FMU state (``fmi2GetFMUstate`` ... ``fmi2DeSerializeFMUstate``): its format tag, its
bytes (JSON), and the check that a state handed back is one of this FMU's."""
from __future__ import annotations

import json

STATE_FORMAT = "heli-fmu-state-1"


def state_problem(state) -> str | None:
    """Why ``state`` is not a state of this FMU (None when it is one)."""
    if not isinstance(state, dict):
        return f"expected a dict, got {type(state).__name__}"
    if state.get("format") != STATE_FORMAT:
        reason = state.get("error") or f"format {state.get('format')!r}"
        return f"{reason} (expected format {STATE_FORMAT!r})"
    kinds = {"phase": str, "start_time": (int, float), "t": (int, float), "settings": dict, "errors": dict,
             "frozen": dict, "x": (list, type(None)), "comp": (list, type(None))}
    wrong = [k for k, kind in kinds.items() if not isinstance(state.get(k), kind)]
    if wrong:
        return f"missing or malformed entries {wrong}"
    if (state["x"] is None) != (state["comp"] is None) or len(state["x"] or []) != len(state["comp"] or []):
        return "the state x and its compensation differ in length"
    return None


def to_bytes(state) -> bytes:
    """The serialised FMU state (JSON); never raises."""
    try:
        return json.dumps(state).encode("utf-8")
    except Exception as exc:
        return json.dumps({"format": "invalid", "error": f"state not serialisable: {exc}"}).encode("utf-8")


def from_bytes(state: bytes):
    """The FMU state from its bytes; a corrupt blob gives a marker that the slave's
    ``_set_fmu_state`` refuses with a message (this is called without an instance, so it cannot log)."""
    try:
        value = json.loads(bytes(state).decode("utf-8"))
    except Exception as exc:
        return {"format": "corrupt", "error": f"the serialised state cannot be decoded ({type(exc).__name__}: "
                                              f"{str(exc)[:200]})"}
    return value if isinstance(value, dict) else {"format": "corrupt", "error": "the serialised state is "
                                                  f"a JSON {type(value).__name__}, not an object"}
