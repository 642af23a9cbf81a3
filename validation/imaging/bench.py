"""Benchmark: window around the target against the full sensor frame (docs/performance.md).

Both renders use the same sensor, target, range and samples per pixel; the
window samples only the box that contains the target's image, the full frame
samples every pixel. The figures must agree within their Monte Carlo
errors; the time ratio window / full frame is the benchmark (target: 1 % or
less for the default 1920 x 1080 EO sensor).
"""

from __future__ import annotations

import math
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
    import time

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
            "dji_mini_4_pro", View(range_m, (37.0 * i) % 360.0, 5.0), EoSensor(), Daylight(), camera, chain, seed=i
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
