"""The detector in the loop (validation/detector/): the AP evaluator against pycocotools and a hand count,
the bins, the physics Pd columns against closed forms, the sets' specs and crop, imports without torch,
and one training step where torchvision is installed."""

from __future__ import annotations

import contextlib
import io
import json
import math
import subprocess
import sys

import numpy as np
import pytest
from scipy.stats import norm

from csuas.base.errors import ParameterError
from csuas.validation.detector import average_precision as ap
from csuas.validation.detector.evaluation import evaluate
from csuas.validation.detector.frames import Frame
from csuas.validation.detector.physics import frame_pd


def _coco_eval(truth: dict, detections: list, image_ids=None) -> tuple[float, float]:
    """pycocotools' AP (0.50:0.95) and AP50 of one category on hand-made boxes."""
    from pycocotools.coco import COCO
    from pycocotools.cocoeval import COCOeval

    images = sorted(truth)
    anns = [
        {
            "id": k + 1,
            "image_id": i,
            "category_id": 1,
            "bbox": list(map(float, b)),
            "area": float(b[2] * b[3]),
            "iscrowd": 0,
        }
        for k, (i, b) in enumerate((i, b) for i in images for b in truth[i])
    ]
    gt = COCO()
    gt.dataset = {
        "images": [{"id": i} for i in images],
        "annotations": anns,
        "categories": [{"id": 1, "name": "drone"}],
    }
    with contextlib.redirect_stdout(io.StringIO()):
        gt.createIndex()
        dt = gt.loadRes(
            [{"image_id": i, "category_id": 1, "bbox": list(map(float, b)), "score": s} for i, b, s in detections]
        )
        evaluator = COCOeval(gt, dt, "bbox")
        if image_ids is not None:
            evaluator.params.imgIds = sorted(image_ids)
        evaluator.evaluate()
        evaluator.accumulate()
        evaluator.summarize()
    return float(evaluator.stats[0]), float(evaluator.stats[1])


def _ours(truth: dict, detections: list, image_ids=None) -> np.ndarray:
    ids = sorted(truth if image_ids is None else image_ids)
    frames = []
    for i in ids:
        mine = [(b, s) for j, b, s in detections if j == i]
        frames.append(ap.match_frame(truth[i], [b for b, _ in mine], [s for _, s in mine]))
    return ap.average_precision(frames)


def _hand_made_case():
    """Twelve frames: clean hits, shifted boxes across the IoU thresholds, duplicates, tied scores, a frame
    without a drone holding a false alarm, a drone never found, two drones in one frame."""
    rng = np.random.default_rng(7)
    truth, detections = {}, []
    for i in range(1, 13):
        truth[i] = [[rng.uniform(0, 200), rng.uniform(0, 150), rng.uniform(2, 40), rng.uniform(2, 30)]]
        x, y, w, h = truth[i][0]
        shift = [0.0, 0.05, 0.15, 0.3, 0.6][i % 5] * w
        detections.append((i, [x + shift, y, w, h], round(float(rng.uniform(0.2, 1.0)), 2)))
        if i % 3 == 0:  # a duplicate of lower score: a false positive at every IoU
            detections.append((i, [x + shift / 2, y, w, h], 0.15))
        if i % 4 == 0:  # a false alarm elsewhere, its score tied with another frame's
            detections.append((i, [250.0, 10.0, 5.0, 5.0], 0.5))
    truth[5] = []  # no drone: its detection is a false alarm
    truth[7].append([100.0, 100.0, 10.0, 10.0])  # two drones, one never found
    truth[11] = [[40.0, 40.0, 3.0, 2.0]]  # a drone of a few pixels, its detection elsewhere
    return truth, detections


def test_average_precision_agrees_with_pycocotools_on_hand_made_detections():
    truth, detections = _hand_made_case()
    coco_ap, coco_ap50 = _coco_eval(truth, detections)
    ours = _ours(truth, detections)
    assert 0.1 < coco_ap < coco_ap50 < 1.0  # a case that exercises the thresholds
    assert ours.mean() == pytest.approx(coco_ap, abs=1e-12)
    assert ours[0] == pytest.approx(coco_ap50, abs=1e-12)


def test_average_precision_of_a_bin_agrees_with_pycocotools_on_the_same_frames():
    truth, detections = _hand_made_case()
    subset = [2, 3, 5, 7, 8, 11]
    coco_ap, coco_ap50 = _coco_eval(truth, detections, subset)
    ours = _ours(truth, detections, subset)
    assert ours.mean() == pytest.approx(coco_ap, abs=1e-12)
    assert ours[0] == pytest.approx(coco_ap50, abs=1e-12)


