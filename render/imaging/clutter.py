"""Ground and skyline clutter of a ``csuas dataset`` frame (docs/datasets.md, spec table ``[clutter]``): land-cover
terrain below the horizon, hills, trees and buildings along the skyline, power lines and soft clouds, in both
bands. Built only for the keys a spec declares.

Every layer is computed per pixel from the frame's viewing rays (``z`` up; the drone's body frame of a still,
east-north-up in a sequence, so that clutter stays put in the world while the camera pans) and added to the
background under the drone (:func:`csuas.render.imaging.compose.blend`), farthest first:

* ``clouds`` (share of the sky): the clear sky's fractal cloud field (:func:`csuas.render.imaging.background.
  cloud_field`) through a smoothstep over twice the field's spread (soft, graded edges instead of a mask),
  lit as a white Lambertian sheet under the illuminance, darker by up to 30 % where the field is thin
  (EO); at the ambient temperature less ``CLOUD_BELOW_AMBIENT_K`` (thermal, opaque where thick);
* ``terrain``: flat ground ``camera_height_m`` below the camera (the ray of a pixel below the horizon meets it
  at distance h / (-z)), or with ``relief_m`` a seeded fractal DEM cast column by column (:func:`_relief_hits`);
  land cover there from two seeded value-noise fields over the ground (metres), with
  the shares of ``LAND_COVER_SHARES``; octaves finer than twice a pixel's ground footprint
  (t IFOV / -z) are left out, so the far ground does not alias;
* ``skyline``: a band of hills (a seeded fractal ridge, forest, at ``HILLS_DISTANCE_M``), tree crowns and
  buildings standing at ``SKYLINE_DISTANCE_M`` on the flat ground, heights from seeded 1-D noise along the
  azimuth; an object covers the elevations from its foot, atan(-h / D), to its top, atan((H - h) / D);
* ``power_lines``: conductors strung across the view at a drawn distance (50-300 m), catenaries
  z(x) = z_0 + a (cosh(x / a) - 1) between towers 300 m apart (a = 1000 m: a sag of 11 m), each a cylinder
  of ``CONDUCTOR_DIAMETER_M`` whose coverage of a pixel column is its angular width over the IFOV (anti-aliased).

Surfaces (Lambertian, lit by the horizontal illuminance E_v: L = rho E_v / pi; thermal: eps B(T) + (1 - eps)
B(T_air)) take the figures of ``SURFACES``: visible reflectance and LWIR emissivity from the ECOSTRESS /
ASTER spectral library (Meerdink et al., Remote Sens. Environ. 230, 2019; Baldridge et al. 2009) rounded,
daytime surface temperature above the air from Oke, Boundary Layer Climates, 2nd ed., 1987 (typical
midday values: vegetation near the air temperature, asphalt and roofs well above it), assumptions within
those ranges.

With ``context["path"]`` (a frame whose scenario declares weather, :func:`csuas.render.imaging.dataset`), each
layer's light takes the path at its own distance along each pixel's ray, as the drone's does at its range
(:func:`csuas.render.imaging.path.eo_path_at` / ``tir_path_at``): a L becomes tau(r) a L + a L_path(r), the
terrain at each pixel's ground distance, the skyline at its distance over the ray's horizontal share, a power
line at the conductor's distance. Clouds are part of the sky seen through the whole atmosphere (as the clear
sky's gradient, :func:`csuas.render.imaging.frame.eo_frame`) and take none.
"""

from __future__ import annotations

import math

import numpy as np

from csuas.core.radiometry import band_radiance

#: Surfaces: visible reflectance, LWIR emissivity, daytime temperature above the air [K] (module docstring).
SURFACES = {
    "grass": (0.10, 0.98, 2.0),
    "forest": (0.05, 0.98, 1.0),
    "road": (0.08, 0.95, 15.0),
    "buildings": (0.30, 0.92, 8.0),
    "power_line": (0.20, 0.80, 3.0),  # weathered conductor: absorptivity and emissivity 0.8 (IEEE Std 738-2012)
}
#: Shares of the land cover of the terrain (assumption: a mixed rural-suburban site).
LAND_COVER_SHARES = {"grass": 0.5, "forest": 0.3, "road": 0.05, "buildings": 0.15}
#: Codes of the per-pixel background class map (difficulty annotations).
CLASSES = (
    "sky",
    "cloud",
    "sun",
    "terrain",
    "grass",
    "forest",
    "road",
    "buildings",
    "skyline_trees",
    "skyline_buildings",
    "power_line",
)
#: Distance of the skyline's trees and buildings, and of the hills [m].
SKYLINE_DISTANCE_M, HILLS_DISTANCE_M = 800.0, 4000.0
#: Diameter of a power-line conductor [m] (a 26 mm ACSR conductor, IEEE Std 738 examples).
CONDUCTOR_DIAMETER_M = 0.026
#: Catenary parameter [m] and tower spacing [m] of the power lines (assumption: a distribution line).
CATENARY_M, TOWER_SPACING_M, TOWER_HEIGHT_M = 1000.0, 300.0, 25.0
#: A cloud's temperature below the ambient air [K] (assumption: a low cloud base).
CLOUD_BELOW_AMBIENT_K = 12.0


