"""Atomic output: complete or absent, with ordinary permissions."""

import os
import stat

import pytest

from csuas.base.fileio import atomic_path, dumps, write_text_atomic


def test_interrupted_write_leaves_nothing(tmp_path):
    target = tmp_path / "out.exr"
    with pytest.raises(KeyboardInterrupt):
        with atomic_path(target) as tmp:
            tmp.write_bytes(b"half")
            raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []


def test_existing_file_survives_a_failed_rewrite(tmp_path):
    target = write_text_atomic(tmp_path / "report.json", "old")
    with pytest.raises(RuntimeError):
        with atomic_path(target) as tmp:
            tmp.write_text("new, partial")
            raise RuntimeError("disk full")
    assert target.read_text() == "old"


def test_permissions_follow_the_umask(tmp_path):
    mask = os.umask(0o022)
    try:
        path = write_text_atomic(tmp_path / "a.html", "x")
    finally:
        os.umask(mask)
    assert stat.S_IMODE(path.stat().st_mode) == 0o644


def test_json_has_no_nan():
    text = dumps({"a": float("nan"), "b": [float("inf"), 1.0]}).replace(" ", "").replace("\n", "")
    assert text == '{"a":null,"a_nonfinite":"nan","b":[null,1.0]}'
    assert "NaN" not in text and "Infinity" not in text


def test_a_non_finite_value_becomes_null_with_its_value_spelled_beside_it():
    import json as _json

    import numpy as _np

    from csuas.base.fileio import dumps

    out = _json.loads(
        dumps(
            {
                "r": float("inf"),
                "e": _np.float64("nan"),
                "a": _np.array(-_np.inf),
                "ok": 1.0,
                "x": float("inf"),
                "x_note": "unbounded: silence",
                "list": [1.0, float("nan")],
            }
        )
    )
    assert out["r"] is None and out["r_nonfinite"] == "+inf"
    assert out["e"] is None and out["e_nonfinite"] == "nan"
    assert out["a"] is None and out["a_nonfinite"] == "-inf"
    assert "ok_nonfinite" not in out and "x_nonfinite" not in out and out["x_note"] == "unbounded: silence"
    assert out["list"] == [1.0, None]
