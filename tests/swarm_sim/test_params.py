"""Presets are data; bad input is one clear InputError naming the value (exit 2 in the CLI)."""

from __future__ import annotations

import pytest

from swarm_sim.errors import InputError
from swarm_sim.params import load_preset, preset_names
from swarm_sim.runner import resolve_params, run_scenario


def test_every_preset_loads_and_validates():
    assert {"case-a", "case-b", "case-c", "case-d", "large-void"} <= set(preset_names())
    for name in preset_names():
        p = load_preset(name).validate()
        assert p.arena_w_cm > p.void_width_cm and p.target_x_cm > p.void_x1_cm


def test_thesis_arenas_and_robots():
    c = load_preset("case-c")
    assert (c.arena_w_cm, c.arena_h_cm, c.robot_length_cm, c.wheel_base_cm) == (500, 300, 10, 7)
    assert (c.target_x_cm, c.target_y_cm, c.dt_s, c.speed_cm_s) == (475, 150, 0.01, 13.89)
    a = load_preset("case-a")
    assert (a.arena_w_cm, a.robot_length_cm, a.case_margin, len(a.obstacles)) == (250, 12, 2, 5)
    assert load_preset("case-d").start == "random" and load_preset("case-c").start == "fixed"


def test_limits_resolve_the_rule_from_the_record():
    from structure_fem.limits import load_limits

    lim = load_limits("thesis").level_for(3)
    p = resolve_params("case-d", 9, 3, "thesis")
    assert (p.ground_ratio, p.ground_margin, p.min_robots_rule) == (lim.ground_ratio, lim.ground_margin, 9)
    pa = resolve_params("case-a", 8, 2, "thesis")
    assert pa.ground_margin == lim.ground_margin + 2 and pa.min_robots_rule == 8


@pytest.mark.parametrize("robots,width,overrides,needle", [
    (0, 3, {}, "robots"),
    (-4, 3, {}, "robots"),
    (9, 0, {}, "void_width"),
    (9, -2, {}, "void_width"),
    (9, 60, {}, "wider than the arena"),
    (9, 3, {"target_x_cm": 250.0}, "inside"),
    (9, 3, {"target_x_cm": 100.0}, "initial side"),
    (9, 3, {"warp_drive": 1.0}, "warp_drive"),
    (9, 3, {"speed_cm_s": -1.0}, "speed_cm_s"),
    (900, 3, {}, "do not fit"),
])
def test_bad_scenarios_raise_input_error_naming_the_value(robots, width, overrides, needle):
    with pytest.raises(InputError, match=needle):
        run_scenario("case-d", robots, width, 1, limits="thesis", **overrides)


def test_unknown_preset_and_malformed_toml(tmp_path):
    with pytest.raises(InputError, match="unknown preset 'case-z'"):
        run_scenario("case-z", 9, 3, 1, limits="thesis")
    bad = tmp_path / "bad.toml"
    bad.write_text("[arena\nwidth_cm = 3\n")
    with pytest.raises(InputError, match="malformed TOML"):
        run_scenario(str(bad), 9, 3, 1, limits="thesis")
    unknown = tmp_path / "unknown.toml"
    unknown.write_text("[arena]\nwidth_furlongs = 3\n")
    with pytest.raises(InputError, match="arena.width_furlongs"):
        run_scenario(str(unknown), 9, 3, 1, limits="thesis")


def test_a_custom_toml_preset_runs(tmp_path):
    src = (load_preset.__globals__["resources"].files("swarm_sim") / "presets" / "case-c.toml").read_text()
    f = tmp_path / "wide.toml"
    f.write_text(src.replace("width_cm = 500.0", "width_cm = 700.0").replace("x_cm = 475.0", "x_cm = 675.0"))
    p = resolve_params(str(f), 3, 1, "thesis")
    assert p.arena_w_cm == 700 and p.preset == "wide" and p.void_x0_cm == 345


def test_bad_limits_spec_is_input_error():
    with pytest.raises(InputError, match="limits"):
        run_scenario("case-d", 9, 3, 1, limits="/no/such/limits.json")
