"""EO and thermal renders against exact geometry and the Johnson criteria, with images at several ranges.

* ``imaging.johnson``: pixels across d_crit of the rendered drone against the
  exact silhouette (polygon union, Eq. 1) over IFOV R, at ranges around the
  Johnson range, and the Johnson range (Eq. 18) implied by the renders against
  the analytic one with Table 8's d_crit;
* ``imaging.pixels_on_target``: rendered fractional coverage against the
  exact projected area / (IFOV R)^2, and its accuracy against samples per pixel;
* ``imaging.birds``: the bird meshes (drone_models/birds.py) rendered in EO and LWIR against their
  exact silhouette and the Planck band closed form (:mod:`csuas.validation.imaging.birds`);
* ``imaging.weather``: the scenario's weather in the renders (the path ``csuas range`` applies) against
  Koschmieder's law, Beer-Lambert with path radiance and a Mitsuba fog slab
  (:mod:`csuas.validation.imaging.weather`);
* ``imaging.gallery``: EO and thermal previews of the default scenario at
  several ranges.

The contrast limit against rendered contrast is ``conv.1`` (docs/conventions.md point 1).
Knob: jittered samples per pixel (:data:`csuas.render.imaging.QUALITY_PRESETS`).
"""

from __future__ import annotations

import numpy as np

from csuas.base.checks import Check
from csuas.core.johnson import ifov_rad, johnson_range_m
from csuas.render.imaging.records import EoSensor, RenderSettings, ThermalScene, ThermalSensor, View
from csuas.validation.report.figures import AccuracyColumns, PlotAxes, curves, image
from csuas.validation.report.figures import accuracy_vs_time as plot_accuracy
from csuas.validation.report.registry import CheckGroup, CheckSpec, Section, timed

QUALITY = {"quick": "draft", "full": "reference"}
SPP_SWEEP = {"quick": (1, 2, 4), "full": (1, 2, 4, 8, 16)}
N_SIGMA = 3.0
PRESET = "dji_mini_4_pro"
VIEW = {"azimuth_deg": 0.0, "elevation_deg": 0.0}


def _sensor():
    from csuas.validation.report.checks_conventions import scenario

    sc = scenario("default")
    p = sc.sensors["eo"].params
    return sc, p, float(ifov_rad(p["hfov_deg"], p["n_h"]))


def _render(r, p, quality, seed=0):
    from csuas.render.imaging import render_eo

    return render_eo(
        PRESET,
        View(float(r), **VIEW),
        sensor=EoSensor(
            hfov_deg=p["hfov_deg"],
            n_h=p["n_h"],
            n_v=p["n_v"],
            lp_task=p["lp_task"],
            n_ttpf=p["n_ttpf"],
            c_min=p["c_min"],
        ),
        settings=RenderSettings(quality=quality, seed=seed),
    )


