"""Every expensive input is estimated and refused before work (issue 22, section 2).

Each case runs the command line as a child process and measures its wall time and its peak
resident memory (:func:`csuas.base.cost.run_measured`: ``os.wait4``'s ru_maxrss of that child
alone): a refusal is exit 2, one line naming the flag that lifts it, within :data:`MAX_SECONDS`
and :data:`MAX_RSS_BYTES`. A child still running after :data:`KILL_AFTER_S` is killed (the
failure then says so) so that a regression cannot exhaust the machine's memory. The models'
accuracy against measured costs is judged by the ``cost_models`` benchmark, not here.
"""

from __future__ import annotations

import math
import os
import sys
from argparse import Namespace

import pytest

from csuas.base.cost import Estimate, check_limits, limits_of, machine_memory_bytes, run_measured
from csuas.base.errors import ParameterError

CSUAS = [sys.executable, "-m", "csuas.cli"]
#: Limits on a refusal (issue 22): generous for a loaded machine; a refusal takes 0.3-4 s and 35-100 MB.
MAX_SECONDS = 10.0
MAX_RSS_BYTES = 2e9
#: A child still running then is killed: the work was started, not refused.
KILL_AFTER_S = 30.0


def _refused(args: list, cwd, flag: str) -> str:
    """Run ``csuas ARGS`` and check it is refused in time and memory with one line naming ``flag``."""
    run = run_measured([*CSUAS, *args], cwd, KILL_AFTER_S)
    err = run.stderr
    assert not run.killed, f"still running after {KILL_AFTER_S} s: the work started ({err[-300:]})"
    assert run.code == 2, err[-500:]
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert flag in err, err
    assert run.seconds < MAX_SECONDS, f"refused after {run.seconds:.1f} s"
    assert run.bytes < MAX_RSS_BYTES, f"peak memory {run.bytes / 1e9:.2f} GB"
    return err


def _write(path, text: str) -> str:
    path.write_text(text)
    return str(path)


SWEEP_AXIS = 'job = "range"\n[axes]\n"environment.rain_rate_mm_h" = {{min = 0.0, max = 50.0, samples = {n}}}\n'


@pytest.mark.parametrize("samples", ["1000000000", "1e12", "inf", "nan", "-3", "2.5"])
def test_a_sweep_axis_too_long_or_not_a_count_is_refused_before_it_is_drawn(tmp_path, samples):
    spec = _write(tmp_path / "s.toml", SWEEP_AXIS.format(n=samples))
    err = _refused(["sweep", spec, "--out", str(tmp_path / "o")], tmp_path, "axes.environment.rain_rate_mm_h.samples")
    assert "100,000,000" in err
    assert not (tmp_path / "o").exists()


def test_a_grid_of_short_axes_above_the_point_limit_is_refused_before_it_is_drawn(tmp_path):
    keys = ("sensors.radar.p_tx_w", "sensors.radar.g_tx_db", "environment.rain_rate_mm_h")
    axes = "".join(f'"{k}" = {{min = 1.0, max = 2.0, samples = 1000}}\n' for k in keys)
    spec = _write(tmp_path / "s.toml", 'job = "range"\n[axes]\n' + axes + '"target.d_crit_m" = [0.1, 0.2]\n')
    err = _refused(["sweep", spec, "--out", str(tmp_path / "o")], tmp_path, "axes")
    assert "2,000,000,000 points" in err  # 1000 * 1000 * 1000 * 2, counted from the spec's numbers


def test_a_pd_sweep_of_5e7_points_is_refused_with_its_estimate(tmp_path):
    spec = _write(tmp_path / "s.toml", SWEEP_AXIS.format(n=50_000_000).replace('"range"', '"pd"'))
    err = _refused(["sweep", spec, "--out", str(tmp_path / "o")], tmp_path, "--max-seconds")
    assert "pd sweep of 50,000,000 points" in err and "days" in err


@pytest.mark.parametrize(
    "options, frequency", [("rays_per_wavelength = 1e9", 10.0), ('quality = "draft"', 10000.0)], ids=["density", "ghz"]
)
def test_the_sweep_rcs_job_estimates_its_tubes(tmp_path, options, frequency):
    spec = _write(
        tmp_path / "s.toml",
        f'job = "rcs"\n[options]\ntarget = "dji_mini_4_pro"\n{options}\n[axes]\nfrequency_ghz = [{frequency}]\n',
    )
    err = _refused(["sweep", spec, "--out", str(tmp_path / "o"), "--max-seconds", "30"], tmp_path, "--max-seconds")
    assert "tubes" in err


def test_ten_thousand_local_workers_are_refused_by_their_memory(tmp_path):
    args = ["sweep", "range_rain", "--out", str(tmp_path / "o"), "--workers", "10000"]
    err = _refused(args, tmp_path, "--max-memory-gb")
    assert "10000 worker(s)" in err


FRAME = 'name = "big"\n[sensors.eo]\nmodality = "eo"\nn_h = {n}\nn_v = {n}\n'


