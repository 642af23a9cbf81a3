"""Lidar mode of ``csuas render``: the scenario's drone seen by its lidar at several ranges.

For each range the result holds

* the far-field LCS toward the sensor (``lcs_m2``, plane wave, the
  ``sigma_lidar`` of Eqs. 7-9 and 99) with its standard error, the exact
  projected area ``A_p`` of the same view (polygon union) and their ratio
  ``k_lcs_measured`` beside the paper's ``k_LCS = 0.1`` (Eq. 9);
* the LCS under the sensor's actual beam at that range
  (``lcs_illuminated_m2``): a point source at the true range (spherical
  wave) with a top-hat footprint of diameter ``D = R * 1.22 lambda / d``
  (Eqs. 87, 90) centred on the target, and the illuminated fraction of the
  projected area. The physical counterpart of Eq. 89 is
  ``I_laser = lcs_illuminated_m2 / A_illum``; with the default 3 mm aperture
  the footprint is 6.3 mm wide at 10 m, so only a spot of the drone returns
  light (docs/conventions.md point 8);
* an EXR and PNG map of the far-field LCS per pixel when ``out_dir`` is given.
"""

from __future__ import annotations

import math
import time

import numpy as np

from csuas.base.errors import ParameterError
from csuas.defaults import default_values
from csuas.render.files import file_stem
from csuas.render.lidar.cross_section import lidar_cross_section
from csuas.render.lidar.files import write_lcs_map
from csuas.render.lidar.sphere_average import K_LCS_PAPER
from csuas.render.lidar.target import LidarTarget
from csuas.render.request import ATMOSPHERE_CHOICES, RenderRequest

#: Diffraction-limited divergence factor of Eq. 87 (circular aperture).
AIRY_FACTOR = 1.22


def lidar_parameters(scenario, sensor: str | None = None) -> dict:
    """Lidar parameters of ``scenario``: its lidar sensor's, else the defaults of Table 45.

    Parameters
    ----------
    scenario : csuas.core.scenario.Scenario
    sensor : str, optional
        Name of a lidar sensor of the scenario; the first lidar sensor when omitted.
    """
    sensors = getattr(scenario, "sensors", {}) or {}
    lidars = {name: spec for name, spec in sensors.items() if getattr(spec, "modality", None) == "lidar"}
    if sensor is not None:
        if sensor not in lidars:
            raise ParameterError("sensor", sensor, ", ".join(lidars) or "no lidar sensor in the scenario")
        params = dict(lidars[sensor].params)
    elif lidars:
        params = dict(next(iter(lidars.values())).params)
    else:
        params = dict(default_values("lidar"))
    for key in ("wavelength_nm", "aperture_mm"):
        value = params.get(key)
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0.0):
            raise ParameterError(f"lidar.{key}", value, "x > 0")
    return params


def beam_diameter_m(range_m: float, wavelength_nm: float, aperture_mm: float) -> float:
    """Top-hat beam diameter at ``range_m`` [m]: ``R * 1.22 lambda / d`` (Eqs. 87, 90)."""
    return range_m * AIRY_FACTOR * wavelength_nm * 1e-9 / (aperture_mm * 1e-3)


def illuminated_fraction(view: dict, centre_m, beam_radius_m: float) -> float:
    """Fraction of the exact silhouette inside a beam disk centred on ``centre_m`` (the T_illum of Eq. 8).

    Parameters
    ----------
    view : dict
        :func:`csuas.drone_models.silhouette.projected_metrics` output
        (``silhouette`` polygon in image axes ``h_axis``, ``v_axis`` [m]).
    centre_m : array_like, shape (3,)
        Beam centre in the body frame [m].
    beam_radius_m : float
        Beam radius at the target [m].
    """
    import shapely

    silhouette = view["silhouette"]
    if silhouette is None or silhouette.area <= 0.0:
        return 0.0
    centre = shapely.Point(float(np.dot(centre_m, view["h_axis"])), float(np.dot(centre_m, view["v_axis"])))
    disk = centre.buffer(beam_radius_m, quad_segs=256)
    return float(silhouette.intersection(disk).area / silhouette.area)


