"""Render files a user can keep (issue 9, section 4): names, EXR windows and metadata, previews."""

import json

import numpy as np
import pytest

from csuas.cli import main
from csuas.render.files import METADATA_KEYS, coordinates_label, file_stem

pytestmark = pytest.mark.slow


def _render(capsys, *argv):
    assert main(["render", *argv, "--quality", "draft", "--quiet", "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _exr(path):
    import OpenEXR

    exr = OpenEXR.File(str(path))
    pixels = {}
    for name, channel in exr.channels().items():
        data = np.array(channel.pixels)
        if data.ndim == 3:  # the reader groups R, G, B, A into one "RGBA" channel
            pixels.update({letter: data[..., i] for i, letter in enumerate(name)})
        else:
            pixels[name] = data
    return dict(exr.header()), pixels


def test_file_names_carry_every_coordinate():
    assert file_stem("s", "eo1", "eo", 100.0, 90.0, -15.0, "draft", 0) == "s_eo1_eo_r100m_az90_elm15_draft"
    assert file_stem("s", "eo1", "eo", 2500.5, 0.0, 0.0, "standard", 7).endswith("r2500.5m_az0_el0_standard_seed7")
    assert coordinates_label(100.0, 0.0, 0.0) != coordinates_label(100.0, 0.0, 0.5)


def test_a_loop_over_azimuths_into_one_folder_keeps_every_render(capsys, tmp_path):
    out = _render(capsys, "eo", "default", "--range-m", "100", "--azimuth-deg", "0", "90", "--out", str(tmp_path))
    assert [(r["azimuth_deg"], r["elevation_deg"]) for r in out["results"]] == [(0.0, 0.0), (90.0, 0.0)]
    files = sorted(p.name for p in tmp_path.iterdir())
    assert files == [
        "default_eo_eo_r100m_az0_el0_draft.exr",
        "default_eo_eo_r100m_az0_el0_draft.png",
        "default_eo_eo_r100m_az90_el0_draft.exr",
        "default_eo_eo_r100m_az90_el0_draft.png",
    ]


def test_renders_whose_names_would_coincide_are_refused_before_work(capsys, tmp_path):
    assert main(["render", "eo", "default", "--range-m", "100", "100.0000001", "--out", str(tmp_path)]) == 2
    assert "distinct coordinates" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("mode, channels", [("eo", {"R", "G", "B", "A"}), ("tir", {"L", "T", "A"}), ("lidar", {"Y"})])
def test_every_mode_writes_the_same_metadata_and_lists_all_its_channels(capsys, tmp_path, mode, channels):
    out = _render(capsys, mode, "default", "--range-m", "150", "--out", str(tmp_path))
    exr = next(f for f in out["results"][0]["files"] if f.endswith(".exr"))
    header, pixels = _exr(exr)
    assert {f"csuas_{k}" for k in METADATA_KEYS} <= set(header)
    assert set(pixels) == channels
    assert set(header["csuas_channels"].split(",")) == channels
    assert header["csuas_range_m"] == 150.0 and header["csuas_quality"] == "draft"


@pytest.mark.parametrize("mode, n_h, n_v", [("eo", 1920, 1080), ("tir", 1280, 720)])
def test_the_window_sits_in_the_full_frame_at_its_offset(capsys, tmp_path, mode, n_h, n_v):
    out = _render(capsys, mode, "default", "--range-m", "120", "--out", str(tmp_path))
    header, pixels = _exr(next(f for f in out["results"][0]["files"] if f.endswith(".exr")))
    (x0, y0), (x1, y1) = (tuple(int(v) for v in corner) for corner in header["dataWindow"])
    (dx0, dy0), (dx1, dy1) = (tuple(int(v) for v in corner) for corner in header["displayWindow"])
    assert (dx0, dy0, dx1, dy1) == (0, 0, n_h - 1, n_v - 1)
    assert (x0, y0) == (header["csuas_window_x0"], header["csuas_window_y0"])
    rows, columns = pixels["A"].shape
    assert (x1 - x0 + 1, y1 - y0 + 1) == (columns, rows)
    assert 0 <= x0 <= x1 < n_h and 0 <= y0 <= y1 < n_v
    # the target sits on the optical axis: the window is centred in the frame to a pixel
    assert abs((x0 + x1) / 2 - (n_h - 1) / 2) <= 1.0 and abs((y0 + y1) / 2 - (n_v - 1) / 2) <= 1.0


def test_night_looks_like_night_unless_auto_exposure_is_asked(capsys, tmp_path):
    import matplotlib.image

    scenario = tmp_path / "night.toml"
    scenario.write_text('name = "night"\n[environment]\npreset = "night"\n[sensors.eo]\nmodality = "eo"\n')

    def mean_png(*extra):
        out = _render(capsys, "eo", str(scenario), "--range-m", "100", "--out", str(tmp_path / str(len(extra))), *extra)
        png = next(f for f in out["results"][0]["files"] if f.endswith(".png"))
        return float(matplotlib.image.imread(png)[..., :3].mean())

    assert mean_png() < 0.01
    assert mean_png("--auto-exposure") > 0.1


@pytest.mark.parametrize("mode", ["tir", "lidar"])
def test_map_previews_are_readable_with_a_colour_bar(capsys, tmp_path, mode):
    import matplotlib.image

    out = _render(capsys, mode, "default", "--range-m", "100", "--out", str(tmp_path))
    png = matplotlib.image.imread(next(f for f in out["results"][0]["files"] if f.endswith(".png")))
    assert png.shape[0] >= 400 and png.shape[1] >= 550
    assert np.ptp(png[..., :3]) > 0.5
