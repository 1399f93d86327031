#!/usr/bin/env python3
"""rigidref and Siconos side by side on the same problem files, in one run (issue 48 item 3).

    /usr/bin/python3 python/siconos_side_by_side.py FILES_OR_FOLDERS [--rigidref BIN]
        [--tolerance 1e-8] [--timeout 120] [--json OUT.json] > table.md

Needs Siconos' Python module (`import siconos.numerics`; Debian's python3-siconos is Siconos 4.4,
under /usr/bin/python3) and the rigidref binary (`target/release/rigidref` of this checkout by
default; built with `--features fclib` for `.hdf5` files). docs/problem-library.md §"Side by side
with Siconos" shows its table and says what is measured; python/tests/test_siconos_side_by_side.py
runs it on two small problems.

For every problem file, one after the other (so that the solvers of one problem run within
seconds of each other on the same machine):

1. `rigidref convert-problem FILE x.json` reads the problem into the local form (W, q, μ) and
   its warm start λ0 (an FCLIB file's first guess; zero for a `.dat` file). A file rigidref
   cannot read as a local problem (a global `.dat`, another problem kind) is skipped with a note.
2. `rigidref solve-problems FILE --solver newton --json` (rigidref's exact solver, the one the
   docs name for the library; `--rigidref-solver newton,newton-regularised,pgs-exact,auto` runs several, each timed
   alone, and compares the fastest that converged, as Siconos' fastest is taken on its side):
   converged or not, iterations, the wall time of the solve as rigidref reports it (reading the
   file excluded), Siconos' error of its answer.
3. Siconos' NSGS, NSN_AC and PROX (3D), or 2D NSGS (Siconos' Python module has no 2D Newton or
   proximal solver), each in its own child process with a wall-time cap (--timeout), started from
   the same λ0, tolerance --tolerance, at most --sweeps NSGS sweeps and --newton-iterations
   NSN_AC iterations (PROX: Siconos' defaults apart from the tolerance). The time is that of the
   `fc3d_driver` / `fc2d_driver` call alone. Siconos reads the file itself where it can (a `.dat`
   file); an `.hdf5` file, and a 2D `.dat` file in CSparse storage (which `fc2d_driver` refuses),
   are converted first by `rigidref convert-problem` to a sparse-block `.dat` (every number to
   the bit; the conversion is checked against Siconos' reader in the suite).
   An answer is judged by Siconos' own error function (`fc3d_compute_error`, or
   `fc2d_compute_error` through ctypes, with norm = ‖q‖ as its solvers call it), not by the
   solver's status: "converged" means that error is at or below --tolerance.

It prints a Markdown table: per problem its contacts, each solver's result (✓/✗, iterations,
time; PROX's iterations are outer / cumulative inner), Siconos' fastest converged solver, and
the ratio rigidref time ÷ that solver's time, "tie" where both are under 1 ms. With --profile it
also writes the performance profile of every solver, rigidref's and Siconos', as an SVG file. Files that cannot
be read are skipped with a note under the table; the exit status is 1 only when none could be.
"""
import argparse
import ctypes
import json
import math
import os
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
SOLVERS_3D = ["NSGS", "NSN_AC", "PROX"]
SOLVERS_2D = ["NSGS"]
SUFFIXES = (".dat", ".hdf5", ".json")
TIE_SECONDS = 1e-3


# rigidref's exact solvers this script may time (`rigidref solve-problems --solver`).
RIGIDREF_SOLVERS = ("newton", "newton-regularised", "pgs-exact", "auto", "newton-twins")


