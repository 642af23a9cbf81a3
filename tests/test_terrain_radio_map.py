"""Sionna RT radio maps over terrain (render/links/terrain_map.py) against closed forms, the two-ray model and
the viewshed.

References: exact geometry of the meshes (vertex positions, areas, a closed-form curvature drop
d^2 / (2 k R_E)); Student's t for the replicas' bound (a Monte Carlo of normal replicas); the two-ray
model with Fresnel reflection averaged over each cell (csuas.render.links.two_ray, Gauss-Legendre);
the R2 viewshed (csuas.core.terrain.viewshed). Tolerances: the bound's stated coverage (95 %), its
binomial spread in the Monte Carlo, and for dark seen cells the Poisson bound on cells a rotated
lattice leaves without a ray (validation/links/terrain_map.py).
"""

import numpy as np
import pytest

from csuas.base.errors import InputErrors, ParameterError
from csuas.core.terrain import bearing_deg, off_boresight_deg
from csuas.render.links import terrain_map as tm

EARTH_RADIUS_M = 6_371_000.0


def _hills(n=41, cell=50.0, seed=4):
    """Six seeded Gaussian hills, 20-80 m high and 100-300 m wide."""
    rng = np.random.default_rng(seed)
    north, east = np.indices((n, n)) * cell
    dem = np.zeros((n, n))
    for cx, cy, h, w in zip(*rng.uniform([[0], [0], [20], [100]], [[n * cell], [n * cell], [80], [300]], (4, 6))):
        dem += h * np.exp(-((east - cx) ** 2 + (north - cy) ** 2) / (2 * w * w))
    return dem


def test_terrain_mesh_frame_faces_and_curvature():
    dem = np.arange(12.0).reshape(3, 4)
    vertices, faces = tm.terrain_mesh(dem, 10.0, k_factor=None)
    assert vertices.shape == (12, 3) and faces.shape == (2 * 2 * 3, 3)
    # row 0, col 3: east of the centre (col 1.5) by 15 m, north of it (row 1) by 10 m
    np.testing.assert_allclose(vertices[3], [15.0, 10.0, 3.0])
    np.testing.assert_allclose(vertices[8], [-15.0, -10.0, 8.0])
    flat, _ = tm.terrain_mesh(np.zeros((3, 4)), 10.0, k_factor=None)
    a, b, c = (flat[faces[:, i].astype(int)] for i in range(3))
    normal_z = np.cross(b - a, c - a)[:, 2]
    assert np.all(normal_z > 0)  # counter-clockwise seen from above
    np.testing.assert_allclose(0.5 * normal_z.sum(), 2 * 3 * 100.0)  # centre-to-centre span
    far, _ = tm.terrain_mesh(np.zeros((3, 201)), 100.0, k_factor=4 / 3)
    d = 10_000.0  # column 200 is 100 cells east of the centre
    assert far[200, 2] == pytest.approx(-(d**2) / (2 * 4 / 3 * EARTH_RADIUS_M), rel=1e-3)  # 5.9 m below


@pytest.mark.parametrize("step", [1, 2, 3])
def test_measurement_blocks_cover_the_terrain_span(step):
    rows, cols = np.indices((5, 7))
    dem = 2.0 * rows + 3.0 * cols  # planar: bilinear interpolation is exact
    vertices, faces = tm.measurement_mesh(dem, 10.0, 50.0, step, k_factor=None)
    r_edges, c_edges = tm.block_edges(5, step), tm.block_edges(7, step)
    assert r_edges[0] == 0 and r_edges[-1] == 4 and c_edges[-1] == 6
    n_blocks = (len(r_edges) - 1) * (len(c_edges) - 1)
    assert faces.shape == (2 * n_blocks, 3)
    corner_r, corner_c = np.meshgrid(r_edges, c_edges, indexing="ij")
    np.testing.assert_allclose(vertices[:, 2], 50.0 + 2.0 * corner_r.ravel() + 3.0 * corner_c.ravel())
    horizontal = vertices.copy()
    horizontal[:, 2] = 0.0
    np.testing.assert_allclose(tm.triangle_areas_m2(horizontal, faces).sum(), 4 * 6 * 100.0)
    grid = tm.blocks_to_grid(np.arange(n_blocks).reshape(len(r_edges) - 1, -1), (5, 7), step)
    assert grid.shape == (5, 7) and grid[0, 0] == 0 and grid[4, 6] == n_blocks - 1
    assert np.all(grid[:step, :step] == 0)


