"""PNG maps of csuas coverage (csuas/commands/coverage_files.py): one draw cropped as matplotlib's tight savefig
crops, and the maps written by worker processes.

References: matplotlib's own ``savefig(bbox_inches="tight")`` of the same figure (the crop it makes); the
maps written in the calling process (byte for byte the same code on the same data).
"""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image
from rasterio.transform import Affine

from csuas.commands import coverage_files as files
from csuas.core.coverage import SitedSensor


def _frame(n=120):
    rows, cols = np.indices((n, n))
    hillshade = 0.5 + 0.4 * np.sin(rows / 9.0) * np.cos(cols / 13.0)
    sited = {"rf": SitedSensor("rf", 40.0, 30.0, 10.0)}
    return {
        "transform": Affine(25.0, 0, 500_000.0, 0, -25.0, 5_010_000.0),
        "crs": "EPSG:32633",
        "hillshade": hillshade,
        "sited": sited,
    }


def _grid(n=120):
    rows, cols = np.indices((n, n))
    grid = np.exp(-((rows - 40.0) ** 2 + (cols - 30.0) ** 2) / 800.0).astype(np.float32)
    grid[:10] = np.nan
    return grid


@pytest.mark.parametrize("legend", [{"scale": "Pd", "low": 0.5, "high": 1.0}, {"patch": "detected"}])
def test_one_draw_gives_matplotlibs_tight_savefig(tmp_path, monkeypatch, legend):
    """The map drawn once with its tight box found beforehand has every pixel of matplotlib's own
    ``savefig(bbox_inches="tight")`` of the same figure (which draws it twice)."""
    original = files._save_tight

    def both(fig, path):
        fig.savefig(tmp_path / "reference.png", dpi=files.MAP_DPI, bbox_inches="tight", pad_inches=files.MAP_PAD_INCHES)
        original(fig, path)

    monkeypatch.setattr(files, "_save_tight", both)
    files.write_map_png(tmp_path / "map.png", _grid(), _frame(), "rf: pd at 30 m AGL", legend)
    ours = np.asarray(Image.open(tmp_path / "map.png"))
    reference = np.asarray(Image.open(tmp_path / "reference.png"))
    assert ours.shape == reference.shape and np.array_equal(ours, reference)


def test_maps_written_by_workers_are_the_callers_and_their_errors_surface(tmp_path):
    """Two spawned workers write the maps the calling process writes, pixel for pixel; a map that fails in a
    worker (a legend without its keys) raises at close, naming the key."""
    frame, grid = _frame(), _grid()
    legends = [
        {"scale": "Pd", "low": 0.5, "high": 1.0},
        {"patch": "detected"},
        {"scale": "dB", "low": None, "high": None},
    ]
    for i, legend in enumerate(legends):
        files.write_map_png(tmp_path / f"here{i}.png", grid * (i + 1), frame, f"map {i}", legend)
    with files.MapWriter(frame, workers=2) as maps:
        for i, legend in enumerate(legends):
            maps.write(tmp_path / f"pool{i}.png", grid * (i + 1), f"map {i}", legend)
    for i in range(len(legends)):
        here = np.asarray(Image.open(tmp_path / f"here{i}.png"))
        assert np.array_equal(np.asarray(Image.open(tmp_path / f"pool{i}.png")), here)
    maps = files.MapWriter(frame, workers=2)
    maps.write(tmp_path / "bad.png", grid, "bad", {"scale": "Pd"})
    with pytest.raises(KeyError, match="low"):
        maps.close()
    assert not (tmp_path / "bad.png").exists()
