"""The robots' own bending (issue 12, deliverable 3): flexural rigidity from the CAD's section.

Every robot between its front and rear couplings is a short beam (SI units). Its flexural
rigidity is ``E I``: ``E`` the record's printed-material modulus, ``I`` the body's effective
second moment of area in the structure's plane, cut from the CAD by
:func:`cubot_cad.checks.section.body_section` (``RobotProperties.body_second_moment_m4``, with its
``body_second_moment_source``: the printed body shell cut at stations along its length, the
compliance ``integral dx / I(x)`` turned into the uniform ``I_eff = L / integral dx / I``).

A record written before the CAD exported the section falls back to the envelope box scaled by
the fill fraction ``m / (rho V)`` (what the model used before), and says so: that is several
times stiffer than a thin-walled printed shell (CuBot: 1.9e6 against 3.4e5 mm^4).

The table's model (:func:`structure_fem.model.statics.solve` with ``flexible=True``) lumps each robot's
compliance ``L / (E I)`` at the front-rear joints, half a robot on each side of a joint, in
series with the coupling's rotational spring (:func:`with_body_bending`). The robots are short
(100 mm) against the spans and the bending moment varies little over one robot, so the lumped
beam is close to a beam-element model: :func:`structure_fem.model.beams.flexible_line_tip` (exudyn
ANCF cable elements with the same ``E I``) checks it (tests/structure_fem/test_bodies.py).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

from cubot_cad.properties import RobotProperties
from structure_fem.errors import InputError

LEGACY_SOURCE = ("legacy record (no body_second_moment_m4): the envelope box b h^3 / 12 scaled by the fill "
                 "fraction m / (rho V), stiffer than the printed shell")


@dataclass(frozen=True)
class BodyBending:
    """One robot body as a beam: ``E I`` (N m^2) over its length (m), and where ``I`` came from."""

    youngs_modulus_pa: float
    second_moment_m4: float
    length_m: float
    source: str

    @property
    def flexural_rigidity_n_m2(self) -> float:
        return self.youngs_modulus_pa * self.second_moment_m4

    @property
    def compliance_rad_per_nm(self) -> float:
        """End-to-end rotation of one body per unit moment, ``L / (E I)`` (rad / (N m))."""
        return self.length_m / self.flexural_rigidity_n_m2

    def to_dict(self) -> dict:
        return {"youngs_modulus_pa": self.youngs_modulus_pa, "second_moment_m4": self.second_moment_m4,
                "flexural_rigidity_n_m2": self.flexural_rigidity_n_m2, "length_m": self.length_m,
                "compliance_rad_per_nm": self.compliance_rad_per_nm, "source": self.source}


def body_bending(robot: RobotProperties) -> BodyBending:
    """The record's body as a beam (module docstring): the CAD's section, else the legacy box."""
    i_cad = getattr(robot, "body_second_moment_m4", None)
    if i_cad is not None:
        if not (i_cad > 0):
            raise InputError(f"{robot.name}.body_second_moment_m4 must be > 0, got {i_cad!r}")
        src = getattr(robot, "body_second_moment_source", None) or "record"
        return BodyBending(robot.youngs_modulus_pa, float(i_cad), robot.length_m, src)
    fill = min(1.0, robot.mass_kg / (robot.density_kg_m3 * robot.length_m * robot.width_m * robot.height_m))
    i_box = fill * robot.width_m * robot.height_m ** 3 / 12.0
    return BodyBending(robot.youngs_modulus_pa, i_box, robot.length_m, LEGACY_SOURCE)


def with_body_bending(conn, robot: RobotProperties):
    """``conn`` (a :class:`structure_fem.model.connectors.ConnectorSet`) with half a robot's bending
    compliance on each side of every front-rear joint, in series with the joint's rotational
    spring: ``1 / k' = 1 / k + L / (E I)``. A joint with an emergent hinge
    (:mod:`structure_fem.model.hinge`) has no rotational spring: its tension rows carry the rotation, so
    their stiffness (the joint's axial and rotational alike) is scaled by ``k' / k``, which gives
    their rotational stiffness about the hinge the same series value."""
    from structure_fem.model.hinge import TOUCHING_GAP_M

    c_body = body_bending(robot).compliance_rad_per_nm
    fr = conn.front_rear
    k = 1.0 / (1.0 / fr.rotational_nm_per_rad + c_body)
    if conn.hinge == "emergent" and fr.kind == "front_rear" and fr.gap_m <= TOUCHING_GAP_M:
        return replace(conn, front_rear=replace(fr, rotational_nm_per_rad=k,
                                                axial_n_per_m=fr.axial_n_per_m * k / fr.rotational_nm_per_rad))
    return replace(conn, front_rear=replace(fr, rotational_nm_per_rad=k))
