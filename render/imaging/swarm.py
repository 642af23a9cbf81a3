"""Swarms in the imaging renders (``target.swarm``, docs/scenarios.md "Swarms"): N copies of the target's
parts at the formation's offsets, one render, and one label per drone.

Each drone's label is the render's coverage inside that drone's own silhouette box (its projected mesh,
:func:`csuas.render.imaging.common.silhouette_box_px`): exact for drones whose boxes do not overlap; where
they overlap, the shared pixels go to each. The blobs of a frame are the 8-connected groups of covered
pixels (:func:`scipy.ndimage.label`), the merged blob of drones closer than a pixel's gap.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from scipy import ndimage

from csuas.core.swarm import target_frame_offsets_m
from csuas.render.imaging.common import silhouette_box_px
from csuas.render.imaging.scene import target_parts


def formation_members(target, formation, azimuth_deg: float, elevation_deg: float) -> list[list]:
    """Each drone's parts: the target's parts moved by its offset (the formation's frame turned into the
    target's for the view, :func:`csuas.core.swarm.target_frame_offsets_m`), names suffixed ``#i``."""
    parts = target_parts(target)
    shifts = target_frame_offsets_m(formation.offsets_m, azimuth_deg, elevation_deg)
    return [
        [dataclasses.replace(p, name=f"{p.name}#{i}", mesh=p.mesh.copy().apply_translation(shift)) for p in parts]
        for i, shift in enumerate(shifts)
    ]


def member_track_id(track_id: int, member: int) -> int:
    """The track of drone ``member`` (0-based) of a sequence's swarm: the video's own ``track_id`` for drone 0,
    1000 x track_id + 100 + member for the others (beside a video's confusers, 1000 x video + 1 to 33)."""
    return int(track_id) if member == 0 else 1000 * int(track_id) + 100 + int(member)


def member_coverage(coverage: np.ndarray, x0: int, y0: int, box: tuple) -> np.ndarray:
    """The window's coverage kept only on pixels that overlap a film box (x_lo, x_hi, y_lo, y_hi); pixel
    (row i, column j) spans [x0 + j, x0 + j + 1] x [y0 + i, y0 + i + 1] (edges at integers)."""
    x_lo, x_hi, y_lo, y_hi = box
    cols = x0 + np.arange(coverage.shape[1])
    rows = y0 + np.arange(coverage.shape[0])
    keep_x = (cols + 1 > x_lo) & (cols < x_hi)
    keep_y = (rows + 1 > y_lo) & (rows < y_hi)
    return np.where(keep_y[:, None] & keep_x[None, :], coverage, 0.0)


def member_results(members: list, view, result, geometry) -> list:
    """One copy of an :class:`~csuas.render.imaging.result.ImagingResult` per drone, its coverage that of
    the drone alone (:func:`member_coverage` of the drone's silhouette box)."""
    cx, cy = geometry.default_target_px()
    centre = (cx + view.target_offset_px[0], cy + view.target_offset_px[1])
    out = []
    for parts in members:
        box = silhouette_box_px(parts, view.range_m, view.azimuth_deg, view.elevation_deg, geometry, centre)
        coverage = member_coverage(result.coverage, result.window.x0, result.window.y0, box)
        out.append(dataclasses.replace(result, coverage=coverage))
    return out


def blobs(coverage: np.ndarray) -> list[int]:
    """Pixels of each blob of a render (8-connected groups of covered pixels), largest first."""
    labels, count = ndimage.label(np.asarray(coverage) > 0, structure=np.ones((3, 3)))
    sizes = np.bincount(labels.ravel())[1:] if count else np.zeros(0, int)
    return sorted((int(s) for s in sizes), reverse=True)


def member_labels(members: list, view, result, n_h: int, n_v: int, chain=None) -> list[dict]:
    """Each drone's label in the frame (:func:`csuas.render.imaging.frame.frame_label` of its own coverage)."""
    from csuas.render.imaging.camera import SensorGeometry
    from csuas.render.imaging.frame import frame_label

    geometry = SensorGeometry(result.ifov_rad, n_h, n_v)
    return [
        frame_label(parts, view, alone, n_h, n_v, chain)
        for parts, alone in zip(members, member_results(members, view, result, geometry))
    ]


def swarm_summary(members: list, view, result, n_h: int, n_v: int) -> dict:
    """What ``csuas render eo|tir`` reports of a swarm: each drone's box and pixels, and the frame's blobs."""
    labels = member_labels(members, view, result, n_h, n_v)
    return {
        "count": len(members),
        "drones": [
            {key: lab[key] for key in ("bbox", "area", "pixels_on_target", "clipped", "in_frame")} for lab in labels
        ],
        "blobs_px": blobs(result.coverage),
    }
