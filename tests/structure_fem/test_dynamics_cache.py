"""The launch transients' allowance cache (structure_fem.dynamics_cache): a pure function of its inputs."""

from __future__ import annotations

import json
from dataclasses import replace

import pytest

from structure_fem import dynamics_cache as dc
from structure_fem.connectors import ConnectorSet
from structure_fem.structures import Structure

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
    from structure_fem.dynamics import dynamic_allowance_m
    from structure_fem.runs import RunOptions, make_inputs

    packaged = json.loads(dc.PACKAGED.read_text())
    line = [e for e in packaged if e["structure"] == "line"]
    assert line, "no packaged line allowance: regenerate with python -m structure_fem.runs"
    e = min(line, key=lambda e: e["width"])
    inp, _ = make_inputs(RunOptions())
    s = Structure("line")
    key = dc.key_of(dc.inputs_of(s, e["width"], e["rows"], inp.robot, inp.connectors, e["flexible"],
                                 e["damping_ratio"], ("support_loss", "docking")))
    assert key == e["key"], "the packaged allowance is not for the default record: regenerate"
    from structure_fem.model import Config, solve

    static = solve(Config(s, e["rows"], int(e["width"]), int(e["width"])), inp.robot, inp.connectors, e["flexible"])
    fresh = dynamic_allowance_m(s, int(e["width"]), inp.robot, e["damping_ratio"], connectors=inp.connectors,
                                flexible=e["flexible"], static=static)
    assert fresh == pytest.approx(e["allowance_m"], rel=1e-6, abs=1e-9)
