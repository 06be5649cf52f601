"""The bridge as a rigid moving line, its stability rule and its decision table.

The structure is data (:class:`swarm_sim.state.Structure`): ordered member ids
(front first), the near-edge origin, a direction and the front face's position
``front_s_cm`` past the near edge. Every member's pose follows from it, so the
stability rule is exact: each member is counted by where its centre of mass is:

* ``n_p`` on the initial ground (centre before the near edge),
* ``n_g`` over the void,
* ``n_o`` on the target ground (centre past the far edge).

Stability rule (the limits record's ``ground_ratio`` r and ``ground_margin`` m,
the case's margin already added; thesis r = 2, m = 0 for cases B-D, m = 2 for A):

* cantilever from the initial side (``n_o = 0``): ``n_p >= r n_g + m``;
* cantilever from the target side (``n_p = 0``): ``n_o >= r n_g + m``;
* both ends on ground: ``n_p + n_o >= r n_g + m``;
* and never more than the line's widest span (``max_span_widths``) over the void.

With r = 2, m = 0 the front reaches the far ledge (``n_g = w``) only with
``n_p = 2w``, so N = 3w crosses and 3w - 1 retreats (Ch. 4.6.3); the bridged
steady state is ``n_p = n_g = n_o`` with 3w + 1 robots while the front one is
released. With m = 2 it is case A's N = 3w + 2.

The decision table (:data:`BUILD_TABLE`, :data:`RETREAT_TABLE`) is evaluated in
order when the structure is idle; the first row whose guard holds is the action.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from swarm_sim.behaviour import rule as R
from swarm_sim.state import OPEN, Structure

if TYPE_CHECKING:
    from swarm_sim.params import Params

EPS = 1e-6

#: Structure actions (the ``action`` field): what the structure is doing now.
ACTIONS = {
    "align": "the seed turns perpendicular to the edge and creeps to it",
    "idle": "decide the next action from the table",
    "wait": "pause after a release until the released robot is clear",
    "recruit": "a called robot approaches the rear dock point",
    "advance": "move forward one robot length",
    "back": "move backward one robot length (retreat)",
    "pier": "a failed robot is brought to the pier beyond the front (swarm_sim.piers)",
}


def row_size(st: Structure) -> int:
    """Robots per row: ``lines`` side by side times ``layers`` stacked (1 for the single line)."""
    return st.lines * st.layers


def full_rows(st: Structure) -> int:
    return len(st.members) // row_size(st)


def all_rows(st: Structure) -> int:
    k = row_size(st)
    return (len(st.members) + k - 1) // k


def centres_s(st: Structure, L: float) -> np.ndarray:
    """Distance of each member's centre past the near edge (cm), in member order."""
    m = np.arange(len(st.members))
    return st.front_s_cm - (m // row_size(st) + 0.5) * L


def slot_pose(st: Structure, m: int, L: float, W: float) -> tuple[float, float, int, int]:
    """Centre (x, y) cm, line and layer of member slot ``m`` (row-major: row, then line, then layer)."""
    k = row_size(st)
    row, q = divmod(m, k)
    line, layer = q % st.lines, q // st.lines
    s = st.front_s_cm - (row + 0.5) * L
    lat = line * W * st.lateral_sign
    return (st.origin_x_cm + s * st.dir_x - lat * st.dir_y, st.origin_y_cm + s * st.dir_y + lat * st.dir_x,
            line, layer)


def occupied(st: Structure) -> tuple[np.ndarray, np.ndarray]:
    """(robot ids, their slot indices) of the filled slots, front to rear."""
    mem = np.asarray(st.members, dtype=np.int64)
    slots = np.flatnonzero(mem != OPEN)
    return mem[slots], slots


def open_columns(st: Structure) -> list[int]:
    """Row positions q (line + layer * lines) that still have an open slot after a switch."""
    k = row_size(st)
    return sorted({m % k for m, r in enumerate(st.members) if r == OPEN})


def filling(st: Structure) -> bool:
    return OPEN in st.members


def widened(st: Structure, lines: int, layers: int) -> tuple[int, ...]:
    """Members laid out for a wider cross-section: every robot keeps its row, line and layer;
    the new lines/layers are open slots."""
    k_old, k_new = row_size(st), lines * layers
    rows = all_rows(st)
    out = [OPEN] * (rows * k_new)
    for m, r in enumerate(st.members):
        row, q = divmod(m, k_old)
        line, layer = q % st.lines, q // st.lines
        out[row * k_new + line + layer * lines] = r
    return tuple(out)


def member_poses(st: Structure, L: float, W: float | None = None,
                 m: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, float]:
    """Centres of the member slots ``m`` (default: every slot) and the common heading."""
    W = L if W is None else W
    k = row_size(st)
    m = np.arange(len(st.members)) if m is None else m
    if k == 1:  # the single line
        s = st.front_s_cm - (m + 0.5) * L
        return st.origin_x_cm + s * st.dir_x, st.origin_y_cm + s * st.dir_y, math.atan2(st.dir_y, st.dir_x)
    s = st.front_s_cm - (m // k + 0.5) * L
    lat = ((m % k) % st.lines) * W * st.lateral_sign
    return (st.origin_x_cm + s * st.dir_x - lat * st.dir_y, st.origin_y_cm + s * st.dir_y + lat * st.dir_x,
            float(np.arctan2(st.dir_y, st.dir_x)))


def counts_at(front_s: float, n: int, L: float, void_cm: float) -> R.Counts:
    """Rows (of any size) counted by where their centre of mass is (:func:`swarm_sim.behaviour.rule.counts`)."""
    return R.counts(front_s, n, L, void_cm)


@dataclass(frozen=True)
class Situation:
    """What the structure knows when idle (all local to the structure or broadcast).
    Counts are in rows; a partly filled rear row (being recruited) is not counted."""

    counts: R.Counts
    n: int
    landed: bool
    front_on_target: bool
    rear_on_initial: bool
    free_available: bool
    dock_ok: bool
    can_advance: bool
    span_blocked: bool
    stable_without_front: bool
    stable_without_rear: bool
    filling: bool = False      # new lines/layers of a switch still have open slots
    can_switch: bool = False   # structure = "switch" and a wider level follows this one
    pier_ready: bool = False   # a pier can be built (or continued) beyond the front (swarm_sim.behaviour.piers)
    can_back: bool = True      # backing one length keeps the rule (only ever false over piers)


def situation(st: Structure, p: Params, free_available: bool, dock_ok: bool, pier_ready: bool = False) -> Situation:
    """With piers (:func:`swarm_sim.behaviour.rule.rule_frame`) the rule is counted from the last
    complete pier's far face once the front has reached it."""
    from swarm_sim.behaviour.rule import rule_frame

    L, V0 = p.robot_length_cm, p.void_width_cm
    n, n_all = full_rows(st), all_rows(st)
    front, V, rule = rule_frame(st, p) if st.piers else (st.front_s_cm, V0, p.rule)
    c = counts_at(front, n, L, V)
    front_on_target = n_all > 0 and st.front_s_cm - L >= V0 - EPS
    rear_on_initial = n_all > 0 and st.front_s_cm - (n_all - 1) * L <= EPS
    after = counts_at(front + L, n, L, V)
    span_blocked = not st.landed and after.n_g > rule[2]
    launch_ok = n >= p.launch_min_robots or st.front_s_cm > EPS
    fill = filling(st)
    short_rear = n_all > n          # a rear row being recruited (not counted)
    partial = short_rear or fill    # ... or new lines still open after a switch: no move, no release
    if st.piers:  # the piers are supports (swarm_sim.behaviour.piers)
        from swarm_sim.behaviour.rule import move_ok, stable_at

        f0 = st.front_s_cm
        # before landing the rear row stays on the initial ground (the pier rule's derivation keeps
        # at least one row on the near ledge in every state it checked): a line that advanced its
        # rear off the ledge could no longer dock a recruit, and one short of the far ledge retreated
        keeps_rear = st.landed or f0 + L - (n_all - 1) * L <= EPS
        can_advance = (launch_ok and not partial and not span_blocked and keeps_rear
                       and move_ok(st, p, f0, f0 + L, n))
        wo_front_ok = n <= 1 or stable_at(st, p, f0 - L, n - 1)
        wo_rear_ok = stable_at(st, p, f0, n) if short_rear else (n <= 1 or stable_at(st, p, f0, n - 1))
        if st.retreating and not short_rear and n > 1:
            # the rest backs off the piers later: it must stay stable all the way back to the edge
            wo_rear_ok = wo_rear_ok and move_ok(st, p, f0, 0.0, n - 1)
        can_back = not st.retreating or move_ok(st, p, f0, f0 - L, n)
    else:
        can_advance = (launch_ok and not partial and not span_blocked
                       and R.move_stable(front, front + L, n, L, V, *rule))
        wo_front = counts_at(front - L, n - 1, L, V) if n > 1 else R.Counts(0, 0, 0)
        wo_rear = c if short_rear else (counts_at(front, n - 1, L, V) if n > 1 else R.Counts(0, 0, 0))
        wo_front_ok, wo_rear_ok = R.stable(wo_front, *rule), R.stable(wo_rear, *rule)
        can_back = True
    return Situation(c, n, st.landed, front_on_target and not partial, rear_on_initial, free_available,
                     dock_ok, can_advance, span_blocked, wo_front_ok, wo_rear_ok,
                     fill, bool(p.switch_levels) and st.level + 1 < len(p.switch_levels), pier_ready, can_back)


def can_recruit(s) -> bool:
    """A robot can be called to the rear: one is free, the rear is on the initial ground and its
    dock point is clear (any structure's situation)."""
    return s.free_available and s.rear_on_initial and s.dock_ok


def first_match(table: tuple, s) -> str:
    """The action of the first row of a decision table whose guard holds for situation ``s``."""
    for action, guard, *_ in table:
        if guard(s):
            return action
    raise AssertionError("decision table has no default row")  # pragma: no cover


#: Building (not retreating): (action, guard, guard in words) rows, first match wins. The docs'
#: table is generated from these rows (:mod:`swarm_sim.decision_docs`).
BUILD_TABLE = (
    ("release_front", lambda s: s.front_on_target and s.stable_without_front,
     "the front robot stands fully on the target ground and the rest stays stable without it"),
    # issue 16: a pier of known failed robots beyond the front lengthens the line's span
    ("pier", lambda s: s.span_blocked and s.pier_ready and not s.filling,
     "the next advance would exceed the span and a pier can be built beyond the front"),
    # Ch. 5.5.2: the far ledge is not found within this level's span: widen to the next level
    ("switch", lambda s: s.span_blocked and s.can_switch and not s.filling,
     "the next advance would exceed this level's span, a wider level follows, no switch under way"),
    ("recruit", lambda s: s.filling and can_recruit(s),
     "a switch is filling its new lines/layers and a robot can be called"),
    ("retreat", lambda s: s.filling, "a switch is filling and no robot can be called"),
    ("retreat", lambda s: s.span_blocked, "the next advance would exceed the widest level's span"),
    ("recruit", lambda s: can_recruit(s) and (s.counts.n_p <= s.counts.n_g if s.landed else not s.can_advance),
     "a robot can be called and (landed: n_p <= n_g; not landed: the structure cannot advance)"),
    ("advance", lambda s: s.can_advance,
     "enough robots to launch, no partial row, and the advance keeps the counting rule"),
    ("recruit", lambda s: can_recruit(s), "a robot can be called"),
    ("retreat", lambda s: True, "otherwise: no robot can be called and the structure cannot advance"),
)

#: Retreating: release at the rear while the rest stays stable, else back off one length.
RETREAT_TABLE = (
    ("release_rear", lambda s: s.rear_on_initial and s.stable_without_rear,
     "the rear robot stands on the initial ground and the rest stays stable without it"),
    ("back", lambda s: s.can_back, "otherwise, if backing keeps the rule (always, without piers): move back one length"),
    ("hold", lambda s: True, "otherwise (over piers, backing would break the rule): stand, stable; the run ends "
     "stranded if nothing changes"),
)


def decide(st: Structure, p: Params, free_available: bool, dock_ok: bool,
           pier_ready: bool = False) -> tuple[str, Situation]:
    """``p``: the structure's level params (:func:`swarm_sim.params.level_params`)."""
    s = situation(st, p, free_available, dock_ok, pier_ready)
    return first_match(RETREAT_TABLE if st.retreating else BUILD_TABLE, s), s
