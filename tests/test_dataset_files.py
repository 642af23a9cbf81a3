"""Dataset files other tools open (render/imaging/dataset_files.py): scaled PNGs, previews, data.yaml, COCO
classes, the clipped flag at every edge and corner, and loading in pycocotools, torchvision and YOLO's format."""

from __future__ import annotations

import json
import struct
import warnings
import zlib

import numpy as np
import pytest

from csuas import cli
from csuas.render.imaging.dataset_files import (
    data_yaml,
    mot_line,
    preview,
    read_dn_png,
    write_dn_png,
)


def _png_chunks(path) -> dict:
    """Chunk type -> data of a PNG, read from its bytes (PNG 1.2, section 5.3), not through Pillow."""
    data, chunks, position = path.read_bytes(), {}, 8
    while position < len(data):
        (length,) = struct.unpack(">I", data[position : position + 4])
        kind = data[position + 4 : position + 8].decode("ascii")
        body = data[position + 8 : position + 8 + length]
        assert struct.unpack(">I", data[position + 8 + length : position + 12 + length])[0] == zlib.crc32(
            data[position + 4 : position + 8 + length]
        )
        chunks.setdefault(kind, []).append(body)
        position += 12 + length
    return chunks


def test_a_12_bit_frame_sits_in_the_high_bits_of_a_16_bit_png_with_its_scale_stated(tmp_path):
    from PIL import Image

    dn = np.random.default_rng(1).integers(0, 4096, (5, 7)).astype(np.uint16)
    dn[0, 0] = 4095
    path = write_dn_png(tmp_path / "f.png", dn, 12)
    pixels = np.asarray(Image.open(path))
    assert pixels.dtype == np.uint16 and np.array_equal(pixels, dn * 16) and pixels.max() == 65520
    assert np.array_equal(pixels >> 8, dn >> 4)  # an 8-bit reader keeping the high byte sees the 8 top bits
    chunks = _png_chunks(path)
    assert chunks["sBIT"] == [bytes([12])] and chunks["IHDR"][0][8] == 16  # significant bits, bit depth
    texts = dict(body.split(b"\0", 1) for body in chunks["tEXt"])
    assert texts[b"csuas_bits"] == b"12" and texts[b"csuas_dn_scale"] == b"16"
    assert np.array_equal(read_dn_png(path), dn)
    eight = write_dn_png(tmp_path / "e.png", dn >> 4, 8)
    assert np.asarray(Image.open(eight)).dtype == np.uint8 and np.array_equal(read_dn_png(eight), dn >> 4)


def test_eo_previews_are_the_srgb_encoding_of_the_linear_dn():
    def srgb(linear):  # IEC 61966-2-1
        return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)

    dn = np.array([[0, 10, 1024, 2048, 4095]], np.uint16)
    expected = np.rint(255 * srgb(dn / 4095.0)).astype(np.uint8)
    assert np.array_equal(preview(dn, 12, thermal=False), expected)
    assert preview(dn, 12, thermal=False)[0, 3] == 188  # half the full well: sRGB 0.735, not 128
    stretched = preview(np.arange(1000, dtype=np.uint16).reshape(10, 100), 14, thermal=True)
    assert stretched.min() == 0 and stretched.max() == 255  # percentiles 0.5 and 99.5 to black and white


def test_yolo_data_file_and_mot_lines_follow_their_formats():
    yaml = pytest.importorskip("yaml")
    parsed = yaml.safe_load(data_yaml(["dji_mini_4_pro", "black_hornet_3"]))
    assert parsed["names"] == {0: "dji_mini_4_pro", 1: "black_hornet_3"} and parsed["nc"] == 2
    assert "path" not in parsed and parsed["train"] == parsed["val"] == "images"  # the root: data.yaml's folder
    fields = mot_line(3, 1, [10, 20, 5, 4], 1, 0.5).split(",")
    assert fields == ["3", "1", "10", "20", "5", "4", "1", "1", "0.5000"]


def _check_yolo_folder(root, names: list) -> int:
    """The Ultralytics detection format, checked by hand: data.yaml, and for each image a label file of lines
    ``class xc yc w h`` with a known class and normalised box inside the frame. Returns the boxes seen."""
    import yaml

    config = yaml.safe_load((root / "data.yaml").read_text())
    images = root / config["train"]  # Ultralytics without ``path``: relative to data.yaml's folder
    assert config["names"] == dict(enumerate(names))
    boxes = 0
    for image in sorted(images.glob("*.png")):
        label = root / "labels" / f"{image.stem}.txt"  # Ultralytics: /images/ -> /labels/, suffix -> .txt
        for line in label.read_text().splitlines():
            cls, xc, yc, w, h = line.split()
            assert int(cls) in config["names"]
            xc, yc, w, h = (float(v) for v in (xc, yc, w, h))
            assert 0 < w <= 1 and 0 < h <= 1 and 0 <= xc - w / 2 + 1e-6 and xc + w / 2 <= 1 + 1e-6
            assert 0 <= yc - h / 2 + 1e-6 and yc + h / 2 <= 1 + 1e-6
            boxes += 1
    return boxes


@pytest.fixture(scope="module")
def small_dataset(tmp_path_factory):
    """Two frames, one of each drone model, centred at 60 m."""
    root = tmp_path_factory.mktemp("small_dataset")
    spec = root / "spec.toml"
    spec.write_text(
        'seed = 4\ncount = 2\ndrones = ["dji_mini_4_pro", "black_hornet_3"]\nrange_m = [60.0]\nposition = "centre"\n'
    )
    assert cli.main(["dataset", str(spec), "--out", str(root / "d")]) == 0
    return root / "d"


