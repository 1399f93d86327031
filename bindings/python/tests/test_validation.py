"""rigidref.validate: the same as `rigidref validate` (docs/validation.md), from Python."""

import pathlib

import pytest

import rigidref

SCENES = pathlib.Path(__file__).resolve().parents[3] / "scenes"


def test_validate_runs_pymunk_on_the_2d_scenes_and_returns_the_report(tmp_path):
    """pymunk (installed in the test environment by the README's command) runs the three 2D
    scenes; the report comes back as report.json's content and the files are written."""
    report = rigidref.validate(tmp_path / "v", engines=["pymunk"], scene_dir=SCENES)
    assert [e["engine"] for e in report["engines"]] == ["pymunk"]
    assert report["engines"][0].get("missing") is None, report["engines"][0]
    names = sorted(s["file"] for s in report["scenes"])
    assert names == ["bar_topple.json", "block_slide.json", "stack_rest.json"], names
    for scene in report["scenes"]:
        assert scene["dimension"] == 2
        engines = [r["engine"] for r in scene["runs"]]
        # rigidref's own run first, then pymunk with its defaults and with the accurate settings.
        assert engines == ["rigidref", "pymunk", "pymunk"], engines
        for run in scene["runs"]:
            assert run["status"]["status"] == "ran", run["status"]
            assert any(m["passed"] is not None for m in run["measured"]), run["measured"]
        # rigidref, judged by the same code, passes every judged observable.
        assert all(m["passed"] in (True, None) for m in scene["runs"][0]["measured"])
    assert (tmp_path / "v" / "report.md").is_file()
    assert (tmp_path / "v" / "report.json").is_file()


def test_validate_refuses_an_unknown_engine_naming_it(tmp_path):
    with pytest.raises(rigidref.SceneError, match="bullet3"):
        rigidref.validate(tmp_path / "v", engines=["bullet3"], scene_dir=SCENES)
