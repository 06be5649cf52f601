"""The working copy of one step: :class:`Tick` holds copies of the state's arrays that the
step's phases change in place, so :func:`swarm_sim.step.step` stays pure (its input state
is never mutated) while each phase is a plain function ``phase(tick) -> None``."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from swarm_sim.engine.world import World
from swarm_sim.params import Params
from swarm_sim.state import Structure, SwarmState, evolve


@dataclass
class Tick:
    p: Params
    world: World
    rng: np.random.Generator
    use_numba: bool | None
    t: float                    # time at the end of this step (s)
    x: np.ndarray               # cm
    y: np.ndarray
    h: np.ndarray               # rad
    goal: np.ndarray            # rad
    run_left: np.ndarray        # cm
    mode: np.ndarray
    sidx: np.ndarray
    sline: np.ndarray
    slayer: np.ndarray
    sopp: np.ndarray
    disp: np.ndarray            # s
    st: Structure | None
    phase: int
    phase_since: float
    seed_robot: int
    seed_pos: tuple | None
    target_finder: int
    events: list = field(default_factory=list)
    #: faults (see :class:`~swarm_sim.state.SwarmState`): copies changed in place, None without faults
    fault_schedule: object | None = None
    fault_next: int = 0
    fault: np.ndarray | None = None
    fault_t: np.ndarray | None = None
    known: np.ndarray | None = None
    #: this step's walk already computed (x, y, h, goal, run_left), or None: the walk phase walks
    walked: tuple | None = None

    @classmethod
    def of(cls, s: SwarmState, p: Params, world: World, rng: np.random.Generator,
           use_numba: bool | None) -> Tick:
        return cls(p, world, rng, use_numba, s.t_s + p.dt_s, s.x_cm, s.y_cm, s.heading_rad,
                   s.goal_heading_rad, s.run_left_cm, s.mode.copy(), s.struct_index.copy(),
                   s.struct_line.copy(), s.struct_layer.copy(),
                   s.struct_opposite.copy() if s.struct_opposite is not None else np.full(s.n, -1, dtype=np.int8),
                   s.disperse_left_s.copy(), s.structure, s.phase, s.phase_since_s, s.seed_robot,
                   s.seed_position, s.target_finder, [], s.fault_schedule, s.fault_next,
                   None if s.fault_flags is None else s.fault_flags.copy(),
                   None if s.fault_t_s is None else s.fault_t_s.copy(),
                   None if s.fault_known is None else s.fault_known.copy())

    def ev(self, kind: str, robot: int = -1, **data) -> None:
        """Record an event at this step's time."""
        self.events.append((round(self.t, 6), kind, int(robot), data))

    def progress(self) -> None:
        """The structure did something (the watchdog of :mod:`swarm_sim.behaviour.retreat` restarts)."""
        if self.st is not None:
            self.st = evolve(self.st, progress_s=self.t)

    def state(self, prev: SwarmState) -> SwarmState:
        """The new state (every field of :class:`SwarmState` given: no ``dataclasses.replace``
        in the per-step path)."""
        return SwarmState(x_cm=self.x, y_cm=self.y, heading_rad=self.h, goal_heading_rad=self.goal,
                          run_left_cm=self.run_left, mode=self.mode, struct_index=self.sidx, struct_line=self.sline,
                          struct_layer=self.slayer, disperse_left_s=self.disp, struct_opposite=self.sopp, t_s=self.t,
                          step=prev.step + 1, phase=int(self.phase), phase_since_s=self.phase_since,
                          structure=self.st, seed_robot=self.seed_robot, seed_position=self.seed_pos,
                          target_finder=self.target_finder,
                          events=prev.events + tuple(self.events) if self.events else prev.events,
                          fault_schedule=self.fault_schedule, fault_next=self.fault_next, fault_flags=self.fault,
                          fault_t_s=self.fault_t, fault_known=self.known)

    # ------------------------------------------------------------------ faults (swarm_sim.faults)
    def failed(self, bits: int) -> np.ndarray:
        """Per robot: has it lost any of the functions ``bits`` (the physics, not knowledge)?"""
        if self.fault is None:
            return np.zeros(self.x.shape[0], dtype=bool)
        return (self.fault & bits) != 0

    def is_failed(self, r: int, bits: int) -> bool:
        return self.fault is not None and bool(self.fault[r] & bits)

    def detect(self, r: int, how: str) -> None:
        """The swarm learns that robot ``r`` failed (``how``: what it sensed); recorded once."""
        if self.known is None or self.known[r]:
            return
        self.known[r] = True
        self.ev("fault_detected", r, how=how, delay_s=round(self.t - float(self.fault_t[r]), 6))