def siconos_solve(path, dim, solver, lambda0_path, tolerance, sweeps, newton_iterations):
    """Child process: one Siconos solve of `path`; returns a dict (printed as JSON)."""
    import numpy as np
    import siconos.numerics as sn

    problem = sn.frictionContact_new_from_filename(path)
    if problem.dimension != dim:
        raise SystemExit(f"{path}: Siconos reads dimension {problem.dimension}, rigidref {dim}")
    n = problem.dimension * problem.numberOfContacts
    reaction = np.zeros(n)
    if lambda0_path:
        reaction[:] = json.load(open(lambda0_path))
    velocity = np.zeros(n)
    ids = {
        (3, "NSGS"): sn.SICONOS_FRICTION_3D_NSGS,
        (3, "NSN_AC"): sn.SICONOS_FRICTION_3D_NSN_AC,
        (3, "PROX"): sn.SICONOS_FRICTION_3D_PROX,
        (2, "NSGS"): sn.SICONOS_FRICTION_2D_NSGS,
    }
    options = sn.SolverOptions(ids[(dim, solver)])
    options.dparam[sn.SICONOS_DPARAM_TOL] = tolerance
    if solver == "NSGS":
        options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = sweeps
    elif solver == "NSN_AC":
        options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = newton_iterations
    driver = sn.fc3d_driver if dim == 3 else sn.fc2d_driver
    start = time.perf_counter()
    info = driver(problem, reaction, velocity, options)
    seconds = time.perf_counter() - start
    norm_q = float(np.linalg.norm(np.array(problem.q)))
    if dim == 3:
        _, error = sn.fc3d_compute_error(problem, reaction.copy(), np.zeros(n), 1e-300, None, norm_q)
    else:
        lib = ctypes.CDLL("libsiconos_numerics.so.7")
        dp = ctypes.POINTER(ctypes.c_double)
        lib.fc2d_compute_error.restype = ctypes.c_int
        lib.fc2d_compute_error.argtypes = [ctypes.c_void_p, dp, dp, ctypes.c_double,
                                           ctypes.c_double, dp]
        e = ctypes.c_double()
        w = np.zeros(n)
        lib.fc2d_compute_error(int(problem.this), reaction.ctypes.data_as(dp),
                               w.ctypes.data_as(dp), 1e-300, norm_q, ctypes.byref(e))
        error = e.value
    iterations = str(options.iparam[sn.SICONOS_IPARAM_ITER_DONE])
    if solver == "PROX":
        cumulative = options.iparam[sn.SICONOS_FRICTION_3D_PROXIMAL_IPARAM_CUMULATIVE_ITER_DONE]
        iterations += f"/{cumulative}"
    return {"solver": solver, "info": int(info), "iterations": iterations,
            "seconds": seconds, "error": float(error),
            "converged": bool(math.isfinite(error) and error <= tolerance)}


def problem_files(inputs):
    files = []
    for name in inputs:
        p = pathlib.Path(name)
        if p.is_dir():
            files += sorted(f for f in p.iterdir() if f.suffix in SUFFIXES)
        else:
            files.append(p)
    return files


def run(command, timeout):
    return subprocess.run(command, capture_output=True, text=True, timeout=timeout)


def read_local(rigidref, path, scratch):
    """rigidref's local form of `path`: (dimension, contacts, λ0 as a list) or an error line."""
    out = scratch / "local.json"
    r = run([rigidref, "convert-problem", str(path), str(out)], 600)
    if r.returncode != 0:
        return None, (r.stderr.strip().splitlines() or ["unreadable"])[-1]
    local = json.load(open(out))
    dim = local["rows_per_contact"]
    lambda0 = [x for c in local["contacts"] for x in c.get("lambda0", [0.0] * dim)]
    return (dim, len(local["contacts"]), lambda0), None


def siconos_input(rigidref, path, dim, scratch):
    """The file Siconos reads: `path` itself where Siconos' reader and driver take it, else
    rigidref's sparse-block `.dat` conversion of it."""
    if path.suffix == ".dat":
        if dim == 3:
            return str(path), False
        tokens = path.read_text().split()
        # 2D: fc2d_driver takes dense (0) and sparse-block (1) storage, not CSparse (2).
        if len(tokens) > 2 and tokens[2] in ("0", "1"):
            return str(path), False
    out = scratch / (path.name + ".dat")
    r = run([rigidref, "convert-problem", str(path), str(out)], 600)
    if r.returncode != 0:
        raise RuntimeError(f"{path}: rigidref convert-problem failed: {r.stderr.strip()}")
    return str(out), True


