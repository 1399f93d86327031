"""compare_traces and grade: the CLI's verdicts and numbers, as Python objects."""

import json
import shutil

import pytest

import rigidref
from conftest import run_cli


@pytest.fixture(scope="module")
def traces(root, cli, tmp_path_factory):
    """The projectile scene's reference trace (1 s), a truncated copy (0.3 s) and a copy with a
    NaN."""
    d = tmp_path_factory.mktemp("traces")
    ref = d / "ref.jsonl"
    run_cli(cli, "run", root / "scenes" / "projectile.json", "--time", 1.0, "--out", ref, "--quiet")
    lines = ref.read_text().splitlines()
    short = d / "short.jsonl"
    short.write_text("\n".join(lines[:31]) + "\n")
    nan = d / "nan.jsonl"
    nan.write_text("\n".join(lines[:-1] + [lines[-1].replace('"x":[', '"x":[NaN,', 1)]) + "\n")
    return ref, short, nan


def cli_json(cli, *args):
    done = run_cli(cli, "compare", *args, "--json", check=False)
    return json.loads(done.stdout)


@pytest.mark.parametrize("outcome", [False, True])
def test_compare_gives_the_clis_report(cli, traces, outcome):
    ref, short, _ = traces
    mode = ["--outcome"] if outcome else []
    for other in (ref, short):
        py = rigidref.compare_traces(ref, other, mode="outcome" if outcome else "trajectory")
        expected = cli_json(cli, ref, other, *mode)
        assert {k: v for k, v in py.items() if k not in ("notes", "first_failure")} == expected
    same = rigidref.compare_traces(ref, ref, mode="outcome" if outcome else "trajectory")
    assert same["agree"] and same["refused"] is None
    cut = rigidref.compare_traces(ref, short, mode="outcome" if outcome else "trajectory")
    assert not cut["agree"]
    assert cut["refused"]["kind"] == "incomplete"
    assert "ends at 0.29 s of 1 s" in cut["refused"]["message"]


def test_a_trace_that_cannot_be_read_is_a_trace_error(cli, traces, tmp_path):
    from conftest import cli_error
    ref, _, nan = traces
    with pytest.raises(rigidref.TraceError) as e:
        rigidref.compare_traces(ref, tmp_path / "none.jsonl")
    assert str(e.value) == cli_error(cli, "compare", ref, tmp_path / "none.jsonl")
    # A NaN is not JSON: the reader refuses the line, naming it (exit 2 from the CLI).
    with pytest.raises(rigidref.TraceError) as e:
        rigidref.compare_traces(ref, nan)
    assert str(e.value) == cli_error(cli, "compare", ref, nan)
    assert "not finite" in str(e.value)


def test_grade_gives_the_clis_rows(root, cli, traces, tmp_path):
    ref, short, _ = traces
    subs = tmp_path / "subs"
    for name, trace in (("alice", ref), ("bob", short)):
        (subs / name).mkdir(parents=True)
        shutil.copy(trace, subs / name / "projectile.jsonl")
    (subs / "carol").mkdir()
    scene = root / "scenes" / "projectile.json"
    py = rigidref.grade(subs, [scene], time=1.0, mode="trajectory", jobs=1)
    out = tmp_path / "out"
    run_cli(cli, "grade", subs, "--scenes", scene, "--time", 1.0, "--out", out, "--jobs", 1)
    import csv
    with open(out / "grade.csv") as f:
        rows = list(csv.DictReader(f))
    assert [dict(r) for r in rows] == py["rows"]
    assert py["verdicts"] == {"alice": {"projectile": "pass"}, "bob": {"projectile": "refused"},
                              "carol": {"projectile": "missing"}}


def test_the_trace_writer_is_importable_from_the_package():
    assert rigidref.TraceWriter.__module__ == "rigidref.trace"
    assert callable(rigidref.write_problem)


def test_compare_reads_2d_traces_as_the_cli_does(root, cli, tmp_path):
    # The 2D stack's trace against itself and against a copy with one body moved by 0.01 block:
    # the same report as `rigidref compare --json`, in both modes.
    ref = tmp_path / "ref.jsonl"
    run_cli(cli, "run", root / "scenes" / "blocks" / "stack.json", "--time", 2, "--out", ref, "--quiet")
    lines = ref.read_text().splitlines()
    moved = tmp_path / "moved.jsonl"
    out = [lines[0]]
    for line in lines[1:]:
        record = json.loads(line)
        if record["t"] >= 1.0:
            record["bodies"][1]["x"][0] += 0.01
        out.append(json.dumps(record))
    moved.write_text("\n".join(out) + "\n")
    same = rigidref.compare_traces(ref, ref)
    assert same["agree"] and same["matched_by"] == "image" and same["first_failure"] is None
    differs = rigidref.compare_traces(ref, moved)
    assert not differs["agree"] and "body 1" in differs["first_failure"]
    expected = cli_json(cli, ref, moved)
    assert {k: v for k, v in differs.items() if k not in ("notes", "first_failure")} == expected
    # Outcome mode reads the shapes from the scene the reference names, as the CLI does.
    outcome = rigidref.compare_traces(ref, moved, mode="outcome")
    assert outcome["mode"] == "outcome" and outcome["matched_by"] == "image"
    expected = cli_json(cli, ref, moved, "--outcome")
    assert {k: v for k, v in outcome.items() if k not in ("notes", "first_failure")} == expected



def test_grade_reads_a_mixed_batch_as_the_cli_does(root, cli, traces, tmp_path):
    # A 3D scene (projectile) and a 2D one (the blocks stack) in one batch: the reference's own
    # traces pass, a 2D trace with a body moved by 0.1 block fails, and the rows are the CLI's.
    ref3, _, _ = traces
    stack = root / "scenes" / "blocks" / "stack.json"
    ref2 = tmp_path / "stack_ref.jsonl"
    run_cli(cli, "run", stack, "--time", 1, "--out", ref2, "--quiet")
    subs = tmp_path / "subs"
    for name in ("alice", "bob"):
        (subs / name).mkdir(parents=True)
        shutil.copy(ref3, subs / name / "projectile.jsonl")
    shutil.copy(ref2, subs / "alice" / "stack.jsonl")
    lines = ref2.read_text().splitlines()
    out = [lines[0]]
    for line in lines[1:]:
        record = json.loads(line)
        record["bodies"][1]["x"][1] += 0.1
        out.append(json.dumps(record))
    (subs / "bob" / "stack.jsonl").write_text("\n".join(out) + "\n")
    scenes = [root / "scenes" / "projectile.json", stack]
    py = rigidref.grade(subs, scenes, time=1.0, mode="trajectory", jobs=1)
    assert py["verdicts"] == {"alice": {"projectile": "pass", "stack": "pass"},
                              "bob": {"projectile": "pass", "stack": "fail"}}
    assert any(r["submission"] == "bob" and r["observable"] == 'body 1 ("body1") position'
               and r["result"] == "fail" for r in py["rows"])
    report = tmp_path / "report"
    run_cli(cli, "grade", subs, "--scenes", *scenes, "--time", 1.0, "--out", report, "--jobs", 1)
    import csv
    with open(report / "grade.csv") as f:
        assert [dict(r) for r in csv.DictReader(f)] == py["rows"]
