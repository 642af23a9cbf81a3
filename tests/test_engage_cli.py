"""``csuas engage``: the example's spec, the public engage.json keys, refused costs and named mistakes."""

from __future__ import annotations

import json
import os
import stat

import tomllib

from csuas.base.fileio import exclusive_lock
from csuas.cli import main
from csuas.commands.engage import LOCK_NAME
from csuas.defaults import engagement_path
from csuas.render.engagement.spec import parse_spec


def _example() -> str:
    return engagement_path("example").read_text(encoding="utf-8")


def test_print_example_is_a_valid_spec(capsys):
    assert main(["engage", "--print-example"]) == 0
    text = capsys.readouterr().out
    spec = parse_spec(tomllib.loads(text))
    assert spec.site == "demo" and spec.sensors == ["radar", "eo"]
    assert spec.scenario["sensors"]["radar"]["preset"] == "paper_section_4_9"
    assert spec.confusers.birds_per_km2 > 0


def test_cost_above_max_seconds_is_refused(tmp_path, capsys):
    spec = tmp_path / "big.toml"
    spec.write_text(_example().replace("runs = 50", "runs = 100000"), encoding="utf-8")
    assert main(["engage", str(spec), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "runs = 100000" in err and "--max-seconds" in err
    assert not (tmp_path / "out").exists()


def test_mistakes_are_named_by_key(tmp_path, capsys):
    spec = tmp_path / "bad.toml"
    text = (
        _example()
        .replace("speed_m_s = 15.0", "speed_m_s = -3.0")
        .replace('land_cover = "rolling_hills"', 'land_cover = "lava"')
    )
    spec.write_text(text, encoding="utf-8")
    assert main(["engage", str(spec), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "drone.speed_m_s" in err and "looks.radar.land_cover" in err


def test_engage_json_public_keys(tmp_path, capsys):
    spec = tmp_path / "small.toml"
    spec.write_text(_example().replace("runs = 50", "runs = 2").replace("birds_per_km2 = 2.0", "birds_per_km2 = 0.3"))
    assert main(["engage", str(spec), "--out", str(tmp_path / "out"), "--json"]) == 0
    capsys.readouterr()
    out = json.loads((tmp_path / "out" / "engage.json").read_text())
    assert out["runs"] == 2 and out["seed"] == 1
    m = out["metrics"]
    for key in ("first_track_time_s", "first_track_range_m"):
        assert {"median", "p10", "p90", "never_fraction"} <= set(m[key])
    assert {"median", "p10", "p90"} <= set(m["warning_time_s"])
    assert set(m["false_tracks_per_hour"]["by_cause"]) == {"noise", "clutter", "birds"}
    assert {"radar", "eo"} == set(m["false_alarms_per_hour"])
    assert "track_continuity" in m and "gospa_mean" in m
    siap = m["siap"]
    for share in ("completeness", "spuriousness", "longest_track_segment"):
        assert 0.0 <= siap[share] <= 1.0
    assert siap["position_accuracy_m"] >= 0.0 and siap["ambiguity"] >= 0.0
    for sensor in ("radar", "eo"):
        looks = out["looks"][sensor]
        assert {"t_s", "x", "y", "slant_range_m", "visible", "pd"} <= set(looks)
        assert len(looks["t_s"]) == len(looks["pd"]) == 339  # 5085 m at 15 m/s, a look a second from t = 0
    assert len(out["runs_detail"]) == 2 and "first_track_time_s" in out["runs_detail"][0]
    assert (tmp_path / "out" / "engage_map.png").stat().st_size > 10_000
    assert (tmp_path / "out" / "engage_curve.png").stat().st_size > 10_000


def test_a_device_node_named_like_an_output_survives_and_is_refused_before_the_runs(tmp_path, capsys):
    """A FIFO where engage.json goes: refused (exit 2, one line) before any run; it stays a FIFO."""
    spec = tmp_path / "small.toml"
    spec.write_text(_example().replace("runs = 50", "runs = 2").replace("birds_per_km2 = 2.0", "birds_per_km2 = 0.0"))
    out = tmp_path / "out"
    out.mkdir()
    os.mkfifo(out / "engage.json")
    assert main(["engage", str(spec), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "never replaced" in err[0], err
    assert stat.S_ISFIFO(os.lstat(out / "engage.json").st_mode)
    assert sorted(p.name for p in out.iterdir()) == ["engage.json"]


def test_a_folder_another_engagement_writes_into_is_refused(tmp_path, capsys):
    """The output folder's lock (the base helper sweep, dataset, coverage and report hold): exit 2, nothing written."""
    spec = tmp_path / "small.toml"
    spec.write_text(_example().replace("runs = 50", "runs = 1").replace("birds_per_km2 = 2.0", "birds_per_km2 = 0.0"))
    out = tmp_path / "out"
    out.mkdir()
    with exclusive_lock(out / LOCK_NAME, "--out"):
        assert main(["engage", str(spec), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--out" in err[0] and LOCK_NAME in err[0], err
    assert sorted(p.name for p in out.iterdir()) == [LOCK_NAME]
