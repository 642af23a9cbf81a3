"""The physics Pd of the very frames a learned detector is scored on, from each label's ``csuas`` block.

A csuas dataset records, per drone, the Johnson cycles its rendered silhouette puts across d_crit
(``johnson_cycles``, pixels across d_crit / 2, Eq. 17) and its blob SNR against the camera's shot and
read noise (``snr``, docs/datasets.md). The core turns them into the two detection probabilities the
paper's EO model and ``csuas pd`` use (docs/detection.md):

* the target transfer probability function of the cycles over those of a 50 % detection,
  x = N / N50 with N50 the detection task's line pairs (Table 20), with the classic (Johnson) and the
  TTP exponent (:func:`csuas.core.detection.ttpf_probability`);
* a per-pixel threshold on the blob SNR in Gaussian noise at the sensor's Pfa,
  Q(Q^-1(Pfa) - SNR) (:func:`csuas.core.detection.gaussian_pd`);
* their product, the EO Pd of ``csuas pd --convention physical`` (core/pd_curves.py).

References
----------
- G. C. Holst, Electro-Optical Imaging System Performance, 5th ed., SPIE, 2008, ch. 21.
- R. H. Vollmerhausen, E. Jacobs and R. G. Driggers, Opt. Eng. 43(11), 2004 (TTP exponent).
"""

from __future__ import annotations

import numpy as np

from csuas.core.detection import gaussian_pd, ttpf_probability
from csuas.core.johnson import line_pairs
from csuas.defaults import load_parameters

#: The physics columns, in the order they are reported.
COLUMNS = ("pd_ttpf_johnson", "pd_ttpf_ttp", "pd_camera_snr", "pd_physical")


def eo_pfa() -> float:
    """The EO sensor's default per-pixel false-alarm probability (``eo.pfa`` of defaults/parameters.toml)."""

    return float(load_parameters()["eo"]["pfa"]["value"])


def frame_pd(johnson_cycles, snr, pfa: float, task: str = "detection") -> dict[str, np.ndarray]:
    """Physics Pd of each frame's drone (module docstring).

    Parameters
    ----------
    johnson_cycles : array_like
        Line pairs across d_crit of each drone (the label's ``johnson_cycles``) [-], >= 0.
    snr : array_like
        Its blob SNR (the label's ``snr``) [-], >= 0.
    pfa : float
        Per-pixel probability of false alarm of the SNR threshold, 0 < Pfa < 1.
    task : str
        The Johnson task whose line pairs are N50 (Table 20).

    Returns
    -------
    dict
        :data:`COLUMNS` -> ndarray, one value per frame.
    """
    x = np.asarray(johnson_cycles, dtype=float) / line_pairs(task)
    johnson = ttpf_probability(x, "johnson")
    camera = gaussian_pd(snr, pfa)
    return {
        "pd_ttpf_johnson": johnson,
        "pd_ttpf_ttp": ttpf_probability(x, "ttp"),
        "pd_camera_snr": camera,
        "pd_physical": johnson * camera,
    }
