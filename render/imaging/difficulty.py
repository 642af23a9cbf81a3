"""How hard an object of a ``csuas dataset`` frame is to see: the background class under its box and its local
contrast against the background around it (docs/datasets.md, annotation keys ``background_class`` and
``local_contrast``), so that results can be binned by difficulty.

Local contrast, on the frame's DN as written (after the whole chain):

    C_local = (mean DN over the object's mask - mean DN over the ring) / sigma_ring

with the mask the label's pixels (coverage > 0), the ring the pixels within ``RING_PX`` of the label's box
and outside it (clipped to the frame), and sigma_ring the standard deviation of the ring's DN (ddof 0). It is
the object's mean signal over its local background in units of the local fluctuation: the sensor's noise
on a uniform sky, noise plus texture (cloud edges, the skyline, clutter) where the background varies.
Its sign says brighter (+) or darker (-) than the surroundings. A ring of constant DN (a noiseless chain)
gives sigma_ring = 0 and C_local = +-inf (JSON null), or 0 when the means are equal.

Background class of the box: ``sky`` or ``cloud`` (above the horizon, a cloud where the seeded cloud opacity
exceeds one half over most of the box's sky pixels), ``terrain`` (below the horizon), ``skyline`` (the box
holds pixels above and below the horizon), ``uniform`` (a Lambertian background of a given reflectance, or a
thermal frame's graybody without a sky temperature); the render's uniform horizon sky (``background = "sky"``)
is ``sky``. The horizon is the frame's own (:func:`csuas.render.imaging.background.view_rays`, the rays of
the box's pixels only).
"""

from __future__ import annotations

import math

import numpy as np

#: Width of the ring of local background around an object's box [px].
RING_PX = 8
#: Share of the box's sky pixels under cloud opacity > 0.5 above which its class is ``cloud``.
CLOUD_SHARE = 0.5


def local_contrast(dn: np.ndarray, mask: np.ndarray, bbox) -> dict:
    """C_local of an object (module docstring) with the means and the ring's sigma it is made of.

    Parameters
    ----------
    dn : ndarray (H, W)
        The frame's DN.
    mask : ndarray (H, W) of bool
        The object's pixels.
    bbox : [x, y, w, h]
        The object's box [px].

    Returns
    -------
    dict
        ``local_contrast`` (None where sigma_ring = 0 and the means differ), ``target_mean_dn``,
        ``ring_mean_dn``, ``ring_sigma_dn``, ``ring_px`` (pixels in the ring).
    """
    x, y, w, h = (int(v) for v in bbox)
    n_v, n_h = dn.shape
    x0, y0, x1, y1 = max(x - RING_PX, 0), max(y - RING_PX, 0), min(x + w + RING_PX, n_h), min(y + h + RING_PX, n_v)
    values = dn[y0:y1, x0:x1].astype(float)  # the box and its ring only
    outer = np.ones(values.shape, bool)
    outer[y - y0 : y - y0 + h, x - x0 : x - x0 + w] = False
    target, ring = float(values[mask[y0:y1, x0:x1]].mean()), values[outer]
    ring_mean, sigma = float(ring.mean()), float(ring.std())
    difference = target - ring_mean
    contrast = difference / sigma if sigma > 0 else (0.0 if difference == 0 else None)
    return {
        "local_contrast": contrast,
        "target_mean_dn": target,
        "ring_mean_dn": ring_mean,
        "ring_sigma_dn": sigma,
        "ring_px": int(ring.size),
    }


def background_class(bbox, horizon: dict | None) -> str:
    """The class of the background under a box (module docstring).

    ``horizon``: None for a uniform background, or ``kind`` ("sky" for the render's uniform sky, else the
    frame's horizon), ``frame`` (n_h, n_v), ``ifov_rad``, ``azimuth_deg``, ``elevation_deg``,
    ``target_offset_px`` (the drone's view, as the background was built), ``clouds`` (the cloud opacity frame
    or None).
    """
    if horizon is None:
        return "uniform"
    if horizon["kind"] == "sky":
        return "sky"
    if horizon["kind"] == "classes":
        return _class_of_box(horizon["codes"], bbox)
    from csuas.render.imaging.background import view_rays

    x, y, w, h = (int(v) for v in bbox)
    n_h, n_v = horizon["frame"]
    ox, oy = horizon["target_offset_px"]
    # a sub-frame of the box's pixels: its centre offset chosen so that its rays are those of the full frame's pixels
    offset = (n_h // 2 + ox - x - w // 2, n_v // 2 + oy - y - h // 2)
    rays = view_rays(w, h, horizon["ifov_rad"], horizon["azimuth_deg"], horizon["elevation_deg"], offset)
    above = rays[..., 2] > 0.0
    if above.all():
        clouds = horizon.get("clouds")
        if clouds is not None and float(np.mean(clouds[y : y + h, x : x + w] > 0.5)) > CLOUD_SHARE:
            return "cloud"
        return "sky"
    return "terrain" if not above.any() else "skyline"


#: Share of a box's pixels a class needs to count in it (a box with sky and ground classes both counting is
#: ``skyline``).
COUNTING_SHARE = 0.1


def _class_of_box(codes: np.ndarray, bbox) -> str:
    """The class under a box from a clutter class map (:data:`csuas.render.imaging.clutter.CLASSES`): ``skyline``
    where sky or cloud and a ground class each cover ``COUNTING_SHARE`` of it, else the commonest class."""
    from csuas.render.imaging.clutter import CLASSES

    x, y, w, h = (int(v) for v in bbox)
    counts = np.bincount(codes[y : y + h, x : x + w].ravel(), minlength=len(CLASSES))[: len(CLASSES)]
    shares = counts / max(counts.sum(), 1)
    airborne = shares[CLASSES.index("sky")] + shares[CLASSES.index("cloud")]
    if airborne >= COUNTING_SHARE and 1.0 - airborne >= COUNTING_SHARE:
        return "skyline"
    return CLASSES[int(np.argmax(counts))]


def annotation_difficulty(dn: np.ndarray, mask: np.ndarray, bbox, horizon: dict | None) -> dict:
    """``background_class`` and the local contrast figures of one labelled object, for its annotation."""
    out = {"background_class": background_class(bbox, horizon), **local_contrast(dn, mask, bbox)}
    value = out["local_contrast"]
    if value is not None and not math.isfinite(value):
        out["local_contrast"] = None
    return out
