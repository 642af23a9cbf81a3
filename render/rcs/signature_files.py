"""Files of a :class:`csuas.render.rcs.signature.SignatureTable` in the layouts other tools load.

The format follows the file's suffix (:data:`FORMATS`); every file is written whole or not at all
(:func:`csuas.base.fileio.atomic_path`).

* ``.mat`` -- MATLAB's ``rcsSignature`` (Radar Toolbox / Sensor Fusion and Tracking Toolbox,
  R2021a and later): ``pattern`` [dBsm] is elevation x azimuth x frequency (Q x P x K), with the
  row vectors ``azimuth`` and ``elevation`` [deg] and ``frequency`` [Hz]. ``pattern`` holds the
  first polarisation of the table (VV by default); ``pattern_VV``, ``pattern_HH``, ... every one,
  ``bound_db_<pol>`` their bounds [dB] with the terms ``discretisation_db_<pol>``,
  ``truncation_db_<pol>`` and ``model_db`` (1 x K, PO's model term). Loaded in MATLAB by::

      s = load('table.mat');
      sig = rcsSignature('Pattern', s.pattern, 'Azimuth', s.azimuth, ...
                         'Elevation', s.elevation, 'Frequency', s.frequency);

* ``.csv`` -- one row per azimuth, elevation, frequency and polarisation, the per-degree monostatic
  layout proposed for the Open Simulation Interface (OSI issue #251, "add RCS to
  VehicleAttributes": monostatic RCS tabulated over the viewing angle, typically in 1-degree
  steps): columns :data:`CSV_COLUMNS`, angles in the object's body frame, azimuth fastest.
* ``.nc`` -- NetCDF 3 (classic, through :class:`scipy.io.netcdf_file`, so that no netCDF library is
  needed), variables ``rcs_dbsm``, ``bound_db``, ``discretisation_db`` and ``truncation_db`` on the dimensions
  (polarisation, frequency, elevation, azimuth), ``model_db`` on (frequency), every variable with a
  ``units`` attribute; ``xarray.open_dataset(path)`` reads it with its scipy engine.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path

import numpy as np

from csuas.base.errors import ParameterError
from csuas.base.fileio import atomic_path, write_text_atomic

#: Columns of the CSV layout, in order.
CSV_COLUMNS = (
    "azimuth_deg",
    "elevation_deg",
    "frequency_ghz",
    "polarisation",
    "rcs_dbsm",
    "bound_db",
    "discretisation_db",
    "model_db",
    "truncation_db",
)

#: What each file says about the method, in its metadata.
SOURCE = "csuas rcs-table: SBR-PO (shooting and bouncing rays, physical optics), monostatic"


def write_mat(table, path) -> None:
    """MATLAB ``rcsSignature`` layout (module docstring), through :func:`scipy.io.savemat`."""
    from scipy.io import savemat

    def qpk(values):  # (K, Q, P) -> (Q, P, K)
        return np.transpose(values, (1, 2, 0))

    data = {
        "pattern": qpk(table.rcs_dbsm[0]),
        "azimuth": table.azimuth_deg,
        "elevation": table.elevation_deg,
        "frequency": table.frequency_ghz * 1e9,
        "model_db": table.model_db,
        "polarisations": np.array(table.polarisations, dtype=object),
        "target": table.target,
        "quality": table.quality,
        "source": SOURCE,
    }
    for i, pol in enumerate(table.polarisations):
        data[f"pattern_{pol}"] = qpk(table.rcs_dbsm[i])
        data[f"bound_db_{pol}"] = qpk(table.bound_db[i])
        data[f"discretisation_db_{pol}"] = qpk(table.discretisation_db[i])
        data[f"truncation_db_{pol}"] = qpk(table.truncation_db[i])
    with atomic_path(path) as tmp:
        savemat(tmp, data, oned_as="row")


def csv_text(table) -> str:
    """The CSV layout (module docstring); floats in full precision (``repr``), ``inf`` for no bound."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    for i, pol in enumerate(table.polarisations):
        for k, f in enumerate(table.frequency_ghz):
            for q, el in enumerate(table.elevation_deg):
                for p, az in enumerate(table.azimuth_deg):
                    writer.writerow(
                        [
                            repr(float(az)),
                            repr(float(el)),
                            repr(float(f)),
                            pol,
                            repr(float(table.rcs_dbsm[i, k, q, p])),
                            repr(float(table.bound_db[i, k, q, p])),
                            repr(float(table.discretisation_db[i, k, q, p])),
                            repr(float(table.model_db[k])),
                            repr(float(table.truncation_db[i, k, q, p])),
                        ]
                    )
    return out.getvalue()


def write_csv(table, path) -> None:
    """Write :func:`csv_text` atomically."""
    write_text_atomic(path, csv_text(table))


def _variable(nc, name, dims, values, units: str, long_name: str) -> None:
    var = nc.createVariable(name, "f8", dims)
    var[:] = values
    var.units = units
    var.long_name = long_name


def write_netcdf(table, path) -> None:
    """NetCDF 3 layout (module docstring), through :class:`scipy.io.netcdf_file`."""
    from scipy.io import netcdf_file

    grid = ("polarisation", "frequency", "elevation", "azimuth")
    with atomic_path(path) as tmp:
        nc = netcdf_file(tmp, "w")
        try:
            nc.title = f"Monostatic RCS of {table.target}"
            nc.source = SOURCE
            nc.quality = table.quality
            nc.rays_per_wavelength = float(table.rays_per_wavelength)
            nc.max_bounces = int(table.max_bounces)
            for dim, size in zip(grid, table.rcs_dbsm.shape):
                nc.createDimension(dim, size)
            nc.createDimension("name_length", 2)
            pol = nc.createVariable("polarisation", "c", ("polarisation", "name_length"))
            pol[:] = np.array([list(p) for p in table.polarisations], "S1")
            pol.long_name = "receive and transmit polarisation (V: theta-hat, H: phi-hat)"
            _variable(nc, "frequency", ("frequency",), table.frequency_ghz, "GHz", "radar frequency")
            _variable(nc, "elevation", ("elevation",), table.elevation_deg, "degree", "elevation of target -> radar")
            _variable(nc, "azimuth", ("azimuth",), table.azimuth_deg, "degree", "azimuth of target -> radar from +x")
            _variable(nc, "rcs_dbsm", grid, table.rcs_dbsm, "dBsm", "monostatic radar cross-section")
            _variable(nc, "bound_db", grid, table.bound_db, "dB", "bound against the exact answer")
            _variable(nc, "discretisation_db", grid, table.discretisation_db, "dB", "bound against physical optics")
            _variable(nc, "truncation_db", grid, table.truncation_db, "dB", "bounce limit's truncation term")
            _variable(nc, "model_db", ("frequency",), table.model_db, "dB", "physical optics' model error bound")
        finally:
            nc.close()


#: File suffix -> writer.
FORMATS = {".mat": write_mat, ".csv": write_csv, ".nc": write_netcdf}


def check_suffix(path) -> str:
    """The format's suffix of ``path``; ParameterError ``out`` for any other."""
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        raise ParameterError("out", str(path), "a file ending in " + ", ".join(FORMATS))
    return suffix


def write_signature(table, path) -> None:
    """Write ``table`` in the format of ``path``'s suffix (:data:`FORMATS`)."""
    FORMATS[check_suffix(path)](table, path)
