"""``csuas rcs-table``: per-aspect RCS tables in MATLAB, OSI CSV and NetCDF layouts, read back by other readers.

Round trips read each file with an independent reader (scipy.io.loadmat, the csv module,
scipy.io.netcdf_file) and compare with the computed table; the sphere's cells are judged against the
closed-form PO sphere (Knott et al. ch. 5) within their discretisation bound and against the exact
Mie series within their total bound.
"""

from __future__ import annotations

import csv
import json
import math

import numpy as np
import pytest

from csuas.cli import main
from csuas.render.rcs import canonical
from csuas.render.rcs.signature import azimuth_axis, signature_table
from csuas.render.rcs.signature_files import CSV_COLUMNS, write_signature
from csuas.validation.rcs.fullwave_checks import mie_pec_over_pia2

C = 299_792_458.0
RADIUS_M = 0.05
F_GHZ = 10.0


def _po_sphere_over_pia2(ka: float) -> float:
    """Closed-form PO sphere, sigma / (pi a^2) = |(e^{-jx}(1 + jx) - 1) / x|^2, x = 2 ka (Knott et al., ch. 5)."""
    x = 2.0 * ka
    return abs((np.exp(-1j * x) * (1 + 1j * x) - 1) / x) ** 2


@pytest.fixture(scope="module")
def plate_table():
    return signature_table(
        canonical.plate(0.06, 0.04),
        azimuth_axis(90.0),
        [-60.0, 0.0, 45.0, 90.0],
        [9.0, 12.0],
        polarisations=("VV", "HH", "HV"),
        quality="draft",
    )


def test_azimuth_axis_spans_minus_to_plus_180_and_rejects_steps_not_dividing_360():
    assert azimuth_axis(90.0).tolist() == [-180.0, -90.0, 0.0, 90.0, 180.0]
    with pytest.raises(Exception, match="azimuth_step_deg"):
        azimuth_axis(7.0)


def test_table_repeats_the_minus_180_column_at_plus_180(plate_table):
    assert plate_table.rcs_dbsm.shape == (3, 2, 4, 5)
    np.testing.assert_array_equal(plate_table.rcs_dbsm[..., 0], plate_table.rcs_dbsm[..., -1])
    # plate at normal incidence: 4 pi A^2 / lambda^2 (Knott et al. ch. 5), within the discretisation bound
    for k, f in enumerate(plate_table.frequency_ghz):
        exact = 10 * math.log10(4 * math.pi * (0.06 * 0.04) ** 2 / (C / (f * 1e9)) ** 2)
        err = abs(plate_table.rcs_dbsm[0, k, 3, 2] - exact)
        assert err <= plate_table.discretisation_db[0, k, 3, 2]


def test_mat_round_trip_in_rcssignature_layout(plate_table, tmp_path):
    from scipy.io import loadmat

    path = tmp_path / "plate.mat"
    write_signature(plate_table, path)
    data = loadmat(path)
    # rcsSignature: Pattern Q x P x K (elevation x azimuth x frequency), Frequency in Hz
    assert data["pattern"].shape == (4, 5, 2)
    np.testing.assert_array_equal(data["pattern"], np.transpose(plate_table.rcs_dbsm[0], (1, 2, 0)))
    np.testing.assert_array_equal(data["pattern_HV"], np.transpose(plate_table.rcs_dbsm[2], (1, 2, 0)))
    np.testing.assert_array_equal(data["bound_db_HH"], np.transpose(plate_table.bound_db[1], (1, 2, 0)))
    np.testing.assert_array_equal(data["truncation_db_VV"], np.transpose(plate_table.truncation_db[0], (1, 2, 0)))
    np.testing.assert_array_equal(data["azimuth"], [plate_table.azimuth_deg])
    np.testing.assert_array_equal(data["elevation"], [plate_table.elevation_deg])
    np.testing.assert_array_equal(data["frequency"], [[9e9, 12e9]])


