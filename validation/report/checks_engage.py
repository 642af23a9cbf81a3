"""Engagements (``csuas engage``, render/engagement) against closed forms and hand-computed values.

* False alarms with no target: a radar's noise false alarms per look, Monte Carlo, against Pfa x its
  resolution cells (range x beam cells of its reach; Richards 2014 Section 6.2), and an RF direction
  finder's and an acoustic array's per hour against Pfa x cells x 3600 / T (frequency bins x bearing
  cells), within 3 standard errors.
* First track of one sensor: the tracker's (Stone Soup, M of N) first-track probability by each look
  against the exact dynamic program over the last N looks (:mod:`csuas.core.m_of_n`), itself against
  enumeration of every hit/miss pattern.
* GOSPA of a known set of tracks (Stone Soup's metric) against its value by hand.
* Bird radar cross-sections (water spheroid, Vaughn 1985) against the drone's measured distribution at 24
  GHz (``defaults/drone_rcs_statistics.csv``): each class's median inside the drone's 10-90 % band.
* Clutter: the constant-gamma clutter false alarms of every seen cell on flat ground against the closed
  form, and none from the ground a ridge hides.
"""

from __future__ import annotations

import itertools

import numpy as np

from csuas.base.checks import Check
from csuas.core.birds import bird_rcs_m2, random_aspects_rad
from csuas.core.coverage import SitedSensor
from csuas.core.false_alarms import beamwidth_deg
from csuas.core.horizon import EARTH_RADIUS_M
from csuas.core.m_of_n import first_confirmation
from csuas.core.scenario import parse_scenario
from csuas.core.units import C_LIGHT
from csuas.defaults import load_birds, load_drone_rcs_statistics
from csuas.validation.report.registry import CheckGroup, CheckSpec, Section, timed

#: Monte Carlo sizes of the quick report: looks of the false-alarm count, tracker runs of the M-of-N check.
FALSE_ALARM_LOOKS, TRACKER_RUNS = {"quick": 200, "full": 2000}, {"quick": 200, "full": 2000}
CELL_M = 25.0
#: The radar's SNR on the 0.01 m^2 drone: 10 dB at its 445.3 m range (Section 4.9.3), as R^-4 (no losses).
RADAR_RANGE_M, RADAR_SNR_DB = 445.30460703828703, 10.0
#: Per-cell Pfa of the RF and acoustic false-alarm checks (high enough for a count of hundreds in the quick report).
RECEIVER_PFA = {"rf": 1e-4, "acoustic": 2e-2}
#: Largest 3-standard-error band of a receiver's false-alarm rate, relative to the rate, that its look count allows.
RECEIVER_RELATIVE_3SE = 0.1


def _radar(dem, settings, gamma_db=None):
    from csuas.render.engagement.sensors import SensorModel, Terrain

    scenario = parse_scenario(
        {
            "name": "engage_check",
            "convention": "paper",
            "target": {"preset": "dji_mini_4_pro"},
            "environment": {"preset": "clear_day"},
            "sensors": {"radar": {"modality": "radar", "preset": "paper_section_4_9"}},
        }
    )
    terrain = Terrain(dem, CELL_M, 0.0, dem.shape[0] * CELL_M)
    return SensorModel(scenario, SitedSensor("radar", 40.0, 40.0, 10.0), terrain, settings, gamma_db)


def false_alarms(quality="quick") -> Section:
    """Noise false alarms per look with no target against Pfa x cells."""
    from csuas.render.engagement.sensors import LookSettings

    s = Section()
    sensor = _radar(np.zeros((80, 80)), LookSettings(pfa=1e-4, clutter=False))
    rng = np.random.default_rng(5)
    looks = FALSE_ALARM_LOOKS.get(quality, FALSE_ALARM_LOOKS["quick"])
    counts, elapsed = timed(lambda: np.array([len(sensor.false_alarm_xy(rng)) for _ in range(looks)]))
    expected = 1e-4 * sensor.cells
    stderr = float(np.sqrt(sensor.cells * 1e-4 * (1 - 1e-4) / looks))
    s.outcomes.append(
        Check(
            "engage.false_alarms.radar_per_look",
            expected,
            float(counts.mean()),
            3 * stderr,
            "per look",
            error_estimate=stderr,
            time_s=elapsed,
            source=f"Pfa x cells = 1e-4 x {sensor.cells:.0f} (range bins c/2B x beams 360 / theta_3dB in its reach)",
            method=f"{looks} looks of the paper's Section 4.9.3 radar with no target, Pfa 1e-4 per cell",
            tolerance_source="3 Monte Carlo standard errors of the binomial count",
            details={"per_hour_expected_at_1_s": expected * 3600},
        )
    )
    for name, pfa in RECEIVER_PFA.items():
        s.outcomes.append(_receiver_per_hour(name, pfa, looks, rng))
    return s


