"""Benchmark: window around the target against the full sensor frame (docs/performance.md).

Both renders use the same sensor, target, range and samples per pixel; the
window samples only the box that contains the target's image, the full frame
samples every pixel. The figures must agree within their Monte Carlo
errors; the time ratio window / full frame is the benchmark (target: 1 % or
less for the default 1920 x 1080 EO sensor).
"""

from __future__ import annotations

import math
import os
import time
from dataclasses import replace

from csuas.render.imaging.eo import render_eo
from csuas.render.imaging.quality import resolve_quality
from csuas.render.imaging.records import EoSensor, RenderSettings, View
from csuas.render.imaging.scene import target_parts


def bench_window_vs_full_frame(
    target="dji_mini_4_pro",
    *,
    range_m: float = 1000.0,
    hfov_deg: float = 10.0,
    n_h: int = 1920,
    n_v: int = 1080,
    quality="draft",
    seed: int = 0,
) -> dict:
    """Time and pixels-on-target of the window and of the full frame.

    Returns
    -------
    dict
        ``window_time_s``, ``full_frame_time_s``, ``time_ratio`` (window /
        full), ``pixels_on_target_window`` and ``_full_frame`` with their
        standard errors, ``difference_sigma`` (difference over the combined
        standard error), ``window_px`` and ``full_frame_px``.
    """
    q = resolve_quality(quality)
    target = target_parts(target)  # build the mesh once: the benchmark compares rendering, not mesh generation
    view, sensor = View(range_m), EoSensor(hfov_deg=hfov_deg, n_h=n_h, n_v=n_v)
    settings = RenderSettings(quality=q, seed=seed)
    render_eo(target, view, sensor, settings=settings)  # compile kernels outside the timing
    window = min(  # best of 3 (ms-scale)
        (render_eo(target, view, sensor, settings=settings) for _ in range(3)), key=lambda r: r.time_s
    )
    full = render_eo(target, view, sensor, settings=replace(settings, full_frame=True))
    pw, pf = window.values["pixels_on_target"], full.values["pixels_on_target"]
    sw, sf = window.stderr["pixels_on_target"], full.stderr["pixels_on_target"]
    combined = math.hypot(sw, sf)
    return {
        "range_m": range_m,
        "sensor_px": [n_h, n_v],
        "samples_per_pixel": q.spp,
        "window_px": window.window.n_pixels,
        "full_frame_px": full.window.n_pixels,
        "window_time_s": window.time_s,
        "full_frame_time_s": full.time_s,
        "time_ratio": window.time_s / full.time_s,
        "pixels_on_target_window": pw,
        "pixels_on_target_window_stderr": sw,
        "pixels_on_target_full_frame": pf,
        "pixels_on_target_full_frame_stderr": sf,
        "difference_sigma": abs(pw - pf) / combined if combined > 0 else (0.0 if pw == pf else math.inf),
    }


def bench_frames(n_frames: int = 10, range_m: float = 300.0) -> dict:
    """Full 1920 x 1080 EO frames with the whole chain at draft quality: frames per second and where time goes.

    Each frame renders the DJI Mini 4 Pro's window at a new aspect (as a dataset does), exposes it and runs
    the chain (psf, shot noise, dark current, PRNU, DSNU, read noise, quantise); the first frame, which
    compiles the render kernels, is left out. ``peak_rss_gib`` is the process's high-water mark after the run,
    ``peak_rss_growth_gib`` its rise after the second frame (flat memory: about 0).
    """
    import resource

    from csuas.render.imaging.frame import camera_from_params, eo_frame
    from csuas.render.imaging.records import Daylight
    from csuas.render.imaging.sensor_chain import ChainSettings

    camera = camera_from_params()
    eo_stages = ("psf", "shot_noise", "dark_current", "prnu", "dsnu", "read_noise", "quantise")
    chain = ChainSettings(stages=eo_stages, prnu=0.005, dsnu_e=1.0)
    render_s, chain_s, rss_after_first = 0.0, 0.0, 0.0
    for i in range(int(n_frames) + 1):
        start = time.perf_counter()
        out = eo_frame(
            "dji_mini_4_pro",
            View(range_m, (37.0 * i) % 360.0, 5.0),
            EoSensor(),
            Daylight(),
            camera,
            chain,
            settings=RenderSettings(quality="draft", seed=i),
        )
        total = time.perf_counter() - start
        if i:
            render_s += out["result"].time_s
            chain_s += total - out["result"].time_s
        if i == 1:
            rss_after_first = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    return {
        "frames": int(n_frames),
        "frames_per_s": n_frames / (render_s + chain_s),
        "render_s_per_frame": render_s / n_frames,
        "camera_and_chain_s_per_frame": chain_s / n_frames,
        "peak_rss_gib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
        "peak_rss_growth_gib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20 - rss_after_first,
    }


