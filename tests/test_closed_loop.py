"""Closing the loop (validation/imaging/closed_loop.py): a matched filter on rendered noisy frames."""

from __future__ import annotations

import pytest

from csuas.validation.imaging.closed_loop import closed_loop_pd


@pytest.mark.slow
def test_empirical_pd_of_the_matched_filter_follows_its_prediction_and_falls_with_range():
    rows = closed_loop_pd([300.0, 600.0, 900.0], illuminance_lx=0.5, trials=3000)
    for row in rows:
        # the Gaussian prediction, up to 3 binomial standard errors and the Poisson skew (measured <= 0.049)
        assert abs(row["pd_empirical"] - row["pd_matched_filter"]) <= 3 * row["pd_empirical_stderr"] + 0.06
    pd = [row["pd_empirical"] for row in rows]
    assert pd[0] > 0.99 and pd[0] > pd[1] > pd[2] > 0.01  # the noise-limited fall the TTPF does not see
    assert rows[0]["pd_ttpf"] < 1.0 and rows[2]["pd_empirical"] < rows[2]["pd_ttpf"] + 0.1
