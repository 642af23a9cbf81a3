"""Radio materials of the SBR-PO radar cross-section engine.

A surface is a perfect electric conductor (PEC), or a lossy dielectric of
complex relative permittivity

    eps_c(f) = eps' - j (eps'' + sigma / (omega eps0))            (e^{+j omega t})

either as a half-space (``thickness_m`` None: Fresnel reflection, the
transmitted wave is absorbed) or as a thin shell of ``thickness_m`` (a slab:
Fabry-Perot reflection and transmission coefficients; the transmitted tube
continues straight on, so the inside of a plastic body is illuminated)
(:mod:`csuas.render.rcs.engine`).

Drone presets: dielectric parts (conductivity below 1 S/m: plastics, paint)
are shells of :data:`DRONE_SHELL_THICKNESS_M` (2 mm, a typical injection-moulded
wall of a class-1 airframe), conductors (carbon fibre, aluminium, battery
cans) are half-spaces: their skin depth at 1 GHz is below 0.2 mm.

Named ITU materials (ITU-R P.2040-3 Table 3: ``"concrete"``, ``"metal"``,
``"wood"``, ...; also accepted with an ``itu_`` prefix as in Sionna RT) are
evaluated with Sionna RT's own implementation,
``sionna.rt.radio_materials.itu.itu_material`` (eps' = a f^b, sigma = c f^d,
f in GHz). Drone part materials (``csuas.drone_models`` ``Material``) are
accepted as they are, by their fields ``relative_permittivity``,
``conductivity_s_m`` and ``is_pec``.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core.dielectric import complex_permittivity

#: Wall thickness given to the dielectric parts of drone presets [m].
DRONE_SHELL_THICKNESS_M = 0.002

#: Conductivity below which a drone part is a dielectric shell rather than a conductor [S/m].
SHELL_MAX_CONDUCTIVITY_S_M = 1.0


@dataclass(frozen=True)
class RadioMaterial:
    """Electromagnetic description of a surface for the SBR engine.

    Attributes
    ----------
    name : str
        Identifier, reported in results.
    relative_permittivity : complex
        ``eps' - j eps''`` without the conduction term [-].
    conductivity_s_m : float
        Bulk conductivity [S/m] (0 for a loss-free dielectric).
    is_pec : bool
        Perfect electric conductor (Fresnel coefficients -1 and +1).
    itu_name : str or None
        ITU-R P.2040 material name when the parameters depend on frequency
        through Sionna RT's ITU model; then ``relative_permittivity`` and
        ``conductivity_s_m`` are ignored.
    thickness_m : float or None
        Thin-shell (slab) thickness [m]; None for a half-space.
    """

    name: str
    relative_permittivity: complex = 1.0 + 0.0j
    conductivity_s_m: float = 0.0
    is_pec: bool = False
    itu_name: str | None = None
    thickness_m: float | None = None

    def with_thickness(self, thickness_m: float | None) -> RadioMaterial:
        """A copy as a shell of ``thickness_m`` [m] (None or 0: half-space); PEC stays PEC."""
        if thickness_m is not None and not (np.isfinite(thickness_m) and thickness_m >= 0):
            raise ParameterError("shell_thickness_m", thickness_m, "x >= 0 m (0 or None: half-space)")
        if self.is_pec:
            return self
        return dataclasses.replace(self, thickness_m=float(thickness_m) if thickness_m else None)

    def complex_permittivity(self, frequency_ghz: float) -> complex:
        """Total relative permittivity ``eps - j sigma/(omega eps0)`` at ``frequency_ghz`` [GHz].

        Raises
        ------
        ParameterError
            For a PEC (it has no finite permittivity) or a frequency outside the
            ITU model's validity range.
        """
        if self.is_pec:
            raise ParameterError(
                f"material.{self.name}.complex_permittivity",
                self.name,
                "a dielectric material (PEC has no finite permittivity)",
            )
        eps = complex(self.relative_permittivity)
        sigma = float(self.conductivity_s_m)
        if self.itu_name is not None:
            eps_real, sigma = _itu_parameters(self.itu_name, frequency_ghz)
            eps = complex(eps_real, 0.0)
        return complex(complex_permittivity(eps, sigma, frequency_ghz))


PEC = RadioMaterial("pec", is_pec=True)


def _sionna_itu():
    """Sionna RT's ITU material module, leaving the active Mitsuba variant as it was.

    ``sionna.rt`` is imported through :func:`csuas.render.links.sionna_backend.load_sionna_rt`,
    which must choose Sionna's variant before the first import (an import on another variant
    would make the Sionna RT links of the same process fail); the caller's variant is then restored.
    """
    import mitsuba as mi

    from csuas.render.backend import BackendError, use_variant
    from csuas.render.links.sionna_backend import load_sionna_rt

    previous = mi.variant()
    try:
        load_sionna_rt()
    except BackendError:  # sionna.rt was imported before, outside csuas: use it as it is
        pass
    if previous is not None and mi.variant() != previous:
        use_variant(variant=previous)
    from sionna.rt.radio_materials import itu

    return itu


def itu_material_names() -> list[str]:
    """Names of the ITU-R P.2040 materials Sionna RT provides."""
    return sorted(_sionna_itu().ITU_MATERIALS_PROPERTIES)


def _itu_parameters(name: str, frequency_ghz: float) -> tuple[float, float]:
    """(eps', sigma [S/m]) of ITU material ``name`` at ``frequency_ghz`` via Sionna RT."""
    try:
        eps_r, sigma = _sionna_itu().itu_material(name, frequency_ghz * 1e9)
    except ValueError as exc:
        raise ParameterError("material", f"itu_{name} at {frequency_ghz} GHz", str(exc)) from None
    return float(eps_r), float(sigma)


def _drone_material_names() -> dict:
    try:
        from csuas.drone_models.materials import MATERIALS
    except ImportError:  # the drone models are optional for the RCS engine
        return {}
    return dict(MATERIALS)


def resolve_material(spec) -> RadioMaterial:
    """Turn a material specification into a :class:`RadioMaterial`.

    Parameters
    ----------
    spec : str, RadioMaterial, or object with ``relative_permittivity``,
        ``conductivity_s_m`` and ``is_pec``
        ``"pec"``; an ITU-R P.2040 name (``"concrete"`` or ``"itu_concrete"``);
        a drone material name (``"plastic"``, ``"carbon_fibre"``, ...); a
        ``complex`` relative permittivity; or a material object.

    Raises
    ------
    ParameterError
        Unknown name, or a non-passive material (positive imaginary part of
        the permittivity, i.e. gain, or negative conductivity).
    """
    if isinstance(spec, RadioMaterial):
        material = spec
    elif isinstance(spec, str):
        key = spec.strip().lower()
        if key == "pec":
            return PEC
        itu = key[4:] if key.startswith("itu_") else key
        drone = _drone_material_names()
        if key in drone:
            material = resolve_material(drone[key])
        elif itu in itu_material_names():
            return RadioMaterial(f"itu_{itu}", itu_name=itu)
        else:
            allowed = list(dict.fromkeys(["pec"] + sorted(drone) + [f"itu_{n}" for n in itu_material_names()]))
            raise ParameterError("material", spec, ", ".join(allowed))
    elif isinstance(spec, complex):
        material = RadioMaterial(f"eps_{spec.real:g}{spec.imag:+g}j", relative_permittivity=spec)
    elif all(hasattr(spec, a) for a in ("relative_permittivity", "conductivity_s_m", "is_pec")):
        material = RadioMaterial(
            getattr(spec, "name", "material"),
            complex(spec.relative_permittivity),
            float(spec.conductivity_s_m),
            bool(spec.is_pec),
        )
    else:
        raise ParameterError(
            "material", spec, "'pec', an ITU or drone material name, a complex permittivity, or a material object"
        )
    if material.is_pec or math.isinf(material.conductivity_s_m):
        return RadioMaterial(material.name, is_pec=True)
    if material.relative_permittivity.imag > 0 or material.conductivity_s_m < 0:
        raise ParameterError(
            f"material.{material.name}",
            (material.relative_permittivity, material.conductivity_s_m),
            "Im(eps) <= 0 (e^{+j omega t} convention) and conductivity >= 0 S/m",
        )
    return material