def test_random_rotations_are_haar_and_proper():
    angles = tm.random_rotation_angles(20_000, np.random.default_rng(3))
    matrices = np.stack([tm.rotation_matrix(a) for a in angles[:200]])
    np.testing.assert_allclose(
        matrices @ matrices.transpose(0, 2, 1), np.broadcast_to(np.eye(3), (200, 3, 3)), atol=1e-12
    )
    np.testing.assert_allclose(np.linalg.det(matrices), 1.0)
    # Haar: a fixed vector lands uniformly on the sphere (every moment below vanishes, sd 1/sqrt(3 n))
    z = np.array([tm.rotation_matrix(a)[:, 2] for a in angles])
    assert np.all(np.abs(z.mean(0)) < 4 / np.sqrt(3 * len(z)))
    assert abs(np.mean(z[:, 2] ** 2) - 1 / 3) < 4 * np.sqrt(4 / 45 / len(z))


def test_bound_covers_normal_replicas_at_its_level():
    rng = np.random.default_rng(11)
    cells = 40_000
    replicas = rng.normal(1.0, 0.1, (tm.REPLICAS, cells))
    mean, error = tm.bound_db(replicas, tm.BOUND_LEVEL)
    coverage = np.mean(np.abs(10 * np.log10(mean)) <= error)
    assert abs(coverage - tm.BOUND_LEVEL) < 3 * np.sqrt(0.01 * 0.99 / cells) + 0.002  # Student model, dB side
    mean, error = tm.bound_db(np.array([[0.0, 1.0, 2.0], [0.0, 1.0, 0.0]]))
    assert np.isinf(error[0]) and error[1] == 0.0 and np.isinf(error[2])  # no power; equal replicas; t SE > mean


def test_bad_input_is_reported_at_once():
    with pytest.raises(ParameterError, match="dem_m"):
        tm.check_dem(np.array([[1.0, np.nan], [0.0, 0.0]]), 10.0)
    with pytest.raises(InputErrors) as caught:
        tm.check_dem(np.zeros(3), -1.0)
    assert [e.name for e in caught.value.errors] == ["dem_m", "cell_m"]


@pytest.mark.slow
@pytest.mark.parametrize(
    "kwargs, names",
    [
        ({"frequency_ghz": 0.05}, ["frequency_ghz"]),
        ({"frequency_ghz": 24.0}, ["frequency_ghz"]),  # medium dry ground: 1-10 GHz
        ({"ground": "lava"}, ["ground"]),
        ({"tx_row": 40.5, "mast_m": 0.0}, ["tx position", "mast_m"]),
        ({"altitude_m": np.nan, "k_factor": -1.0}, ["altitude_m", "k_factor"]),
        ({"samples": 0, "replicas": 1, "step": 0}, ["step", "replicas", "samples"]),
        ({"max_depth": 11, "polarization": "X", "los": 1}, ["polarization", "los", "max_depth"]),
        ({"sector_deg": (90.0, 0.0)}, ["sector_deg"]),
        ({"sector_deg": 90.0, "altitude_m": -1.0}, ["altitude_m", "sector_deg"]),
    ],
)
def test_radio_map_bad_input(kwargs, names):
    args = {
        "dem_m": np.zeros((41, 41)),
        "cell_m": 10.0,
        "tx_row": 20.0,
        "tx_col": 20.0,
        "mast_m": 10.0,
        "altitude_m": 50.0,
        "frequency_ghz": 2.4,
        "sector_deg": None,
        **kwargs,
    }
    with pytest.raises((ParameterError, InputErrors)) as caught:
        site = {key: args.pop(key) for key in tm.RadioMapSite.__dataclass_fields__}
        tm.terrain_radio_map(tm.RadioMapSite(**site), tm.RadioMapOptions(**args))
    errors = getattr(caught.value, "errors", [caught.value])
    assert [e.name for e in errors] == names


