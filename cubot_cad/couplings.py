"""Compliance estimates of the couplings, from the connector geometry (SI out).

These are documented first estimates that `structure_fem` calibrates; what is
*measured from the CAD* is the geometry that enters them: pin heights, lever
arms, clearances and docked gaps.

* Backlash = free axial play at the loaded feature / lever arm about the hinge.
  Zero gap (faces touch): the joint hinges on the bottom edge of the contact
  face, so the lever arm is the height of the highest pin (long). With a gap
  (Cube Robot) the faces never touch, the joint hinges on the lowest pin row
  and the lever arm is only the pin spread: the gap, not the material, makes
  the joint soft and loose (thesis Ch. 6.3.1.3, 7.1.3).
* Stiffness: pins and fingers are ABS bars loaded along their axis
  (k = E A / L through the groove core); the rail lips and the cross-key arms
  are cantilevers (k = E w t^3 / 4 L^3); rotational stiffness =
  sum k_i * (lever arm_i)^2 about the hinge.
"""

from __future__ import annotations

import math

from .properties import ConnectorProperties

#: Faces closer than this (mm) are in contact (the docking bisection resolves 1e-4 mm).
CONTACT_GAP_MM = 0.01
MIN_LIP_MM = 0.8


def front_rear(spec, pin_heights_mm: list[float], gap_mm: float, youngs_modulus_pa: float,
               height_mm: float) -> ConnectorProperties:
    """Grooved pins in engagement latches. ``pin_heights_mm``: z of every pin (robot frame)."""
    c = spec.clearance_mm
    area = math.pi * (spec.groove_diameter_mm / 2) ** 2 * 1e-6
    head_end = spec.head_x_mm + spec.head_mm
    groove_start = spec.design_gap_mm + spec.wall_mm + 2 * spec.plate_mm
    k_pin = youngs_modulus_pa * area / ((groove_start - head_end) * 1e-3)
    if gap_mm < CONTACT_GAP_MM:
        hinge = 0.0  # bottom edge of the touching faces = underside
    else:
        hinge = min(pin_heights_mm)  # no face contact: hinges on the lowest pins
    arms = [z - hinge for z in pin_heights_mm]
    lever = max(arms)
    k_rot = sum(k_pin * (a * 1e-3) ** 2 for a in arms)
    return ConnectorProperties(
        kind="front_rear", rotational_stiffness_nm_per_rad=k_rot,
        axial_stiffness_n_per_m=k_pin * len(pin_heights_mm),
        backlash_rad=c / lever, gap_m=(gap_mm if gap_mm >= CONTACT_GAP_MM else 0.0) * 1e-3,
        height_m=height_mm * 1e-3)


def cantilever_k(E: float, width_mm: float, thickness_mm: float, length_mm: float) -> float:
    """Tip stiffness (N/m) of a rectangular ABS cantilever: k = E w t^3 / (4 L^3)."""
    return E * (width_mm * 1e-3) * (thickness_mm * 1e-3) ** 3 / (4 * (length_mm * 1e-3) ** 3)


def side_rail(spec, youngs_modulus_pa: float, height_mm: float) -> ConnectorProperties:
    """Dovetail rail: the female groove's two lips bend as cantilevers (length = groove depth,
    thickness = the flank overhang, width = rail length), acting at +-tip/2 about the rail axis."""
    lip = max((spec.tongue_tip_mm - spec.tongue_root_mm) / 2, MIN_LIP_MM)
    k_lip = cantilever_k(youngs_modulus_pa, spec.length_mm, lip, spec.tongue_mm)
    arm = spec.tongue_tip_mm / 2
    return ConnectorProperties(
        kind="side_rail", rotational_stiffness_nm_per_rad=2 * k_lip * (arm * 1e-3) ** 2,
        axial_stiffness_n_per_m=2 * k_lip, backlash_rad=spec.clearance_mm / arm, gap_m=0.0,
        height_m=height_mm * 1e-3)


def top_twist(spec, youngs_modulus_pa: float, height_mm: float, gap_mm: float) -> ConnectorProperties:
    """Cross key: the four head arms bend as cantilevers (stem radius to arm tip) under the
    collar roof, acting at arm_length/2 about the horizontal axis."""
    length = spec.arm_length_mm / 2 - spec.arm_width_mm / 2
    k_arm = cantilever_k(youngs_modulus_pa, spec.arm_width_mm, spec.head_mm, length)
    arm = spec.arm_length_mm / 2
    return ConnectorProperties(
        kind="top_twist", rotational_stiffness_nm_per_rad=2 * k_arm * (arm * 1e-3) ** 2,
        axial_stiffness_n_per_m=4 * k_arm, backlash_rad=spec.clearance_mm / arm, gap_m=gap_mm * 1e-3,
        height_m=height_mm * 1e-3)


def ring_capture(finger_area_mm2: float, finger_length_mm: float, finger_radius_mm: float,
                 ring_outer_mm: float, clearance_mm: float, gap_mm: float, youngs_modulus_pa: float,
                 height_mm: float) -> ConnectorProperties:
    """Three fingers (bars) at 90/210/330 deg; the ring hinges on its bottom edge against the housing."""
    k_f = youngs_modulus_pa * finger_area_mm2 * 1e-6 / (finger_length_mm * 1e-3)
    arms = [ring_outer_mm + finger_radius_mm * math.sin(math.radians(a)) for a in (90, 210, 330)]
    return ConnectorProperties(
        kind="ring_capture", rotational_stiffness_nm_per_rad=sum(k_f * (a * 1e-3) ** 2 for a in arms),
        axial_stiffness_n_per_m=3 * k_f, backlash_rad=clearance_mm / max(arms), gap_m=gap_mm * 1e-3,
        height_m=height_mm * 1e-3)


def bolt(tab_width_mm: float, tab_mm: float, tab_length_mm: float, bolt_mm: float, clearance_mm: float,
         youngs_modulus_pa: float, height_mm: float) -> ConnectorProperties:
    """Lap joint with one bolt: the tab bends (E I / L), the hole bears on the bolt (E d t)."""
    inertia = tab_width_mm * tab_mm ** 3 / 12 * 1e-12
    k_rot = youngs_modulus_pa * inertia / (tab_length_mm * 1e-3)
    k_ax = youngs_modulus_pa * bolt_mm * 1e-3 * tab_mm * 1e-3
    return ConnectorProperties(kind="bolt", rotational_stiffness_nm_per_rad=k_rot, axial_stiffness_n_per_m=k_ax,
                               backlash_rad=clearance_mm / tab_length_mm, gap_m=0.0, height_m=height_mm * 1e-3)