def rigidref_solve(rigidref, path, tolerance, timeout, solvers=("newton",)):
    """rigidref's answers on one file, one dict per solver of `solvers` (one process: `--solver
    a,b,c`, each solver timed by rigidref alone)."""
    try:
        r = run([rigidref, "solve-problems", str(path), "--solver", ",".join(solvers), "--json",
                 "--quiet", "--tolerance", repr(tolerance)], timeout * len(solvers))
    except subprocess.TimeoutExpired:
        return {s: {"solver": s, "timeout": timeout * len(solvers)} for s in solvers}
    if r.returncode != 0:
        return {s: {"solver": s, "failed": r.stderr.strip()} for s in solvers}
    out = {}
    for attempt in json.loads(r.stdout)["problems"][0]["attempts"]:
        solver = attempt["solver"]
        iterations = str(attempt["iterations"])
        if solver == "auto":
            # The automatic choice's path: NSGS sweeps + Newton iterations.
            sweeps = attempt.get("sweeps", 0)
            iterations = f"{attempt.get('method')} {sweeps}+{attempt['iterations'] - sweeps}"
        elif attempt.get("left_out"):
            # newton-twins: the contacts its answer leaves out.
            iterations += " without " + ",".join(str(k) for k in attempt["left_out"])
        out[solver] = {"solver": solver, "iterations": iterations,
                       "seconds": attempt["seconds"], "error": attempt["error"],
                       "converged": attempt["converged"], "method": attempt.get("method")}
    return out


def fastest_of(attempts):
    """The converged attempt of least time, None where none converged."""
    converged = [a for a in attempts if a.get("converged")]
    return min(converged, key=lambda a: a["seconds"]) if converged else None


def siconos_attempt(script_args, timeout):
    try:
        r = run([sys.executable, str(pathlib.Path(__file__).resolve()), "--child"] + script_args,
                timeout)
    except subprocess.TimeoutExpired:
        return {"timeout": timeout}
    if r.returncode != 0:
        return {"failed": (r.stderr.strip().splitlines() or ["?"])[-1]}
    return json.loads(r.stdout)


def fmt_seconds(s):
    return f"{s:.2g} s"


def cell(a):
    if a is None:
        return "–"
    if "timeout" in a:
        return f"no answer in {a['timeout']:g} s"
    if "failed" in a:
        return f"failed: {a['failed']}"
    mark = "✓" if a["converged"] else f"✗ ({a['error']:.1e})"
    return f"{mark} {a['iterations']} / {fmt_seconds(a['seconds'])}"


def ratio_cell(ours, fastest):
    if fastest is None:
        return "Siconos: none converged"
    if not ours.get("converged"):
        return "rigidref: not converged"
    if ours["seconds"] < TIE_SECONDS and fastest["seconds"] < TIE_SECONDS:
        return "tie (< 1 ms)"
    return f"{ours['seconds'] / fastest['seconds']:.2g}"


PROFILE_COLOURS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2"]


def profile_curves(rows):
    """Dolan–Moré performance profile of every solver in `rows` (rigidref's each, Siconos' each):
    for each solver the sorted ratios t / t_best over the problems some solver solved (t_best the
    fastest converged time on that problem, any solver), infinity where it did not converge."""
    names, per_problem = [], []
    for row in rows:
        times = {}
        for solver, a in row.get("rigidref_solvers", {}).items():
            times[f"rigidref {solver}"] = a
        for solver, a in row["siconos"].items():
            times[f"Siconos {solver}"] = a
        for n in times:
            if n not in names:
                names.append(n)
        per_problem.append(times)
    curves = {n: [] for n in names}
    for times in per_problem:
        ok = [a["seconds"] for a in times.values() if a.get("converged")]
        if not ok:
            continue
        best = max(min(ok), 1e-12)
        for n in names:
            a = times.get(n)
            curves[n].append(a["seconds"] / best if a and a.get("converged") else math.inf)
    return {n: sorted(r) for n, r in curves.items()}, sum(
        1 for t in per_problem if any(a.get("converged") for a in t.values()))


