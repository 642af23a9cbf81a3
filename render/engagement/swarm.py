"""A swarm in an engagement (the scenario's ``target.swarm``, docs/engagements.md "Swarms"): N truths flying
the drone's path in formation, and the groups each sensor resolves of them at each look.

The formation's offsets are taken in the flight frame: x behind the lead (against its heading), y to its
left, z up. On a straight approach to a sensor at the protected point this is the frame of
:mod:`csuas.core.swarm` (x away from the sensor, y across, z up). At each look a sensor resolves the
groups of :func:`csuas.core.swarm.groups_at` (its cell, :func:`csuas.core.swarm_detection.sensor_cells`,
at the lead's slant range, the offsets turned into that look's line of sight); each group is detected at
its centroid with the Pd of its merged signature (:func:`csuas.core.swarm_detection.group_target`), the
groups of a look independently and the looks independently (no copula across looks for a swarm).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from csuas.core.swarm import Formation, groups_at, line_of_sight_axes, link_range_m
from csuas.core.swarm_detection import group_target, sensor_cells


@dataclass
class SwarmLooks:
    """The swarm as one sensor sees it at each look (the same in every run).

    Attributes
    ----------
    t_s : ndarray (K,)
        Look times [s].
    x, y : ndarray (K, N)
        Each drone's position [m].
    groups : list of list of tuple
        The groups resolved at each look (drone indices).
    centres : list of ndarray (G_k, 2)
        Each group's centroid (x, y) [m].
    pd : list of ndarray (G_k,)
        Each group's Pd.
    """

    t_s: np.ndarray
    x: np.ndarray
    y: np.ndarray
    groups: list
    centres: list
    pd: list

    @property
    def resolved_count(self) -> np.ndarray:
        """Groups resolved at each look."""
        return np.array([len(g) for g in self.groups])

    @property
    def pd_any(self) -> np.ndarray:
        """Pd that any group is detected at each look, 1 - prod (1 - Pd_g)."""
        return np.array([1.0 - np.prod(1.0 - p) for p in self.pd])


def member_positions(path, formation: Formation, t_s) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each drone's (x, y, height above the terrain) at times ``t_s`` (K, N): the lead on ``path``, the
    others at the formation's offsets in the flight frame (module docstring)."""
    x0, y0, h0, heading = path.at(np.asarray(t_s, float))
    ox, oy, oz = formation.offsets_m.T
    back, left = (-np.cos(heading), -np.sin(heading)), (-np.sin(heading), np.cos(heading))
    x = x0[:, None] + ox * back[0][:, None] + oy * left[0][:, None]
    y = y0[:, None] + ox * back[1][:, None] + oy * left[1][:, None]
    return x, y, h0[:, None] + oz


def _look_groups(sensor, cells, points: np.ndarray, lead: int = 0) -> list:
    """The groups one sensor resolves among points (N, 3) [m] seen from it, at the lead's slant range."""
    to_sensor = np.array([sensor.x, sensor.y, sensor.eye_z]) - points[lead]
    slant = float(np.linalg.norm(to_sensor))
    az = np.degrees(np.arctan2(to_sensor[1], to_sensor[0]))
    el = np.degrees(np.arcsin(to_sensor[2] / max(slant, 1e-9)))
    offsets = (points - points[lead]) @ line_of_sight_axes(az, el).T
    link = link_range_m(offsets, cells.along_m, cells.across_m, cells.across_per_m)
    return [tuple(int(i) for i in g) for g in groups_at(link, slant)]


def swarm_looks(terrain, sensor, path, formation: Formation, t_s) -> SwarmLooks:
    """The swarm at every look of a sensor: positions, resolved groups, their centroids and Pd."""
    x, y, h = member_positions(path, formation, t_s)
    z = terrain.height(x, y) + h
    cells = sensor_cells(sensor.scenario, sensor.spec)
    groups = [_look_groups(sensor, cells, np.stack([x[k], y[k], z[k]], axis=1)) for k in range(len(t_s))]
    centres = [np.array([[x[k, list(g)].mean(), y[k, list(g)].mean()] for g in gs]) for k, gs in enumerate(groups)]
    heights = [np.array([z[k, list(g)].mean() for g in gs]) for k, gs in enumerate(groups)]
    pd = [np.zeros(len(gs)) for gs in groups]
    for members in {g for gs in groups for g in gs}:  # one Pd evaluation per distinct group
        where = [(k, j) for k, gs in enumerate(groups) for j, g in enumerate(gs) if g == members]
        xs = np.array([centres[k][j, 0] for k, j in where])
        ys = np.array([centres[k][j, 1] for k, j in where])
        zs = np.array([heights[k][j] for k, j in where])
        variant = replace(sensor.scenario, target=group_target(sensor.scenario, sensor.modality, np.array(members)))
        values = sensor.drone_pd(sensor.geometry(xs, ys, zs), variant)
        for (k, j), value in zip(where, values):
            pd[k][j] = value
    return SwarmLooks(np.asarray(t_s, float), x, y, groups, centres, pd)