@pytest.mark.parametrize("pixels", [20_000, 100_000])
def test_a_huge_dataset_frame_is_refused_before_it_is_rendered(tmp_path, pixels):
    scenario = _write(tmp_path / "big.toml", FRAME.format(n=pixels))
    spec = _write(tmp_path / "d.toml", f'count = 1\nscenario = "{scenario}"\n')
    err = _refused(["dataset", spec, "--out", str(tmp_path / "o")], tmp_path, "--max-memory-gb")
    assert f"{pixels} x {pixels} px" in err


@pytest.mark.parametrize(
    "spec, images",
    [
        ("count = 1000000\n", "1,000,000 images"),
        ("count = 1000\nrange_m = [{r}]\nazimuth_deg = [{a}]\n", "1,000,000,000 images"),
    ],
    ids=["count", "grid"],
)
def test_a_dataset_of_too_many_images_is_refused_before_they_are_drawn(tmp_path, spec, images):
    text = spec.format(r=", ".join(str(100.0 + i) for i in range(1000)), a=", ".join(str(i / 10) for i in range(1000)))
    err = _refused(["dataset", _write(tmp_path / "d.toml", text), "--out", str(tmp_path / "o")], tmp_path, "--max")
    assert images in err


def _sparse_dem(path, cells: int) -> str:
    """A GeoTIFF header of ``cells`` x ``cells`` (no block written: a few kB on disk)."""
    import rasterio
    from rasterio.transform import from_origin

    profile = {"driver": "GTiff", "height": cells, "width": cells, "count": 1, "dtype": "float32"}
    transform = from_origin(500_000.0, 5_000_000.0 + 25.0 * cells, 25.0, 25.0)
    with rasterio.open(path, "w", crs="EPSG:32633", transform=transform, sparse_ok=True, tiled=True, **profile):
        pass
    return str(path)


SITE = 'scenario = "default"\naltitudes_agl_m = [{levels}]\n[sensors.radar]\nx = {x}\ny = {y}\n'


def test_a_20000_square_dem_is_refused_from_its_header(tmp_path):
    dem = _sparse_dem(tmp_path / "dem.tif", 20_000)
    site = _write(tmp_path / "site.toml", f'dem = "{dem}"\n' + SITE.format(levels="30.0", x=750_000.0, y=5_250_000.0))
    err = _refused(["coverage", site, "--out", str(tmp_path / "o")], tmp_path, "--max-")
    assert "20,000 x 20,000 cells" in err


def test_a_thousand_flight_levels_are_refused(tmp_path):
    """The demo terrain's three sensors (no radio map) at 1000 levels."""
    levels = ", ".join(str(10.0 + 5.0 * i) for i in range(1000))
    site = SITE.format(levels=levels, x=505_000.0, y=5_005_000.0)
    site += "[sensors.rf]\nx = 502500.0\ny = 5007000.0\n[sensors.eo]\nx = 507000.0\ny = 5003000.0\n"
    err = _refused(["coverage", _write(tmp_path / "site.toml", site), "--out", str(tmp_path / "o")], tmp_path, "--max")
    # 3 a sensor and level + 4 fused + 2 Fresnel (rf, radar), + min_altitude each, + 2 fused lowest heights
    assert "1000 flight level(s)" in err and "15,005 layers" in err


def test_rcs_statistics_with_an_absurd_aspect_budget_is_refused(tmp_path):
    err = _refused(["rcs-statistics", "--max-aspects", str(10**12)], tmp_path, "--max-seconds and --max-memory-gb")
    assert "1,000,000,000,000" in err


def test_a_refusal_names_every_limit_exceeded_in_one_line():
    args = Namespace(max_seconds=600.0, max_memory_gb=1.0)
    with pytest.raises(ParameterError) as caught:
        check_limits(Estimate("a test", 601.0, 1.5e9), args, "test")
    assert caught.value.name == "max_seconds"
    assert "10 min" in str(caught.value) and "1.5 GB" in str(caught.value)
    assert "--max-seconds and --max-memory-gb" in str(caught.value)
    check_limits(Estimate("a test", 599.0, 0.9e9), args, "test")  # inside both: nothing raised


@pytest.mark.parametrize("seconds, gb", [(math.nan, 1.0), (0.0, 1.0), (1.0, math.inf), (1.0, -2.0)])
def test_the_limits_themselves_are_checked(seconds, gb):
    with pytest.raises(ParameterError):
        limits_of(Namespace(max_seconds=seconds, max_memory_gb=gb))


def test_the_default_memory_limit_is_half_the_machine():
    total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    assert 0 < machine_memory_bytes() <= total
    assert limits_of(Namespace(max_seconds=1.0, max_memory_gb=None))[1] == pytest.approx(
        machine_memory_bytes() / 2e9, rel=1e-12
    )


def test_work_in_series_adds_times_and_keeps_the_larger_peak():
    both = Estimate("a", 2.0, 3e9) + Estimate("b", 5.0, 1e9)
    assert (both.seconds, both.bytes) == (7.0, 3e9)