def _dataset_rate(name: str, n_frames: int, normal_above_e: float, out_dir) -> dict:
    """Frames per second of an embedded dataset spec end to end (render, chain, PNGs, previews, labels)."""
    import resource
    from dataclasses import replace

    from csuas.render.imaging.dataset import generate, load_dataset_spec

    spec = replace(load_dataset_spec(name), normal_shot_noise_above_e=normal_above_e)
    if spec.sequence is not None:
        spec = replace(spec, sequence=replace(spec.sequence, frames=n_frames))
    else:
        spec = replace(spec, count=n_frames)
    cpu_start = time.process_time()
    summary = generate(spec, out_dir)
    return {
        "dataset": name,
        "shot_noise": "poisson" if normal_above_e == math.inf else f"normal above {normal_above_e:g} e",
        "frames": summary["rendered"],
        "frames_per_s": summary["rendered"] / summary["time_s"],
        "cpu_s_per_frame": (time.process_time() - cpu_start) / summary["rendered"],
        "load_average": os.getloadavg()[0],
        "peak_rss_gib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
    }


def _best_time_s(work, repeats: int = 3, clock=time.process_time) -> float:
    """The shortest of ``repeats`` runs of ``work`` after a first one, by ``clock`` (default: this process's CPU time,
    which other processes on a shared machine do not inflate)."""
    work()
    best = math.inf
    for _ in range(repeats):
        start = clock()
        work()
        best = min(best, clock() - start)
    return best


def _chain_levers() -> list:
    """The sensor chain's levers on one 1920 x 1080 frame: FFT precision and shot-noise draw (best of 3, CPU
    seconds), and 16-bit PNG writing by one or two threads (wall seconds per frame over 4 frames)."""
    import io
    from concurrent.futures import ThreadPoolExecutor

    import numpy as np
    from PIL import Image
    from scipy import fft

    rng = np.random.default_rng(0)
    mean = rng.uniform(4000.0, 6000.0, (1080, 1920))
    transfer = rng.uniform(0.0, 1.0, (1080, 961))
    single, transfer32 = mean.astype(np.float32), transfer.astype(np.float32)
    fft64 = _best_time_s(lambda: np.fft.irfft2(np.fft.rfft2(mean) * transfer, s=mean.shape))
    fft32 = _best_time_s(lambda: fft.irfft2(fft.rfft2(single) * transfer32, s=mean.shape))
    poisson = _best_time_s(lambda: rng.poisson(mean))
    normal = _best_time_s(lambda: np.rint(mean + np.sqrt(mean) * rng.standard_normal(mean.shape, dtype=np.float32)))
    frames = [(rng.poisson(mean) * 16).astype(np.uint16) for _ in range(4)]

    def write(pixels):
        Image.fromarray(pixels).save(io.BytesIO(), format="PNG", compress_level=1)

    rates = {}
    for writers in (1, 2):
        with ThreadPoolExecutor(max_workers=writers) as pool:
            elapsed = _best_time_s(lambda: list(pool.map(write, frames)), repeats=1, clock=time.perf_counter)
            rates[writers] = elapsed / len(frames)
    return [
        {"lever": "blur FFT", "numpy_float64_s": fft64, "scipy_float32_s": fft32, "speedup": fft64 / fft32},
        {"lever": "shot noise", "poisson_s": poisson, "normal_s": normal, "speedup": poisson / normal},
        {"lever": "16-bit PNG", "one_writer_s": rates[1], "two_writers_s": rates[2], "speedup": rates[1] / rates[2]},
    ]


def bench_dataset_rates(n_frames: int = 10) -> list:
    """Frames per second of ``csuas dataset`` end to end: the embedded single-frame ``example`` and the
    ``sequence`` spec (rolling shutter and motion), each with the exact Poisson shot noise and with its
    normal approximation above 1000 e, and the cluttered scene ``example-cluttered`` (terrain, skyline, a power
    line, soft clouds, confusers; Poisson) (wall frames per second, CPU seconds per frame of this process, all
    its threads, and the machine's load average, since a shared machine slows the wall clock); then the
    chain's levers one by one (:func:`_chain_levers`). A first frame, which compiles the render kernels,
    runs before the timing."""
    import tempfile

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        _dataset_rate("sequence", 1, math.inf, f"{tmp}/warm")
        for name in ("example", "sequence"):
            for normal_above_e in (math.inf, 1000.0):
                rows.append(_dataset_rate(name, n_frames, normal_above_e, f"{tmp}/{name}_{normal_above_e:g}"))
        rows.append(_dataset_rate("example-cluttered", n_frames, math.inf, f"{tmp}/cluttered"))
    return rows + _chain_levers()