def _receiver_per_hour(name: str, pfa: float, looks: int, rng) -> Check:
    """An RF or acoustic sensor of the paper's defaults, no target: noise false alarms per hour at 1 s looks."""
    from csuas.render.engagement.sensors import LookSettings, SensorModel, Terrain

    scenario = parse_scenario(
        {
            "name": "engage_check",
            "convention": "paper",
            "target": {"preset": "dji_mini_4_pro"},
            "environment": {"preset": "clear_day"},
            "sensors": {name: {"modality": name}},
        }
    )
    dem = np.zeros((80, 80))
    terrain = Terrain(dem, CELL_M, 0.0, dem.shape[0] * CELL_M)
    settings = LookSettings(pfa=pfa, instrumented_range_m=500.0)
    sensor = SensorModel(scenario, SitedSensor(name, 40.0, 40.0, 10.0), terrain, settings)
    # enough looks for 3 standard errors of the count to stay within 10 % of the expected rate
    looks = max(looks, int(np.ceil(9.0 / (RECEIVER_RELATIVE_3SE**2 * pfa * sensor.cells))))
    counts, elapsed = timed(lambda: np.array([len(sensor.false_alarm_xy(rng)) for _ in range(looks)]))
    per_hour = 3600.0 / settings.revisit_s
    stderr = float(np.sqrt(sensor.cells * pfa * (1 - pfa) / looks)) * per_hour
    rule = "1024 bins x 360 / theta(g_rx_db)" if name == "rf" else "1 band x 360 / theta(g_array_db)"
    return Check(
        f"engage.false_alarms.{name}_per_hour",
        pfa * sensor.cells * per_hour,
        float(counts.mean()) * per_hour,
        3 * stderr,
        "per hour",
        error_estimate=stderr,
        time_s=elapsed,
        source=f"Pfa x cells x 3600 / T = {pfa:g} x {sensor.cells:.0f} x 3600 ({rule})",
        method=f"{looks} looks, 1 s apart, of the default {name} sensor with no target, Pfa {pfa:g} per cell",
        tolerance_source="3 Monte Carlo standard errors of the binomial count",
    )


def enumerated_first_confirmation(pd, m, n):
    """P(first M-of-N confirmation at look k) by enumerating every hit/miss pattern (the exact program's oracle)."""
    out = np.zeros(pd.size)
    for pattern in itertools.product((0, 1), repeat=pd.size):
        hits = np.array(pattern)
        prob = np.prod(np.where(hits == 1, pd, 1 - pd))
        for k in range(pd.size):
            if hits[max(0, k - n + 1) : k + 1].sum() >= m:
                out[k] += prob
                break
    return out


