"""How the swarm finds out that a robot failed, and what it does then (issue 16).

No robot reads another's fault flags (``Tick.fault``: the physics). The others learn of a
failure only through what the thesis's robots can sense (``Tick.detect`` records it once, as
a ``fault_detected`` event with ``how`` and the delay since the fault):

==========================  =================================================================
``how``                     sensed by
==========================  =================================================================
``no_heartbeat``            the structure: a member (or the seed) whose heartbeat, broadcast
                            every ``heartbeat_s``, is missed ``heartbeat_misses`` times running
                            (a total failure: no motion, no communication)
``no_motion``               the structure's neighbours: a member that does not drive when the
                            structure moves (a drive failure; the neighbours carry it)
``seed_reports_no_motion``  the others: the seed broadcasts that it cannot align (its own
                            wheels do not turn: a robot knows its own drive failed)
``no_reply_to_call``        the structure: a called robot does not answer (total failure)
``replied_cannot_drive``    the structure: a called robot answers that it cannot drive
``reports_cannot_drive``    the structure: a recruit whose drive fails on its way says so
``no_motion_when_called``   the structure: a recruit that stopped coming for ``recruit_stall_s``
                            and does not answer when asked (a total failure on its way; a
                            recruit that is only stuck answers, and is passed over for this
                            dock, see :mod:`swarm_sim.behaviour.recruitment`)
``answered_pier_call``      the structure: a free robot that cannot drive or cannot see answers
                            the call for pier material (:mod:`swarm_sim.behaviour.piers`)
==========================  =================================================================

A robot knows its own drive and sensor failures (wheel odometry, sensor self-test) and says so
when it is asked and can still communicate: a free robot that cannot drive, or cannot see the
edge or the target, stops where it is (fail-safe:
walking on blind would risk the fall the invariants forbid) and never offers itself as a seed.
A failed robot is then an obstacle (the walk's neighbour avoidance already sees every robot).

What the structure can no longer do is done by its neighbours: a failed member is dead weight,
counted by the stability rule like any robot (same mass), carried by the members that can
still drive (one is enough: traction is not modelled); a structure with no member that can
drive cannot move (its watchdog makes it retreat; a retreat that cannot move either ends the
run ``stranded``, the structure standing where it is, stable). A failed robot released at the
front or rear is pushed clear by the structure (:func:`swarm_sim.behaviour.release.push_clear`).
"""

from __future__ import annotations

import numpy as np

from swarm_sim.engine.tick import Tick
from swarm_sim.faults import DRIVE, SENSOR, TOTAL
from swarm_sim.state import OPEN, Mode, Phase, evolve

_EXPLORE, _SEED, _TARGET = int(Mode.EXPLORE), int(Mode.SEED), int(Mode.TARGET)
EPS = 1e-6


def members(tk: Tick) -> list[int]:
    """Every robot in the structure (core and feet)."""
    st = tk.st
    if st is None:
        return []
    out = [r for r in st.members if r != OPEN]
    out += [r for r in st.shell if r != OPEN]
    return out


def heartbeats(tk: Tick) -> None:
    """Members (and the seed) whose heartbeat has been missed ``heartbeat_misses`` times are
    known to have failed."""
    if tk.fault is None or tk.st is None:
        return
    timeout = tk.p.heartbeat_s * tk.p.heartbeat_misses
    for r in members(tk):
        if tk.fault[r] & TOTAL and not tk.known[r] and tk.t - tk.fault_t[r] >= timeout - 1e-9:
            tk.detect(r, "no_heartbeat")


def drivers(tk: Tick) -> bool:
    """Can the structure move? (some member can still drive; the others are carried). Members
    that do not drive when it moves are detected (``no_motion``)."""
    ids = members(tk)
    if tk.fault is None or not ids:
        return True
    dead = [r for r in ids if tk.fault[r] & DRIVE]
    for r in dead:
        tk.detect(r, "no_motion")
    return len(dead) < len(ids)


