"""Compliant couplings between docked robots (SI units), as the mechanics model sees them.

A docked coupling is lumped at one point (the coupling's load point) and has

* a translational spring of ``axial_n_per_m`` in both in-plane directions
  (the pins / rail / key carry axial and shear load: a stiff pin), and
* a rotational (pitch) spring of ``rotational_nm_per_rad`` with a *dead band*
  of half-width ``backlash_rad``: the joint turns freely by ``backlash_rad``
  either side of its docked position before the spring carries load;
* translational play per axis from the record's per-feature play
  (:class:`cubot_cad.properties.FeaturePlay`): ``play_x`` / ``play_z`` are the free
  travel ``(closing, opening)`` before the spring bears in that direction, e.g. a
  front-rear coupling's ``(0, tension play)`` along x (tension-only gap: the faces
  touch in compression) and ``(slip, slip)`` along z (pins in their holes).

The dead band is smooth (``dead_band_moment``) because a sharp one makes the
Newton Jacobian jump and the static solver stall on long chains (see the
toolchain notes). :class:`ConnectorSet` holds the three CuBot couplings
(front-rear pins, side rail, top twist-lock) or a robot's single coupling,
with overridable scale factors for the studies.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from cubot_cad.properties import RobotProperties
from structure_fem.errors import InputError

#: Width of the smooth transition at the dead-band edges as a fraction of the band.
SMOOTHING = 0.1


def _pos(name: str, v: float) -> None:
    if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
        raise InputError(f"{name} must be a finite number > 0, got {v!r}")


def _nonneg(name: str, v: float) -> None:
    if not (isinstance(v, (int, float)) and math.isfinite(v) and v >= 0):
        raise InputError(f"{name} must be a finite number >= 0, got {v!r}")


@dataclass(frozen=True)
class Joint:
    """One planar coupling: stiffnesses (N m/rad, N/m), dead-band half-width (rad), load-point height (m)."""

    kind: str
    rotational_nm_per_rad: float
    axial_n_per_m: float
    backlash_rad: float = 0.0
    height_m: float = 0.0
    gap_m: float = 0.0
    #: Free travel (m) along x before the spring bears: (closing, opening); opening = +x of the
    #: front / upper / odd body's marker relative to the other's.
    play_x: tuple[float, float] = (0.0, 0.0)
    #: The same along z (opening = up).
    play_z: tuple[float, float] = (0.0, 0.0)
    #: Stiffness along z (N/m) when it differs from the axial one (the FE's shear after the play).
    shear_n_per_m: float | None = None
    provenance: str = ""
    #: Lever arm (m) of every tension member about the hinge (the record's ``pin_levers_m``):
    #: the emergent hinge's tension rows (:mod:`structure_fem.model.hinge`); empty: not known.
    levers_m: tuple[float, ...] = ()
    #: Axial preload (N) pressing the faces together (the wedge latch; the record's ``preload_n``):
    #: the emergent hinge pre-stretches its tension rows by it and pre-compresses its face contacts.
    preload_n: float = 0.0
    #: Static friction between the pressed faces (the record's; reported with the preload, not used).
    friction_coefficient: float = 0.0

    def __post_init__(self) -> None:
        _pos(f"{self.kind} rotational stiffness (N m/rad)", self.rotational_nm_per_rad)
        _pos(f"{self.kind} axial stiffness (N/m)", self.axial_n_per_m)
        if self.shear_n_per_m is not None:
            _pos(f"{self.kind} shear stiffness (N/m)", self.shear_n_per_m)
        _nonneg(f"{self.kind} backlash (rad)", self.backlash_rad)
        _nonneg(f"{self.kind} height (m)", self.height_m)
        _nonneg(f"{self.kind} gap (m)", self.gap_m)
        _nonneg(f"{self.kind} preload (N)", self.preload_n)
        _nonneg(f"{self.kind} friction coefficient", self.friction_coefficient)
        for name in ("play_x", "play_z"):
            v = getattr(self, name)
            if len(v) != 2:
                raise InputError(f"{self.kind} {name} must be (closing, opening), got {v!r}")
            for x in v:
                _nonneg(f"{self.kind} {name} (m)", x)
                if x >= 0.01:
                    raise InputError(f"{self.kind} {name} {x} m is not a clearance (< 10 mm)")
        if self.backlash_rad >= 0.5:
            raise InputError(f"{self.kind} backlash {self.backlash_rad} rad is not a small angle (< 0.5 rad)")

    @property
    def k_z(self) -> float:
        """Stiffness along z (N/m): the shear stiffness if known, else the axial one."""
        return self.axial_n_per_m if self.shear_n_per_m is None else self.shear_n_per_m

    @property
    def has_translational_play(self) -> bool:
        return any(v > 0 for v in self.play_x + self.play_z)

    def scaled(self, stiffness: float = 1.0, backlash: float = 1.0) -> Joint:
        """Every stiffness times ``stiffness``, every play (pitch dead band and translational
        play per feature) times ``backlash``."""
        _pos("stiffness scale", stiffness)
        _nonneg("backlash scale", backlash)
        return replace(self, rotational_nm_per_rad=self.rotational_nm_per_rad * stiffness,
                       axial_n_per_m=self.axial_n_per_m * stiffness,
                       shear_n_per_m=None if self.shear_n_per_m is None else self.shear_n_per_m * stiffness,
                       backlash_rad=self.backlash_rad * backlash,
                       play_x=tuple(v * backlash for v in self.play_x),
                       play_z=tuple(v * backlash for v in self.play_z))


def joint_play(play) -> dict[str, tuple[float, float]]:
    """``{"play_x": (closing, opening), "play_z": ...}`` from a record's per-feature play
    (:class:`cubot_cad.properties.FeaturePlay`): ``both`` opens both ways, ``tension`` only
    the opening one; two features on one axis and sense add (in series)."""
    out = {"play_x": [0.0, 0.0], "play_z": [0.0, 0.0]}
    for f in play:
        v = out[f"play_{f.axis}"]
        v[1] += f.play_m
        if f.sense == "both":
            v[0] += f.play_m
    return {k: (v[0], v[1]) for k, v in out.items()}


def band_force(u: float, k: float, closing: float, opening: float, e: float) -> float:
    """Force (N) of a spring ``k`` free over ``[-closing, opening]`` about its docked position,
    smoothed over ``e``: ``k/2 [(u - o) + sqrt((u - o)^2 + e^2)] + k/2 [(u + c) - sqrt((u + c)^2 + e^2)]``
    less its value at ``u = 0`` (an undeformed coupling carries nothing). ``closing = 0``: a
    compression-only contact at the docked position (the smooth ``k min(u, 0)``) plus the
    tension gap ``opening``. Both zero: the plain spring ``k u``."""
    if closing <= 0 and opening <= 0:
        return k * u

    def f(x: float) -> float:
        a = x - opening
        b = x + closing
        return 0.5 * k * (a + math.sqrt(a * a + e * e)) + 0.5 * k * (b - math.sqrt(b * b + e * e))

    return f(u) - f(0.0)


def dead_band_moment(theta: float, k: float, half_width: float, smoothing: float | None = None) -> float:
    """Moment (N m) of a rotational spring ``k`` with a smooth dead band of ``half_width`` rad.

    ``M = k/2 [(t - h) + sqrt((t - h)^2 + e^2)] + k/2 [(t + h) - sqrt((t + h)^2 + e^2)]``
    with ``e = smoothing`` (default ``SMOOTHING * h``): zero at ``t = 0``, odd,
    and ``k (t -/+ h)`` outside the band to within ``k e^2 / (4 |t -/+ h|)``;
    at the band edge it carries ``k e / 2``, so the model picks ``e`` small
    enough that this is a negligible moment (see ``model.solve``). Its slope at
    zero, ``k (1 - h / sqrt(h^2 + e^2))``, keeps the Jacobian regular.
    ``h = 0`` is the plain spring.
    """
    if half_width <= 0:
        return k * theta
    e = SMOOTHING * half_width if smoothing is None else smoothing
    a = theta - half_width
    b = theta + half_width
    return 0.5 * k * (a + math.sqrt(a * a + e * e)) + 0.5 * k * (b - math.sqrt(b * b + e * e))


#: The hinge models (:attr:`ConnectorSet.hinge`; built in :mod:`structure_fem.model.hinge`).
HINGES = ("emergent", "lumped")


@dataclass(frozen=True)
class ConnectorSet:
    """The couplings one robot model offers: ``front_rear`` (along a line), optional
    ``side_rail`` (between lines side by side) and ``top_twist`` (between layers)."""

    front_rear: Joint
    side_rail: Joint | None = None
    top_twist: Joint | None = None
    #: How a coupling whose faces touch is modelled (:data:`HINGES`):
    #: ``"emergent"`` (tension rows + compression-only face contacts: the default and the packaged
    #: record's model) or ``"lumped"`` (one point spring + a pitch dead band of tension play / highest pin).
    hinge: str = "emergent"

    def __post_init__(self) -> None:
        if self.hinge not in HINGES:
            raise InputError(f"hinge model {self.hinge!r} is not one of {', '.join(HINGES)}")

    @classmethod
    def from_robot(cls, robot: RobotProperties) -> ConnectorSet:
        """Map a robot's connectors: its along-the-line coupling is ``front_rear``
        (CuBot, Cube Robot), ``ring_capture`` (OctBot) or ``bolt`` (test platform)."""
        kinds = {c.kind: c for c in robot.connectors}
        line = next((kinds[k] for k in ("front_rear", "ring_capture", "bolt") if k in kinds), None)
        if line is None:
            raise InputError(f"robot {robot.name!r} has no front-rear coupling (has: {', '.join(kinds) or 'none'})")

        def joint(c) -> Joint | None:
            if c is None:
                return None
            return Joint(c.kind, c.rotational_stiffness_nm_per_rad, c.axial_stiffness_n_per_m,
                         c.backlash_rad, c.height_m, c.gap_m, **joint_play(c.play),
                         shear_n_per_m=c.shear_stiffness_n_per_m, provenance=c.provenance,
                         levers_m=tuple(c.pin_levers_m), preload_n=c.preload_n,
                         friction_coefficient=c.friction_coefficient)

        return cls(joint(line), joint(kinds.get("side_rail")), joint(kinds.get("top_twist")))

    def scaled(self, stiffness: float = 1.0, backlash: float = 1.0) -> ConnectorSet:
        def s(j: Joint | None) -> Joint | None:
            return None if j is None else j.scaled(stiffness, backlash)
        return replace(self, front_rear=s(self.front_rear), side_rail=s(self.side_rail), top_twist=s(self.top_twist))

    def to_dict(self) -> dict:
        out = {}
        for name in ("front_rear", "side_rail", "top_twist"):
            j = getattr(self, name)
            if j is not None:
                out[name] = {"kind": j.kind, "rotational_nm_per_rad": j.rotational_nm_per_rad,
                             "axial_n_per_m": j.axial_n_per_m, "shear_n_per_m": j.k_z,
                             "backlash_rad": j.backlash_rad, "play_x_m": list(j.play_x),
                             "play_z_m": list(j.play_z), "height_m": j.height_m, "levers_m": list(j.levers_m),
                             "provenance": j.provenance}
                if j.preload_n > 0:
                    out[name].update(preload_n=j.preload_n, friction_coefficient=j.friction_coefficient)
        out["hinge"] = self.hinge
        return out