def johnson(quality: str) -> Section:
    """Rendered pixels across d_crit vs exact geometry; rendered vs analytic Johnson range."""
    from csuas.drone_models import build_drone
    from csuas.drone_models.silhouette import projected_metrics
    from csuas.render.imaging import resolve_quality

    s = Section()
    sc, p, ifov = _sensor()
    d_exact = projected_metrics(build_drone(PRESET), **VIEW)["d_crit_min_m"]
    r_johnson = float(johnson_range_m(sc.target["d_crit_m"], ifov, p["lp_task"], p["n_ttpf"]))
    n_side = resolve_quality(quality).n_side
    ranges = np.array([0.25, 0.5, 0.75, 1.0, 1.5]) * r_johnson
    px, se, rj, rj_se = [], [], [], []
    for r in ranges:
        res = _render(r, p, quality)
        px.append(res.values["pixels_across_dcrit"])
        se.append(res.stderr["pixels_across_dcrit"])
        rj.append(res.values["johnson_range_rendered_m"])
        rj_se.append(res.stderr["johnson_range_rendered_m"])
        expected = d_exact / (ifov * r)
        # extents come from jittered sample hits: allow a quarter of a stratum per edge beyond the sampling error
        s.outcomes.append(
            Check(
                f"imaging.pixels_across_dcrit.{r:.0f}m",
                expected,
                px[-1],
                0.25 / n_side + N_SIGMA * se[-1],
                "px",
                error_estimate=se[-1],
                time_s=res.time_s,
                source="exact silhouette (Eq. 1) / (IFOV R)",
                method=f"Mitsuba EO render of the {PRESET} mesh, front view, {res.quality.spp} spp",
            )
        )
    px, se, rj, rj_se = map(np.array, (px, se, rj, rj_se))
    weights = 1.0 / np.maximum(rj_se, 1e-6 * rj) ** 2
    r_sim = float(np.sum(weights * rj) / np.sum(weights))
    r_sim_se = float(np.sqrt(1.0 / np.sum(weights)))
    extra_rel = abs(d_exact - sc.target["d_crit_m"]) / sc.target["d_crit_m"]
    s.outcomes.append(
        Check(
            "imaging.johnson_range_m",
            r_johnson,
            r_sim,
            r_johnson * (extra_rel + 0.005) + N_SIGMA * r_sim_se,
            "m",
            error_estimate=r_sim_se,
            source="Eq. 18 with Table 8's d_crit (csuas.core.johnson)",
            method="range x rendered pixels across d_crit / (2 lp n_TTPF), weighted over the rendered ranges",
            details={"d_crit_mesh_m": d_exact, "d_crit_table8_m": sc.target["d_crit_m"]},
        )
    )
    rr = np.linspace(0.2 * r_johnson, 1.6 * r_johnson, 200)
    s.figures.append(
        curves(
            "imaging_pixels_vs_range",
            "EO: pixels across d_crit vs range (Johnson, Eq. 18)",
            axes=PlotAxes("slant range [m]", "pixels across d_crit"),
            lines=[
                (
                    f"d_crit / (IFOV R), Table 8 d_crit {sc.target['d_crit_m']} m",
                    rr,
                    sc.target["d_crit_m"] / (ifov * rr),
                ),
                (f"mesh silhouette d_crit {d_exact:.4f} m", rr, d_exact / (ifov * rr)),
            ],
            points=[("rendered (Mitsuba)", ranges, px, N_SIGMA * se)],
            hlines=[
                (
                    f"2 lp n_TTPF = {2 * p['lp_task'] * p['n_ttpf']:g} px: Johnson range {r_johnson:.0f} m",
                    2 * p["lp_task"] * p["n_ttpf"],
                )
            ],
            caption="Detection at P = 0.5: the range where the target spans 2 lp n_TTPF pixels.",
        )
    )
    return s


def pixels_on_target(settings: dict) -> Section:
    """Rendered pixels on target vs exact projected area; accuracy against samples per pixel."""
    from csuas.drone_models import build_drone
    from csuas.drone_models.silhouette import projected_metrics
    from csuas.validation.imaging.accuracy import accuracy_sweep

    s = Section()
    _, p, ifov = _sensor()
    area = projected_metrics(build_drone(PRESET), **VIEW)["projected_area_m2"]
    for r in (100.0, 300.0, 1000.0):
        res = _render(r, p, settings["quality"], seed=5)
        expected = area / (ifov * r) ** 2
        s.outcomes.append(
            Check(
                f"imaging.pixels_on_target.{r:g}m",
                expected,
                res.values["pixels_on_target"],
                N_SIGMA * res.stderr["pixels_on_target"] + 0.01 * expected,
                "px",
                error_estimate=res.stderr["pixels_on_target"],
                time_s=res.time_s,
                source="exact projected area (polygon union) / (IFOV R)^2",
                method=f"fractional coverage of the rendered window, {res.quality.spp} spp",
            )
        )
    r = 100.0
    rows, elapsed = timed(
        accuracy_sweep, lambda q: _render(r, p, q, seed=7), settings["n_sides"], area / (ifov * r) ** 2
    )
    for row in rows:
        row["abs_relative_error"] = abs(row["relative_error"])
        row["stderr_rel"] = row["stderr"] / (area / (ifov * r) ** 2)
    from csuas.render.imaging.quality import QUALITY_PRESETS

    s.figures.append(
        plot_accuracy(
            "imaging_accuracy_vs_time",
            f"EO render: pixels on target at {r:g} m vs time",
            rows,
            columns=AccuracyColumns(
                "spp", "abs_relative_error", error_label="|relative error| vs exact area", stderr_key="stderr_rel"
            ),
            caption="Labels: samples per pixel (jittered strata x 8 batches).",
            presets={name: q.n_side**2 * q.n_batches for name, q in QUALITY_PRESETS.items()},
        )
    )
    s.table = rows
    s.notes.append(f"spp sweep {elapsed:.1f} s")
    return s


