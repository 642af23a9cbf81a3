"""Full-wave monostatic RCS of small PEC objects: the EFIE solved by bempp-cl, an oracle for SBR-PO.

The shooting-and-bouncing-rays engine of :mod:`csuas.render.rcs` is a high-frequency
method: it has no edge diffraction, creeping waves or resonances, so it cannot be judged
against itself at the electrical sizes of a small drone's arms and motors (a few
wavelengths). This module solves Maxwell's equations for a perfectly conducting surface
instead: the electric field integral equation (EFIE)

    n x E^s(J) = -n x E^i   on the surface S,
    E^s(J)(x) = i k eta0 int_S [J(y) + grad(div J(y)) / k^2] G(x, y) dS(y),

discretised with Rao-Wilton-Glisson (RWG) trial functions and rotated (SNC) test
functions (a Galerkin method of moments), assembled densely by bempp-cl, solved by GMRES
(or LU), and radiated to the far field in the direction of the radar. An open surface (a
zero-thickness plate) is fine for the EFIE: RWG functions carry the sum of the currents
on its two faces and vanish on its rim.

Normalisation. bempp's Maxwell far-field operator returns the far-field pattern F with
E^s(r d) = F(d) e^{ikr} / r + O(1/r^2) (its kernel is e^{-ik d.y} / (4 pi)), so for a
unit-amplitude incident wave ``sigma = 4 pi |F . p_rx|^2`` [m^2] (Eq. 2-1 of Knott,
Shaeffer and Tuley with lim 4 pi r^2 |E^s|^2 / |E^i|^2). The sign of F (bempp's trace
convention) does not enter. Checked against the Mie series (below and in
``tests/test_rcs_fullwave.py``).

Conventions (:mod:`csuas.render.rcs.geometry`): the direction ``d`` of an aspect points
from the target toward the radar (azimuth from +x toward +y, elevation from the
xy-plane); the incident wave ``p exp(-i k d.x)`` propagates along ``-d``; V = theta-hat,
H = phi-hat of ``d``; "HV" means receive H, transmit V (:data:`POLARISATIONS`).

Measured accuracy and cost (2 CPU cores, numba back-end, this module's meshes). The
first call in a process spends about 35 s compiling bempp's numba kernels (operator
assembly about 22 s, right-hand side about 7 s, far field about 4 s); the figures below
exclude it. PEC sphere of radius a, icosphere meshes (vertices on the sphere), VV at
az 17 deg, el 23 deg, against the Mie series:

=====  ========  ======  ====================  ===========
ka     elements  DOFs    sigma / (pi a^2)      error
=====  ========  ======  ====================  ===========
1      80        120     3.238 (Mie 3.638)     -11.0 %
1      320       480     3.539                 -2.71 %
1      1280      1920    3.613                 -0.68 %
2      80        120     0.576 (Mie 1.008)     -42.9 %
2      320       480     0.886                 -12.1 %
2      1280      1920    0.977                 -3.1 %
=====  ========  ======  ====================  ===========

The error falls as h^2 (ratio 4.0 per halving of the edge), so Richardson's
extrapolation of two levels, ``sigma_h + (sigma_h - sigma_2h) / 3``, is accurate to
a few 1e-4 and its correction is the error estimate of ``sigma_h``
(:func:`richardson`): ka = 1 from 80 and 320 triangles, 3.639 (+0.04 %); ka = 2 from 320
and 1280, 1.007 (-0.09 %). Assembly of 1920 DOFs takes about 18 s, GMRES (relative residual
1e-6, no preconditioner) 0.3 s and 180 iterations, the far field well under a second.
The issue's 2048-element sphere at ka = 3 (4.5 min) is beyond what CI runs: keep
elements below about 1500 there (:data:`CI_MAX_ELEMENTS`).

References
----------
- bempp-cl documentation, "Electromagnetic scattering from a screen" and "Maxwell
  scattering" tutorials (bempp.com/documentation); S. Betcke and M. W. Scroggs,
  "Bempp-cl: A fast Python based just-in-time compiling boundary element library",
  J. Open Source Software 6(59), 2879 (2021).
- R. F. Harrington, *Field Computation by Moment Methods*, Macmillan 1968 (the EFIE
  and the method of moments).
- S. M. Rao, D. R. Wilton and A. W. Glisson, "Electromagnetic scattering by surfaces of
  arbitrary shape", IEEE Trans. Antennas Propag. 30(3), 409-418 (1982) (RWG functions).
- G. Mie, Ann. Phys. 330(3), 377-445 (1908); the PEC sphere series as in
  ``docs/validation.md`` and Ruck et al., *Radar Cross Section Handbook*, Vol. 1, Ch. 3.
- E. F. Knott, J. F. Shaeffer and M. T. Tuley, *Radar Cross Section*, 2nd ed., SciTech
  2004 (Eq. 2.1, the definition; Table 6.1, the flat plate 4 pi A^2 / lambda^2).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from csuas.base.errors import ParameterError
from csuas.core import units

#: Polarisation name -> (receive index, transmit index); 0 = V (theta-hat), 1 = H (phi-hat),
#: as :data:`csuas.render.rcs.solver.POLARISATIONS`.
POLARISATIONS = {"VV": (0, 0), "HH": (1, 1), "HV": (1, 0), "VH": (0, 1)}

#: Guidance for the mesh: at least this many edges per wavelength (mean edge); 10 keeps the
#: sphere's RCS within about 3 % at ka = 1 (320 elements, 21 edges per wavelength: -2.7 %).
EDGES_PER_WAVELENGTH = 10.0

#: Meshes coarser than this many mean edges per wavelength are refused (the EFIE's
#: discretisation error grows past 10 % there: ka = 1 with 80 elements, 10 edges, -11 %).
MIN_EDGES_PER_WAVELENGTH = 5.0

#: Largest element count run in CI (2 cores): assembly about 18 s for 1280 elements, growing
#: as elements^2 (a dense matrix of 1.5 x elements unknowns).
CI_MAX_ELEMENTS = 1500

#: Largest element count accepted: 15 000 elements are 22 500 RWG unknowns, an 8 GB dense matrix.
MAX_ELEMENTS = 15000

SOLVERS = ("gmres", "lu")


@dataclass
class FullWaveResult:
    """Monostatic RCS of a PEC mesh from the EFIE over several aspects at one frequency.

    Attributes
    ----------
    sigma_m2 : ndarray (A,)
        RCS of ``polarisation`` [m^2] per aspect.
    scattering_m2 : ndarray (A, 2, 2)
        RCS [m^2] for receive (V, H) x transmit (V, H), :data:`POLARISATIONS`.
    polarisation : str
    frequency_ghz : float
    azimuth_deg, elevation_deg : ndarray (A,)
        Directions from the target toward the radar [deg].
    elements : int
        Triangles of the mesh.
    unknowns : int
        RWG degrees of freedom (interior edges).
    edges_per_wavelength : float
        Wavelength over the mean edge length.
    iterations : ndarray (A, 2)
        GMRES iterations per aspect and transmit polarisation (V, H); 0 for LU.
    solver : str
        ``"gmres"`` or ``"lu"``; ``tolerance`` GMRES's relative residual.
    assembly_s, rhs_s, solve_s, far_field_s : float
        Wall times [s] of the operator assembly (once), the right-hand sides, the solves and
        the far fields; numba's compilation on a process's first call is included.
    """

    sigma_m2: np.ndarray
    scattering_m2: np.ndarray
    polarisation: str
    frequency_ghz: float
    azimuth_deg: np.ndarray
    elevation_deg: np.ndarray
    elements: int
    unknowns: int
    edges_per_wavelength: float
    iterations: np.ndarray
    solver: str
    tolerance: float
    assembly_s: float
    rhs_s: float
    solve_s: float
    far_field_s: float
    details: dict = field(default_factory=dict)

    @property
    def time_s(self) -> float:
        """Total wall time [s]."""
        return self.assembly_s + self.rhs_s + self.solve_s + self.far_field_s

    def rcs_m2(self, polarisation: str = "VV") -> np.ndarray:
        """RCS (A,) [m^2] of one polarisation."""
        rx, tx = _polarisation(polarisation)
        return self.scattering_m2[:, rx, tx]

    def rcs_dbsm(self, polarisation: str = "VV") -> np.ndarray:
        """RCS (A,) [dBsm] of one polarisation, floored at -300 dBsm."""
        return to_dbsm(self.rcs_m2(polarisation))


def to_dbsm(sigma_m2):
    """10 log10(sigma / 1 m^2) [dBsm], floored at -300 dBsm."""
    return np.maximum(10.0 * np.log10(np.maximum(np.asarray(sigma_m2, float), 1e-300)), -300.0)


def _polarisation(name) -> tuple[int, int]:
    key = str(name).upper()
    if key not in POLARISATIONS:
        raise ParameterError("polarisation", name, ", ".join(POLARISATIONS))
    return POLARISATIONS[key]


def wavelength_m(frequency_ghz: float) -> float:
    """Free-space wavelength [m] of a frequency [GHz]."""
    return float(units.wavelength_m(frequency_ghz))


def mesh_size_m(frequency_ghz: float, edges_per_wavelength: float = EDGES_PER_WAVELENGTH) -> float:
    """Target edge length h = lambda / n [m] of an EFIE mesh.

    Parameters
    ----------
    frequency_ghz : float
        Frequency [GHz], positive and finite.
    edges_per_wavelength : float
        n, at least :data:`MIN_EDGES_PER_WAVELENGTH`; :data:`EDGES_PER_WAVELENGTH` (10) is the
        usual rule for RWG discretisations (about 3 % on the sphere's RCS, module docstring).

    Raises
    ------
    ParameterError
        A non-positive or non-finite frequency, or fewer edges than the minimum.
    """
    f = _positive_frequency(frequency_ghz)
    n = float(edges_per_wavelength)
    if not (math.isfinite(n) and n >= MIN_EDGES_PER_WAVELENGTH):
        raise ParameterError("edges_per_wavelength", edges_per_wavelength, f">= {MIN_EDGES_PER_WAVELENGTH:g}")
    return wavelength_m(f) / n


def _positive_frequency(frequency_ghz) -> float:
    try:
        f = float(frequency_ghz)
    except (TypeError, ValueError):
        raise ParameterError("frequency_ghz", frequency_ghz, "0 < f < inf GHz") from None
    if not (math.isfinite(f) and f > 0.0):
        raise ParameterError("frequency_ghz", frequency_ghz, "0 < f < inf GHz")
    return f


def _check_mesh(vertices, faces) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Validated (vertices (V, 3), faces (F, 3), unique edge lengths)."""
    v = np.asarray(vertices, dtype=float)
    f = np.asarray(faces)
    if v.ndim != 2 or v.shape[1] != 3 or len(v) < 3 or not np.isfinite(v).all():
        raise ParameterError("vertices", f"array of shape {v.shape}", "finite (V, 3) coordinates [m], V >= 3")
    if f.ndim != 2 or f.shape[1] != 3 or len(f) == 0 or not np.issubdtype(f.dtype, np.integer):
        raise ParameterError("faces", f"array of shape {f.shape}", "(F, 3) integer vertex indices, F >= 1")
    if f.min() < 0 or f.max() >= len(v):
        raise ParameterError("faces", f"indices {f.min()}..{f.max()}", f"0..{len(v) - 1}")
    if len(f) > MAX_ELEMENTS:
        raise ParameterError("faces", f"{len(f)} triangles", f"<= {MAX_ELEMENTS} (a dense EFIE matrix)")
    area = 0.5 * np.linalg.norm(np.cross(v[f[:, 1]] - v[f[:, 0]], v[f[:, 2]] - v[f[:, 0]]), axis=1)
    if not (area > 0.0).all():
        raise ParameterError("faces", f"{int((area <= 0).sum())} degenerate triangles", "triangles of non-zero area")
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    unique, counts = np.unique(edges, axis=0, return_counts=True)
    if counts.max() > 2:
        raise ParameterError(
            "faces", f"{int((counts > 2).sum())} edges shared by more than two triangles", "a manifold surface"
        )
    lengths = np.linalg.norm(v[unique[:, 1]] - v[unique[:, 0]], axis=1)
    return v, f.astype(np.uint32), lengths


def _angles(azimuth_deg, elevation_deg) -> tuple[np.ndarray, np.ndarray]:
    az, el = np.broadcast_arrays(
        np.atleast_1d(np.asarray(azimuth_deg, float)), np.atleast_1d(np.asarray(elevation_deg, float))
    )
    az, el = az.ravel().copy(), el.ravel().copy()
    if len(az) == 0 or not np.isfinite(az).all():
        raise ParameterError("azimuth_deg", azimuth_deg, "finite angles [deg], at least one")
    if not (np.isfinite(el).all() and (np.abs(el) <= 90.0).all()):
        raise ParameterError("elevation_deg", elevation_deg, "-90 <= el <= 90 deg")
    return az, el


_INCIDENT = None


def _incident_trace():
    """The tangential trace n x E^i of p exp(i k_vec . x), compiled once per process.

    Parameters (complex array of 6): the wave vector k_vec = -k d (real) and the polarisation p.
    """
    global _INCIDENT
    if _INCIDENT is None:
        import bempp_cl.api as bempp

        @bempp.callable(complex=True, parameterized=True)
        def incident(x, n, domain_index, result, p):
            phase = np.exp(1j * (p[0].real * x[0] + p[1].real * x[1] + p[2].real * x[2]))
            e0, e1, e2 = p[3] * phase, p[4] * phase, p[5] * phase
            result[0] = e1 * n[2] - e2 * n[1]
            result[1] = e2 * n[0] - e0 * n[2]
            result[2] = e0 * n[1] - e1 * n[0]

        _INCIDENT = incident
    return _INCIDENT


@dataclass(frozen=True)
class EfieSettings:
    """How :func:`monostatic_rcs_efie` solves.

    Attributes
    ----------
    solver : {"gmres", "lu"}
        GMRES (scipy, no restart below 2000 iterations, relative residual ``tolerance``) or
        an LU factorisation of the dense matrix, reused for every aspect.
    tolerance : float
        GMRES's relative residual, in (0, 0.1]; with 1e-6 sigma differs from LU's by 3e-9
        (relative) on the 320-triangle sphere at ka = 1 (50 iterations).
    min_edges_per_wavelength : float
        Refuse meshes whose wavelength over mean edge length is below this.
    """

    solver: str = "gmres"
    tolerance: float = 1e-6
    min_edges_per_wavelength: float = MIN_EDGES_PER_WAVELENGTH


def monostatic_rcs_efie(
    vertices,
    faces,
    frequency_ghz: float,
    azimuth_deg=0.0,
    elevation_deg=0.0,
    polarisation: str = "VV",
    settings: EfieSettings = EfieSettings(),
) -> FullWaveResult:
    """Monostatic RCS of a PEC triangle mesh by the EFIE (bempp-cl, RWG/SNC Galerkin).

    The EFIE operator is assembled once; each aspect needs two right-hand sides (V and H
    transmit), two solves and one far-field evaluation, so all four polarisations come
    together in :attr:`FullWaveResult.scattering_m2`.

    Parameters
    ----------
    vertices : array_like (V, 3)
        Vertex positions [m].
    faces : array_like (F, 3)
        Triangles (vertex indices); a closed or open manifold surface, conforming (every
        interior edge shared by exactly two triangles).
    frequency_ghz : float
        Frequency [GHz].
    azimuth_deg, elevation_deg : float or array_like, broadcast to (A,)
        Directions from the target toward the radar [deg].
    polarisation : {"VV", "HH", "VH", "HV"}
        Receive-transmit pair of :attr:`FullWaveResult.sigma_m2`.
    settings : EfieSettings
        Solver, GMRES tolerance and the coarsest mesh accepted.

    Returns
    -------
    FullWaveResult

    Raises
    ------
    ParameterError
        Bad mesh (shape, indices, degenerate triangles, non-manifold edges, too many
        elements), bad frequency, angles, polarisation, solver or tolerance, a mesh too
        coarse for the frequency, or GMRES not converging.
    """
    v, f, lengths = _check_mesh(vertices, faces)
    freq = _positive_frequency(frequency_ghz)
    az, el = _angles(azimuth_deg, elevation_deg)
    pol = str(polarisation).upper()
    _polarisation(pol)
    solver, tol = settings.solver, _checked_settings(settings)
    lam = wavelength_m(freq)
    per_wavelength = lam / float(lengths.mean())
    if per_wavelength < float(settings.min_edges_per_wavelength):
        raise ParameterError(
            "mesh",
            f"{per_wavelength:.2f} mean edges per wavelength at {freq:g} GHz",
            f">= {float(settings.min_edges_per_wavelength):g} (mesh_size_m gives the edge length)",
        )
    k = float(units.wavenumber_rad_m(freq))
    t0 = time.perf_counter()
    system = _EfieSystem.assemble(v, f, k, solver)
    assembly_s = time.perf_counter() - t0
    field, iterations, times = system.solve_aspects(az, el, tol)
    scattering = 4.0 * math.pi * np.abs(field) ** 2
    rx, tx = POLARISATIONS[pol]
    return FullWaveResult(
        sigma_m2=scattering[:, rx, tx],
        scattering_m2=scattering,
        polarisation=pol,
        frequency_ghz=freq,
        azimuth_deg=az,
        elevation_deg=el,
        elements=len(f),
        unknowns=int(system.rwg.global_dof_count),
        edges_per_wavelength=per_wavelength,
        iterations=iterations,
        solver=solver,
        tolerance=tol,
        assembly_s=assembly_s,
        rhs_s=times[0],
        solve_s=times[1],
        far_field_s=times[2],
        details={"wavenumber_rad_m": k, "mean_edge_m": float(lengths.mean()), "max_edge_m": float(lengths.max())},
    )


def _checked_settings(settings: EfieSettings) -> float:
    """The GMRES tolerance, after refusing an unknown solver or a tolerance outside (0, 0.1]."""
    if settings.solver not in SOLVERS:
        raise ParameterError("solver", settings.solver, ", ".join(SOLVERS))
    tol = float(settings.tolerance)
    if not (math.isfinite(tol) and 0.0 < tol <= 0.1):
        raise ParameterError("tolerance", settings.tolerance, "0 < tolerance <= 0.1")
    return tol


@dataclass
class _EfieSystem:
    """The assembled EFIE of a mesh at one wavenumber: spaces, dense matrix and its LU factors (LU solver)."""

    bempp: object
    k: float
    rwg: object
    snc: object
    matrix: np.ndarray
    lu: object

    @classmethod
    def assemble(cls, v, f, k: float, solver: str) -> _EfieSystem:
        """Grid, RWG/SNC spaces and the EFIE's dense weak form (factorised for ``solver == "lu"``)."""
        import bempp_cl.api as bempp
        from scipy import linalg

        grid = bempp.Grid(np.ascontiguousarray(v.T), np.ascontiguousarray(f.T))
        rwg = bempp.function_space(grid, "RWG", 0)
        snc = bempp.function_space(grid, "SNC", 0)
        operator = bempp.operators.boundary.maxwell.electric_field(rwg, rwg, snc, k)
        matrix = np.asarray(operator.weak_form().to_dense())
        lu = linalg.lu_factor(matrix) if solver == "lu" else None
        return cls(bempp, k, rwg, snc, matrix, lu)

    def solve_aspects(self, az, el, tol: float):
        """Far-field amplitudes (A, 2, 2) (receive x transmit), GMRES iterations (A, 2) and the times [s].

        The times are those of the right-hand sides, the solves and the far fields, summed.
        """
        from csuas.render.rcs.geometry import polarisation_basis

        bempp, k, rwg = self.bempp, self.k, self.rwg
        a, e = np.radians(az), np.radians(el)
        d = np.stack([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)], axis=1)
        theta_hat, phi_hat = polarisation_basis(az, el)
        basis = np.stack([theta_hat, phi_hat], axis=1)  # (A, 2 = V/H, 3)
        incident = _incident_trace()
        rhs_s = solve_s = far_s = 0.0
        iterations = np.zeros((len(az), 2), dtype=int)
        field = np.zeros((len(az), 2, 2), dtype=complex)  # receive x transmit far-field amplitude
        far = bempp.operators.far_field.maxwell.electric_field(rwg, np.ascontiguousarray(d.T), k)
        for i in range(len(az)):
            for tx in range(2):
                t = time.perf_counter()
                params = np.concatenate([-k * d[i], basis[i, tx]]).astype(complex)
                rhs = bempp.GridFunction(rwg, fun=incident, dual_space=self.snc, function_parameters=params)
                b = rhs.projections(self.snc)
                rhs_s += time.perf_counter() - t
                t = time.perf_counter()
                x, iterations[i, tx] = self._solve(b, tol)
                solve_s += time.perf_counter() - t
                t = time.perf_counter()
                pattern = far.evaluate(bempp.GridFunction(rwg, coefficients=x))[:, i]  # (3,)
                field[i, :, tx] = basis[i] @ pattern
                far_s += time.perf_counter() - t
        return field, iterations, (rhs_s, solve_s, far_s)

    def _solve(self, b, tol: float):
        """Surface-current coefficients for the right-hand side ``b`` and the GMRES iterations (0 with LU)."""
        from scipy import linalg
        from scipy.sparse.linalg import gmres

        if self.lu is not None:
            return linalg.lu_solve(self.lu, b), 0
        count = [0]

        def _count(_residual, count=count):
            count[0] += 1

        x, info = gmres(
            self.matrix,
            b,
            rtol=tol,
            atol=0.0,
            restart=2000,
            maxiter=1,
            callback=_count,
            callback_type="pr_norm",
        )
        if info != 0:
            raise ParameterError(
                "solver", f"gmres did not converge in {count[0]} iterations", "solver='lu' for this mesh"
            )
        return x, count[0]


