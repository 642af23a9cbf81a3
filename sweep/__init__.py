"""Sweeps over scenario parameters and simulator settings, in one process or on a Dask cluster (docs/sweeps.md).

>>> from csuas.sweep import load_spec, run_sweep
>>> run_sweep(load_spec("range_rain"), "out", scheduler="serial")["results"]
'out/results.parquet'
"""

from csuas.sweep.run import read_results, run_sweep
from csuas.sweep.spec import load_spec, parse_spec

__all__ = ["load_spec", "parse_spec", "run_sweep", "read_results"]
