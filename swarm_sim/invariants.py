"""Invariants checked every step in tests and ``--debug`` runs.

* robot count conserved (no robot vanishes, no NaN pose);
* no robot body over the void unless it is a member of a structure that satisfies
  the stability rule (:func:`swarm_sim.behaviour.structure.stable`) where it stands;
* no robot outside the arena walls;
* structure bookkeeping: members unique, their ``struct_index`` equals 1..n front to rear,
  member poses lie on the structure's line;
* tapering arch (:mod:`swarm_sim.behaviour.taper`): every shell slot holds at most one robot and no
  robot is both in the core and in a foot; shell robots sit at their slot pose with their
  (q, layer, foot) roles; the rule is checked in robots (core rows plus shell robots).
"""

from __future__ import annotations

import numpy as np

from swarm_sim.behaviour import piers as PR
from swarm_sim.behaviour import rule as R
from swarm_sim.behaviour import structure as S
from swarm_sim.behaviour import taper as T
from swarm_sim.engine.world import World

from .params import Params, level_params
from .state import OPEN, Mode, SwarmState


def violations(state: SwarmState, p: Params, world: World, n_robots: int) -> list[str]:
    out: list[str] = []
    n = state.n
    if n != n_robots or any(a.shape[0] != n_robots for a in (state.y_cm, state.heading_rad, state.mode)):
        out.append(f"t={state.t_s:.2f}s: robot count {n} != {n_robots}")
        return out
    if not (np.isfinite(state.x_cm).all() and np.isfinite(state.y_cm).all()):
        out.append(f"t={state.t_s:.2f}s: non-finite robot pose")
        return out
    st = state.structure
    filled = [m for m in st.members if m != OPEN] if st is not None else []
    shell = [m for m in st.shell if m != OPEN] if st is not None else []
    members = set(filled) | set(shell)
    if st is not None and len(members) != len(filled) + len(shell):
        out.append(f"t={state.t_s:.2f}s: a robot holds two structure slots")
    if st is not None and len(set(filled)) != len(filled):
        out.append(f"t={state.t_s:.2f}s: duplicate structure members {st.members}")
    ex, ey = world.half_extents(state.heading_rad)
    x, y = state.x_cm, state.y_cm
    over = (x + ex > world.x0_cm + 1e-9) & (x - ex < world.x1_cm - 1e-9)
    # supported otherwise: robots stacked in a pier (on the floor) and a pier round's robots
    # riding on the structure's top (swarm_sim.behaviour.piers)
    held = members | set(np.flatnonzero(state.mode == Mode.PIER).tolist()) | set(
        PR.carried(st) if st is not None else ())
    for i in (np.flatnonzero(over) if over.any() else ()):
        if int(i) not in held:
            out.append(f"t={state.t_s:.2f}s: robot {int(i)} (mode {Mode(int(state.mode[i])).name}) is over the "
                       f"void at ({state.x_cm[i]:.2f}, {state.y_cm[i]:.2f}) cm outside any structure")
    if st is not None and (st.members or st.shell) and st.action != "align":
        fr, vv, rule = PR.rule_frame(st, p) if st.piers else (st.front_s_cm, p.void_width_cm, level_params(p, st).rule)
        c = S.counts_at(fr, S.full_rows(st), p.robot_length_cm, vv)
        if (not level_params(p, st).taper_block_rows and st.members
                and S.all_rows(st) > S.full_rows(st)) and S.centres_s(st, p.robot_length_cm)[-1] > 0:
            out.append(f"t={state.t_s:.2f}s: a partly filled row is off the initial ground")
        p = level_params(p, st)
        if p.taper_block_rows:
            g = T.shell_geometry(p.layers, p.taper_block_rows, p.void_width)
            rc = T.counts(st.front_s_cm, T.core_rows(st), T.shell_counts(st.shell, g), p.robot_length_cm,
                          p.void_width_cm)
            if not R.stable(rc, *p.rule):
                out.append(f"t={state.t_s:.2f}s: tapering arch n_p={rc.n_p} n_g={rc.n_g} n_o={rc.n_o} robots "
                           f"breaks the rule (ratio {p.ground_ratio}, margin {p.ground_margin}, span "
                           f"{p.max_span_widths}, core rows over {rc.core_rows_over})")
            out += _shell_violations(state, st, g, p)
        elif st.piers and not PR.stable_at(st, p, st.front_s_cm, S.full_rows(st)):
            out.append(f"t={state.t_s:.2f}s: structure n_p={c.n_p} n_g={c.n_g} n_o={c.n_o} (from the last pier) "
                       f"breaks the rule over its piers {st.piers}")
        elif c.n_g and not R.stable(c, *rule):
            out.append(f"t={state.t_s:.2f}s: structure n_p={c.n_p} n_g={c.n_g} n_o={c.n_o} breaks the "
                       f"rule (ratio {rule[0]}, margin {rule[1]}, span {rule[2]}"
                       + (f", counted from pier far face at {vv - p.void_width_cm:+.1f} cm" if st.piers else "")
                       + ")")
        ids, slots = S.occupied(st)
        if (state.struct_index[ids] != slots // S.row_size(st) + 1).any():
            out.append(f"t={state.t_s:.2f}s: structure indices {state.struct_index[ids].tolist()} are not 1..n")
        mx, my, _ = S.member_poses(st, p.robot_length_cm, p.robot_width_cm, slots)
        if ids.size and (np.abs(state.x_cm[ids] - mx).max() > 1e-6 or np.abs(state.y_cm[ids] - my).max() > 1e-6):
            out.append(f"t={state.t_s:.2f}s: structure members are off the line")
    outside = (x - ex < -1e-6) | (x + ex > world.w_cm + 1e-6) | (y - ey < -1e-6) | (y + ey > world.h_cm + 1e-6)
    for i in (np.flatnonzero(outside) if outside.any() else ()):
        out.append(f"t={state.t_s:.2f}s: robot {int(i)} is outside the arena at "
                   f"({state.x_cm[i]:.2f}, {state.y_cm[i]:.2f}) cm")
    return out


def _shell_violations(state: SwarmState, st, g, p: Params) -> list[str]:
    out: list[str] = []
    if len(st.shell) != g.n:
        return [f"t={state.t_s:.2f}s: shell has {len(st.shell)} slots, geometry {g.n}"]
    sh = np.asarray(st.shell, dtype=np.int64)
    slots = np.flatnonzero(sh != OPEN)
    if not slots.size:
        return out
    ids = sh[slots]
    sx, sy = T.slot_xy(st, g, p.robot_length_cm, p.robot_width_cm, slots)
    if np.abs(state.x_cm[ids] - sx).max() > 1e-6 or np.abs(state.y_cm[ids] - sy).max() > 1e-6:
        out.append(f"t={state.t_s:.2f}s: shell robots are off their slot poses")
    if (state.mode[ids] != Mode.MEMBER).any():
        out.append(f"t={state.t_s:.2f}s: a shell robot is not a structure member")
    if (state.struct_line[ids] != g.q[slots]).any() or (state.struct_layer[ids] != g.z[slots]).any() or (
            state.struct_opposite is not None and (state.struct_opposite[ids] != g.foot[slots]).any()):
        out.append(f"t={state.t_s:.2f}s: shell robots' line/layer/opposite roles disagree with their slots")
    return out


def lost_robots(state: SwarmState, world: World) -> np.ndarray:
    """Robots that would fall: body over the void while not in the structure (cheap check)."""
    x = state.x_cm
    r = world.body_radius_cm  # no body reaches farther than this from its centre
    near = np.flatnonzero((x > world.x0_cm - r) & (x < world.x1_cm + r))
    if not near.size:
        return near
    near = near[world.over_void(x[near], state.heading_rad[near])]
    if near.size:
        near = near[state.mode[near] != Mode.PIER]  # in a pier: standing on the floor, never lost
    st = state.structure
    if near.size and st is not None and (st.members or st.shell):
        # structure members (open slots are OPEN = -1, never a robot id) and the feet are carried
        carried = set(st.members)
        carried.update(st.shell)
        carried.update(PR.carried(st))
        near = np.array([i for i in near.tolist() if i not in carried], dtype=np.int64)
    return near
