"""Retreat: when the structure gives up, the watchdog that makes it give up, and how a run ends.

A structure retreats (``Structure.retreating``; then :data:`~swarm_sim.behaviour.structure.RETREAT_TABLE`
or :data:`~swarm_sim.behaviour.taper.TAPER_RETREAT_TABLE` drive it: release at the rear, back off)
for one of these reasons, recorded in the ``retreat`` event's ``why``:

==========================  =================================================================
``why``                     when
==========================  =================================================================
``no_free_robot``           the rule needs another robot and none is left (Ch. 4.6.3)
``span``                    the far ledge is not found within the widest structure's span
``stalled``                 no free robot can reach the dock (every one called was handed over),
                            or nothing progressed for ``stall_s`` (:func:`stalled`)
``dock_blocked``            the rear dock point is off the arena or on an obstacle
``no_room_for_the_feet``    a tapering arch's feet would stick out of the arena
==========================  =================================================================

The run's ``end_reason`` (:func:`end_reason`) is ``crossed`` (the target was found),
``retreated-no-robots``, ``retreated-span``, ``retreated-stalled``, ``retreated-blocked``,
``retreated-no-room``, ``stranded`` (faults: nothing that could still finish the task can move,
:mod:`swarm_sim.behaviour.detection`) or ``timeout`` (the ``max_time_s`` guard; a shipped preset never
reaches it, the tests check that).
"""

from __future__ import annotations

from swarm_sim.engine.tick import Tick
from swarm_sim.state import OPEN, Mode, Phase, evolve

REASONS = {
    "no_free_robot": "retreated-no-robots",
    "span": "retreated-span",
    "stalled": "retreated-stalled",
    "dock_blocked": "retreated-blocked",
    "no_room_for_the_feet": "retreated-no-room",
}
END_REASONS = ("crossed", *REASONS.values(), "stranded", "timeout")

_EXPLORE, _RECRUIT, _TARGET, _RETREAT = int(Mode.EXPLORE), int(Mode.RECRUIT), int(Mode.TARGET), int(Mode.RETREAT)


def start_retreat(tk: Tick, why: str, counts=None, free: int | None = None) -> None:
    """The structure gives up for reason ``why`` (a key of :data:`REASONS`)."""
    if why not in REASONS:
        raise ValueError(f"unknown retreat reason {why!r}")
    st = tk.st
    if st.retreating:
        return
    tk.st = evolve(st, retreating=True, progress_s=tk.t)
    data = {"n": len(st.members), "why": why}
    if counts is not None:
        data.update(n_p=counts.n_p, n_g=counts.n_g)
    if free is not None:
        data["free"] = int(free)
    tk.ev("retreat", st.members[0] if st.members else -1, **data)


def stalled(tk: Tick) -> bool:
    """The watchdog's rule: a building structure that has not docked, moved, released, switched
    or seen a robot come closer for ``stall_s`` seconds cannot proceed (the step then calls off
    what is under way and retreats with ``why = "stalled"``)."""
    st = tk.st
    return not (st is None or st.retreating or st.action == "align" or tk.t - st.progress_s <= tk.p.stall_s)


def dissolved(tk: Tick) -> None:
    """The structure is gone: after a retreat every robot on the initial side wanders, then
    the run stops; otherwise the swarm is delivered and searches the target."""
    st = tk.st
    if not (st.action in ("wait", "idle") and not st.members and not st.job and all(r == OPEN for r in st.shell)):
        return
    if st.retreating:
        tk.phase, tk.phase_since = int(Phase.WANDER), tk.t
        tk.ev("dissolved", retreated=True)
        m = (tk.mode == _EXPLORE) | (tk.mode == _RECRUIT)
        tk.mode[m] = _RETREAT
    else:
        tk.phase, tk.phase_since = int(Phase.DELIVERED), tk.t
        tk.ev("dissolved", retreated=False)
    tk.st = None


def end_reason(events, phase: int) -> str | None:
    """How a run ended (see the module docstring); ``None`` while it is still running."""
    if phase == Phase.SUCCESS:
        return "crossed"
    if phase == Phase.TIMEOUT:
        return "timeout"
    if phase == Phase.STRANDED:
        return "stranded"
    if phase in (Phase.RETREATED, Phase.WANDER):
        why = next((d.get("why") for _t, k, _r, d in events if k == "retreat"), None)
        return REASONS.get(why, "retreated-no-robots")
    return None