def test_the_two_ray_oracle_refuses_terrain_and_ignores_a_constant_height():
    """The flat-ground oracle: a DEM with relief is refused (naming dem_m); a DEM at one height everywhere gives
    the map of a DEM at zero, since the mast and the flight level are heights above the ground."""
    from csuas.validation.links.terrain_map import block_average_two_ray

    site = tm.RadioMapSite(np.zeros((3, 9)), 25.0, 1.0, 0.0, 10.0, 60.0, 1.0)
    hill = tm.RadioMapSite(np.eye(3, 9), 25.0, 1.0, 0.0, 10.0, 60.0, 1.0)
    with pytest.raises(ParameterError, match="dem_m"):
        block_average_two_ray(hill, 15.0 - 0.3j)
    raised = tm.RadioMapSite(np.full((3, 9), 120.0), 25.0, 1.0, 0.0, 10.0, 60.0, 1.0)
    assert np.array_equal(block_average_two_ray(raised, 15.0 - 0.3j), block_average_two_ray(site, 15.0 - 0.3j))


@pytest.mark.slow
def test_rotation_convention_is_sionnas():
    from csuas.render.links.sionna_backend import load_sionna_rt

    load_sionna_rt()
    import mitsuba as mi
    from sionna.rt.utils import rotation_matrix

    angles = (0.3, -1.1, 2.5)
    expected = np.array(rotation_matrix(mi.Point3f(*angles)), dtype=float).reshape(3, 3)
    np.testing.assert_allclose(tm.rotation_matrix(angles), expected, atol=1e-6)


@pytest.mark.slow
@pytest.mark.parametrize("polarization, step", [("H", 1), ("V", 1), ("H", 3)])
def test_flat_ground_is_the_two_ray_power_sum(polarization, step):
    from csuas.validation.links.terrain_map import flat_ground_comparison

    out = flat_ground_comparison(2**18, scene={"polarization": polarization, "step": step})
    result = out["result"]
    assert result.path_gain_db.shape == (21, 61) and not np.isnan(result.path_gain_db).any()
    assert out["reliable_fraction"] > 0.9
    assert out["coverage"] >= tm.STATED_COVERAGE
    assert out["median_abs_error_db"] <= out["median_bound_db"]
    assert result.time_s > 0 and result.budget.samples == 2**18 and result.replicas == tm.REPLICAS
    if polarization == "H" and step == 1:
        # Sionna adds the rays' powers: the coherent lobes and nulls are not in the map
        assert out["coherent_p95_abs_db"] > 3.0


@pytest.mark.slow
def test_a_seed_gives_the_map_and_unreached_cells_are_minus_infinity():
    dem = np.zeros((21, 31))
    site = tm.RadioMapSite(dem, 10.0, 10.0, 0.0, 10.0, 60.0, 2.4)
    a = tm.terrain_radio_map(site, tm.RadioMapOptions(samples=2**14, seed=5, k_factor=None))
    b = tm.terrain_radio_map(site, tm.RadioMapOptions(samples=2**14, seed=5, k_factor=None))
    c = tm.terrain_radio_map(site, tm.RadioMapOptions(samples=2**14, seed=6, k_factor=None))
    # the same rotations; Sionna's atomic float32 sums add the rays in a varying order (1e-7 dB measured)
    np.testing.assert_allclose(a.path_gain_db, b.path_gain_db, rtol=0, atol=1e-5)
    both = a.reached & c.reached
    assert np.max(np.abs(a.path_gain_db[both] - c.path_gain_db[both])) > 0.01  # other rotations
    np.testing.assert_allclose(a.extra["tx_position_m"], [-150.0, 0.0, 10.0])
    # 2^14 rays leave far cells without any: -inf dB and an infinite bound there, never NaN
    assert (~a.reached).any() and a.reached.any()
    assert np.array_equal(a.path_gain_db == -np.inf, ~a.reached) and np.all(a.error_db[~a.reached] == np.inf)
    assert np.all(a.reached[a.reliable]) and not np.isnan(a.path_gain_db).any() and not np.isnan(a.error_db).any()