def gallery(quality: str) -> Section:
    """EO and thermal previews of the default scenario's drone at several ranges."""
    from csuas.render.imaging import render_tir
    from csuas.render.imaging.output import preview_rgb

    s = Section()
    sc, p, _ = _sensor()
    for r in (30.0, 150.0, 555.0):
        res = _render(r, p, quality, seed=11)
        s.figures.append(
            image(
                f"eo_{r:g}m",
                f"EO, {r:g} m",
                preview_rgb(res),
                caption=f"{res.window.width} x {res.window.height} px window, "
                f"{res.values['pixels_on_target']:.1f} px on "
                f"target, contrast {res.values['contrast']:.3f}",
            )
        )
    tp, env, t = sc.sensors["tir"].params, sc.environment, sc.target
    for r in (10.0, 30.0, 100.0):
        res = render_tir(
            PRESET,
            View(r, **VIEW),
            sensor=ThermalSensor(hfov_deg=tp["hfov_deg"], n_h=tp["n_h"], n_v=tp["n_v"], band=tp["band"]),
            scene=ThermalScene(
                t_bg_k=env["t_bg_k"], emissivity_bg=env["emissivity_bg"], surroundings_k=env["temperature_k"]
            ),
            settings=RenderSettings(quality=quality, seed=11),
            linear_reference=(t["emissivity_suas"], t["t_suas_k"]),
            reflected_surroundings=True,
        )
        s.figures.append(
            image(
                f"tir_{r:g}m",
                f"thermal LWIR, {r:g} m",
                preview_rgb(res),
                caption=f"apparent Delta T {res.values['delta_t_k']:.2f} K (paper's linear "
                f"{res.values['delta_t_linear_k']:.1f} K), {res.values['pixels_on_target']:.1f} "
                "px on target",
            )
        )
    return s


def birds(quality: str) -> Section:
    """The bird mesh's EO pixels on target and thermal apparent excess against exact oracles, and its images."""
    from csuas.drone_models.birds import build_bird
    from csuas.render.imaging.eo import render_eo
    from csuas.render.imaging.output import preview_rgb
    from csuas.validation.imaging import birds as bird_checks

    s = Section()
    s.outcomes += bird_checks.eo_checks(quality) + bird_checks.tir_checks(quality)
    for phase in bird_checks.PHASES:
        bird = build_bird(bird_checks.BIRD, phase)
        res = render_eo(bird, View(40.0, **bird_checks.BELOW), settings=RenderSettings(quality=quality, seed=11))
        s.figures.append(
            image(
                f"bird_eo_phase_{phase:g}",
                f"EO, {bird_checks.BIRD} at 40 m from below, wingbeat phase {phase:g}",
                preview_rgb(res),
                caption=f"wings {bird.spec['wing_angle_deg']:.0f} deg above level, "
                f"{res.values['pixels_on_target']:.1f} px on target",
            )
        )
    return s