def front_sees(tk: Tick) -> bool:
    """Can the front robot see the far ledge? (its ground sensor works)."""
    if tk.fault is None or tk.st is None:
        return True
    front = next((r for r in tk.st.members if r != OPEN), None)
    return front is None or not tk.fault[front] & SENSOR


def can_decide(tk: Tick) -> bool:
    """Some member can still communicate (the structure's decisions are its members')."""
    ids = members(tk)
    return tk.fault is None or not ids or any(not tk.fault[r] & TOTAL for r in ids)


def seed_failed(tk: Tick) -> bool:
    """The aligning seed cannot go on and the others know it: it broadcast that it cannot drive
    (drive failure) or its heartbeat stopped (total failure), ``heartbeat_misses`` beats ago."""
    st = tk.st
    if tk.fault is None or st is None or st.action != "align" or not st.members:
        return False
    s0 = st.members[0]
    if not tk.fault[s0] & DRIVE:
        return False
    if tk.t - tk.fault_t[s0] < tk.p.heartbeat_s * tk.p.heartbeat_misses - 1e-9:
        return False
    tk.detect(s0, "no_heartbeat" if tk.fault[s0] & TOTAL else "seed_reports_no_motion")
    return True


def abandon(tk: Tick, why: str) -> None:
    """The structure never got over the void and no member can go on: its robots are free
    again (the failed ones stand where they are) and the search for the void starts over."""
    from swarm_sim.behaviour.retreat import dissolved

    st = tk.st
    ids = members(tk)
    for r in ids:
        tk.mode[r] = _EXPLORE
        tk.sidx[r], tk.sline[r], tk.slayer[r], tk.sopp[r] = 0, -1, -1, -1
    if st.recruits:
        tk.mode[list(st.recruits)] = _EXPLORE
    tk.ev("structure_abandoned", ids[0] if ids else -1, why=why, robots=ids)
    if st.retreating:  # the retreat is over: what is left of the structure stands on the initial ground
        tk.st = evolve(st, members=(), shell=(), job=(), recruits=(), action="idle")
        dissolved(tk)
        return
    tk.st = None
    tk.phase, tk.phase_since = int(Phase.SEARCH), tk.t


def strand(tk: Tick, why: str) -> None:
    """Nothing that could still finish the task can move: the run ends ``stranded`` (the
    structure, if any, stands where it is: it satisfies the rule there)."""
    tk.phase, tk.phase_since = int(Phase.STRANDED), tk.t
    tk.mode[np.isin(tk.mode, (int(Mode.EXPLORE), int(Mode.TARGET), int(Mode.RETREAT), int(Mode.RECRUIT)))] = \
        int(Mode.STOPPED)
    tk.ev("stranded", why=why)


def watch(tk: Tick) -> None:
    """The structure's part of the fault handling, each step after it moved and decided."""
    if tk.fault is None or tk.st is None or tk.phase != int(Phase.BUILD):
        return
    heartbeats(tk)
    st = tk.st
    if seed_failed(tk):
        abandon(tk, "seed_failed")
        return
    ids = members(tk)
    if ids and not can_decide(tk) and all(tk.known[r] for r in ids):
        # every member is silent: nothing over the void -> the others start again, else it stands
        if st.front_s_cm <= EPS and not st.shell:
            abandon(tk, "members_failed")
        else:
            strand(tk, "every member failed")
        return
    if st.retreating and tk.t - st.progress_s > tk.p.stall_s:
        strand(tk, "the retreat cannot move")


def search_possible(tk: Tick) -> bool:
    """Some free robot on the initial side can still find the void (drives and sees)."""
    ok = tk.mode == _EXPLORE
    if tk.fault is not None:
        ok &= tk.fault == 0
    return bool(ok.any())


def target_search_possible(tk: Tick) -> bool:
    """Some robot on the target side can still find the target (drives and sees)."""
    ok = tk.mode == _TARGET
    if tk.fault is not None:
        ok &= tk.fault == 0
    return bool(ok.any())


__all__ = ["abandon", "can_decide", "drivers", "front_sees", "heartbeats", "members", "search_possible",
           "seed_failed", "strand", "target_search_possible", "watch"]
