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
    assert dumps({"a": float("nan"), "b": [float("inf"), 1.0]}).replace(" ", "").replace("\n", "") == '{"a":null,"b":[null,1.0]}'