#: Closed-loop detection settings per report quality: ranges [m], frames per range and hypothesis.
CLOSED_LOOP = {
    "quick": {"ranges_m": (300.0, 450.0, 600.0, 750.0), "trials": 2000},
    "full": {"ranges_m": (150.0, 300.0, 450.0, 525.0, 600.0, 675.0, 750.0, 900.0), "trials": 20000},
}
#: Illuminance of the closed loop [lx]: dusk, where the camera's noise decides (Table 11's twilight is 3 lx).
CLOSED_LOOP_LUX = 0.5
#: Largest |empirical - Gaussian| Pd of the matched filter allowed on top of 3 binomial standard errors: the
#: Poisson skew of an 8-electron background puts the empirical Pd above the Gaussian one by up to 0.049
#: (4000 frames per range, 150-900 m).
GAUSSIAN_ALLOWANCE = 0.06
#: Smallest predicted Pd a closed-loop check judges (the allowance stays within a fifth of the value above it).
JUDGED_FROM_PD = 0.5


#: The sensor-chain cameras of the report: optics for the slanted edge, detector for the photon transfer.
CHAIN_EDGE = {"f_number": 8.0, "wavelength_um": 0.55, "pixel_pitch_um": 2.9, "jitter_px": 0.3}
CHAIN_DETECTOR = {"read_noise_e": 6.0, "bits": 12}
CHAIN_NETD_K = 0.05


def sensor_chain(_knob=None) -> Section:
    """Slanted-edge MTF, photon-transfer gain and read noise, and flat-field NETD of the sensor chain."""
    s = Section()
    mtf = _slanted_edge_check(s)
    _photon_transfer_checks(s)
    _flat_field_netd_check(s)
    _rendered_snr_checks(s)
    _light_limited_range_checks(s)
    f = mtf["frequency_cy_px"]
    s.figures.append(
        curves(
            "imaging_sensor_chain_mtf",
            "Sensor chain MTF: slanted edge against the analytic chain",
            axes=PlotAxes("spatial frequency [cycles / pixel]", "MTF"),
            lines=[("analytic: diffraction x jitter x pixel", f, mtf["analytic"])],
            points=[("slanted edge (ISO 12233)", f, mtf["measured"], None)],
            caption="f/8 at 0.55 um on 2.9 um pixels, 0.3 px rms jitter.",
        )
    )
    return s


def _slanted_edge_check(s: Section) -> dict:
    """The slanted edge's MTF at 0.25 cy/px against the analytic chain; returns the measured and analytic MTF."""
    from csuas.render.imaging.sensor_chain import ChainSettings
    from csuas.validation.imaging.chain_checks import slanted_edge_mtf

    edge_settings = ChainSettings(stages=("psf",), **CHAIN_EDGE)
    mtf, t_mtf = timed(slanted_edge_mtf, edge_settings)
    quarter = int(np.argmin(np.abs(mtf["frequency_cy_px"] - 0.25)))
    s.outcomes.append(
        Check(
            "imaging.sensor_chain.slanted_edge.mtf_at_quarter_cycle",
            float(mtf["analytic"][quarter]),
            float(mtf["measured"][quarter]),
            0.02,
            "-",
            time_s=t_mtf,
            source="analytic MTF: diffraction (Goodman Eq. 6-31) x jitter x pixel footprint sinc",
            method="ISO 12233 slanted edge (5 deg, quarter-pixel bins), f/8, 2.9 um, 0.3 px jitter, at 0.25 cy/px",
            tolerance_source="0.02 absolute in MTF (the binning's residual)",
            details={"max_abs_difference_to_nyquist": mtf["max_abs_difference"]},
        )
    )
    return mtf


def _photon_transfer_checks(s: Section) -> None:
    """EMVA 1288 photon transfer: the conversion gain and the read noise of the detector stages."""
    from csuas.render.imaging.sensor_chain import ChainSettings
    from csuas.validation.imaging.chain_checks import photon_transfer

    detector = ChainSettings(stages=("shot_noise", "read_noise", "quantise"), **CHAIN_DETECTOR)
    ptc, t_ptc = timed(photon_transfer, detector)
    s.outcomes += [
        Check(
            "imaging.sensor_chain.photon_transfer.gain_e_per_dn",
            detector.gain_e_per_dn,
            ptc["gain_e_per_dn"],
            0.02 * detector.gain_e_per_dn,
            "e/DN",
            time_s=t_ptc / 2,
            source="the configured conversion gain (full well / 4095)",
            method="EMVA 1288 photon transfer: variance of two-frame differences vs mean, ten levels, 256 x 256",
            tolerance_source="2 %: the variance estimates of 65 536 pixels per level (0.6 % each)",
        ),
        Check(
            "imaging.sensor_chain.photon_transfer.read_noise_e",
            CHAIN_DETECTOR["read_noise_e"],
            ptc["read_noise_e"],
            0.1 * CHAIN_DETECTOR["read_noise_e"],
            "e",
            time_s=t_ptc / 2,
            source="the configured read noise",
            method="the photon-transfer intercept less 1/12 DN^2 of quantisation",
            tolerance_source="10 %: the intercept of a fit dominated by shot noise",
        ),
    ]