@pytest.mark.slow
def test_ridge_shadow_is_the_viewshed():
    from csuas.validation.links.terrain_map import dark_tolerance, ridge_line_of_sight

    out = ridge_line_of_sight(2**18)
    result = out["result"]
    assert out["hidden_lit"] == 0  # exact: no straight ray crosses the ridge
    assert out["visible_dark"] <= dark_tolerance(out["expected_dark"])
    assert out["agreement"] >= 0.999 and 0.3 < out["visible"].mean() < 0.9
    hidden = ~out["visible"] & ~out["edge"]
    assert np.all(result.path_gain_db[hidden] == -np.inf) and np.all(result.error_db[hidden] == np.inf)
    assert not np.isnan(result.path_gain_db).any() and not np.isnan(result.error_db).any()
    assert not result.reached[hidden].any() and not result.reliable[hidden].any()


@pytest.mark.slow
def test_hills_direct_rays_follow_the_viewshed_and_reflections_only_add():
    from csuas.validation.links.terrain_map import dark_tolerance, line_of_sight_agreement

    dem = _hills()
    site = tm.RadioMapSite(dem, 50.0, 20.0, 20.0, 10.0, 40.0, 2.4)
    out = line_of_sight_agreement(site, 2**18)
    assert out["hidden_lit"] == 0
    assert out["visible_dark"] <= dark_tolerance(out["expected_dark"])
    assert 0.5 < out["visible"].mean() < 0.9
    full = tm.terrain_radio_map(site, tm.RadioMapOptions(samples=2**18, max_depth=2))
    los = out["result"].path_gain_db
    # the same rotations shoot the same direct rays: the reflections add power, never remove it
    assert np.all(full.path_gain_db >= los - 1e-4)
    assert np.all(full.reached[out["result"].reached])


@pytest.mark.slow
def test_budget_meets_the_requested_bound():
    from csuas.core.dielectric import complex_permittivity
    from csuas.validation.links.terrain_map import FLAT, block_average_two_ray

    p = FLAT
    dem = np.zeros(p["shape"])
    site = tm.RadioMapSite(dem, p["cell_m"], p["tx_row"], p["tx_col"], p["mast_m"], p["altitude_m"], p["frequency_ghz"])
    options = tm.RadioMapOptions(k_factor=None, polarization="H", max_depth=1)
    budget, result = tm.radio_map_budget(1.0, site, options, start_samples=2**13)
    steps = result.extra["budget_steps"]
    assert result.extra["budget_met"] and budget.samples == steps[-1]["samples"] == result.budget.samples
    assert [s["samples"] for s in steps] == [2**13 * 2**i for i in range(len(steps))] and len(steps) > 1
    assert steps[-1]["fraction_met"] >= 0.95 > steps[0]["fraction_met"]
    eta = complex_permittivity(result.extra["relative_permittivity"], result.extra["conductivity_s_m"], 1.0)
    oracle = block_average_two_ray(site, eta, polarization="H")
    error = np.abs(result.path_gain_db - 10 * np.log10(oracle))
    assert np.mean(error <= 1.0) >= tm.STATED_COVERAGE  # the promise holds against the oracle
    with pytest.raises(ParameterError, match="target_db"):
        tm.radio_map_budget(0.0, site)


@pytest.mark.slow
def test_a_ground_given_by_its_constants_reflects_as_the_itu_ground_of_those_constants():
    """medium_dry_ground at 2.4 GHz (ITU-R P.2040-3 Table 3) and the pair of its constants give the same map;
    a pair out of range is refused."""
    from csuas.render.links.scene import ground_properties

    dem = np.zeros((21, 31))
    site = tm.RadioMapSite(dem, 10.0, 10.0, 0.0, 10.0, 60.0, 2.4)
    constants = ground_properties("medium_dry_ground", 2.4)
    named = tm.terrain_radio_map(site, tm.RadioMapOptions(samples=2**14, seed=5, k_factor=None))
    given = tm.terrain_radio_map(site, tm.RadioMapOptions(samples=2**14, seed=5, k_factor=None, ground=constants))
    assert np.array_equal(named.reached, given.reached)
    np.testing.assert_allclose(named.path_gain_db[named.reached], given.path_gain_db[given.reached], atol=1e-5)
    with pytest.raises(ParameterError, match="ground"):
        ground_properties((0.5, 0.0), 2.4)