def frame_rays(n_h: int, n_v: int, ifov_rad: float, item: dict) -> np.ndarray:
    """Unit rays (n_v, n_h, 3) of a frame, ``z`` up: the drone's body frame of a still, east-north-up in a
    sequence (the body frame turned by the drone's heading, sun_world - sun_azimuth)."""
    from csuas.render.imaging.background import view_rays

    rays = view_rays(n_h, n_v, ifov_rad, item["azimuth_deg"], item["elevation_deg"], item["target_offset_px"])
    if "sun_world_deg" not in item:
        return rays
    heading = math.radians(item["sun_world_deg"] - item["sun_azimuth_deg"])
    c, s = math.cos(heading), math.sin(heading)
    return np.stack([c * rays[..., 0] - s * rays[..., 1], s * rays[..., 0] + c * rays[..., 1], rays[..., 2]], -1)


def value_noise(x: np.ndarray, y: np.ndarray, seed: int, cell_m: float, octaves: int, footprint=None) -> np.ndarray:
    """Seeded fractal value noise (about -1..1) at ground points [m]: octaves of bilinear lattice noise, each of
    half the cell and half the weight of the last; an octave whose cell is under twice ``footprint`` is left out."""
    table = np.random.default_rng([int(seed), 9]).uniform(-1.0, 1.0, (256, 256))
    total, weight, norm = np.zeros(np.shape(x)), 1.0, 0.0
    for octave in range(octaves):
        cell = cell_m / 2**octave
        keep = 1.0 if footprint is None else np.clip(cell / (2.0 * footprint) - 1.0, 0.0, 1.0)
        norm += weight
        if not np.any(keep):  # finer than every pixel's footprint
            weight /= 2.0
            continue
        u, v = np.asarray(x) / cell + 17.3 * octave, np.asarray(y) / cell + 5.1 * octave
        i, j = np.floor(u).astype(np.int64), np.floor(v).astype(np.int64)
        fu, fv = u - i, v - j
        i0, j0, i1, j1 = i % 256, j % 256, (i + 1) % 256, (j + 1) % 256
        sample = (1 - fu) * ((1 - fv) * table[i0, j0] + fv * table[i0, j1]) + fu * (
            (1 - fv) * table[i1, j0] + fv * table[i1, j1]
        )
        total += weight * keep * sample
        weight /= 2.0
    return total / norm


def _surface_light(name: str, context: dict) -> float:
    """EO luminance [cd/m^2] or thermal band radiance of a surface class (module docstring)."""
    reflectance, emissivity, above_k = SURFACES[name]
    if context["band"] == "eo":
        return reflectance * context["illuminance_lx"] / math.pi

    air = context["ambient_k"]
    return float(
        emissivity * band_radiance(air + above_k, context["band"])
        + (1 - emissivity) * band_radiance(air, context["band"])
    )


def _land_cover(x: np.ndarray, y: np.ndarray, footprint: np.ndarray, context: dict, seed: int) -> tuple:
    """Land-cover class codes and light at ground points [m] (module docstring, ``terrain``)."""
    urban = value_noise(x, y, seed, 400.0, 5, footprint)
    green = value_noise(x, y, seed + 1, 250.0, 5, footprint)
    building_edge, road_edge = np.quantile(urban, [1 - LAND_COVER_SHARES["buildings"], 0.5])
    forest_edge = np.quantile(green, 1 - LAND_COVER_SHARES["forest"])
    kind = np.full(x.shape, CLASSES.index("grass"), np.uint8)
    kind[green > forest_edge] = CLASSES.index("forest")
    kind[urban > building_edge] = CLASSES.index("buildings")
    kind[np.abs(urban - road_edge) < 0.02] = CLASSES.index("road")  # thin bands along a level line: roads
    values = np.zeros(x.shape)
    for name in LAND_COVER_SHARES:
        values[kind == CLASSES.index(name)] = _surface_light(name, context)
    if context["band"] == "eo":
        values *= 1.0 + 0.25 * value_noise(x, y, seed + 2, 8.0, 4, footprint)  # texture: +-25 % of the reflectance
    return kind, values