def first_track(quality="quick") -> Section:
    """The tracker's first-track probability of one sensor against the exact M-of-N program."""
    from csuas.render.engagement.sensors import LookSettings
    from csuas.render.engagement.simulate import BirdSettings, DronePath, Engagement, run_once

    s = Section()
    pd = np.random.default_rng(1).uniform(0, 1, 12)
    exact, elapsed = timed(first_confirmation, pd, 3, 5)
    s.outcomes.append(
        Check(
            "engage.m_of_n.dp_vs_enumeration_max_abs",
            0.0,
            float(np.max(np.abs(exact - enumerated_first_confirmation(pd, 3, 5)))),
            1e-12,
            time_s=elapsed,
            source="enumeration of all 2^12 hit/miss patterns, 3 of 5",
            method="the dynamic program over the last N-1 looks",
            tolerance_source="rounding",
        )
    )
    settings = LookSettings(pfa=0.0, clutter=False, decorrelation="independent", sigma_bearing_deg=0.5)
    sensor = _radar(np.zeros((80, 80)), settings)
    path = DronePath(np.array([[sensor.x - 900.0, sensor.y, 30.0], [sensor.x - 20.0, sensor.y, 30.0]]), 15.0)
    engagement = Engagement(sensor.terrain, {"radar": sensor}, path, BirdSettings(0.0, ()), (3, 5), 5, 3, load_birds())
    runs = TRACKER_RUNS.get(quality, TRACKER_RUNS["quick"])
    records, elapsed = timed(lambda: [run_once(engagement, i) for i in range(runs)])
    first = np.array([np.inf if r["first_track_time_s"] is None else r["first_track_time_s"] for r in records])
    looks = engagement.looks["radar"]
    cdf = np.cumsum(first_confirmation(looks.pd, 3, 5))
    measured = np.array([np.mean(first <= t + 1e-9) for t in looks.t_s])
    stderr = np.sqrt(cdf * (1 - cdf) / runs)
    s.outcomes.append(_mean_first_track(cdf, looks.t_s, first, runs, elapsed / 3))
    for level in (0.5, 0.9):  # at 0.1 the binomial bound of a quick run exceeds a fifth of the value
        k = int(np.searchsorted(cdf, level))
        s.outcomes.append(
            Check(
                f"engage.m_of_n.tracker_first_track_p{int(level * 100)}",
                float(cdf[k]),
                float(measured[k]),
                float(3 * stderr[k] + 0.5 / runs),
                "probability",
                error_estimate=float(stderr[k]),
                time_s=elapsed / 3,
                source="exact P(3 of the last 5 looks detect by this look) from the per-look Pd (core/m_of_n.py)",
                method=f"{runs} tracker runs (Stone Soup, 3 of 5) of a drone at 15 m/s toward the radar, no false "
                f"alarms, independent looks; look at t = {looks.t_s[k]:.0f} s",
                tolerance_source="3 binomial standard errors plus half a run",
            )
        )
    worst = float(np.max(np.abs(measured - cdf) - 3 * stderr - 0.5 / runs))
    s.notes.append(f"every look: largest excess over 3 s.e. + 0.5/runs = {worst:.3g} (<= 0 passes)")
    s.outcomes.append(
        Check(
            "engage.m_of_n.every_look_excess",
            0.0,
            max(worst, 0.0),
            0.0,
            time_s=0.0,
            source="the exact program at every look",
            method="largest |tracker - exact| beyond 3 standard errors + 0.5/runs over all looks",
            tolerance_source="none beyond the per-look bound",
        )
    )
    return s


def _mean_first_track(cdf, t_s, first, runs: int, elapsed: float) -> Check:
    """Mean first-track time of the confirmed runs against the exact program's conditional mean."""
    p = np.diff(np.concatenate([[0.0], cdf]))
    mean = float(np.sum(p * t_s) / np.sum(p))
    sd = float(np.sqrt(np.sum(p * (t_s - mean) ** 2) / np.sum(p)))
    confirmed = first[np.isfinite(first)]
    stderr = sd / np.sqrt(max(confirmed.size, 1))
    return Check(
        "engage.m_of_n.tracker_mean_first_track_s",
        mean,
        float(confirmed.mean()) if confirmed.size else float("nan"),
        float(3 * stderr),
        "s",
        error_estimate=float(stderr),
        time_s=elapsed,
        source="the exact first-confirmation distribution (core/m_of_n.py), its mean over confirmed runs",
        method=f"{runs} tracker runs (Stone Soup, 3 of 5), the mean of their first-track times",
        tolerance_source="3 standard errors of a mean of the exact distribution's spread",
    )


def gospa(_knob=None) -> Section:
    """GOSPA of known tracks against the hand-computed value and Stone Soup's own example; SIAP by hand."""
    from csuas.render.engagement.simulate import gospa_distance

    s = Section()
    by_hand = "by hand: (sum of d^p over pairs + c^p / 2 per missed or false)^(1/p)"
    truths = [[float(i), 0.0] for i in range(5)]
    cases = (
        ("one_near_one_false", ([[3.0, 4.0], [500.0, 0.0]], [[0.0, 0.0]]), {}, np.sqrt(25 + 100**2 / 2), by_hand),
        ("missed", ([], [[0.0, 0.0]]), {}, np.sqrt(100**2 / 2), by_hand),
        ("beyond_cutoff", ([[0.0, 200.0]], [[0.0, 0.0]]), {}, np.sqrt(100**2), by_hand),
        (
            "stone_soup_example_half",
            ([[i + 0.5, 0.0] for i in range(5)], truths),
            {"c_m": 10.0, "p": 1},
            2.5,
            "Stone Soup's test_gospametric_computemetric: distance / 5 = 0.5 (c = 10, p = 1)",
        ),
        (
            "stone_soup_example_one",
            ([[i + 1.0, 0.0] for i in range(5)], truths),
            {"c_m": 10.0, "p": 1},
            5.0,
            "Stone Soup's test_gospametric_computemetric: distance / 5 = 1 (c = 10, p = 1)",
        ),
    )
    for name, (tracks, truth), options, expected, source in cases:
        value, elapsed = timed(gospa_distance, tracks, truth, **options)
        s.outcomes.append(
            Check(
                f"engage.gospa.{name}",
                float(expected),
                value,
                1e-9,
                "m",
                time_s=elapsed,
                source=source,
                method="Stone Soup's GOSPAMetric on the tracks against the truths",
                tolerance_source="rounding",
            )
        )
    s.outcomes.extend(_siap_checks())
    return s


