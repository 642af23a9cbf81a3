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


def pd_plot(
    path,
    title: str,
    range_m,
    curves: dict,
    *,
    fused=None,
    markers=None,
    cumulative=None,
    false_alarms=None,
):
    """Write probability of detection against range, one line per sensor and the fused one, as PNG.

    Parameters
    ----------
    path : str or Path
        Output PNG.
    title : str
    range_m : array_like
        Range grid [m] (log axis).
    curves : dict
        ``{label: Pd}`` on the grid.
    fused : (str, array_like), optional
        Label and fused Pd (thick black line).
    markers : dict, optional
        ``{label: (range_m, pd)}``: each sensor's deterministic range and the Pd there.
    cumulative : dict, optional
        ``{label: cumulative Pd}`` along an approach, drawn in a second panel.
    false_alarms : dict, optional
        ``{label: cumulative probability}`` of noise crossings alone along the approach, dotted in
        the second panel in the sensor's colour and labelled: the plateau they put under that
        sensor's cumulative Pd.
    """
    plt = _pyplot()
    panels = 2 if cumulative else 1
    fig, axes = plt.subplots(panels, 1, figsize=(8.0, 4.2 * panels), dpi=110, sharex=True, squeeze=False)
    ax = axes[0, 0]
    colours = {}
    for label, pd in curves.items():
        (line,) = ax.plot(range_m, pd, lw=1.6, label=label)
        colours[label] = line.get_color()
    fused_label, fused_pd = fused if fused is not None else ("", None)
    if fused is not None:
        ax.plot(range_m, fused_pd, color="k", lw=2.2, ls="--", label=fused_label)
    for label, (r, p) in (markers or {}).items():
        if r and p is not None and r > 0:
            ax.plot([r], [p], marker="o", ms=6, mfc="white", color=colours.get(label, "k"))
    ax.set_xscale("log")
    ax.set_ylim(-0.02, 1.02)
    ax.set_ylabel("probability of detection per look")
    ax.set_title(f"{title}\n(circles: each sensor's deterministic range and the Pd it implies)", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="lower left")
    if cumulative:
        ax2 = axes[1, 0]
        for label, c in cumulative.items():
            ax2.plot(
                range_m,
                c,
                lw=2.6 if label == fused_label else 1.6,
                color="k" if label == fused_label else colours.get(label),
                label=label,
            )
        for label, c in (false_alarms or {}).items():
            ax2.plot(range_m, c, lw=1.2, ls=":", color=colours.get(label), label=f"{label}: false alarms alone")
        ax2.set_ylim(-0.02, 1.02)
        ax2.set_ylabel("cumulative Pd along the approach")
        ax2.grid(alpha=0.3, which="both")
        ax2.legend(fontsize=8, loc="lower left")
    axes[-1, 0].set_xlabel("slant range [m]")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)
    return Path(path)
