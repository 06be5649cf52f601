"""Lead-ins and capture range: every coupling that robots dock by themselves takes a robot arriving
1 mm off (lateral and vertical, both ways) or turned 3 deg (about both transverse axes, both ways)
and guides it in (criterion: cubot_cad.checks.capture); without the lead-ins the same check fails."""

from __future__ import annotations

import pytest

from cubot_cad.checks.capture import (
    MAX_GIVE_PER_STEP,
    REQUIRED_ANGLE_DEG,
    REQUIRED_OFFSET_MM,
    entry,
    geometry,
    measure,
)
from cubot_cad.checks.docking import PAIRS

DOCKED = tuple(p for p in PAIRS if p != "platform-bolt")  # the platform's lap joint is bolted by hand


@pytest.fixture(scope="module")
def captures(robots, pairs):
    """Every pair's capture by the geometry's hash: `cad dock`'s (the whole ladder) where the
    geometry, the checker and manifold3d are the packaged ones (the freshness test below says when
    to regenerate it); otherwise measured, on the ladder's rungs up to 1 mm / 3 deg only."""
    from cubot_cad.checks import capture_cache as CC
    from cubot_cad.checks.docking import ROBOT_OF_PAIR

    jobs = {n: (robots[ROBOT_OF_PAIR[n]], n, pairs[n]) for n in DOCKED}
    out = {n: CC.lookup(CC.key_of(n, CC.portable(geometry(*j)), True)) for n, j in jobs.items()}
    missing = [jobs[n] for n, c in out.items() if c is None]
    return out | (CC.measure_all(missing, full_ladder=False) if missing else {})


@pytest.mark.parametrize("name", DOCKED)
def test_every_coupling_captures_1_mm_and_3_deg_at_the_default_clearance(captures, name):
    c = captures[name]
    assert len(c.offset_mm) == 4 and len(c.angle_deg) == 4  # +- two transverse axes, +- two turns
    bad = [e for e in c.entries if not e.captured]
    assert c.min_offset_mm >= REQUIRED_OFFSET_MM, bad
    assert c.min_angle_deg >= REQUIRED_ANGLE_DEG, bad
    assert c.ok
    # the lead-ins did work: somewhere the robot had to give way, and never more than the criterion allows
    assert max(e.worst_give_per_step for e in c.entries) > 0.5
    assert all(e.worst_give_per_step <= MAX_GIVE_PER_STEP for e in c.entries if e.captured)  # (a rung past the
    # range, on the whole ladder, is one where it gave more)


def test_the_packaged_captures_are_the_default_geometrys(robots, pairs, tmp_path, monkeypatch):
    """Fails when a coupling's geometry, the checker or manifold3d changed: regenerate with
    `python -m cubot_cad.checks.capture_cache` (the captures above were then measured, not read)."""
    from cubot_cad.checks import capture_cache as CC
    from cubot_cad.checks.docking import ROBOT_OF_PAIR

    keys = CC.packaged_keys([(robots[ROBOT_OF_PAIR[n]], n, pairs[n]) for n in DOCKED])
    stale = sorted(n for n, k in keys.items() if k not in CC._packaged())
    assert not stale, f"{CC.PACKAGED.name} is stale for {stale}: run `python -m cubot_cad.checks.capture_cache`"
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))  # an empty user cache: a fresh clone reads them
    for n, k in keys.items():
        assert CC.lookup(k).summary() == CC._from_json(CC._packaged()[k]).summary() and CC.lookup(k).pair == n


def test_the_platform_joint_has_no_capture_range(robots, pairs):
    assert measure(robots["platform"], "platform-bolt", pairs["platform-bolt"]) is None


def _no_lead_in(name):
    from dataclasses import replace

    from cubot_cad.checks.docking import dock_robot
    from cubot_cad.robots.cubot import CuBot
    from cubot_cad.robots.registry import make_robot

    base = make_robot("cubot", 0.2)
    if name == "cubot-front-rear":
        r = CuBot(fr=replace(base.fr_spec, pin_chamfer_mm=0.0, hole_chamfer_mm=0.0))
    elif name == "cubot-top-down":
        r = CuBot(top=replace(base.top_spec, key_chamfer_mm=0.0, hole_chamfer_mm=0.0))
    else:
        r = CuBot(rail=replace(base.rail_spec, groove_flare_mm=0.0, tongue_taper_mm=0.0, end_chamfer_mm=0.0))
    return r, dock_robot(r, name)


@pytest.mark.parametrize("name, axis", [("cubot-front-rear", "y"), ("cubot-top-down", "x"),
                                        ("cubot-side-rail", "z")])
