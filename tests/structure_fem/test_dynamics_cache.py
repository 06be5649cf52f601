"""The launch transients' allowance cache (structure_fem.model.dynamics_cache): a pure function of its inputs."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from structure_fem.model import dynamics_cache as dc
from structure_fem.model.connectors import ConnectorSet
from structure_fem.model.structures import Structure

pytest.importorskip("exudyn")


class Counter:
    """A stand-in for the integration: counts its calls, returns a value made of its inputs."""

    def __init__(self):
        self.calls = 0

    def __call__(self, structure, width, robot, damping_ratio, **kw):
        self.calls += 1
        return 1e-4 * width + robot.mass_kg * 1e-5


@pytest.fixture
def setup(make_robot, tmp_path):
    robot = make_robot(backlash=0.005)  # a play to scale
    return robot, ConnectorSet.from_robot(robot), tmp_path


LINE = Structure("line")


def _call(robot, conn, cache, fn, width=3, rows=5, flexible=True, damping=0.02, structure=LINE):
    return dc.allowance_m(structure, width, robot, damping, rows=rows, connectors=conn, flexible=flexible,
                          cache_dir=cache, compute=fn)


def test_a_miss_integrates_once_and_a_hit_does_not(setup):
    robot, conn, cache = setup
    fn = Counter()
    a = _call(robot, conn, cache, fn)
    b = _call(robot, conn, cache, fn)
    assert a == b == pytest.approx(3e-4 + robot.mass_kg * 1e-5)
    assert fn.calls == 1
    assert len(list(cache.glob("*.json"))) == 1


def test_every_input_that_changes_the_transient_changes_the_key(setup):
    robot, conn, cache = setup
    fn = Counter()
    _call(robot, conn, cache, fn)
    variants = [dict(width=4), dict(rows=6), dict(flexible=False), dict(damping=0.05),
                dict(structure=Structure("arch", 4, 2, "staggered"))]
    for v in variants:
        _call(robot, conn, cache, fn, **v)
    _call(replace(robot, mass_kg=robot.mass_kg * 1.01), conn, cache, fn)
    _call(robot, conn.scaled(1.1, 1.0), cache, fn)
    _call(robot, conn.scaled(1.0, 1.5), cache, fn)
    assert fn.calls == 1 + len(variants) + 3


def test_a_record_that_differs_in_its_last_bits_finds_the_transient_and_a_real_change_does_not(setup):
    """The CAD's mass properties differ in their last bits between builds (the CuBot's inertia,
    1.2e-16 relative, a fresh `make demo` against the packaged record): the key is over floats to
    12 significant digits, so such noise finds the cached transient; a change of 1e-9 does not."""
    import math

    robot, conn, cache = setup
    fn = Counter()
    _call(robot, conn, cache, fn)
    noisy = replace(robot, mass_kg=math.nextafter(robot.mass_kg, 1.0),  # last bits; a zero off by 1e-22
                    inertia_kg_m2=tuple(math.nextafter(v, -1.0) if v else 1e-22 for v in robot.inertia_kg_m2))
    assert noisy != robot
    _call(noisy, conn, cache, fn)
    assert fn.calls == 1
    _call(replace(robot, mass_kg=robot.mass_kg * (1 + 1e-9)), conn, cache, fn)
    assert fn.calls == 2
    canon = dc.canonical({"a": [0.1 + 0.2, 1.0, float("inf"), -3e-20], "b": 3, "c": True, "d": "x"})
    assert canon == {"a": [0.3, 1.0, float("inf"), 0.0], "b": 3.0, "c": True, "d": "x"}
    assert type(canon["b"]) is float and canon["c"] is True


def test_a_corrupt_cache_file_is_recomputed_and_rewritten(setup):
    robot, conn, cache = setup
    fn = Counter()
    _call(robot, conn, cache, fn)
    (f,) = cache.glob("*.json")
    for bad in ("{not json", json.dumps({"key": f.stem, "allowance_m": -1.0}), json.dumps([1, 2])):
        f.write_text(bad)
        _call(robot, conn, cache, fn)
        assert json.loads(f.read_text())["allowance_m"] >= 0
    assert fn.calls == 4


def test_the_packaged_allowances_are_the_current_models(tmp_path):
    """The shipped line allowance is what a fresh integration of today's model gives for the
    default record (a stale ``MODEL_VERSION`` or record shows here)."""
    from structure_fem.model.dynamics import dynamic_allowance_m
    from structure_fem.outputs.runs import RunOptions, make_inputs

    packaged = json.loads(dc.PACKAGED.read_text())
    line = [e for e in packaged if e["structure"] == "line"]
    assert line, "no packaged line allowance: regenerate with python -m structure_fem.outputs.runs"
    inp, _ = make_inputs(RunOptions())
    s = Structure("line")
    # the record's own (the others are the margins' range variants: other play, modulus, mass)
    own = [e for e in line if dc.key_of(dc.inputs_of(s, e["width"], e["rows"], inp.robot, inp.connectors,
                                                     e["flexible"], e["damping_ratio"], ("support_loss", "docking")))
           == e["key"]]
    assert own, "no packaged line allowance is for the default record: regenerate"
    e = min(own, key=lambda e: e["width"])
    from structure_fem.model.statics import Config, solve

    static = solve(Config(s, e["rows"], int(e["width"]), int(e["width"])), inp.robot, inp.connectors, e["flexible"])
    fresh = dynamic_allowance_m(s, int(e["width"]), inp.robot, e["damping_ratio"], connectors=inp.connectors,
                                flexible=e["flexible"], static=static)
    assert fresh == pytest.approx(e["allowance_m"], rel=1e-6, abs=1e-9)


def _jobs(robot, conn, widths=(1, 2)):
    from structure_fem.analysis.study import StudyInputs, min_rows

    inp = StudyInputs(robot, conn, clearance_m=0.015, max_width=4)
    out = []
    for w in widths:
        rows, _res = min_rows(LINE, w, inp)
        out.append(dc.Job(LINE, w, rows, robot, conn, True, 0.02))
    return out


def test_prefill_integrates_in_workers_what_a_direct_integration_gives(setup, monkeypatch):
    """Two transients integrated side by side in worker processes are then served from the
    cache (no integration here) and equal, bit for bit, the same integration in this process."""
    from structure_fem.model import dynamics

    robot, conn, cache = setup
    jobs = _jobs(robot, conn)
    assert dc.prefill(jobs, workers=2, cache_dir=cache) == 2
    assert dc.prefill(jobs, workers=2, cache_dir=cache) == 0  # nothing left to do
    direct = [dynamics.dynamic_allowance_m(j.structure, j.width, robot, 0.02, rows=j.rows, connectors=conn, flexible=True)
              for j in jobs]

    def boom(*a, **k):
        raise AssertionError("integrated what prefill computed")

    monkeypatch.setattr(dynamics, "dynamic_allowance_m", boom)
    got = [dc.allowance_m(j.structure, j.width, robot, 0.02, rows=j.rows, connectors=conn, flexible=True,
                          cache_dir=cache) for j in jobs]
    assert got == direct and all(a > 0 for a in got)
    assert {e["key"] for e in dc.used()} >= {j.key() for j in jobs}  # shipped by write_packaged


def test_a_transient_that_fails_in_a_worker_fails_at_once_for_the_caller(setup, monkeypatch):
    """A worker's SolverFailure is remembered: the caller's own call raises it (and counts the
    width as failing) without integrating it a second time."""
    from structure_fem.errors import SolverFailure
    from structure_fem.model import dynamics

    robot, conn, cache = setup
    jobs = _jobs(replace(robot, mass_kg=robot.mass_kg * 1.37), conn, (3, 4))
    calls = []

    def fails(*a, **k):
        calls.append(1)
        raise SolverFailure("test: no convergence")

    monkeypatch.setattr(dynamics, "dynamic_allowance_m", fails)  # the forked workers inherit it
    assert dc.prefill(jobs, workers=2, cache_dir=cache) == 2
    assert calls == []  # it ran in the workers
    for j in jobs:
        with pytest.raises(SolverFailure, match="no convergence"):
            dc.allowance_m(j.structure, j.width, j.robot, 0.02, rows=j.rows, connectors=conn, flexible=True,
                           cache_dir=cache)
    assert calls == []
    assert not list(cache.glob("*.json"))


def test_bad_worker_counts_are_refused(monkeypatch):
    from structure_fem.errors import InputError

    monkeypatch.setenv(dc.WORKERS_ENV, "0")
    with pytest.raises(InputError, match="VOIDCROSS_TRANSIENT_WORKERS.*'0'"):
        dc.workers_default()
    monkeypatch.setenv(dc.WORKERS_ENV, "3")
    assert dc.workers_default() == 3


def _prefill_in_a_daemon(robot, conn, cache) -> int:
    heavier = [replace(robot, mass_kg=robot.mass_kg * f) for f in (1.11, 1.13)]  # keys no other test computed
    return dc.prefill(_jobs(heavier[0], conn, (1,)) + _jobs(heavier[1], conn, (1,)), workers=2, cache_dir=cache)


def test_prefill_inside_a_daemonic_pool_worker_runs_in_that_worker(setup):
    """A daemonic process (a multiprocessing.Pool's worker) may not start processes: prefill then
    integrates in that process instead of failing."""
    import multiprocessing as mp

    robot, conn, cache = setup
    with mp.get_context("fork").Pool(1) as pool:
        assert pool.apply_async(_prefill_in_a_daemon, (robot, conn, cache)).get(timeout=300) == 2
    assert len(list(cache.glob("*.json"))) == 2
