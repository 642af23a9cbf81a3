"""SBR-PO engine: materials (Fresnel), hard cases, bad input, batching and memory."""

from __future__ import annotations

import cmath
import math
import resource

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st

from csuas.base.errors import ParameterError
from csuas.render.rcs import canonical, load_target, prepare_mesh, resolve_material
from csuas.render.rcs.engine import Jobs, SbrEngine
from csuas.render.rcs.solver import DBSM_FLOOR, compute_rcs

C = 299_792_458.0
LAM = C / 10e9
EPS0 = 8.8541878128e-12


def plate_sigma(a=0.1):
    return 4 * math.pi * (a * a) ** 2 / LAM**2


# ---------------------------------------------------------------- materials
def test_dielectric_half_space_plate_scales_by_fresnel_power():
    """Normal incidence: sigma = |(1 - sqrt(eps)) / (1 + sqrt(eps))|^2 * sigma_PEC."""
    pec = compute_rcs(canonical.plate(0.1), 10.0, 0.0, 90.0, material="pec", error_estimate=False)
    for eps in (4.0 + 0j, 2.8 - 0.03j):
        gamma = (1 - cmath.sqrt(eps)) / (1 + cmath.sqrt(eps))
        res = compute_rcs(canonical.plate(0.1), 10.0, 0.0, 90.0, material=eps, error_estimate=False)
        for pol in ("VV", "HH"):
            ratio = res.rcs_m2(pol)[0, 0, 0] / pec.rcs_m2(pol)[0, 0, 0]
            assert ratio == pytest.approx(abs(gamma) ** 2, rel=2e-3)


def test_itu_concrete_uses_p2040_parameters():
    """ITU-R P.2040-3 Table 3, concrete 1-100 GHz: eps' = 5.24, sigma = 0.0462 f^0.7822 S/m (f in GHz)."""
    f = 10.0
    eps = complex(5.24, -0.0462 * f**0.7822 / (2 * math.pi * f * 1e9 * EPS0))
    gamma = (1 - cmath.sqrt(eps)) / (1 + cmath.sqrt(eps))
    pec = compute_rcs(canonical.plate(0.1), f, 0.0, 90.0, material="pec", error_estimate=False)
    res = compute_rcs(canonical.plate(0.1), f, 0.0, 90.0, material="itu_concrete", error_estimate=False)
    assert res.rcs_m2("VV")[0, 0, 0] / pec.rcs_m2("VV")[0, 0, 0] == pytest.approx(abs(gamma) ** 2, rel=2e-3)
    assert resolve_material("concrete").itu_name == "concrete"


def test_dielectric_dihedral_applies_te_and_tm_fresnel_at_45_degrees():
    """Two reflections at 45 deg: HH (E along the fold, TE) scales by |G_perp|^4, VV (TM) by |G_par|^4."""
    eps = 4.0
    c = math.cos(math.pi / 4)
    root = math.sqrt(eps - 0.5)
    g_perp = (c - root) / (c + root)
    g_par = (eps * c - root) / (eps * c + root)
    mesh = canonical.dihedral(0.1, 0.15)
    pec = compute_rcs(mesh, 10.0, 0.0, 0.0, material="pec", error_estimate=False)
    die = compute_rcs(mesh, 10.0, 0.0, 0.0, material=complex(eps), error_estimate=False)
    hh = die.rcs_m2("HH")[0, 0, 0] / pec.rcs_m2("HH")[0, 0, 0]
    vv = die.rcs_m2("VV")[0, 0, 0] / pec.rcs_m2("VV")[0, 0, 0]
    assert 10 * math.log10(hh) == pytest.approx(10 * math.log10(g_perp**4), abs=0.3)
    assert 10 * math.log10(vv) == pytest.approx(10 * math.log10(g_par**4), abs=0.5)


def test_material_specifications():
    assert resolve_material("PEC").is_pec
    assert resolve_material(complex(3.0, -0.1)).relative_permittivity == complex(3.0, -0.1)

    class Part:  # duck-typed drone material with infinite conductivity
        name, relative_permittivity, conductivity_s_m, is_pec = "metal", 1.0 + 0j, float("inf"), False

    assert resolve_material(Part()).is_pec
    with pytest.raises(ParameterError, match="material"):
        resolve_material("unobtainium")
    with pytest.raises(ParameterError):
        resolve_material(complex(3.0, +0.5))  # gain, not loss
    with pytest.raises(ParameterError, match="itu_wet_ground"):
        resolve_material("itu_wet_ground").complex_permittivity(35.0)  # outside 1-10 GHz


