"""Static solves cached by input and code hash (structure_fem.solve_cache)."""

from __future__ import annotations

from dataclasses import replace

import pytest

pytest.importorskip("exudyn")

from structure_fem import solve_cache
from structure_fem.errors import SolverFailure  # noqa: E402
from structure_fem.model import statics as model  # noqa: E402
from structure_fem.model.statics import Config, solve  # noqa: E402
from structure_fem.model.structures import Structure  # noqa: E402


@pytest.fixture
def counted(monkeypatch, tmp_path):
    """A private cache and a count of the real solves."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.delenv("VOIDCROSS_SOLVE_CACHE", raising=False)
    calls = []
    real = model.solve_uncached

    def counting(*a, **k):
        calls.append(a[0])
        return real(*a, **k)

    monkeypatch.setattr(model, "solve_uncached", counting)
    return calls


CFG = Config(Structure("line"), 5, 2, 2)


def test_a_repeated_solve_is_read_back_identical(counted, make_robot):
    robot = make_robot(backlash=0.005)
    a = solve(CFG, robot)
    b = solve(CFG, robot)
    assert len(counted) == 1
    assert b.tip_deflection_m == a.tip_deflection_m and (b.com_m == a.com_m).all()
    assert solve_cache.cache_path().is_file()


def test_every_input_is_in_the_key(counted, make_robot):
    robot = make_robot(backlash=0.005)
    solve(CFG, robot)
    solve(replace(CFG, rows_over=1), robot)
    solve(CFG, replace(robot, mass_kg=robot.mass_kg * 1.001))
    solve(CFG, robot, flexible=True)
    solve(CFG, robot, options=model.SolverOptions(load_steps=16))
    from structure_fem.model.connectors import ConnectorSet

    solve(CFG, robot, ConnectorSet.from_robot(robot).scaled(1.0, 1.01))
    assert len(counted) == 6
    # and a change of the model's code is too: it is in every key
    assert solve_cache.key_of(1) != __import__("hashlib").sha256(repr((1,)).encode()).hexdigest()


def test_a_failure_is_cached_and_raised_again(monkeypatch, counted, make_robot):
    def fails(config, *a, **k):
        counted.append(config)
        raise SolverFailure(f"static solve failed for {config.describe()}: forced")

    monkeypatch.setattr(model, "solve_uncached", fails)
    for _ in range(2):
        with pytest.raises(SolverFailure, match="forced"):
            solve(CFG, make_robot())
    assert len(counted) == 1


def test_a_corrupt_cache_file_is_ignored(counted, make_robot):
    robot = make_robot()
    p = solve_cache.cache_path()
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_bytes(b"this is not a database" * 100)
    solve_cache._CONN = None
    a = solve(CFG, robot)
    b = solve(CFG, robot)
    assert a.tip_deflection_m == b.tip_deflection_m and len(counted) == 2  # no cache, still right


def test_it_can_be_turned_off(monkeypatch, counted, make_robot):
    monkeypatch.setenv("VOIDCROSS_SOLVE_CACHE", "0")
    solve(CFG, make_robot())
    solve(CFG, make_robot())
    assert len(counted) == 2


def _slow_solver(config, robot, conn, flexible, options):
    """A stand-in solve that takes 1 s and says it ran (one line per real solve)."""
    import time

    with open(config, "a") as fh:  # ``config`` is the count file's path here
        fh.write("solved\n")
    time.sleep(1.0)
    return {"tip_mm": 1.25}


def _solve_in_child(count_file, cache, out):
    import os

    os.environ["XDG_CACHE_HOME"] = cache
    solve_cache._CONN = solve_cache._LOCK_FD = None  # the child's own connection and lock
    res = solve_cache.cached_solve(_slow_solver, SolverFailure, count_file, "robot", "conn", False, "options")
    out.put(res)


def test_two_processes_asking_for_one_solve_solve_it_once(tmp_path, monkeypatch):
    """Two processes sharing a cache (two `fem table`s, the test workers) ask for the same
    configuration at once: one solves, the other waits on the key's lock and reads its result."""
    import multiprocessing as mp

    monkeypatch.delenv("VOIDCROSS_SOLVE_CACHE", raising=False)
    count = tmp_path / "count.txt"
    ctx = mp.get_context("fork")
    q = ctx.Queue()
    procs = [ctx.Process(target=_solve_in_child, args=(str(count), str(tmp_path / "cache"), q)) for _ in range(2)]
    for p in procs:
        p.start()
    results = [q.get(timeout=60) for _ in procs]
    for p in procs:
        p.join(60)
        assert p.exitcode == 0
    assert results == [{"tip_mm": 1.25}] * 2
    assert count.read_text() == "solved\n"  # once, not twice