def richardson(sigma_fine: float, sigma_coarse: float, ratio: float = 2.0, order: float = 2.0) -> tuple[float, float]:
    """Richardson's extrapolation of two mesh levels and the error estimate of the fine one.

    Parameters
    ----------
    sigma_fine, sigma_coarse : float
        The same quantity on meshes of edge h and ``ratio`` h.
    ratio : float
        Edge-length ratio of the two meshes (2 for one icosphere subdivision).
    order : float
        Convergence order p (2 for RWG on the EFIE's far field, measured: module docstring).

    Returns
    -------
    (extrapolated, error_estimate) : float, float
        ``sigma_fine + c`` and ``|c|`` with ``c = (sigma_fine - sigma_coarse) / (ratio^p - 1)``.
    """
    c = (float(sigma_fine) - float(sigma_coarse)) / (float(ratio) ** float(order) - 1.0)
    return float(sigma_fine) + c, abs(c)


# --------------------------------------------------------------------------------------------
# Meshes of the oracle cases: conforming triangulations with a near-uniform edge length.
# --------------------------------------------------------------------------------------------


def _trimesh(vertices, faces, merge: bool = True):
    import trimesh

    mesh = trimesh.Trimesh(vertices=np.asarray(vertices, float), faces=np.asarray(faces, np.int64), process=False)
    if merge:
        mesh.merge_vertices(digits_vertex=9)
        mesh.remove_unreferenced_vertices()
    return mesh


