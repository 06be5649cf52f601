"""The coupling bench test a maker runs (docs/measure-coupling.md), run on the model (SI units).

Two printed robots docked by the coupling under test: robot A held flat on the bench (clamped,
as :data:`structure_fem.analysis.calibration.HELD_READING` holds the platforms), robot B
overhanging, weights hung at B's far end (its front underside edge) and the drop read there. A
maker turns each reading into the coupling's moment and rotation and ``fem calibrate --measured
FILE`` / ``fem table --measured FILE`` fit ``rotation = play + moment / k``
(:func:`structure_fem.couplings.connector_sources.fit_moment_rotation`); this module does the same
on the multibody model, the table's own (``statics.solve`` with a tip load, the record's
couplings, flexible bodies), so

* :func:`bench_test` says what a print of the drawn robot should measure (a maker compares), and
* :func:`synthetic_measurement` writes a file in the ``--measured`` format from it, **labelled
  synthetic** in its ``note`` (which every report's provenance then carries): the worked example
  of the protocol, never a measurement.

The moment about the coupling counts B's own weight (``m_B g`` at its centre of mass) and the
hung weight ``W g`` at B's far end. Two gauges read B's top: one just past the coupling (``near``)
and one at B's far end (``far``), each from B held level with the coupling unloaded (the
protocol's zero). Their difference over the distance between them is the coupling's rotation
(small angles), ``(far - near) / span``, with half of B's bending in it; the near gauge alone is
the coupling's vertical slip, which a single gauge at the tip would read as rotation: the model
of the drawn CuBot slips the pins' whole 0.4 mm vertical play under B's own weight (its faces are
frictionless in the multibody joint), so one gauge would report 4 mrad of "play" that is slip.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cubot_cad.properties import RobotProperties
from structure_fem.errors import InputError
from structure_fem.model.connectors import ConnectorSet
from structure_fem.model.statics import Config, solve
from structure_fem.model.structures import GRAVITY, Structure

#: Hung masses (kg) of the protocol's loading sequence: 0 (B's own weight alone) to 3 kg (about 3 N m at
#: the coupling, the order of the root moment of a 5-robot cantilever).
DEFAULT_MASSES_KG = (0.0, 0.5, 1.0, 1.5, 2.0, 3.0)
#: A dial gauge's resolution (m) that the synthetic readings are rounded to (0.01 mm).
GAUGE_RESOLUTION_M = 1e-5
#: The near gauge's distance past the coupling face (m): on B's top, clear of the latch.
NEAR_GAUGE_M = 0.01


@dataclass(frozen=True)
class BenchReading:
    """One load step: hung mass (kg), moment about the coupling (N m), drops at the near and far
    gauges (m), the rotation they give (rad) and the model's own relative rotation of the
    coupling's bodies (rad)."""

    mass_kg: float
    moment_nm: float
    drop_near_m: float
    drop_far_m: float
    rotation_rad: float
    model_joint_rotation_rad: float


@dataclass(frozen=True)
class BenchTest:
    """:func:`bench_test`'s result: the readings and the set-up (lever from the coupling to B's far
    end ``lever_m``, B's own-weight moment ``own_moment_nm``), and the line a maker would fit."""

    robot: str
    coupling: str
    lever_m: float
    #: Distance between the near and the far gauge (m).
    span_m: float
    own_moment_nm: float
    readings: tuple[BenchReading, ...]
    provenance: str

    def fit(self) -> tuple[float, float, int]:
        """``(k N m/rad, play rad, points)``: the fit ``fem calibrate --measured`` makes."""
        from structure_fem.couplings.connector_sources import fit_moment_rotation

        return fit_moment_rotation([[r.moment_nm, r.rotation_rad] for r in self.readings], "bench test")


def _check_masses(masses_kg) -> tuple[float, ...]:
    out = []
    for m in masses_kg:
        if isinstance(m, bool) or not isinstance(m, (int, float)) or not math.isfinite(m) or m < 0:
            raise InputError(f"bench test: hung masses must be numbers >= 0 kg, got {m!r}")
        out.append(float(m))
    if len(set(out)) < 2:
        raise InputError(f"bench test: give at least two different hung masses, got {list(masses_kg)!r}")
    return tuple(sorted(out))


