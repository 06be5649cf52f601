"""The stability (counting) rule: one home for every structure the simulator builds.

Robots are counted by where their centre of mass is (Ch. 4.6.3, Table 5.1):

* ``n_p`` on the initial ground (centre at or before the near edge),
* ``n_g`` over the void,
* ``n_o`` on the target ground (centre at or past the far edge),

and ``core_rows_over`` is the number of the moving core's rows over the void (the span).

The rule, with the level's ``ratio`` r, ``margin`` m (robots or rows) and ``span``:

* never more than ``span`` core rows over the void;
* cantilever from the initial side (``n_o = 0``): ``n_p >= r n_g + m``;
* cantilever from the target side (``n_p = 0``): ``n_o >= r n_g + m``;
* both ends on ground: ``n_p + n_o >= r n_g + m``.

What is counted is the caller's choice of row *weights*: a uniform structure (line, two
lines, rectangular arch) counts rows (weight 1 per row, the thesis's small-void rule with
r = 2, m = 0), a tapering arch counts robots (weight = robots in the row, plus the static
feet's robots; thesis r = 1, m = 1). Lengths are in the caller's unit (cm, or robot
lengths with ``L = 1``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

EPS = 1e-6


@dataclass(frozen=True)
class Counts:
    """Weights by where their centre is, and the core rows over the void."""

    n_p: float
    n_g: float
    n_o: float
    core_rows_over: int = field(default=-1, compare=False)  # -1: the same as n_g (uniform rows)

    @property
    def span_rows(self) -> int:
        return int(self.n_g) if self.core_rows_over < 0 else self.core_rows_over


def counts(front_s: float, rows, L: float, void: float, shell_pgo: tuple = (0, 0, 0)) -> Counts:
    """Counts of a moving core whose front face is ``front_s`` past the near edge.

    ``rows``: the weight of each core row, front first (an int ``n`` means ``n`` rows of
    weight 1); ``shell_pgo``: static weights already on (initial ground, void, target ground)."""
    # plain floats: asked a few hundred times per decision, where numpy's per-call cost on a
    # handful of rows dominated; the same IEEE operations as (front_s - (arange(n) + 0.5) * L)
    if np.isscalar(rows):
        return _uniform_counts(front_s, int(rows), L, void, shell_pgo)
    w = np.asarray(rows).tolist()
    p = g = o = 0
    span = 0
    for k, wk in enumerate(w):
        s = front_s - (k + 0.5) * L
        on_p, on_o = s <= EPS, s >= void - EPS
        if on_p:
            p += wk
        if on_o:
            o += wk
        if not (on_p or on_o):
            g += wk
            span += wk > 0
    sp, sg, so = shell_pgo
    return Counts(int(p) + sp, int(g) + sg, int(o) + so, int(span))


def _uniform_counts(front_s: float, n: int, L: float, void: float, shell_pgo: tuple) -> Counts:
    """:func:`counts` for ``n`` rows of weight 1: a row's centre ``s_k = front_s - (k + 0.5) * L``
    falls with k (rounding is monotone), so the rows on the initial ground are a tail and those
    on the target ground a head of the rows: two binary searches on the same expression
    instead of a pass over every row (``tests/swarm_sim/test_structure.py`` compares both)."""
    def centre(k: int) -> float:
        return front_s - (k + 0.5) * L

    lo, hi = 0, n  # first row on the initial ground (centre <= EPS)
    while lo < hi:
        mid = (lo + hi) // 2
        if centre(mid) <= EPS:
            hi = mid
        else:
            lo = mid + 1
    first_p = lo
    lo, hi = 0, n  # first row not on the target ground (centre < void - EPS)
    while lo < hi:
        mid = (lo + hi) // 2
        if centre(mid) >= void - EPS:
            lo = mid + 1
        else:
            hi = mid
    end_o = lo
    if end_o > first_p:  # a row on both grounds (a void narrower than 2 EPS): count it row by row
        return counts(front_s, (1,) * n, L, void, shell_pgo)
    p, o = n - first_p, end_o
    g = n - p - o
    sp, sg, so = shell_pgo
    return Counts(p + sp, g + sg, o + so, g)


def stable(c: Counts, ratio: float, margin: float, span: int) -> bool:
    """The rule (module docstring) for counts ``c``."""
    if c.span_rows > span:
        return False
    if c.n_g == 0:
        return True
    need = ratio * c.n_g + margin - EPS
    if c.n_p and c.n_o:
        return c.n_p + c.n_o >= need
    if c.n_p:
        return c.n_p >= need
    if c.n_o:
        return c.n_o >= need
    return False


def move_stable(front_from: float, front_to: float, rows, L: float, void: float, ratio: float, margin: float,
                span: int, shell_pgo: tuple = (0, 0, 0)) -> bool:
    """The rule holds at every configuration the core passes through on a move (counts change
    only where a row centre crosses an edge: checked just before and after each crossing)."""
    n = int(rows) if np.isscalar(rows) else len(rows)
    lo, hi = min(front_from, front_to), max(front_from, front_to)
    pts = [front_from, front_to]
    for edge in (0.0, void):
        # only the rows whose centre can cross this edge on the move (a window one row wider each
        # way than the division says, so its rounding cannot drop one), tested as before
        k0 = max(0, math.floor((lo - EPS - edge) / L - 0.5) - 1)
        k1 = min(n - 1, math.ceil((hi + EPS - edge) / L - 0.5) + 1)
        for k in range(k0, k1 + 1):
            f = edge + (k + 0.5) * L
            if lo - EPS <= f <= hi + EPS:
                pts += [f - 10 * EPS, f + 10 * EPS]
    return all(stable(counts(f, rows, L, void, shell_pgo), ratio, margin, span)
               for f in pts if lo - 20 * EPS <= f <= hi + 20 * EPS)


# -- the pier rule: the counting rule once the front has reached a complete pier (swarm_sim.behaviour.piers) --

def robots_per_pier(depth_cm: float, standing_cm: float, pitch_cm: float, clearance_cm: float,
                    deck_cm: float = 0.0) -> int:
    """Robots a pier needs for its running surface (``standing + (k - 1) pitch + deck``: the top
    robot wears the printed deck the line rolls over, ``cubot_cad.piers.deck``) to reach from the
    floor to within ``clearance_cm`` below the ledge, never above it; 0 when no stack fits (or
    no depth is given)."""
    if not (depth_cm > 0 and standing_cm > 0 and pitch_cm > 0):
        return 0
    k = max(1, math.ceil((depth_cm - clearance_cm - standing_cm - deck_cm) / pitch_cm - 1e-9) + 1)
    top = standing_cm + (k - 1) * pitch_cm + deck_cm
    return k if depth_cm - clearance_cm - 1e-9 <= top <= depth_cm + 1e-9 else 0


def complete_piers(st, p) -> list[tuple[float, int]]:
    """The piers that have their robots: (near face s, cm; robots)."""
    return [(s, k) for s, k in st.piers if k >= p.pier_robots]


def rule_frame(st, p) -> tuple[float, float, tuple[float, int, int]]:
    """(front_s, void_cm, rule) the counting rule is evaluated in: once the front has reached a
    complete pier (its near face), the last such pier's far face is the edge and the pier rule
    applies; else the structure's own (near edge, its level's rule)."""
    L = p.robot_length_cm
    done = [s for s, _k in complete_piers(st, p) if st.front_s_cm >= s - 1e-6]
    if not done:
        return st.front_s_cm, p.void_width_cm, p.rule
    far = max(done) + L
    return (st.front_s_cm - far, p.void_width_cm - far,
            (p.pier_ground_ratio, p.pier_ground_margin, p.pier_overhang_widths))


def stable_at(st, p, front_s: float, n: int) -> bool:
    """The counting rule for ``n`` rows with the front at ``front_s`` (cm past the near edge),
    the complete piers being supports: before the first pier the level's own rule; from a pier
    on, the pier rule counted from the last pier reached (rows behind its far face against rows
    beyond it); and once no row is left on the initial ground, the rows still over the first
    span hang back from the first pier: at most the level's span of them, and the rows from the
    pier on must weigh ``pier_ground_ratio`` times them plus ``pier_ground_margin``."""
    L, V = p.robot_length_cm, p.void_width_cm
    sites = [s for s, _k in complete_piers(st, p) if front_s >= s - 1e-6]
    if not sites:
        return stable(counts(front_s, n, L, V), *p.rule)
    far = max(sites) + L
    ratio, margin = p.pier_ground_ratio, p.pier_ground_margin
    if not stable(counts(front_s - far, n, L, V - far), ratio, margin, p.pier_overhang_widths):
        return False
    centres = front_s - (np.arange(n) + 0.5) * L
    if n and centres[-1] > 1e-6:  # nothing on the initial ground any more
        back = int(np.sum(centres < min(sites) - 1e-6))
        if back and (back > p.max_span_widths or n - back < ratio * back + margin - 1e-6):
            return False
    return True


def move_ok(st, p, front_from: float, front_to: float, n: int) -> bool:
    """:func:`stable_at` at every configuration a move passes through (counts change only where
    a row centre crosses an edge or a pier face: checked just before and after each)."""
    L, V = p.robot_length_cm, p.void_width_cm
    lo, hi = min(front_from, front_to), max(front_from, front_to)
    edges = [0.0, V] + [e for s, _k in complete_piers(st, p) for e in (s, s + L)]
    pts = [front_from, front_to]
    for k in range(n):
        for e in edges:
            f = e + (k + 0.5) * L
            if lo - 1e-6 <= f <= hi + 1e-6:
                pts += [f - 1e-5, f + 1e-5]
    pts += [s - 1e-5 for s, _k in complete_piers(st, p)] + [s + 1e-5 for s, _k in complete_piers(st, p)]
    return all(stable_at(st, p, f, n) for f in pts if lo - 2e-5 <= f <= hi + 2e-5)
