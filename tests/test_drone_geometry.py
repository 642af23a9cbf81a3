"""View directions, image axes and direction sets of csuas.drone_models.geometry."""

import numpy as np
import pytest

from csuas.base.errors import ParameterError
from csuas.drone_models.geometry import (
    direction_angles,
    direction_vector,
    fibonacci_sphere,
    random_rotations,
    validate_angles,
    view_basis,
)


def test_direction_vector_cardinal_directions():
    np.testing.assert_allclose(direction_vector(0, 0), [1, 0, 0], atol=1e-15)
    np.testing.assert_allclose(direction_vector(90, 0), [0, 1, 0], atol=1e-15)
    np.testing.assert_allclose(direction_vector(-90, 0), [0, -1, 0], atol=1e-15)
    np.testing.assert_allclose(direction_vector(123, 90), [0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(direction_vector(0, -90), [0, 0, -1], atol=1e-15)
    np.testing.assert_allclose(direction_vector(45, 45), [0.5, 0.5, np.sqrt(0.5)], atol=1e-15)


def test_direction_vector_broadcasts_and_round_trips():
    az = np.linspace(-170, 170, 7)[:, None]
    el = np.linspace(-80, 80, 5)[None, :]
    d = direction_vector(az, el)
    assert d.shape == (7, 5, 3)
    np.testing.assert_allclose(np.linalg.norm(d, axis=-1), 1.0, atol=1e-15)
    az2, el2 = direction_angles(d)
    np.testing.assert_allclose(az2, np.broadcast_to(az, (7, 5)), atol=1e-12)
    np.testing.assert_allclose(el2, np.broadcast_to(el, (7, 5)), atol=1e-12)


@pytest.mark.parametrize(
    "az, el, name",
    [
        (400, 0, "azimuth_deg"),
        (-361, 0, "azimuth_deg"),
        (0, 90.5, "elevation_deg"),
        (0, -91, "elevation_deg"),
        (np.nan, 0, "azimuth_deg"),
        (0, np.inf, "elevation_deg"),
    ],
)
def test_angles_out_of_range_raise(az, el, name):
    with pytest.raises(ParameterError, match=name):
        validate_angles(az, el)


def test_view_basis_is_right_handed_and_level():
    rng = np.random.default_rng(1)
    d = rng.normal(size=(200, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    h, v = view_basis(d)
    np.testing.assert_allclose(np.sum(h * d, axis=1), 0, atol=1e-14)
    np.testing.assert_allclose(np.sum(v * d, axis=1), 0, atol=1e-14)
    np.testing.assert_allclose(h[:, 2], 0, atol=1e-15)  # horizontal axis is level (perpendicular to world z)
    np.testing.assert_allclose(np.linalg.norm(h, axis=1), 1, atol=1e-14)
    assert np.all(v[:, 2] >= 0)  # the vertical image axis points upward
    np.testing.assert_allclose(np.cross(h, v), d, atol=1e-14)  # (h, v, d) right-handed: d toward the viewer


def test_view_basis_front_view_axes():
    h, v = view_basis([1.0, 0.0, 0.0])
    np.testing.assert_allclose(h, [0, 1, 0], atol=1e-15)  # sensor on the nose side sees the drone's left on its right
    np.testing.assert_allclose(v, [0, 0, 1], atol=1e-15)


@pytest.mark.parametrize("az", [0.0, 30.0, 90.0, -135.0])
@pytest.mark.parametrize("el", [90.0, -90.0])
def test_view_basis_straight_up_down_is_the_limit_at_that_azimuth(az, el):
    d = direction_vector(az, el)
    h, v = view_basis(d, az)
    near = direction_vector(az, np.sign(el) * (90.0 - 1e-7))
    h_near, v_near = view_basis(near)
    np.testing.assert_allclose(h, [-np.sin(np.radians(az)), np.cos(np.radians(az)), 0.0], atol=1e-12)
    np.testing.assert_allclose(h, h_near, atol=1e-6)
    np.testing.assert_allclose(v, v_near, atol=1e-6)


def test_view_basis_rejects_zero_vector():
    with pytest.raises(ParameterError, match="direction"):
        view_basis([0.0, 0.0, 0.0])


def test_fibonacci_sphere_is_unit_and_balanced():
    p = fibonacci_sphere(1000)
    assert p.shape == (1000, 3)
    np.testing.assert_allclose(np.linalg.norm(p, axis=1), 1.0, atol=1e-14)
    np.testing.assert_allclose(p.mean(axis=0), 0.0, atol=2e-3)
    # uniform on the sphere: E[z^2] = 1/3; a lattice gets it to O(1/n^2) for z
    assert abs(np.mean(p[:, 2] ** 2) - 1 / 3) < 1e-5
    with pytest.raises(ParameterError):
        fibonacci_sphere(0)


def test_random_rotations_are_proper_rotations():
    r = random_rotations(50, np.random.default_rng(3))
    np.testing.assert_allclose(r @ r.transpose(0, 2, 1), np.broadcast_to(np.eye(3), (50, 3, 3)), atol=1e-13)
    np.testing.assert_allclose(np.linalg.det(r), 1.0, atol=1e-13)


def test_rotated_lattices_are_rotations_of_one_fibonacci_lattice():
    from csuas.drone_models.geometry import fibonacci_sphere, rotated_lattices

    dirs = rotated_lattices(3, 50, seed=4)
    assert dirs.shape == (3, 50, 3)
    np.testing.assert_allclose(np.linalg.norm(dirs, axis=-1), 1.0, rtol=1e-12)
    base = fibonacci_sphere(50)
    for replicate in dirs:  # a rotation preserves every pairwise angle of the lattice
        np.testing.assert_allclose(replicate @ replicate.T, base @ base.T, atol=1e-12)
    assert not np.allclose(dirs[0], dirs[1])
