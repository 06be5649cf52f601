"""The thesis's tapering arch (Ch. 5.5.2 (c)-(f), Fig. 5.2-5.3): a moving core and a static foot per ledge.

Geometry (robot lengths ``L``, widths ``W``): row ``i`` occupies ``[i, i + 1) L`` past the
near edge (negative rows on the initial ground). Its half-level ``j`` comes from the limits
record (:func:`structure_fem.limits.taper_half_level`); the row's section is ``2j`` robots
wide, ``j`` high, with lateral positions ``q = -(j-1) .. j`` and layers ``z = 0 .. j-1``.

* The CORE is the two lines ``q in {0, 1}``, ``z = 0``: the ordinary conveyor (recruit a row
  of two at the rear, advance one row, release a row at the front). It lives in
  ``Structure.members`` (``lines = 2``, ``layers = 1``) and slides through the feet.
* Every other ``(q, z)`` slot is a SHELL slot, fixed relative to its ledge. The shell slots
  of one ``(q, z)`` and one foot form a contiguous COLUMN of rows. A column grows from its
  rear (the end on the ground away from the void): the column slides one row towards the
  void and the recruit docks at the rear slot (:func:`fill_column`); it dissolves in
  reverse (:func:`pop_column`). ``Structure.shell`` holds the robot of each shell slot
  (:data:`~swarm_sim.state.OPEN` when empty), in :class:`ShellGeometry` slot order.

Role variables of Table 5.1 as state arrays (:class:`swarm_sim.state.SwarmState`):

=====================  ===========================================================
thesis variable        state
=====================  ===========================================================
start = 1              ``mode == EXPLORE`` (0 once the robot joins or is released)
coreL n / coreR n      ``struct_line == 0 / 1``, ``struct_layer == 0``, ``struct_index == n``
layerXside(L/R)Y n     ``struct_layer == X``; side L: ``struct_line == -(Y-1)`` (q <= 0),
                       side R: ``struct_line == Y`` (q >= 1, Y >= 2 or X >= 1),
                       ``struct_opposite == 0``, ``struct_index`` = position in the column
OlayerXside(L/R)Y n    the same with ``struct_opposite == 1`` (the far foot)
opposite = 1           ``mode == TARGET`` (released on the target side)
=====================  ===========================================================

Counting rule of a tapered level: robots (not rows) by where their centre is, core rows
plus shell robots: cantilever ``n_p >= r n_g + m``, landed ``n_p + n_o >= r n_g + m`` (r, m
from the level: thesis r = 1, m = 1 robot), and never more core rows over the void than the
level's span. The decision table :data:`TAPER_TABLE` drives the structure.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from structure_fem.limits import taper_half_level
from swarm_sim.behaviour import rule as R
from swarm_sim.behaviour import structure as S
from swarm_sim.state import OPEN, Structure

EPS = 1e-6
NEAR, FAR = 0, 1


def jmin(q: int, z: int) -> int:
    """Smallest half-level whose section holds slot ``(q, z)``."""
    return max(1 - q, q, z + 1)


@dataclass(frozen=True)
class ShellGeometry:
    """Shell slots of a tapering arch with ``k`` layers, blocks of ``B`` rows, ``V`` void rows.

    Per slot: ``row``, ``q``, ``z``, ``foot`` (0 near, 1 far), ``col`` and ``pos`` (0 = the
    column's front, towards the middle of the void). ``cols[c]``: slot indices front first.
    ``groups[foot]``: column ids in fill order, grouped: layer by layer, inner columns first.
    """

    k: int
    B: int
    V: int
    row: np.ndarray
    q: np.ndarray
    z: np.ndarray
    foot: np.ndarray
    col: np.ndarray
    pos: np.ndarray
    cols: tuple
    col_q: tuple
    col_z: tuple
    col_foot: tuple
    groups: tuple   # (near groups, far groups); each group a tuple of column ids

    @property
    def n(self) -> int:
        return int(self.row.shape[0])

    def slot_of(self) -> dict:
        return {(int(r), int(q), int(z), int(f)): i for i, (r, q, z, f) in
                enumerate(zip(self.row, self.q, self.z, self.foot, strict=True))}


@lru_cache(maxsize=32)
def shell_geometry(k: int, B: int, V: int) -> ShellGeometry:
    rows_near = range(-k * B, V)
    rows_all = range(-k * B, V + k * B)
    jn = {r: taper_half_level(k, B, r, V, far_foot=False) for r in rows_all}
    jf = {r: taper_half_level(k, B, r, V, far_foot=True) for r in rows_all}
    row, qq, zz, ft, cc, pp = [], [], [], [], [], []
    cols, col_q, col_z, col_foot, keys = [], [], [], [], []
    for foot in (NEAR, FAR):
        for z in range(k):
            for q in range(-(k - 1), k + 1):
                if z == 0 and q in (0, 1):
                    continue  # the core
                need = jmin(q, z)
                if foot == NEAR:
                    rs = sorted((r for r in rows_near if jn[r] >= need), reverse=True)
                else:
                    rs = sorted(r for r in rows_all if jf[r] >= need and jn[r] < need)
                if not rs:
                    continue
                c = len(cols)
                ids = []
                for pos, r in enumerate(rs):
                    ids.append(len(row))
                    row.append(r)
                    qq.append(q)
                    zz.append(z)
                    ft.append(foot)
                    cc.append(c)
                    pp.append(pos)
                cols.append(np.array(ids, dtype=np.int64))
                col_q.append(q)
                col_z.append(z)
                col_foot.append(foot)
                keys.append((z, max(1 - q, q)))
    groups = []
    for foot in (NEAR, FAR):
        g: dict = {}
        for c, key in enumerate(keys):
            if col_foot[c] == foot:
                g.setdefault(key, []).append(c)
        groups.append(tuple(tuple(g[key]) for key in sorted(g)))
    a = lambda v: np.array(v, dtype=np.int64)  # noqa: E731
    return ShellGeometry(k, B, V, a(row), a(qq), a(zz), a(ft), a(cc), a(pp), tuple(cols), tuple(col_q),
                         tuple(col_z), tuple(col_foot), tuple(groups))


def empty_shell(g: ShellGeometry) -> tuple:
    return (OPEN,) * g.n


def remap_shell(shell: tuple, old: ShellGeometry, new: ShellGeometry) -> tuple:
    """Shell robots keep their (row, q, z, foot) slot when the level (k) grows."""
    out = list(empty_shell(new))
    where = new.slot_of()
    for i, r in enumerate(shell):
        if r != OPEN:
            out[where[(int(old.row[i]), int(old.q[i]), int(old.z[i]), int(old.foot[i]))]] = r
    return tuple(out)


# ---------------------------------------------------------------------------- columns

def column_open(shell: tuple, g: ShellGeometry, c: int) -> bool:
    return any(shell[i] == OPEN for i in g.cols[c])


def column_any(shell: tuple, g: ShellGeometry, c: int) -> bool:
    return any(shell[i] != OPEN for i in g.cols[c])


def fill_column(shell: list, g: ShellGeometry, c: int, robot: int) -> None:
    """The column's part behind its front-most open slot slides one row towards the void;
    ``robot`` docks at the rear slot (in place)."""
    ids = g.cols[c]
    vals = [shell[i] for i in ids]
    gap = vals.index(OPEN)
    vals = vals[:gap] + vals[gap + 1:] + [robot]
    for i, v in zip(ids, vals, strict=True):
        shell[i] = v


def pop_column(shell: list, g: ShellGeometry, c: int) -> int:
    """Reverse of :func:`fill_column`: the rear-most robot leaves, the column slides back one row."""
    ids = g.cols[c]
    vals = [shell[i] for i in ids]
    last = max(i for i, v in enumerate(vals) if v != OPEN)
    robot = vals[last]
    vals[last] = OPEN
    if vals[-1] == OPEN:
        vals = [OPEN] + vals[:-1]
    for i, v in zip(ids, vals, strict=True):
        shell[i] = v
    return robot


def next_fill_group(shell: tuple, g: ShellGeometry, foot: int) -> tuple:
    """Columns of the first group (fill order) with an open slot, only those still open."""
    for grp in g.groups[foot]:
        open_ = tuple(c for c in grp if column_open(shell, g, c))
        if open_:
            return open_
    return ()


def next_unfill_group(shell: tuple, g: ShellGeometry, foot: int) -> tuple:
    """Columns of the last group (reverse fill order) that still hold a robot."""
    for grp in reversed(g.groups[foot]):
        any_ = tuple(c for c in grp if column_any(shell, g, c))
        if any_:
            return any_
    return ()


def rear_slot(g: ShellGeometry, c: int) -> int:
    return int(g.cols[c][-1])


def slot_s_lat(g: ShellGeometry, L: float, W: float, slots: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance past the near edge (cm) and lateral offset (cm, before ``lateral_sign``) of slots."""
    return (g.row[slots] + 0.5) * L, g.q[slots] * W


def slot_xy(st: Structure, g: ShellGeometry, L: float, W: float, slots) -> tuple[np.ndarray, np.ndarray]:
    slots = np.asarray(slots, dtype=np.int64)
    s, lat = slot_s_lat(g, L, W, slots)
    lat = lat * st.lateral_sign
    return st.origin_x_cm + s * st.dir_x - lat * st.dir_y, st.origin_y_cm + s * st.dir_y + lat * st.dir_x


def staging_xy(st: Structure, g: ShellGeometry, L: float, W: float, c: int) -> tuple[float, float]:
    """Ground point one row behind column ``c``'s rear slot (away from the void)."""
    i = rear_slot(g, c)
    back = -1.0 if g.foot[i] == NEAR else 1.0
    s = (g.row[i] + 0.5 + back) * L
    lat = g.q[i] * W * st.lateral_sign
    return (float(st.origin_x_cm + s * st.dir_x - lat * st.dir_y),
            float(st.origin_y_cm + s * st.dir_y + lat * st.dir_x))


# ---------------------------------------------------------------------------- counting rule

def shell_counts(shell: tuple, g: ShellGeometry) -> tuple[int, int, int]:
    if not shell:
        return 0, 0, 0
    occ = np.asarray(shell, dtype=np.int64) != OPEN
    r = g.row[occ]
    p = int(np.sum(r < 0))
    o = int(np.sum(r >= g.V))
    return p, int(r.size) - p - o, o


def counts(front_s: float, rows: np.ndarray, shell_pgo: tuple, L: float, V_cm: float) -> R.Counts:
    """Robots (core rows, the rear one possibly partly filled, plus the shell) by where their
    centre is (:func:`swarm_sim.behaviour.rule.counts` with the rows' robot counts as weights)."""
    return R.counts(front_s, rows, L, V_cm, shell_pgo)


# ---------------------------------------------------------------------------- rule minimum

def near_shell_robots(k: int, B: int, V: int) -> int:
    g = shell_geometry(k, B, V)
    return int(np.sum(g.foot == NEAR))


def rule_min_robots(stages: list, V: int, entry_front_rows: int, entry_ground_rows: int, ratio: float,
                    margin: int) -> int:
    """Fewest robots with which the build lands on the far ledge, following the table's own
    sequence: at each tapered stage ``(k, B, span)`` the core first extends to ``k B`` ground
    rows, the near foot is built, then the core advances (recruiting a row only when fewer
    than ``k B`` rows would stay on the ground, or the rule needs it) to ``min(V, span)``.
    ``entry_*``: the core (rows of two) when the first tapered level takes over."""
    F, G, need = entry_front_rows, entry_ground_rows, 0
    for k, B, span in stages:
        G = max(G, k * B)
        F_end = min(V, span)
        G = max(k * B, G - max(0, F_end - F))
        g = shell_geometry(k, B, V)
        near = tuple(OPEN + 1 if f == NEAR else OPEN for f in g.foot)  # the complete near foot
        pgo = shell_counts(near, g)
        while not R.stable(counts(F_end * 1.0, np.full(F_end + G, 2), pgo, 1.0, float(V)), ratio, margin, span):
            G += 1
        need = max(need, int(np.sum(g.foot == NEAR)) + 2 * (F_end + G))
        F = F_end
    return need


# ---------------------------------------------------------------------------- decision table

@dataclass(frozen=True)
class TaperSituation:
    counts: R.Counts
    rows: int                 # full core rows
    ground_rows: int          # full core rows with their centre on the initial ground
    foot_rows: int            # k B: core rows kept on each ground while a foot stands
    landed: bool
    front_ready: bool
    rear_on_initial: bool
    free_available: bool
    dock_ok: bool
    can_advance: bool
    span_blocked: bool
    stable_without_front: bool
    stable_without_rear: bool
    filling: bool             # core line being widened to two (coming from a single line)
    can_switch: bool
    job_busy: bool
    near_open: bool
    near_any: bool
    far_any: bool
    fill_ok: bool
    unfill_ok: bool
    supply: bool = True       # a free robot or a near-foot robot can still join the core


#: Building a tapered level: (action, guard, guard in words), first match wins.
TAPER_TABLE = (
    ("hold", lambda s: s.job_busy and not s.landed, "not landed and a near-foot round is under way"),
    # no robot left to recruit: the core first walks onto the target ground, then releases
    ("advance", lambda s: s.landed and not s.supply and s.can_advance,
     "landed, no robot left to join the core, and the core can advance"),
    ("release_front", lambda s: s.front_ready and s.stable_without_front and not s.job_busy,
     "the front row is ready on the target ground, the rest stays stable, no foot round under way"),
    ("switch", lambda s: s.span_blocked and s.can_switch and not s.filling and not s.job_busy,
     "the next advance would exceed this level's span and a wider level follows (nothing under way)"),
    ("recruit", lambda s: s.filling and S.can_recruit(s), "the single line is being widened to two and a robot can be called"),
    ("retreat", lambda s: s.filling, "the line is being widened and no robot can be called"),
    # the core extends until k B rows stand on the initial ground (thesis: 15 rows for k = 3)
    ("recruit", lambda s: not s.landed and s.ground_rows < s.foot_rows and S.can_recruit(s),
     "not landed, fewer than k B core rows on the initial ground, a robot can be called"),
    ("retreat", lambda s: not s.landed and s.ground_rows < s.foot_rows,
     "not landed, fewer than k B core rows on the initial ground, no robot can be called"),
    ("fill_near", lambda s: not s.landed and s.near_open and s.free_available and s.fill_ok,
     "not landed, the near foot has open slots, a free robot exists and the fill keeps the rule"),
    ("recruit", lambda s: not s.landed and s.near_open and S.can_recruit(s),
     "not landed, the near foot has open slots: more counterweight is called"),
    ("retreat", lambda s: not s.landed and s.near_open, "not landed, the near foot is open and nobody can come"),
    ("retreat", lambda s: s.span_blocked, "the next advance would exceed the widest level's span"),
    ("recruit", lambda s: s.landed and s.ground_rows <= s.foot_rows and S.can_recruit(s),
     "landed, at most k B core rows on the initial ground, a robot can be called"),
    # no free robot left: the near foot breaks away into the core's rear (reverse fill order)
    ("unfill_near", lambda s: s.landed and s.near_any and not s.free_available and not s.job_busy
        and s.unfill_ok and s.ground_rows <= s.foot_rows,
     "landed, no free robot left: the near foot joins the core's rear in reverse fill order"),
    ("advance", lambda s: s.can_advance, "the core can advance"),
    ("recruit", lambda s: S.can_recruit(s), "a robot can be called"),
    ("dissolve_far", lambda s: s.rows == 0 and not s.near_any and s.far_any and not s.job_busy,
     "the core is gone and only the far foot remains: it dissolves onto the target ground"),
    ("hold", lambda s: s.landed or s.job_busy, "landed or a foot round under way: wait"),
    ("retreat", lambda s: True, "otherwise"),
)

#: Retreating a tapered level: the near foot dissolves first (reverse fill order, robots go
#: back to the initial side), then the core releases at the rear / backs off as the line does.
TAPER_RETREAT_TABLE = (
    ("hold", lambda s: s.job_busy, "a foot round is under way"),
    ("unfill_near", lambda s: s.near_any and (s.unfill_ok or s.counts.core_rows_over == 0),
     "the near foot still has robots and removing one keeps the rule (or no core row is over the void)"),
    ("release_rear", lambda s: not s.near_any and s.rear_on_initial and s.stable_without_rear,
     "no near foot, the rear row is on the initial ground and the rest stays stable"),
    ("back", lambda s: True, "otherwise: move back one robot length"),
)


def _fill_preview(shell: tuple, g: ShellGeometry, cols: tuple) -> tuple:
    out = list(shell)
    for c in cols:
        fill_column(out, g, c, 0)
    return tuple(out)


def _unfill_preview(shell: tuple, g: ShellGeometry, cols: tuple) -> tuple:
    out = list(shell)
    for c in cols:
        pop_column(out, g, c)
    return tuple(out)


def near_state(shell: tuple, g: ShellGeometry) -> tuple[bool, bool, bool]:
    """(near foot has an open slot, near foot holds a robot, far foot holds a robot)."""
    a = np.asarray(shell, dtype=np.int64)
    near = g.foot == NEAR
    occ = a != OPEN
    return bool((~occ & near).any()), bool((occ & near).any()), bool((occ & ~near).any())


def core_rows(st: Structure) -> np.ndarray:
    """Robots in each core row, front first."""
    k = S.row_size(st)
    mem = np.asarray(st.members, dtype=np.int64)
    if mem.size == 0:
        return np.zeros(0, dtype=np.int64)
    pad = (-mem.size) % k
    occ = np.concatenate([mem != OPEN, np.zeros(pad, dtype=bool)])
    return occ.reshape(-1, k).sum(axis=1)


def situation(st: Structure, p, g: ShellGeometry, free_count: int, row_free: bool,
              dock_ok: bool) -> TaperSituation:
    """What a tapered structure knows when idle (``p``: the level's params; ``free_count``
    free robots on the initial side, ``row_free``: enough of them for the core's rear row)."""
    L, V_cm = p.robot_length_cm, p.void_width_cm
    ratio, margin, span = p.ground_ratio, p.ground_margin, p.max_span_widths
    rows = core_rows(st)
    n_all = int(rows.size)
    n = S.full_rows(st)
    pgo = shell_counts(st.shell, g)
    c = counts(st.front_s_cm, rows, pgo, L, V_cm)
    ground = S.counts_at(st.front_s_cm, n_all, L, V_cm).n_p
    foot_rows = g.k * g.B
    near_open, near_any, far_any = near_state(st.shell, g)
    fill = S.filling(st)
    free = free_count > 0
    supply = free or near_any
    # a partly filled rear row waits for its robots while any can come (else it moves along)
    partial = fill or (n_all > n and supply)
    front_on_target = n_all > 0 and st.front_s_cm - L >= V_cm - EPS
    front_ready = (front_on_target and not partial
                   and (st.front_s_cm - foot_rows * L >= V_cm - EPS or not supply))
    rear_on_initial = n_all > 0 and st.front_s_cm - (n_all - 1) * L <= EPS
    after = counts(st.front_s_cm + L, rows, pgo, L, V_cm)
    span_blocked = not st.landed and after.core_rows_over > span
    launch_ok = n_all >= p.launch_min_robots or st.front_s_cm > EPS
    keep_ground = near_any or (near_open and not st.landed)
    ground_after = S.counts_at(st.front_s_cm + L, n_all, L, V_cm).n_p
    room = st.origin_x_cm + (st.front_s_cm + L) * st.dir_x <= p.arena_w_cm - 1e-6  # the far wall
    can_advance = (n_all > 0 and launch_ok and not partial and not span_blocked and room
                   and (not keep_ground or ground_after >= foot_rows)
                   and R.move_stable(st.front_s_cm, st.front_s_cm + L, rows, L, V_cm, ratio, margin, span, pgo))
    wo_front = counts(st.front_s_cm - L, rows[1:], pgo, L, V_cm)
    wo_rear = counts(st.front_s_cm, rows[:-1], pgo, L, V_cm)
    fill_ok = unfill_ok = False
    if near_open and free:
        grp = next_fill_group(st.shell, g, NEAR)[:free_count]
        fill_ok = R.stable(counts(st.front_s_cm, rows, shell_counts(_fill_preview(st.shell, g, grp), g), L, V_cm),
                         ratio, margin, span)
    if near_any:
        grp = next_unfill_group(st.shell, g, NEAR)
        unfill_ok = R.stable(counts(st.front_s_cm, rows, shell_counts(_unfill_preview(st.shell, g, grp), g), L,
                                  V_cm), ratio, margin, span)
    return TaperSituation(
        c, n_all, ground, foot_rows, st.landed, front_ready, rear_on_initial, free,
        (row_free or not near_any) and dock_ok,
        can_advance, span_blocked, R.stable(wo_front, ratio, margin, span), R.stable(wo_rear, ratio, margin, span),
        fill, bool(p.switch_levels) and st.level + 1 < len(p.switch_levels), bool(st.job), near_open, near_any,
        far_any, fill_ok, unfill_ok, supply)


def decide(st: Structure, p, g: ShellGeometry, free_count: int, row_free: bool,
           dock_ok: bool) -> tuple[str, TaperSituation]:
    s = situation(st, p, g, free_count, row_free, dock_ok)
    return S.first_match(TAPER_RETREAT_TABLE if st.retreating else TAPER_TABLE, s), s
