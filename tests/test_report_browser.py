"""The report's HTML opens in a real browser: a headless Chromium screenshot shows the page and its plots.

Skipped when no Chromium is installed (Debian: ``apt-get install chromium``, which tools/setup.sh does).
"""

import shutil
import subprocess

import numpy as np
import pytest
from waiting import PATIENCE_S

from csuas.base.checks import Check
from csuas.validation.report import checks_conventions, runner
from csuas.validation.report.checks_conventions import SPECS as CONVENTION_SPECS
from csuas.validation.report.registry import CheckSpec, Section

BROWSER = next((shutil.which(b) for b in ("chromium", "chromium-browser", "google-chrome") if shutil.which(b)), None)


def _plots(_knob):
    from csuas.validation.report.figures import PlotAxes, curves, image

    x = np.linspace(1.0, 10.0, 50)
    rgb = np.zeros((16, 16, 3))
    rgb[4:12, 4:12, 0] = 1.0  # a red square
    return Section(
        outcomes=[Check("browser.figure", 1.0, 1.0, 0.1)],
        figures=[
            curves("browser_curve", "a plot", axes=PlotAxes("x", "y"), lines=[("x^2", x, x * x)]),
            image("browser_image", "an image", rgb),
        ],
    )


@pytest.mark.skipif(BROWSER is None, reason="no Chromium installed")
def test_report_html_renders_in_headless_chromium(tmp_path):
    spec = CheckSpec("browser.plots", "plots for the browser", checks_conventions.GROUP, "-", "-", _plots)
    specs = [spec] + [s for s in CONVENTION_SPECS if s.name in ("conv.6", "conv.7")]
    runner.run_report("quick", tmp_path / "r", specs=specs)
    shot = tmp_path / "shot.png"
    subprocess.run(
        [
            BROWSER,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--disable-component-update",
            "--no-first-run",
            f"--screenshot={shot}",
            "--window-size=1400,3000",
            (tmp_path / "r" / "report.html").resolve().as_uri(),
        ],
        check=True,
        capture_output=True,
        timeout=PATIENCE_S,  # ends a hung browser only; a loaded machine just takes longer
    )
    from matplotlib import image as mpimg

    pixels = mpimg.imread(shot)[..., :3]
    assert pixels.shape[:2] == (3000, 1400)
    assert pixels.std() > 0.05, "blank page"
    red = (pixels[..., 0] > 0.9) & (pixels[..., 1] < 0.1) & (pixels[..., 2] < 0.1)
    assert red.sum() > 1000, "the embedded image is not displayed"
    blue_line = (pixels[..., 2] > 0.6) & (pixels[..., 0] < 0.3)  # matplotlib's C0 curve and the links
    assert blue_line.sum() > 200, "the embedded plot is not displayed"