def test_average_precision_by_hand_two_hits_around_a_false_alarm():
    """Scores 0.9 hit, 0.8 miss, 0.7 hit on two drones: precision 1 up to recall 0.5 (51 of COCO's 101
    points), then 2/3 (50 points): AP50 = (51 + 50 * 2/3) / 101."""
    box = [10.0, 10.0, 8.0, 6.0]
    frames = [
        ap.match_frame([box], [box, [50.0, 50.0, 8.0, 6.0]], [0.9, 0.8]),
        ap.match_frame([box], [box], [0.7]),
    ]
    assert ap.average_precision(frames)[0] == pytest.approx((51 + 50 * 2 / 3) / 101, abs=1e-12)
    assert ap.average_precision([ap.match_frame(np.empty((0, 4)), [box], [0.9])]) is None  # no drone: COCO's -1
    assert ap.average_precision([ap.match_frame([box], np.empty((0, 4)), [])]).tolist() == [0.0] * 10


def test_the_false_alarm_threshold_and_the_detection_rate_count_by_hand():
    box = [10.0, 10.0, 8.0, 6.0]
    frames = [
        ap.match_frame([box], [box, [60.0, 60.0, 5.0, 5.0]], [0.6, 0.9]),  # a false alarm above the hit
        ap.match_frame([box], [box, [90.0, 60.0, 5.0, 5.0]], [0.8, 0.3]),
        ap.match_frame(np.empty((0, 4)), [[5.0, 5.0, 5.0, 5.0]], [0.2]),
    ]
    # false alarms 0.9, 0.3, 0.2 over 3 frames: at most 1/3 a frame allows the one at 0.9, not the one at 0.3
    threshold = ap.false_alarm_threshold(frames, 1 / 3)
    assert 0.3 < threshold <= 0.6
    assert ap.detection_rate(frames, threshold) == (1.0, 2)
    assert ap.false_alarm_threshold(frames, 0.0) == np.nextafter(0.9, np.inf)
    assert ap.detection_rate(frames, ap.false_alarm_threshold(frames, 0.0)) == (0.0, 2)
    assert ap.false_alarm_threshold(frames, 1.0) == -np.inf
    with pytest.raises(ParameterError, match="false_alarms_per_frame"):
        ap.false_alarm_threshold(frames, -1.0)


def test_bins_are_closed_below_and_open_above():
    edges = (0.0, 1.0, 4.0, math.inf)
    assert ap.bin_index([0.0, 0.99, 1.0, 3.999, 4.0, 1e9, -0.1, math.inf], edges).tolist() == [0, 0, 1, 1, 2, 2, -1, -1]
    with pytest.raises(ParameterError, match="edges"):
        ap.bin_index([1.0], (0.0, 4.0, 1.0))


def test_the_physics_columns_are_the_ttpf_and_the_gaussian_threshold_in_closed_form():
    cycles, snr, pfa = np.array([0.0, 0.5, 1.0, 2.0, 8.0]), np.array([0.0, 3.0, 4.753424, 6.0, 50.0]), 1e-6
    got = frame_pd(cycles, snr, pfa)
    for key, (e0, e1) in (("pd_ttpf_johnson", (2.7, 0.7)), ("pd_ttpf_ttp", (1.51, 0.24))):
        with np.errstate(divide="ignore"):
            expected = np.where(cycles > 0, cycles ** (e0 + e1 * cycles) / (1 + cycles ** (e0 + e1 * cycles)), 0.0)
        np.testing.assert_allclose(got[key], expected, rtol=1e-12, atol=1e-15)
        assert got[key][2] == pytest.approx(0.5, abs=1e-15)  # N = N50: half the drones found (Table 20)
    camera = norm.sf(norm.isf(pfa) - snr)  # Q(Q^-1(Pfa) - SNR)
    np.testing.assert_allclose(got["pd_camera_snr"], np.maximum(camera, pfa), rtol=1e-12)
    assert got["pd_camera_snr"][2] == pytest.approx(0.5, abs=1e-6)  # SNR at the threshold Q^-1(1e-6) = 4.753424
    np.testing.assert_allclose(got["pd_physical"], got["pd_ttpf_johnson"] * got["pd_camera_snr"], rtol=1e-15)