@pytest.mark.slow
def test_a_dataset_opens_in_pycocotools_pillow_and_yolo_readers(small_dataset, capsys):
    out = small_dataset
    capsys.readouterr()
    from pycocotools.coco import COCO

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        coco = COCO(str(out / "annotations.json"))
    capsys.readouterr()  # pycocotools prints its timing
    assert [(c["name"], c["supercategory"]) for c in coco.loadCats(coco.getCatIds())] == [
        ("dji_mini_4_pro", "drone"),
        ("black_hornet_3", "drone"),
    ]
    info = json.loads((out / "annotations.json").read_text())["info"]
    assert info["bits"] == 12 and info["dn_scale"] == 16 and info["png_bits"] == 16
    for annotation in coco.loadAnns(coco.getAnnIds()):
        image = coco.loadImgs(annotation["image_id"])[0]
        drone = image["file_name"].split("_", 1)[1].removesuffix(".png")
        assert coco.loadCats(annotation["category_id"])[0]["name"] == drone
        mask = coco.annToMask(annotation)
        rows, cols = np.nonzero(mask)
        x, y, w, h = annotation["bbox"]
        assert (cols.min(), rows.min(), cols.max() - cols.min() + 1, rows.max() - rows.min() + 1) == (x, y, w, h)
    assert _check_yolo_folder(out, ["dji_mini_4_pro", "black_hornet_3"]) == len(coco.getAnnIds()) == 2
    from PIL import Image

    for name in ("contact_sheet.png", *(f"previews/{p.name}" for p in (out / "previews").iterdir())):
        shown = np.asarray(Image.open(out / name).convert("L"))
        assert shown.dtype == np.uint8 and np.median(shown) > 100  # a daylight sky, not a black frame
    # torchvision's CocoDetection loads Image.open(root / file_name).convert("RGB"): Pillow clips a 16-bit frame to
    # white there, so such loaders take annotations_previews.json, the same labels on the 8-bit previews
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        shown = COCO(str(out / "annotations_previews.json"))
    capsys.readouterr()
    assert shown.getAnnIds() == coco.getAnnIds() and shown.loadAnns(1)[0]["bbox"] == coco.loadAnns(1)[0]["bbox"]
    for image in shown.loadImgs(shown.getImgIds()):
        rgb = np.asarray(Image.open(out / image["file_name"]).convert("RGB"))
        assert rgb.shape == (1080, 1920, 3) and 100 < np.median(rgb) < 250  # a grey sky, neither black nor clipped


@pytest.mark.slow
def test_torchvisions_coco_detection_loads_the_previews_and_their_boxes(small_dataset):
    datasets = pytest.importorskip("torchvision.datasets")
    from pycocotools.coco import COCO

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        loaded = datasets.CocoDetection(str(small_dataset), str(small_dataset / "annotations_previews.json"))
        picture, targets = loaded[0]
    assert 100 < np.median(np.asarray(picture)) < 250
    coco = COCO(str(small_dataset / "annotations.json"))
    assert targets[0]["bbox"] == coco.loadAnns(coco.getAnnIds(imgIds=[1]))[0]["bbox"]


@pytest.mark.slow
@pytest.mark.parametrize(
    "where",
    [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, -1), (-1, 1), (1, 1)],
    ids=["left", "right", "top", "bottom", "top_left", "top_right", "bottom_left", "bottom_right"],
)
def test_a_drone_cut_by_any_edge_or_corner_is_clipped_and_one_just_inside_is_not(where):
    from csuas.render.imaging.common import silhouette_box_px
    from csuas.render.imaging.eo import render_eo
    from csuas.render.imaging.frame import frame_label
    from csuas.render.imaging.records import EoSensor, RenderSettings, View

    sensor, range_m = EoSensor(), 30.0
    geometry_view = View(range_m, 30.0, 10.0)
    first = render_eo("black_hornet_3", geometry_view, sensor, settings=RenderSettings("draft", 0))
    from csuas.render.imaging.camera import SensorGeometry

    geometry = SensorGeometry(first.ifov_rad, sensor.n_h, sensor.n_v)
    cx, cy = geometry.default_target_px()
    x_lo, x_hi, y_lo, y_hi = silhouette_box_px("black_hornet_3", range_m, 30.0, 10.0, geometry, (cx, cy))
    # the projected mesh and the traced coverage agree on the box (to the pixel edges around it)
    assert first.window.x0 <= x_lo and frame_label("black_hornet_3", geometry_view, first, 1920, 1080)["bbox"] == [
        int(np.floor(x_lo)),
        int(np.floor(y_lo)),
        int(np.ceil(x_hi) - np.floor(x_lo)),
        int(np.ceil(y_hi) - np.floor(y_lo)),
    ]

    def offset(inset_x: float, inset_y: float) -> tuple:
        """Centre offset that puts the silhouette's box this far inside the named edges [px] (negative: outside)."""
        ox = {-1: -x_lo + inset_x, 0: 0.0, 1: sensor.n_h - x_hi - inset_x}[where[0]]
        oy = {-1: -y_lo + inset_y, 0: 0.0, 1: sensor.n_v - y_hi - inset_y}[where[1]]
        return (ox, oy)

    width, height = x_hi - x_lo, y_hi - y_lo
    for inset_x, inset_y, clipped in ((0.5, 0.5, False), (-0.4 * width, -0.4 * height, True), (-0.3, -0.3, True)):
        view = View(range_m, 30.0, 10.0, offset(inset_x, inset_y))
        result = render_eo("black_hornet_3", view, sensor, settings=RenderSettings("draft", 0))
        assert frame_label("black_hornet_3", view, result, sensor.n_h, sensor.n_v)["clipped"] is clipped, inset_x