def siap_picture() -> tuple:
    """A hand-built picture (tracks, truth): a drone flying 10 m/s along x for 9 s, held by track A (exact,
    0-4 s), then by track B (3 m off, 2 m/s fast, 5-9 s), while track C sits 14 km away."""
    from stonesoup.types.state import State
    from stonesoup.types.track import Track

    from csuas.render.engagement.siap import truth_path
    from csuas.render.engagement.tracker import timestamp

    t = np.arange(10.0)

    def track(times, x_off, dy, vx):
        return Track([State(np.array([[10.0 * k + x_off], [vx], [dy], [0.0]]), timestamp=timestamp(k)) for k in times])

    tracks = [track(range(5), 0.0, 0.0, 10.0), track(range(5, 10), 0.0, 3.0, 12.0), track(t, 1e4, 1e4, 0.0)]
    return tracks, truth_path(t, 10 * t, 0 * t, 10 + 0 * t, 0 * t)


def _siap_checks() -> list:
    """SIAP scores of :func:`siap_picture` against their values by hand."""
    from csuas.render.engagement.siap import siap_scores

    scores, elapsed = timed(siap_scores, *siap_picture(), 100.0)
    expected = {
        "completeness": (1.0, "1", "a track on the drone at each of 10 looks"),
        "spuriousness": (0.5, "1", "10 of 20 track-looks on nothing"),
        "position_accuracy_m": (1.5, "m", "(5 x 0 + 5 x 3 m) / 10 associated track-looks"),
        "velocity_accuracy_m_s": (1.0, "m/s", "(5 x 0 + 5 x 2 m/s) / 10"),
        "track_number_changes_per_s": (0.125, "1/s", "(2 tracks - 1) / 8 s held"),
        "longest_track_segment": (4 / 9, "1", "4 s of a 9 s flight"),
    }
    return [
        Check(
            f"engage.siap.{name}",
            value,
            scores[name],
            1e-9,
            unit,
            time_s=elapsed,
            source=f"by hand (Votruba et al. 2001 definitions): {why}",
            method="Stone Soup's SIAPMetrics with TrackToTruth (2 pairs start, 1 miss ends), 100 m",
            tolerance_source="rounding",
        )
        for name, (value, unit, why) in expected.items()
    ]


def bird_rcs(_knob=None) -> Section:
    """Each bird class's RCS median at 24 GHz inside the drone's measured 10-90 % band."""

    s = Section()
    drone = next(
        r for r in load_drone_rcs_statistics() if r["preset"] == "dji_mini_4_pro" and r["frequency_ghz"] == 24.0
    )
    rng = np.random.default_rng(7)
    centre = (drone["p10_dbsm"] + drone["p90_dbsm"]) / 2
    for name, bird in load_birds().items():
        rcs, elapsed = timed(
            bird_rcs_m2, random_aspects_rad(rng, 20000), bird["body_length_m"], bird["body_diameter_m"], 24.0
        )
        s.outcomes.append(
            Check(
                f"engage.bird_rcs.{name}.median_dbsm",
                centre,
                float(10 * np.log10(np.median(rcs))),
                (drone["p90_dbsm"] - drone["p10_dbsm"]) / 2,
                "dBsm",
                time_s=elapsed,
                source="the DJI Mini 4 Pro's RCS over aspects at 24 GHz VV (SBR-PO, drone_rcs_statistics.csv): "
                f"10-90 % from {drone['p10_dbsm']:.1f} to {drone['p90_dbsm']:.1f} dBsm; birds and small drones "
                "overlap at 24 GHz (Rahman & Robertson 2019)",
                method="water prolate spheroid of the bird's body (Vaughn 1985), uniform aspects",
                tolerance_source="inside the drone's 10-90 % band (expected: its centre)",
            )
        )
    return s