def write_profile(rows, path):
    """The performance profile as an SVG file: ρ(τ), the fraction of the problems some solver
    solved that each solver solved within τ times the fastest time, τ on a log₂ axis."""
    curves, count = profile_curves(rows)
    finite = [r for rs in curves.values() for r in rs if math.isfinite(r)]
    top = max(1.0, math.ceil(math.log2(max(finite)))) if finite else 1.0
    w, h, left, bottom, right, top_margin = 720, 420, 60, 50, 190, 30
    pw, ph = w - left - right, h - bottom - top_margin
    x = lambda tau: left + pw * math.log2(tau) / top
    y = lambda rho: top_margin + ph * (1.0 - rho)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
           f'font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{left}" y="18">Performance profile, {count} problems (side by side with '
           f'Siconos)</text>',
           f'<line x1="{left}" y1="{y(0)}" x2="{left + pw}" y2="{y(0)}" stroke="black"/>',
           f'<line x1="{left}" y1="{y(0)}" x2="{left}" y2="{y(1)}" stroke="black"/>']
    for k in range(int(top) + 1):
        out.append(f'<text x="{x(2.0 ** k)}" y="{y(0) + 16}" text-anchor="middle">{2 ** k}</text>')
    for k in range(0, 11, 2):
        out.append(f'<text x="{left - 6}" y="{y(k / 10) + 4}" text-anchor="end">{k / 10:g}</text>')
    out.append(f'<text x="{left + pw / 2}" y="{h - 10}" text-anchor="middle">τ (time ÷ the '
               f'fastest solver\'s, log₂ axis)</text>')
    out.append(f'<text x="14" y="{top_margin + ph / 2}" transform="rotate(-90 14 '
               f'{top_margin + ph / 2})" text-anchor="middle">ρ(τ)</text>')
    for i, (name, ratios) in enumerate(curves.items()):
        colour = PROFILE_COLOURS[i % len(PROFILE_COLOURS)]
        dash = ' stroke-dasharray="5,3"' if name.startswith("Siconos") else ""
        points, solved = [(x(1.0), y(0.0))], 0
        for r in ratios:
            if not math.isfinite(r):
                break
            solved += 1
            px = x(max(r, 1.0))
            points += [(px, points[-1][1]), (px, y(solved / count))]
        points.append((x(2.0 ** top), points[-1][1]))
        d = " ".join(f"{px:.1f},{py:.1f}" for px, py in points)
        out.append(f'<polyline fill="none" stroke="{colour}" stroke-width="2"{dash} '
                   f'points="{d}"><title>{name}</title></polyline>')
        ly = top_margin + 18 * i + 10
        out.append(f'<line x1="{left + pw + 15}" y1="{ly}" x2="{left + pw + 40}" y2="{ly}" '
                   f'stroke="{colour}" stroke-width="2"{dash}/>')
        out.append(f'<text x="{left + pw + 45}" y="{ly + 4}">{name}</text>')
    out.append("</svg>")
    pathlib.Path(path).write_text("\n".join(out) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("inputs", nargs="+", help="problem files or folders of them")
    parser.add_argument("--rigidref-solver", default="newton",
                        help="rigidref's solvers, comma-separated, of newton (default), "
                             "newton-regularised (ε following ‖F‖), pgs-exact (NSGS) and auto "
                             "(NSGS, then Newton) and newton-twins (near-duplicate contacts left out); with several, the table has a "
                             "column each and the ratio is rigidref's fastest converged one ÷ "
                             "Siconos' fastest")
    parser.add_argument("--rigidref", default=os.environ.get(
        "RIGIDREF_BIN", str(ROOT / "target" / "release" / "rigidref")))
    parser.add_argument("--tolerance", type=float, default=1e-8)
    parser.add_argument("--sweeps", type=int, default=20000, help="Siconos NSGS sweeps at most")
    parser.add_argument("--newton-iterations", type=int, default=2000,
                        help="Siconos NSN_AC iterations at most")
    parser.add_argument("--timeout", type=float, default=120.0,
                        help="wall-time cap of each solve, s (rigidref's too)")
    parser.add_argument("--json", help="also write every result to this JSON file")
    parser.add_argument("--profile", help="also write the performance profile of every solver, "
                                          "rigidref's and Siconos', to this SVG file")
    args = parser.parse_args()
    ours_solvers = [x.strip() for x in args.rigidref_solver.split(",") if x.strip()]
    for x in ours_solvers:
        if x not in RIGIDREF_SOLVERS:
            parser.error(f"--rigidref-solver: unknown solver {x!r} ({', '.join(RIGIDREF_SOLVERS)})")
    if not ours_solvers or len(set(ours_solvers)) != len(ours_solvers):
        parser.error("--rigidref-solver: name each solver once")

    try:
        import siconos.numerics  # noqa: F401
    except ImportError as e:
        sys.exit(f"siconos_side_by_side: Siconos' Python module is not importable here ({e})")

    rows, notes = [], []
    for path in problem_files(args.inputs):
        with tempfile.TemporaryDirectory() as tmp:
            scratch = pathlib.Path(tmp)
            local, why = read_local(args.rigidref, path, scratch)
            if local is None:
                notes.append(f"{path.name}: skipped ({why})")
                continue
            dim, contacts, lambda0 = local
            print(f"{path.name} ({dim}D, {contacts} contacts)", file=sys.stderr, flush=True)
            ours_all = rigidref_solve(args.rigidref, path, args.tolerance, args.timeout,
                                      ours_solvers)
            ours = fastest_of(ours_all.values()) or ours_all.get(ours_solvers[0]) or {
                "solver": ours_solvers[0], "failed": "no answer"}
            try:
                source, converted = siconos_input(args.rigidref, path, dim, scratch)
            except RuntimeError as e:
                notes.append(f"{path.name}: skipped ({e})")
                continue
            lambda0_path = ""
            if any(x != 0.0 for x in lambda0):
                lambda0_path = str(scratch / "lambda0.json")
                json.dump(lambda0, open(lambda0_path, "w"))
            theirs = {}
            for solver in (SOLVERS_3D if dim == 3 else SOLVERS_2D):
                theirs[solver] = siconos_attempt(
                    [source, str(dim), solver, lambda0_path, repr(args.tolerance),
                     str(args.sweeps), str(args.newton_iterations)], args.timeout)
        fastest = fastest_of(theirs.values())
        rows.append({"problem": path.name, "dimension": dim, "contacts": contacts,
                     "warm_start": bool(lambda0_path), "siconos_reads_conversion": converted,
                     "rigidref": ours, "rigidref_solvers": ours_all, "siconos": theirs,
                     "fastest": fastest["solver"] if fastest else None,
                     "ratio": ratio_cell(ours, fastest)})

    several = len(ours_solvers) > 1
    ours_head = "".join(f" rigidref {x} |" for x in ours_solvers)
    if several:
        ours_head += " rigidref fastest |"
    print(f"| problem | contacts |{ours_head} Siconos NSGS | Siconos NSN_AC | Siconos PROX "
          f"| Siconos fastest | rigidref ÷ fastest |")
    print("|---|---:|" + "---|" * (len(ours_solvers) + several) + "---|---|---|---|---:|")
    for row in rows:
        s = row["siconos"]
        name = row["problem"] + (" (2D)" if row["dimension"] == 2 else "")
        na = "no 2D solver" if row["dimension"] == 2 else "–"
        ours_cells = "".join(f" {cell(row['rigidref_solvers'].get(x))} |" for x in ours_solvers)
        if several:
            ours_cells += f" {row['rigidref']['solver'] if row['rigidref'].get('converged') else '–'} |"
        print(f"| {name} | {row['contacts']} |{ours_cells} {cell(s.get('NSGS'))} "
              f"| {cell(s['NSN_AC']) if 'NSN_AC' in s else na} "
              f"| {cell(s['PROX']) if 'PROX' in s else na} "
              f"| {row['fastest'] or '–'} | {row['ratio']} |")
    solved = sum(1 for r in rows if r["rigidref"].get("converged"))
    any_siconos = sum(1 for r in rows if r["fastest"])
    print(f"\n{len(rows)} problems; rigidref ({args.rigidref_solver}) solved {solved}, Siconos (any solver) "
          f"{any_siconos}; tolerance {args.tolerance:g} in Siconos' error measure.")
    for n in notes:
        print(f"- {n}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"tolerance": args.tolerance, "problems": rows, "skipped": notes}, f,
                      indent=1)
    if args.profile and rows:
        write_profile(rows, args.profile)
    if not rows:
        sys.exit("siconos_side_by_side: no problem could be read (see the notes above)")


def child():
    path, dim, solver, lambda0_path, tolerance, sweeps, newton_iterations = sys.argv[2:9]
    result = siconos_solve(path, int(dim), solver, lambda0_path, float(tolerance), int(sweeps),
                           int(newton_iterations))
    print(json.dumps(result))


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        child()
    else:
        main()
