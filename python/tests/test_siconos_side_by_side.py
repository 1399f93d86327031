"""python/siconos_side_by_side.py: rigidref and Siconos' NSGS, NSN_AC and PROX on the same files
in one run (docs/problem-library.md §"Side by side with Siconos").

The script runs under an interpreter where `import siconos.numerics` works: $SICONOS_PYTHON if
set, else this one, else /usr/bin/python3 (Debian's python3-siconos lives there while pytest runs
in a venv). Skipped, with the reason printed, where none imports Siconos. The rigidref binary as in
test_rigidref_trace.py ($RIGIDREF_BIN, else target/release/rigidref)."""

import json
import os
import re
import pathlib
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "python" / "siconos_side_by_side.py"
# Two small problems of Siconos' test data kept in the repository: Rover1039 (4 contacts, W not
# symmetric) and the 4-contact Confeti problem (one contact carries 387 N·s).
FILES = [ROOT / "tests/data/siconos/Rover1039.dat",
         ROOT / "tests/data/siconos/Confeti-ex13-4contact-Fc3D-SBM.dat"]
TOLERANCE = 1e-8


def siconos_python():
    if "SICONOS_PYTHON" in os.environ:
        candidates = [os.environ["SICONOS_PYTHON"]]
    else:
        candidates = [sys.executable, "/usr/bin/python3"]
    why = []
    for python in candidates:
        try:
            r = subprocess.run([python, "-c", "import siconos.numerics"], capture_output=True,
                               text=True)
        except OSError as e:
            why.append(f"{python}: {e}")
            continue
        if r.returncode == 0:
            return python
        why.append(f"{python}: {(r.stderr.strip().splitlines() or ['?'])[-1]}")
    reason = ("Siconos' Python module is not importable (" + "; ".join(why) + "); set "
              "SICONOS_PYTHON to an interpreter that has it (Debian: apt-get install python3-siconos)")
    print(reason)
    pytest.skip(reason)


def rigidref_bin():
    path = pathlib.Path(os.environ.get("RIGIDREF_BIN", ROOT / "target" / "release" / "rigidref"))
    if not path.is_file():
        pytest.fail(f"{path} is missing: run `cargo build --release` (or cargo test --release) first")
    return path