def clutter(_knob=None) -> Section:
    """Constant-gamma clutter on flat ground against the closed form; none behind a ridge."""
    from csuas.render.engagement.sensors import LookSettings

    s = Section()
    sensor, elapsed = timed(_radar, np.zeros((80, 80)), LookSettings(clutter_rejection_db=50.0), -15.0)
    ground = np.hypot(sensor.clutter_xy[:, 0] - sensor.x, sensor.clutter_xy[:, 1] - sensor.y)
    drop = ground**2 / (2 * 4 / 3 * EARTH_RADIUS_M)  # the curvature drop of radio (k = 4/3)
    slant, psi = np.hypot(ground, sensor.eye_z), np.arctan2(sensor.eye_z + drop, ground)
    dr, beam = C_LIGHT / (2 * 50e6), np.radians(beamwidth_deg(35.0))
    area = slant * beam * dr / np.cos(psi)
    cnr = 10 ** ((RADAR_SNR_DB + 40 * np.log10(RADAR_RANGE_M / slant)) / 10) * 10 ** (-1.5) * np.sin(psi) * area / 0.01
    rate = CELL_M**2 / area * (1e-6 ** (1 / (1 + cnr * 1e-5)) - 1e-6)
    s.outcomes.append(
        Check(
            "engage.clutter.flat_ground_max_rel_error",
            0.0,
            float(np.max(np.abs(sensor.clutter_rate / rate - 1))),
            1e-9,
            time_s=elapsed,
            source="sigma0 = gamma sin(psi), gamma -15 dB; cell R theta dR / cos(psi); SNR 10 dB at 445.3 m as "
            "R^-4; false alarms Pfa^(1/(1+CNR')) - Pfa per resolution cell, 50 dB Doppler rejection",
            method=f"every seen 25 m cell of flat ground within the radar's reach ({sensor.clutter_rate.size} cells)",
            tolerance_source="rounding",
        )
    )
    ridge = np.zeros((80, 80))
    ridge[:, 50:52] = 60.0
    hidden, elapsed = timed(_radar, ridge, LookSettings(clutter_rejection_db=0.0), -10.0)
    behind = int(np.sum(hidden.clutter_xy[:, 0] > 52 * CELL_M))
    s.outcomes.append(
        Check(
            "engage.clutter.cells_behind_ridge",
            0.0,
            float(behind),
            0.0,
            "cells",
            time_s=elapsed,
            source="a 60 m ridge 250 m east of a 10 m mast hides the ground beyond it",
            method="clutter cells of the radar east of the ridge",
            tolerance_source="none: hidden ground returns no clutter",
        )
    )
    return s


#: The report section of these checks.
GROUP = CheckGroup(
    "engage",
    "Engagements: false alarms, M-of-N first tracks, GOSPA, bird RCS and clutter vs closed forms",
    100,
    "Simulated engagements (csuas engage) against closed forms: false alarms, M-of-N first tracks, GOSPA, "
    "bird RCS and clutter.",
)


SPECS = [
    CheckSpec(
        "engage.false_alarms",
        "False alarms with no target vs Pfa x resolution cells",
        GROUP,
        "noise false alarms per look of a radar, and per hour of an RF and an acoustic sensor (Monte Carlo), "
        "vs Pfa x range bins x beams and Pfa x frequency bins x bearing cells x looks per hour",
        "3 Monte Carlo standard errors",
        false_alarms,
        "looks",
        FALSE_ALARM_LOOKS,
        False,
    ),
    CheckSpec(
        "engage.m_of_n",
        "First track of one sensor vs the exact M-of-N program",
        GROUP,
        "the tracker's probability of a confirmed track by each look vs the dynamic program over the last N looks "
        "(itself vs enumeration)",
        "3 binomial standard errors + half a run; 1e-12 for the program vs enumeration",
        first_track,
        "tracker runs",
        TRACKER_RUNS,
        False,
    ),
    CheckSpec(
        "engage.gospa",
        "GOSPA and SIAP of known tracks vs the hand-computed values",
        GROUP,
        "Stone Soup's GOSPA (p = 2, c = 100 m, alpha = 2; its own c = 10, p = 1 example) and SIAP vs values by hand",
        "1e-9 m",
        gospa,
    ),
    CheckSpec(
        "engage.bird_rcs",
        "Bird RCS vs the drone's measured distribution at 24 GHz",
        GROUP,
        "each bird class's median RCS (water spheroid over aspects) vs the drone's 10-90 % band",
        "inside the band",
        bird_rcs,
    ),
    CheckSpec(
        "engage.clutter",
        "Ground clutter vs the constant-gamma closed form, and terrain masking",
        GROUP,
        "clutter false alarms of flat ground vs the closed form; clutter cells behind a ridge",
        "1e-9 relative; none behind the ridge",
        clutter,
    ),
]
