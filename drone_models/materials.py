"""Surface materials of drone parts: optical, thermal and radio properties.

Every part of a drone model carries one :class:`Material`. The values are
nominal, broadband figures meant for signature simulation, each with its
source:

* Thermal emissivities are the mid-points of the ranges the paper lists for
  the main components of commercial sUAS (Section 4.4.3, Table 27): plastic
  0.9-1 [114], carbon fibre 0.8-0.84 [115], aluminium 0.05-0.1 [116],
  paint 0.8-0.95 [114]. The unweighted mean of those four mid-points is the
  paper's ``epsilon_sUAS = 0.68`` (:func:`paper_component_mean_emissivity`).
  The same figures are used for LWIR (8-12 um) and MWIR (3-5 um) unless a
  better value is known (bare aluminium is slightly less emissive in MWIR).
* Temperatures default to the paper's ``T_sUAS = 288.15 K`` (Table 8).
* Radio properties are complex relative permittivity ``eps' - j eps''`` and
  bulk conductivity at about 1-30 GHz: ABS/polycarbonate eps' ~ 2.8,
  tan(delta) ~ 0.01 (Riddle, Baker-Jarvis & Krupka, IEEE T-MTT 51(3), 2003);
  carbon-fibre laminate ~1e4 S/m in-plane (Holloway, Sarto & Johansson, IEEE
  T-EMC 47(4):833, 2005: 1e3-1e5 S/m; a good conductor at GHz); aluminium
  3.5e7 S/m (CRC Handbook); copper 5.8e7 S/m (IACS annealed copper, CRC
  Handbook) for a circuit board's ground plane and the wiring; FR-4 eps' 4.4,
  tan(delta) 0.02 (Djordjevic et al., IEEE T-EMC 43(4):662, 2001: 4.3-4.5 to
  a few GHz); the Li-ion battery's pouch cells are sealed in an aluminium
  laminate (a ~40 um foil, some 20 skin depths at 2.4 GHz): a conductor of
  aluminium's conductivity; paint as a thin lossy dielectric over its
  substrate.
* Parts inside the airframe (circuit board, wiring, camera module: a drone's
  ``internal_parts``) are seen by the radar only, through the dielectric
  shell; their optical and thermal figures are given for completeness.
* Optical reflectances are diffuse (Lambertian) albedos at 550 nm and
  1550 nm and linear sRGB triples for previews; grey plastics from
  DJI's light-grey finish, black carbon composite, bare aluminium.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from csuas.base.errors import ParameterError
from csuas.core.dielectric import complex_permittivity

#: Default part temperature [K], the paper's T_sUAS (Table 8).
T_SUAS_K = 288.15


@dataclass(frozen=True)
class Material:
    """Optical, thermal and radio description of a part surface.

    Attributes
    ----------
    name : str
        Identifier, e.g. ``"plastic"``.
    reflectance_rgb : tuple of float
        Diffuse albedo in linear sRGB primaries [0..1].
    reflectance_550nm, reflectance_1550nm : float
        Diffuse albedo at 550 nm (EO) and 1550 nm (lidar) [0..1].
    emissivity_lwir, emissivity_mwir : float
        Band-averaged hemispherical emissivity, 8-12 um and 3-5 um [0..1].
    temperature_k : float
        Surface temperature [K].
    relative_permittivity : complex
        Dielectric part ``eps' - j eps''`` at radio frequencies [-], without
        the conduction term (ignored when ``is_pec``).
    conductivity_s_m : float
        Bulk conductivity [S/m]; :meth:`complex_permittivity` adds its
        ``-j sigma / (omega eps0)`` term.
    is_pec : bool
        Treat as a perfect electric conductor in radar/RF solvers.
    source : str
        Where the numbers come from.
    """

    name: str
    reflectance_rgb: tuple
    reflectance_550nm: float
    reflectance_1550nm: float
    emissivity_lwir: float
    emissivity_mwir: float
    temperature_k: float
    relative_permittivity: complex
    conductivity_s_m: float
    is_pec: bool
    source: str = ""

    def __post_init__(self):
        for field_name in ("reflectance_550nm", "reflectance_1550nm", "emissivity_lwir", "emissivity_mwir"):
            value = getattr(self, field_name)
            if not 0.0 <= value <= 1.0:
                raise ParameterError(f"material.{self.name}.{field_name}", value, "0 <= x <= 1")
        if len(self.reflectance_rgb) != 3 or not all(0.0 <= c <= 1.0 for c in self.reflectance_rgb):
            raise ParameterError(
                f"material.{self.name}.reflectance_rgb", self.reflectance_rgb, "three values in [0, 1]"
            )
        if not self.temperature_k > 0.0:
            raise ParameterError(f"material.{self.name}.temperature_k", self.temperature_k, "x > 0 K")
        if self.conductivity_s_m < 0.0:
            raise ParameterError(f"material.{self.name}.conductivity_s_m", self.conductivity_s_m, "x >= 0 S/m")

    def complex_permittivity(self, frequency_ghz: float) -> complex:
        """Total relative permittivity ``eps - j sigma / (omega eps0)`` at ``frequency_ghz`` [GHz].

        Infinite conductivity (PEC) gives ``-inf j``; radar solvers test ``is_pec`` first.
        """
        if not frequency_ghz > 0.0:
            raise ParameterError("frequency_ghz", frequency_ghz, "x > 0 GHz")
        return complex(complex_permittivity(self.relative_permittivity, self.conductivity_s_m, frequency_ghz))

    def with_temperature(self, temperature_k: float) -> Material:
        """A copy of this material at another surface temperature [K]."""
        return dataclasses.replace(self, temperature_k=float(temperature_k))


PLASTIC = Material(
    name="plastic",
    reflectance_rgb=(0.42, 0.42, 0.43),
    reflectance_550nm=0.42,
    reflectance_1550nm=0.45,
    emissivity_lwir=0.95,
    emissivity_mwir=0.93,
    temperature_k=T_SUAS_K,
    relative_permittivity=complex(2.8, -0.03),
    conductivity_s_m=0.0,
    is_pec=False,
    source="emissivity 0.9-1 (paper 4.4.3 [114]); ABS/PC eps' 2.8, tan d 0.01 (Riddle, Baker-Jarvis & Krupka, "
    "IEEE T-MTT 51(3):727, 2003, common plastics; ABS eps' 2.6-3.0 as commonly quoted)",
)

DARK_PLASTIC = Material(
    name="dark_plastic",
    reflectance_rgb=(0.05, 0.05, 0.05),
    reflectance_550nm=0.05,
    reflectance_1550nm=0.06,
    emissivity_lwir=0.95,
    emissivity_mwir=0.93,
    temperature_k=T_SUAS_K,
    relative_permittivity=complex(2.8, -0.03),
    conductivity_s_m=0.0,
    is_pec=False,
    source="black propeller/gimbal plastic; emissivity as plastic (paper 4.4.3 [114]); radio as ABS/PC, eps' 2.8, "
    "tan d 0.01 (Riddle, Baker-Jarvis & Krupka, IEEE T-MTT 51(3):727, 2003)",
)

CARBON_FIBRE = Material(
    name="carbon_fibre",
    reflectance_rgb=(0.05, 0.05, 0.05),
    reflectance_550nm=0.05,
    reflectance_1550nm=0.06,
    emissivity_lwir=0.82,
    emissivity_mwir=0.82,
    temperature_k=T_SUAS_K,
    relative_permittivity=complex(12.0, 0.0),
    conductivity_s_m=1.0e4,
    is_pec=False,
    source="emissivity 0.8-0.84 (paper 4.4.3 [115]); CFRP in-plane conductivity ~1e4 S/m (1e3-1e5 S/m: "
    "Holloway, Sarto & Johansson, IEEE T-EMC 47(4):833, 2005)",
)

ALUMINIUM = Material(
    name="aluminium",
    reflectance_rgb=(0.70, 0.70, 0.72),
    reflectance_550nm=0.70,
    reflectance_1550nm=0.85,
    emissivity_lwir=0.075,
    emissivity_mwir=0.07,
    temperature_k=T_SUAS_K,
    relative_permittivity=complex(1.0, 0.0),
    conductivity_s_m=3.5e7,
    is_pec=False,
    source="emissivity 0.05-0.1 (paper 4.4.3 [116]); conductivity 3.5e7 S/m (CRC Handbook)",
)

ANODISED_ALUMINIUM = Material(
    name="anodised_aluminium",
    reflectance_rgb=(0.06, 0.06, 0.07),
    reflectance_550nm=0.06,
    reflectance_1550nm=0.10,
    emissivity_lwir=0.82,
    emissivity_mwir=0.80,
    temperature_k=T_SUAS_K,
    relative_permittivity=complex(1.0, 0.0),
    conductivity_s_m=3.5e7,
    is_pec=False,
    source="black-anodised motor bell: emissivity 0.82 near 300 K (Incropera et al., Fundamentals of Heat and "
    "Mass Transfer, Table A.11; MWIR 0.80 assumed); the micrometre oxide leaves aluminium's 3.5e7 S/m at GHz",
)

PAINT = Material(
    name="paint",
    reflectance_rgb=(0.45, 0.45, 0.46),
    reflectance_550nm=0.45,
    reflectance_1550nm=0.50,
    emissivity_lwir=0.875,
    emissivity_mwir=0.85,
    temperature_k=T_SUAS_K,
    relative_permittivity=complex(3.0, -0.1),
    conductivity_s_m=0.0,
    is_pec=False,
    source="emissivity 0.8-0.95 (paper 4.4.3 [114]); thin lossy dielectric coat",
)

BATTERY_PACK = Material(
    name="battery_pack",
    reflectance_rgb=(0.30, 0.30, 0.31),
    reflectance_550nm=0.30,
    reflectance_1550nm=0.33,
    emissivity_lwir=0.95,
    emissivity_mwir=0.93,
    temperature_k=T_SUAS_K,
    relative_permittivity=complex(1.0, 0.0),
    conductivity_s_m=3.5e7,
    is_pec=False,
    source="plastic-sleeved Li-ion pouch cells: plastic surface (IR/optical); the pouch's aluminium laminate "
    "(~40 um foil) is a conductor of aluminium's 3.5e7 S/m (CRC Handbook) at radio frequencies",
)

COPPER = Material(
    name="copper",
    reflectance_rgb=(0.55, 0.35, 0.25),
    reflectance_550nm=0.50,
    reflectance_1550nm=0.95,
    emissivity_lwir=0.03,
    emissivity_mwir=0.03,
    temperature_k=T_SUAS_K,
    relative_permittivity=complex(1.0, 0.0),
    conductivity_s_m=5.8e7,
    is_pec=False,
    source="circuit-board ground plane and wiring: conductivity 5.8e7 S/m (IACS annealed copper, CRC Handbook); "
    "emissivity 0.03 polished (Incropera et al., Table A.11); inside the airframe, radio only",
)

FR4 = Material(
    name="fr4",
    reflectance_rgb=(0.05, 0.25, 0.10),
    reflectance_550nm=0.20,
    reflectance_1550nm=0.30,
    emissivity_lwir=0.90,
    emissivity_mwir=0.88,
    temperature_k=T_SUAS_K,
    relative_permittivity=complex(4.4, -0.088),
    conductivity_s_m=0.0,
    is_pec=False,
    source="FR-4 glass-epoxy board: eps' 4.4, tan d 0.02 (Djordjevic, Biljic, Likar-Smiljanic & Sarkar, IEEE "
    "T-EMC 43(4):662, 2001: eps' 4.3-4.5, tan d ~0.02 at 1-10 GHz); solder-mask emissivity ~0.9 (assumption); "
    "inside the airframe, radio only",
)

PEC = Material(
    name="pec",
    reflectance_rgb=(0.90, 0.90, 0.90),
    reflectance_550nm=0.90,
    reflectance_1550nm=0.95,
    emissivity_lwir=0.02,
    emissivity_mwir=0.02,
    temperature_k=T_SUAS_K,
    relative_permittivity=complex(1.0, 0.0),
    conductivity_s_m=float("inf"),
    is_pec=True,
    source="idealised perfect electric conductor (radar oracles)",
)

#: Source of the bird plumage materials (drone_models/birds.py; MWIR emissivity taken as LWIR's; the radio
#: figures stand for the water-filled body of Vaughn 1985; Gabriel, Lau and Gabriel, Phys. Med. Biol. 41, 1996).
_PLUMAGE_SOURCE = (
    "LWIR emissivity 0.95 of feathered surfaces (McCafferty et al. 2017); visible albedo typical of the "
    "plumage colour (assumption); body as muscle at 10 GHz, eps' 43, sigma 10.6 S/m (Gabriel et al. 1996)"
)


def _plumage(name: str, albedo: float, rgb: tuple) -> Material:
    return Material(
        name=name,
        reflectance_rgb=rgb,
        reflectance_550nm=albedo,
        reflectance_1550nm=albedo,
        emissivity_lwir=0.95,
        emissivity_mwir=0.95,
        temperature_k=T_SUAS_K,
        relative_permittivity=complex(43.0, 0.0),
        conductivity_s_m=10.6,
        is_pec=False,
        source=_PLUMAGE_SOURCE,
    )


PLUMAGE_WHITE = _plumage("plumage_white", 0.70, (0.70, 0.70, 0.68))
PLUMAGE_GREY = _plumage("plumage_grey", 0.25, (0.24, 0.25, 0.27))
PLUMAGE_BROWN = _plumage("plumage_brown", 0.12, (0.16, 0.11, 0.07))

#: Registry of the named materials.
MATERIALS = {
    m.name: m
    for m in (
        PLASTIC,
        DARK_PLASTIC,
        CARBON_FIBRE,
        ALUMINIUM,
        ANODISED_ALUMINIUM,
        PAINT,
        BATTERY_PACK,
        COPPER,
        FR4,
        PEC,
        PLUMAGE_WHITE,
        PLUMAGE_GREY,
        PLUMAGE_BROWN,
    )
}

#: The paper's component list of Section 4.4.3: material -> (low, high) LWIR emissivity.
PAPER_EMISSIVITY_RANGES = {
    "plastic": (0.90, 1.00),
    "carbon_fibre": (0.80, 0.84),
    "aluminium": (0.05, 0.10),
    "paint": (0.80, 0.95),
}


def get_material(name: str) -> Material:
    """The registered material called ``name``; :class:`ParameterError` otherwise."""
    try:
        return MATERIALS[name]
    except KeyError:
        raise ParameterError("material", name, ", ".join(sorted(MATERIALS))) from None


def paper_component_mean_emissivity() -> float:
    """Unweighted mean of the mid-points of the paper's four component ranges [-].

    Section 4.4.3 lists plastic, carbon fibre, aluminium and paint and states
    ``epsilon_sUAS = 0.68``; the mean of the range mid-points is
    (0.95 + 0.82 + 0.075 + 0.875) / 4 = 0.68, i.e. each component class
    weighs one quarter whatever its share of the surface.
    """
    mids = [(lo + hi) / 2.0 for lo, hi in PAPER_EMISSIVITY_RANGES.values()]
    return sum(mids) / len(mids)
