"""Swarms (issue 26, Section 3): what the core reports of N drones, and the simulators tracing them together,
against closed forms and exact geometry.

- ``swarm.ranges``: the first detection of a swarm in ``csuas range`` (:mod:`csuas.core.swarm_detection`)
  against the paper's range laws: a radar line merged in one beam at k sigma, R_1 k^(1/4) (Eq. 80's R^4);
  k incoherent acoustic sources, +10 log10 k dB, R_1 sqrt(k) (spherical spreading, Eq. 44); two cameras'
  drones merged under a one-pixel gap, Johnson's range proportional to the blob's d_crit (Eq. 18).
- ``swarm.rcs``: three PEC spheres traced together by SBR-PO (single bounces) against one sphere times the
  array factor |sum exp(j 2 k u . r_i)|^2 (:func:`csuas.core.swarm.array_factor`), and against the PO sphere
  (Knott et al., *Radar Cross Section*, 2nd ed., ch. 5) times it.
- ``swarm.pixels``: two plates in one EO render: each drone's box against its exact projection, the covered
  area against the plates' exact area, one blob under a one-pixel gap and two above it.
"""

from __future__ import annotations

import math
import time

import numpy as np
import tomllib

from csuas.base.checks import Check
from csuas.core.scenario import parse_scenario
from csuas.core.swarm import array_factor, line_formation
from csuas.core.swarm_detection import swarm_range
from csuas.validation.rcs.model_error import po_sphere_over_pia2
from csuas.validation.report.registry import CheckGroup, CheckSpec, Section

C_M_S = 299_792_458.0
SPHERE_RADIUS_M, SPHERE_KA = 0.05, 10.0
#: Three spheres 0.25-0.39 m apart across the line of sight (+x), a few mm along it: distinct phases, no shadow.
SPHERE_OFFSETS_M = np.array([[0.0, 0.0, 0.0], [0.0123, 0.3, 0.0], [-0.0071, -0.25, 0.2]])
#: Round-off and tube-grid agreement of single-bounce SBR of N spheres with one sphere times the array factor [dB].
SUM_TOLERANCE_DB = 0.01
PLATE_SIDE_M, PLATE_RANGE_M = 0.5, 500.0


def _db(x: float) -> float:
    return 10.0 * math.log10(x)


def _swarm_scenario(swarm: str, modality: str):
    """A scenario of one sensor of ``modality`` at its defaults and a target with the swarm (TOML inline table)."""
    return parse_scenario(tomllib.loads(f'[target]\nswarm = {swarm}\n[sensors.{modality}]\nmodality = "{modality}"\n'))


def range_cases(_knob=None) -> Section:
    """First detection of merged swarms against the paper's range laws (module docstring)."""
    s = Section()
    start = time.perf_counter()
    cases = []
    radar = swarm_range(_swarm_scenario("{count = 4, spacing_m = 5.0}", "radar"), "radar", "paper")
    cases.append(("radar_line_of_4", radar["single_drone_range_m"] * 4**0.25, radar, "Eq. 80: R ~ sigma^(1/4)"))
    sound = swarm_range(_swarm_scenario("{count = 5, spacing_m = 2.0}", "acoustic"), "acoustic", "paper")
    cases.append(("acoustic_5", sound["single_drone_range_m"] * math.sqrt(5), sound, "Eq. 44: +10 log10 5 dB"))
    ifov, d = math.radians(10.0) / 1920, 0.101  # Table 22's EO camera, Table 8's d_crit
    single = swarm_range(_swarm_scenario("{count = 2, spacing_m = 100.0}", "eo"), "eo", "paper")
    gap = d + 0.5 * single["single_drone_range_m"] * ifov  # centres half a pixel's gap apart there
    camera = swarm_range(_swarm_scenario(f"{{offsets_m = [[0, 0, 0], [0, {gap!r}, 0]]}}", "eo"), "eo", "paper")
    expected = single["single_drone_range_m"] * math.sqrt((gap + d) * d) / d
    cases.append(("eo_pair_half_pixel_gap", expected, camera, "Eq. 18: R ~ d_crit of the blob's bounding box"))
    elapsed = time.perf_counter() - start
    for name, expected, got, source in cases:
        s.outcomes.append(
            Check(
                f"swarm.ranges.{name}.first_detection_m",
                expected,
                got["first_detection_m"],
                1e-9 * expected,
                "m",
                tolerance_source="float64 round-off of the same range law",
                time_s=elapsed / len(cases),
                source=source,
                method="csuas.core.swarm_detection.swarm_range",
            )
        )
    return s