def test_csv_round_trip_one_row_per_cell(plate_table, tmp_path):
    path = tmp_path / "plate.csv"
    write_signature(plate_table, path)
    with open(path, newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert tuple(rows[0]) == CSV_COLUMNS and len(rows) == plate_table.rcs_dbsm.size
    pols = list(plate_table.polarisations)
    for row in rows:
        i = pols.index(row["polarisation"])
        k = list(plate_table.frequency_ghz).index(float(row["frequency_ghz"]))
        q = list(plate_table.elevation_deg).index(float(row["elevation_deg"]))
        p = list(plate_table.azimuth_deg).index(float(row["azimuth_deg"]))
        assert float(row["rcs_dbsm"]) == plate_table.rcs_dbsm[i, k, q, p]
        assert float(row["bound_db"]) == plate_table.bound_db[i, k, q, p]
        assert float(row["discretisation_db"]) == plate_table.discretisation_db[i, k, q, p]
        assert float(row["model_db"]) == plate_table.model_db[k]
        assert float(row["truncation_db"]) == plate_table.truncation_db[i, k, q, p]


def test_netcdf_round_trip_with_units(plate_table, tmp_path):
    from scipy.io import netcdf_file

    path = tmp_path / "plate.nc"
    write_signature(plate_table, path)
    with netcdf_file(path, "r", mmap=False) as nc:
        assert nc.variables["rcs_dbsm"].dimensions == ("polarisation", "frequency", "elevation", "azimuth")
        np.testing.assert_array_equal(nc.variables["rcs_dbsm"][:], plate_table.rcs_dbsm)
        np.testing.assert_array_equal(nc.variables["bound_db"][:], plate_table.bound_db)
        np.testing.assert_array_equal(nc.variables["truncation_db"][:], plate_table.truncation_db)
        np.testing.assert_array_equal(nc.variables["azimuth"][:], plate_table.azimuth_deg)
        np.testing.assert_array_equal(nc.variables["frequency"][:], plate_table.frequency_ghz)
        assert [b"".join(p).decode() for p in nc.variables["polarisation"][:]] == ["VV", "HH", "HV"]
        units = {name: var.units.decode() for name, var in nc.variables.items() if name != "polarisation"}
    assert units["rcs_dbsm"] == "dBsm" and units["bound_db"] == "dB" and units["frequency"] == "GHz"
    assert units["azimuth"] == units["elevation"] == "degree"


def test_cli_sphere_table_against_po_and_mie(tmp_path, capsys):
    mesh = tmp_path / "sphere.ply"
    canonical.sphere(RADIUS_M, subdivisions=5).export(mesh)
    out = tmp_path / "sphere.csv"
    argv = ["rcs-table", str(mesh), "--out", str(out), "--azimuth-step-deg", "90", "--elevation-deg", "-45", "0", "60"]
    assert main([*argv, "--frequency-ghz", str(F_GHZ), "--polarisations", "VV", "HH", "--json"]) == 0
    result = json.loads(capsys.readouterr().out)
    assert result["cells"] == 2 * 3 * 5 and result["written"] == str(out)
    ka = 2 * math.pi * RADIUS_M / (C / (F_GHZ * 1e9))
    po = 10 * math.log10(math.pi * RADIUS_M**2 * _po_sphere_over_pia2(ka))
    mie = 10 * math.log10(math.pi * RADIUS_M**2 * mie_pec_over_pia2(ka))
    with open(out, newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 30
    for row in rows:
        # faceting (5120... 20480 triangles) adds a small error beyond the tube grid's: 0.05 dB allowed
        assert abs(float(row["rcs_dbsm"]) - po) <= float(row["discretisation_db"]) + 0.05
        assert abs(float(row["rcs_dbsm"]) - mie) <= float(row["bound_db"])


def test_cli_refuses_above_max_seconds_with_the_estimate(tmp_path, capsys):
    code = main(
        ["rcs-table", "dji_mini_4_pro", "--out", str(tmp_path / "t.mat"), "--frequency-ghz", "35", "--max-seconds", "1"]
    )
    err = capsys.readouterr().err
    assert code == 2 and "max_seconds" in err and "estimated" in err
    assert not (tmp_path / "t.mat").exists()


def test_cli_rejects_unknown_suffix_and_bad_grid_at_once(tmp_path, capsys):
    code = main(
        [
            "rcs-table",
            "dji_mini_4_pro",
            "--out",
            str(tmp_path / "t.xlsx"),
            "--azimuth-step-deg",
            "7",
            "--elevation-deg",
            "95",
            "--max-bounces",
            "0",
        ]
    )
    err = capsys.readouterr().err
    assert code == 2 and "out" in err and "azimuth_step_deg" in err and "elevation_deg" in err
    assert "max_bounces" in err