def _frame(box, pixels, background, cycles=1.0, snr=10.0):
    labels = [] if box is None else [{"pixels_on_target": pixels, "johnson_cycles": cycles, "snr": snr}]
    boxes = np.empty((0, 4)) if box is None else np.array([box], dtype=float)
    return Frame(path=f"{background}.png", size_px=(320, 256), boxes=boxes, labels=labels, background=background)


def test_evaluate_groups_frames_by_pixels_on_target_and_background():
    box = [10.0, 10.0, 8.0, 6.0]
    frames = [
        _frame(box, 0.5, "sky", cycles=0.2),
        _frame(box, 3.0, "sky", cycles=1.0),
        _frame(box, 300.0, "ground", cycles=8.0),
        _frame(None, 0.0, "ground"),
    ]
    miss = (np.array([[100.0, 100.0, 8.0, 6.0]]), np.array([0.05]))
    detections = [miss, (np.array([box]), np.array([0.9])), (np.array([box]), np.array([0.8])), miss]
    result = evaluate(frames, detections, pfa=1e-6, edges=(0.0, 1.0, 4.0, math.inf))
    assert result["false_alarms_per_frame"] == pytest.approx(1e-6 * 320 * 256)
    assert result["score_threshold"] == pytest.approx(np.nextafter(0.05, 1.0))  # 0.08 a frame: no false alarm allowed
    rows = result["by_pixels_on_target"]
    assert [r["targets"] for r in rows] == [1, 1, 1]
    assert [r["ap50"] for r in rows] == pytest.approx([0.0, 1.0, 1.0], abs=1e-12)  # COCO divides by tp + fp + eps
    assert [r["pd_learned"] for r in rows] == [0.0, 1.0, 1.0]
    expected = frame_pd([0.2, 1.0, 8.0], [10.0, 10.0, 10.0], 1e-6)["pd_ttpf_johnson"]
    assert [r["pd_ttpf_johnson"] for r in rows] == pytest.approx(expected.tolist(), abs=1e-15)
    by_background = {r["background"]: r for r in result["by_background"]}
    assert by_background["ground"]["frames"] == 2 and by_background["ground"]["targets"] == 1
    assert by_background["sky"]["pd_ttpf_johnson"] == pytest.approx(expected[:2].mean(), abs=1e-15)
    assert result["all"]["pd_learned"] == pytest.approx(2 / 3)
    assert [f["found_score"] for f in result["frames"]] == [None, 0.9, 0.8, None]
    json.dumps(result, allow_nan=False)  # strict JSON: no NaN or infinity anywhere


def test_the_sets_share_frames_evenly_draw_other_seeds_and_crop_the_default_camera(tmp_path):
    from csuas.core.scenario import load_scenario
    from csuas.render.imaging.dataset import parse_dataset_spec
    from csuas.validation.detector import sets

    scenario = tmp_path / "crop.toml"
    scenario.write_text(sets.crop_scenario_text())
    crop, full = load_scenario(scenario).sensors["eo"].params, load_scenario("default").sensors["eo"].params
    assert (crop["n_h"], crop["n_v"]) == sets.FRAME_PX
    for fov, n, pixels in (("hfov_deg", "n_h", 320), ("vfov_deg", "n_v", 256)):  # the same focal length in pixels
        focal_crop = (pixels / 2) / math.tan(math.radians(crop[fov]) / 2)
        assert focal_crop == pytest.approx((full[n] / 2) / math.tan(math.radians(full[fov]) / 2), rel=1e-12)
    train = sets.set_specs(scenario, 11, 192, sets.TRAIN_BACKGROUNDS)
    test = sets.set_specs(scenario, 23, 108, sets.TEST_BACKGROUNDS)
    assert [s["count"] for s in train.values()] == [16, 16] and [s["count"] for s in test.values()] == [5, 5, 5, 5]
    assert not {s["seed"] for s in train.values()} & {s["seed"] for s in test.values()}
    assert set(test) - set(train) == {"ground_0.2", "cluttered"}
    for spec in (*train.values(), *test.values()):
        parse_dataset_spec(spec)  # every set is a valid dataset spec
    with pytest.raises(ParameterError, match="seeds"):
        sets.make_sets(tmp_path / "out", seeds=(3, 3))