# ---------------------------------------------------------------- hard cases
@pytest.mark.parametrize("elevation", [0.0, 0.01, 0.5, 1.0])
def test_grazing_and_edge_on_plate_stay_finite_and_small(elevation):
    res = compute_rcs(canonical.plate(0.1), 10.0, 0.0, elevation, rays_per_wavelength=10)
    for pol in ("VV", "HH", "HV", "VH"):
        sigma = res.rcs_m2(pol)[0, 0, 0]
        assert np.isfinite(sigma) and 0.0 <= sigma < 1e-3 * plate_sigma()
        assert np.isfinite(res.rcs_dbsm(pol)).all() and res.rcs_dbsm(pol)[0, 0, 0] >= DBSM_FLOOR
    assert np.isfinite(res.error_estimate_db("VV")).all()


def test_grazing_on_a_closed_body_and_at_the_poles():
    cube = trimesh.creation.box(extents=(0.2, 0.2, 0.2))
    res = compute_rcs(cube, 10.0, [0.0, 0.0, 45.0, 0.0], [90.0, -90.0, 0.0, 0.001], rays_per_wavelength=6)
    sig = res.rcs_m2("VV")[0, :, 0]
    assert np.isfinite(sig).all()
    assert 10 * np.log10(sig[0]) == pytest.approx(10 * np.log10(4 * math.pi * 0.04**2 / LAM**2), abs=0.5)
    assert sig[1] == pytest.approx(sig[0], rel=0.05)


def test_degenerate_faces_are_dropped_without_changing_the_result():
    clean = canonical.plate(0.1)
    v = np.vstack([clean.vertices, [[0.05, 0.05, 0.0], [np.nan, 0.0, 0.0]]])
    f = np.vstack([clean.faces, [[0, 0, 1], [1, 2, 4], [0, 1, 5], [2, 2, 2]]])  # zero-area, collinear, NaN
    target = prepare_mesh(v, f)
    assert target.dropped_faces == 4 and len(target.faces) == 2
    a = compute_rcs(target, 10.0, 10.0, 80.0, error_estimate=False).rcs_m2("VV")
    b = compute_rcs(clean, 10.0, 10.0, 80.0, error_estimate=False).rcs_m2("VV")
    np.testing.assert_allclose(a, b, rtol=1e-6)
    with pytest.raises(ParameterError, match="zero area"):
        prepare_mesh([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 2]])
    with pytest.raises(ParameterError):
        prepare_mesh(np.zeros((0, 3)), np.zeros((0, 3), int))
    with pytest.raises(ParameterError, match="faces"):
        prepare_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 3]])


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "kwargs, name",
    [
        ({"frequency_ghz": -1.0}, "frequency_ghz"),
        ({"frequency_ghz": 0.0}, "frequency_ghz"),
        ({"frequency_ghz": float("nan")}, "frequency_ghz"),
        ({"rays_per_wavelength": 0.5}, "rays_per_wavelength"),
        ({"rays_per_wavelength": float("inf")}, "rays_per_wavelength"),
        ({"max_bounces": 0}, "max_bounces"),
        ({"material": "unobtainium"}, "material"),
        ({"elevation_deg": 91.0}, "elevation_deg"),
        ({"azimuth_deg": float("nan")}, "azimuth_deg"),
        ({"quality": "ultra"}, "quality"),
        ({"observe_azimuth_deg": [0.0]}, "observe_elevation_deg"),
    ],
)
def test_bad_input_raises_parameter_error(kwargs, name):
    args = {"frequency_ghz": 10.0, **kwargs}
    freq = args.pop("frequency_ghz")
    with pytest.raises(ParameterError, match=name):
        compute_rcs(canonical.plate(0.1), freq, error_estimate=False, **args)


def test_unknown_polarisation_and_missing_file():
    res = compute_rcs(canonical.plate(0.1), 10.0, 0.0, 90.0, error_estimate=False)
    with pytest.raises(ParameterError, match="polarisation"):
        res.rcs_m2("XX")
    with pytest.raises(ParameterError, match="mesh"):
        load_target("/nonexistent/file.stl")


# ---------------------------------------------------------------- launches
def test_batches_give_the_same_sum_as_one_launch():
    mesh = canonical.dihedral(0.1, 0.15)
    jobs = Jobs.build([0.0, 20.0, 200.0], [0.0, 10.0, -5.0], [10.0, 10.0, 12.0], 8.0)
    one = SbrEngine(load_target(mesh)).trace(jobs)
    many = SbrEngine(load_target(mesh), batch_size=1000).trace(jobs)
    assert one.tubes.sum() > 5000
    np.testing.assert_allclose(many.amplitude, one.amplitude, rtol=1e-5, atol=1e-9)
    again = SbrEngine(load_target(mesh)).trace(jobs)
    np.testing.assert_array_equal(again.amplitude, one.amplitude)  # deterministic