def test_sector_cells_and_blocks_follow_the_bearing():
    inside = tm.sector_cells((5, 5), 2.0, 2.0, (90.0, 100.0))  # east, +-50 degrees
    # the own cell; one column east: 3 cells (45 degrees off at most); two columns east: all 5 (45 at most)
    assert inside.sum() == 1 + 3 + 5 and inside[2, 2] and inside[:, 4].all() and inside[1:4, 3].all()
    assert not inside[0, 3] and not inside[4, 3]  # 63.4 degrees off the boresight
    assert tm.sector_cells((3, 4), 1.0, 1.0).all()
    blocks = tm.cells_to_blocks(np.eye(5, dtype=bool), 2)
    np.testing.assert_array_equal(blocks, [[True, False, False], [False, True, False], [False, False, True]])
    np.testing.assert_array_equal(tm.sensor_blocks((5, 5), 2, 2.0, 1.5), [[0, 0, 0], [1, 1, 0], [0, 0, 0]])


def test_the_ray_band_spans_the_sector_and_its_blocks_footprints():
    """East +-50 degrees from the centre of 5 x 5 cells: the cells one column east, north and south of the
    row reach 71.57 degrees off the boresight with their far corners (atan(1.5 / 0.5)); all round: no fold."""
    inside = tm.sector_cells((5, 5), 2.0, 2.0, (90.0, 100.0))
    first, share = tm.ray_band((90.0, 100.0), (5, 5), 1, 2.0, 2.0, inside)
    edge = np.degrees(np.arctan(1.5 / 0.5))
    assert np.degrees(first) == pytest.approx(-edge) and share == pytest.approx(2 * edge / 360.0)
    far = np.zeros((41, 41), dtype=bool)
    far[20, 40] = True  # one cell 20 cells east: within the sector's +-50 degrees, no widening
    first, share = tm.ray_band((90.0, 100.0), (41, 41), 1, 20.0, 20.0, far)
    assert np.degrees(first) == pytest.approx(-50.0) and share == pytest.approx(100.0 / 360.0)
    assert tm.ray_band(None, (5, 5), 1, 2.0, 2.0, inside) == (-np.pi, 1.0)
    # north +-175 degrees: the cells due south are outside it, but a measured one there straddles the seam
    around = tm.sector_cells((5, 5), 2.0, 2.0, (0.0, 350.0))
    first, share = tm.ray_band((0.0, 350.0), (5, 5), 1, 2.0, 2.0, around)
    assert not around[3, 2] and share == pytest.approx(350.0 / 360.0)
    assert tm.ray_band((0.0, 350.0), (5, 5), 1, 2.0, 2.0, np.ones((5, 5), bool)) == (-np.pi, 1.0)


def test_folded_directions_are_uniform_over_the_band():
    """Uniform directions on the sphere land uniformly on the band: bearings in it, z kept, unit length, and
    the bearing's histogram flat (chi-square, 9 degrees of freedom, 0.1 % level)."""
    from drjit.llvm import Float64
    from scipy.stats import chi2

    rng = np.random.default_rng(8)
    d = rng.normal(size=(3, 40_000))
    d /= np.linalg.norm(d, axis=0)
    folded = tm.fold_directions(*(Float64(v) for v in d), (float(np.radians(90.0 - 300.0 - 30.0)), 60.0 / 360.0))
    x, y, z = (np.asarray(v) for v in folded)
    np.testing.assert_allclose(x * x + y * y + z * z, 1.0, atol=1e-12)
    np.testing.assert_array_equal(z, d[2])
    off = off_boresight_deg(bearing_deg(-y, x), 300.0)  # a direction (x, y) has grid offset (-y rows, x cols)
    assert np.all(np.abs(off) <= 30.0 + 1e-9)
    counts, _ = np.histogram(off, bins=10, range=(-30.0, 30.0))
    expected = len(off) / 10
    assert np.sum((counts - expected) ** 2 / expected) < chi2.ppf(0.999, 9)


