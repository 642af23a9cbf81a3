"""The modality records (csuas.core.modality): every table keyed by modality follows them, and a record
missing a part fails naming the modality and the part."""

from dataclasses import replace

import pytest

from csuas.base.errors import InputErrors, ParameterError
from csuas.base.registry import resolve
from csuas.commands.render import MODES
from csuas.core import coverage, pd_curves, ranges
from csuas.core.modality import (
    BY_NAME,
    RECORDS,
    Modality,
    ModalityError,
    PartTable,
    check_declared,
    check_modality,
    resolve_part,
)
from csuas.defaults import MODALITIES
from csuas.validation.report.runner import SPEC_LISTS

#: Effective Earth-radius factors written out: 4/3 for radio (ITU-R P.834), 1 / (1 - 0.13) for light
#: (Bomford 1980), 1 for the straight rays of sound.
K_RADIO, K_LIGHT, K_STRAIGHT = 4.0 / 3.0, 1.0 / 0.87, 1.0


def test_one_record_per_modality_section_and_every_table_derived_from_them():
    assert [m.name for m in RECORDS] == list(MODALITIES) == list(ranges.ADAPTERS) == list(pd_curves.DETECTORS)
    assert coverage.K_FACTOR == pytest.approx(
        {"eo": K_LIGHT, "tir": K_LIGHT, "lidar": K_LIGHT, "rf": K_RADIO, "radar": K_RADIO, "acoustic": K_STRAIGHT}
    )
    assert {name: k for name, (k, _) in ranges.HORIZONS.items()} == pytest.approx(
        {"eo": K_LIGHT, "tir": K_LIGHT, "lidar": K_LIGHT, "rf": K_RADIO, "radar": K_RADIO}
    )


@pytest.mark.parametrize("name", MODALITIES)
def test_model_and_detector_of_every_record_resolve_to_functions(name):
    assert callable(ranges.ADAPTERS[name]) and callable(pd_curves.DETECTORS[name])
    assert ranges.ADAPTERS[name] is resolve(BY_NAME[name].model)


def test_renderers_are_exactly_the_render_modes():
    assert {m.renderer for m in RECORDS if m.renderer is not None} == set(MODES)


def test_report_groups_are_groups_the_report_checks_declare():
    groups = {spec.group.name for reference in SPEC_LISTS for spec in resolve(reference)}
    assert {m.report_group for m in RECORDS} <= groups


@pytest.mark.parametrize("model, expected", [("snr", ("snr_min_db", True)), ("range_equation", ("p_rx_min_w", False))])
def test_the_radar_threshold_follows_its_model(model, expected):
    assert BY_NAME["radar"].threshold_key({"model": model}) == expected


def test_an_imaging_sensor_has_no_threshold_to_shift():
    with pytest.raises(ParameterError, match="threshold-limited sensor: acoustic, rf, radar, lidar"):
        BY_NAME["eo"].threshold_key({})


#: (changes to the complete radar record, part the error must name)
BROKEN = {
    "no detector": ({"detector": ""}, "detector: '' is not a core function"),
    "detector above the core": ({"detector": "csuas.render.links.radar:f"}, "detector: 'csuas.render"),
    "no model": ({"model": None}, "model: None is not a core function"),
    "unknown horizon kind": ({"horizon": "acoustic"}, "horizon: 'acoustic' is not one of radio, optical, None"),
    "threshold not a parameter": ({"threshold": "snr_db"}, "threshold: 'snr_db' is not a numeric parameter of [radar]"),
    "threshold for one model only": (
        {"threshold": (("snr", "snr_min_db"),)},
        "threshold: pairs for the models ['snr'], parameters.toml's are ['snr', 'range_equation']",
    ),
    "empty renderer": ({"renderer": ""}, "renderer: '' is neither a render mode nor None"),
    "no report group": ({"report_group": None}, "report_group: None is not a report group"),
}


@pytest.mark.parametrize("case", BROKEN)
def test_a_record_missing_a_part_names_the_modality_and_the_part(case):
    changes, message = BROKEN[case]
    errors = check_modality(replace(BY_NAME["radar"], **changes))
    assert [type(e) for e in errors] == [ModalityError]
    assert str(errors[0]).startswith(f"modality 'radar': {message}")


def test_parts_left_out_of_a_record_are_each_named():
    errors = [str(e) for e in check_modality(Modality("radar", model="csuas.core.ranges:_radar", renderer=None))]
    assert errors == [
        "modality 'radar': detector: not given",
        "modality 'radar': horizon: not given",
        "modality 'radar': report_group: not given",
        "modality 'radar': threshold: not given",
    ]


def test_a_record_without_its_sections_names_both():
    errors = [str(e) for e in check_modality(replace(BY_NAME["lidar"], name="sonar", threshold=None))]
    assert errors == [
        "modality 'sonar': parameters: no section [sonar] in defaults/parameters.toml",
        "modality 'sonar': presets: no [sensor.sonar] tables in defaults/presets.toml",
    ]


def test_a_section_without_a_record_and_a_record_declared_twice_fail_together():
    with pytest.raises(InputErrors) as caught:
        check_declared([*RECORDS[:-1], RECORDS[0]])
    assert sorted(str(e) for e in caught.value.errors) == [
        "modality 'eo': declared twice",
        "modality 'lidar': a section of defaults/parameters.toml without a Modality record",
    ]


def test_a_detector_that_does_not_resolve_fails_naming_the_part_when_first_used():
    broken = replace(BY_NAME["rf"], detector="csuas.core.pd_curves:_no_such_detector")
    with pytest.raises(ModalityError, match="modality 'rf': detector 'csuas.core.pd_curves:_no_such_detector'"):
        resolve_part(broken, "detector")
    table = PartTable("detector", [broken])
    assert list(table) == ["rf"]
    with pytest.raises(ModalityError, match="does not resolve"):
        table["rf"]