def _positive_length(name: str, value) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, value, "a positive finite length [m]") from None
    if not (math.isfinite(x) and x > 0.0):
        raise ParameterError(name, value, "a positive finite length [m]")
    return x


def sphere_mesh(radius_m: float, subdivisions: int = 2):
    """Icosphere of radius [m] (trimesh): 20 x 4^s triangles, vertices on the sphere.

    ``subdivisions`` 1, 2, 3 give 80, 320, 1280 triangles with mean edges of about
    0.62, 0.31 and 0.15 radii.
    """
    import trimesh

    r = _positive_length("radius_m", radius_m)
    if int(subdivisions) != subdivisions or not 0 <= int(subdivisions) <= 5:
        raise ParameterError("subdivisions", subdivisions, "an integer 0..5")
    return trimesh.creation.icosphere(subdivisions=int(subdivisions), radius=r)


def _grid_patch(origin, u, v, nu: int, nv: int):
    """Triangulated parallelogram origin + s u + t v, s, t in [0, 1], nu x nv cells (alternating diagonals)."""
    s, t = np.meshgrid(np.linspace(0, 1, nu + 1), np.linspace(0, 1, nv + 1), indexing="ij")
    pts = np.asarray(origin, float) + s[..., None] * np.asarray(u, float) + t[..., None] * np.asarray(v, float)
    idx = np.arange((nu + 1) * (nv + 1)).reshape(nu + 1, nv + 1)
    a, b, c, d = idx[:-1, :-1], idx[1:, :-1], idx[1:, 1:], idx[:-1, 1:]
    flip = ((np.arange(nu)[:, None] + np.arange(nv)[None, :]) % 2).astype(bool)
    t1 = np.where(flip[..., None], np.stack([a, b, d], -1), np.stack([a, b, c], -1))
    t2 = np.where(flip[..., None], np.stack([b, c, d], -1), np.stack([a, c, d], -1))
    return pts.reshape(-1, 3), np.concatenate([t1.reshape(-1, 3), t2.reshape(-1, 3)])


