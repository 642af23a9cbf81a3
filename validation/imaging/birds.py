"""Bird meshes (drone_models/birds.py) through the EO and thermal renderers, against exact oracles.

* EO: rendered pixels on target against the exact silhouette (polygon union of the projected
  triangles, :func:`csuas.drone_models.silhouette.projected_metrics`) over (IFOV R)^2, at two ranges
  and two wingbeat phases (wings up, wings level), seen from a ground sensor below the bird.
* Thermal: the rendered apparent excess temperature of a bird in air at ambient T_a (surroundings
  and background blackbodies at T_a) against the Planck band closed form of a graybody of the
  plumage's emissivity at T_a + excess,

      Delta T = T_r(eps L_band(T_a + excess) + (1 - eps) L_band(T_a)) - T_a,

  T_r the band radiance temperature (:func:`csuas.core.radiometry.radiance_temperature`). The closed
  form leaves out what the bird's parts reflect of each other: (1 - eps) F (L_bird - L_band(T_a))
  with F the view factor from a seen surface to the bird's other parts, at most (1 - eps) F Delta T
  in temperature; :data:`INTER_REFLECTION_VIEW_FACTOR` bounds F.
"""

from __future__ import annotations

from csuas.base.checks import Check
from csuas.core.radiometry import band_radiance, radiance_temperature
from csuas.drone_models.birds import MID_STROKE_PHASE, bird_class, build_bird
from csuas.drone_models.materials import T_SUAS_K
from csuas.drone_models.silhouette import projected_metrics
from csuas.render.imaging.eo import render_eo
from csuas.render.imaging.records import RenderSettings, ThermalScene, View
from csuas.render.imaging.tir import render_tir

#: The bird class of the checks, the ranges of the EO checks [m] and the thermal check's range [m].
BIRD, EO_RANGES_M, TIR_RANGE_M = "pigeon", (100.0, 300.0), 30.0
#: Wingbeat phases of the checks [cycles]: the top of the stroke (wings raised) and mid-stroke (level).
PHASES = (0.0, MID_STROKE_PHASE)
#: Direction from the bird toward a ground sensor below and ahead of it [deg].
BELOW = {"azimuth_deg": 30.0, "elevation_deg": -30.0}
#: Standard errors allowed; relative allowance of the EO oracle, an orthographic silhouette against the
#: render's pinhole camera (the near half of the bird is magnified, the far half shrunk: their first-order
#: changes cancel; measured 0.05 % at 100 m and standard quality, 0.2 px of 414).
N_SIGMA, PERSPECTIVE_ALLOWANCE = 3.0, 0.005
#: Bound on the view factor from a seen surface of the bird to its other parts (measured 0.05 averaged over
#: the silhouette, from a render of the level-winged bird in black surroundings: the inter-reflected radiance
#: over (1 - eps) of the emitted one). At standard quality the rendered excess sits 0.0006 K (wings up) and
#: 0.0076 K (level) above the closed form, within the allowance of 0.024 K.
INTER_REFLECTION_VIEW_FACTOR = 0.1


def _settings(quality, seed):
    return RenderSettings(quality=quality, seed=seed)


def eo_checks(quality="draft", seed: int = 0) -> list:
    """Rendered pixels on target of the bird against its exact silhouette, two ranges x two phases."""
    out = []
    for phase in PHASES:
        bird = build_bird(BIRD, phase)
        area = projected_metrics(bird.mesh(), **BELOW)["projected_area_m2"]
        for r in EO_RANGES_M:
            res = render_eo(bird, View(r, **BELOW), settings=_settings(quality, seed))
            expected = area / (res.ifov_rad * r) ** 2
            se = res.stderr["pixels_on_target"]
            out.append(
                Check(
                    f"imaging.birds.pixels_on_target.{BIRD}.phase_{phase:g}.{r:g}m",
                    expected,
                    res.values["pixels_on_target"],
                    N_SIGMA * se + PERSPECTIVE_ALLOWANCE * expected,
                    "px",
                    error_estimate=se,
                    time_s=res.time_s,
                    source="exact projected area (polygon union of the mesh's triangles) / (IFOV R)^2",
                    method=f"Mitsuba EO render of the {BIRD} mesh, wingbeat phase {phase:g}, {res.quality.spp} spp",
                    details={"wing_angle_deg": bird.spec["wing_angle_deg"]},
                )
            )
    return out


def apparent_excess_k(emissivity: float, excess_k: float, ambient_k: float = T_SUAS_K, band: str = "lwir") -> float:
    """Planck band closed form of a graybody's apparent excess over air at ambient [K] (module docstring)."""
    radiance = emissivity * band_radiance(ambient_k + excess_k, band) + (1.0 - emissivity) * band_radiance(
        ambient_k, band
    )
    return float(radiance_temperature(radiance, band)) - ambient_k


def tir_checks(quality="draft", seed: int = 0, ambient_k: float = T_SUAS_K) -> list:
    """Rendered apparent excess temperature of the bird against the Planck band closed form, two phases."""
    out = []
    excess = bird_class(BIRD)["surface_temperature_excess_k"]
    scene = ThermalScene(t_bg_k=ambient_k, emissivity_bg=1.0, surroundings_k=ambient_k)
    for phase in PHASES:
        bird = build_bird(BIRD, phase, ambient_k)
        eps = bird.parts[0].material.emissivity_lwir
        expected = apparent_excess_k(eps, excess, ambient_k)
        res = render_tir(
            bird,
            View(TIR_RANGE_M, **BELOW),
            scene=scene,
            reflected_surroundings=True,
            settings=_settings(quality, seed),
        )
        se = res.stderr["delta_t_k"]
        out.append(
            Check(
                f"imaging.birds.apparent_excess_k.{BIRD}.phase_{phase:g}",
                expected,
                res.values["delta_t_k"],
                N_SIGMA * se + (1.0 - eps) * INTER_REFLECTION_VIEW_FACTOR * expected,
                "K",
                error_estimate=se,
                time_s=res.time_s,
                source=f"Planck band closed form: eps {eps:g} at {ambient_k:g} + {excess:g} K in air at ambient",
                method=f"Mitsuba LWIR render of the {BIRD} mesh, wingbeat phase {phase:g}, surroundings at ambient",
            )
        )
    return out
