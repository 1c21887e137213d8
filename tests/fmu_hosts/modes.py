"""Fresh-process runs of an FMU for the tests: ``python -m fmu_hosts.modes MODE ARGS_JSON`` runs one
of the ``MODES`` over :mod:`fmu.hosts` and prints one JSON line; ``"block": ["mbs", "casadi"]`` in the
arguments makes those packages unimportable first (the FMU must need none of them on the host)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

from fmu.hosts import Instance, call_status, finish, grid, inputs_at, run_fmpy, run_instance, run_libcosim


def _table(args: dict) -> np.ndarray:
    rows = args["table"]
    names = list(rows[0])
    table = np.zeros(len(rows), dtype=[(n, float) for n in names])
    for i, r in enumerate(rows):
        table[i] = tuple(r[n] for n in names)
    return table


def _mode_fmpy(a: dict) -> dict:
    res = run_fmpy(a["fmu"], a["stop"], a["dt"], _table(a), a.get("start_values"), a["names"], True)
    return {"time": res["time"][1:].tolist(), **{n: res[n][1:].tolist() for n in a["names"]}}


def _mode_fmpy_starts(a: dict) -> dict:
    """``fmpy.simulate_fmu`` with ``start_values``, and with ``apply_defaults`` every XML start value of
    the inputs and parameters written before them (fmpy's own ``apply_default_start_values`` is
    deprecated and does nothing): the ``names`` after every step."""
    from fmpy import read_model_description, simulate_fmu

    starts = {}
    if a["apply_defaults"]:
        starts = {v.name: v.start for v in read_model_description(a["fmu"]).modelVariables
                  if v.causality in ("input", "parameter") and v.start is not None}
    res = simulate_fmu(a["fmu"], stop_time=a["stop"], output_interval=a["dt"],
                       start_values={**starts, **a["start_values"]}, output=a["names"])
    return {"time": res["time"].tolist(), **{n: res[n].tolist() for n in a["names"]}}


def _mode_libcosim(a: dict) -> dict:
    return run_libcosim(a["fmu"], a["stop"], a["dt"], _table(a), a["names"])


def _mode_save(a: dict) -> dict:
    """Run to t1, save the serialised state to ``a['blob']``, continue to the end."""
    inst, times = Instance(a["fmu"]), grid(a["stop"], a["dt"])
    inst.initialise(reals=a.get("reals"))
    k1 = int(round(a["t1"] / a["dt"]))
    run_instance(inst, times[: k1 + 1], _table(a), a["names"])
    Path(a["blob"]).write_bytes(inst.save())
    return run_instance(inst, times, _table(a), a["names"], first=k1)


def _mode_restore(a: dict) -> dict:
    """A fresh instance, initialised with defaults, restores the blob and continues."""
    inst, times = Instance(a["fmu"]), grid(a["stop"], a["dt"])
    inst.initialise()
    inst.restore(Path(a["blob"]).read_bytes())
    return run_instance(inst, times, _table(a), a["names"], first=int(round(a["t1"] / a["dt"])))


def _mode_steps(a: dict) -> dict:
    """Explicit (possibly uneven) communication points ``a['times']``."""
    inst = Instance(a["fmu"])
    inst.initialise(reals=a.get("reals"))
    return run_instance(inst, a["times"], _table(a), a["names"])


def _mode_initial(a: dict) -> dict:
    """Values of ``a['names']`` right after initialisation with ``a['reals']``."""
    inst = Instance(a["fmu"])
    inst.initialise(reals=a.get("reals"), strings=a.get("strings"))
    return {"values": inst.get(a["names"])}


def _mode_two(a: dict) -> dict:
    """Two instances of one extracted FMU, stepped alternately with different inputs."""
    first = Instance(a["fmu"], "first")
    second = Instance(a["fmu"], "second", unzipdir=first.unzipdir)
    first.initialise()
    second.initialise()
    times, tables = grid(a["stop"], a["dt"]), [_table({"table": t}) for t in a["tables"]]
    out = [[], []]
    for k in range(len(times) - 1):
        for j, inst in enumerate((first, second)):
            inst.set(inputs_at(tables[j], times[k]))
            if inst.step(times[k], times[k + 1] - times[k]):
                raise RuntimeError(f"instance {j} failed: {inst.messages[-3:]}")
            out[j].append(inst.get(a["names"]))
    return {"time": times[1:], "runs": [{n: [r[i] for r in rows] for i, n in enumerate(a["names"])}
                                        for rows in out]}


def _bad_case(fmu: str, unzipdir: str, case: dict, dt: float) -> dict:
    """One bad-input case: initialise (``init``), one good step, then ``set`` (reals or
    strings) and a step of ``step`` seconds (default ``dt``); then ``fix`` and step again."""
    inst = Instance(fmu, case["name"], unzipdir=unzipdir)
    out = {"init_status": call_status(inst.initialise, 0.0, case.get("init"), case.get("init_strings"))}
    if out["init_status"]:
        return {**out, "messages": inst.messages}
    out["first_step"] = inst.step(0.0, dt)
    out["set_status"] = call_status(inst.set, case.get("set", {}), case.get("set_strings"))
    out["step_status"] = inst.step(dt, case.get("step", dt))
    if case.get("fix") is not None:
        inst.set(case["fix"])
        out["recovered_status"] = inst.step(dt, dt)
    out["messages"] = inst.messages
    return out


def _mode_errors(a: dict) -> dict:
    """Every bad-input case in its own instance of one extracted FMU."""
    from fmpy import extract

    unzipdir = extract(a["fmu"])
    return {c["name"]: _bad_case(a["fmu"], unzipdir, c, a["dt"]) for c in a["cases"]}


def _mode_broken(a: dict) -> dict:
    """A damaged FMU (``info.json`` overwritten): the exception must come with its traceback."""
    from fmpy import extract

    unzipdir = extract(a["fmu"])
    for info in Path(unzipdir, "resources", "heli_models").glob("*/info.json"):
        info.write_text("{ damaged")
    inst = Instance(a["fmu"], "broken", unzipdir=unzipdir)
    return {"init_status": call_status(inst.initialise), "messages": inst.messages}


MODES = {"fmpy": _mode_fmpy, "fmpy_starts": _mode_fmpy_starts, "libcosim": _mode_libcosim, "save": _mode_save,
         "restore": _mode_restore, "two": _mode_two, "errors": _mode_errors, "broken": _mode_broken,
         "steps": _mode_steps, "initial": _mode_initial}


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    mode, args = argv[0], json.loads(Path(argv[1]).read_text())
    for name in args.get("block", []):  # prove the FMU needs none of these on the host
        sys.modules[name] = None
    print(json.dumps(MODES[mode](args)))
    return 0


if __name__ == "__main__":
    finish(main())