def test_frequency_batch_scales_with_frequency_squared():
    res = compute_rcs(canonical.plate(0.1), [5.0, 10.0, 20.0], 0.0, 90.0, rays_per_wavelength=12, error_estimate=False)
    db = res.rcs_dbsm("VV")[:, 0, 0]
    assert db[1] - db[0] == pytest.approx(20 * math.log10(2), abs=0.3)
    assert db[2] - db[1] == pytest.approx(20 * math.log10(2), abs=0.3)


def test_bounce_limit_and_radiation_modes():
    mesh = canonical.dihedral(0.1, 0.15)
    two = compute_rcs(mesh, 10.0, 0.0, 0.0, max_bounces=2, error_estimate=False).rcs_m2("VV")[0, 0, 0]
    one = compute_rcs(mesh, 10.0, 0.0, 0.0, max_bounces=1, error_estimate=False).rcs_m2("VV")[0, 0, 0]
    assert one < 0.05 * two  # the double bounce carries the return
    plate_exit = compute_rcs(canonical.plate(0.1), 10.0, 5.0, 80.0, radiate="exit", error_estimate=False)
    plate_all = compute_rcs(canonical.plate(0.1), 10.0, 5.0, 80.0, radiate="all", error_estimate=False)
    np.testing.assert_allclose(plate_all.sigma_m2, plate_exit.sigma_m2, rtol=1e-6)
    with pytest.raises(ParameterError, match="radiate"):
        compute_rcs(canonical.plate(0.1), 10.0, radiate="never")


@pytest.mark.slow
def test_memory_stays_bounded_for_ten_million_tubes():
    """1e7 tubes in batches of 2^20: resident memory grows by well under 1 GiB (1e8 tubes: see bench_memory)."""
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    engine = SbrEngine(load_target(canonical.plate(1.0)), batch_size=1 << 20)
    n = math.sqrt(1e7) * LAM
    res = engine.trace(Jobs.build(0.0, 90.0, 10.0, n), 1)
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    assert res.tubes.sum() >= 1e7
    assert after - before < 1.0
    assert 10 * math.log10(res.sigma_m2[0, 0, 0, 0]) == pytest.approx(10 * math.log10(4 * math.pi / LAM**2), abs=0.05)


# ---------------------------------------------------------------- thin shells
def tmm_normal(layers, k0, back="air"):
    """Reflection (and transmission) at normal incidence of a stack by transfer matrices (e^{+j w t}).

    ``layers``: list of (refractive index, thickness [m]) from the illuminated side; ``back``: "air" or "pec".
    Amplitudes (A, B) of exp(-j k n z) and exp(+j k n z); E and H/eta0 continuous at each interface.
    Returns (r, t) at the first face, t relative to the field at the last face (air backing only).
    """

    def interface(n1, n2):
        return np.array([[n1 + n2, n1 - n2], [n1 - n2, n1 + n2]]) / (2 * n1)

    m = np.eye(2, dtype=complex)
    n_prev = 1.0
    for n, h in layers:
        m = m @ interface(n_prev, n) @ np.diag([np.exp(1j * k0 * n * h), np.exp(-1j * k0 * n * h)])
        n_prev = n
    if back == "pec":  # E = A + B = 0 at the conductor: (A, B) = (1, -1)
        a, b = m @ np.array([1.0, -1.0])
        return b / a, None
    m = m @ interface(n_prev, 1.0)
    return m[1, 0] / m[0, 0], 1.0 / m[0, 0]


@pytest.mark.parametrize("f_ghz, h", [(10.0, 0.002), (35.0, 0.00256)])
def test_thin_shell_plate_reflects_like_a_slab(f_ghz, h):
    """Normal incidence on a 2.8 - 0.03j slab: sigma / sigma_PEC = |r_slab|^2 (35 GHz, 2.56 mm: near half-wave)."""
    eps = complex(2.8, -0.03)
    k0 = 2 * math.pi * f_ghz * 1e9 / C
    r, _ = tmm_normal([(cmath.sqrt(eps), h)], k0)
    plate = canonical.plate(0.1)
    pec = compute_rcs(plate, f_ghz, 0.0, 90.0, error_estimate=False).rcs_m2("VV")[0, 0, 0]
    shell = compute_rcs(plate, f_ghz, 0.0, 90.0, material=eps, shell_thickness_m=h, error_estimate=False).rcs_m2("VV")[
        0, 0, 0
    ]
    assert shell / pec == pytest.approx(abs(r) ** 2, rel=0.02, abs=1e-5)


