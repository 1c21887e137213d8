"""``heli fmu linearize`` (A, B, C, D of any FMU with directional derivatives) and ``heli bench
fmu-me`` (the native FMU's model exchange and exact Jacobian against differences)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from mbs import arguments as A
from mbs.cli import add_json, emit


def start_value(text: str) -> tuple[str, object]:
    """Argument type of ``--set NAME=VALUE``: a number, or else the text (a String parameter)."""
    name, eq, value = text.partition("=")
    if not eq or not name.strip() or not value.strip():
        raise A.Bad(f"{text!r} is not NAME=VALUE")
    try:
        return name.strip(), float(value)
    except ValueError:
        return name.strip(), value.strip()


def fmu_file(text: str) -> Path:
    """Argument type: an FMU, i.e. a zip archive with a ``modelDescription.xml``."""
    import zipfile

    path = Path(text).expanduser()
    if path.is_dir():
        raise A.Bad(f"{text} is a folder; give an .fmu file ('heli fmu build --native' makes one)")
    if not path.is_file():
        raise A.Bad(f"{text}: no such FMU file ('heli fmu build --native' makes one)")
    try:
        with zipfile.ZipFile(path) as z:
            z.getinfo("modelDescription.xml")
    except (zipfile.BadZipFile, OSError) as exc:
        raise A.Bad(f"{text} is not an FMU: an FMU is a zip archive, and this file is not one "
                    f"({getattr(exc, 'strerror', None) or exc}); give an .fmu file") from None
    except KeyError:
        raise A.Bad(f"{text} is a zip archive without a modelDescription.xml, so not an FMU; give an .fmu file") \
            from None
    return path


def cmd_linearize(args) -> int:
    from fmu.linearize import linearize

    settings = dict(args.set or [])
    if len(settings) != len(args.set or []):
        raise ValueError("--set names a variable more than once; give each name once")
    lin = linearize(args.fmu, settings, time=args.time, interface=args.interface)
    res = {"fmu": str(args.fmu), "fmi_version": lin.fmi_version, "interface": lin.interface, "time_s": lin.time,
           "states": lin.states, "inputs": lin.inputs, "outputs": lin.outputs, "x": lin.x, "u": lin.u,
           "A": lin.A, "B": lin.B, "C": lin.C, "D": lin.D, "directional_derivative_calls": lin.calls}
    lines = [f"{args.fmu.name}: FMI {lin.fmi_version} {lin.interface} at t = {lin.time:g} s, {lin.calls} "
             f"directional derivatives: A {lin.A.shape[0]}x{lin.A.shape[1]}, B {lin.B.shape[0]}x{lin.B.shape[1]}, "
             f"C {lin.C.shape[0]}x{lin.C.shape[1]}, D {lin.D.shape[0]}x{lin.D.shape[1]}"]
    if lin.A.size:
        lam = np.linalg.eigvals(lin.A)
        lines.append("eigenvalues of A, largest |λ| first: " + ", ".join(
            f"{z.real:.4g}{z.imag:+.4g}i" for z in lam[np.argsort(-np.abs(lam))][:6]))
    if args.out:
        _write(args.out, lin)
        lines.append(f"wrote {args.out}")
        res["file"] = str(args.out)
    emit(res, args.json, lines)
    return 0


def _write(path: Path, lin) -> None:
    from mbs.analysis.derivatives import write_matrix_file

    write_matrix_file(path, {"A": lin.A, "B": lin.B, "C": lin.C, "D": lin.D, "x": lin.x, "u": lin.u,
                             "states": np.array(lin.states, dtype=object), "inputs": np.array(lin.inputs, dtype=object),
                             "outputs": np.array(lin.outputs, dtype=object)})


def cmd_bench_me(args) -> int:
    from fmu.bench import derivatives

    r = derivatives.run(args.revs, args.repeats)
    j, s = r["jacobian"], r["simulation"]
    lines = [f"{r['scene']}, native FMI 2.0 FMU in fmpy (this process)",
             f"  Jacobian {j['shape'][0]}x{j['shape'][1]} (median of the repeats):",
             f"    directional derivatives ({j['evaluations']['directional']} calls)  {j['directional_ms']:.2f} ms, exact",
             f"    forward differences ({j['evaluations']['forward']} evaluations)  {j['forward_ms']:.2f} ms, "
             f"error {j['forward_error']:.1e} of the largest entry",
             f"    central differences ({j['evaluations']['central']} evaluations)  {j['central_ms']:.2f} ms, "
             f"error {j['central_error']:.1e}",
             f"  {s['revs']:g} revolutions under fmpy (median wall time):",
             f"    ME, CVode (rtol {s['cvode_rtol']:g}): {s['me_wall_s']:.3f} s, {s['cvode_steps']} steps, "
             f"{s['cvode_rhs']} right-hand sides",
             f"    CS, RK4 1/100 rev: {s['cs_wall_s']:.3f} s, {s['cs_steps']} steps ({s['cs_rhs']} right-hand sides)",
             f"    largest flap difference ME vs CS: {s['largest_flap_difference_rad']:.1e} rad"]
    emit(r, args.json, lines)
    return 0


def register(fsub, bench) -> None:
    p = fsub.add_parser("linearize", help="A, B, C, D of an FMU from its directional derivatives (FMI 2.0 or 3.0; "
                        "model exchange, or D only for co-simulation)")
    p.add_argument("fmu", type=fmu_file, help="the .fmu file")
    p.add_argument("--set", action="append", type=start_value, metavar="NAME=VALUE",
                   help="start value of a parameter or input before initialisation (e.g. scene=hover); repeatable")
    p.add_argument("--time", type=A.finite, default=None, help="time of the point, s (default the start time)")
    p.add_argument("--interface", choices=["ModelExchange", "CoSimulation"], default=None,
                   help="default: model exchange when the FMU has it")
    p.add_argument("--out", type=A.output_file(".npz", ".mat"), default=None,
                   help="write the matrices and names (.npz or .mat)")
    add_json(p)
    p.set_defaults(fn=cmd_linearize)

    p = bench.add_parser("fmu-me", help="native FMU: Jacobian by directional derivatives against differences; "
                         "CVode model exchange against co-simulation")
    p.add_argument("--revs", type=A.positive, default=5.0, help="revolutions per run (default 5)")
    p.add_argument("--repeats", type=A.positive_int, default=5, help="runs per kind (median; default 5)")
    add_json(p)
    p.set_defaults(fn=cmd_bench_me)
