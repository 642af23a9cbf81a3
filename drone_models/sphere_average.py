"""Orientation-averaged silhouette metrics with an error estimate.

Averages over all view directions (uniform on the sphere, the weighting of
Eq. 7 with its cos(phi) Jacobian) are estimated by randomised quasi-Monte
Carlo: ``replicates`` independent, uniformly random rotations of a Fibonacci
lattice of ``n_directions / replicates`` points. Each replicate gives an
unbiased estimate; their mean is the result and the spread of the replicate
means gives its standard error (Owen, "Monte Carlo theory, methods and
examples", ch. 17). For a convex body the mean projected area is a quarter of
its surface area (Cauchy's formula), which the tests use as an oracle.
"""

from __future__ import annotations

import time

import numpy as np

from csuas.base.errors import ParameterError
from csuas.base.quality import QualityLadder, Setting
from csuas.drone_models.geometry import rotated_lattices
from csuas.drone_models.silhouette import SilhouetteModel, metrics_for_directions

#: The quality ladder of the sphere-averaged silhouette (csuas.base.quality).
LADDER = QualityLadder(
    "sphere-averaged silhouette (exact polygon union)",
    "sphere_average; csuas drone --quality, the report's defaults.drone",
    (
        Setting("replicates", "randomly rotated direction lattices (the standard error)"),
        Setting("directions_per_replicate", "Fibonacci directions per lattice"),
    ),
    draft=(4, 64),
    standard=(8, 128),
    reference=(16, 512),
    summary=lambda v: f"{v['replicates'] * v['directions_per_replicate']:,} directions",
)

#: Accuracy presets from :data:`LADDER`: name -> (replicates, directions per replicate).
QUALITY_PRESETS = LADDER.presets()

#: Metrics averaged over the sphere.
AVERAGED_METRICS = ("projected_area_m2", "d_x_proj_m", "d_y_proj_m", "d_crit_min_m", "d_crit_geometric_mean_m")


def sphere_average(
    mesh,
    quality: str = "standard",
    replicates: int | None = None,
    directions_per_replicate: int | None = None,
    seed: int = 0,
) -> dict:
    """Sphere-averaged silhouette metrics with standard errors.

    Parameters
    ----------
    mesh : SilhouetteModel or trimesh.Trimesh or Drone
        Geometry [m].
    quality : {"draft", "standard", "reference"}
        Preset of :data:`QUALITY_PRESETS`; ``replicates`` and
        ``directions_per_replicate`` override it.
    replicates : int, optional
        Number of randomly rotated lattices, >= 2.
    directions_per_replicate : int, optional
        Fibonacci points per lattice, >= 1.
    seed : int
        Seed of the random rotations (results are deterministic for a seed).

    Returns
    -------
    dict
        ``<metric>: {"mean", "stderr", "min", "max"}`` for each of
        :data:`AVERAGED_METRICS`, plus ``n_directions``, ``replicates``,
        ``quality``, ``seed`` and ``time_s`` [s].
    """
    if quality not in QUALITY_PRESETS:
        raise ParameterError("quality", quality, ", ".join(QUALITY_PRESETS))
    r_default, m_default = QUALITY_PRESETS[quality]
    r = r_default if replicates is None else replicates
    m = m_default if directions_per_replicate is None else directions_per_replicate
    if not isinstance(r, (int, np.integer)) or r < 2:
        raise ParameterError("replicates", r, "integer >= 2")
    if not isinstance(m, (int, np.integer)) or m < 1:
        raise ParameterError("directions_per_replicate", m, "integer >= 1")
    start = time.perf_counter()
    model = mesh if isinstance(mesh, SilhouetteModel) else SilhouetteModel.from_mesh(mesh)
    directions = rotated_lattices(r, m, seed).reshape(-1, 3)
    values = metrics_for_directions(model, directions)
    out = {}
    for key in AVERAGED_METRICS:
        per_replicate = values[key].reshape(r, m).mean(axis=1)
        out[key] = {
            "mean": float(per_replicate.mean()),
            "stderr": float(per_replicate.std(ddof=1) / np.sqrt(r)),
            "min": float(values[key].min()),
            "max": float(values[key].max()),
        }
    out.update(
        n_directions=int(r * m), replicates=int(r), quality=quality, seed=int(seed), time_s=time.perf_counter() - start
    )
    return out
