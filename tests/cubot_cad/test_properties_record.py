"""RobotProperties (the cad -> fem record): round-trip, versioning, validation."""

from __future__ import annotations

import dataclasses
import json

import pytest

from cubot_cad.errors import InputError
from cubot_cad.properties import (
    SCHEMA_VERSION,
    ConnectorProperties,
    RobotPropertiesFile,
    default_properties,
)


@pytest.fixture
def props() -> RobotPropertiesFile:
    return default_properties()


def test_packaged_defaults_hold_every_robot(props):
    assert {"cubot", "octbot", "cube-robot", "platform"} <= set(props.names)
    assert props.get("cubot").connector("front_rear").kind == "front_rear"


def test_round_trip_is_lossless(props, tmp_path):
    path = props.save(tmp_path / "robot_properties.json")
    assert RobotPropertiesFile.load(path) == props


def test_wrong_schema_version_is_rejected(props, tmp_path):
    data = props.to_dict()
    data["schema_version"] = SCHEMA_VERSION + 1
    p = tmp_path / "p.json"
    p.write_text(json.dumps(data))
    with pytest.raises(InputError, match="schema_version"):
        RobotPropertiesFile.load(p)


def test_corrupt_file_names_the_file(tmp_path):
    p = tmp_path / "broken.json"
    p.write_text('{"schema_version": 1, "robots": [')
    with pytest.raises(InputError, match="broken.json is not valid JSON"):
        RobotPropertiesFile.load(p)


def test_missing_file_is_input_error(tmp_path):
    with pytest.raises(InputError, match="not found"):
        RobotPropertiesFile.load(tmp_path / "nope.json")


@pytest.mark.parametrize("field,value,match", [
    ("mass_kg", -0.3, "mass_kg must be > 0"),
    ("mass_kg", 0.0, "mass_kg must be > 0"),
    ("length_m", float("nan"), "length_m must be > 0"),
    ("inertia_kg_m2", (1e-3, 1e-3, 5e-3, 0, 0, 0), "triangle inequality"),
    ("com_m", (0.0, 0.0), "com_m"),
])
def test_bad_values_are_named(props, field, value, match):
    cubot = props.get("cubot")
    with pytest.raises(InputError, match=match):
        dataclasses.replace(cubot, **{field: value})


def test_bad_connector_values_are_named():
    with pytest.raises(InputError, match="rotational_stiffness_nm_per_rad must be > 0"):
        ConnectorProperties("front_rear", -1.0, 1e5)
    with pytest.raises(InputError, match="kind 'glue'"):
        ConnectorProperties("glue", 1.0, 1e5)


def test_wrong_types_in_json_are_rejected(props, tmp_path):
    data = props.to_dict()
    data["robots"][0]["mass_kg"] = "heavy"
    p = tmp_path / "p.json"
    p.write_text(json.dumps(data))
    with pytest.raises(InputError, match="mass_kg: expected a number"):
        RobotPropertiesFile.load(p)


def test_unknown_robot_lists_the_known_ones(props):
    with pytest.raises(InputError, match="unknown robot 'hexbot'.*cubot"):
        props.get("hexbot")


def test_atomic_save_keeps_old_file_when_serialisation_fails(props, tmp_path):
    path = props.save(tmp_path / "robot_properties.json")
    before = path.read_bytes()
    from cubot_cad.jsonrecord import write_json_atomic

    with pytest.raises(TypeError):
        write_json_atomic(path, {"x": object()})
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["robot_properties.json"]