def test_the_detector_modules_import_and_skip_cleanly_without_torch():
    code = (
        "import sys; sys.modules['torch'] = None; sys.modules['torchvision'] = None\n"
        "import pkgutil, importlib, csuas.validation.detector as d\n"
        "for m in pkgutil.iter_modules(d.__path__): importlib.import_module(f'csuas.validation.detector.{m.name}')\n"
        "from csuas.validation.detector.detector_loop import bench_detector_loop, main\n"
        "print(bench_detector_loop(out_dir='unused'))\n"
        "print(main(['--train', 'a', '--test', 'b', '--out', 'c']))\n"
        "print(main(['--train', 'a', '--test', 'b', '--out', 'c', '--epochs', '0', '--learning-rate', '-1']))\n"
        "assert 'mitsuba' not in sys.modules and 'drjit' not in sys.modules\n"
    )
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout.splitlines() == [
        "{'skipped': 'torchvision not installed: pip install csuas[detector]'}",
        "0",
        "2",
    ]
    missing, *bad = run.stderr.strip().splitlines()  # bad input: a line per mistake, all at once, exit 2
    assert missing == "torchvision not installed: pip install csuas[detector]"
    assert len(bad) == 2 and "epochs" in bad[0] and "learning_rate" in bad[1]


def _tiny_dataset(folder, n=2):
    """A hand-written csuas-format dataset: 12-bit grey frames (DN x 16 in 16-bit PNGs), one bright drone each."""
    from PIL import Image

    (folder / "images").mkdir(parents=True)
    images, anns = [], []
    for i in range(n):
        dn = np.full((64, 80), 2048, dtype=np.uint16)
        dn[20 + i : 26 + i, 30:38] = 3500
        Image.fromarray(dn * 16).save(folder / "images" / f"{i}.png")
        images.append({"id": i + 1, "file_name": f"images/{i}.png", "width": 80, "height": 64})
        label = {"pixels_on_target": 48.0, "johnson_cycles": 2.0, "snr": 30.0}
        anns.append(
            {
                "id": i + 1,
                "image_id": i + 1,
                "category_id": 1,
                "bbox": [30, 20 + i, 8, 6],
                "area": 48,
                "iscrowd": 0,
                "csuas": label,
            }
        )
    coco = {
        "info": {"bits": 12, "dn_scale": 16},
        "images": images,
        "annotations": anns,
        "categories": [{"id": 1, "name": "d"}],
    }
    (folder / "annotations.json").write_text(json.dumps(coco))
    return folder


def test_the_frames_read_as_dn_over_full_scale(tmp_path):
    from csuas.validation.detector.frames import load_frames, read_image

    frames = load_frames({"sky": _tiny_dataset(tmp_path / "sky")})
    assert [f.background for f in frames] == ["sky", "sky"]
    image = read_image(frames[0])
    assert image.shape == (64, 80)
    assert image[0, 0] == pytest.approx(2048 / 4095, rel=1e-6) and image[22, 33] == pytest.approx(3500 / 4095, rel=1e-6)


#: Packages the training step must not need: it runs where only torch, torchvision, NumPy, SciPy, Pillow and
#: matplotlib are (a GPU machine with ``pip install --no-deps -e .``).
NOT_NEEDED = ("mitsuba", "drjit", "sionna", "pydantic", "trimesh", "shapely", "dask", "rasterio", "OpenEXR", "colour")


def test_one_training_step_runs_and_scores_without_mitsuba_where_torchvision_is_installed(tmp_path):
    pytest.importorskip("torchvision")
    data = _tiny_dataset(tmp_path / "data")
    blocked = "; ".join(f"sys.modules[{name!r}] = None" for name in NOT_NEEDED)
    code = (
        f"import sys; {blocked}\nfrom csuas.validation.detector.detector_loop import main\nsys.exit(main(sys.argv[1:]))"
    )
    argv = ["--train", str(data), "--test", str(data), "--out", str(tmp_path / "out"), "--epochs", "1", "--batch", "2"]
    run = subprocess.run(
        [sys.executable, "-c", code, *argv, "--max-steps", "1"], capture_output=True, text=True, timeout=600
    )
    assert run.returncode == 0, run.stderr
    result = json.loads((tmp_path / "out" / "detector_loop.json").read_text())
    assert result["conditions"]["steps"] == 1 and math.isfinite(result["conditions"]["loss_first"])
    assert result["all"]["targets"] == 2 and 0.0 <= result["all"]["ap50"] <= 1.0
    assert (tmp_path / "out" / "detector_loop.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(json.loads((tmp_path / "out" / "detections.json").read_text())) <= 2 * 100
