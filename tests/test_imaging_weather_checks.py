"""The report's weather checks (validation/imaging/weather.py): the renders' path against Koschmieder, Beer-Lambert
with path radiance and a Mitsuba fog slab, at draft quality (about 30 s on 2 busy CPU cores)."""

from __future__ import annotations

import pytest

from csuas.render.imaging.records import Daylight
from csuas.validation.imaging.weather import plate_contrast_closed_form, weather_checks


def test_the_plate_contrast_closed_form_by_hand():
    # E_v = 70 klx, 15 % diffuse, sun at 45 deg behind the sensor, ground 0.2: the vertical plate receives
    # 0.85 E (sun) + 0.075 E (half the sky) + 0.1 E (half the ground) = 1.025 E; L = 0.05 * 1.025 E / pi
    # against the sky's 0.15 E / pi
    assert plate_contrast_closed_form(Daylight(), 0.05) == pytest.approx((0.05 * 1.025 - 0.15) / 0.15, rel=1e-12)


@pytest.mark.slow
def test_weather_checks_pass_within_their_monte_carlo_errors():
    checks, rows, elapsed = weather_checks("draft")
    names = [c.name for c in checks]
    assert len(names) == len(set(names)) == 18 and elapsed > 0
    for check in checks:
        # the participating medium's comparisons where the analytic path is an approximation state the difference
        assert check.ok or check.limitation, check.as_dict()
        assert check.error_estimate is not None and check.time_s > 0
    assert sum(name.startswith("imaging.weather.thermal_fog.") for name in names) == 2
    assert sum(name.startswith("imaging.weather.confuser_fog.") for name in names) == 2
    # the fog really attenuates: 400 m in 500 m visibility leaves exp(-3.912 * 0.8) = 4.4 % of the contrast
    assert rows[-1, 3] / rows[0, 3] == pytest.approx(2.718281828 ** (-3.912023 / 0.5 * 0.3), rel=1e-6)
