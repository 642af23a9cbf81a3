"""Shooting and bouncing rays with physical optics (SBR-PO) on Mitsuba 3 / Dr.Jit.

The method of Ling, Chou & Lee (IEEE Trans. Antennas Propag. 37(2), 1989):

1. *Ray tubes.* The incident plane wave (unit amplitude, polarisation V =
   theta-hat or H = phi-hat of the incidence direction) is sampled by a square
   grid of ray tubes of spacing ``d = lambda / N`` (``N`` rays per
   wavelength) on a plane perpendicular to the propagation direction,
   covering the target's projection.
2. *Geometric optics.* Each tube is traced through up to ``max_bounces``
   interactions with ``scene.ray_intersect_preliminary``; at each hit the
   field is split into its components perpendicular (TE) and parallel (TM)
   to the plane of incidence and multiplied by the reflection coefficients
   (PEC: -1 and +1 in the convention ``e_par = k x e_perp``; Fresnel for a
   lossy dielectric half-space; Fabry-Perot slab coefficients for a thin
   shell, whose transmitted tube continues straight on as a second branch).
   The path length is accumulated for the phase. Tubes weaker than
   ``power_cutoff`` of the incident tube power stop.
3. *Physical optics.* At the tube's exit point (its last hit), the surface
   currents ``J = n x (H_i + H_r)`` and ``M = (E_i + E_r) x n`` (for a tube
   leaving through a shell: the aperture currents of the transmitted field
   on the far side) radiate to the observation direction ``s`` over the
   tube's footprint on the flat facet, a parallelogram spanned by the tube
   edges projected along the ray.
   The footprint integral of the linear phase ``exp(jk (s - k_i).r')`` is
   evaluated exactly as ``area * sinc(x1) * sinc(x2)`` (Bhalla & Ling, Radio
   Science 30(5), 1995), which removes the aliasing of point-sampled tubes at
   oblique angles.
4. *Coherent sum.* The far-field contributions

       E_s r e^{jkr} = -jk/(4 pi) * A * S * e^{j psi} * [eta J_perp + M x s]

   are summed in float64 per job; ``sigma = 4 pi |E_s|^2 / |E_i|^2``.
5. *Exact first hits.* The single reflection of every fully lit facet (its
   vertices see the transmitter, it faces it on a closed surface, and its
   reflection escapes) is integrated over the whole facet in closed form,
   ``2 A exp(j phi_0) G(a, b)`` with ``G`` the second divided difference of
   ``exp(jx)`` at the vertex phases (Gordon, IEEE TAP 23(4), 1975, in its
   Hermite-Genocchi form), and the first-hit radiation of the tubes that hit
   those facets is left out (:meth:`SbrEngine._exact_first_hits`). Grazing
   facets near a shadow boundary, which a tube grid samples badly and whose
   currents make a sphere's small-ka oscillation, so count in full.

A "job" is one incidence direction and frequency with ``M`` observation
directions (``M = 1`` and ``s = d_inc`` for monostatic). Many jobs share one
launch: every tube carries its job index, and tubes are traced in batches of
at most ``batch_size`` so memory stays bounded whatever the total count.

Limitations (documented, not hidden): no edge diffraction here (PTD is the
optional :mod:`csuas.render.rcs.edges`) and no creeping waves, so RCS far from
specular directions and at small ka is under-estimated; a dielectric is a
half-space (transmitted wave absorbed) or a thin shell without refraction
offset, never a thick refracting body; tubes do not diverge on curved
(faceted) surfaces; where tubes radiate (multiple reflections, partly
shadowed facets) a tube straddling a facet edge counts entirely for the facet
its centre hits (error proportional to perimeter * d / area, see
:mod:`csuas.render.rcs.convergence`); a facet whose vertices all see the
transmitter counts as fully lit even if a small occluder shades its middle;
no shadow test from exit points toward a bistatic observer.
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass

import numpy as np

from csuas.base.errors import ParameterError
from csuas.base.interrupts import raise_if_interrupted
from csuas.core.units import wavelength_m, wavenumber_rad_m
from csuas.drone_models.geometry import direction_vector

from .geometry import TargetMesh, closed_faces, polarisation_basis

#: Default tube batch on CPU and on GPU [tubes]; about 200 bytes of state per tube.
BATCH_SIZE_CPU = 1 << 20
BATCH_SIZE_GPU = 1 << 23

#: Default offset of the tube grid from the target's projected centre, in tube spacings.
#: Not 0 or 1/2, so that tube centres never fall exactly on the symmetry planes, folds
#: and edges of symmetric targets (a centred grid puts a row of tubes on a dihedral's fold).
DEFAULT_GRID_SHIFT = (0.2371, 0.3719)

#: Tubes are followed while their power relative to the incident tube exceeds this (-30 dB); weaker
#: tubes radiate where they are (reflected branch) or are dropped (transmitted branch). PEC tubes keep
#: full power and end only at ``max_bounces``; the cut bounds the branching of thin shells.
POWER_CUTOFF = 1e-3


@dataclass
class Jobs:
    """Incidence/frequency combinations traced in one launch (NumPy arrays).

    Attributes
    ----------
    incident_az_deg, incident_el_deg : ndarray (J,)
        Direction from the target toward the transmitter [deg].
    observe_az_deg, observe_el_deg : ndarray (J, M)
        Directions from the target toward the receiver(s) [deg]; equal to the
        incidence direction for monostatic RCS.
    frequency_ghz : ndarray (J,)
        Frequency [GHz].
    rays_per_wavelength : ndarray (J,)
        Tube density ``N``; tube spacing ``d = lambda / N`` [-].
    grid_shift : ndarray (J, 2)
        Offset of the tube grid in units of ``d`` (0 = centred on the target's
        projection; default :data:`DEFAULT_GRID_SHIFT`).
    """

    incident_az_deg: np.ndarray
    incident_el_deg: np.ndarray
    observe_az_deg: np.ndarray
    observe_el_deg: np.ndarray
    frequency_ghz: np.ndarray
    rays_per_wavelength: np.ndarray
    grid_shift: np.ndarray

    @classmethod
    def build(
        cls,
        incident_az_deg,
        incident_el_deg,
        frequency_ghz,
        rays_per_wavelength,
        observe_az_deg=None,
        observe_el_deg=None,
        grid_shift=DEFAULT_GRID_SHIFT,
    ) -> Jobs:
        """Broadcast incidence angles, frequency and density to J jobs.

        ``observe_*`` of shape (J, M) or (M,) (same receivers for every job);
        ``None`` means monostatic.
        """
        az, el, f, n = (
            np.atleast_1d(np.asarray(x, dtype=float))
            for x in (incident_az_deg, incident_el_deg, frequency_ghz, rays_per_wavelength)
        )
        az, el, f, n = np.broadcast_arrays(az, el, f, n)
        az, el, f, n = (np.ravel(x).copy() for x in (az, el, f, n))
        if observe_az_deg is None:
            oaz, oel = az[:, None].copy(), el[:, None].copy()
        else:
            oaz, oel = np.broadcast_arrays(
                np.atleast_1d(np.asarray(observe_az_deg, float)), np.atleast_1d(np.asarray(observe_el_deg, float))
            )
            oaz = np.broadcast_to(oaz if oaz.ndim == 2 else oaz[None, :], (len(az), oaz.shape[-1])).copy()
            oel = np.broadcast_to(oel if oel.ndim == 2 else oel[None, :], (len(az), oel.shape[-1])).copy()
        shift = np.broadcast_to(np.asarray(grid_shift, float), (len(az), 2)).copy()
        jobs = cls(az, el, oaz, oel, f, n, shift)
        jobs.validate()
        return jobs

    def validate(self) -> None:
        """Raise :class:`ParameterError` for non-finite angles, f <= 0 or N < 1."""
        for name, values in (
            ("azimuth_deg", self.incident_az_deg),
            ("elevation_deg", self.incident_el_deg),
            ("observe_azimuth_deg", self.observe_az_deg),
            ("observe_elevation_deg", self.observe_el_deg),
        ):
            if not np.isfinite(values).all():
                raise ParameterError(name, values[~np.isfinite(values)][0], "finite angle [deg]")
        for name, values in (("elevation_deg", self.incident_el_deg), ("observe_elevation_deg", self.observe_el_deg)):
            if np.abs(values).max() > 90.0:
                raise ParameterError(name, values[np.abs(values) > 90][0], "-90 <= x <= 90 deg")
        bad = ~(np.isfinite(self.frequency_ghz) & (self.frequency_ghz > 0))
        if bad.any():
            raise ParameterError("frequency_ghz", float(self.frequency_ghz[bad][0]), "0 < f < inf GHz")
        bad = ~(np.isfinite(self.rays_per_wavelength) & (self.rays_per_wavelength >= 1.0))
        if bad.any():
            raise ParameterError("rays_per_wavelength", float(self.rays_per_wavelength[bad][0]), "N >= 1")

    def __len__(self) -> int:
        return len(self.incident_az_deg)


@dataclass
class TraceResult:
    """Scattered far-field amplitudes of a launch and its cost.

    Attributes
    ----------
    amplitude : ndarray complex (J, M, 2, 2)
        ``r e^{jkr} E_s`` for a unit incident field [m]; axis 2 is the
        receive component (0 = theta/V, 1 = phi/H), axis 3 the transmit
        polarisation (0 = V, 1 = H). ``sigma = 4 pi |amplitude|^2`` [m^2].
    tubes : ndarray int (J,)
        Tubes launched per job.
    ray_casts : int
        Ray-scene intersection queries (tubes x bounces traced).
    exits_by_bounce : ndarray int (max_bounces + 1,)
        Tubes radiating after 1, 2, ... bounces (index 0: tubes that missed).
    time_s : float
        Wall time of the launch [s], including kernel compilation.
    trace_time_s : float
        Part of ``time_s`` spent in ray-scene intersection [s].
    live_sigma_m2 : ndarray (J, 2)
        Per job and transmit polarisation (V, H), the RCS [m^2] the tubes still alive at the bounce
        limit could add if each radiated once more at random phase: ``sum k^2 A^2 P / pi`` over them,
        with A a tube's cross-section and P its power relative to the incident tube (a flat aperture
        A re-radiating power P has at most ``4 pi A^2 P / lambda^2``; Knott et al., ch. 5).
    """

    amplitude: np.ndarray
    tubes: np.ndarray
    ray_casts: int
    exits_by_bounce: np.ndarray
    time_s: float
    trace_time_s: float
    live_sigma_m2: np.ndarray | None = None

    @property
    def sigma_m2(self) -> np.ndarray:
        """RCS (J, M, 2, 2) [m^2]: 4 pi |amplitude|^2."""
        return 4.0 * math.pi * np.abs(self.amplitude) ** 2


def backend(variant: str | None = None):
    """Select a Mitsuba variant (CUDA first, then LLVM) and return ``(mi, dr)``."""
    from csuas.render.backend import use_variant

    use_variant("ad_mono", variant)
    import drjit as dr
    import mitsuba as mi

    return mi, dr


class SbrEngine:
    """SBR-PO solver bound to one target mesh (the Mitsuba scene is built once).

    Parameters
    ----------
    target : TargetMesh
        Prepared mesh with per-face materials (:func:`load_target`).
    batch_size : int, optional
        Maximum tubes in flight [tubes]; default 2^20 on CPU, 2^23 on CUDA.
    variant : str, optional
        Exact Mitsuba variant (default: ``ad_mono`` family, CUDA preferred).
    """

    def __init__(self, target: TargetMesh, batch_size: int | None = None, variant: str | None = None):
        mi, dr = backend(variant)
        self.mi, self.dr, self.target = mi, dr, target
        self.variant = mi.variant()
        if batch_size is None:
            batch_size = BATCH_SIZE_GPU if self.variant.startswith("cuda") else BATCH_SIZE_CPU
        if int(batch_size) < 1:
            raise ParameterError("batch_size", batch_size, "integer >= 1")
        self.batch_size = int(batch_size)
        mesh = mi.Mesh(
            "rcs_target", len(target.vertices), len(target.faces), has_vertex_normals=False, has_vertex_texcoords=False
        )
        params = mi.traverse(mesh)
        params["vertex_positions"] = mi.Float(np.asarray(target.vertices, np.float32).ravel())
        params["faces"] = mi.UInt32(np.asarray(target.faces, np.uint32).ravel())
        params.update()
        self.scene = mi.load_dict({"type": "scene", "target": mesh})
        n = np.asarray(target.face_normals, np.float32)
        self._face_normal = mi.Vector3f(mi.Float(n[:, 0]), mi.Float(n[:, 1]), mi.Float(n[:, 2]))
        # first vertex and the two edges from it of every face, and its area, for the facet integrals
        tri = np.asarray(target.vertices, float)[np.asarray(target.faces)]
        self._face_origin, self._face_edge1, self._face_edge2 = (
            mi.Vector3f(*(mi.Float(np.asarray(x[:, i], np.float32)) for i in range(3)))
            for x in (tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        )
        self._face_area = mi.Float(np.asarray(target.face_areas_m2, np.float32))
        self._face_material = mi.UInt32(np.asarray(target.face_material, np.uint32))
        self._centroid = tri.mean(axis=1)
        self._one_sided = closed_faces(target.faces)
        self._radius = 1.01 * target.bounding_radius_m + 1e-3
        self._hull = _hull_points(target.vertices)
        # Without thin shells no tube is ever transmitted, and the kernels leave that branch out.
        self._has_shells = any(m.thickness_m for m in target.materials if not m.is_pec)

    @functools.cached_property
    def edges(self):
        """The target's diffracting edges (:func:`csuas.render.rcs.edges.find_edges`), found once."""
        from .edges import find_edges

        return find_edges(self.target)

    # ------------------------------------------------------------------ set-up
    def _job_tables(self, jobs: Jobs):
        """Per-job NumPy tables: grid, wave numbers, bases, materials."""
        d_in = direction_vector(jobs.incident_az_deg, jobs.incident_el_deg)
        pol_v, pol_h = polarisation_basis(jobs.incident_az_deg, jobs.incident_el_deg)
        wavelength = wavelength_m(jobs.frequency_ghz)
        spacing = wavelength / jobs.rays_per_wavelength
        e1, e2 = pol_h, pol_v  # grid axes, both perpendicular to d_in
        pu, pv = self._hull @ e1.T, self._hull @ e2.T  # (H, J)
        counts, first = [], []
        for p in (pu, pv):
            lo, hi = p.min(axis=0), p.max(axis=0)
            count = np.ceil((hi - lo) / spacing).astype(np.int64) + 1
            counts.append(count)
            first.append(0.5 * (lo + hi) - 0.5 * (count - 1) * spacing)
        nu, nv = counts
        u0 = first[0] + (jobs.grid_shift[:, 0] % 1.0) * spacing
        v0 = first[1] + (jobs.grid_shift[:, 1] % 1.0) * spacing
        tubes = nu * nv
        if (tubes >= 2**32).any():
            raise ParameterError(
                "rays_per_wavelength",
                float(jobs.rays_per_wavelength.max()),
                "a density giving fewer than 2^32 tubes per aspect and frequency",
            )
        s = direction_vector(jobs.observe_az_deg, jobs.observe_el_deg)  # (J, M, 3)
        s_theta, s_phi = polarisation_basis(jobs.observe_az_deg, jobs.observe_el_deg)
        # Complex permittivity of each (material, job): index material * J + job.
        n_jobs, mats = len(jobs), self.target.materials
        eps = np.zeros((len(mats), n_jobs), complex)
        pec = np.zeros((len(mats), n_jobs), bool)
        thick = np.zeros((len(mats), n_jobs))
        for i, m in enumerate(mats):
            if m.is_pec:
                pec[i] = True
            else:
                eps[i] = [m.complex_permittivity(f) for f in jobs.frequency_ghz]
                thick[i] = m.thickness_m or 0.0
        return dict(
            k=wavenumber_rad_m(jobs.frequency_ghz),
            d=spacing,
            nu=nu,
            tubes=tubes,
            u0=u0,
            v0=v0,
            kin=-d_in,
            e1=e1,
            e2=e2,
            pol_v=pol_v,
            pol_h=pol_h,
            s=s,
            s_theta=s_theta,
            s_phi=s_phi,
            eps=eps.ravel(),
            pec=pec.ravel(),
            thick=thick.ravel(),
        )

    def _upload(self, tab):
        mi = self.mi

        def vec(a):
            a = np.asarray(a, np.float32).reshape(-1, 3)
            return mi.Vector3f(mi.Float(a[:, 0]), mi.Float(a[:, 1]), mi.Float(a[:, 2]))

        def f32(a):
            return mi.Float(np.asarray(a, np.float32).ravel())

        return dict(
            k=f32(tab["k"]),
            d=f32(tab["d"]),
            nu=mi.UInt32(np.asarray(tab["nu"], np.uint32)),
            u0=f32(tab["u0"]),
            v0=f32(tab["v0"]),
            kin=vec(tab["kin"]),
            e1=vec(tab["e1"]),
            e2=vec(tab["e2"]),
            pol_v=vec(tab["pol_v"]),
            pol_h=vec(tab["pol_h"]),
            s=vec(tab["s"]),
            s_theta=vec(tab["s_theta"]),
            s_phi=vec(tab["s_phi"]),
            eps_re=f32(tab["eps"].real),
            eps_im=f32(tab["eps"].imag),
            pec=mi.Bool(np.asarray(tab["pec"], bool)),
            thick=f32(tab["thick"]),
            radius=mi.Float([self._radius]),
        )

    # ------------------------------------------------------------------ launch
    def trace(
        self,
        jobs: Jobs,
        max_bounces: int = 5,
        radiate: str = "exit",
        power_cutoff: float = POWER_CUTOFF,
        exact_first_hits: bool = True,
    ) -> TraceResult:
        """Trace every job's tubes and return the scattered far-field amplitudes.

        Parameters
        ----------
        jobs : Jobs
            Incidence directions, frequencies, densities and receivers.
        max_bounces : int
            Maximum interactions (reflections or shell crossings) per tube (>= 1).
        radiate : {"exit", "all"}
            ``"exit"``: each tube radiates at its last hit (Ling et al. 1989);
            ``"all"``: at every hit (adds the off-specular PO of intermediate
            surfaces).
        power_cutoff : float
            Tubes weaker than this fraction of the incident tube power stop
            (:data:`POWER_CUTOFF`); 0 follows every tube to ``max_bounces``.
        exact_first_hits : bool
            Integrate the single reflection of every fully lit facet exactly (:meth:`_exact_first_hits`);
            False radiates every first hit from its tube footprint, as Ling et al.

        Returns
        -------
        TraceResult
        """
        if self.mi.variant() != self.variant:
            # another module (e.g. Sionna RT links) switched variants since this engine was built:
            # its scene only accepts rays of its own variant
            from csuas.render.backend import use_variant

            use_variant(variant=self.variant)
        if int(max_bounces) != max_bounces or max_bounces < 1:
            raise ParameterError("max_bounces", max_bounces, "integer >= 1")
        if radiate not in ("exit", "all"):
            raise ParameterError("radiate", radiate, "'exit' or 'all'")
        if not (0.0 <= power_cutoff < 1.0):
            raise ParameterError("power_cutoff", power_cutoff, "0 <= x < 1")
        max_bounces = int(max_bounces)
        start = time.perf_counter()
        tab = self._job_tables(jobs)
        dev = self._upload(tab)
        dev["cutoff"] = self.dr.opaque(self.mi.Float, float(power_cutoff))
        dev["n_jobs"] = len(jobs)
        n_jobs, n_obs = len(jobs), tab["s"].shape[1]
        # Float64 sums per job of (receiver, tx pol, rx pol, re/im).
        acc = np.zeros((n_jobs, n_obs * 8))
        offsets = np.concatenate([[0], np.cumsum(tab["tubes"])])
        total = int(offsets[-1])
        stats = {
            "casts": 0,
            "trace_s": 0.0,
            "exits": np.zeros(max_bounces + 1, np.int64),
            "live": np.zeros((n_jobs, 2)),
        }
        dev["clean"] = None
        if exact_first_hits:
            escape_needed = radiate == "exit" and max_bounces > 1
            dev["clean"] = self._exact_first_hits(dev, tab, n_obs, escape_needed, acc, stats)
        for lo in range(0, total, self.batch_size):
            raise_if_interrupted()  # an interrupt a C extension swallowed ends the trace here, not after it
            hi = min(total, lo + self.batch_size)
            g = np.arange(lo, hi, dtype=np.int64)
            job = np.searchsorted(offsets, g, side="right") - 1
            local = (g - offsets[job]).astype(np.uint32)
            self._trace_batch(dev, job.astype(np.uint32), local, n_obs, max_bounces, radiate, acc, stats)
        sums = acc.reshape(n_jobs, n_obs, 2, 2, 2)  # (job, obs, tx, rx, re/im)
        amplitude = (sums[..., 0] + 1j * sums[..., 1]).transpose(0, 1, 3, 2)  # -> (job, obs, rx, tx)
        live = np.asarray(tab["k"], float)[:, None] ** 2 / math.pi * stats["live"]
        return TraceResult(
            amplitude, tab["tubes"], stats["casts"], stats["exits"], time.perf_counter() - start, stats["trace_s"], live
        )

    def _trace_batch(self, dev, job_np, local_np, n_obs, max_bounces, radiate, acc, stats):
        mi, dr = self.mi, self.dr
        Float, UInt, V3 = mi.Float, mi.UInt32, mi.Vector3f
        job, local = UInt(job_np), UInt(local_np)
        nu = dr.maximum(dr.gather(UInt, dev["nu"], job), 1)  # >= 1 in every SIMD lane (udiv traps on 0)
        d = dr.gather(Float, dev["d"], job)
        u = dr.gather(Float, dev["u0"], job) + Float(local % nu) * d
        v = dr.gather(Float, dev["v0"], job) + Float(local // nu) * d
        e1, e2 = dr.gather(V3, dev["e1"], job), dr.gather(V3, dev["e2"], job)
        kin = dr.gather(V3, dev["kin"], job)
        radius = dr.gather(Float, dev["radius"], UInt(0))
        zero = V3(0.0)
        st = {
            "job": job,
            "o": -radius * kin + u * e1 + v * e2,
            "dir": kin,
            "a1": d * e1,
            "a2": d * e2,
            "phase_len": -radius + Float(0.0),
            # complex field amplitudes (real, imaginary) for V and H transmit polarisation
            "ev_re": dr.gather(V3, dev["pol_v"], job),
            "ev_im": zero + 0.0,
            "eh_re": dr.gather(V3, dev["pol_h"], job),
            "eh_im": zero + 0.0,
        }
        dr.eval(st)

        def count(mask) -> int:
            return int(dr.count(mask)[0]) if dr.width(mask) else 0

        # The tubes of a bounce are not copied into compact arrays: they are references ``ref`` into the
        # arrays the previous interaction wrote, its reflected branch ``states[0]`` (indices below its
        # width) and transmitted branch ``states[1]`` (indices from its width on), read by the kernels
        # that need them (see _fetch). None: every tube of ``states[0]`` in order.
        states, contribs, ref = [st], None, None
        for bounce in range(1, max_bounces + 1):
            dr.sync_thread()  # launches are asynchronous; time the intersection alone
            t0 = time.perf_counter()
            split = _split_ref(dr, states, ref)
            ray = mi.Ray3f(_fetch(dr, states, split, "o"), _fetch(dr, states, split, "dir"))
            pi = self.scene.ray_intersect_preliminary(ray, coherent=bounce == 1)
            hit = pi.is_valid()
            dr.eval(hit, pi.t, pi.prim_index)
            dr.sync_thread()
            stats["trace_s"] += time.perf_counter() - t0
            n_rays, n_hit = dr.width(hit), count(hit)
            stats["casts"] += n_rays
            stats["exits"][bounce - 1] += n_rays - n_hit
            if contribs is not None and n_hit < n_rays:  # tubes that left after their previous hit radiate there
                out = _split_ref(dr, states, _select(dr, ref, dr.compress(~hit)))
                self._accumulate(
                    acc, _fetch(dr, states, out, "job"), [_fetch(dr, contribs, out, i) for i in range(len(contribs[0]))]
                )
            if n_hit == 0:
                break
            idx = dr.compress(hit)
            ref_hit = _split_ref(dr, states, _select(dr, ref, idx))
            st = {key: _fetch(dr, states, ref_hit, key) for key in states[0]}
            t = dr.gather(Float, pi.t, idx)
            prim = dr.gather(UInt, pi.prim_index, idx)
            silent = None
            if bounce == 1 and dev["clean"] is not None:
                silent = dr.gather(mi.Bool, dev["clean"], st["job"] * dr.opaque(UInt, len(self.target.faces)) + prim)
            contrib, st_r, contrib_t, st_t, has_t, keep = self._interact(dev, st, t, prim, n_obs, silent=silent)
            dr.eval(contrib, st_r, contrib_t, st_t, has_t, keep)  # (the *_t are empty without shells)
            last = bounce == max_bounces
            n_keep, n_through = count(keep), (count(has_t) if self._has_shells else 0)
            # Reflected branches radiate now when every hit radiates, at the last bounce, or when too weak
            # to follow; otherwise their contribution waits for the next trace (exit point).
            if radiate == "all" or last:
                self._accumulate(acc, st_r["job"], contrib)
            elif n_keep < n_hit:
                weak = dr.compress(~keep)
                self._accumulate(acc, dr.gather(UInt, st_r["job"], weak), [dr.gather(Float, c, weak) for c in contrib])
            if last:
                self._live_power(stats, st_r, keep)
                if n_through:
                    self._live_power(stats, st_t, has_t)
                if n_through:
                    through = dr.compress(has_t)
                    self._accumulate(
                        acc, dr.gather(UInt, st_t["job"], through), [dr.gather(Float, c, through) for c in contrib_t]
                    )
                stats["exits"][bounce] += n_keep + n_through
                break
            stats["exits"][bounce] += n_hit - n_keep
            if n_keep + n_through == 0:
                break
            # Thin shells split the tube: the reflected and the transmitted branch both go on.
            states, contribs = ([st_r, st_t], [contrib, contrib_t]) if n_through else ([st_r], [contrib])
            ref = None if n_keep == n_hit and not n_through else dr.compress(keep)
            if n_through:
                ref = _concat(dr, ref, dr.compress(has_t) + dr.opaque(UInt, n_hit))
            if radiate == "all":
                contribs = None

    def _exact_first_hits(self, dev, tab, n_obs, escape_needed, acc, stats):
        """Add the exact single-reflection PO of every fully lit facet; return which facets those are.

        A facet is *fully lit* for a job when its three vertices see the transmitter (a ray from each
        toward it hits nothing), when it faces the transmitter if it belongs to a closed surface
        (:func:`closed_faces`), and, where tubes radiate at their exit point only, when the ray
        reflected from its centroid escapes. Its reflection's PO integral over the whole facet is
        added in closed form (plane-wave incidence, :func:`_simplex_phase_integral`), however few
        tubes hit it: grazing facets near a shadow boundary, which a tube grid samples badly and
        whose currents make the small-ka oscillation of a sphere's RCS, count in full. The tubes
        that hit these facets still reflect on, but their first-hit radiation is left out.

        Returns
        -------
        mi.Bool (J * F,)
            True for (job, facet) pairs integrated here, index ``job * F + facet``.
        """
        mi, dr = self.mi, self.dr
        Float, UInt, V3 = mi.Float, mi.UInt32, mi.Vector3f
        n_faces = len(self.target.faces)
        vertices, faces, normals = self.target.vertices, self.target.faces, self.target.face_normals
        # Jobs that differ only in their grid offset (the replicas of an error estimate) share the result.
        key = np.column_stack([tab["kin"], tab["k"], tab["s"].reshape(len(tab["k"]), -1)])
        _, first, which = np.unique(key, axis=0, return_index=True, return_inverse=True)
        which = which.ravel()
        n_jobs = len(first)
        toward = -np.asarray(tab["kin"], float)[first]  # (U, 3) from the target toward the transmitter
        nudge = 2e-5 * self._radius
        clean = np.zeros((n_jobs, n_faces), bool)
        per = max(1, self.batch_size // max(len(vertices), n_faces))
        for j0 in range(0, n_jobs, per):
            js = np.arange(j0, min(n_jobs, j0 + per))
            w = toward[js]  # (Jc, 3)
            origin = (vertices[None, :, :] + nudge * w[:, None, :]).reshape(-1, 3)
            seen = ~self._occluded(origin, np.repeat(w, len(vertices), axis=0), stats).reshape(len(js), -1)
            cos_w = w @ normals.T  # (Jc, F)
            lit = seen[:, faces].all(axis=2) & (np.abs(cos_w) > 1e-6) & (~self._one_sided[None, :] | (cos_w > 0))
            if escape_needed:
                facing = np.where(cos_w[..., None] > 0, normals[None], -normals[None])  # (Jc, F, 3)
                reflected = 2.0 * np.abs(cos_w)[..., None] * facing - w[:, None, :]
                start = (self._centroid[None] + nudge * facing).reshape(-1, 3)
                escapes = ~self._occluded(start, reflected.reshape(-1, 3), stats).reshape(len(js), -1)
                lit &= escapes
            clean[js] = lit
        unique_acc = np.zeros((n_jobs, acc.shape[1]))
        unique_job, facet = np.nonzero(clean)  # job-major, as _accumulate wants
        for lo in range(0, len(unique_job), self.batch_size):
            u = unique_job[lo : lo + self.batch_size]
            j, f = UInt(first[u].astype(np.uint32)), facet[lo : lo + self.batch_size]
            centre = V3(*(Float(np.asarray(self._centroid[f, i], np.float32)) for i in range(3)))
            kin = dr.gather(V3, dev["kin"], j)
            zero = V3(0.0)
            st = {
                "job": j,
                "o": centre,
                "dir": kin,
                "a1": zero,
                "a2": zero,
                "phase_len": dr.dot(kin, centre),
                "ev_re": dr.gather(V3, dev["pol_v"], j),
                "ev_im": zero + 0.0,
                "eh_re": dr.gather(V3, dev["pol_h"], j),
                "eh_im": zero + 0.0,
            }
            prim = UInt(f.astype(np.uint32))
            contrib = self._interact(
                dev, st, Float(0.0), prim, n_obs, exact_area=dr.gather(Float, self._face_area, prim)
            )[0]
            self._accumulate(unique_acc, UInt(u.astype(np.uint32)), contrib)
        acc += unique_acc[which]
        return mi.Bool(clean[which].ravel())

    def _occluded(self, origin: np.ndarray, direction: np.ndarray, stats) -> np.ndarray:
        """Whether rays (NumPy (R, 3) origins and directions) hit the target, in batches."""
        mi, dr = self.mi, self.dr
        out = np.empty(len(origin), bool)
        for lo in range(0, len(origin), self.batch_size):
            o, d = origin[lo : lo + self.batch_size], direction[lo : lo + self.batch_size]
            ray = mi.Ray3f(
                mi.Point3f(*(mi.Float(np.asarray(o[:, i], np.float32)) for i in range(3))),
                mi.Vector3f(*(mi.Float(np.asarray(d[:, i], np.float32)) for i in range(3))),
            )
            blocked = self.scene.ray_test(ray)
            dr.eval(blocked)
            out[lo : lo + len(o)] = np.asarray(blocked)
        stats["casts"] += len(origin)
        return out

    def _interact(self, dev, st, t, prim, n_obs, exact_area=None, silent=None):
        """Hit-point physics: PO contributions and the reflected (and transmitted) tubes.

        Returns ``(contrib_r, state_r, contrib_t, state_t, has_t, keep_r)``:
        the PO field of the surface currents of the reflection, the reflected
        tube, the aperture field of the transmitted wave on the far side of a
        thin shell, the transmitted tube, where a transmitted tube exists,
        and where the reflected tube is strong enough to follow. Without thin
        shells in the scene the transmitted parts are empty.
        """
        hit = self._hit_frame(dev, st, t, prim)
        r_perp, r_par, t_perp, t_par, slab, pec = self._fresnel(dev, prim, hit)
        refl, trans = [], []
        for pol in ("ev", "eh"):
            e_re, e_im = st[pol + "_re"], st[pol + "_im"]
            r_re, r_im = self._split(hit, e_re, e_im, (r_perp, r_par), hit.par_r)
            u_re, u_im = self._split(hit, e_re, e_im, (t_perp, t_par), hit.par_i)
            # Reflection: eta*J = n x (k_i x E_i + k_r x E_r), M = (E_i + E_r) x n.
            refl.append(
                (
                    self.dr.cross(hit.direction, e_re) + self.dr.cross(hit.dir_r, r_re),
                    self.dr.cross(hit.direction, e_im) + self.dr.cross(hit.dir_r, r_im),
                    e_re + r_re,
                    e_im + r_im,
                    r_re,
                    r_im,
                )
            )
            # Transmission aperture on the far side (normal -n): eta*J = -n x (k x E_t), M = E_t x (-n).
            trans.append(
                (self.dr.cross(hit.direction, u_re), self.dr.cross(hit.direction, u_im), u_re, u_im, u_re, u_im)
            )
        contrib_r, contrib_t = self._po_contributions(dev, st, prim, hit, (refl, trans), n_obs, exact_area, silent)
        keep_r = _tube_power(self.dr, refl) > dev["cutoff"]
        has_t = slab & ~pec & (_tube_power(self.dr, trans) > dev["cutoff"])
        st_r, st_t = self._new_tubes(dev, st, hit, refl, trans)
        if not self._has_shells:
            return contrib_r, st_r, [], {}, self.mi.Bool(), keep_r
        return contrib_r, st_r, contrib_t, st_t, has_t, keep_r

    def _hit_frame(self, dev, st, t, prim) -> _HitFrame:
        """The hit point, the facet's normal toward the ray, the reflected direction and the local TE/TM basis."""
        mi, dr = self.mi, self.dr
        Float, V3 = mi.Float, mi.Vector3f
        job, direction = st["job"], st["dir"]
        p = st["o"] + t * direction
        n = dr.gather(V3, self._face_normal, prim)
        cos_raw = dr.dot(direction, n)
        n = dr.select(cos_raw > 0, -n, n)  # normal facing the incoming ray
        cos_i = dr.maximum(dr.abs(cos_raw), 1e-6)  # cos of incidence angle, >= 0
        phase_len = st["phase_len"] + t
        dir_r = direction + 2.0 * cos_i * n
        k = dr.gather(Float, dev["k"], job)
        # Local TE/TM basis: e_par = k x e_perp for incident and reflected waves.
        perp = dr.cross(direction, n)
        fallback = dr.cross(direction, dr.select(dr.abs(direction.x) < 0.9, V3(1, 0, 0), V3(0, 1, 0)))
        perp = dr.normalize(dr.select(dr.norm(perp) > 1e-6, perp, fallback))
        par_i, par_r = dr.cross(direction, perp), dr.cross(dir_r, perp)
        return _HitFrame(job, direction, p, n, cos_i, phase_len, dir_r, k, perp, par_i, par_r)

    def _fresnel(self, dev, prim, hit: _HitFrame):
        """Reflection and transmission coefficients (TE, TM) of the face material at the job's frequency.

        The interface's Fresnel coefficients, or the slab's where the material is a thin shell (a
        sheet at the slab's mid-plane); -1, +1 and no transmission on a perfect conductor. Returns
        ``(r_perp, r_par, t_perp, t_par, slab, pec)``.
        """
        mi, dr = self.mi, self.dr
        Float, UInt, C = mi.Float, mi.UInt32, mi.Complex2f
        k, cos_i = hit.k, hit.cos_i
        mat = dr.gather(UInt, self._face_material, prim) * dr.opaque(UInt, dev["n_jobs"]) + hit.job
        eps = C(dr.gather(Float, dev["eps_re"], mat), dr.gather(Float, dev["eps_im"], mat))
        thick = dr.gather(Float, dev["thick"], mat)
        pec = dr.gather(mi.Bool, dev["pec"], mat)
        root = dr.sqrt(eps - C(1.0 - cos_i * cos_i, 0.0))
        ccos = C(cos_i, 0.0)
        g_perp = (ccos - root) / (ccos + root)
        g_par = (eps * ccos - root) / (eps * ccos + root)
        # Slab of thickness h, represented by a sheet at its mid-plane (the same from either side):
        # delta = k h sqrt(eps - sin^2), R = G (1 - e^{-2j delta}) e^{+j k h cos} / (1 - G^2 e^{-2j delta})
        # (phase moved from the front face to the mid-plane), T = (1 - G^2) e^{-j delta} e^{+j k h cos} /
        # (1 - G^2 e^{-2j delta}) (phase relative to free space over h).
        delta = root * (k * thick)
        decay = dr.exp(delta.imag)  # |e^{-j delta}| (Im delta <= 0 for a lossy slab)
        s1, c1 = dr.sincos(delta.real)
        e1 = C(decay * c1, -decay * s1)
        e2 = e1 * e1
        s0, c0 = dr.sincos(k * thick * cos_i)
        free = C(c0, s0)
        slab = thick > 0

        def slab_coefficients(g):
            den = C(1.0, 0.0) - g * g * e2
            return g * (C(1.0, 0.0) - e2) * free / den, (C(1.0, 0.0) - g * g) * e1 * free / den

        r_perp, t_perp = slab_coefficients(g_perp)
        r_par, t_par = slab_coefficients(g_par)
        zero = C(0.0, 0.0)
        r_perp = dr.select(pec, C(-1.0, 0.0), dr.select(slab, r_perp, g_perp))
        r_par = dr.select(pec, C(1.0, 0.0), dr.select(slab, r_par, g_par))
        t_perp = dr.select(slab & ~pec, t_perp, zero)
        t_par = dr.select(slab & ~pec, t_par, zero)
        return r_perp, r_par, t_perp, t_par, slab, pec

    def _split(self, hit: _HitFrame, e_re, e_im, coefficients, out_par):
        """Field (re, im) after multiplying the TE and TM components by ``coefficients`` (c_perp, c_par)."""
        dr, perp, par_i = self.dr, hit.perp, hit.par_i
        c_perp, c_par = coefficients
        s_re, s_im = dr.dot(e_re, perp), dr.dot(e_im, perp)
        q_re, q_im = dr.dot(e_re, par_i), dr.dot(e_im, par_i)
        a_re = c_perp.real * s_re - c_perp.imag * s_im
        a_im = c_perp.real * s_im + c_perp.imag * s_re
        b_re = c_par.real * q_re - c_par.imag * q_im
        b_im = c_par.real * q_im + c_par.imag * q_re
        return a_re * perp + b_re * out_par, a_im * perp + b_im * out_par

    def _po_contributions(self, dev, st, prim, hit: _HitFrame, fields, n_obs, exact_area, silent):
        """PO far fields toward every receiver of the reflection's and the transmission's currents.

        Over the tube's footprint on the facet, or over the whole facet where ``exact_area`` is given
        (lit by the incident plane wave); the reflection of a facet integrated exactly elsewhere
        (:meth:`_exact_first_hits`, ``silent``) is left out. Returns ``(contrib_r, contrib_t)``.
        """
        mi, dr = self.mi, self.dr
        Float, V3 = mi.Float, mi.Vector3f
        refl, trans = fields
        job, direction, p, n, cos_i, k = hit.job, hit.direction, hit.p, hit.n, hit.cos_i, hit.k
        area = dr.norm(dr.cross(st["a1"], st["a2"])) / cos_i
        f1 = st["a1"] + (dr.dot(st["a1"], n) / cos_i) * direction  # footprint edges on the facet
        f2 = st["a2"] + (dr.dot(st["a2"], n) / cos_i) * direction
        if exact_area is not None:  # the whole facet, lit by the incident plane wave
            rel0 = dr.gather(V3, self._face_origin, prim) - p
            edge1, edge2 = dr.gather(V3, self._face_edge1, prim), dr.gather(V3, self._face_edge2, prim)
        # the reflection's PO of a facet integrated exactly elsewhere (:meth:`_exact_first_hits`) is left out
        audible = Float(1.0) if silent is None else dr.select(silent, 0.0, 1.0)
        contrib_r, contrib_t = [], []
        sides = ((refl, n, contrib_r), (trans, -n, contrib_t)) if self._has_shells else ((refl, n, contrib_r),)
        for m in range(n_obs):
            o_idx = job * n_obs + m
            s = dr.gather(V3, dev["s"], o_idx)
            th, ph = dr.gather(V3, dev["s_theta"], o_idx), dr.gather(V3, dev["s_phi"], o_idx)
            q = s - direction
            # integral of exp(j k q.(r - p)) [m^2] over the tube's footprint (a parallelogram) or the facet
            if exact_area is None:
                foot_re = area * _sinc(dr, 0.5 * k * dr.dot(q, f1)) * _sinc(dr, 0.5 * k * dr.dot(q, f2))
                foot_im = Float(0.0)
            else:
                g_re, g_im = _simplex_phase_integral(dr, k * dr.dot(q, edge1), k * dr.dot(q, edge2))
                s0, c0 = dr.sincos(k * dr.dot(q, rel0))
                foot_re = 2.0 * exact_area * (c0 * g_re - s0 * g_im)
                foot_im = 2.0 * exact_area * (c0 * g_im + s0 * g_re)
            psi = k * (dr.dot(s, p) - hit.phase_len)
            sin_psi, cos_psi = dr.sincos(psi)
            amp = k * (1.0 / (4.0 * math.pi))
            # -j k (foot e^{j psi}) / (4 pi)
            f_re = amp * (foot_re * sin_psi + foot_im * cos_psi)
            f_im = -amp * (foot_re * cos_psi - foot_im * sin_psi)
            for side_fields, normal, out in sides:
                tn, pn = dr.cross(th, normal), dr.cross(ph, normal)
                w_re, w_im = (f_re * audible, f_im * audible) if out is contrib_r else (f_re, f_im)
                for x_re, x_im, y_re, y_im, _, _ in side_fields:
                    # V_theta = X.(theta x n) - Y.(phi x n);  V_phi = X.(phi x n) + Y.(theta x n)
                    vt_re = dr.dot(x_re, tn) - dr.dot(y_re, pn)
                    vt_im = dr.dot(x_im, tn) - dr.dot(y_im, pn)
                    vp_re = dr.dot(x_re, pn) + dr.dot(y_re, tn)
                    vp_im = dr.dot(x_im, pn) + dr.dot(y_im, tn)
                    out += [
                        w_re * vt_re - w_im * vt_im,
                        w_re * vt_im + w_im * vt_re,
                        w_re * vp_re - w_im * vp_im,
                        w_re * vp_im + w_im * vp_re,
                    ]
        return contrib_r, contrib_t

    def _new_tubes(self, dev, st, hit: _HitFrame, refl, trans):
        """The reflected tube's state and, with thin shells in the scene, the transmitted one's (else None).

        Origins nudged off the surface, path length corrected for the nudge. The nudge is relative to
        the target's bounding radius (>= 20 float32 ulps of any coordinate inside it), so that a scaled
        target at a scaled wavelength traces exactly the same tubes.
        """
        dr, n, p = self.dr, hit.n, hit.p
        nudge = 2e-5 * dr.gather(self.mi.Float, dev["radius"], self.mi.UInt32(0))
        st_r = dict(st)
        st_r.update(
            o=p + nudge * n,
            dir=dr.normalize(hit.dir_r),
            phase_len=hit.phase_len + nudge * hit.cos_i,
            a1=st["a1"] - 2.0 * dr.dot(st["a1"], n) * n,
            a2=st["a2"] - 2.0 * dr.dot(st["a2"], n) * n,
            ev_re=refl[0][4],
            ev_im=refl[0][5],
            eh_re=refl[1][4],
            eh_im=refl[1][5],
        )
        if not self._has_shells:
            return st_r, None
        st_t = dict(st)
        st_t.update(
            o=p - nudge * n,
            phase_len=hit.phase_len + nudge * hit.cos_i,
            ev_re=trans[0][4],
            ev_im=trans[0][5],
            eh_re=trans[1][4],
            eh_im=trans[1][5],
        )
        return st_r, st_t

    def _live_power(self, stats, st, mask) -> None:
        """Add ``|a1 x a2|^2 |E|^2`` (V, H transmit) of the tubes ``mask`` of ``st`` that would hit again to
        ``stats["live"]`` per job.

        These tubes still carry power when the bounce limit stops them: the cross-section squared times
        the power relative to the incident tube is what :class:`TraceResult`'s ``live_sigma_m2`` scales.
        """
        mi, dr = self.mi, self.dr
        idx = dr.compress(mask)
        if dr.width(idx) == 0:
            return
        # alive: its next ray hits the target again (one more cast per stopped tube)
        ray = mi.Ray3f(dr.gather(mi.Vector3f, st["o"], idx), dr.gather(mi.Vector3f, st["dir"], idx))
        hit = self.scene.ray_intersect_preliminary(ray).is_valid()
        dr.eval(hit)
        stats["casts"] += dr.width(hit)
        idx = dr.gather(mi.UInt32, idx, dr.compress(hit))
        if dr.width(idx) == 0:
            return
        job = dr.gather(mi.UInt32, st["job"], idx)
        area2 = dr.squared_norm(dr.cross(dr.gather(mi.Vector3f, st["a1"], idx), dr.gather(mi.Vector3f, st["a2"], idx)))
        powers = [
            area2
            * (
                dr.squared_norm(dr.gather(mi.Vector3f, st[re], idx))
                + dr.squared_norm(dr.gather(mi.Vector3f, st[im], idx))
            )
            for re, im in (("ev_re", "ev_im"), ("eh_re", "eh_im"))
        ]
        dr.eval(job, powers)
        job_np = np.asarray(job)
        for pol, power in enumerate(powers):
            np.add.at(stats["live"][:, pol], job_np, np.asarray(power, dtype=np.float64))

    def _accumulate(self, acc, job, parts):
        """Add contributions (float32, 8 per receiver and tube) to the float64 sums ``acc`` of their jobs.

        ``job`` and ``parts`` hold the radiating tubes only. The sums are taken on the host in a fixed
        order, so that results are bit-for-bit reproducible (device atomics would add in a varying order).
        """
        dr = self.dr
        if dr.width(job) == 0:
            return
        dr.eval(job, parts)  # one kernel for all gathers
        job_np = np.asarray(job)  # (host memory on LLVM: no copy)
        # Tubes are launched job by job and compaction keeps their order, so jobs come in a few long
        # runs (one per job and branch): sum each run, then add the run sums in order.
        starts = np.flatnonzero(np.r_[True, job_np[1:] != job_np[:-1]])
        # columns: receiver, tx (V, H), rx (theta, phi), re/im; one float32 row at a time, summed in float64
        sums = np.stack([np.add.reduceat(np.asarray(v), starts, dtype=np.float64) for v in parts], axis=1)
        np.add.at(acc, job_np[starts], sums)


def _select(dr, ref, index):
    """``ref[index]`` for tube references (``ref`` None: the identity)."""
    return index if ref is None else dr.gather(type(ref), ref, index)


def _fetch(dr, sources, ref, key):
    """Entry ``key`` of the tubes ``ref`` of the concatenation of ``sources`` (one or two dicts or lists).

    ``ref`` is None (all of ``sources[0]`` in order), an index array into ``sources[0]``, or, with two
    sources, the tuple returned by :func:`_split_ref`. The gathers stay lazy, so the tubes are read inside
    the kernel that uses them instead of being copied.
    """
    first = sources[0][key]
    kind = type(first)
    if ref is None:
        return first
    if len(sources) == 1:
        return dr.gather(kind, first, ref)
    in_first, in_second, index_first, index_second = ref
    return dr.select(
        in_second,
        dr.gather(kind, sources[1][key], index_second, in_second),
        dr.gather(kind, first, index_first, in_first),
    )


def _split_ref(dr, sources, ref):
    """Tube references into two concatenated state dicts as (in first, in second, index in first, in second)."""
    if ref is None or len(sources) == 1:
        return ref
    width = dr.opaque(type(ref), dr.width(sources[0]["job"]))  # opaque: no recompilation per width
    in_second = ref >= width
    return ~in_second, in_second, ref, ref - width


def _concat(dr, a, b):
    """Concatenate two Dr.Jit arrays (scalar or 3-vector) along the ray axis."""
    if dr.width(a) == 0:
        return b
    if dr.width(b) == 0:
        return a
    if dr.size_v(a) == 3:
        return type(a)(*(dr.concat([a[i], b[i]]) for i in range(3)))
    return dr.concat([a, b])


@dataclass(frozen=True)
class _HitFrame:
    """Where and how a tube hits a facet (Dr.Jit arrays, one per tube).

    ``job``, the incident ``direction``, hit point ``p``, the facet's normal ``n`` facing the ray,
    ``cos_i`` the cosine of incidence, ``phase_len`` the path length to ``p`` [m], ``dir_r`` the
    reflected direction, ``k`` the wavenumber [rad/m], and the TE/TM basis ``perp``, ``par_i``,
    ``par_r`` (e_par = k x e_perp of the incident and reflected waves).
    """

    job: object
    direction: object
    p: object
    n: object
    cos_i: object
    phase_len: object
    dir_r: object
    k: object
    perp: object
    par_i: object
    par_r: object


def _tube_power(dr, fields):
    """The larger of the V- and H-transmit powers |E|^2 of a tube's field (per tube)."""
    return dr.maximum(
        dr.squared_norm(fields[0][4]) + dr.squared_norm(fields[0][5]),
        dr.squared_norm(fields[1][4]) + dr.squared_norm(fields[1][5]),
    )


def _sinc(dr, x):
    """sin(x)/x, 1 at x = 0."""
    small = dr.abs(x) < 1e-4
    return dr.select(small, 1.0 - x * x * (1.0 / 6.0), dr.sin(x) / dr.select(small, 1.0, x))


def _phase_mean(dr, x):
    """E(x) = (exp(jx) - 1)/(jx), the mean of exp(j x t) over t in [0, 1], as (re, im): (sinc x, x/2 sinc^2(x/2))."""
    half = _sinc(dr, 0.5 * x)
    return _sinc(dr, x), 0.5 * x * half * half


def _phase_mean_slope(dr, x):
    """dE/dx = j * mean of t exp(j x t) over [0, 1], as (re, im); Taylor series below |x| = 0.1."""
    small = dr.abs(x) < 0.1
    xs = dr.select(small, 1.0, x)
    sin_x, cos_x = dr.sincos(xs)
    # j [exp(jx)/(jx) - (exp(jx) - 1)/(jx)^2] = [x exp(jx) + j (exp(jx) - 1)] / x^2, in real and imaginary parts:
    exact_re = (cos_x * xs - sin_x) / (xs * xs)
    exact_im = (sin_x * xs + cos_x - 1.0) / (xs * xs)
    x2 = x * x
    series_re = -x / 3.0 + x2 * x / 30.0
    series_im = 0.5 - x2 / 8.0 + x2 * x2 / 144.0
    return dr.select(small, series_re, exact_re), dr.select(small, series_im, exact_im)


def _simplex_phase_integral(dr, a, b):
    """Integral of exp(j(a u + b v)) over the unit simplex (1/2 at a = b = 0), as (re, im).

    The second divided difference of exp(jx) (Hermite-Genocchi): -j (E(a) - E(b)) / (a - b), and
    -j dE/dx at the midpoint when |a - b| < 0.01 (float32 cancellation); E from :func:`_phase_mean`.
    """
    ea_re, ea_im = _phase_mean(dr, a)
    eb_re, eb_im = _phase_mean(dr, b)
    diff = a - b
    close = dr.abs(diff) < 0.01
    inv = 1.0 / dr.select(close, 1.0, diff)
    slope_re, slope_im = _phase_mean_slope(dr, 0.5 * (a + b))
    d_re = dr.select(close, slope_re, (ea_re - eb_re) * inv)
    d_im = dr.select(close, slope_im, (ea_im - eb_im) * inv)
    return d_im, -d_re  # -j (d_re + j d_im)


def _hull_points(vertices: np.ndarray) -> np.ndarray:
    """Vertices of the convex hull (all vertices when the hull is degenerate, e.g. a plate)."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        return vertices[ConvexHull(vertices).vertices]
    except (QhullError, ValueError):
        return vertices
