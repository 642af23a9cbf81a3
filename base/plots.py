"""Figures written by csuas (matplotlib, Agg back-end, atomic PNG output)."""

from __future__ import annotations

from pathlib import Path

from csuas.base.fileio import atomic_path


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def tornado_plot(path, title: str, baseline_m: float, bars, *, log_scale: bool = False) -> Path:
    """Write a tornado plot (Section 4.9, Figures 3-5) as PNG.

    Parameters
    ----------
    path : str or Path
        Output PNG.
    title : str
    baseline_m : float
        Range with every parameter at its default [m] (dashed line).
    bars : list of csuas.core.sensitivity.TornadoBar
        Sorted by decreasing span (largest on top).
    log_scale : bool
        Logarithmic range axis (useful when a parameter spans decades).
    """
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 0.6 * len(bars) + 1.6), dpi=110)
    for i, bar in enumerate(reversed(bars)):
        for value, r, colour in (
            (bar.low_value, bar.range_at_low_m, "#4c72b0"),
            (bar.high_value, bar.range_at_high_m, "#dd8452"),
        ):
            ax.barh(i, r - baseline_m, left=baseline_m, color=colour, height=0.6)
            ax.annotate(
                f"{value:g}",
                (r, i),
                xytext=(3 if r >= baseline_m else -3, 0),
                textcoords="offset points",
                va="center",
                ha="left" if r >= baseline_m else "right",
                fontsize=8,
            )
    ax.set_yticks(range(len(bars)), [b.parameter for b in reversed(bars)])
    ax.axvline(baseline_m, color="k", ls="--", lw=1)
    ax.set_xlabel("predicted range R* [m]  (blue: low value, orange: high value)")
    ax.set_title(f"{title}\nbaseline R* = {baseline_m:.1f} m", fontsize=10)
    if log_scale:
        ax.set_xscale("log")
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)
    return Path(path)
