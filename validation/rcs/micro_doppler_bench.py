"""Benchmark of the rotor micro-Doppler: PO slow-time samples per second (``csuas bench``)."""

from __future__ import annotations

import time

import numpy as np


def bench_micro_doppler(samples: int = 2000) -> list[dict]:
    """Slow-time samples x blade facets per second of :func:`csuas.render.rcs.micro_doppler.rotor_field`.

    The DJI Mini 4 Pro's four two-blade rotors at 10 GHz, 6000 rpm, PRF 20 kHz, 10 deg elevation.

    Returns
    -------
    list of dict
        One row: ``samples``, ``facets`` (all rotors), ``time_s``, ``facet_samples_per_s``.
    """
    from csuas.render.rcs.micro_doppler import drone_rotors, rotor_field

    rotors, _ = drone_rotors("dji_mini_4_pro")
    times = np.arange(samples) / 20_000.0
    start = time.perf_counter()
    for rotor in rotors:
        rotor_field(rotor, 100.0, times, 10.0, 0.0, 10.0)
    elapsed = time.perf_counter() - start
    facets = sum(len(r.faces) for r in rotors)
    return [
        {"samples": samples, "facets": facets, "time_s": elapsed, "facet_samples_per_s": samples * facets / elapsed}
    ]
