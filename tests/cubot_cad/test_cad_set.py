"""`voidcross cad export|dock|check --set NAME=VALUE`: the dimensions a maker tunes, each validated
by the robot's own dataclass (and the parts it derives); a refused value is one `error:` line, exit 2,
nothing written."""

from __future__ import annotations

import json

import pytest


def _fresh(name="cubot", **kw):
    from cubot_cad.robots.registry import make_robot

    return make_robot(name, 0.2, tuple(sorted(kw.items())))


# --- bad values: one error line naming the value, exit 2, nothing written ------------------------

BAD = [
    (("--set", "hull_mm=3"), "hull_mm"),                       # unknown name
    (("--set", "wall_mm=thick"), "thick"),                     # not a number
    (("--set", "wall_mm=nan"), "nan"),                         # not finite
    (("--set", "wall_mm"), "wall_mm"),                         # no '='
    (("--set", "wall_mm=-1"), "wall_mm"),                      # refused by CuBot.__post_init__
    (("--set", "wall_mm=5"), "wheel_base_mm"),                 # refused by the geometry: names what to change
    (("--set", "pin_diameter_mm=4"), "groove_diameter_mm"),    # refused by FrontRearSpec
    (("--set", "wheel_base_mm=80"), "wheel_base_mm"),
    (("--set", "clearance_mm=0.05"), "clearance_mm 0.05 mm"),  # the clearance's own validation
    (("--set", "clearance_mm=0.3", "--clearance-mm", "0.2"), "contradicts"),
    (("--set", "wall_mm=3", "--set", "wall_mm=4"), "twice"),
]


@pytest.mark.parametrize("argv, word", BAD)
@pytest.mark.parametrize("sub", ["export", "dock", "check"])
def test_a_bad_setting_is_one_error_line_exit_2_and_nothing_written(cli, tmp_path, sub, argv, word):
    out = tmp_path / "new"
    extra = {"export": ("--robot", "cubot", "--out", str(out)), "dock": ("--pair", "cubot-front-rear", "--out", str(out)),
             "check": ("--robot", "cubot")}[sub]
    res = cli("cad", sub, *extra, *argv)
    assert res.code == 2, (res.code, res.err)
    assert len(res.error_lines) == 1 and res.error_lines[0].startswith("error: "), res.err
    assert word in res.error_lines[0], res.error_lines[0]
    assert not out.exists()


def test_a_setting_no_selected_robot_has_is_refused(cli, tmp_path):
    res = cli("cad", "export", "--robot", "platform", "--set", "wall_mm=3", "--out", str(tmp_path / "x"))
    assert res.code == 2 and len(res.error_lines) == 1
    assert "wall_mm=3" in res.err and "platform" in res.err
    assert not (tmp_path / "x").exists()


def test_packaged_default_refuses_settings(cli, tmp_path):
    res = cli("cad", "export", "--packaged-default", "--set", "wall_mm=3", "--out", str(tmp_path / "x"))
    assert res.code == 2 and "--packaged-default" in res.err and len(res.error_lines) == 1


# --- the values move the geometry ------------------------------------------------------------------

def test_a_thicker_wall_gives_a_heavier_body_and_longer_pins(robots):
    base = robots["cubot"]
    vols = [_fresh(wall_mm=w).body.volume_mm3 for w in (3.0, 4.0)]
    assert base.body.volume_mm3 < vols[0] < vols[1]
    thick = _fresh(wall_mm=4.0)
    assert thick.body.wall_mm == 4.0 and thick.fr_spec.wall_mm == 4.0
    # the pins reach through the thicker wall: 1.6 mm more of it on each robot
    assert thick.fr_spec.protrusion_mm == pytest.approx(base.fr_spec.protrusion_mm + 1.6)


@pytest.mark.parametrize("wall", [2.6, 3.0, 3.5, 4.0, 4.5])
def test_a_cubot_wall_up_to_4_5_mm_builds_with_the_default_wheel_base(wall):
    """The wheels are centred on the body (not on the footprint, which includes the thicker female
    rail): a 70 mm wheel base leaves 4.6 mm to the inner walls, not 0.1 mm (wall >= 2.6 was refused)."""
    r = _fresh(wall_mm=wall)
    yc = r.y_centre_mm
    wheel = next(c for c in r.components() if c.key == "wheel")
    assert [p[1] for p in wheel.positions_mm] == pytest.approx([yc - 35.0, yc + 35.0])
    if wall == 4.5:
        assert r.body.solid.isValid() and r.body.volume_mm3 > _fresh(wall_mm=4.0).body.volume_mm3


def test_a_wall_beyond_the_wheels_names_the_dimension_to_change():
    from cubot_cad.errors import InputError

    with pytest.raises(InputError, match=r"wall_mm=4.6.*reduce wheel_base_mm to 69.8 or wall_mm to 4.5"):
        _fresh(wall_mm=4.6)
    assert _fresh(wall_mm=4.6, wheel_base_mm=69.8).body.wall_mm == 4.6  # ... and that change builds