def _cells(length: float, h: float) -> int:
    return max(1, int(math.ceil(length / h - 1e-9)))


def plate_mesh(side_m: float, h_m: float, width_m: float | None = None):
    """Plate side x width [m] (square without ``width_m``; side along x) in the xy-plane, centred, normal +z,
    edges about ``h_m`` [m].

    A single zero-thickness sheet (the EFIE's RWG currents are the sum of both faces'
    currents); normal incidence is elevation 90 deg.
    """
    a = _positive_length("side_m", side_m)
    b = a if width_m is None else _positive_length("width_m", width_m)
    h = _positive_length("h_m", h_m)
    pts, tri = _grid_patch([-a / 2, -b / 2, 0.0], [a, 0, 0], [0, b, 0], _cells(a, h), _cells(b, h))
    return _trimesh(pts, tri, merge=False)


def _disc_cap(radius: float, z: float, n_rim: int, h: float, up: bool):
    """Triangulated disc of ``radius`` at height z whose rim has ``n_rim`` equally spaced points."""
    from scipy.spatial import Delaunay

    pts = [np.zeros((1, 2))]
    n_rings = max(1, int(round(radius / h)))
    for j in range(1, n_rings + 1):
        r = radius * j / n_rings
        m = n_rim if j == n_rings else max(6, int(round(2 * math.pi * r / h)))
        phi = 2 * math.pi * np.arange(m) / m
        pts.append(np.stack([r * np.cos(phi), r * np.sin(phi)], axis=1))
    p2 = np.concatenate(pts)
    tri = Delaunay(p2).simplices

    def signed_area(t):
        e1, e2 = p2[t[:, 1]] - p2[t[:, 0]], p2[t[:, 2]] - p2[t[:, 0]]
        return e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]

    tri = tri[np.abs(signed_area(tri)) > 1e-12 * radius * radius]
    wrong = (signed_area(tri) > 0) != up
    tri[wrong] = tri[wrong][:, ::-1]
    return np.column_stack([p2, np.full(len(p2), z)]), tri