def _flat_field_netd_check(s: Section) -> None:
    """The NETD stage: the temporal standard deviation of a flat frame against the configured NETD."""
    from csuas.render.imaging.sensor_chain import ChainSettings
    from csuas.validation.imaging.chain_checks import flat_field_netd

    thermal = ChainSettings(stages=("netd",), netd_k=CHAIN_NETD_K)
    netd, t_netd = timed(flat_field_netd, thermal)
    s.outcomes.append(
        Check(
            "imaging.sensor_chain.flat_field.netd_k",
            CHAIN_NETD_K,
            netd,
            0.02 * CHAIN_NETD_K,
            "K",
            time_s=t_netd,
            source="the configured NETD",
            method="temporal standard deviation of a flat 300 K frame, 256 x 256",
            tolerance_source="2 %: the standard deviation of 65 536 samples (0.3 %)",
        )
    )


def _rendered_snr_checks(s: Section) -> None:
    """Blob SNR of rendered full frames against the core's camera equation, per illuminance."""
    from csuas.validation.imaging.chain_checks import rendered_snr_against_core

    rows, t_snr = timed(rendered_snr_against_core)
    for row in rows:
        s.outcomes.append(
            Check(
                f"imaging.sensor_chain.rendered_snr.{row['illuminance_lx']:g}lx",
                row["snr_core"],
                row["snr_rendered"],
                0.01 * row["snr_core"],
                "-",
                time_s=t_snr / len(rows),
                source="core.camera: camera equation, photons per lumen, auto-exposure, Michelson excess (Eq. 3)",
                method="blob SNR of the DJI Mini 4 Pro's rendered full frame at 300 m (Lambertian 0.3 background)",
                tolerance_source="1 %: the two paths compute the same radiometry (float32 render images)",
                details={"background_e": row["background_e_rendered"]},
            )
        )


def _light_limited_range_checks(s: Section) -> None:
    """The range where rendered frames' SNR meets the threshold against the core's light-limited range."""
    from csuas.validation.imaging.chain_checks import rendered_light_limited_range

    ranges, t_range = timed(rendered_light_limited_range)
    for row in ranges:
        s.outcomes.append(
            Check(
                f"imaging.sensor_chain.light_limited_range.{row['illuminance_lx']:g}lx",
                row["range_core_m"],
                row["range_rendered_m"],
                3.0 * row["relative_stderr"] * row["range_core_m"],
                "m",
                time_s=t_range / len(ranges),
                source="core.camera.light_limited_range_m given the render's contrast and projected area",
                method=f"bisection on rendered full frames' blob SNR down to {row['required_snr']:.3g} "
                f"(Pfa 1e-6, Pd 0.5), standard quality, {row['renders']} renders",
                tolerance_source="3 standard errors of the rendered SNR (pixels on target and contrast, at the "
                "root and at the 300 m reference); the range moves by at most the SNR's relative error",
            )
        )


