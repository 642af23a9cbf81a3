"""Plots of the report as PNG bytes (matplotlib, Agg back-end), ready to embed in HTML.

Every function returns a :class:`~csuas.validation.report.registry.Figure`;
nothing is written to disk here (the runner writes what it embeds).
"""

from __future__ import annotations

import io
import tempfile
from pathlib import Path

import numpy as np

from csuas.validation.report.registry import Figure


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _png(fig) -> bytes:
    plt = _pyplot()
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", dpi=90, bbox_inches="tight")
    plt.close(fig)
    return buffer.getvalue()


def curves(name: str, title: str, *, x_label: str, y_label: str, lines=(), points=(), hlines=(),
           log_x: bool = False, log_y: bool = False, caption: str = "") -> Figure:
    """Analytic curves and simulated points with error bars.

    Parameters
    ----------
    lines : iterable of (label, x, y)
        Analytic curves.
    points : iterable of (label, x, y, yerr or None)
        Simulated values.
    hlines : iterable of (label, y)
        Thresholds.
    """
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for label, x, y in lines:
        ax.plot(x, y, label=label, lw=1.5)
    for label, x, y, err in points:
        ax.errorbar(x, y, yerr=err, fmt="o", ms=5, capsize=3, label=label)
    for label, y in hlines:
        ax.axhline(y, ls="--", color="grey", lw=1, label=label)
    if log_x:
        ax.set_xscale("log")
    if log_y:
        ax.set_yscale("log")
    ax.set_xlabel(x_label)
    ax.set_ylabel(y_label)
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    return Figure(name, title, _png(fig), caption)


def accuracy_vs_time(name: str, title: str, rows, *, knob: str, error_key: str, time_key: str = "time_s",
                     error_label: str = "error", caption: str = "") -> Figure:
    """Error against wall time, one point per knob value, labelled with the value (log-log)."""
    plt = _pyplot()
    t = np.array([max(float(r[time_key]), 1e-6) for r in rows])
    e = np.array([max(abs(float(r[error_key])), 1e-9) for r in rows])
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    ax.loglog(t, e, "o-")
    for r, x, y in zip(rows, t, e):
        ax.annotate(f"{r[knob]:g}" if isinstance(r[knob], (int, float)) else str(r[knob]), (x, y),
                    xytext=(4, 4), textcoords="offset points", fontsize=8)
    ax.set_xlabel("wall time [s]")
    ax.set_ylabel(error_label)
    ax.set_title(f"{title}\n(labels: {knob})", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    return Figure(name, title, _png(fig), caption)


def image(name: str, title: str, rgb: np.ndarray, caption: str = "", min_px: int = 192) -> Figure:
    """An RGB image in [0, 1] (H, W, 3), enlarged by pixel replication to at least ``min_px``."""
    plt = _pyplot()
    factor = max(1, min_px // max(rgb.shape[:2]))
    big = np.repeat(np.repeat(np.clip(rgb, 0.0, 1.0), factor, axis=0), factor, axis=1)
    buffer = io.BytesIO()
    plt.imsave(buffer, big, format="png")
    return Figure(name, title, buffer.getvalue(), caption)


def from_writer(name: str, title: str, write, caption: str = "") -> Figure:
    """A figure from a function that writes a PNG to a path (``write(path)``), e.g. tornado and polar plots."""
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"{name}.png"
        write(path)
        return Figure(name, title, path.read_bytes(), caption)
