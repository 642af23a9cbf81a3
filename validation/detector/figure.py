"""The detector loop's figure: the learned detector's AP50 and Pd against pixels on target, beside the
physics Pd of the same frames (matplotlib, Agg, atomic PNG)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from csuas.base.fileio import atomic_path

#: Physics columns drawn, with their legend, colour and line style (the product dotted over the TTPF it follows).
PHYSICS_LINES = (
    ("pd_ttpf_johnson", "physics: TTPF of the Johnson cycles (Johnson exponent)", "#4c72b0", "-"),
    ("pd_ttpf_ttp", "physics: TTPF, TTP exponent", "#8172b2", "-"),
    ("pd_camera_snr", "physics: camera blob SNR at the Pfa", "#55a868", "-"),
    ("pd_physical", "physics: TTPF x camera SNR (csuas pd, physical)", "#222222", ":"),
)
#: Where a frame with no pixel on target is drawn on the log axis.
FLOOR_PX = 0.01


def _x(value) -> float:
    return max(float(value), FLOOR_PX)


def loop_figure(path, result: dict, title: str) -> Path:
    """Write the figure of :func:`csuas.validation.detector.evaluation.evaluate`'s ``result`` as PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8.0, 5.0), dpi=110)
    frames = [f for f in result["frames"] if f["pixels_on_target"] is not None]
    px = np.array([_x(f["pixels_on_target"]) for f in frames])
    rows = [r for r in result["by_pixels_on_target"] if r["targets"]]
    centre = np.array([_x(r["pixels_on_target_mean"]) for r in rows])
    for key, label, colour, style in PHYSICS_LINES:
        ax.scatter(px, [f[key] for f in frames], s=6, color=colour, alpha=0.25, linewidths=0)
        errors = [r[f"{key}_stderr"] or 0.0 for r in rows]
        ax.errorbar(centre, [r[key] for r in rows], yerr=errors, color=colour, ls=style, lw=1.6, capsize=2, label=label)
    learned = (
        ("ap50", "learned detector: AP50 (bootstrap s.e.)", "s", "#c44e52"),
        (
            "pd_learned",
            f"learned detector: Pd at {result['false_alarms_per_frame']:.2g} false alarms a frame",
            "o",
            "#dd8452",
        ),
    )
    for key, label, marker, colour in learned:
        ax.errorbar(
            centre,
            [r[key] for r in rows],
            yerr=[r[f"{key}_stderr"] or 0.0 for r in rows],
            color=colour,
            marker=marker,
            ls="--",
            lw=1.4,
            ms=6,
            capsize=3,
            label=label,
        )
    for r, x in zip(rows, centre):
        ax.annotate(f"{r['targets']}", (x, 1.02), ha="center", fontsize=7, color="#666666")
    ax.set_xscale("log")
    ax.set_ylim(-0.03, 1.08)
    ax.set_xlabel("pixels on target (bins: mean of their frames; dots: frames; grey: drones per bin)")
    ax.set_ylabel("probability of detection / average precision")
    ax.set_title(title, fontsize=9)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2)  # below: clear of the curves
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", bbox_inches="tight")
    plt.close(fig)
    return Path(path)
