"""One sensor of an engagement: where it sees, what it detects at each look, and what it reports.

Every look of a sensor at a point (the drone, a bird) takes the point's line of sight over the terrain
(:func:`csuas.core.terrain.line_of_sight`, the modality's refraction), its field of regard (sector,
elevation limits, minimum range; :mod:`csuas.core.coverage`) and its slant range from the eye; the
drone's Pd there is the sensor's Pd curve (:func:`csuas.core.pd_curves.sensor_pd`). A bird's Pd comes
from its own signature: on radar its RCS at that aspect (:func:`csuas.core.birds.bird_rcs_m2`) as a
steady target at the SNR that RCS gives; on a camera the drone's Pd at the range where the drone
subtends what the bird does (Johnson's cycles scale as d_crit / R, Eq. 17), d_crit of the bird
sqrt(wingspan x body diameter) until rendered bird signatures (drone_models/birds.py) replace it
(:meth:`SensorModel.bird_pd`); on a lidar the drone's Pd with the drone's lidar cross-section and
projected area scaled by the bird's d_crit^2 over the drone's (the same seam, the same reflectance);
RF and acoustic sensors see no bird (a bird emits no radio signal, and its wingbeat is quiet in the
drone's rotor bands: Pd 0). Where the terrain hides the drone the Pd is 0, except for an acoustic
array of the physical convention, which hears it over the terrain's top edge less the ISO 9613-2
barrier attenuation (:func:`csuas.core.barrier.terrain_barrier_db`). A detection reports the ground
bearing and ground range from the sensor with Gaussian noise: a radar and a lidar their measured
range; a camera its bearing and a range from the target's apparent size, with a relative error
(passive ranging); an RF direction finder and an acoustic array their bearing and a coarse range
from the received level (the level's spread of a few dB inverted through spherical spreading, a
relative error of 50 %).

False alarms per look are binomial with the sensor's cells and Pfa (:mod:`csuas.core.false_alarms`;
the cells by modality in :meth:`SensorModel.cells_per_look`), placed uniformly over the ground area of
its field of regard out to its reach. Ground clutter
(radar): every DEM cell the radar sees, inside its sector and reach, holds cell area / (dR R theta)
resolution cells of constant-gamma clutter (:mod:`csuas.core.clutter`); each raises a false alarm at a
fixed threshold with probability Pfa^(1/(1+CNR')) (the excess over Pfa is counted as clutter), placed
in that DEM cell. The grazing angle is the depression of the cell from the eye (the local slope is
left out).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core import birds as bird_model
from csuas.core import clutter, false_alarms, radar, radar_detection
from csuas.core.acoustic_spectrum import BAND_NUMBERS
from csuas.core.barrier import barrier_frequency_hz, terrain_barrier_db
from csuas.core.coverage import K_FACTOR, SitedSensor, elevation_deg, mapped_reach_m
from csuas.core.pd_curves import acoustic_pd_with_loss, margin_db, sensor_pd
from csuas.core.scenario import Scenario
from csuas.core.terrain import RayLimits, bearing_deg, height_at, line_of_sight, off_boresight_deg, viewshed

#: Defaults of ``[looks.NAME]`` by modality (docs/engagements.md); the rest are LookSettings' own. RF and
#: acoustic ranges come from the received level: a level known to +-4.3 dB (emitter power, fading,
#: directivity) is a relative range error of 4.3 ln(10) / 20 = 0.5 through spherical spreading.
LOOK_DEFAULTS = {
    "radar": {"revisit_s": 1.0, "sigma_range_m": 5.0, "sigma_range_fraction": 0.0, "sigma_bearing_deg": 1.0},
    "eo": {"revisit_s": 1.0, "sigma_range_m": 0.0, "sigma_range_fraction": 0.2, "sigma_bearing_deg": 0.05},
    "tir": {"revisit_s": 1.0, "sigma_range_m": 0.0, "sigma_range_fraction": 0.2, "sigma_bearing_deg": 0.05},
    "rf": {"revisit_s": 1.0, "sigma_range_m": 0.0, "sigma_range_fraction": 0.5, "sigma_bearing_deg": 3.0},
    "acoustic": {"revisit_s": 1.0, "sigma_range_m": 0.0, "sigma_range_fraction": 0.5, "sigma_bearing_deg": 2.0},
    "lidar": {"revisit_s": 1.0, "sigma_range_m": 0.5, "sigma_range_fraction": 0.0, "sigma_bearing_deg": 0.1},
}
#: Modalities an engagement simulates: those with look defaults and a cell rule (:meth:`SensorModel.cells_per_look`).
ENGAGED_MODALITIES = tuple(LOOK_DEFAULTS)
#: An RF channeliser's frequency bins per bearing cell (assumption: a 1024-point FFT over the monitored band).
RF_FREQUENCY_BINS = 1024
#: A scanning lidar's beam positions per look (assumption: a 100 x 100 scan pattern).
LIDAR_BEAM_POSITIONS = 10_000
#: A lidar's range gate [m] (assumption: a 10 ns gate, c tau / 2).
LIDAR_RANGE_GATE_M = 1.5
#: Gain [dB] below which a receiver's bearing cell is taken as 1 rad wide (the pencil-beam rule's limit).
BEARING_CELL_MIN_GAIN_DB = 11.0


@dataclass(frozen=True)
class Terrain:
    """A north-up DEM and where it lies: heights [m], cell size [m], its west and north edges in the CRS [m]."""

    dem_m: np.ndarray
    cell_m: float
    west_m: float
    north_m: float

    def rowcol(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """Fractional (row, col) of CRS points (cell centres at whole numbers)."""
        x, y = np.asarray(x, float), np.asarray(y, float)
        return (self.north_m - y) / self.cell_m - 0.5, (x - self.west_m) / self.cell_m - 0.5

    def xy(self, row, col) -> tuple[np.ndarray, np.ndarray]:
        """CRS (x, y) of fractional cell positions."""
        return self.west_m + (np.asarray(col) + 0.5) * self.cell_m, self.north_m - (np.asarray(row) + 0.5) * self.cell_m

    def height(self, x, y) -> np.ndarray:
        """Terrain height [m] under CRS points (bilinear)."""
        row, col = self.rowcol(x, y)
        return height_at(self.dem_m, np.atleast_1d(row), np.atleast_1d(col)).reshape(np.shape(x))


@dataclass(frozen=True)
class LookSettings:
    """How one sensor looks and reports (``[looks.NAME]``; defaults by modality in docs/engagements.md).

    Attributes
    ----------
    revisit_s : float
        Time between looks [s].
    sigma_range_m, sigma_range_fraction : float
        Range noise [m] and its part proportional to range [-]: sigma_R = a + b R.
    sigma_bearing_deg : float
        Bearing noise [deg].
    pfa : float or None
        Per-cell false-alarm probability; None: the sensor's ``pfa``.
    frames_per_look : int or None
        Camera frames per look; None: enough fields of view to cover the sector.
    doppler_bins, elevation_beams : int
        Radar cells per range-beam cell (Doppler filters) and stacked elevation beams.
    instrumented_range_m : float or None
        The reach searched for detections and false alarms [m]; None: the sensor's mapped reach.
    land_cover : str
        Land cover of the constant-gamma clutter (``defaults/clutter.toml``); radar only.
    clutter_rejection_db : float
        Doppler (MTI) clutter attenuation before the fixed threshold [dB].
    clutter : bool
        Whether the radar's ground clutter is simulated.
    decorrelation : str
        ``aspect`` (radar: the drone's RCS decorrelates with its aspect change), ``independent`` or
        ``correlated`` looks; None: ``aspect`` for radar, the sensor's ``looks`` otherwise.
    attitude_jitter_deg : float
        RMS change of the drone's attitude between looks [deg] (wind, control), added to the aspect change.
    frequency_bins : int or None
        RF: channeliser bins (None: RF_FREQUENCY_BINS); acoustic: frequency bands (None: the 24
        one-third-octave bands 50 Hz-10 kHz of the physical convention's ``bands`` detector, else 1).
    bearing_cells : int or None
        RF and acoustic: bearing cells across the sector; None: sector / theta, theta = sqrt(4 pi / G)
        of the RF antenna's gain or the acoustic array's gain (its directivity), 1 rad below 11 dB.
    range_gate_m : float
        Lidar range gate [m].
    beam_positions : int
        Lidar beam positions per look (one scan).
    """

    revisit_s: float = 1.0
    sigma_range_m: float = 5.0
    sigma_range_fraction: float = 0.0
    sigma_bearing_deg: float = 1.0
    pfa: float | None = None
    frames_per_look: int | None = None
    doppler_bins: int = 1
    elevation_beams: int = 1
    instrumented_range_m: float | None = None
    land_cover: str = "rolling_hills"
    clutter_rejection_db: float = 0.0
    clutter: bool = True
    decorrelation: str | None = None
    attitude_jitter_deg: float = 2.0
    frequency_bins: int | None = None
    bearing_cells: int | None = None
    range_gate_m: float = LIDAR_RANGE_GATE_M
    beam_positions: int = LIDAR_BEAM_POSITIONS


@dataclass
class Geometry:
    """Where points lie as one sensor sees them (arrays over the points)."""

    ground_m: np.ndarray
    slant_m: np.ndarray
    bearing_rad: np.ndarray  # mathematical angle from +x (east) toward +y (north), Stone Soup's bearing
    in_regard: np.ndarray
    visible: np.ndarray
    barrier_db: np.ndarray | None = None  # acoustic, physical convention: ISO 9613-2 A_bar where the terrain hides


class SensorModel:
    """A sited sensor of a scenario, looking at an engagement's points over a terrain."""

    def __init__(
        self, scenario: Scenario, sited: SitedSensor, terrain: Terrain, settings: LookSettings, clutter_gamma_db=None
    ):
        self.scenario, self.sited, self.terrain, self.settings = scenario, sited, terrain, settings
        self.name = sited.name
        self.spec = scenario.sensors[sited.name]
        self.modality = self.spec.modality
        self.k_factor = K_FACTOR[self.modality]
        if settings.decorrelation == "aspect" and self.modality != "radar":
            raise ParameterError(
                f"looks.{self.name}.decorrelation", "aspect", "independent or correlated (aspect: a radar's rule)"
            )
        self.x, self.y = (float(v) for v in terrain.xy(sited.row, sited.col))
        self.eye_z = float(height_at(terrain.dem_m, np.array([sited.row]), np.array([sited.col]))[0]) + sited.mast_m
        farthest = float(np.hypot(*terrain.dem_m.shape) * terrain.cell_m)
        reach = settings.instrumented_range_m or mapped_reach_m(scenario, sited.name, farthest)
        self.reach_m = float(min(reach, farthest))
        self.pfa = float(settings.pfa if settings.pfa is not None else self.spec.params["pfa"])
        self.cells = self._cells()
        self.false_alarms_per_look = float(false_alarms.false_alarms_per_look(self.pfa, self.cells))
        self.clutter_xy, self.clutter_rate = np.empty((0, 2)), np.empty(0)
        self.barrier_hz = barrier_frequency_hz(scenario, sited.name)
        if self.modality == "radar" and settings.clutter and clutter_gamma_db is not None:
            self.clutter_xy, self.clutter_rate = self._clutter_map(float(clutter_gamma_db))

    # --- cells and false alarms -------------------------------------------------------------
    def beam_deg(self) -> float:
        """Radar azimuth beamwidth from its receive gain [deg]."""
        return float(false_alarms.beamwidth_deg(self.spec.params["g_rx_db"]))

    def range_resolution_m(self) -> float:
        """Radar range bin c / 2B [m]."""
        return float(false_alarms.range_resolution_m(self.spec.params["bandwidth_mhz"]))

    def frames_per_look(self) -> int:
        """Camera frames per look: the spec's, or the fields of view that cover the sector."""
        if self.settings.frames_per_look is not None:
            return int(self.settings.frames_per_look)
        return int(np.ceil(self.sited.sector_deg / self.spec.params["hfov_deg"] - 1e-9))

    def _cells(self) -> float:
        """Cells tested per look by modality (:mod:`csuas.core.false_alarms`; docs/engagements.md)."""
        p, low = self.spec.params, min(self.sited.min_range_m, 0.99 * self.reach_m)
        if self.modality == "radar":
            return false_alarms.radar_cells(
                self.reach_m,
                low,
                self.range_resolution_m(),
                self.sited.sector_deg,
                self.beam_deg(),
                self.settings.doppler_bins,
                self.settings.elevation_beams,
            )
        if self.modality in ("rf", "acoustic"):
            return false_alarms.receiver_cells(self.frequency_bins(), self.sited.sector_deg, self.bearing_cell_deg())
        if self.modality == "lidar":
            return false_alarms.lidar_cells(self.reach_m, low, self.settings.range_gate_m, self.settings.beam_positions)
        return false_alarms.imaging_cells(p["n_h"], p["n_v"], self.frames_per_look())

    def frequency_bins(self) -> int:
        """RF channeliser bins or acoustic frequency bands tested at each bearing (LookSettings.frequency_bins)."""
        if self.settings.frequency_bins is not None:
            return int(self.settings.frequency_bins)
        if self.modality == "rf":
            return RF_FREQUENCY_BINS
        bands = self.scenario.convention == "physical" and self.spec.params["detector"] == "bands"
        return BAND_NUMBERS.size if bands else 1  # the paper's acoustic model is one broadband SNR

    def bearing_cell_deg(self) -> float:
        """Width of an RF or acoustic bearing cell [deg]: sector / bearing_cells, else the beam of its gain."""
        if self.settings.bearing_cells is not None:
            return self.sited.sector_deg / int(self.settings.bearing_cells)
        gain_db = self.spec.params["g_rx_db" if self.modality == "rf" else "g_array_db"]
        return float(false_alarms.beamwidth_deg(max(float(gain_db), BEARING_CELL_MIN_GAIN_DB)))

    def false_alarm_xy(self, rng: np.random.Generator) -> np.ndarray:
        """Noise false alarms of one look, uniform over the ground area of the field of regard (n, 2) [m]."""
        count = rng.binomial(int(round(self.cells)), self.pfa)
        low = min(self.sited.min_range_m, 0.99 * self.reach_m)
        ground = np.sqrt(rng.uniform(low**2, self.reach_m**2, count))
        bearing = np.radians(self.sited.azimuth_deg + rng.uniform(-0.5, 0.5, count) * self.sited.sector_deg)
        return np.stack([self.x + ground * np.sin(bearing), self.y + ground * np.cos(bearing)], axis=1)

    def clutter_alarm_xy(self, rng: np.random.Generator) -> np.ndarray:
        """Clutter false alarms of one look: Poisson per seen DEM cell, placed uniformly in it (n, 2) [m]."""
        counts = rng.poisson(self.clutter_rate)
        where = np.repeat(self.clutter_xy, counts, axis=0)
        return where + rng.uniform(-0.5, 0.5, where.shape) * self.terrain.cell_m

    # --- radar signal -------------------------------------------------------------------
    def radar_snr_db(self, range_m, rcs_m2) -> np.ndarray:
        """Integrated SNR [dB] of a steady target of ``rcs_m2`` at ``range_m`` (the budget's margin, pd_curves)."""
        p, convention = self.spec.params, self.scenario.convention
        gain_db = 10 * np.log10(float(radar.integration_gain(int(p["n_pulses"]), p["integration"], convention)))
        m = margin_db(self.scenario, self.spec, convention, np.asarray(range_m, float))
        single = (
            p["snr_min_db"] - gain_db + m + 10 * np.log10(np.asarray(rcs_m2) / self.scenario.target["sigma_radar_m2"])
        )
        return single + gain_db

    def wavelength_m(self) -> float:
        """Radar wavelength [m]."""
        return float(radar.radar_wavelength_m(self.spec.params, self.scenario.convention))

    def _clutter_map(self, gamma_db: float) -> tuple[np.ndarray, np.ndarray]:
        """Seen DEM cells in the sector and reach, and their clutter false alarms per look (above Pfa)."""
        t, s = self.terrain, self.sited
        seen = viewshed(
            t.dem_m,
            t.cell_m,
            s.row,
            s.col,
            s.mast_m,
            0.0,
            self.k_factor,
            RayLimits(self.reach_m, None if s.sector_deg >= 360 else (s.azimuth_deg, s.sector_deg)),
        )
        rows, cols = np.nonzero(seen)
        ground = np.hypot(rows - s.row, cols - s.col) * t.cell_m
        keep = (ground >= max(s.min_range_m, t.cell_m)) & (ground <= self.reach_m)
        rows, cols, ground = rows[keep], cols[keep], ground[keep]
        depression = -np.radians(elevation_deg(ground, t.dem_m[rows, cols] - self.eye_z, self.k_factor))
        grazing = np.clip(depression, 0.0, np.pi / 2)
        slant = np.hypot(ground, t.dem_m[rows, cols] - self.eye_z)
        beam, dr = np.radians(self.beam_deg()), self.range_resolution_m()
        sigma_c = clutter.cell_rcs_m2(gamma_db, grazing, slant, dr, beam)
        cnr = 10 ** (self.radar_snr_db(slant, np.maximum(sigma_c, 1e-30)) / 10)
        resolution_cells = t.cell_m**2 / (dr * slant * beam / np.maximum(np.cos(grazing), 1e-6))
        excess = clutter.exceedance(self.pfa, cnr, self.settings.clutter_rejection_db) - self.pfa
        rate = resolution_cells * np.maximum(excess, 0.0)
        x, y = t.xy(rows, cols)
        busy = rate > 1e-9
        return np.stack([x, y], axis=1)[busy], rate[busy]

    # --- geometry, Pd, measurements -------------------------------------------------------
    def geometry(self, x, y, z) -> Geometry:
        """Ground and slant range, bearing, field of regard and line of sight of points at CRS (x, y, z)."""
        x, y, z = (np.atleast_1d(np.asarray(v, float)) for v in (x, y, z))
        dx, dy, rise = x - self.x, y - self.y, z - self.eye_z
        ground = np.hypot(dx, dy)
        slant = np.hypot(ground, rise)
        compass = np.degrees(np.arctan2(dx, dy)) % 360.0
        s = self.sited
        elevation = elevation_deg(ground, rise, self.k_factor)
        regard = (
            ((np.abs(off_boresight_deg(compass, s.azimuth_deg)) <= s.sector_deg / 2) | (ground == 0))
            & (elevation >= s.elevation_min_deg)
            & (elevation <= s.elevation_max_deg)
            & (slant >= s.min_range_m)
            & (ground <= self.reach_m)
        )
        visible = np.zeros(x.shape, dtype=bool)
        if regard.any():
            rows, cols = self.terrain.rowcol(x[regard], y[regard])
            visible[regard] = line_of_sight(
                self.terrain.dem_m,
                self.terrain.cell_m,
                (s.row, s.col, self.eye_z),
                np.stack([rows, cols, z[regard]], axis=1),
                self.k_factor,
            )
        barrier = None
        if self.barrier_hz is not None:
            barrier = np.zeros(x.shape)
            hidden = regard & ~visible
            if hidden.any():
                rows, cols = self.terrain.rowcol(x[hidden], y[hidden])
                barrier[hidden] = terrain_barrier_db(
                    self.scenario,
                    self.name,
                    self.terrain.dem_m,
                    self.terrain.cell_m,
                    (s.row, s.col, self.eye_z),
                    np.stack([rows, cols, z[hidden]], axis=1),
                    slant[hidden],
                )
        return Geometry(ground, slant, np.arctan2(dy, dx), regard, visible, barrier)

    def drone_pd(self, geometry: Geometry, scenario: Scenario | None = None) -> np.ndarray:
        """The drone's Pd at each point: the sensor's Pd at the slant range where seen, else 0.

        An acoustic array of the physical convention hears a drone the terrain hides, through the barrier
        attenuation of the terrain's top edge (ISO 9613-2, Section 7.4; :mod:`csuas.core.barrier`).
        ``scenario`` replaces the sensor's (a swarm's merged group: :mod:`csuas.render.engagement.swarm`).
        """
        scenario = self.scenario if scenario is None else scenario
        gate = geometry.in_regard & geometry.visible
        pd = np.zeros(geometry.slant_m.shape)
        if gate.any():
            pd[gate] = sensor_pd(scenario, self.name, geometry.slant_m[gate]).pd
        if geometry.barrier_db is not None:
            hidden = geometry.in_regard & ~geometry.visible
            if hidden.any():
                pd[hidden] = acoustic_pd_with_loss(
                    scenario, self.name, geometry.slant_m[hidden], geometry.barrier_db[hidden]
                )
        return pd

    def bird_pd(self, geometry: Geometry, bird: dict, aspect_rad) -> np.ndarray:
        """A bird's Pd at each point: radar from its RCS at its aspect, cameras, lidar from size; RF and acoustic 0."""
        gate = geometry.in_regard & geometry.visible
        pd = np.zeros(geometry.slant_m.shape)
        if not gate.any():
            return pd
        slant = geometry.slant_m[gate]
        if self.modality == "radar":
            frequency = radar.radar_frequency_ghz(self.spec.params)
            rcs = bird_model.bird_rcs_m2(
                np.asarray(aspect_rad)[gate], bird["body_length_m"], bird["body_diameter_m"], frequency
            )
            p = self.spec.params
            n, mode = (1, "noncoherent") if p["integration"] == "none" else (int(p["n_pulses"]), p["integration"])
            gain_db = 10 * np.log10(
                float(radar.integration_gain(int(p["n_pulses"]), p["integration"], self.scenario.convention))
            )
            if self.pfa > 0:  # Pfa 0 (no noise alarms): the look's threshold is infinite, no bird crosses it
                pd[gate] = radar_detection.pd_exact(self.radar_snr_db(slant, rcs) - gain_db, self.pfa, n, 0, mode)
            return pd
        if self.modality in ("rf", "acoustic"):
            return pd  # a bird emits no radio signal and is quiet in the drone's rotor bands: Pd 0
        scale = self.scenario.target["d_crit_m"] / bird_critical_dimension_m(bird)
        if self.modality == "lidar":
            pd[gate] = sensor_pd(self.bird_scenario(scale), self.name, slant).pd
            return pd
        pd[gate] = sensor_pd(self.scenario, self.name, slant * scale).pd
        return pd

    def bird_scenario(self, scale: float) -> Scenario:
        """The scenario with the drone's lidar cross-section and projected area times 1 / scale^2 (a bird's size)."""
        t = self.scenario.target
        area = 1.0 / scale**2
        target = {**t, "sigma_lidar_m2": t["sigma_lidar_m2"] * area, "projected_area_m2": t["projected_area_m2"] * area}
        return replace(self.scenario, target=target)

    def look_correlation(self, aspect_change_rad) -> np.ndarray:
        """Correlation of the drone's detection draws between successive looks (docs/engagements.md).

        ``aspect``: exp(-delta / theta_c), delta the change of the drone's aspect between looks
        combined with the attitude jitter (sqrt(delta^2 + 2 j^2)), theta_c = lambda / (2 L) the aspect
        over which the RCS of a body of size L decorrelates, L the diameter of the drone's projected
        area; ``independent``: 0; ``correlated``: 1.
        """
        rule = self.settings.decorrelation or ("aspect" if self.modality == "radar" else self.spec.params["looks"])
        delta = np.asarray(aspect_change_rad, float)
        if rule == "independent":
            return np.zeros(delta.shape)
        if rule == "correlated":
            return np.ones(delta.shape)
        size = 2.0 * np.sqrt(self.scenario.target["projected_area_m2"] / np.pi)
        theta_c = self.wavelength_m() / (2.0 * size)
        jitter = np.radians(self.settings.attitude_jitter_deg)
        return np.exp(-np.sqrt(delta**2 + 2 * jitter**2) / theta_c)

    def range_sigma_m(self, ground_m) -> np.ndarray:
        """Range noise at each ground range [m]."""
        return self.settings.sigma_range_m + self.settings.sigma_range_fraction * np.asarray(ground_m, float)

    def measure(self, rng: np.random.Generator, x, y) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Noisy (bearing [rad], ground range [m]) of points at (x, y), and the range noise used [m]."""
        dx, dy = np.asarray(x, float) - self.x, np.asarray(y, float) - self.y
        ground = np.hypot(dx, dy)
        sigma_r = self.range_sigma_m(ground)
        bearing = np.arctan2(dy, dx) + rng.normal(0.0, np.radians(self.settings.sigma_bearing_deg), ground.shape)
        measured = np.abs(ground + rng.normal(0.0, 1.0, ground.shape) * sigma_r)
        return bearing, measured, sigma_r

    def covers(self, x, y) -> np.ndarray:
        """Whether ground points lie in the sensor's sector and reach (a track there expects its looks)."""
        dx, dy = np.asarray(x, float) - self.x, np.asarray(y, float) - self.y
        ground = np.hypot(dx, dy)
        aside = np.abs(off_boresight_deg(bearing_deg(-dy, dx), self.sited.azimuth_deg))
        return (ground <= self.reach_m) & ((aside <= self.sited.sector_deg / 2) | (ground == 0))


def bird_critical_dimension_m(bird: dict) -> float:
    """A bird's critical dimension for Johnson's criteria, sqrt(wingspan x body diameter) [m]."""
    return float(np.sqrt(bird["wingspan_m"] * bird["body_diameter_m"]))
