"""Benchmarks of the SBR-PO engine for ``csuas bench`` (docs/performance.md).

:func:`bench_sbr` measures, on the same mesh and machine,

* Mitsuba's raw ``scene.ray_intersect`` throughput (full surface
  interaction) and ``ray_intersect_preliminary`` throughput for a wide
  wavefront of parallel rays, and
* the SBR engine's rays x bounces per second (ray-scene queries per second of
  a warm launch, including tube generation, Fresnel reflection, the PO
  radiation integral and the sums),

and their ratio (docs/performance.md: "within a small factor of Mitsuba's raw throughput").
:func:`bench_memory` runs a large launch in bounded batches and reports the
peak resident memory.
"""

from __future__ import annotations

import resource
import time

import numpy as np

from csuas.core.units import wavelength_m
from csuas.render.rcs.engine import Jobs, SbrEngine, backend
from csuas.render.rcs.geometry import load_target


def _raw_throughput(engine: SbrEngine, n_rays: int, repeats: int) -> dict:
    """Rays per second of Mitsuba's intersection on parallel rays covering the target."""
    mi, dr = engine.mi, engine.dr
    radius = engine.target.bounding_radius_m
    side = int(np.sqrt(n_rays))
    g = (np.arange(side) + 0.5) / side * 2.0 * radius - radius
    u, v = np.meshgrid(g, g, indexing="ij")
    d = np.array([0.3, 0.5, -0.81])
    d /= np.linalg.norm(d)
    e1 = np.cross(d, [0.0, 0.0, 1.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(d, e1)
    o = -1.01 * radius * d + u.reshape(-1, 1) * e1 + v.reshape(-1, 1) * e2
    o = o.astype(np.float32)
    ray = mi.Ray3f(
        mi.Point3f(mi.Float(o[:, 0]), mi.Float(o[:, 1]), mi.Float(o[:, 2])), mi.Vector3f(*[float(x) for x in d])
    )
    out = {}
    for name, fn in (
        ("ray_intersect", engine.scene.ray_intersect),
        ("ray_intersect_preliminary", engine.scene.ray_intersect_preliminary),
    ):
        times = []
        for _ in range(repeats + 1):  # first call compiles
            start = time.perf_counter()
            res = fn(ray)
            if name == "ray_intersect":
                dr.eval(res.t, res.p, res.n, res.prim_index)
            else:
                dr.eval(res.t, res.prim_index)
            dr.sync_thread()
            times.append(time.perf_counter() - start)
        out[f"{name}_rays_per_s"] = side * side / min(times[1:])
    return out


def bench_sbr(
    target="dji_mini_4_pro",
    frequency_ghz: float = 24.0,
    rays_per_wavelength: float = 10.0,
    max_bounces: int = 5,
    n_aspects: int = 16,
    raw_rays: int = 1 << 20,
    repeats: int = 3,
) -> dict:
    """SBR rays x bounces per second against Mitsuba's raw intersection throughput.

    Parameters
    ----------
    target : mesh, file or preset name
        Default the DJI Mini 4 Pro model (PEC faces are not forced: part materials).
    frequency_ghz, rays_per_wavelength, max_bounces : float, float, int
        SBR settings of the timed launch.
    n_aspects : int
        Azimuths (elevation 20 deg) traced in one launch.
    raw_rays : int
        Rays of the raw-throughput measurement.
    repeats : int
        Timed repetitions (best is kept) after one warm-up.

    Returns
    -------
    dict
        ``variant``, ``sbr_rays_x_bounces_per_s``, ``sbr_tubes_per_s``,
        ``ray_intersect_rays_per_s``, ``ray_intersect_preliminary_rays_per_s``,
        ``ratio_sbr_to_ray_intersect``, ``ratio_sbr_to_preliminary``,
        ``sbr_trace_fraction`` (share of SBR time spent intersecting), launch size.
    """
    backend()
    engine = SbrEngine(load_target(target))
    az = np.linspace(0.0, 360.0, int(n_aspects), endpoint=False)
    jobs = Jobs.build(az, 20.0, frequency_ghz, rays_per_wavelength)
    best = None
    for _ in range(int(repeats) + 1):
        res = engine.trace(jobs, max_bounces)
        if best is None or res.time_s < best.time_s:
            best = res
    raw = _raw_throughput(engine, int(raw_rays), int(repeats))
    sbr = best.ray_casts / best.time_s
    return {
        "variant": engine.variant,
        "target": str(target),
        "frequency_ghz": frequency_ghz,
        "rays_per_wavelength": rays_per_wavelength,
        "max_bounces": max_bounces,
        "aspects": int(n_aspects),
        "tubes": int(best.tubes.sum()),
        "ray_casts": int(best.ray_casts),
        "sbr_time_s": best.time_s,
        "sbr_rays_x_bounces_per_s": sbr,
        "sbr_tubes_per_s": float(best.tubes.sum()) / best.time_s,
        "sbr_trace_fraction": best.trace_time_s / best.time_s,
        **raw,
        "ratio_sbr_to_ray_intersect": sbr / raw["ray_intersect_rays_per_s"],
        "ratio_sbr_to_preliminary": sbr / raw["ray_intersect_preliminary_rays_per_s"],
    }


def bench_memory(n_tubes: float = 1e8, batch_size: int | None = None) -> dict:
    """Trace about ``n_tubes`` tubes on a PEC plate and report time and peak memory.

    The tube count is reached by the density on a 1 m plate at 10 GHz (one
    aspect), so the whole launch is one job split into batches.

    Returns
    -------
    dict
        ``tubes``, ``batch_size``, ``time_s``, ``tubes_per_s``,
        ``peak_rss_gib`` (process high-water mark after the run) and
        ``peak_rss_before_gib``.
    """
    from csuas.render.rcs import canonical

    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    engine = SbrEngine(load_target(canonical.plate(1.0)), batch_size=batch_size)
    wavelength = float(wavelength_m(10.0))
    n = float(np.sqrt(n_tubes)) * wavelength / 1.0
    res = engine.trace(Jobs.build(0.0, 90.0, 10.0, n), 1)
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    return {
        "tubes": int(res.tubes.sum()),
        "batch_size": engine.batch_size,
        "time_s": res.time_s,
        "tubes_per_s": float(res.tubes.sum()) / res.time_s,
        "peak_rss_gib": after,
        "peak_rss_before_gib": before,
        "rcs_dbsm": float(10 * np.log10(res.sigma_m2[0, 0, 0, 0])),
        "exact_dbsm": float(10 * np.log10(4 * np.pi / wavelength**2)),
    }


def bench_po_accuracy(max_error_db: float = 0.5, densities=(5, 10, 20, 40, 80, 160), n_aspects: int = 8) -> list[dict]:
    """Rays, time and memory to reach ``max_error_db`` against exact PO, before and after the exact first hits.

    Targets: a PEC sphere at ka = 5 and ka = 20 (10 GHz) and the NASA almond at 9.92 GHz, ``n_aspects``
    random aspects each, VV and HH, against :func:`csuas.render.rcs.facet_po.facet_po_sigma_m2`.
    *Before*: tubes alone on one grid (``exact_first_hits=False``, the engine of Ling et al.), at
    increasing density until the largest error meets the target; *after*: the default engine at the
    draft density (2 rays per wavelength, one grid). ``peak_rss_gib`` is the process's high-water
    mark after the run (monotone: the after rows run first).

    Returns
    -------
    list of dict
        One row per target and engine: ``rays_per_wavelength`` reached (None if none did),
        ``max_error_db``, ``tubes``, ``ray_casts``, ``time_s`` (warm), ``peak_rss_gib``.
    """
    from csuas.render.rcs import canonical
    from csuas.render.rcs.facet_po import facet_po_sigma_m2

    rng = np.random.default_rng(3)
    az = rng.uniform(0.0, 360.0, n_aspects)
    el = np.degrees(np.arcsin(rng.uniform(-0.9, 0.9, n_aspects)))
    k = 2 * np.pi / float(wavelength_m(10.0))
    targets = {
        "sphere_ka5": (canonical.sphere(5.0 / k, 6), 10.0),
        "sphere_ka20": (canonical.sphere(20.0 / k, 6), 10.0),
        "almond_9.92GHz": (canonical.nasa_almond(), 9.92),
    }
    rows = []
    for name, (mesh, f) in targets.items():
        engine = SbrEngine(load_target(mesh))
        exact = facet_po_sigma_m2(mesh.vertices, mesh.faces, f, az, el)

        def measure(n, exact_first_hits, engine=engine, f=f, exact=exact, name=name):
            jobs = Jobs.build(az, el, f, float(n))
            engine.trace(jobs, 1, exact_first_hits=exact_first_hits)  # warm: kernels compiled
            res = engine.trace(jobs, 1, exact_first_hits=exact_first_hits)
            sigma = res.sigma_m2[:, 0, [0, 1], [0, 1]]
            error = float(np.max(np.abs(10 * np.log10(np.maximum(sigma, 1e-300) / exact[:, None]))))
            return {
                "target": name,
                "rays_per_wavelength": float(n),
                "max_error_db": error,
                "tubes": int(res.tubes.sum()),
                "ray_casts": int(res.ray_casts),
                "time_s": res.time_s,
                "peak_rss_gib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
            }

        rows.append({"engine": "after: exact first hits", **measure(2.0, True)})
        for n in densities:
            row = measure(n, False)
            if row["max_error_db"] <= max_error_db or n == densities[-1]:
                reached = row["max_error_db"] <= max_error_db
                rows.append({"engine": "before: tubes alone", **row, "reached": reached})
                break
    return rows