def cylinder_mesh(radius_m: float, length_m: float, h_m: float, center=(0.0, 0.0, 0.0)):
    """Closed circular cylinder [m], axis along z, centred at ``center``, edges about ``h_m``.

    Side: a structured n_phi x n_z grid (n_phi = ceil(2 pi r / h), at least 8); caps:
    Delaunay triangulations of concentric rings sharing the side's rim points, so the
    surface is conforming and closed.
    """
    r, length, h = (_positive_length(n, x) for n, x in (("radius_m", radius_m), ("length_m", length_m), ("h_m", h_m)))
    n_phi = max(8, _cells(2 * math.pi * r, h))
    n_z = _cells(length, h)
    phi = 2 * math.pi * np.arange(n_phi) / n_phi
    z = np.linspace(-length / 2, length / 2, n_z + 1)
    side = np.stack(
        [np.repeat(r * np.cos(phi)[:, None], n_z + 1, 1), np.repeat(r * np.sin(phi)[:, None], n_z + 1, 1)], -1
    )
    side_pts = np.concatenate([side, np.broadcast_to(z[None, :, None], (n_phi, n_z + 1, 1))], -1).reshape(-1, 3)
    idx = np.arange(n_phi * (n_z + 1)).reshape(n_phi, n_z + 1)
    nxt = np.roll(idx, -1, axis=0)
    a, b, c, d = idx[:, :-1], nxt[:, :-1], nxt[:, 1:], idx[:, 1:]
    side_tri = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    parts_v, parts_f, offset = [side_pts], [side_tri], len(side_pts)
    for zc, up in ((-length / 2, False), (length / 2, True)):
        pts, tri = _disc_cap(r, zc, n_phi, h, up)
        parts_v.append(pts)
        parts_f.append(tri + offset)
        offset += len(pts)
    return _trimesh(np.concatenate(parts_v) + np.asarray(center, float), np.concatenate(parts_f))