def closed_loop(settings: dict) -> Section:
    """A matched filter on rendered noisy frames: empirical Pd beside its Gaussian prediction, the core's
    light-limited blob model and the TTPF."""
    from csuas.validation.imaging.closed_loop import closed_loop_pd

    rows, elapsed = timed(
        closed_loop_pd, settings["ranges_m"], illuminance_lx=CLOSED_LOOP_LUX, trials=settings["trials"]
    )
    s = Section(table=rows)
    s.notes.append(
        f"Judged where the predicted Pd is at least {JUDGED_FROM_PD:g}: below it the {GAUSSIAN_ALLOWANCE:g} allowance "
        "of the Gaussian approximation would exceed a fifth of the value; those ranges are in the figure and table."
    )
    for row in rows:
        if row["pd_matched_filter"] < JUDGED_FROM_PD:
            continue
        s.outcomes.append(
            Check(
                f"imaging.closed_loop.{row['range_m']:g}m.pd",
                row["pd_matched_filter"],
                row["pd_empirical"],
                3 * row["pd_empirical_stderr"] + GAUSSIAN_ALLOWANCE,
                "-",
                error_estimate=row["pd_empirical_stderr"],
                time_s=elapsed / len(rows),
                source="matched filter's Gaussian Pd (Kay 1998, ch. 4) with the chain's shot and read noise",
                method=f"{settings['trials']} noisy frames with and without the DJI Mini 4 Pro (draft render, "
                f"{CLOSED_LOOP_LUX:g} lx, f/2, 2.9 um, QE 0.6), threshold at Pfa 0.01 from the target-free frames",
                tolerance_source=f"3 binomial standard errors + {GAUSSIAN_ALLOWANCE:g} for the Gaussian approximation",
                details={k: row[k] for k in ("pd_core_light", "pd_ttpf", "snr_matched_filter", "pixels_on_target")},
            )
        )
    r = [row["range_m"] for row in rows]
    s.figures.append(
        curves(
            "imaging_closed_loop",
            f"Detection of a DJI Mini 4 Pro at {CLOSED_LOOP_LUX:g} lx: a matched filter on rendered frames",
            axes=PlotAxes("range [m]", "Pd (Pfa 0.01)"),
            lines=[
                ("matched filter, Gaussian prediction", r, [row["pd_matched_filter"] for row in rows]),
                ("core: uniform blob, light-limited model", r, [row["pd_core_light"] for row in rows]),
                ("TTPF (the paper's Pd, no noise)", r, [row["pd_ttpf"] for row in rows]),
            ],
            points=[
                (
                    "empirical (rendered frames)",
                    r,
                    [row["pd_empirical"] for row in rows],
                    [row["pd_empirical_stderr"] for row in rows],
                )
            ],
            caption=f"{settings['trials']} frames per range and hypothesis, {elapsed:.1f} s.",
        )
    )
    return s


def weather(quality: str) -> Section:
    """The path of the scenario's weather in the renders vs Koschmieder, Beer-Lambert and a Mitsuba fog slab."""
    from csuas.validation.imaging.weather import FOG_VISIBILITY_M, weather_checks

    s = Section()
    checks, rows, elapsed = weather_checks(quality)
    s.outcomes += checks
    r = rows[:, 0]
    s.figures.append(
        curves(
            "imaging_weather_koschmieder",
            f"Rendered contrast of a plate in fog (V = {FOG_VISIBILITY_M:g} m) vs Koschmieder's law",
            axes=PlotAxes("range [m]", "Weber contrast against the horizon sky"),
            lines=[("C0 exp(-beta R), C0 closed form, beta from csuas range", r, rows[:, 3])],
            points=[("rendered (csuas render's path)", r, rows[:, 1], rows[:, 2])],
            caption=f"{quality} quality, all weather checks {elapsed:.1f} s.",
        )
    )
    return s


#: The report section of these checks.
GROUP = CheckGroup(
    "imaging",
    "EO and thermal renders vs Johnson criteria and exact geometry",
    70,
    "EO and thermal renders against the exact silhouette, the Johnson criteria, band-Planck radiometry "
    "and the sensor chain's closed forms.",
)


