"""csuas dataset (render/imaging/dataset.py): spec validation, draws, files, labels, determinism, resume."""

from __future__ import annotations

import json

import numpy as np
import pytest

from csuas import cli
from csuas.base.errors import InputErrors
from csuas.render.imaging.dataset import draws, load_dataset_spec, parse_dataset_spec


def test_every_spec_mistake_is_named_at_once():
    with pytest.raises(InputErrors) as caught:
        parse_dataset_spec(
            {"count": 0, "drones": ["no_such"], "range_m": {"min": 900.0, "max": 10.0}, "chain": ["jpeg"], "colour": 1}
        )
    text = str(caught.value)
    for key in ("count", "drones", "range_m", "chain", "colour"):
        assert key in text


def test_a_chain_without_quantise_is_named_not_an_internal_error(tmp_path):
    """The frames are written as DN: a chain that never quantises is refused by key (it raised KeyError 'dn')."""
    with pytest.raises(InputErrors, match="chain.*quantise"):
        parse_dataset_spec({"count": 1, "chain": []})
    with pytest.raises(InputErrors, match="chain.*quantise"):
        parse_dataset_spec({"count": 1, "chain": ["psf", "shot_noise"]})
    spec = tmp_path / "spec.toml"
    spec.write_text("count = 1\nchain = []\n")
    assert cli.main(["dataset", str(spec), "--out", str(tmp_path / "out")]) == 2
    assert not (tmp_path / "out").exists()


def test_list_axes_are_a_grid_and_tables_are_drawn():
    spec = parse_dataset_spec(
        {"seed": 5, "count": 3, "range_m": [100.0, 200.0], "azimuth_deg": {"min": 10.0, "max": 20.0}}
    )
    items = draws(spec, (1920, 1080))
    assert [i["range_m"] for i in items] == [100.0] * 3 + [200.0] * 3
    assert all(10.0 <= i["azimuth_deg"] <= 20.0 for i in items)
    assert all(abs(i["target_offset_px"][0]) <= 960 and abs(i["target_offset_px"][1]) <= 540 for i in items)
    assert draws(spec, (1920, 1080)) == items  # the seed fixes every draw
    example = load_dataset_spec("example")
    assert example.count == 20 and example.axes["drones"] == ["dji_mini_4_pro", "black_hornet_3"]


