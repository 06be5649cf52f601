"""The brief: swarm_sim imports without cadquery, exudyn or gmsh installed (it shares only light
modules with the other packages, e.g. cubot_cad.atomic's writer and structure_fem's limits record)."""

from __future__ import annotations

import subprocess
import sys

BLOCK = """
import sys
class Block:
    def find_spec(self, name, path=None, target=None):
        if name.split('.')[0] in ('cadquery', 'OCP', 'exudyn', 'gmsh', 'skfem'):
            raise ImportError('blocked for this test: ' + name)
sys.meta_path.insert(0, Block())
import swarm_sim.runner, swarm_sim.render, swarm_sim.experiments.soak, swarm_sim.sweeps.export, swarm_sim.compiled
from swarm_sim.runner import run_scenario
r = run_scenario('case-d', 3, 1, 1, limits='thesis', max_time_s=5.0)
print('ok', r.steps)
"""


def test_swarm_sim_runs_without_cadquery_exudyn_or_gmsh():
    res = subprocess.run([sys.executable, "-c", BLOCK], capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr[-2000:]
    assert res.stdout.startswith("ok ")