def test_pin_diameter_moves_pins_holes_and_docks(robots):
    from cubot_cad.checks.docking import dock

    base = robots["cubot"]
    fat = _fresh(pin_diameter_mm=5.5)
    pin = next(p.part for p in fat.placed if p.role == "pin")
    base_pin = next(p.part for p in base.placed if p.role == "pin")
    assert pin.spec.pin_diameter_mm == 5.5 and pin.volume_mm3 > base_pin.volume_mm3
    assert fat.body.volume_mm3 < base.body.volume_mm3  # its pin holes (pin + 2 clearances) are larger
    pair = dock("cubot-front-rear", 0.2, settings=(("pin_diameter_mm", 5.5),))
    assert pair.ok and pair.interference_mm3 <= 1e-3 and pair.gap_mm == pytest.approx(0.0, abs=0.01)
    assert pair.shapes_a[0].Volume() == pytest.approx(fat.body.volume_mm3)  # docked: the tuned robot


def test_wheel_base_moves_the_wheel_slots():
    import cadquery as cq

    narrow = _fresh(wheel_base_mm=50.0)
    yc, f = narrow.y_centre_mm, narrow.floor_mm
    base = _fresh()
    for y in (yc - 25.0, yc + 25.0):  # the floor at the narrow wheels' mid-planes: open for them only
        assert not narrow.body.solid.isInside(cq.Vector(0, y, f / 2))
        assert base.body.solid.isInside(cq.Vector(0, y, f / 2))
    wheel = next(c for c in narrow.components() if c.key == "wheel")
    assert [p[1] for p in wheel.positions_mm] == pytest.approx([yc - 25.0, yc + 25.0])


def test_other_robots_take_the_settings_they_have():
    cube = _fresh("cube-robot", wall_mm=3.0, pin_diameter_mm=5.5)
    assert cube.fr_spec.wall_mm == 3.0 and cube.fr_spec.pin_diameter_mm == 5.5
    oct_ = _fresh("octbot", wall_mm=3.0, wheel_base_mm=66.0, pin_diameter_mm=5.5)  # no pins: ignored
    assert oct_.wall_mm == 3.0 and oct_.wheel_base_mm == 66.0
    assert _fresh("octbot", wall_mm=3.0).body.volume_mm3 > _fresh("octbot").body.volume_mm3


# --- on the command line -----------------------------------------------------------------------------

def test_export_with_set_records_and_uses_the_values(cli, tmp_path, robots):
    out = tmp_path / "w3"
    res = cli("cad", "export", "--robot", "cubot", "--set", "wall_mm=3", "--set", "clearance_mm=0.3",
              "--format", "stl", "--no-dock", "--out", str(out), "--json")
    assert res.code == 0, res.err
    payload = res.json()
    assert payload["settings"] == {"wall_mm": 3.0} and payload["clearance_mm"] == 0.3
    man = json.loads((out / "manifest.json").read_text())
    assert man["settings"] == {"wall_mm": 3.0} and man["clearance_mm"] == 0.3
    body = next(p for p in man["parts"] if p["part"] == "cubot_body")
    assert body["volume_mm3"] == pytest.approx(_fresh_c(0.3, wall_mm=3.0).body.volume_mm3, rel=1e-6)
    assert body["volume_mm3"] > robots["cubot"].body.volume_mm3


def _fresh_c(c, **kw):
    from cubot_cad.robots.registry import make_robot

    return make_robot("cubot", c, tuple(sorted(kw.items())))


def test_set_clearance_is_the_clearance(cli):
    a = cli("cad", "dock", "--pair", "platform-bolt", "--no-capture", "--json", "--set", "clearance_mm=0.3")
    b = cli("cad", "dock", "--pair", "platform-bolt", "--no-capture", "--json", "--clearance-mm", "0.3")
    assert a.code == 0 and b.code == 0, a.err + b.err
    assert a.json() == b.json() and a.json()["clearance_mm"] == 0.3


def test_dock_with_a_thick_wall_docks_every_cubot_pair(cli):
    res = cli("cad", "dock", "--pair", "cubot-front-rear,cubot-side-rail,cubot-top-down", "--no-capture", "--json",
              "--set", "wall_mm=4")
    assert res.code == 0, res.err
    out = res.json()
    assert out["settings"] == {"wall_mm": 4.0}
    assert all(r["ok"] and r["interference_mm3"] <= 1e-3 for r in out["pairs"]), out["pairs"]


def test_check_builds_and_checks_the_tuned_parts(cli):
    res = cli("cad", "check", "--robot", "platform", "--set", "clearance_mm=0.4", "--no-slice", "--json")
    assert res.code == 0, res.err
    out = res.json()
    assert out["built"] == {"robots": ["platform"], "clearance_mm": 0.4, "settings": {}}
    assert out["files"] == 1 and out["failed"] == 0


def test_check_refuses_a_directory_and_a_build(cli, tmp_path):
    res = cli("cad", "check", str(tmp_path), "--set", "wall_mm=3")
    assert res.code == 2 and len(res.error_lines) == 1 and "not both" in res.err


def test_the_front_rear_coupling_is_a_variant_chosen_by_name():
    """The clearance latch stays selectable (issue 38): ``--set front_rear_coupling=clearance``; a name
    that is not a variant is one error naming it."""
    from cubot_cad.errors import InputError
    from cubot_cad.settings import parse_settings

    assert parse_settings(["front_rear_coupling=clearance"]) == (("front_rear_coupling", "clearance"),)
    r = _fresh_c(0.2, front_rear_coupling="clearance")
    assert r.front_rear_coupling == "clearance" and r.fr_spec.wedge is None
    assert _fresh_c(0.2).fr_spec.wedge is not None
    with pytest.raises(InputError, match="'loose' is not one of wedge, clearance"):
        parse_settings(["front_rear_coupling=loose"])
