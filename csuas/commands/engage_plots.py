"""The figures of ``csuas engage``: the map of truth, tracks and false tracks, and the warning curve."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from csuas.base.fileio import atomic_path

#: Colour of each track cause on the map and in the legends.
CAUSE_COLOURS = {"drone": "#1f5fbf", "birds": "#e07b00", "noise": "#7a7a7a", "clutter": "#9b2fae"}
#: Colour of each sensor's curves.
SENSOR_COLOURS = ("#2a9d3a", "#c0392b", "#8e44ad", "#16a085")
#: Margin of the map around the path, the sensors and the false tracks [m].
MAP_MARGIN_M = 400.0


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _extent(engagement, records) -> tuple[float, float, float, float]:
    """(west, east, south, north) [m] of what the map shows."""
    points = [engagement.path.waypoints[:, :2]]
    points += [np.array([[s.x, s.y] for s in engagement.sensors.values()])]
    west, east, south, north = engagement.bird_box()
    points.append(np.array([[west, south], [east, north]]))
    allxy = np.concatenate(points)
    t = engagement.terrain
    lo, hi = allxy.min(axis=0) - MAP_MARGIN_M, allxy.max(axis=0) + MAP_MARGIN_M
    south_edge, east_edge = t.north_m - t.dem_m.shape[0] * t.cell_m, t.west_m + t.dem_m.shape[1] * t.cell_m
    return max(lo[0], t.west_m), min(hi[0], east_edge), max(lo[1], south_edge), min(hi[1], t.north_m)


def _hillshade(dem: np.ndarray, cell: float) -> np.ndarray:
    """Lambertian hillshade, sun from the north-west 45 degrees up (as ``csuas coverage``), 0..1."""
    gy, gx = np.gradient(dem, cell)
    normal = np.stack([-gx, gy, np.ones_like(dem)])
    normal /= np.linalg.norm(normal, axis=0)
    sun = np.array([-0.5, 0.5, np.sqrt(0.5)])
    return np.clip(np.tensordot(sun, normal, axes=1), 0.0, 1.0)


def _sensor_patches(ax, engagement) -> None:
    """Each sensor: its position and the outline of its field of regard out to its reach (drawn to 3 km at most)."""
    from matplotlib.patches import Wedge

    for colour, (name, s) in zip(SENSOR_COLOURS, engagement.sensors.items()):
        reach = min(s.reach_m, 3000.0)
        start = 90.0 - s.sited.azimuth_deg - s.sited.sector_deg / 2  # compass to mathematical angles
        ax.add_patch(
            Wedge((s.x, s.y), reach, start, start + s.sited.sector_deg, fill=False, ec=colour, lw=1.2, ls="--")
        )
        ax.plot(s.x, s.y, marker="^", ms=11, color=colour, mec="black", zorder=6)
        label = f"{name} ({s.modality}): reach {s.reach_m / 1000:.1f} km"
        east = s.x > np.mean([other.x for other in engagement.sensors.values()])
        ax.annotate(
            label,
            (s.x, s.y),
            xytext=(-12, -22) if east else (12, 10),
            ha="right" if east else "left",
            textcoords="offset points",
            fontsize=9,
            weight="bold",
            color=colour,
            bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": colour, "alpha": 0.85},
            zorder=9,
        )


def map_plot(path: Path, engagement, records: list, metrics: dict) -> Path:
    """Truth, the tracks of the first runs and every run's false tracks where confirmed, over the hillshade."""
    plt = _pyplot()
    t = engagement.terrain
    west, east, south, north = _extent(engagement, records)
    shade = _hillshade(t.dem_m, t.cell_m)
    full = (t.west_m, t.west_m + t.dem_m.shape[1] * t.cell_m, t.north_m - t.dem_m.shape[0] * t.cell_m, t.north_m)
    fig, ax = plt.subplots(figsize=(9.5, 8.5))
    ax.imshow(shade, cmap="gray", vmin=0.0, vmax=1.0, extent=full, origin="upper", zorder=0)
    height = ax.imshow(t.dem_m, cmap="gist_earth", alpha=0.45, extent=full, origin="upper", zorder=0.5)
    fig.colorbar(height, ax=ax, shrink=0.6, pad=0.02, label="terrain height [m]")
    levels = np.linspace(t.dem_m.min(), t.dem_m.max(), 9)
    xs = t.west_m + (np.arange(t.dem_m.shape[1]) + 0.5) * t.cell_m
    ys = t.north_m - (np.arange(t.dem_m.shape[0]) + 0.5) * t.cell_m
    ax.contour(xs, ys, t.dem_m, levels=levels, colors="white", linewidths=0.4, alpha=0.5, zorder=1)
    for record in records:
        for cause in ("birds", "noise", "clutter"):
            pts = np.array([[f["x"], f["y"]] for f in record["false_tracks"] if f["cause"] == cause]).reshape(-1, 2)
            ax.scatter(pts[:, 0], pts[:, 1], s=6, color=CAUSE_COLOURS[cause], alpha=0.35, lw=0, zorder=2)
    for number, record in enumerate(records):
        for track in record.get("tracks", []):
            xy = np.array(track["xy"])
            if track["cause"] == "drone":
                ax.plot(xy[:, 0], xy[:, 1], color=CAUSE_COLOURS["drone"], lw=2.6, alpha=0.9, zorder=6)
            elif number == 0:
                ax.plot(xy[:, 0], xy[:, 1], color=CAUSE_COLOURS[track["cause"]], lw=0.8, alpha=0.6, zorder=3)
    wp = engagement.path.waypoints
    ax.plot(wp[:, 0], wp[:, 1], color="black", lw=1.5, ls=(0, (4, 2)), zorder=7)
    ax.plot(*engagement.protected_xy, marker="*", ms=20, color="gold", mec="black", zorder=8)
    ax.annotate(
        "protected point",
        engagement.protected_xy,
        xytext=(12, -18),
        textcoords="offset points",
        fontsize=9,
        bbox={"boxstyle": "round,pad=0.2", "fc": "white", "alpha": 0.85},
        zorder=9,
    )
    ax.annotate("drone enters", wp[0, :2], xytext=(-10, -16), textcoords="offset points", fontsize=9, ha="right")
    _sensor_patches(ax, engagement)
    from matplotlib.lines import Line2D

    handles = [
        Line2D([], [], color="black", ls=(0, (4, 2)), label="drone's path (truth)"),
        Line2D([], [], color=CAUSE_COLOURS["drone"], lw=2.2, label="drone tracks (runs 1-3)"),
    ] + [
        Line2D(
            [],
            [],
            color=CAUSE_COLOURS[c],
            marker="o",
            ls="-",
            lw=1,
            ms=4,
            label=f"false tracks, {c}: run 1 (lines), confirmed (dots, all runs)",
        )
        for c in ("birds", "noise", "clutter")
    ]
    ax.legend(handles=handles, loc="lower right", fontsize=8, framealpha=0.9)
    ax.set_xlim(west, east)
    ax.set_ylim(south, north)
    ax.set_aspect("equal")
    ax.set_xlabel("easting [m]")
    ax.set_ylabel("northing [m]")
    ax.ticklabel_format(useOffset=False, style="plain")
    w, f = metrics["warning_time_s"], metrics["false_tracks_per_hour"]
    median = "none" if w["median"] is None else f"{w['median']:.0f} s"
    ax.set_title(
        f"Engagement over {len(records)} runs: median warning {median}, "
        f"{f['total']:.0f} false tracks per hour "
        f"(birds {f['by_cause']['birds']:.0f}, noise {f['by_cause']['noise']:.0f}, "
        f"clutter {f['by_cause']['clutter']:.0f})",
        fontsize=10,
    )
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130, format="png")
    plt.close(fig)
    return path


