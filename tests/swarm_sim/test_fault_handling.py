"""Robots that fail mid-task (issue 16): what the swarm senses and does, with the invariants on."""

import pytest

from structure_fem.limits import load_limits
from swarm_sim.errors import InputError
from swarm_sim.runner import resolve_params, run_scenario, simulate


def run(faults, robots=12, width=3, seed=3, preset="case-d", **kw):
    return run_scenario(preset, robots, width, seed, faults=faults, check_invariants=True, **kw)


def kinds(res, kind):
    return [e for e in res.events if e[1] == kind]


def first_recruit(seed=3):
    """(time, robot) of the fault-free run's first recruit call (case D, 12 robots, 3 wide)."""
    rec = next(e for e in run_scenario("case-d", 12, 3, seed).events if e[1] == "recruit")
    return rec[0], rec[3]["robots"][0]


def calls(res):
    return {e[0] for e in res.events if e[1] in ("recruit", "hand_over")}


def test_without_faults_the_run_is_the_fault_free_one():
    a = run_scenario("case-d", 9, 3, 5).to_dict()
    b = run_scenario("case-d", 9, 3, 5, faults="").to_dict()
    for d in (a, b):
        d.pop("wall_s")
    assert a == b and a["faults"] == [] and a["robots_failed"] == 0


def test_same_seed_same_faults_and_a_fault_event_per_failure():
    a, b = run("drive:20/h"), run("drive:20/h")
    assert a.faults == b.faults and a.end_reason == b.end_reason and a.steps == b.steps
    assert len(kinds(a, "fault")) == len(a.faults) > 0
    assert all(f["mode"] == "drive" for f in a.faults)


def test_a_robot_that_cannot_drive_never_moves_again():
    p = resolve_params("case-d", 12, 3, "derived", faults="0@0.5:drive")
    seen = []
    simulate(p, 3, check=True, on_step=lambda s: seen.append((s.t_s, s.x_cm[0], s.y_cm[0])))
    after = [(x, y) for t, x, y in seen if t >= 0.5 + 1e-9]
    assert after and len(set(after)) == 1


def test_a_silent_member_is_detected_by_its_missed_heartbeats():
    p = resolve_params("case-d", 12, 3, "derived")
    base = run_scenario("case-d", 12, 3, 3)
    # a robot that docks early: fail it (total) a little after it joined
    dock = next(e for e in base.events if e[1] == "dock")
    r, t = dock[2], dock[0] + 1.0
    res = run(f"{r}@{t}:total")
    det = [e for e in kinds(res, "fault_detected") if e[2] == r]
    assert det and det[0][3]["how"] == "no_heartbeat"
    bound = p.heartbeat_s * p.heartbeat_misses
    assert bound - 1e-6 <= det[0][3]["delay_s"] <= bound + p.dt_s + 1e-6
    assert res.robots_lost == 0 and not res.violations and res.end_reason != "timeout"


def test_a_robot_that_cannot_drive_says_so_when_called_and_the_next_is_called():
    _, r = first_recruit()
    res = run(f"{r}@0:drive")
    det = [e for e in kinds(res, "fault_detected") if e[2] == r]
    assert det and det[0][3]["how"] == "replied_cannot_drive" and det[0][0] in calls(res)
    assert not any(r in e[3]["robots"] for e in kinds(res, "recruit"))  # known failed: never called again


def test_a_recruit_that_dies_on_its_way_is_found_by_no_motion_and_handed_over():
    t, r = first_recruit()
    t += 0.5
    p = resolve_params("case-d", 12, 3)
    res = run(f"{r}@{t}:total")
    det = [e for e in kinds(res, "fault_detected") if e[2] == r]
    assert det and det[0][3]["how"] == "no_motion_when_called"
    assert det[0][3]["delay_s"] <= p.recruit_stall_s + 1.0
    hand = [e for e in kinds(res, "hand_over") if e[2] == r]
    assert hand and hand[0][3]["to"] != r


def test_a_robot_that_does_not_answer_a_call_is_passed_by_at_once():
    _, r = first_recruit()
    res = run(f"{r}@0:total")
    det = [e for e in kinds(res, "fault_detected") if e[2] == r]
    assert det and det[0][3]["how"] == "no_reply_to_call" and det[0][0] in calls(res)
    assert not any(r in e[3]["robots"] for e in kinds(res, "recruit"))


def test_a_blind_robot_never_seeds_nor_finds_the_target():
    res = run("sensor:200/h", robots=12, seed=4)
    blind = {f["robot"]: f["t_s"] for f in res.faults}
    for t, kind, r, _d in res.events:
        if kind in ("seed", "target_found") and r in blind:
            assert t < blind[r]