@pytest.mark.slow
def test_a_small_dataset_has_images_labels_and_the_same_bytes_for_the_same_seed(tmp_path, capsys):
    spec = tmp_path / "spec.toml"
    spec.write_text(
        'seed = 1\ncount = 2\nscenario = "default"\ndrones = ["dji_mini_4_pro"]\nrange_m = [150.0]\n'
        'position = "centre"\nexr = true\n'
    )
    assert cli.main(["dataset", str(spec), "--out", str(tmp_path / "a"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["images"] == 2 and summary["rendered"] == 2
    coco = json.loads((tmp_path / "a" / "annotations.json").read_text())
    assert len(coco["images"]) == 2 and len(coco["annotations"]) == 2
    first = coco["annotations"][0]
    x, y, w, h = first["bbox"]
    assert abs(x + w / 2 - 960) < w and abs(y + h / 2 - 540) < h  # centred target
    assert not first["csuas"]["clipped"] and first["csuas"]["pixels_on_target"] > 1
    cycles = first["csuas"]["johnson_cycles"]
    table_20 = [("identification", 8.0), ("recognition", 4.0), ("detection", 1.0)]  # line pairs, standard column
    assert first["csuas"]["dri"] == next((task for task, pairs in table_20 if cycles >= pairs), "none")
    import OpenEXR

    with OpenEXR.File(str(tmp_path / "a" / "images" / "000000_dji_mini_4_pro.exr")) as exr:
        signal, units = exr.channels()["Y"].pixels, exr.header()["csuas_units"]
    assert signal.shape == (1080, 1920) and signal.dtype == np.float32 and units == "electrons"
    yolo = (tmp_path / "a" / "labels" / "000000_dji_mini_4_pro.txt").read_text().split()
    assert float(yolo[1]) == pytest.approx((x + w / 2) / 1920, abs=1e-6)
    from PIL import Image

    image = np.asarray(Image.open(tmp_path / "a" / "images" / "000000_dji_mini_4_pro.png"))
    assert image.shape == (1080, 1920) and image.max() < 65536 and not (image % 16).any()  # 12-bit DN << 4
    assert cli.main(["dataset", str(spec), "--out", str(tmp_path / "b")]) == 0
    for name in ("000000_dji_mini_4_pro.png", "000001_dji_mini_4_pro.png"):
        assert (tmp_path / "a" / "images" / name).read_bytes() == (tmp_path / "b" / "images" / name).read_bytes()
    capsys.readouterr()
    assert cli.main(["dataset", str(spec), "--out", str(tmp_path / "a"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["rendered"] == 0  # resumed: nothing redone


@pytest.mark.slow
def test_a_thermal_dataset_labels_the_drone_in_temperature_frames(tmp_path, capsys):
    spec = tmp_path / "tir.toml"
    spec.write_text(
        'seed = 2\ncount = 1\nscenario = "default"\nsensor = "tir"\ndrones = ["dji_mini_4_pro"]\n'
        'range_m = [120.0]\nposition = "centre"\nchain = ["psf", "netd", "quantise"]\nbits = 14\nexr = true\n'
    )
    assert cli.main(["dataset", str(spec), "--out", str(tmp_path / "t"), "--json"]) == 0
    coco = json.loads((tmp_path / "t" / "annotations.json").read_text())
    block = coco["annotations"][0]["csuas"]
    assert block["modality"] == "tir" and abs(block["delta_t_k"]) > 0.5 and block["snr"] > 5.0
    import OpenEXR

    with OpenEXR.File(str(tmp_path / "t" / "images" / "000000_dji_mini_4_pro.exr")) as exr:
        kelvin, units = exr.channels()["Y"].pixels, exr.header()["csuas_units"]
    assert units == "K" and kelvin.shape == (720, 1280) and 250.0 < float(np.median(kelvin)) < 330.0


@pytest.mark.slow
def test_the_frame_bench_times_render_and_chain_separately():
    from csuas.validation.imaging.bench import bench_frames

    out = bench_frames(2)
    assert out["frames"] == 2 and out["frames_per_s"] > 0
    assert out["render_s_per_frame"] > 0 and out["camera_and_chain_s_per_frame"] > 0
    assert out["peak_rss_gib"] > out["peak_rss_growth_gib"] >= 0


def test_a_thermal_sky_needs_a_thermal_sensor_and_a_plausible_temperature(tmp_path, capsys):
    with pytest.raises(InputErrors, match="sky_temperature_k"):
        parse_dataset_spec({"sky_temperature_k": 1000.0})
    spec = tmp_path / "eo_sky.toml"
    spec.write_text('count = 1\nsensor = "eo"\nsky_temperature_k = 230.0\n')
    assert cli.main(["dataset", str(spec), "--out", str(tmp_path / "e")]) == 2
    assert "sky_temperature_k" in capsys.readouterr().err


@pytest.mark.slow
def test_the_dataset_rate_bench_runs_both_embedded_specs_and_each_lever():
    from csuas.validation.imaging.bench import bench_dataset_rates

    rows = bench_dataset_rates(1)
    runs = [r for r in rows if "dataset" in r]
    assert [(r["dataset"], r["shot_noise"]) for r in runs] == [
        ("example", "poisson"),
        ("example", "normal above 1000 e"),
        ("sequence", "poisson"),
        ("sequence", "normal above 1000 e"),
        ("example-cluttered", "poisson"),
    ]
    assert all(r["frames"] == 1 and r["frames_per_s"] > 0 and r["cpu_s_per_frame"] > 0 for r in runs)
    assert [r["lever"] for r in rows if "lever" in r] == ["blur FFT", "shot noise", "16-bit PNG"]