def curve_plot(path: Path, engagement, curves: dict, metrics: dict) -> Path:
    """Cumulative probability of a confirmed drone track against the distance still to fly, each sensor's beside."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9.5, 5.8))
    d = np.array(curves["distance_m"]) / 1000
    p, e = np.array(curves["confirmed_track"]), np.array(curves["confirmed_track_stderr"])
    ax.fill_between(
        d, np.clip(p - 2 * e, 0, 1), np.clip(p + 2 * e, 0, 1), color=CAUSE_COLOURS["drone"], alpha=0.2, lw=0
    )
    ax.plot(
        d,
        p,
        color=CAUSE_COLOURS["drone"],
        lw=2.6,
        label="confirmed drone track, all sensors through the tracker (Monte Carlo, ±2 s.e.)",
    )
    m, n = engagement.confirm
    for colour, (name, c) in zip(SENSOR_COLOURS, curves["sensors"].items()):
        dist = np.array(c["distance_m"]) / 1000
        ax.step(
            dist,
            c["cumulative_pd"],
            where="post",
            color=colour,
            lw=1.4,
            ls="--",
            label=f"{name}: at least one detection (cumulative Pd of its looks at the drone)",
        )
        if c["m_of_n"] is not None:
            label = f"{name} alone: {m} of {n} looks (exact, independent looks)"
            ax.step(dist, c["m_of_n"], where="post", color=colour, lw=1.4, ls=":", label=label)
    ax.set_xlim(d.max(), 0)
    ax.set_ylim(0, 1.02)
    ax.set_xlabel("distance the drone still has to fly to the protected point [km] (it approaches: left to right)")
    ax.set_ylabel("probability by then")
    ax.grid(alpha=0.3)
    w = metrics["warning_time_s"]
    if w["median"] is not None:
        ax.set_title(
            f"Warning: median {w['median']:.0f} s (p10 {w['p10']:.0f} s, p90 {w['p90']:.0f} s); never confirmed "
            f"in {100 * metrics['first_track_time_s']['never_fraction']:.0f} % of runs",
            fontsize=10,
        )
    ax.legend(loc="upper left", fontsize=8, framealpha=0.9)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130, format="png")
    plt.close(fig)
    return path
