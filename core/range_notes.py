"""Notes ``csuas range`` attaches to a sensor's predicted range: what a reader of the figure should know.

Today one note: Table 39's default radar reaches only tens of metres because Table 44's losses and its
small default target apply (Section 4.9.3 of the paper prints 445.3 m for another radar). Shown for a
radar at the ``default`` preset whose link budget the scenario did not change (:data:`RADAR_BUDGET_KEYS`).
Read by ``csuas range`` (each sensor's ``notes``) and the ``range`` and ``pd`` sweep jobs (``notes.SENSOR``).
"""

from __future__ import annotations

#: Why Table 39's default radar reaches only tens of metres (shown for radars at the default preset).
DEFAULT_RADAR_NOTE = (
    "Table 39's default radar (10 W, 25 dB, 200 MHz, 10 pulses integrated coherently) loses Table 44's "
    "13 dB (10 dB hardware + 3 dB processing, a factor 10^(-13/40) = 0.47 on the range): 47 m on the "
    "default 0.01 m^2 target (100 m without the losses, 56 m with neither losses nor integration). The "
    "paper's Section 4.9.3 radar, preset paper_section_4_9 (100 W, 35 dB, 50 MHz, no losses, no "
    "integration), gives 445.3 m."
)

#: Radar parameters whose change makes DEFAULT_RADAR_NOTE's figures wrong.
RADAR_BUDGET_KEYS = frozenset(
    {
        "p_tx_w",
        "g_tx_db",
        "g_rx_db",
        "wavelength_m",
        "frequency_ghz",
        "snr_min_db",
        "noise_figure_db",
        "bandwidth_mhz",
        "n_pulses",
        "integration",
        "l_hardware_db",
        "l_processing_db",
        "model",
    }
)


def sensor_notes(modality: str, preset: str | None, explicit) -> list[str]:
    """The notes of one sensor's range (``csuas range --json``'s ``sensors.NAME.notes``).

    Parameters
    ----------
    modality : str
        The sensor's modality (``radar``, ``eo``, ...).
    preset : str or None
        The sensor's preset name.
    explicit : set of str
        The parameters the scenario set itself (not from the preset or a default).
    """
    at_table_39 = modality == "radar" and preset == "default" and not set(explicit) & RADAR_BUDGET_KEYS
    return [DEFAULT_RADAR_NOTE] if at_table_39 else []
