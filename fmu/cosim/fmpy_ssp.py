"""fmpy's own SSP runner (``fmpy.ssp.simulation.simulate_ssp``, FMPy 0.3.x) on the closed loop's
``.ssp``, in a fresh process: what it does with the file, for the README and the tests.

It cannot run it, and no SSP 1.0 file could make it: it starts every connector at 0.0 and sets
each component's inputs from its connectors before the first step, without the initialised
FMUs' outputs and without the SSD's parameter bindings (it reads them but applies only a
ParameterSet passed as an argument, and of those no String), so the helicopter FMU gets
``collective = 0.0``, below its range, and answers fmi2Error, whereupon fmpy raises. SSP 1.0
gives connectors no start value: initial values come from the bindings (which may bind inputs,
as ours do) and from the connected outputs after initialisation, as libcosim applies them.
The work-around is a master loop that does so over fmpy itself, :func:`fmu.cosim.run_fmpy`.

``python -m fmu.cosim.fmpy_ssp SSP STOP STEP`` prints one JSON object: ``completed``, and otherwise
the exception fmpy raised and the helicopter FMU's message (from its stderr).
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path


def run(ssp_file: Path, stop: float, step: float, timeout: float = 600) -> dict:
    """fmpy's ``simulate_ssp`` of ``ssp_file`` to ``stop`` in steps of ``step`` (s), in a fresh process:
    ``{"completed": bool, "error": the exception's text, "refused": the FMUs' error messages}``."""
    proc = subprocess.run([sys.executable, "-m", "fmu.cosim.fmpy_ssp", str(ssp_file), repr(stop), repr(step)],
                          capture_output=True, text=True, timeout=timeout)
    if proc.returncode:
        raise RuntimeError(f"the fmpy SSP run's process failed:\n{proc.stderr[-3000:]}")
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    res["refused"] = [line.split(": ", 1)[1] for line in proc.stderr.splitlines() if ") error: " in line]
    return res


def main(argv: list[str] | None = None) -> int:
    from fmpy.ssp.simulation import simulate_ssp

    ssp_file, stop, step = (argv or sys.argv[1:])[:3]
    try:
        rows = simulate_ssp(ssp_file, stop_time=float(stop), step_size=float(step))
        out = {"completed": True, "rows": len(rows)}
    except Exception as exc:  # noqa: BLE001 (what fmpy raises is the result)
        out = {"completed": False, "error": f"{type(exc).__name__}: {exc}"}
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    from fmu.hosts import finish

    finish(main())
