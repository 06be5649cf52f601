"""Compliance estimates of the couplings, from the connector geometry (SI out).

These are documented first estimates that `structure_fem` calibrates; what is
*measured from the CAD* is the geometry that enters them: pin heights, lever
arms, clearances and docked gaps.

* Play per feature (:class:`~cubot_cad.properties.FeaturePlay`), always the sum of the CAD's
  clearances in series on that load path, never a separate number: a front-rear coupling
  opens in tension by the pin head's axial clearance in its counterbore plus the latch
  blade's clearance in the pin groove (2 x 0.2 mm at the default clearance), and slips
  vertically by the pin's radial clearance in its own bores plus that in the mating
  robot's bores; the rail's tongue moves vertically by its flank clearance, the cross key
  slips horizontally in the cross hole and lifts by its head's clearance under the collar
  roof. In compression the faces (or pin tips, the wheels on the cover) already touch: no gap.
* Backlash = the tension play / lever arm about the hinge (pitch play).
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

from cubot_cad.properties import ConnectorProperties, FeaturePlay

#: Faces closer than this (mm) are in contact (the docking bisection resolves 1e-4 mm).
CONTACT_GAP_MM = 0.01
MIN_LIP_MM = 0.8


def front_rear_play_mm(spec, stretch_mm: float = 0.0) -> dict[str, float]:
    """Play of the front-rear coupling per feature (mm), from the spec's clearances.

    ``tension``: pin head's axial clearance in plate (b)'s counterbore (its depth less the head)
    plus the blade's clearance to the pin groove's shoulder (half of groove width less blade);
    with the wedge latch (``spec.wedge``) what its draw cannot take up of the head's clearance
    (plus ``stretch_mm``, the pins' stretch under the preload), the blade bearing on the cone
    (:meth:`~cubot_cad.couplings.preload.WedgeLatch.residual_play_mm`: 0 for the design's prints).
    ``vertical_slip``: the pin's radial clearance in its own bores plus in the mating robot's
    wall and latch bores (both are pin + 2 clearances across)."""
    head = spec.locking_plate_mm - spec.head_mm - spec.head_wall_mm
    blade = (spec.separation_mm - spec.blade_mm) / 2
    bore = spec.clearance_mm  # (pin + 2 c - pin) / 2, every bore the pin passes
    out = {"head_in_counterbore": head, "blade_in_groove": blade, "tension": head + blade,
           "own_bore": bore, "mating_bore": bore, "vertical_slip": 2 * bore}
    if spec.wedge is not None:
        out.update(blade_in_groove=0.0, tension=spec.wedge.residual_play_mm(spec, head, stretch_mm))
    return out


def front_rear(spec, pin_heights_mm: list[float], gap_mm: float, youngs_modulus_pa: float,
               height_mm: float, servo_torque_nm: float | None = None, servo_source: str = "") -> ConnectorProperties:
    """Grooved pins in engagement latches. ``pin_heights_mm``: z of every pin (robot frame).
    A wedge latch (``spec.wedge``) needs ``servo_torque_nm``, the latch servo's stall torque on each
    blade (``servo_source`` names it): its preload and residual play come from it."""
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
    preload = {}
    stretch = 0.0
    if spec.wedge is not None:
        if servo_torque_nm is None or not servo_torque_nm > 0:
            raise ValueError("a wedge latch's coupling needs the latch servo's torque (servo_torque_nm > 0)")
        from cubot_cad.couplings.preload import FRICTION_SOURCE, wedge_summary

        w = wedge_summary(spec, spec.wedge, servo_torque_nm, len(pin_heights_mm), k_pin * len(pin_heights_mm))
        stretch = w["stretch_mm"]
        preload = {"preload_n": w["preload_n"], "friction_coefficient": spec.wedge.friction,
                   "preload_source": (f"wedge latch: {servo_source or f'{servo_torque_nm:g} N m'} stall torque on "
                                      f"each blade, slot taper {w['taper_deg']:.3g} deg, cone "
                                      f"{spec.wedge.cone_deg:g} deg, friction {spec.wedge.friction:g} "
                                      f"({FRICTION_SOURCE}); {w['preload_per_pin_n']:.3g} N per pin")}
    pl = front_rear_play_mm(spec, stretch)
    if spec.wedge is not None:
        tension_text = (f"wedge latch: pin head's {pl['head_in_counterbore']:.3g} mm in its counterbore + "
                        f"{stretch:.2g} mm preload stretch, less the wedge's {spec.wedge.take_up_mm(spec):.3g} mm "
                        f"draw (the blade bears on the groove's cone)")
    else:
        tension_text = (f"pin head in its counterbore ({pl['head_in_counterbore']:.3g} mm) + latch blade in the "
                        f"pin groove ({pl['blade_in_groove']:.3g} mm), in series")
    play = (
        FeaturePlay("tension", "x", "tension", pl["tension"] * 1e-3, tension_text),
        FeaturePlay("vertical_slip", "z", "both", pl["vertical_slip"] * 1e-3,
                    f"pin in its own bores ({pl['own_bore']:.3g} mm radial) + in the mating robot's wall and "
                    f"latch bores ({pl['mating_bore']:.3g} mm radial)"),
    )
    return ConnectorProperties(
        kind="front_rear", rotational_stiffness_nm_per_rad=k_rot,
        axial_stiffness_n_per_m=k_pin * len(pin_heights_mm),
        backlash_rad=pl["tension"] / lever, gap_m=(gap_mm if gap_mm >= CONTACT_GAP_MM else 0.0) * 1e-3,
        height_m=height_mm * 1e-3, play=play, pin_levers_m=tuple(a * 1e-3 for a in arms), **preload,
        provenance=(f"hand formula: {len(pin_heights_mm)} pins as axial bars E A_groove / L (head to groove), "
                    f"k_rot = sum k_pin a_i^2 about the hinge at z = {hinge:g} mm; robots and walls rigid; "
                    f"pitch play = tension play / highest pin ({lever:.3g} mm)"))


def cantilever_k(E: float, width_mm: float, thickness_mm: float, length_mm: float) -> float:
    """Tip stiffness (N/m) of a rectangular ABS cantilever: k = E w t^3 / (4 L^3)."""
    return E * (width_mm * 1e-3) * (thickness_mm * 1e-3) ** 3 / (4 * (length_mm * 1e-3) ** 3)


def side_rail(spec, youngs_modulus_pa: float, height_mm: float) -> ConnectorProperties:
    """Dovetail rail: the female groove's two lips bend as cantilevers (length = groove depth,
    thickness = the flank overhang, width = rail length), acting at +-tip/2 about the rail axis."""
    lip = max((spec.tongue_tip_mm - spec.tongue_root_mm) / 2, MIN_LIP_MM)
    k_lip = cantilever_k(youngs_modulus_pa, spec.length_mm, lip, spec.tongue_mm)
    arm = spec.tongue_tip_mm / 2
    play = (FeaturePlay("rail_vertical", "z", "both", spec.flank_offset_mm * 1e-3,
                        f"dovetail tongue between the groove's slanted flanks: normal clearance "
                        f"{spec.clearance_mm:g} mm = {spec.flank_offset_mm:.3g} mm vertically"),)
    return ConnectorProperties(
        kind="side_rail", rotational_stiffness_nm_per_rad=2 * k_lip * (arm * 1e-3) ** 2,
        axial_stiffness_n_per_m=2 * k_lip, backlash_rad=spec.clearance_mm / arm, gap_m=0.0,
        height_m=height_mm * 1e-3, play=play,
        provenance=("hand formula: two groove lips as cantilevers E w t^3 / 4 L^3 (w = rail length), "
                    "rotation and play about the rail's own axis (roll, not the pitch over the overlap)"))


def top_twist(spec, youngs_modulus_pa: float, height_mm: float, gap_mm: float) -> ConnectorProperties:
    """Cross key: the four head arms bend as cantilevers (stem radius to arm tip) under the
    collar roof, acting at arm_length/2 about the horizontal axis."""
    length = spec.arm_length_mm / 2 - spec.arm_width_mm / 2
    k_arm = cantilever_k(youngs_modulus_pa, spec.arm_width_mm, spec.head_mm, length)
    arm = spec.arm_length_mm / 2
    lift = spec.roof_under_mm - (spec.head_z0_mm + spec.head_mm)
    play = (FeaturePlay("key_slip", "x", "both", spec.clearance_mm * 1e-3,
                        f"cross key arm in the cross hole (arm + 2 x {spec.clearance_mm:g} mm)"),
            FeaturePlay("pull_out", "z", "tension", lift * 1e-3,
                        f"key head under the collar roof ({lift:.3g} mm); pressing down the robot stands on "
                        "the cover"))
    return ConnectorProperties(
        kind="top_twist", rotational_stiffness_nm_per_rad=2 * k_arm * (arm * 1e-3) ** 2,
        axial_stiffness_n_per_m=4 * k_arm, backlash_rad=spec.clearance_mm / arm, gap_m=gap_mm * 1e-3,
        height_m=height_mm * 1e-3, play=play,
        provenance=("hand formula: four key arms as cantilevers E w t^3 / 4 L^3 under the collar roof "
                    "(vertical bending), the same value used for horizontal shear"))


def ring_capture(finger_area_mm2: float, finger_length_mm: float, finger_radius_mm: float,
                 ring_outer_mm: float, clearance_mm: float, gap_mm: float, youngs_modulus_pa: float,
                 height_mm: float) -> ConnectorProperties:
    """Three fingers (bars) at 90/210/330 deg; the ring hinges on its bottom edge against the housing."""
    k_f = youngs_modulus_pa * finger_area_mm2 * 1e-6 / (finger_length_mm * 1e-3)
    arms = [ring_outer_mm + finger_radius_mm * math.sin(math.radians(a)) for a in (90, 210, 330)]
    return ConnectorProperties(
        kind="ring_capture", rotational_stiffness_nm_per_rad=sum(k_f * (a * 1e-3) ** 2 for a in arms),
        axial_stiffness_n_per_m=3 * k_f, backlash_rad=clearance_mm / max(arms), gap_m=gap_mm * 1e-3,
        height_m=height_mm * 1e-3,
        play=(FeaturePlay("tension", "x", "tension", clearance_mm * 1e-3,
                          f"fingers in the ring ({clearance_mm:g} mm clearance)"),),
        provenance=("hand formula: three fingers as axial bars E A / L, k_rot = sum k_f a_i^2 about the "
                    "ring's bottom edge"))


def bolt(tab_width_mm: float, tab_mm: float, tab_length_mm: float, bolt_mm: float, clearance_mm: float,
         youngs_modulus_pa: float, height_mm: float) -> ConnectorProperties:
    """Lap joint with one bolt: the tab bends (E I / L), the hole bears on the bolt (E d t)."""
    inertia = tab_width_mm * tab_mm ** 3 / 12 * 1e-12
    k_rot = youngs_modulus_pa * inertia / (tab_length_mm * 1e-3)
    k_ax = youngs_modulus_pa * bolt_mm * 1e-3 * tab_mm * 1e-3
    return ConnectorProperties(kind="bolt", rotational_stiffness_nm_per_rad=k_rot, axial_stiffness_n_per_m=k_ax,
                               backlash_rad=clearance_mm / tab_length_mm, gap_m=0.0, height_m=height_mm * 1e-3,
                               provenance=("hand formula: tab bending E I / L, hole bearing E d t; the bolt's "
                                           "slip is left to the calibration's backlash family (no feature play)"))
