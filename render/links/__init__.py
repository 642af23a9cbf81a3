"""Sionna RT links (docs/simulation.md): RF path gain drone -> RF sensor and the monostatic radar link.

Modules
-------
sionna_backend
    Imports Sionna RT on the Mitsuba variant csuas selects (CUDA first, LLVM fallback).
budget
    Sample budgets (rays per source, maximum depth) with draft/standard/reference presets.
scene
    Programmatic scenes: free space, or a graded flat ground of an ITU-R P.2040 material.
paths
    Coherent sum of Sionna's paths with the phase from float64 path lengths.
rf
    :func:`rf_path_gain` (PathSolver), compared with Friis (Eq. 54) and the two-ray model.
radar
    :func:`radar_link_gain` (RCSSolver, the drone as a sensing target), compared with Eq. 68.
rcs_table
    sigma(azimuth, elevation) tables and callables for the sensing target.
two_ray
    NumPy closed forms: Fresnel coefficients, two-ray and four-path (radar) models.
terrain_map
    :func:`terrain_radio_map` (RadioMapSolver on a mesh of a DEM, path gain at a flight level above
    it, with an error bound from rotated replicas) and :func:`radio_map_budget` (rays for a bound).

The accuracy-against-time rows and the benchmark of the chosen budget against Sionna's defaults are
validation: :mod:`csuas.validation.links.accuracy` and :mod:`csuas.validation.links.bench`.

Importing this package imports neither Mitsuba nor Sionna; the functions do, lazily.
"""
