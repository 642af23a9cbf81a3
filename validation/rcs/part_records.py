"""Dated EFIE references of PEC cylinders and the DJI Mini 4 Pro's arm with its motor (2026-11-27).

Written from runs of :func:`csuas.validation.rcs.part_references.efie_reference` (bempp-cl 0.4, numba, 2
shared CPU cores; ``load_average`` the 1-minute load before and after the case). Per case: the frequency
[GHz], the aspects (azimuth, elevation) [deg], the elements, RWG unknowns and mean edges per wavelength of
the fine and the coarse mesh, their mean-edge ratio, the fine mesh's EFIE RCS [dBsm], Richardson's
extrapolation of the two (the reference) [dBsm] and its correction as a larger-side error [dB] (the
reference's own error), and the EFIE's wall time [s] (both meshes; the first case includes about 35 s of
numba compilation). The cylinders' fine meshes have cells of lambda/10 (mean edges 8.8 per wavelength with
the diagonals); the arm's cells are at most 4 mm (11.6 and 28 mean edges per wavelength at 5.8 and 2.4 GHz).
"""

import math

PART_RECORDS = {
    "cylinder_r0.25_l2": {
        "date": "2026-11-27",
        "frequency_ghz": 10.0,
        "aspects_deg": [
            (7.0, 0.0),
            (7.0, 10.0),
            (7.0, 20.0),
            (7.0, 30.0),
            (7.0, 45.0),
            (7.0, 60.0),
            (7.0, 75.0),
            (7.0, 90.0),
        ],
        "elements": (704, 408),
        "unknowns": (1056, 612),
        "edges_per_wavelength": (8.83, 6.76),
        "edge_ratio": 1.3061,
        "efie_dbsm": {
            "VV": [-21.9872, -28.8987, -36.1812, -65.8602, -35.9678, -31.5231, -39.5832, -30.0268],
            "HH": [-25.3447, -31.7502, -39.2322, -36.7438, -35.6936, -34.4542, -35.2232, -30.0268],
        },
        "reference_dbsm": {
            "VV": [-21.9337, -28.9383, -36.2169, -69.4111, -35.9026, -31.469, -38.7646, -29.615],
            "HH": [-25.1771, -31.5909, -39.1333, -36.9093, -35.4601, -34.7521, -34.5718, -29.615],
        },
        "reference_error_db": {
            "VV": [0.0529, 0.0396, 0.0357, 3.5509, 0.0642, 0.0534, 0.6885, 0.3761],
            "HH": [0.1614, 0.1537, 0.0968, 0.1655, 0.2216, 0.2979, 0.5664, 0.3761],
        },
        "efie_s": 202.3,
        "load_average": (0.8, 5.8),
    },
    "cylinder_r0.5_l1": {
        "date": "2026-11-27",
        "frequency_ghz": 10.0,
        "aspects_deg": [
            (7.0, 0.0),
            (7.0, 10.0),
            (7.0, 20.0),
            (7.0, 30.0),
            (7.0, 45.0),
            (7.0, 60.0),
            (7.0, 75.0),
            (7.0, 90.0),
        ],
        "elements": (956, 550),
        "unknowns": (1434, 825),
        "edges_per_wavelength": (8.97, 6.81),
        "edge_ratio": 1.3163,
        "efie_dbsm": {
            "VV": [-25.1567, -26.3415, -29.7935, -47.8083, -36.2329, -28.2429, -24.2012, -20.5413],
            "HH": [-25.1702, -26.7752, -31.3924, -37.6471, -38.9417, -33.9182, -24.1088, -20.5415],
        },
        "reference_dbsm": {
            "VV": [-25.1776, -26.4058, -29.8139, -47.4214, -36.0706, -28.3022, -24.2011, -20.4572],
            "HH": [-25.0449, -26.7064, -31.5222, -38.288, -39.4925, -34.3945, -24.1083, -20.4576],
        },
        "reference_error_db": {
            "VV": [0.0209, 0.0643, 0.0205, 0.3553, 0.1564, 0.0593, 0.0001, 0.0825],
            "HH": [0.1217, 0.0676, 0.1297, 0.641, 0.5508, 0.4764, 0.0006, 0.0822],
        },
        "efie_s": 473.5,
        "load_average": (5.8, 13.8),
    },
    "cylinder_r0.35_l1.5": {
        "date": "2026-11-27",
        "frequency_ghz": 10.0,
        "aspects_deg": [
            (7.0, 0.0),
            (7.0, 10.0),
            (7.0, 20.0),
            (7.0, 30.0),
            (7.0, 45.0),
            (7.0, 60.0),
            (7.0, 75.0),
            (7.0, 90.0),
        ],
        "elements": (792, 416),
        "unknowns": (1188, 624),
        "edges_per_wavelength": (8.74, 6.35),
        "edge_ratio": 1.3764,
        "efie_dbsm": {
            "VV": [-21.9622, -26.5234, -54.1698, -42.5047, -43.6552, -29.7115, -28.2273, -24.3027],
            "HH": [-22.3129, -27.2846, -40.7426, -34.2914, -53.9774, -33.253, -26.5338, -24.3031],
        },
        "reference_dbsm": {
            "VV": [-21.9372, -26.4698, -53.1453, -43.8033, -43.2564, -29.5325, -28.0089, -24.1148],
            "HH": [-22.3003, -27.3456, -40.2528, -34.4114, -53.9774, -33.0471, -26.3494, -24.1157],
        },
        "reference_error_db": {
            "VV": [0.0248, 0.053, 0.8284, 1.2986, 0.3652, 0.1719, 0.2079, 0.1801],
            "HH": [0.0126, 0.061, 0.4401, 0.12, math.inf, 0.1966, 0.1769, 0.1796],
        },
        "efie_s": 560.9,
        "load_average": (13.8, 12.8),
    },
    "arm_motor_5.8ghz": {
        "date": "2026-11-27",
        "frequency_ghz": 5.8,
        "aspects_deg": [
            (90.0, 0.0),
            (90.0, 20.0),
            (0.0, 90.0),
            (0.0, 0.0),
            (180.0, 0.0),
            (45.0, 30.0),
            (135.0, 10.0),
            (270.0, 45.0),
        ],
        "elements": (848, 504),
        "unknowns": (1272, 756),
        "edges_per_wavelength": (11.87, 9.12),
        "edge_ratio": 1.3014,
        "efie_dbsm": {
            "VV": [-22.3402, -20.6227, -16.9375, -28.773, -30.2538, -33.0649, -30.8865, -17.2993],
            "HH": [-18.6761, -18.6237, -15.8994, -25.9926, -25.8633, -39.9857, -30.1242, -18.0968],
        },
        "reference_dbsm": {
            "VV": [-22.5048, -20.7091, -16.9164, -29.0322, -30.7091, -33.1387, -31.2002, -17.2817],
            "HH": [-18.7126, -18.6581, -15.9046, -26.1417, -26.0998, -40.5065, -30.3261, -18.0909],
        },
        "reference_error_db": {
            "VV": [0.1645, 0.0864, 0.0209, 0.2592, 0.4552, 0.0738, 0.3137, 0.0176],
            "HH": [0.0365, 0.0344, 0.0052, 0.1491, 0.2365, 0.5208, 0.2019, 0.0059],
        },
        "efie_s": 1222.0,
        "load_average": (13.1, 10.4),
    },
}