def test_conductor_behind_a_radome_sheet_multiple_reflections():
    """PEC plate 37.5 mm behind a 3 mm dielectric sheet (mid-plane): the SBR series of internal bounces
    reproduces the stack's reflection air | slab | air gap | PEC by transfer matrices."""
    f_ghz, h, gap, eps = 10.0, 0.003, 0.0375, complex(4.0, -0.2)
    k0 = 2 * math.pi * f_ghz * 1e9 / C
    r, _ = tmm_normal([(cmath.sqrt(eps), h), (1.0, gap - h / 2)], k0, back="pec")
    sheet = canonical.plate(0.1)
    sheet.vertices[:, 2] += gap
    conductor = canonical.plate(0.1)
    mesh = trimesh.util.concatenate([sheet, conductor])
    target = prepare_mesh(mesh.vertices, mesh.faces, [0, 0, 1, 1], [eps, "pec"]).with_shells(h)
    pec = compute_rcs(canonical.plate(0.1), f_ghz, 0.0, 90.0, error_estimate=False).rcs_m2("HH")[0, 0, 0]
    res = compute_rcs(
        target, f_ghz, 0.0, 90.0, rays_per_wavelength=10, max_bounces=16, power_cutoff=1e-6, error_estimate=False
    )
    assert res.rcs_m2("HH")[0, 0, 0] / pec == pytest.approx(abs(r) ** 2, rel=0.03)
    assert res.exits_by_bounce[5:].sum() > 0  # several round trips were traced


def test_drone_presets_have_dielectric_shells_and_conductors():
    target = load_target("dji_mini_4_pro")
    by_name = {m.name: m for m in target.materials}
    assert by_name["paint"].thickness_m == pytest.approx(0.002)
    assert by_name["aluminium"].thickness_m is None and by_name["carbon_fibre"].thickness_m is None
    half = load_target("dji_mini_4_pro", shell_thickness_m=0)
    assert all(m.thickness_m is None for m in half.materials)
    with pytest.raises(ParameterError, match="shell_thickness_m"):
        load_target("dji_mini_4_pro", shell_thickness_m=-1.0)


# ---------------------------------------------------------------- scaling law
@settings(max_examples=8, deadline=None)
@given(scale=st.floats(0.2, 5.0), azimuth=st.floats(-30.0, 30.0), elevation=st.floats(-20.0, 20.0))
def test_electromagnetic_scaling(scale, azimuth, elevation):
    """Maxwell's equations are scale invariant: the mesh scaled by s at frequency f / s has s^2 times the RCS."""
    mesh = canonical.dihedral(0.1, 0.15)
    big = canonical.dihedral(0.1 * scale, 0.15 * scale)
    a = compute_rcs(mesh, 10.0, azimuth, elevation, rays_per_wavelength=6, error_estimate=False).sigma_m2
    b = compute_rcs(big, 10.0 / scale, azimuth, elevation, rays_per_wavelength=6, error_estimate=False).sigma_m2
    np.testing.assert_allclose(b, scale**2 * a, rtol=2e-3, atol=1e-6 * scale**2 * a.max())


def slab_reflection_oblique(eps, h, k0, theta):
    """|r|^2 of a slab in air for TE and TM by the characteristic matrix (Born & Wolf 1.6)."""
    sin_t = math.sin(theta)
    cos_0 = math.cos(theta)
    n1 = cmath.sqrt(eps)
    cos_1 = cmath.sqrt(1 - sin_t**2 / eps)
    delta = k0 * n1 * h * cos_1
    out = []
    for eta0, eta1 in ((cos_0, n1 * cos_1), (1 / cos_0, n1 / cos_1)):  # TE, TM admittances
        m11, m12 = cmath.cos(delta), 1j * cmath.sin(delta) / eta1
        m21, m22 = 1j * eta1 * cmath.sin(delta), cmath.cos(delta)
        r = (eta0 * m11 + eta0 * eta0 * m12 - m21 - eta0 * m22) / (eta0 * m11 + eta0 * eta0 * m12 + m21 + eta0 * m22)
        out.append(abs(r) ** 2)
    return out


def test_thin_shell_oblique_specular_te_and_tm():
    """Bistatic specular reflection at 40 deg off a 3 mm slab: HH (TE) and VV (TM) scale by |r|^2."""
    eps, h, f_ghz, theta = complex(4.0, -0.1), 0.003, 10.0, math.radians(40.0)
    k0 = 2 * math.pi * f_ghz * 1e9 / C
    r_te, r_tm = slab_reflection_oblique(eps, h, k0, theta)
    kwargs = dict(
        observe_azimuth_deg=[180.0], observe_elevation_deg=[50.0], rays_per_wavelength=10, error_estimate=False
    )
    pec = compute_rcs(canonical.plate(0.1), f_ghz, 0.0, 50.0, **kwargs)
    shell = compute_rcs(canonical.plate(0.1), f_ghz, 0.0, 50.0, material=eps, shell_thickness_m=h, **kwargs)
    assert shell.rcs_m2("HH")[0, 0, 0] / pec.rcs_m2("HH")[0, 0, 0] == pytest.approx(r_te, rel=0.01)
    assert shell.rcs_m2("VV")[0, 0, 0] / pec.rcs_m2("VV")[0, 0, 0] == pytest.approx(r_tm, rel=0.01)