def sphere_cases(rays_per_wavelength=10) -> Section:
    """Three PEC spheres traced together against one sphere times the array factor, and the PO sphere's."""
    from csuas.render.rcs import canonical
    from csuas.render.rcs.geometry import formation_target, load_target
    from csuas.render.rcs.solver import compute_rcs

    s = Section()
    f_ghz = SPHERE_KA * C_M_S / (2 * math.pi * SPHERE_RADIUS_M) / 1e9
    factor = array_factor(SPHERE_OFFSETS_M, [1, 0, 0], [1, 0, 0], C_M_S / (f_ghz * 1e9))
    kwargs = dict(rays_per_wavelength=rays_per_wavelength, max_bounces=1, error_estimate=False)
    start = time.perf_counter()
    one = load_target(canonical.sphere(SPHERE_RADIUS_M, 5))
    sigma_one = float(compute_rcs(one, f_ghz, 0.0, 0.0, **kwargs).rcs_m2("VV").ravel()[0])
    together = formation_target(one, SPHERE_OFFSETS_M)
    sigma_n = float(compute_rcs(together, f_ghz, 0.0, 0.0, **kwargs).rcs_m2("VV").ravel()[0])
    elapsed = time.perf_counter() - start
    po = math.pi * SPHERE_RADIUS_M**2 * float(po_sphere_over_pia2(SPHERE_KA)) * factor
    common = {"unit": "dBsm", "time_s": elapsed, "method": "csuas.render.rcs (SBR-PO), N meshes traced together"}
    s.outcomes += [
        Check(
            "swarm.rcs.three_spheres_vs_one_times_array_factor",
            _db(sigma_one * factor),
            _db(sigma_n),
            SUM_TOLERANCE_DB,
            tolerance_source="single bounces: the same tubes' fields summed; the tube grid's offset per sphere",
            source="array factor of N point scatterers (csuas.core.swarm.array_factor)",
            **common,
        ),
        Check(
            "swarm.rcs.three_spheres_vs_po_sphere_times_array_factor",
            _db(po),
            _db(sigma_n),
            0.25 + 20 * math.log10(1 + 4.0 / (2 * SPHERE_KA)),
            tolerance_source="tests/test_rcs_oracles: point-sampled tubes lack PO's shadow-boundary term, "
            "relative amplitude 2 / (2 ka)",
            source="PO sphere (Knott et al., ch. 5) x array factor",
            **common,
        ),
    ]
    s.notes.append(f"ka = {SPHERE_KA:g}, array factor {factor:.4f} (9 in phase), one sphere {sigma_one:.5g} m^2")
    return s


def plate_cases(quality="draft") -> Section:
    """Two plates in one EO render: boxes, covered area and blobs against exact geometry."""
    from csuas.render.imaging.eo import render_eo
    from csuas.render.imaging.records import Daylight, EoSensor, RenderSettings, View
    from csuas.render.imaging.swarm import blobs, formation_members, member_labels
    from csuas.render.imaging.targets import plate

    s = Section()
    sensor = EoSensor()
    pixel_m = PLATE_RANGE_M * math.radians(sensor.hfov_deg) / sensor.n_h
    area_px = (PLATE_SIDE_M / pixel_m) ** 2
    for gap_px, expected_blobs in ((3.0, 2), (0.4, 1)):
        formation = line_formation(2, PLATE_SIDE_M + gap_px * pixel_m)
        members = formation_members(plate(PLATE_SIDE_M, PLATE_SIDE_M), formation, 0.0, 0.0)
        view = View(PLATE_RANGE_M, 0.0, 0.0)
        start = time.perf_counter()
        res = render_eo([p for m in members for p in m], view, sensor, Daylight(), settings=RenderSettings(quality, 0))
        labels = member_labels(members, view, res, sensor.n_h, sensor.n_v)
        elapsed = time.perf_counter() - start
        common = {"time_s": elapsed, "method": "csuas.render.imaging.swarm (Mitsuba EO render)"}
        name = f"swarm.pixels.gap_{gap_px:g}px"
        s.outcomes += [
            Check(
                f"{name}.blobs",
                float(expected_blobs),
                float(len(blobs(res.coverage))),
                0.0,
                "-",
                tolerance_source="a count: one blob under a one-pixel gap, two above",
                source="exact geometry",
                **common,
            ),
            Check(
                f"{name}.covered_px",
                2 * area_px,
                float(res.coverage.sum()),
                0.01 * 2 * area_px,
                "px",
                tolerance_source="the render's pixel sampling at draft (measured 0.2 % at the 0.4 px gap)",
                source="two plates of 0.5 m at 500 m: (0.5 / (R IFOV))^2 each",
                **common,
            ),
        ]
        s.notes.append(f"gap {gap_px:g} px: boxes {[lab['bbox'] for lab in labels]}")
    return s


GROUP = CheckGroup(
    "swarm",
    "Swarms: resolution, merged signatures and N meshes traced together",
    120,
    "The first detection of a swarm against the paper's range laws, N spheres traced together against the "
    "array factor of point scatterers, and two plates in one render against exact geometry.",
)

SPECS = [
    CheckSpec(
        "swarm.ranges",
        "Swarm first detection vs the range laws",
        GROUP,
        "csuas range's swarm first detection of a merged radar line, acoustic sources and an EO blob vs R_1 k^(1/4), "
        "R_1 sqrt(k) and R_1 d_blob / d",
        "float64 round-off",
        range_cases,
    ),
    CheckSpec(
        "swarm.rcs",
        "Three spheres traced together vs the array factor",
        GROUP,
        "SBR-PO of three PEC spheres at ka 10 vs one sphere x |sum exp(j 2 k u.r)|^2 and vs the PO sphere x it",
        f"{SUM_TOLERANCE_DB:g} dB against one sphere x array factor; the sphere oracle's tolerance against PO",
        sphere_cases,
        knob="rays_per_wavelength",
        knob_values={"quick": 10, "full": 10},
        simulated=True,
    ),
    CheckSpec(
        "swarm.pixels",
        "Two plates in one EO render vs exact geometry",
        GROUP,
        "blobs and covered pixels of two 0.5 m plates at 500 m, 3 px and 0.4 px apart",
        "blob count exact; covered area 1 %",
        plate_cases,
        knob="quality",
        knob_values={"quick": "draft", "full": "standard"},
        simulated=True,
    ),
]
