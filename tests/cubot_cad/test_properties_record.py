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


def test_the_sliced_records_say_what_they_weigh_printed_solid(props):
    """Each packaged (sliced) record carries the same robot's mass with its printed parts solid: the
    heavy end of the infill range structure_fem's threshold range takes."""
    for r in props.robots:
        assert r.solid_print_mass_kg > r.mass_kg and "100 % infill" in r.solid_print_mass_source


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
    ("solid_print_mass_kg", 0.1, r"solid_print_mass_kg \S+ must be >= mass_kg"),
    ("solid_print_mass_kg", float("inf"), r"solid_print_mass_kg \S+ must be >= mass_kg"),
    ("solid_print_mass_source", None, "needs a solid_print_mass_source"),
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


# --- play per feature and provenance (issue 12) ------------------------------------------------

def test_a_record_without_play_or_provenance_loads_as_legacy(props, tmp_path):
    from cubot_cad.properties import LEGACY_PROVENANCE

    data = props.to_dict()
    for r in data["robots"]:
        for c in r["connectors"]:
            for k in ("play", "provenance", "shear_stiffness_n_per_m"):
                c.pop(k, None)
    p = tmp_path / "old.json"
    p.write_text(json.dumps(data))
    old = RobotPropertiesFile.load(p).get("cubot").connector("front_rear")
    assert old.provenance == LEGACY_PROVENANCE == "hand formula (legacy record)"
    assert old.play == () and old.play_of("tension") is None


def test_every_shipped_connector_names_where_its_values_come_from(props):
    for r in props.robots:
        for c in r.connectors:
            assert c.provenance.startswith("hand formula: "), (r.name, c.kind, c.provenance)
            for p in c.play:
                assert p.cad_feature, (r.name, c.kind, p)
                if c.preload_n > 0 and p.feature == "tension":  # the wedge latch: taken up by design
                    assert p.play_m == 0 and "wedge" in p.cad_feature, (r.name, c.kind, p)
                else:
                    assert p.play_m > 0, (r.name, c.kind, p)


def test_front_rear_tension_play_is_the_two_clearances_in_series():
    """Pin head in its counterbore + blade in the pin groove: 0.4 mm at 0.2 mm clearance, and the
    pitch backlash is that play over the highest pin's lever arm (not one clearance)."""
    from cubot_cad.robots.cubot import CuBot

    cub = CuBot(front_rear_coupling="clearance")
    fr = cub.connector_properties(2.2e9)[0]
    t = fr.play_of("tension")
    assert (t.axis, t.sense) == ("x", "tension")
    assert t.play_m == pytest.approx(2 * 0.2e-3, rel=1e-9)
    assert fr.play_of("vertical_slip").play_m == pytest.approx(2 * 0.2e-3, rel=1e-9)
    assert fr.backlash_rad == pytest.approx(t.play_m / (max(cub.pin_heights_mm()) * 1e-3), rel=1e-9)
    assert "counterbore" in t.cad_feature and "groove" in t.cad_feature


def test_the_wedge_latch_takes_up_the_tension_play_and_keeps_the_vertical_slip():
    """The default CuBot's wedge latch draws the head onto its counterbore: no tension play, no pitch
    backlash, a preload computed from the servo; the pins still slide 2 clearances vertically."""
    from cubot_cad.robots.cubot import CuBot

    fr = CuBot().connector_properties(2.2e9)[0]
    assert fr.play_of("tension").play_m == 0 and fr.backlash_rad == 0
    assert fr.play_of("vertical_slip").play_m == pytest.approx(2 * 0.2e-3, rel=1e-9)
    assert fr.preload_n > 0 and "stall torque" in fr.preload_source


@pytest.mark.parametrize("kind,feature", [("front_rear", "tension"), ("front_rear", "vertical_slip"),
                                          ("side_rail", "rail_vertical"), ("top_twist", "key_slip"),
                                          ("top_twist", "pull_out")])
def test_doubling_the_cad_clearance_doubles_each_feature_play(kind, feature):
    from cubot_cad.robots.cubot import CuBot

    def play(c):
        # the tension play of the clearance latch (the wedge latch takes it up: 0 at every clearance)
        conns = {x.kind: x for x in CuBot(clearance_mm=c, front_rear_coupling="clearance").connector_properties(2.2e9)}
        return conns[kind].play_of(feature).play_m

    assert play(0.4) == pytest.approx(2 * play(0.2), rel=1e-6)
    assert play(0.4) > play(0.2) > 0


def test_bad_play_and_provenance_are_named():
    from cubot_cad.properties import FeaturePlay

    with pytest.raises(InputError, match="sense 'sideways'"):
        FeaturePlay("tension", "x", "sideways", 1e-4, "pins")
    with pytest.raises(InputError, match="play_m"):
        FeaturePlay("tension", "x", "tension", -1e-4, "pins")
    with pytest.raises(InputError, match="provenance must start with"):
        ConnectorProperties("front_rear", 1.0, 1e5, provenance="a guess")
    p = FeaturePlay("tension", "x", "tension", 1e-4, "pins")
    with pytest.raises(InputError, match="duplicate play features"):
        ConnectorProperties("front_rear", 1.0, 1e5, play=(p, p))
