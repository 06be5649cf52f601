"""Cost fields shared by what they are, not only by what their caller calls them.

:func:`swarm_sim.engine.navigation.cost_field` is asked for a field by a *name* of its closed cells
(``blocked_key``: for a recruitment, the structure's member poses in cm rounded to 1e-3 cm).
Two recruitments often close exactly the same cells under different names: the structure
has slid or regrown by less than a grid cell (a third of a robot's width; on the large-void
arenas about 10 cm) between them, or its members were renumbered, and the approach point is
the same. Before, each such call ran its Dijkstra search again from the goal.

:class:`FieldCache` keeps the fields under both keys, each an immutable tuple:

* by name: ``(world geometry, goal cell, goal point rounded to 1e-6 cm, blocked_key)``;
  a hit skips even computing the closed mask (the caller's function is not called);
* by contents: ``(world geometry, goal cell, goal point (cm, exact floats), the closed cells
  packed to bits)``: everything the field's costs, paths and goal point depend on, so a hit
  is the same field, and the search it has already settled is reused (a lazy field answers
  every question as the whole search does, however far it is settled:
  :class:`swarm_sim.engine.navigation.CostField`).

Both are least-recently-used tables, of ``size`` and ``size // 2`` entries (so at most
``1.5 * size`` fields are kept; one of the 100,000-cell large-void grid is about 1.7 MB).
``share=False`` keeps the by-name table only (the behaviour before the by-contents one existed; ``tests/swarm_sim/test_field_cache.py`` runs both and compares).
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np


def contents_key(world_key: tuple, goal_cell: int, goal_x: float, goal_y: float, closed: np.ndarray) -> tuple:
    """The by-contents key of a field towards (goal_x, goal_y) cm whose closed cells are ``closed``
    (bool over the grid's cells, the goal's own cell already opened)."""
    return (world_key, int(goal_cell), float(goal_x), float(goal_y), int(closed.size),
            np.packbits(closed).tobytes())


class FieldCache:
    """Two LRU tables of cost fields (module docstring): by name and, with ``share``, by contents.
    ``hits`` counts the answers of each table (``named``, ``contents``) and the fields built
    (``built``)."""

    def __init__(self, size: int = 64, share: bool = True) -> None:
        self.size, self.share = int(size), bool(share)
        self._named: OrderedDict = OrderedDict()
        self._contents: OrderedDict = OrderedDict()
        self.hits = {"named": 0, "contents": 0, "built": 0}

    def named(self, key: tuple):
        """The field cached under this name, or None."""
        f = self._named.get(key)
        if f is not None:
            self._named.move_to_end(key)
            self.hits["named"] += 1
        return f

    def by_contents(self, key: tuple):
        """The field cached with these contents (:func:`contents_key`), or None (always None
        without ``share``); a hit is also filed under the caller's name by :meth:`put`."""
        if not self.share:
            return None
        f = self._contents.get(key)
        if f is not None:
            self._contents.move_to_end(key)
            self.hits["contents"] += 1
        return f

    def put(self, name: tuple, contents: tuple, field, built: bool = True):
        """File ``field`` under both keys (``built``: it was just computed); returns it."""
        self.hits["built"] += built
        self._named[name] = field
        self._named.move_to_end(name)
        _trim(self._named, self.size)
        if self.share:
            self._contents[contents] = field
            self._contents.move_to_end(contents)
            _trim(self._contents, self.size // 2)
        return field

    def clear(self) -> None:
        """Forget every field (both tables); the counters stay."""
        self._named.clear()
        self._contents.clear()

    def __len__(self) -> int:
        return len(self._named)


def _trim(table: OrderedDict, size: int) -> None:
    while len(table) > size:
        table.popitem(last=False)


__all__ = ["FieldCache", "contents_key"]
