"""Resolving a run's parameters against a ``StructureLimits`` record: the structure (line,
switch, auto), its counting rule and robot minimum (swarm_sim.behaviour.taper for tapering arches), and
the pier rule (swarm_sim.behaviour.rule). Above params, taper and rule, so the parameter record itself
depends on no behaviour."""

from __future__ import annotations

import math
from dataclasses import replace

from swarm_sim.behaviour.rule import robots_per_pier
from swarm_sim.behaviour.taper import rule_min_robots

from .errors import InputError
from .params import Params


def with_limits(params: Params, limits) -> Params:
    """Resolve the structure and its stability rule from a ``StructureLimits`` record.

    ``structure = "line"``: the single line of the small-void algorithms (a void wider than
    the line may span ends in a retreat). ``"switch"`` (Ch. 5.5.2): the robots do not know
    the void width; the structure starts as the record's first level and upgrades to the
    next one during the build whenever the front has not found the far ledge and one more
    advance would exceed the current level's span (the resolved rule fields describe the
    first level; ``switch_levels`` holds them all). ``"auto"``: the record's level for the
    void width from the start, as if the width were known (like case B). For ``switch`` and
    ``auto`` a void wider than the widest level is rejected before the run.
    """
    w = params.void_width
    if params.structure in ("auto", "switch"):
        if w > limits.max_span_widths:
            raise InputError(f"void_width {w} is wider than the widest structure in the {limits.source} "
                             f"limits ({limits.max_span_widths} robot widths)")
        level = limits.level_for(w)
    else:
        level = next((lvl for lvl in limits.levels if lvl.kind == "line"), None)
        if level is None:
            raise InputError(f"the {limits.source} limits define no single-line structure")

    def rows_for(lvl, width):
        return width + math.ceil(lvl.ground_ratio * width + int(lvl.ground_margin) + params.case_margin - 1e-9)

    def row_robots(lvl):  # robots per row: a tapering arch's moving core is two lines
        return 2 if lvl.tapered else lvl.lines * lvl.layers

    def taper_need(chain):
        """Rule minimum of a chain ending in tapering arches (swarm_sim.behaviour.taper.rule_min_robots)."""
        flat = [lvl for lvl in chain if not lvl.tapered]
        tap = [lvl for lvl in chain if lvl.tapered]
        F = G = need = 0
        if flat:
            a = flat[-1]
            F = a.max_span_widths
            G = rows_for(a, F) - F
            for x, y in zip(chain, chain[1:], strict=False):
                if not x.tapered:
                    need = max(need, rows_for(x, x.max_span_widths) * row_robots(y))
        fin = tap[-1]
        return max(need, rule_min_robots([(t.layers, t.taper_block_rows, t.max_span_widths) for t in tap], w, F, G,
                                         float(fin.ground_ratio), int(fin.ground_margin) + params.case_margin))

    # a tapering arch stands k B rows onto each ground (plus a staging row): the arena must hold it
    used = [lvl for lvl in limits.levels if lvl.max_span_widths < w] + [level] \
        if params.structure == "switch" else [level]
    feet = max((lvl.layers * lvl.taper_block_rows for lvl in used if lvl.tapered), default=0)
    if feet:
        L = params.robot_length_cm
        room = min(params.void_x0_cm, params.arena_w_cm - params.void_x1_cm)
        if room < (feet + 2) * L:
            raise InputError(f"the tapering arch's feet need {(feet + 2) * L:g} cm of ground either side of "
                             f"the void ({feet} rows + 2), the arena leaves {room:g} cm")

    margin = int(level.ground_margin) + params.case_margin
    if w <= level.max_span_widths:
        rule_min = taper_need([level]) if level.tapered else rows_for(level, w) * level.lines * level.layers
        record_min = level.robots_for(w) + params.case_margin
    else:
        rule_min = record_min = 0  # this structure cannot span it: the swarm must retreat
    switch: tuple = ()
    if params.structure == "switch":
        switch = tuple((lvl.name, int(lvl.lines), int(lvl.layers), float(lvl.ground_ratio),
                        int(lvl.ground_margin) + params.case_margin, int(lvl.max_span_widths),
                        int(lvl.taper_block_rows or 0))
                       for lvl in limits.levels)
        # every level passed on the way keeps its rows (they are widened, not rebuilt): the swarm
        # needs the most robots of any stage: rows at each switch times the next level's row size
        chain = [lvl for lvl in limits.levels if lvl.max_span_widths < w] + [level]
        if level.tapered:
            need = taper_need(chain)
        else:
            need = rows_for(level, w) * level.lines * level.layers
            for a, b in zip(chain, chain[1:], strict=False):
                need = max(need, rows_for(a, a.max_span_widths) * b.lines * b.layers)
        rule_min = need
        level = limits.levels[0]
        margin = int(level.ground_margin) + params.case_margin
    piers = _pier_fields(params, limits, level)
    return replace(params, **piers, limits_source=limits.source, ground_ratio=float(level.ground_ratio),
                   ground_margin=margin, max_span_widths=int(level.max_span_widths), min_robots_rule=int(rule_min),
                   record_min_robots=int(record_min), level_name=level.name, lines=int(level.lines),
                   layers=int(level.layers), taper_block_rows=int(level.taper_block_rows or 0),
                   switch_levels=switch)


def _pier_fields(params: Params, limits, level) -> dict:
    """The pier rule for this run (swarm_sim.behaviour.piers): none without a rule in the record, for a
    structure other than the rule's, or for a depth no stack of robots fits."""
    rule = getattr(limits, "piers", None)
    none = {"pier_robots": 0, "pier_max": 0}
    if rule is None or params.structure != "line" or level.name != rule.structure or not params.void_depth_cm:
        return none
    standing, pitch = getattr(rule, "standing_height_m", None), getattr(rule, "stack_pitch_m", None)
    if not standing or not pitch:
        return none
    deck = getattr(rule, "deck_height_m", None) or 0.0
    k = robots_per_pier(params.void_depth_cm, 100 * standing, 100 * pitch, 0.1 * float(limits.clearance_mm),
                        100 * deck)
    if not k or k > len(rule.overhang_widths) or rule.overhang_widths[k - 1] < 1:
        return none
    # a second pier when the record found the same overhang safe beyond it
    two = rule.overhang_widths_two_piers[k - 1] >= rule.overhang_widths[k - 1]
    return {"pier_robots": k, "pier_max": 2 if two else 1,
            "pier_ground_ratio": float(rule.ground_ratio),
            "pier_ground_margin": int(rule.ground_margin) + params.case_margin,
            "pier_overhang_widths": int(rule.overhang_widths[k - 1])}