def box_mesh(extents_m, h_m: float, center=(0.0, 0.0, 0.0)):
    """Closed rectangular box of extents (x, y, z) [m] at ``center``, structured faces, edges about ``h_m``."""
    ext = [_positive_length("extents_m", e) for e in np.atleast_1d(extents_m)]
    if len(ext) != 3:
        raise ParameterError("extents_m", extents_m, "three positive lengths [m]")
    h = _positive_length("h_m", h_m)
    n = [_cells(e, h) for e in ext]
    lo = -np.asarray(ext) / 2
    parts_v, parts_f, offset = [], [], 0
    for axis in range(3):
        i, j = [q for q in range(3) if q != axis]
        u, v = np.zeros(3), np.zeros(3)
        u[i], v[j] = ext[i], ext[j]
        for side in (0, 1):
            origin = lo.copy()
            origin[axis] += side * ext[axis]
            pts, tri = _grid_patch(origin, u, v, n[i], n[j])
            parts_v.append(pts)
            parts_f.append(tri + offset)
            offset += len(pts)
    return _trimesh(np.concatenate(parts_v) + np.asarray(center, float), np.concatenate(parts_f))


#: The DJI Mini 4 Pro's arm and motor as modelled in ``drone_models/presets.py``
#: (``_mini_4_pro``: ``arm_width_m=0.014``, ``arm_thickness_m=0.008``, ``motor_diameter_m=0.020``,
#: ``motor_height_m=0.016``, flat ``"bar"`` arms); the front arm of
#: ``build_drone("dji_mini_4_pro")`` runs 0.1111 m from its root in the body to the motor axis,
#: so 0.1011 m of it lies outside the motor. Those figures are the model's estimates from
#: photographs and DJI's published box (presets module docstring), not measured parts.
MINI4PRO_ARM = {
    "arm_width_m": 0.014,
    "arm_thickness_m": 0.008,
    "arm_to_motor_axis_m": 0.1111,
    "motor_diameter_m": 0.020,
    "motor_height_m": 0.016,
    "source": "drone_models/presets.py _mini_4_pro (DJI Mini 4 Pro model; arm and motor sizes are estimates)",
}

