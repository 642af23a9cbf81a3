"""What a render mode is asked to render: the :class:`RenderRequest` of ``csuas render`` and the render sweeps.

A *render mode* (``csuas render eo|tir|lidar``, :data:`csuas.commands.render.MODES`) is a callable
``mode(scenario, request) -> list of dict`` returning one JSON-ready result per range with at least
the docs/command-line.md keys ``range_m``, ``pixels_on_target`` (or ``lcs_m2``), ``stderr``,
``time_s`` and ``files``; the request carries the command's options.
"""

from __future__ import annotations

from dataclasses import dataclass

#: Choices of the ``atmosphere`` option of a render request.
ATMOSPHERE_CHOICES = ("auto", "on", "off")
#: Choices of the ``atmosphere_method`` option: how an EO render's path is computed.
ATMOSPHERE_METHODS = ("auto", "analytic", "medium")


@dataclass(frozen=True)
class RenderRequest:
    """The options of one render mode's call.

    Attributes
    ----------
    ranges_m : float or sequence of float
        Slant ranges [m].
    quality : str
        Render quality preset (``draft``, ``standard``, ``reference``).
    azimuth_deg, elevation_deg : float
        Direction from the target toward the sensor [deg] (docs/command-line.md).
    out_dir : str or pathlib.Path or None
        Where to write each range's EXR and PNG; None: no files.
    seed : int
        Random seed (results are deterministic for a given seed).
    sensor : str or None
        Sensor name in the scenario; None: the scenario's first sensor of the mode's modality.
    atmosphere : {"auto", "on", "off"}
        The path (transmittance, airlight or path radiance): ``auto`` wherever ``csuas range`` applies
        one (:mod:`csuas.render.imaging.modes`).
    progress : text stream or callable or None
        Where progress goes; None: silent.
    exposure : {"scene", "auto"}
        EO previews only: a camera set for clear daylight (night looks dark), or the brightest pixel white.
    convention : {"paper", "physical"} or None
        The convention of the path (as ``csuas range --convention``); None: the scenario's.
    atmosphere_method : {"analytic", "medium", "auto"}
        EO only: the analytic path, Mitsuba's participating medium, or the medium where the analytic path is an
        approximation (:func:`csuas.render.imaging.medium_choice.choose_method`); ``csuas render`` asks ``auto``.
    """

    ranges_m: object
    quality: str = "standard"
    azimuth_deg: float = 0.0
    elevation_deg: float = 0.0
    out_dir: object = None
    seed: int = 0
    sensor: str | None = None
    atmosphere: str = "auto"
    progress: object = None
    exposure: str = "scene"
    convention: str | None = None
    atmosphere_method: str = "analytic"