def test_without_the_lead_ins_a_1_mm_offset_is_not_captured(robots, pairs, name, axis):
    """Chamfers and countersinks set to 0: the robot meets a face across the docking axis and would
    have to jump sideways (the check can fail); with them, the same entry is guided."""
    r, pair = _no_lead_in(name)
    assert pair.ok  # still docks when aligned
    bare = entry(geometry(r, name, pair), "offset", axis, REQUIRED_OFFSET_MM)
    assert not bare.captured and "steep contact" in bare.reason, bare
    good = entry(geometry(robots["cubot"], name, pairs[name]), "offset", axis, REQUIRED_OFFSET_MM)
    assert good.captured, good


def test_a_misalignment_within_the_clearance_needs_no_lead_in(pairs):
    """0.15 mm off with 0.2 mm clearance: the pins pass without touching, with or without chamfers."""
    r, pair = _no_lead_in("cubot-front-rear")
    e = entry(geometry(r, "cubot-front-rear", pair), "offset", "z", 0.15)
    assert e.captured and e.worst_give_per_step == 0.0


def test_lead_in_sizes_follow_the_estimate():
    """clearance + pin chamfer + countersink >= 1 mm for the pins, clearance + two chamfers for the key."""
    from cubot_cad.couplings.connectors import FrontRearSpec, TopTwistSpec

    assert FrontRearSpec().capture_estimate_mm >= REQUIRED_OFFSET_MM + 0.2
    assert TopTwistSpec().capture_estimate_mm >= REQUIRED_OFFSET_MM + 0.2


def test_cli_dock_reports_the_capture_of_a_pair(cli):
    res = cli("cad", "dock", "--pair", "cubot-top-down", "--json")
    assert res.code == 0, res.err
    (row,) = res.json()["pairs"]
    cap = row["capture"]
    assert cap["ok"] and cap["min_offset_mm"] >= 1.0 and cap["min_angle_deg"] >= 3.0
    assert set(cap["offset_mm"]) == {"+x", "-x", "+y", "-y"}
    assert set(cap["angle_deg"]) == {"+rot_x", "-rot_x", "+rot_y", "-rot_y"}


# -- the cache by geometry hash and the parallel measurement (issue 41) ------------------------

def test_a_capture_is_measured_once_per_geometry_and_the_same_in_a_worker(robots, pairs, tmp_path, monkeypatch):
    from cubot_cad.checks import capture as C
    from cubot_cad.checks import capture_cache as CC
    from cubot_cad.checks.docking import ROBOT_OF_PAIR

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    names = ("cubot-top-down", "octbot-ring")
    jobs = [(robots[ROBOT_OF_PAIR[n]], n, pairs[n]) for n in names]
    par = CC.measure_all(jobs, workers=2, full_ladder=False)  # one coupling per worker process
    direct = {n: measure(*j, full_ladder=False) for n, j in zip(names, jobs, strict=True)}
    for n in names:
        assert par[n].summary() == direct[n].summary() and par[n].entries == direct[n].entries
    assert len(list((tmp_path / "voidcross" / "capture").glob("*.json"))) == 2

    def boom(*a, **k):
        raise AssertionError("measured what the cache holds")

    monkeypatch.setattr(C, "measure_geometry", boom)
    again = CC.measure_all(jobs, workers=1, full_ladder=False)
    assert {n: c.summary() for n, c in again.items()} == {n: c.summary() for n, c in par.items()}


def test_the_cache_key_moves_with_the_geometry_the_ladder_and_the_checker(robots, pairs, monkeypatch, tmp_path):
    from cubot_cad.checks import capture_cache as CC

    g = geometry(robots["cubot"], "cubot-top-down", pairs["cubot-top-down"])
    p = CC.portable(g)
    k = CC.key_of("cubot-top-down", p, False)
    assert CC.key_of("cubot-top-down", CC.portable(g), False) == k  # the same geometry, the same key
    moved = dict(p, moving=(p["moving"][0] + 0.01, p["moving"][1]))
    assert CC.key_of("cubot-top-down", moved, False) != k
    assert CC.key_of("cubot-top-down", p, True) != k
    assert CC.key_of("cubot-top-down", dict(p, step_mm=0.1), False) != k
    monkeypatch.setattr(CC, "CACHE_VERSION", CC.CACHE_VERSION + 1)
    assert CC.key_of("cubot-top-down", p, False) != k
    # an unreadable cache entry is measured again, not an error
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    (tmp_path / "voidcross" / "capture").mkdir(parents=True)
    (tmp_path / "voidcross" / "capture" / f"{k}.json").write_text("{torn")
    assert CC.lookup(k) is None