#: Gap [m] between the arm's end and the motor: two closed bodies instead of a boolean union
#: (a conforming T-junction needs a mesher csuas does not have). 1 mm is lambda/30 at 10 GHz.
ARM_MOTOR_GAP_M = 0.001


def arm_motor_mesh(h_m: float, gap_m: float = ARM_MOTOR_GAP_M):
    """A DJI Mini 4 Pro arm (flat bar) ending ``gap_m`` [m] short of its motor (a closed cylinder).

    Motor axis along z through the origin, motor centred at z = 0; the arm lies along +x..-x
    from the motor toward the body (x < 0), centred on the motor's mid-height, its width
    along y. Dimensions: :data:`MINI4PRO_ARM`. Edges about ``h_m`` [m].
    """
    h = _positive_length("h_m", h_m)
    g = _positive_length("gap_m", gap_m)
    p = MINI4PRO_ARM
    r = p["motor_diameter_m"] / 2.0
    arm_len = p["arm_to_motor_axis_m"] - r - g
    motor = cylinder_mesh(r, p["motor_height_m"], h)
    arm = box_mesh(
        (arm_len, p["arm_width_m"], p["arm_thickness_m"]),
        h,
        center=(-(r + g + arm_len / 2.0), 0.0, 0.0),
    )
    return _trimesh(
        np.concatenate([motor.vertices, arm.vertices]),
        np.concatenate([motor.faces, arm.faces + len(motor.vertices)]),
        merge=False,
    )


# --------------------------------------------------------------------------------------------
# SBR-PO against the EFIE on the same mesh.
# --------------------------------------------------------------------------------------------

#: Oracle cases of :func:`case_mesh`: sizes in wavelengths (sphere: ka), quick (CI) and full.
CASES = {
    "sphere": {"quick": {"ka": 1.0, "subdivisions": 2}, "full": {"ka": 2.0, "subdivisions": 3}},
    "plate": {"quick": {"side_wavelengths": 1.0}, "full": {"side_wavelengths": 2.5}},
    "cylinder": {
        "quick": {"radius_wavelengths": 1.0 / 3.0, "length_wavelengths": 1.0},
        "full": {"radius_wavelengths": 0.5, "length_wavelengths": 2.0},
    },
    "arm_motor": {"quick": {}, "full": {}},
}