def _counted(monkeypatch, owner, name: str, counts: dict, which=lambda *args: True):
    """Wrap ``owner.name`` so that each call whose arguments pass ``which`` adds one to ``counts[name]``."""
    original = getattr(owner, name)

    def counting(*args, **kwargs):
        counts[name] += bool(which(*args))
        return original(*args, **kwargs)

    monkeypatch.setattr(owner, name, counting)


@pytest.mark.slow
def test_a_map_builds_its_scene_once_and_its_replicas_none(monkeypatch):
    """Every Mitsuba scene (and its acceleration structure) comes from ``mi.load_dict`` of a ``scene`` dict,
    and moving a mesh in one from ``SceneParameters.update``: counted over maps of a new terrain, a new
    flight level and a repeated one, each of 8 replicas (Sionna also loads a sampler per solve: not a scene)."""
    from csuas.render.links.sionna_backend import load_sionna_rt

    load_sionna_rt()
    import mitsuba as mi

    counts = {"load_dict": 0, "update": 0}
    _counted(monkeypatch, mi, "load_dict", counts, lambda spec, *rest: spec.get("type") == "scene")
    _counted(monkeypatch, mi.SceneParameters, "update", counts)
    dem = _hills(21, seed=9)
    options = tm.RadioMapOptions(samples=2**12, replicas=8)
    tm.terrain_radio_map(tm.RadioMapSite(dem, 50.0, 10.0, 10.0, 10.0, 40.0, 2.4), options)
    first = dict(counts)
    # Sionna's empty scene, the terrain added, the flight level; Sionna's own updates while it sets up (2)
    assert first["load_dict"] == 3 and first["update"] < options.replicas
    higher = tm.RadioMapSite(dem, 50.0, 10.0, 10.0, 10.0, 70.0, 2.4)
    tm.terrain_radio_map(higher, options)
    second = dict(counts)
    assert second["load_dict"] == first["load_dict"] + 1  # the new flight level only
    tm.terrain_radio_map(higher, tm.RadioMapOptions(samples=2**12, replicas=2))
    assert counts == second  # nothing built, nothing moved: the replicas turn the rays
    assert second["update"] - first["update"] <= 1  # Sionna's, once with the new flight level


def _scene_rotated_map(site: tm.RadioMapSite, options: tm.RadioMapOptions) -> np.ndarray:
    """Block power of the replicas made the other way: terrain, surface and antenna rigidly rotated about the
    transmitter by each replica's rotation R, the lattice left in place (the scheme before rays turned)."""
    import mitsuba as mi

    terrain = tm.terrain_scene(site.dem_m, site.cell_m, site.frequency_ghz, options.ground, options.k_factor)
    full = np.ones(tm.cells_to_blocks(np.ones(site.dem_m.shape, bool), options.step).shape, bool)
    surface = terrain.surface(site.altitude_m, options.step, full)
    params = mi.traverse(surface.mi_scene)
    keys = [key for key in params.keys() if key.endswith(".vertex_positions")]
    unmoved = {key: np.array(params[key], dtype=float).reshape(-1, 3) for key in keys}
    centre = np.array(terrain.transmitter.position.numpy(), dtype=float).ravel()
    areas, powers = surface.areas_m2.reshape(-1, 2), []
    try:
        for angles in tm.random_rotation_angles(options.replicas, np.random.default_rng(options.seed)):
            rotation = tm.rotation_matrix(angles)
            for key, vertices in unmoved.items():
                params[key] = mi.Float(((vertices - centre) @ rotation.T + centre).astype(np.float32).ravel())
            params.update()
            terrain.transmitter.orientation = [float(a) for a in angles]
            radio_map = tm.radio_map_solver()(
                terrain.scene,
                measurement_surface=surface.mesh,
                samples_per_tx=options.samples,
                max_depth=options.max_depth,
                modified_scene=surface.mi_scene,
            )
            gain = np.asarray(radio_map.path_gain.numpy(), dtype=float)[0].reshape(-1, 2)
            powers.append(np.sum(gain * areas, axis=1) / areas.sum(axis=1))
    finally:
        for key, vertices in unmoved.items():
            params[key] = mi.Float(vertices.astype(np.float32).ravel())
        params.update()
        terrain.transmitter.orientation = [0.0, 0.0, 0.0]
    with np.errstate(divide="ignore"):
        return 10 * np.log10(np.mean(powers, axis=0)).reshape(site.dem_m.shape)