def test_a_failed_front_robot_is_pushed_onto_the_target_ground():
    # a void the derived line crosses with 12 robots (its span, at most 3): it releases at the front
    w = min(3, load_limits("derived").level_for(1).max_span_widths)
    base = run_scenario("case-d", 12, w, 3)
    rel = next(e for e in base.events if e[1] == "release_front")
    r = rel[3]["robots"][0]
    res = run(f"{r}@{rel[0] - 0.5}:drive", width=w)
    push = [e for e in kinds(res, "pushed_clear") if e[2] == r]
    assert push and push[0][3]["x_cm"] > resolve_params("case-d", 12, w).void_x1_cm
    assert res.robots_lost == 0 and not res.violations


@pytest.mark.parametrize("faults", ["drive:20/h", "total:20/h", "sensor:20/h", "drive:8/h,total:8/h,sensor:8/h"])
def test_every_run_with_random_faults_ends_and_loses_no_robot(faults):
    for seed in range(4):
        res = run(faults, robots=10, seed=seed)
        assert res.end_reason not in (None, "timeout"), (faults, seed)
        assert res.robots_lost == 0 and not res.violations, (faults, seed, res.violations[:2])


def test_when_every_robot_fails_the_run_ends_stranded():
    res = run("drive:3600/h", robots=6, seed=1)
    assert res.end_reason == "stranded" and res.robots_lost == 0


def test_the_faults_spec_is_checked_before_the_run():
    with pytest.raises(InputError, match="no robot 40"):
        resolve_params("case-d", 9, 3, faults="40@1:drive")
    with pytest.raises(InputError, match="heartbeat_misses"):
        resolve_params("case-d", 9, 3, heartbeat_misses=0)


def test_cli_reports_failures_and_refuses_a_bad_spec(cli):
    ok = cli("sim", "run", "--preset", "case-d", "--robots", "12", "--faults", "drive:20/h", "--seed", "3")
    assert ok.code == 0, ok.err
    assert "robots failed" in ok.out and "detected" in ok.out
    js = cli("sim", "run", "--preset", "case-d", "--robots", "12", "--faults", "drive:20/h", "--seed", "3", "--json")
    d = js.json()
    assert d["robots_failed"] == len({f["robot"] for f in d["faults"]}) > 0 and d["faults_spec"] == "drive:20/h"
    bad = cli("sim", "run", "--faults", "drive:fast/h")
    assert bad.code == 2 and "'fast'" in bad.err and len(bad.error_lines) == 1


@pytest.mark.parametrize("faults", ["drive:20/h", "3@40:total,5@41:sensor"])
def test_both_engines_give_the_same_run_with_faults(faults):
    a = run_scenario("case-d", 12, 3, 6, faults=faults, engine="reference").to_dict(events=True)
    b = run_scenario("case-d", 12, 3, 6, faults=faults, engine="compiled").to_dict(events=True)
    a.pop("wall_s"), b.pop("wall_s")
    assert a == b


#: draws the fault soak found breaking an invariant (voidcross sim soak --runs 300 --faults --seed 16)
SOAK_FINDINGS = [
    {"preset": "case-b", "robots": 18, "void_width": 5, "seed": 209195719, "limits": "thesis", "arena_w_cm": 559.0,
     "arena_h_cm": 364.0, "target_x_cm": 534.0, "target_y_cm": 171.9198880261185, "structure": "switch",
     "obstacles": [], "faults": "total:39.489/h,sensor:23.245/h"},
    {"preset": "pier", "robots": 22, "void_width": 5, "seed": 81307159, "limits": "derived"},
    {"preset": "case-d", "robots": 5, "void_width": 4, "seed": 1905404674, "limits": "thesis", "arena_w_cm": 731.0,
     "arena_h_cm": 315.0, "target_x_cm": 706.0, "target_y_cm": 202.06842915921536, "structure": "switch",
     "obstacles": [[443.7283921396444, 206.50640031419613, 4.750526912026057]], "faults": "total:34.745/h"},
]


@pytest.mark.parametrize("d", SOAK_FINDINGS, ids=[f"{d['preset']}-{d['seed']}" for d in SOAK_FINDINGS])
def test_the_fault_soaks_findings_hold_the_invariants(d):
    kw = {k: v for k, v in d.items() if k not in ("preset", "robots", "void_width", "seed", "limits")}
    p = resolve_params(d["preset"], d["robots"], d["void_width"], d["limits"], **kw)
    _, res = simulate(p, d["seed"], check=True)
    assert not res.violations and res.robots_lost == 0 and res.end_reason not in (None, "timeout")
