"""Full-wave references of a drone's parts for PO's model-error bound: finite PEC cylinders and the arm with its motor.

Each case is solved by the EFIE (:func:`csuas.validation.rcs.fullwave.monostatic_rcs_efie`, bempp-cl) on
two meshes, a fine one (edges about ``h``) and a coarse one (about 1.4 ``h``); Richardson's extrapolation
of the two (order 2, the ratio of their mean edges) is the reference and its correction the reference's
own error (:func:`csuas.validation.rcs.fullwave.richardson`, measured h^2 on the sphere); in a null that
the two meshes place apart the extrapolation can fall below zero, and that entry has no reference (its
error is infinite, the fine mesh's value is kept). SBR-PO
(:func:`csuas.render.rcs.solver.compute_rcs`, PEC, standard quality) runs on the fine mesh, so both see the
same faceted geometry; its bound against the exact answer (discretisation, PO's model error, bounce
truncation) is recorded beside its error against the reference.

Cases (:data:`PART_CASES`): three closed PEC cylinders at 10 GHz (radius x length 0.25 x 2, 0.5 x 1 and
0.35 x 1.5 wavelengths, axis z, elevations 0-90 deg: broadside to end-on), and the DJI Mini 4 Pro's front
arm with its motor (:func:`csuas.validation.rcs.fullwave.arm_motor_mesh`, dimensions of
``drone_models/presets.py``) at 2.4, 5.8 and 10 GHz from eight aspects. The EFIE is a PEC solver: the arm, carbon-fibre
composite in the drone's RF model (``drone_models/multirotor.py`` and ``materials.py``, isotropic 1e4 S/m:
skin depth 0.10 mm at 2.4 GHz against its 8 mm thickness, surface resistance 0.97 ohm, a normal-incidence
reflection loss of 0.05 dB), and the aluminium motor (3.5e7 S/m) are both solved as PEC.

Recorded results: :mod:`csuas.validation.rcs.part_records`.
"""

from __future__ import annotations

import time

import numpy as np

from . import fullwave as fw

#: Elevations [deg] of the cylinder cases (axis z: 0 is broadside, 90 end-on); azimuth 7 deg keeps the
#: radar off the facets' symmetry planes.
CYLINDER_ASPECTS = tuple((7.0, el) for el in (0.0, 10.0, 20.0, 30.0, 45.0, 60.0, 75.0, 90.0))

#: Aspects (azimuth, elevation) [deg] of the arm with its motor (arm along -x from the motor, motor axis z):
#: broadside to the arm's side and 20 deg above it, from above, end-on from the motor and from the root,
#: and three oblique aspects.
ARM_ASPECTS = (
    (90.0, 0.0),
    (90.0, 20.0),
    (0.0, 90.0),
    (0.0, 0.0),
    (180.0, 0.0),
    (45.0, 30.0),
    (135.0, 10.0),
    (270.0, 45.0),
)

#: Fine mesh edge of the arm [m]: at most lambda / 10 and at most 4 mm (the arm is 8 mm thick).
ARM_MAX_EDGE_M = 0.004

#: Coarse over fine target edge of the Richardson pair.
COARSE_RATIO = 1.4

#: The cases: name -> kind, sizes (wavelengths for cylinders), frequency [GHz].
PART_CASES = {
    "cylinder_r0.25_l2": {"kind": "cylinder", "radius_wl": 0.25, "length_wl": 2.0, "frequency_ghz": 10.0},
    "cylinder_r0.5_l1": {"kind": "cylinder", "radius_wl": 0.5, "length_wl": 1.0, "frequency_ghz": 10.0},
    "cylinder_r0.35_l1.5": {"kind": "cylinder", "radius_wl": 0.35, "length_wl": 1.5, "frequency_ghz": 10.0},
    "arm_motor_2.4ghz": {"kind": "arm_motor", "frequency_ghz": 2.4},
    "arm_motor_5.8ghz": {"kind": "arm_motor", "frequency_ghz": 5.8},
    "arm_motor_10ghz": {"kind": "arm_motor", "frequency_ghz": 10.0},
}


def case_mesh(name: str, h_m: float):
    """The mesh [m] of :data:`PART_CASES` ``name`` with edges about ``h_m`` [m]."""
    case = PART_CASES[name]
    if case["kind"] == "cylinder":
        lam = fw.wavelength_m(case["frequency_ghz"])
        return fw.cylinder_mesh(case["radius_wl"] * lam, case["length_wl"] * lam, h_m)
    return fw.arm_motor_mesh(h_m)


def fine_edge_m(name: str) -> float:
    """Fine mesh edge [m] of a case: lambda / 10, and at most :data:`ARM_MAX_EDGE_M` for the arm."""
    case = PART_CASES[name]
    h = fw.mesh_size_m(case["frequency_ghz"], fw.EDGES_PER_WAVELENGTH)
    return min(h, ARM_MAX_EDGE_M) if case["kind"] == "arm_motor" else h