def _check_ranges(ranges_m) -> np.ndarray:
    values = np.atleast_1d(np.asarray(ranges_m, dtype=float))
    if values.ndim != 1 or values.size == 0:
        raise ParameterError("range_m", ranges_m, "one or more ranges > 0 m")
    bad = ~np.isfinite(values) | (values <= 0.0)
    if np.any(bad):
        raise ParameterError("range_m", float(values[bad][0]), "finite x > 0 m")
    return values


def render_lidar(scenario, request: RenderRequest) -> list:
    """Lidar cross-section of the scenario's drone at each range, with errors, times and files.

    Parameters
    ----------
    scenario : csuas.core.scenario.Scenario
        Uses ``target_preset`` (a :func:`csuas.drone_models.build_drone`
        preset) and the lidar sensor's ``wavelength_nm`` and ``aperture_mm``.
    request : RenderRequest
        The render mode's options (:class:`csuas.render.request.RenderRequest`): ``ranges_m`` (finite,
        > 0 and beyond the drone's bounding sphere); ``quality``, the ray-sampling preset
        (:data:`csuas.render.lidar.QUALITY_PRESETS`); ``azimuth_deg``, ``elevation_deg``; ``out_dir``
        for an EXR and PNG map of the far-field LCS per pixel (no files without it); ``sensor``, which
        lidar sensor of the scenario; ``seed`` of the ray jitter; ``atmosphere``, accepted for the
        render-mode contract: the LCS is a property of the target, so no atmosphere enters it (the path
        transmission is the range equation's, Eqs. 100-104), and a note says so when ``"on"``;
        ``progress``: a stream gets one line per range, a callable is called as
        ``progress(index, count, message)``.

    Returns
    -------
    list of dict
        Per range: ``range_m``, ``lcs_m2``, ``stderr`` [m^2], ``time_s`` [s],
        ``files``, ``projected_area_m2`` (exact), ``k_lcs_measured``,
        ``k_lcs_paper``, ``lcs_rule_m2`` (``k_LCS * A_p``, Eq. 9),
        ``beam_diameter_m``, ``illuminated_fraction``,
        ``lcs_illuminated_m2``, ``lcs_illuminated_stderr``, ``rays``,
        ``quality``, ``method``, ``wavelength_nm``, ``azimuth_deg``,
        ``elevation_deg``, ``notes`` (list of str).
    """
    from csuas.drone_models import build_drone
    from csuas.drone_models.silhouette import projected_metrics

    ranges = _check_ranges(request.ranges_m)
    if request.atmosphere not in ATMOSPHERE_CHOICES:
        raise ParameterError("atmosphere", request.atmosphere, ", ".join(ATMOSPHERE_CHOICES))
    params = lidar_parameters(scenario, request.sensor)
    sensors = getattr(scenario, "sensors", {}) or {}
    lidars = [n for n, s in sensors.items() if getattr(s, "modality", None) == "lidar"]
    labels = {"scenario": scenario.name, "sensor": request.sensor or (lidars[0] if lidars else "table45")}
    notes = _lidar_notes(bool(lidars), request.atmosphere)
    drone = build_drone(getattr(scenario, "target_preset", None))
    labels["target"] = drone.name
    target = LidarTarget.from_drone(drone, params["wavelength_nm"])
    view = projected_metrics(drone, request.azimuth_deg, request.elevation_deg)
    results = []
    for index, range_m in enumerate(ranges):
        start = time.perf_counter()
        row, far = _range_row(target, view, params, range_m, request)
        if request.out_dir is not None:
            row["files"] = _lcs_map_files(far, range_m, labels, params, request)
        row["time_s"] = time.perf_counter() - start
        row["notes"] = list(notes)
        results.append(row)
        message = f"lidar {range_m:g} m: LCS {far.lcs_m2:.4g} m^2 ({time.perf_counter() - start:.2f} s)"
        if callable(request.progress):
            request.progress(index + 1, len(ranges), message)
        elif request.progress is not None:
            request.progress.write(f"[{index + 1}/{len(ranges)}] {message}\n")
            request.progress.flush()
    return results


