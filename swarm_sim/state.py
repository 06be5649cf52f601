"""Simulator state: a struct of numpy arrays (one entry per robot) plus the structure record.

Robot modes are small integers (:class:`Mode`); the thesis's Table 4.3 state
(-1 initial exploration, -2 target exploration, -3 retreat, 1..n position in
the structure) is derived from ``mode`` and ``struct_index`` by
:func:`thesis_state`, never stored in a second place.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, replace
from enum import IntEnum

import numpy as np


class Mode(IntEnum):
    EXPLORE = 0   # -1: initial exploration (free robot on the initial side)
    SEED = 1      # the seed while it aligns perpendicular to the edge (structure index 1)
    RECRUIT = 2   # a free robot called to the rear of the structure, approaching to dock
    MEMBER = 3    # docked in the structure (index 1..n, front = 1)
    TARGET = 4    # -2: released at the front, explores the target side
    RETREAT = 5   # -3: released at the rear after a failed crossing, wanders
    STOPPED = 6   # -3 after the wander period (failure) / any robot once the run ended
    PIER = 7      # -4: a failed robot stacked in a pier on the void's floor (swarm_sim.behaviour.piers)


#: Modes whose motion is the exploration walk (vectorised over a mask).
WALKING_MODES = (Mode.EXPLORE, Mode.TARGET, Mode.RETREAT)


class Phase(IntEnum):
    SEARCH = 0        # no void found yet
    BUILD = 1         # a structure exists (assembly, crossing or retreat)
    DELIVERED = 2     # structure dissolved on the target side, robots search the target
    WANDER = 3        # after a retreat: robots wander wander_after_retreat_s, then stop
    SUCCESS = 4       # target found
    RETREATED = 5     # wandered after the retreat and stopped
    TIMEOUT = 6       # max_time_s reached
    STRANDED = 7      # faults: every robot that could still finish the task has failed (swarm_sim.faults)


#: An open slot in ``Structure.members`` (a new line/layer not yet filled after a switch).
OPEN = -1


@dataclass(frozen=True)
class Structure:
    """A rigid bridge: ``members`` ordered front (index 1) to rear, moving as one body.

    Geometry is data: the near edge point ``origin`` (x, y cm) on the line axis,
    the unit ``direction`` towards the far ledge, and ``front_s_cm``, the front
    face's distance past the near edge along ``direction``. Member k (0-based from
    the front) has its centre at ``origin + (front_s_cm - (k + 0.5) * L) * direction``.
    ``lines``/``layers`` describe the cross-section (1 x 1 for the single line).
    ``members`` is row-major (row, then line, then layer); after a switch to a wider level
    the new lines/layers are open slots (``-1``) until they are filled (:data:`OPEN`).
    """

    members: tuple[int, ...]
    origin_x_cm: float
    origin_y_cm: float
    dir_x: float
    dir_y: float
    front_s_cm: float
    lines: int = 1
    layers: int = 1
    action: str = "align"          # see structure.ACTIONS
    goal_s_cm: float = 0.0         # front_s target of the current move
    wait_until_s: float = 0.0
    recruits: tuple[int, ...] = ()   # robots called for the rear slots, in slot order
    recruit_slots: tuple[int, ...] = ()  # the slot each recruit docks at (row-major member index)
    #: per recruit: the shortest remaining path seen (cm) and when it last shortened (s)
    recruit_best_cm: tuple[float, ...] = ()
    recruit_progress_s: tuple[float, ...] = ()
    #: per recruit: reached its approach point, now driving straight in
    recruit_final: tuple[bool, ...] = ()
    #: robots that failed to reach this dock point (handed over); cleared by the next dock
    passed_over: tuple[int, ...] = ()
    #: when the structure last docked, moved, released, switched or saw a robot come closer (s)
    progress_s: float = 0.0
    lateral_sign: float = 1.0        # extra lines go to this side of the core line
    landed: bool = False
    retreating: bool = False
    level: int = 0                   # index into Params.switch_levels (structure = "switch")
    #: tapering arch (swarm_sim.behaviour.taper): robot per shell slot (OPEN when empty), in
    #: ShellGeometry slot order; () for structures without feet
    shell: tuple[int, ...] = ()
    #: a foot job under way: robots, one column each, kind fill_near | fill_far | unfill_near |
    #: dissolve_far, stage drive | climb (climb also covers the dock and the column's slide)
    job: tuple[int, ...] = ()
    job_cols: tuple[int, ...] = ()
    job_kind: str = ""
    job_stage: str = ""
    job_until_s: float = 0.0
    job_best_cm: tuple[float, ...] = ()
    job_progress_s: tuple[float, ...] = ()
    #: piers (swarm_sim.behaviour.piers): per pier (near face s past the near edge, cm; robots in it), the
    #: robots in piers, and the round under way: (carrier, failed robot), its stage, the
    #: carrier's pick-up point (cm), when a timed stage ends, its best path (cm) and last progress (s)
    piers: tuple[tuple[float, int], ...] = ()
    pier_members: tuple[int, ...] = ()
    pier_job: tuple[int, ...] = ()
    pier_stage: str = ""
    pier_goal: tuple[float, float] = (0.0, 0.0)
    pier_until_s: float = 0.0
    pier_best_cm: float = 0.0
    pier_progress_s: float = 0.0


@dataclass(frozen=True)
class SwarmState:
    x_cm: np.ndarray
    y_cm: np.ndarray
    heading_rad: np.ndarray
    goal_heading_rad: np.ndarray
    run_left_cm: np.ndarray      # Levy walk: length left on the current straight run
    mode: np.ndarray             # int8 Mode
    struct_index: np.ndarray     # int16: row 1..n while in the structure (front = 1), else 0
    struct_line: np.ndarray      # int8: role: 0 core line (coreL), 1 coreR, 2.. side lines; -1 free
                                 # (tapering arch: lateral position q, side L q <= 0, side R q >= 1)
    struct_layer: np.ndarray     # int8: role: 0 ground layer, 1.. stacked layers; -1 free
    disperse_left_s: np.ndarray  # released robots drive straight away for this long
    #: Table 5.1 "O" prefix: 1 in the far foot (on the target side), 0 core / near foot; -1 free
    struct_opposite: np.ndarray | None = None
    t_s: float = 0.0
    step: int = 0
    phase: int = Phase.SEARCH
    phase_since_s: float = 0.0
    structure: Structure | None = None
    seed_robot: int = -1
    seed_position: tuple[float, float] | None = None
    target_finder: int = -1
    events: tuple = field(default_factory=tuple)
    #: faults (swarm_sim.faults; all None in a fault-free run): the run's schedule, the index of
    #: its next fault, each robot's disabled functions (int8 DRIVE | SENSOR | TOTAL: the physics,
    #: which no robot reads for another), the time of its first fault (s, inf: none) and what the
    #: swarm knows: ``fault_known`` robots were detected as failed by what the others can sense
    fault_schedule: object | None = None
    fault_next: int = 0
    fault_flags: np.ndarray | None = None
    fault_t_s: np.ndarray | None = None
    fault_known: np.ndarray | None = None

    @property
    def n(self) -> int:
        return int(self.x_cm.shape[0])

    def with_event(self, kind: str, robot: int = -1, **data) -> SwarmState:
        return evolve(self, events=self.events + ((round(self.t_s, 6), kind, int(robot), data),))


def _field_names(cls) -> frozenset:
    """The fields of a record :func:`evolve` may copy: every field set by ``__init__``, and no
    ``__post_init__`` (so a copy with some fields changed is what ``__init__`` would build)."""
    fs = fields(cls)
    assert not hasattr(cls, "__post_init__") and all(f.init for f in fs), cls
    return frozenset(f.name for f in fs)


#: the per-step records :func:`evolve` copies directly
_EVOLVES = {Structure: _field_names(Structure), SwarmState: _field_names(SwarmState)}


def evolve(record, **changes):
    """``dataclasses.replace(record, **changes)`` for the per-step records (:class:`SwarmState`,
    :class:`Structure`): the same new record, its fields copied instead of passed through the
    frozen ``__init__`` (~1-2 us against ~9-14 us per call; the engines make a few per step
    that decides anything). Any other record goes to ``dataclasses.replace``."""
    names = _EVOLVES.get(type(record))
    if names is None:
        return replace(record, **changes)
    if not names.issuperset(changes):
        bad = sorted(set(changes) - names)
        raise TypeError(f"{type(record).__name__} has no field {bad[0]!r}")
    new = object.__new__(type(record))
    d = new.__dict__  # the frozen __setattr__ guards attributes, not the instance dict
    d.update(record.__dict__)
    d.update(changes)
    return new


def thesis_state(state: SwarmState) -> np.ndarray:
    """Table 4.3 numbering: -1 initial, -2 target, -3 retreat, 1..n structure position (and
    ours: -4 in a pier)."""
    out = np.full(state.n, -1, dtype=np.int16)
    m = state.mode
    out[m == Mode.TARGET] = -2
    out[(m == Mode.RETREAT) | (m == Mode.STOPPED)] = -3
    out[m == Mode.PIER] = -4  # not in the thesis's table: a robot in a pier
    ins = (m == Mode.MEMBER) | (m == Mode.SEED)
    out[ins] = state.struct_index[ins]
    return out


def new_state(x_cm: np.ndarray, y_cm: np.ndarray, heading_rad: np.ndarray) -> SwarmState:
    n = x_cm.shape[0]
    return SwarmState(
        x_cm=np.asarray(x_cm, dtype=np.float64), y_cm=np.asarray(y_cm, dtype=np.float64),
        heading_rad=np.asarray(heading_rad, dtype=np.float64),
        goal_heading_rad=np.asarray(heading_rad, dtype=np.float64).copy(),
        run_left_cm=np.zeros(n), mode=np.zeros(n, dtype=np.int8),
        struct_index=np.zeros(n, dtype=np.int16), struct_line=np.full(n, -1, dtype=np.int8),
        struct_layer=np.full(n, -1, dtype=np.int8), disperse_left_s=np.zeros(n),
        struct_opposite=np.full(n, -1, dtype=np.int8))