@pytest.mark.slow
def test_turning_the_rays_gives_the_map_of_turning_the_scene():
    """A replica turns the lattice by R^T in the unmoved scene; rotating terrain, flight level and antenna by R
    about the transmitter shoots the same rays relative to the ground. Over hills with reflections the two
    maps differ only where float32 rounding sends a grazing ray into a neighbouring triangle: the median
    difference is nil and the map's own bound covers the difference on at least its stated share of cells."""
    dem = _hills(31, seed=5)
    site = tm.RadioMapSite(dem, 50.0, 15.0, 15.0, 10.0, 40.0, 2.4)
    options = tm.RadioMapOptions(samples=2**16, max_depth=2, seed=3)
    turned = tm.terrain_radio_map(site, options)
    rotated = _scene_rotated_map(site, options)
    assert np.array_equal(turned.reached, np.isfinite(rotated))
    reliable = turned.reliable
    difference = np.abs(turned.path_gain_db[reliable] - rotated[reliable])  # finite there
    assert reliable.mean() > 0.5 and np.median(difference) < 1e-3
    assert np.mean(difference <= turned.error_db[reliable]) >= tm.STATED_COVERAGE


@pytest.mark.slow
def test_a_sector_map_traces_and_measures_only_its_sector():
    """Flat ground, the sensor looking east over 90 degrees: cells outside the sector are NaN (not measured),
    inside the rays of the whole budget land where the two-ray oracle puts the power, within the bound on
    at least its stated share of the reliable cells, and the bound is tighter than the all-round map's with
    the same rays (4 times the rays over the sector)."""
    from csuas.core.dielectric import complex_permittivity
    from csuas.validation.links.terrain_map import block_average_two_ray

    dem = np.zeros((31, 31))
    site = tm.RadioMapSite(dem, 20.0, 15.0, 15.0, 10.0, 60.0, 1.0, sector_deg=(90.0, 90.0))
    options = tm.RadioMapOptions(samples=2**16, max_depth=1, k_factor=None, polarization="H")
    sector = tm.terrain_radio_map(site, options)
    inside = tm.sector_cells(dem.shape, 15.0, 15.0, (90.0, 90.0))
    assert np.array_equal(np.isnan(sector.path_gain_db), ~inside) and np.array_equal(np.isnan(sector.error_db), ~inside)
    assert not sector.reached[~inside].any() and np.array_equal(sector.extra["in_sector"], inside)
    eta = complex_permittivity(sector.extra["relative_permittivity"], sector.extra["conductivity_s_m"], 1.0)
    oracle = 10 * np.log10(block_average_two_ray(site, eta, polarization="H"))
    judged = sector.reliable
    assert judged.sum() > 0.9 * inside.sum()
    assert np.mean(np.abs(sector.path_gain_db - oracle)[judged] <= sector.error_db[judged]) >= tm.STATED_COVERAGE
    around = tm.terrain_radio_map(replace_sector(site, None), options)
    both = judged & around.reliable
    assert np.median(sector.error_db[both]) < 0.75 * np.median(around.error_db[both])


def replace_sector(site: tm.RadioMapSite, sector_deg) -> tm.RadioMapSite:
    from dataclasses import replace

    return replace(site, sector_deg=sector_deg)