SPECS = [
    CheckSpec(
        "imaging.johnson",
        "Johnson range vs rendered pixels across d_crit",
        GROUP,
        "exact silhouette pixels and the analytic Johnson range vs Mitsuba EO renders",
        f"a quarter stratum per edge (0.25/n_side px) + {N_SIGMA:g} standard errors; the Johnson range "
        "0.5 % + the mesh's d_crit vs Table 8's",
        johnson,
        "render quality (samples per pixel)",
        QUALITY,
        True,
    ),
    CheckSpec(
        "imaging.pixels_on_target",
        "Rendered pixels on target vs exact projected area",
        GROUP,
        "exact projected area / (IFOV R)^2 vs rendered fractional coverage",
        f"{N_SIGMA:g} standard errors + 1 %: the oracle is an orthographic silhouette, the render a pinhole "
        "camera, whose perspective magnifies the near half of the drone (0.3 m deep: +0.15 % in size, +0.3 % "
        "in area at 100 m; measured +0.2 % at reference quality)",
        pixels_on_target,
        "render quality; spp sweep",
        {
            "quick": {"quality": "draft", "n_sides": SPP_SWEEP["quick"]},
            "full": {"quality": "reference", "n_sides": SPP_SWEEP["full"]},
        },
        True,
    ),
    CheckSpec(
        "imaging.sensor_chain",
        "Sensor chain: slanted-edge MTF, photon transfer, flat-field NETD, rendered SNR vs the core",
        GROUP,
        "the chain's measured MTF, conversion gain, read noise and NETD vs its configured and analytic values; the "
        "rendered frame's target SNR by day, twilight and night vs the core's camera model",
        "0.02 in MTF; 2 % gain; 10 % read noise; 2 % NETD; 1 % SNR",
        sensor_chain,
        None,
        {},
        False,
    ),
    CheckSpec(
        "imaging.closed_loop",
        "Closing the loop: a detector on rendered noisy frames",
        GROUP,
        "empirical Pd of a matched filter on rendered frames through the sensor chain vs its Gaussian prediction, "
        "beside the core's light-limited model and the TTPF",
        f"3 binomial standard errors + {GAUSSIAN_ALLOWANCE:g} (the Gaussian approximation of 8-electron Poisson "
        "backgrounds, measured up to 0.049)",
        closed_loop,
        "frames per range",
        CLOSED_LOOP,
        True,
    ),
    CheckSpec(
        "imaging.birds",
        "Bird meshes (flapping wings) in the EO and thermal renders",
        GROUP,
        "the pigeon mesh's rendered pixels on target vs its exact silhouette at 100 and 300 m, wings up and level; "
        "its rendered LWIR apparent excess temperature vs the Planck band closed form (plumage emissivity 0.95, "
        "surface excess of defaults/birds.toml, in air at ambient)",
        "EO: 3 standard errors + 0.5 % (orthographic oracle, pinhole render); thermal: 3 standard errors + "
        "(1 - eps) 0.1 Delta T, what the bird's parts reflect of each other with a view factor up to 0.1",
        birds,
        "render quality (samples per pixel)",
        QUALITY,
        True,
    ),
    CheckSpec(
        "imaging.weather",
        "Weather in the renders: Koschmieder, Beer-Lambert with path radiance, layered fog",
        GROUP,
        "a plate's rendered contrast in fog vs C0 exp(-beta R) (C0 closed form, beta csuas range's); a graybody "
        "plate's rendered LWIR Delta T in heavy rain and in fog (LOWTRAN 7 advection fog) vs Beer-Lambert with the "
        "air's path radiance; a dataset confuser's contrast in fog at its own range vs exp(-beta R); the render's "
        "slant-path transmittance through a fog layer (fog_top_m) vs an absorbing Mitsuba fog slab; the EO render "
        "through the participating medium (render --atmosphere-method medium) vs its analytic path (equal in "
        "uniform isotropic fog under uniform light; the difference stated for forward scattering and a slant layer)",
        "4 Monte Carlo standard errors (render batches, slab batches); thermal + 1e-4 K for float32 radiances",
        weather,
        "render quality (samples per pixel)",
        QUALITY,
        True,
    ),
    CheckSpec(
        "imaging.gallery",
        "Rendered drone images, EO and thermal",
        GROUP,
        "images only",
        "none",
        gallery,
        "render quality (samples per pixel)",
        QUALITY,
        True,
    ),
]
