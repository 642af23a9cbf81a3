"""Plots of the report as PNG bytes (matplotlib, Agg back-end), ready to embed in HTML.

Every function returns a :class:`~csuas.validation.report.registry.Figure`;
nothing is written to disk here (the runner writes what it embeds).
"""

from __future__ import annotations

import io
import math
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


def curves(
    name: str,
    title: str,
    *,
    x_label: str,
    y_label: str,
    lines=(),
    points=(),
    hlines=(),
    log_x: bool = False,
    log_y: bool = False,
    caption: str = "",
) -> Figure:
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


def _plain_log_ticks(axis, values=None) -> None:
    """Log-axis ticks labelled as plain numbers (``0.002``, ``50``), no minor labels.

    1, 2 and 5 per decade over up to three decades of ``values``; one per decade beyond.
    """
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    wide = values is not None and np.max(values) / max(np.min(values), 1e-300) > 1e3
    axis.set_major_locator(LogLocator(base=10.0, subs=(1.0,) if wide else (1.0, 2.0, 5.0)))
    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(NullFormatter())


def _at_least_a_decade(ax, t: np.ndarray) -> float:
    """Widen the time axis to one decade around the measured times; return their span (max / min)."""
    span = float(t.max() / t.min())
    if span < 10.0:
        centre = math.sqrt(float(t.max() * t.min()))
        ax.set_xlim(centre / math.sqrt(10.0) / 1.2, centre * math.sqrt(10.0) * 1.2)
    return span


def accuracy_vs_time(
    name: str,
    title: str,
    rows,
    *,
    knob: str,
    error_key: str,
    time_key: str = "time_s",
    error_label: str = "error",
    stderr_key: str | None = None,
    stderr_label: str = "standard error (estimate)",
    caption: str = "",
    presets: dict | None = None,
) -> Figure:
    """Accuracy against the knob (left) and against wall time (right), log-log.

    Both the measured error and the run's own error estimate are drawn; the quality presets are
    marked by name; the time axis always shows at least a decade, and says so when the measured
    times span less (a per-call floor, e.g. Sionna's, dominates the cost).

    Parameters
    ----------
    rows : list of dict
        One per knob value, with ``knob``, ``error_key``, ``time_key`` and optionally ``stderr_key``.
    stderr_key : str, optional
        The run's own error estimate (standard error), drawn beside the
        measured |error| (a single Monte Carlo run's error scatters about it).
    presets : dict, optional
        Preset name -> knob value (``{"draft": 4, "standard": 10, ...}``), marked where a row has it.
    """
    plt = _pyplot()
    k = [r[knob] for r in rows]
    numeric = all(isinstance(v, (int, float)) for v in k)
    x = np.array(k, float) if numeric else np.arange(len(k), dtype=float)
    t = np.array([max(float(r[time_key]), 1e-6) for r in rows])
    e = np.array([max(abs(float(r[error_key])), 1e-9) for r in rows])
    fig, (left, right) = plt.subplots(1, 2, figsize=(9.6, 3.8))
    if numeric:
        left.loglog(x, e, "o-", color="C0", label="measured |error|")
        _plain_log_ticks(left.xaxis)
    else:
        left.semilogy(x, e, "o-", color="C0", label="measured |error|")
        left.set_xticks(x, [str(v) for v in k], rotation=30, fontsize=7)
    if stderr_key is not None:
        se = np.array([max(abs(float(r[stderr_key])), 1e-12) for r in rows])
        left.plot(x, se, "s--", color="C1", label=stderr_label)
        right.loglog(t, se, "s--", color="C1", label=stderr_label)
    right.loglog(t, e, "o-", color="C0", label="measured |error|")
    for label, xt, y in zip(k, t, e):
        right.annotate(
            f"{label:g}" if numeric else str(label), (xt, y), xytext=(4, 4), textcoords="offset points", fontsize=8
        )
    for preset, value in (presets or {}).items():
        hits = [i for i, v in enumerate(k) if v == value]
        for i in hits:
            for ax, px in ((left, x[i]), (right, t[i])):
                ax.plot(px, e[i], "o", ms=13, mfc="none", mec="C3", mew=1.5)
                ax.annotate(preset, (px, e[i]), xytext=(-6, -14), textcoords="offset points", fontsize=8, color="C3")
    span = _at_least_a_decade(right, t)
    _plain_log_ticks(right.xaxis)
    if span < 10.0:
        right.text(
            0.02, 0.02, f"measured times span only x{span:.2g}", transform=right.transAxes, fontsize=7, color="0.3"
        )
    left.set_xlabel(knob + ("  (red rings: quality presets)" if presets else ""))
    right.set_xlabel("wall time [s]  (labels: " + knob + ")")
    shown = np.concatenate([e, se]) if stderr_key is not None else e
    for ax in (left, right):
        _plain_log_ticks(ax.yaxis, shown)
        ax.set_ylabel(error_label)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
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