def aspects(name: str) -> tuple:
    """(azimuth, elevation) pairs [deg] of a case."""
    return CYLINDER_ASPECTS if PART_CASES[name]["kind"] == "cylinder" else ARM_ASPECTS


def efie_reference(name: str) -> dict:
    """EFIE of a case on the fine and the coarse mesh, Richardson-extrapolated, per aspect and polarisation.

    Returns a dict with the elements, unknowns and mean edges per wavelength of both meshes, the EFIE RCS
    [dBsm] of the fine mesh and the extrapolation, the reference's error [dB] (Richardson's correction as a
    larger-side relative amplitude, ``fullwave.richardson``), and the times [s].
    """
    case = PART_CASES[name]
    f = case["frequency_ghz"]
    asp = np.asarray(aspects(name), float)
    h = fine_edge_m(name)
    runs, meshes = {}, {}
    for level, edge in (("fine", h), ("coarse", COARSE_RATIO * h)):
        meshes[level] = case_mesh(name, edge)
        mesh = meshes[level]
        runs[level] = fw.monostatic_rcs_efie(mesh.vertices, mesh.faces, f, asp[:, 0], asp[:, 1], "VV")
    ratio = runs["coarse"].details["mean_edge_m"] / runs["fine"].details["mean_edge_m"]
    out = {"efie_dbsm": {}, "reference_dbsm": {}, "reference_error_db": {}}
    for pol in ("VV", "HH"):
        fine, coarse = runs["fine"].rcs_m2(pol), runs["coarse"].rcs_m2(pol)
        pairs = [fw.richardson(a, b, ratio) for a, b in zip(fine, coarse, strict=True)]
        extrapolated = np.array([p[0] for p in pairs])
        correction = np.array([p[1] for p in pairs])
        usable = extrapolated > 0.0  # a null the two meshes place apart extrapolates below zero: no reference
        out["efie_dbsm"][pol] = fw.to_dbsm(fine).tolist()
        out["reference_dbsm"][pol] = fw.to_dbsm(np.where(usable, extrapolated, fine)).tolist()
        with np.errstate(divide="ignore"):
            error = np.where(usable, 10.0 * np.log10(1.0 + correction / np.where(usable, extrapolated, 1.0)), np.inf)
        out["reference_error_db"][pol] = error.tolist()
    out.update(
        {
            "frequency_ghz": f,
            "aspects_deg": asp.tolist(),
            "elements": [runs["fine"].elements, runs["coarse"].elements],
            "unknowns": [runs["fine"].unknowns, runs["coarse"].unknowns],
            "edges_per_wavelength": [runs["fine"].edges_per_wavelength, runs["coarse"].edges_per_wavelength],
            "edge_ratio": ratio,
            "efie_s": runs["fine"].time_s + runs["coarse"].time_s,
        }
    )
    return out, meshes["fine"]


def sbr_on_mesh(mesh, frequency_ghz: float, aspect_pairs, quality: str = "standard") -> dict:
    """SBR-PO (PEC) on a mesh: RCS [dBsm], discretisation, model and total bounds [dB] per aspect and polarisation."""
    from csuas.render.rcs.solver import compute_rcs

    asp = np.asarray(aspect_pairs, float)
    t = time.perf_counter()
    res = compute_rcs(mesh, frequency_ghz, asp[:, 0], asp[:, 1], material="pec", quality=quality)
    out = {"sbr_dbsm": {}, "discretisation_db": {}, "bound_db": {}, "truncation_db": {}}
    for pol in ("VV", "HH"):
        out["sbr_dbsm"][pol] = res.rcs_dbsm(pol)[0, :, 0].tolist()
        out["discretisation_db"][pol] = res.error_estimate_db(pol)[0, :, 0].tolist()
        out["truncation_db"][pol] = res.truncation_db(pol)[0, :, 0].tolist()
        out["bound_db"][pol] = res.bound_db(pol)[0, :, 0].tolist()
    out["model_db_bounding_radius"] = float(res.model_error_db[0])
    out["bounding_radius_m"] = float(np.sqrt(((mesh.vertices - mesh.bounds.mean(axis=0)) ** 2).sum(axis=1)).max())
    out["sbr_s"] = time.perf_counter() - t
    out["quality"] = quality
    return out


def run_case(name: str) -> dict:
    """EFIE reference and SBR-PO of one case (:func:`efie_reference`, :func:`sbr_on_mesh`) in one record."""
    record, mesh = efie_reference(name)
    record.update(sbr_on_mesh(mesh, record["frequency_ghz"], record["aspects_deg"]))
    record["case"] = dict(PART_CASES[name])
    record["error_db"] = {
        pol: (np.abs(np.array(record["sbr_dbsm"][pol]) - np.array(record["reference_dbsm"][pol]))).tolist()
        for pol in ("VV", "HH")
    }
    return record
