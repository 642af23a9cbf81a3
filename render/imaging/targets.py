"""Canonical imaging targets with exact silhouettes (uniform graybody plates) for oracles and validation."""

from __future__ import annotations

import dataclasses

import trimesh

from csuas.base.errors import ParameterError
from csuas.drone_models import Part, get_material


def grey_material(reflectance: float = 0.5, emissivity: float = 0.68, temperature_k: float = 288.15):
    """A grey Lambertian graybody: one reflectance in all RGB channels, one emissivity in both thermal bands."""
    for name, value in (("reflectance", reflectance), ("emissivity", emissivity)):
        if not 0.0 <= value <= 1.0:
            raise ParameterError(name, value, "0 <= x <= 1")
    return dataclasses.replace(
        get_material("paint"),
        name="grey",
        reflectance_rgb=(reflectance,) * 3,
        reflectance_550nm=reflectance,
        emissivity_lwir=emissivity,
        emissivity_mwir=emissivity,
        temperature_k=temperature_k,
    )


def plate(width_m: float = 1.0, height_m: float = 1.0, thickness_m: float = 0.01, **material) -> list:
    """A thin closed box whose large faces are normal to body +x.

    Seen from azimuth 0, elevation 0 (docs/command-line.md) it shows ``width_m`` across
    (body y) and ``height_m`` up (body z); from azimuth 90 deg it is edge-on
    (``thickness_m`` across). ``material`` goes to :func:`grey_material`.
    """
    for name, value in (("width_m", width_m), ("height_m", height_m), ("thickness_m", thickness_m)):
        if not value > 0:
            raise ParameterError(name, value, "> 0 [m]")
    box = trimesh.creation.box((thickness_m, width_m, height_m))
    return [Part("plate", "body", box, grey_material(**material))]