def test_the_side_by_side_table_has_every_solver_and_every_converged_answer_meets_the_tolerance(
        tmp_path):
    python = siconos_python()
    out = tmp_path / "results.json"
    r = subprocess.run([python, str(SCRIPT), *map(str, FILES), "--rigidref", str(rigidref_bin()),
                        "--tolerance", repr(TOLERANCE), "--timeout", "60", "--json", str(out)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    print(r.stdout)
    lines = r.stdout.splitlines()
    header = [c.strip() for c in lines[0].strip("|").split("|")]
    assert header == ["problem", "contacts", "rigidref newton", "Siconos NSGS", "Siconos NSN_AC",
                      "Siconos PROX", "Siconos fastest", "rigidref ÷ fastest"], header
    rows = [line for line in lines[2:] if line.startswith("| ")]
    assert [row.split("|")[1].strip() for row in rows] == [f.name for f in FILES], rows
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert len(cells) == len(header), row
        # Every solver gave an answer (✓ or ✗, iterations / time), none timed out or failed.
        assert all(c[0] in "✓✗" and " / " in c for c in cells[2:6]), row

    results = json.load(open(out))
    assert [p["problem"] for p in results["problems"]] == [f.name for f in FILES]
    for p in results["problems"]:
        answers = [p["rigidref"]] + [p["siconos"][s] for s in ("NSGS", "NSN_AC", "PROX")]
        for a in answers:
            # The error is Siconos' own (fc3d_compute_error for Siconos' answers; rigidref's
            # siconos_error, checked against Siconos in the Rust suite, for rigidref's).
            assert a["converged"] == (a["error"] <= TOLERANCE), (p["problem"], a)
            assert a["seconds"] >= 0.0
        # These two small problems are solved by all four (docs/problem-library.md's table).
        assert all(a["converged"] for a in answers), p
        assert p["fastest"] in ("NSGS", "NSN_AC", "PROX")
        fastest = p["siconos"][p["fastest"]]["seconds"]
        assert all(fastest <= p["siconos"][s]["seconds"] for s in ("NSGS", "NSN_AC", "PROX"))


def test_several_rigidref_solvers_get_a_column_each_and_the_ratio_is_their_fastest_converged(
        tmp_path):
    python = siconos_python()
    out = tmp_path / "results.json"
    svg = tmp_path / "profile.svg"
    ours = ["newton", "pgs-exact", "auto"]
    r = subprocess.run([python, str(SCRIPT), *map(str, FILES), "--rigidref", str(rigidref_bin()),
                        "--rigidref-solver", ",".join(ours), "--tolerance", repr(TOLERANCE),
                        "--timeout", "60", "--json", str(out), "--profile", str(svg)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr
    print(r.stdout)
    header = [c.strip() for c in r.stdout.splitlines()[0].strip("|").split("|")]
    assert header == ["problem", "contacts", "rigidref newton", "rigidref pgs-exact",
                      "rigidref auto", "rigidref fastest", "Siconos NSGS", "Siconos NSN_AC",
                      "Siconos PROX", "Siconos fastest", "rigidref ÷ fastest"], header
    results = json.load(open(out))
    for p in results["problems"]:
        mine = p["rigidref_solvers"]
        assert sorted(mine) == sorted(ours), p
        for a in mine.values():
            assert a["converged"] == (a["error"] <= TOLERANCE), (p["problem"], a)
        # The answer compared is rigidref's fastest converged one, named in the row.
        assert p["rigidref"]["converged"]
        assert p["rigidref"]["seconds"] == min(a["seconds"] for a in mine.values()
                                               if a["converged"]), p
        row = next(line for line in r.stdout.splitlines() if line.startswith(f"| {p['problem']} "))
        assert row.split("|")[6].strip() == p["rigidref"]["solver"], row
    # The performance profile names a curve for each of the six solvers, and each curve reaches
    # ρ = 1 (every solver solves both problems): its last point is at the plot's top.
    text = svg.read_text()
    assert text.startswith("<svg") and text.rstrip().endswith("</svg>")
    for name in [f"rigidref {x}" for x in ours] + ["Siconos NSGS", "Siconos NSN_AC",
                                                   "Siconos PROX"]:
        assert f"<title>{name}</title>" in text, name
    tops = re.findall(r'points="[^"]*?([0-9.]+)"><title>', text)
    assert len(tops) == 6 and all(float(t) == 30.0 for t in tops), tops


def test_an_unknown_rigidref_solver_is_a_one_line_error():
    python = siconos_python()
    r = subprocess.run([python, str(SCRIPT), str(FILES[0]), "--rigidref", str(rigidref_bin()),
                        "--rigidref-solver", "newton,prox"], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode != 0
    assert "unknown solver 'prox'" in r.stderr, r.stderr


def test_the_profile_ratios_are_times_over_the_fastest_and_infinite_where_not_converged():
    # Pure Python: no Siconos or rigidref needed.
    sys.path.insert(0, str(ROOT / "python"))
    import siconos_side_by_side as script
    ok = lambda s: {"converged": True, "seconds": s}
    rows = [
        {"rigidref_solvers": {"newton": ok(2.0), "auto": ok(1.0)},
         "siconos": {"NSGS": ok(4.0), "PROX": {"converged": False, "seconds": 0.5}}},
        {"rigidref_solvers": {"newton": {"converged": False, "seconds": 9.0}, "auto": ok(3.0)},
         "siconos": {"NSGS": ok(1.5), "PROX": ok(6.0)}},
        # Nobody solved it: left out of the profile.
        {"rigidref_solvers": {"newton": {"converged": False, "seconds": 1.0}},
         "siconos": {"NSGS": {"converged": False, "seconds": 1.0}}},
    ]
    curves, count = script.profile_curves(rows)
    assert count == 2
    inf = float("inf")
    assert curves == {"rigidref newton": [2.0, inf], "rigidref auto": [1.0, 2.0],
                      "Siconos NSGS": [1.0, 4.0], "Siconos PROX": [4.0, inf]}, curves