def case_mesh(case: str, frequency_ghz: float, edges_per_wavelength: float = EDGES_PER_WAVELENGTH, full: bool = False):
    """The mesh of an oracle case of :data:`CASES` at a frequency [GHz].

    ``sphere``: icosphere of radius ka / k; ``plate``: square plate (normal +z) of the given
    side; ``cylinder``: closed cylinder, axis z; ``arm_motor``: :func:`arm_motor_mesh` (its
    size is the drone's, not scaled with the wavelength). Edges about lambda /
    ``edges_per_wavelength``.
    """
    if case not in CASES:
        raise ParameterError("case", case, ", ".join(CASES))
    lam = wavelength_m(_positive_frequency(frequency_ghz))
    h = mesh_size_m(frequency_ghz, edges_per_wavelength)
    size = CASES[case]["full" if full else "quick"]
    if case == "sphere":
        return sphere_mesh(size["ka"] * lam / (2 * math.pi), size["subdivisions"])
    if case == "plate":
        return plate_mesh(size["side_wavelengths"] * lam, h)
    if case == "cylinder":
        return cylinder_mesh(size["radius_wavelengths"] * lam, size["length_wavelengths"] * lam, h)
    return arm_motor_mesh(h)


@dataclass
class Comparison:
    """SBR-PO against the EFIE on one mesh, per aspect and polarisation.

    Attributes
    ----------
    efie_dbsm, sbr_dbsm, difference_db : dict of str -> ndarray (A,)
        RCS [dBsm] by polarisation; difference = SBR - EFIE [dB].
    sbr_error_db : dict of str -> ndarray (A,)
        SBR's own discretisation error estimate [dB] (:func:`compute_rcs`).
    azimuth_deg, elevation_deg : ndarray (A,)
    frequency_ghz : float
    elements : int
    efie : FullWaveResult
    efie_s, sbr_s : float
        Wall times [s] of the two computations.
    """

    efie_dbsm: dict
    sbr_dbsm: dict
    difference_db: dict
    sbr_error_db: dict
    azimuth_deg: np.ndarray
    elevation_deg: np.ndarray
    frequency_ghz: float
    elements: int
    efie: FullWaveResult
    efie_s: float
    sbr_s: float


def compare_sbr_to_fullwave(
    mesh,
    frequency_ghz: float,
    aspects,
    *,
    polarisations=("VV", "HH"),
    sbr_quality: str = "reference",
    efie: EfieSettings = EfieSettings(),
    edge_diffraction: bool = False,
) -> Comparison:
    """Run :func:`csuas.render.rcs.solver.compute_rcs` (PEC) and the EFIE on the same mesh.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The mesh [m], e.g. a case of :data:`CASES` meshed by :func:`case_mesh`.
    frequency_ghz : float
        Frequency [GHz].
    aspects : array_like (A, 2)
        (azimuth_deg, elevation_deg) pairs [deg], toward the radar.
    polarisations : sequence of {"VV", "HH", "VH", "HV"}
    sbr_quality : str
        :data:`csuas.render.rcs.solver.QUALITY_PRESETS` name.
    efie : EfieSettings
        How the EFIE solves.
    edge_diffraction : bool
        Add the PTD fringe field to the SBR-PO result (:mod:`csuas.render.rcs.edges`).

    Returns
    -------
    Comparison
    """
    from csuas.render.rcs.solver import compute_rcs

    asp = np.asarray(aspects, dtype=float)
    if asp.ndim == 1 and asp.shape == (2,):
        asp = asp[None, :]
    if asp.ndim != 2 or asp.shape[1] != 2 or len(asp) == 0:
        raise ParameterError("aspects", f"array of shape {asp.shape}", "(A, 2) pairs of azimuth, elevation [deg]")
    pols = [str(p).upper() for p in polarisations]
    for p in pols:
        _polarisation(p)
    efie = monostatic_rcs_efie(mesh.vertices, mesh.faces, frequency_ghz, asp[:, 0], asp[:, 1], pols[0], efie)
    t = time.perf_counter()
    sbr = compute_rcs(
        mesh,
        frequency_ghz,
        asp[:, 0],
        asp[:, 1],
        material="pec",
        quality=sbr_quality,
        edge_diffraction=edge_diffraction,
    )
    sbr_s = time.perf_counter() - t
    e_db = {p: efie.rcs_dbsm(p) for p in pols}
    s_db = {p: sbr.rcs_dbsm(p)[0, :, 0] for p in pols}
    return Comparison(
        efie_dbsm=e_db,
        sbr_dbsm=s_db,
        difference_db={p: s_db[p] - e_db[p] for p in pols},
        sbr_error_db={p: sbr.error_estimate_db(p)[0, :, 0] for p in pols},
        azimuth_deg=asp[:, 0],
        elevation_deg=asp[:, 1],
        frequency_ghz=float(frequency_ghz),
        elements=efie.elements,
        efie=efie,
        efie_s=efie.time_s,
        sbr_s=sbr_s,
    )