def _lidar_notes(has_lidar: bool, atmosphere: str) -> list:
    """Notes of every range: Table 45's defaults without a lidar sensor; an atmosphere asked for but not applied."""
    notes = []
    if not has_lidar:
        notes.append("no lidar sensor in the scenario: Table 45 defaults (1550 nm, 3 mm aperture)")
    if atmosphere == "on":
        notes.append(
            "atmosphere not applied: the LCS is a target property; path transmission belongs to the "
            "lidar range equation (Eqs. 100-104)"
        )
    return notes


def _range_row(target: LidarTarget, view: dict, params: dict, range_m, request: RenderRequest) -> tuple:
    """One range's row (``time_s``, ``files`` and ``notes`` still to fill) and its far-field :class:`LcsResult`.

    The far-field LCS (its image kept when files are written) and the LCS under the sensor's beam at
    the range, beside the exact projected area and the paper's rule k_LCS A_p (Eq. 9).
    """
    az, el, quality, seed = request.azimuth_deg, request.elevation_deg, request.quality, request.seed
    far = lidar_cross_section(target, az, el, math.inf, quality, seed=seed, keep_image=request.out_dir is not None)
    diameter = beam_diameter_m(range_m, params["wavelength_nm"], params["aperture_mm"])
    near = lidar_cross_section(target, az, el, range_m, quality, seed=seed + 1, beam_radius_m=0.5 * diameter)
    fraction = illuminated_fraction(view, target.centre_m, 0.5 * diameter)
    area = view["projected_area_m2"]
    row = {
        "range_m": float(range_m),
        "lcs_m2": far.lcs_m2,
        "stderr": far.stderr_m2,
        "time_s": None,
        "files": [],
        "projected_area_m2": area,
        "k_lcs_measured": far.lcs_m2 / area if area > 0.0 else 0.0,
        "k_lcs_paper": K_LCS_PAPER,
        "lcs_rule_m2": K_LCS_PAPER * area,
        "beam_diameter_m": diameter,
        "illuminated_fraction": fraction,
        "lcs_illuminated_m2": near.lcs_m2,
        "lcs_illuminated_stderr": near.stderr_m2,
        "rays": far.rays + near.rays,
        "quality": far.quality,
        "method": "single_bounce",
        "wavelength_nm": float(params["wavelength_nm"]),
        "azimuth_deg": float(az),
        "elevation_deg": float(el),
        "notes": [],
    }
    return row, far


def _lcs_map_files(far, range_m, labels: dict, params: dict, request: RenderRequest) -> list:
    """The far-field LCS per pixel as EXR and PNG in the request's ``out_dir``, with its metadata.

    ``labels``: the ``scenario``, ``sensor`` and ``target`` names of the file's stem and metadata.
    """
    az, el, quality, seed = request.azimuth_deg, request.elevation_deg, request.quality, request.seed
    pixel = (far.window_m[1] - far.window_m[0]) / far.image_m2.shape[1]
    stem = file_stem(labels["scenario"], labels["sensor"], "lidar", range_m, az, el, quality, seed)
    rows, columns = far.image_m2.shape
    return write_lcs_map(
        request.out_dir,
        stem,
        far.image_m2,
        {
            "modality": "lidar",
            "target": labels["target"],
            "scenario": labels["scenario"],
            "sensor": labels["sensor"],
            "band": f"{params['wavelength_nm']:g} nm",
            "units": "m^2 per pixel",
            "channels": "Y",
            "quality": str(far.quality),
            "seed": seed,
            "frame_width_px": columns,
            "frame_height_px": rows,
            "range_m": float(range_m),
            "azimuth_deg": float(az),
            "elevation_deg": float(el),
            "ifov_rad": pixel / range_m,
            "quantity": "lidar cross-section per pixel (far field)",
            "pixel_size_m": pixel,
            "lcs_m2": far.lcs_m2,
            "stderr_m2": far.stderr_m2,
        },
    )