def _terrain(rays: np.ndarray, clutter, context: dict, seed: int) -> tuple:
    """Land cover below the horizon: (alpha, light, class codes, distance along each ground pixel's ray [m]); flat
    ground, or with ``relief_m`` the seeded fractal DEM (:func:`_relief_hits`). The noise is evaluated on the
    ground's pixels only."""
    z = rays[..., 2]
    codes = np.full(z.shape, 255, np.uint8)
    light, along_ray = np.zeros(z.shape), np.zeros(z.shape)
    if clutter.relief_m > 0:
        ground, x, y, distance = _relief_hits(rays, clutter, context["ifov_rad"], seed)
        grazing = np.maximum(np.abs(z[ground]), 0.02)
        along_ray[ground] = distance / np.sqrt(np.maximum(1.0 - z[ground] ** 2, 1e-12))  # horizontal -> slant
    else:
        ground = z < -1e-6
        distance = clutter.camera_height_m / np.maximum(-z[ground], 1e-9)
        x, y, grazing = distance * rays[..., 0][ground], distance * rays[..., 1][ground], -z[ground]
        along_ray[ground] = distance
    if not ground.any():
        return ground.astype(float), light, codes, along_ray
    footprint = np.maximum(distance * context["ifov_rad"] / np.maximum(grazing, 1e-3), 1e-3)
    codes[ground], light[ground] = _land_cover(x, y, footprint, context, seed)
    return ground.astype(float), light, codes, along_ray


#: Horizontal scale of the fractal DEM's largest features [m] and its samples along each column's azimuth.
RELIEF_CELL_M, RELIEF_SAMPLES = 2000.0, 384
#: Nearest and farthest ground distance a column's profile samples [m].
RELIEF_NEAR_M, RELIEF_FAR_M = 2.0, 20000.0


