"""Plots of the report as PNG bytes (matplotlib, Agg back-end), ready to embed in HTML.

Every function returns a :class:`~csuas.validation.report.registry.Figure`;
nothing is written to disk here (the runner writes what it embeds).
"""

from __future__ import annotations

import io
import math
import tempfile
from dataclasses import dataclass
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


@dataclass(frozen=True)
class PlotAxes:
    """The axes of a plot: their labels (with units) and scales.

    Attributes
    ----------
    x_label, y_label : str
        Axis labels, units in brackets.
    log_x, log_y : bool
        Logarithmic scales.
    """

    x_label: str
    y_label: str
    log_x: bool = False
    log_y: bool = False


def curves(name: str, title: str, *, axes: PlotAxes, lines=(), points=(), hlines=(), caption: str = "") -> Figure:
    """Analytic curves and simulated points with error bars.

    Parameters
    ----------
    axes : PlotAxes
        Labels and scales.
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
    if axes.log_x:
        ax.set_xscale("log")
    if axes.log_y:
        ax.set_yscale("log")
    ax.set_xlabel(axes.x_label)
    ax.set_ylabel(axes.y_label)
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    return Figure(name, title, _png(fig), caption)


def _plain_log_ticks(axis, values=None) -> None:
    """Log-axis ticks labelled as plain numbers (``0.002``, ``50``), no minor labels.

    1, 2 and 5 per decade over up to two decades of ``values`` (or of the axis' limits when None),
    one per decade beyond, so that the labels never run into each other.
    """
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    low, high = (np.min(values), np.max(values)) if values is not None else sorted(axis.get_view_interval())
    wide = high / max(low, 1e-300) > 1e2
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


#: Where a point's label may go, tried in turn: offset [pt], horizontal and vertical alignment.
_LABEL_SPOTS = (
    ((5, 4), "left", "bottom"), ((5, -4), "left", "top"), ((-5, 4), "right", "bottom"),
    ((-5, -4), "right", "top"), ((0, 8), "center", "bottom"), ((0, -8), "center", "top"),
    ((9, 0), "left", "center"), ((-9, 0), "right", "center"),
)  # fmt: skip

#: Clearance kept between a label and any other marked point [display px].
_MARK_RADIUS_PX = 5.0


def _label_points(ax, labels, marks, fontsize: float = 8.0) -> int:
    """Write each ``(text, x, y, colour)`` label beside its data point where it covers nothing else.

    Tries the positions of ``_LABEL_SPOTS`` in turn and keeps the first whose box lies inside the
    axes and clear of the labels already placed, the legend (frozen where it stands) and every other
    point of ``marks`` (data coordinates); a label without a clear position is left out, never
    printed over another. Call it on the final layout (after ``tight_layout``).

    Returns
    -------
    int
        The number of labels left out.
    """
    renderer = ax.figure.canvas.get_renderer()
    inside = ax.get_window_extent(renderer)
    taken = []
    legend = ax.get_legend()
    if legend is not None:
        box = legend.get_window_extent(renderer)
        legend.set_loc(tuple(ax.transAxes.inverted().transform((box.x0, box.y0))))  # 'best' stays put
        taken.append(box)
    dots = ax.transData.transform(np.asarray(marks, float).reshape(-1, 2))
    left_out = 0
    for text, px, py, colour in labels:
        own = ax.transData.transform((px, py))
        others = dots[np.hypot(*(dots - own).T) > 1.0]
        for (dx, dy), ha, va in _LABEL_SPOTS:
            note = ax.annotate(
                text, (px, py), xytext=(dx, dy), textcoords="offset points", ha=ha, va=va, fontsize=fontsize,
                color=colour,
            )  # fmt: skip
            box = note.get_window_extent(renderer).expanded(1.1, 1.2)
            r = _MARK_RADIUS_PX
            clear = (
                inside.contains(box.x0, box.y0)
                and inside.contains(box.x1, box.y1)
                and not any(box.overlaps(b) for b in taken)
                and not any(box.x0 - r < u < box.x1 + r and box.y0 - r < v < box.y1 + r for u, v in others)
            )
            if clear:
                taken.append(box)
                break
            note.remove()
        else:
            left_out += 1
    return left_out


@dataclass(frozen=True)
class AccuracyColumns:
    """Which columns of an accuracy sweep's rows :func:`accuracy_vs_time` plots, and their labels.

    Attributes
    ----------
    knob : str
        The accuracy knob (rays per wavelength, samples per pixel, grid), one value per row.
    error_key, error_label : str
        The measured error against the reference, and its axis label.
    stderr_key : str or None
        The run's own error estimate (standard error), drawn beside the measured |error| (a single
        Monte Carlo run's error scatters about it); None: none drawn.
    stderr_label : str
        Its legend label.
    time_key : str
        The wall time [s].
    """

    knob: str
    error_key: str
    error_label: str = "error"
    stderr_key: str | None = None
    stderr_label: str = "standard error (estimate)"
    time_key: str = "time_s"


def accuracy_vs_time(
    name: str, title: str, rows, columns: AccuracyColumns, *, caption: str = "", presets: dict | None = None
) -> Figure:
    """Accuracy against the knob (left) and against wall time (right), log-log.

    Both the measured error and the run's own error estimate are drawn; the quality presets are
    marked by name; the time axis always shows at least a decade, and says so when the measured
    times span less (a per-call floor, e.g. Sionna's, dominates the cost).

    Parameters
    ----------
    rows : list of dict
        One per knob value, with the columns' ``knob``, ``error_key``, ``time_key`` and optionally ``stderr_key``.
    columns : AccuracyColumns
        Which columns to plot, and their labels.
    presets : dict, optional
        Preset name -> knob value (``{"draft": 4, "standard": 10, ...}``), marked where a row has it.
    """
    plt = _pyplot()
    knob, error_key, time_key = columns.knob, columns.error_key, columns.time_key
    error_label, stderr_key, stderr_label = columns.error_label, columns.stderr_key, columns.stderr_label
    k = [r[knob] for r in rows]
    numeric = all(isinstance(v, (int, float)) for v in k)
    x = np.array(k, float) if numeric else np.arange(len(k), dtype=float)
    t = np.array([max(float(r[time_key]), 1e-6) for r in rows])
    e = np.array([max(abs(float(r[error_key])), 1e-9) for r in rows])
    fig, (left, right) = plt.subplots(1, 2, figsize=(9.6, 3.8))
    if numeric:
        left.loglog(x, e, "o-", color="C0", label="measured |error|")
        _plain_log_ticks(left.xaxis, x)
    else:
        left.semilogy(x, e, "o-", color="C0", label="measured |error|")
        left.set_xticks(x, [str(v) for v in k], rotation=30, fontsize=8)
    if stderr_key is not None:
        se = np.array([max(abs(float(r[stderr_key])), 1e-12) for r in rows])
        left.plot(x, se, "s--", color="C1", label=stderr_label)
        right.loglog(t, se, "s--", color="C1", label=stderr_label)
    right.loglog(t, e, "o-", color="C0", label="measured |error|")
    ringed = [(preset, i) for preset, value in (presets or {}).items() for i, v in enumerate(k) if v == value]
    for _, i in ringed:
        for ax, px in ((left, x[i]), (right, t[i])):
            ax.plot(px, e[i], "o", ms=13, mfc="none", mec="C3", mew=1.5)
    span = _at_least_a_decade(right, t)
    _plain_log_ticks(right.xaxis)
    notes = [f"measured times span only x{span:.2g}"] if span < 10.0 else []
    left.set_xlabel(knob + ("  (red rings: quality presets)" if presets else ""))
    right.set_xlabel("wall time [s]  (labels: " + knob + ")")
    shown = np.concatenate([e, se]) if stderr_key is not None else e
    for ax in (left, right):
        _plain_log_ticks(ax.yaxis, shown)
        ax.set_ylabel(error_label)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    # labels last, on the final layout: each beside its point where it covers no other label, point or legend
    marks = {"left": [(px, y) for px, y in zip(x, e)], "right": [(xt, y) for xt, y in zip(t, e)]}
    if stderr_key is not None:
        marks["left"] += list(zip(x, se))
        marks["right"] += list(zip(t, se))
    left_out = _label_points(left, [(preset, x[i], e[i], "C3") for preset, i in ringed], marks["left"])
    preset_at = {i: preset for preset, i in ringed}
    knob_labels = [
        (f"{v:g}" if numeric else str(v)) + (f" ({preset_at[i]})" if i in preset_at else "") for i, v in enumerate(k)
    ]
    order = sorted(range(len(k)), key=lambda i: i not in preset_at)  # presets' labels first
    right_labels = [(knob_labels[i], t[i], e[i], "C3" if i in preset_at else "black") for i in order]
    left_out += _label_points(right, right_labels, marks["right"])
    notes += [f"{left_out} crowded label(s) left out"] if left_out else []
    if notes:  # under the axis, where they cover nothing (the saved bounding box grows to hold them)
        right.set_xlabel(right.get_xlabel() + "\n" + "; ".join(notes))
    return Figure(name, title, _png(fig), caption, wide=True)


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
