"""Flash-aware aspect sampling (render/rcs/aspect_sampling.py): the proposal is a density, its draws follow
it, and the balance-heuristic weights give unbiased sphere means of known integrands."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from csuas.drone_models.geometry import fibonacci_sphere
from csuas.render.rcs import canonical
from csuas.render.rcs.aspect_sampling import flash_proposal, flat_panels, uniform_weight
from csuas.render.rcs.geometry import load_target


def test_coplanar_faces_merge_into_panels_with_their_areas():
    normal, area = flat_panels(load_target(trimesh.creation.box(extents=(0.1, 0.2, 0.3))))
    assert len(area) == 6  # two triangles per face of the box
    assert sorted(np.round(area, 6)) == sorted([0.02, 0.02, 0.03, 0.03, 0.06, 0.06])
    assert np.allclose(np.abs(normal).max(axis=1), 1.0)


def test_proposal_density_integrates_to_one_and_draws_follow_it():
    proposal = flash_proposal(load_target(canonical.plate(0.1)), 10.0)
    grid = fibonacci_sphere(400_000)
    assert proposal.density(grid).mean() * 4 * np.pi == pytest.approx(1.0, rel=1e-3)
    draws = proposal.sample(200_000, np.random.default_rng(1))
    assert np.allclose(np.linalg.norm(draws, axis=1), 1.0)
    # the fraction of draws within 10 deg of the plate's normals against the density's integral there
    near = np.abs(draws[:, 2]) > np.cos(np.radians(10.0))
    expected = (proposal.density(grid) * (np.abs(grid[:, 2]) > np.cos(np.radians(10.0)))).mean() * 4 * np.pi
    assert near.mean() == pytest.approx(expected, abs=0.005)


def test_weighted_half_and_half_sample_is_unbiased_for_known_sphere_means():
    """(1/4 pi) int f dOmega for f = 1, z^2, and a sharp lobe exp(100 (z - 1)) (mean (1 - e^-200)/200)."""
    proposal = flash_proposal(load_target(canonical.plate(0.1)), 10.0)
    rng = np.random.default_rng(5)
    uniform = rng.normal(size=(100_000, 3))
    uniform /= np.linalg.norm(uniform, axis=1, keepdims=True)
    both = np.concatenate([uniform, proposal.sample(100_000, rng)])
    w = uniform_weight(both, proposal)
    for f, exact in (
        (np.ones(len(both)), 1.0),
        (both[:, 2] ** 2, 1 / 3),
        (np.exp(100 * (both[:, 2] - 1)), (1 - np.exp(-200)) / 200),
    ):
        estimate = (f * w).mean()
        standard_error = (f * w).std() / np.sqrt(len(both))
        assert abs(estimate - exact) < 4 * standard_error + 1e-12
    # the lobe is estimated far better than by the uniform half alone
    lobe = np.exp(100 * (both[:, 2] - 1))
    assert (lobe * w).std() < 0.5 * lobe[: len(uniform)].std()