def _relief_hits(rays: np.ndarray, clutter, ifov_rad: float, seed: int) -> tuple:
    """Where each pixel's ray meets a seeded fractal DEM (heights ``relief_m`` x value noise, the camera
    ``camera_height_m`` above the ground below it): a height-profile ("voxel space") cast per column.

    Each column's azimuth (its middle row's, as :func:`_along_azimuth`) gives a profile of the ground's
    elevation angle atan((H(d) - H(0) - h) / d) at ``RELIEF_SAMPLES`` distances d, geometric from 2 m to 20 km;
    its running maximum is what the camera sees up to d, so a pixel at elevation e sees the ground at the
    nearest d whose running maximum reaches e (sky above the profile's maximum), interpolated linearly in
    the angle from the sample before. Returns the mask of ground
    pixels, their ground points x, y [m] and distances [m].
    """
    n_v, n_h = rays.shape[:2]
    middle = rays[n_v // 2]
    azimuth = np.unwrap(np.arctan2(middle[:, 1], middle[:, 0]))
    distance = np.geomspace(RELIEF_NEAR_M, RELIEF_FAR_M, RELIEF_SAMPLES)
    px, py = distance[None, :] * np.cos(azimuth)[:, None], distance[None, :] * np.sin(azimuth)[:, None]
    footprint = np.broadcast_to(distance * ifov_rad, px.shape)
    height = value_noise(px, py, seed + 7, RELIEF_CELL_M, 5, footprint)
    origin = float(value_noise(np.zeros(1), np.zeros(1), seed + 7, RELIEF_CELL_M, 5)[0])
    angle = np.arctan2(clutter.relief_m * (height - origin) - clutter.camera_height_m, distance[None, :])
    seen = np.maximum.accumulate(angle, axis=1)  # (n_h, samples), non-decreasing along each column's profile
    elevation = np.arcsin(np.clip(rays[..., 2], -1.0, 1.0))
    index = np.empty((n_v, n_h), np.int64)
    for column in range(n_h):
        index[:, column] = np.searchsorted(seen[column], elevation[:, column])
    ground = index < RELIEF_SAMPLES
    columns = np.broadcast_to(np.arange(n_h), (n_v, n_h))[ground]
    after = index[ground]
    before = np.maximum(after - 1, 0)
    # between the last sample below the pixel's elevation and the first reaching it, linear in the angle
    low, high = angle[columns, before], angle[columns, after]
    share = np.clip((elevation[ground] - low) / np.where(high > low, high - low, 1.0), 0.0, 1.0)
    hit = distance[before] + share * (distance[after] - distance[before])
    return ground, hit * np.cos(azimuth[columns]), hit * np.sin(azimuth[columns]), hit


def _along_azimuth(rays: np.ndarray, distance_m: float, seed: int, cell_m: float, octaves: int) -> np.ndarray:
    """Value noise on the ground circle of ``distance_m`` at each pixel's azimuth, evaluated once per column of
    the middle row and interpolated in azimuth (the azimuth varies along a row, next to nothing down a column
    of a view near level)."""
    azimuth = np.arctan2(rays[..., 1], rays[..., 0])
    row = np.unwrap(azimuth[azimuth.shape[0] // 2])
    order = np.argsort(row)
    samples = value_noise(distance_m * np.cos(row), distance_m * np.sin(row), seed, cell_m, octaves)
    centre = row[row.size // 2]
    wrapped = (azimuth - centre + np.pi) % (2 * np.pi) - np.pi + centre  # onto the middle row's branch
    return np.interp(wrapped, row[order], samples[order])


def _skyline(rays: np.ndarray, clutter, context: dict, seed: int) -> list:
    """Hills, then trees and buildings at the skyline: [(alpha, light, code, distance)] farthest first."""
    elevation = np.arcsin(np.clip(rays[..., 2], -1.0, 1.0))
    h = clutter.camera_height_m

    def standing(height, distance):  # between the ground at that distance and the object's top
        return (elevation < np.arctan2(height - h, distance)) & (elevation > math.atan2(-h, distance)) & (height > 0)

    hills = 60.0 + 80.0 * _along_azimuth(rays, HILLS_DISTANCE_M, seed + 3, 1500.0, 4)
    forest, buildings_light = _surface_light("forest", context), _surface_light("buildings", context)
    out = [(standing(hills, HILLS_DISTANCE_M), forest, CLASSES.index("skyline_trees"), HILLS_DISTANCE_M)]
    crowns = 14.0 + 6.0 * _along_azimuth(rays, SKYLINE_DISTANCE_M, seed + 4, 12.0, 3)
    kind = _along_azimuth(rays, SKYLINE_DISTANCE_M, seed + 5, 150.0, 2)
    storeys = _along_azimuth(rays, SKYLINE_DISTANCE_M, seed + 6, 20.0, 1) > 0
    buildings = np.where(kind > 0.25, 10.0 + 20.0 * storeys, 0.0)
    trees = np.where((kind < 0.1) & (kind > -0.6), crowns, 0.0)
    out.append((standing(trees, SKYLINE_DISTANCE_M), forest, CLASSES.index("skyline_trees"), SKYLINE_DISTANCE_M))
    out.append(
        (
            standing(buildings, SKYLINE_DISTANCE_M),
            buildings_light,
            CLASSES.index("skyline_buildings"),
            SKYLINE_DISTANCE_M,
        )
    )
    return out


def _power_line(rays: np.ndarray, forward, distance_m: float, phase_m: float, context: dict) -> tuple:
    """One conductor across the view at ``distance_m`` ahead along ``forward`` (horizontal unit): (coverage, light,
    the conductor's distance along each pixel's column [m])."""
    lateral = np.array([-forward[1], forward[0]])
    depth = rays[..., 0] * forward[0] + rays[..., 1] * forward[1]
    t = distance_m / np.maximum(depth, 1e-6)
    along = t * (rays[..., 0] * lateral[0] + rays[..., 1] * lateral[1])
    span = (along + phase_m) % TOWER_SPACING_M - TOWER_SPACING_M / 2.0
    sag = CATENARY_M * (math.cosh(TOWER_SPACING_M / 2.0 / CATENARY_M) - np.cosh(span / CATENARY_M))
    wire_z = TOWER_HEIGHT_M - context["camera_height_m"] - sag
    # the wire's elevation along this column and the pixel's; its angular width d / r over the IFOV
    ground = t * np.hypot(rays[..., 0], rays[..., 1])
    r = np.hypot(ground, wire_z)
    wire_elevation = np.arctan2(wire_z, ground)
    elevation = np.arcsin(np.clip(rays[..., 2], -1.0, 1.0))
    half_px, half_wire = context["ifov_rad"] / 2.0, CONDUCTOR_DIAMETER_M / r / 2.0
    overlap = np.minimum(elevation + half_px, wire_elevation + half_wire) - np.maximum(
        elevation - half_px, wire_elevation - half_wire
    )
    coverage = np.where(depth > 0, np.clip(overlap / context["ifov_rad"], 0.0, 1.0), 0.0)
    return coverage, _surface_light("power_line", context), r


def _soft_clouds(rays: np.ndarray, cover: float, context: dict, seed: int) -> tuple:
    """Soft clouds over the sky's pixels (module docstring): (alpha, light)."""
    from csuas.render.imaging.background import cloud_field

    n_v, n_h = rays.shape[:2]
    field = cloud_field(n_v, n_h, seed)
    edge, width = np.quantile(field, 1.0 - cover), 2.0 * float(np.std(field))
    ramp = np.clip((field - edge) / width + 0.5, 0.0, 1.0)
    opacity = ramp * ramp * (3.0 - 2.0 * ramp) * (rays[..., 2] > 0)  # smoothstep
    if context["band"] == "eo":
        return opacity, opacity * context["illuminance_lx"] / math.pi * (0.7 + 0.3 * opacity)

    cloud = float(band_radiance(context["ambient_k"] - CLOUD_BELOW_AMBIENT_K, context["band"]))
    return opacity, opacity * cloud


def clutter_layers(rays: np.ndarray, clutter, context: dict, seed: int) -> tuple:
    """Every declared clutter layer of a frame, farthest first, and the frame's background class map.

    Parameters
    ----------
    rays : ndarray (n_v, n_h, 3)
        The frame's rays (:func:`frame_rays`).
    clutter : ClutterSchema
        The spec's ``[clutter]`` table.
    context : dict
        ``band`` ("eo", "lwir" or "mwir"), ``illuminance_lx``, ``ambient_k``, ``ifov_rad``, ``camera_height_m``;
        optionally ``path``: (distance [m], upward component of the ray) -> (transmittance, path light per unit
        opacity), the frame's path at each layer's own distance (module docstring).
    seed : int
        The frame's seed (a sequence: the video's, so that the ground stays the same).

    Returns
    -------
    (list, ndarray)
        [(alpha, light, distance_m)] with alpha and light (alpha L) frames, and the uint8 class codes
        (:data:`CLASSES`: sky or terrain by the horizon where no layer covers a pixel more than half).
    """
    context = {**context, "camera_height_m": clutter.camera_height_m}
    codes = np.where(rays[..., 2] > 0, CLASSES.index("sky"), CLASSES.index("terrain")).astype(np.uint8)
    layers = []
    if clutter.clouds > 0:
        alpha, light = _soft_clouds(rays, clutter.clouds, context, seed)
        layers.append((alpha, light, math.inf))
        codes[alpha > 0.5] = CLASSES.index("cloud")
    path = context.get("path")
    if clutter.terrain:
        alpha, light, terrain_codes, along_ray = _terrain(rays, clutter, context, seed)
        layers.append((alpha, _through_path(alpha, alpha * light, along_ray, rays, path), 1e4))
        codes = np.where(alpha > 0.5, terrain_codes, codes).astype(np.uint8)
    if clutter.skyline:
        horizontal = np.sqrt(np.maximum(1.0 - rays[..., 2] ** 2, 1e-12))
        for covered, light, code, distance in _skyline(rays, clutter, context, seed):
            alpha = covered.astype(float)
            layers.append((alpha, _through_path(alpha, covered * light, distance / horizontal, rays, path), distance))
            codes[covered] = code
    if clutter.power_lines:
        rng = np.random.default_rng([int(seed), 13])
        centre = rays[rays.shape[0] // 2, rays.shape[1] // 2]
        forward = np.array([centre[0], centre[1]]) / max(math.hypot(centre[0], centre[1]), 1e-9)
        for distance in sorted(rng.uniform(50.0, 300.0, clutter.power_lines), reverse=True):
            coverage, light, wire_m = _power_line(rays, forward, float(distance), float(rng.uniform(0, 300)), context)
            layers.append((coverage, _through_path(coverage, coverage * light, wire_m, rays, path), float(distance)))
            codes[coverage > 0.5] = CLASSES.index("power_line")
    return layers, codes


def _through_path(alpha: np.ndarray, light: np.ndarray, range_m, rays: np.ndarray, path) -> np.ndarray:
    """A layer's light a L after the path at its own distance: tau a L + a L_path (module docstring); as it is
    without a path (None)."""
    if path is None:
        return light
    tau, added = path(range_m, rays[..., 2])
    return tau * light + alpha * added


#: Angular radius of the sun [rad] (0.2666 deg, its mean apparent diameter of 0.533 deg).
SUN_RADIUS_RAD = math.radians(0.2666)
#: Ghost images of the sun: their place along the line from the sun's image through the frame's centre (the
#: sun at 1, the centre at 0, mirrored beyond it at -1) and their radius [px of a 1920 px frame] (stated model).
GHOSTS = ((-0.4, 60.0), (-0.8, 120.0), (-1.2, 180.0), (0.5, 40.0))
#: Reflectance of one lens surface with a multi-layer coating; a ghost is light reflected twice, rho^2 of the
#: sun's flux (Smith, Modern Optical Engineering, 4th ed., 2008: 0.2-1 % a coated surface; 0.3 % assumed).
SURFACE_REFLECTANCE = 0.003


def sun_pixel(sensor_size: tuple, ifov_rad: float, sun_offset_deg) -> tuple:
    """Film position (x, y) [px] of the sun ``sun_offset_deg`` (right, up) [deg] from the frame's centre (pinhole)."""
    n_h, n_v = sensor_size
    x_deg, y_deg = sun_offset_deg
    return (n_h / 2.0 + math.tan(math.radians(x_deg)) / ifov_rad, n_v / 2.0 - math.tan(math.radians(y_deg)) / ifov_rad)


def sun_direction(sensor_size: tuple, ifov_rad: float, item: dict, sun_offset_deg) -> tuple:
    """Azimuth and elevation [deg] of the sun, the frame's ray at :func:`sun_pixel`, in the drone's body frame."""
    from csuas.render.imaging.background import view_rays

    n_h, n_v = sensor_size
    px, py = sun_pixel(sensor_size, ifov_rad, sun_offset_deg)
    ox, oy = item["target_offset_px"]
    # a one-pixel frame whose pixel is the sun's place in the full frame (view_rays's centre convention)
    offset = (n_h // 2 + ox - (px - 0.5), n_v // 2 + oy - (py - 0.5))
    ray = view_rays(1, 1, ifov_rad, item["azimuth_deg"], item["elevation_deg"], offset)[0, 0]
    return math.degrees(math.atan2(ray[1], ray[0])), math.degrees(math.asin(float(np.clip(ray[2], -1.0, 1.0))))


def ghost_centres(sun_px: tuple, sensor_size: tuple) -> list:
    """Centres [px] of the ghosts: c + g (s - c) for each g of :data:`GHOSTS` (c the frame's centre, s the sun)."""
    cx, cy = sensor_size[0] / 2.0, sensor_size[1] / 2.0
    return [(cx + g * (sun_px[0] - cx), cy + g * (sun_px[1] - cy)) for g, _ in GHOSTS]


def _disk(shape: tuple, centre: tuple, radius_px: float) -> np.ndarray:
    """Coverage of a disk (anti-aliased over one pixel at its edge)."""
    y, x = np.indices(shape, dtype=float)
    distance = np.hypot(x + 0.5 - centre[0], y + 0.5 - centre[1])
    return np.clip(radius_px + 0.5 - distance, 0.0, 1.0)


def sun_and_flare(shape: tuple, ifov_rad: float, sun_px: tuple, sun_irradiance_lx: float, flare: bool) -> list:
    """The sun's disk (luminance E_sun / Omega_sun, beyond everything) and, with ``flare``, its ghosts (in the
    lens, over everything): [(alpha, light, distance)].

    A ghost spreads rho^2 of the sun's flux over its disk of solid angle Omega_g = pi (r IFOV)^2, so its added
    luminance is rho^2 E_sun / Omega_g (alpha 0: it adds light, hides nothing).
    """
    n_v, n_h = shape
    sun_luminance = sun_irradiance_lx / (math.pi * SUN_RADIUS_RAD**2)
    disk = _disk(shape, sun_px, SUN_RADIUS_RAD / ifov_rad)
    out = [(disk, disk * sun_luminance, math.inf)]
    if flare:
        scale = n_h / 1920.0
        for (_, radius), centre in zip(GHOSTS, ghost_centres(sun_px, (n_h, n_v))):
            r = radius * scale
            ghost = _disk(shape, centre, r)
            luminance = SURFACE_REFLECTANCE**2 * sun_irradiance_lx / (math.pi * (r * ifov_rad) ** 2)
            out.append((np.zeros(shape), ghost * luminance, 0.0))  # in the lens: over everything
    return out