def bench_test(robot: RobotProperties, conn: ConnectorSet | None = None,
               masses_kg=DEFAULT_MASSES_KG, flexible: bool = True) -> BenchTest:
    """Run the bench test on the model: robot A clamped, B overhanging on the front-rear coupling
    (``conn``, default the record's), each of ``masses_kg`` hung at B's far end (module docstring)."""
    masses = _check_masses(masses_kg)
    conn = conn if conn is not None else ConnectorSet.from_robot(robot)
    base = Config(Structure("line"), rows=2, rows_over=1, void_widths=1, clamped=True)
    lay_res = solve(base, robot, conn, flexible=flexible)
    lay = lay_res.layout
    (cp,) = [c for c in lay.couplings if c.role == "front_rear"]
    i = lay.front_body
    b = lay.bodies[i]
    x_tip = b.x_m + lay.length_m / 2
    lever = x_tip - cp.point_m[0]
    x_near = cp.point_m[0] + NEAR_GAUGE_M
    span = x_tip - x_near
    own = b.mass_kg * GRAVITY * (b.com_m[0] - cp.point_m[0])
    cx, cz = b.com_m

    def drop_at(res, x: float) -> float:  # B's top at x, rigid body motion of the solved state
        nz, phi = float(res.com_m[i][1]), float(res.rotation_rad[i])
        dx, dz = x - cx, b.z_m + lay.height_m - cz
        return -((nz + math.sin(phi) * dx + math.cos(phi) * dz) - (cz + dz))

    out = []
    for m in masses:
        res = lay_res if m == 0 else solve(Config(Structure("line"), rows=2, rows_over=1, void_widths=1, clamped=True,
                                                  tip_load_n=m * GRAVITY), robot, conn, flexible=flexible)
        near, far = drop_at(res, x_near), drop_at(res, x_tip)
        out.append(BenchReading(m, own + m * GRAVITY * lever, float(near), float(far), float((far - near) / span),
                                float(res.joint_rotation_rad[0])))
    src = (f"structure_fem.bench_test: the multibody model (statics.solve, {'flexible' if flexible else 'rigid'} "
           f"bodies, hinge {conn.hinge}) of {robot.name} A clamped and B overhanging on its front_rear coupling "
           f"({conn.front_rear.provenance}), masses hung {lever * 1e3:.4g} mm from the coupling")
    return BenchTest(robot.name, "front_rear", lever, span, own, tuple(out), src)


def synthetic_measurement(test: BenchTest, resolution_m: float = GAUGE_RESOLUTION_M) -> dict:
    """A file in ``fem calibrate --measured`` / ``fem table --measured`` format from ``test``, the
    drops rounded to the gauge's ``resolution_m`` as a reading would be, labelled SYNTHETIC."""
    if not (resolution_m > 0 and math.isfinite(resolution_m)):
        raise InputError(f"gauge resolution must be > 0 m, got {resolution_m!r}")
    def read(v: float) -> float:
        return round(v / resolution_m) * resolution_m

    pts, slips = [], []
    for r in test.readings:
        near, far = read(r.drop_near_m), read(r.drop_far_m)
        slips.append(near)
        rot = (far - near) / test.span_m
        if r.moment_nm > 0 and rot > 0:
            pts.append([round(r.moment_nm, 6), round(rot, 9)])
    note = (f"SYNTHETIC, NOT A MEASUREMENT: generated by `voidcross fem bench-example` from {test.provenance}; "
            f"gauges read to {resolution_m * 1e3:g} mm on B's top {NEAR_GAUGE_M * 1e3:g} mm past the coupling and at "
            f"B's far end, {test.span_m * 1e3:.4g} mm apart; each point [moment about the coupling N m (B's own weight "
            f"{test.own_moment_nm:.4g} N m + the hung weight at {test.lever_m * 1e3:.4g} mm), rotation rad ((far - near) "
            "/ span)]; hung masses kg " + ", ".join(f"{r.mass_kg:g}" for r in test.readings)
            + "; vertical slip at the near gauge mm " + ", ".join(f"{v * 1e3:.2f}" for v in slips))
    if len(pts) < 2:
        raise InputError(f"bench test of {test.robot}: fewer than two readings turn the coupling beyond the gauge's "
                         f"{resolution_m * 1e3:g} mm: hang heavier weights")
    return {test.coupling: {"moment_rotation": pts, "note": note}}


__all__ = ["DEFAULT_MASSES_KG", "BenchReading", "BenchTest", "bench_test", "synthetic_measurement"]
