"""The wedge latch: a front-rear coupling without free play by design (issue 38, deliverable 1; mm, N).

The clearance latch (:class:`~cubot_cad.couplings.connectors.FrontRearSpec` without a wedge) holds the
pins with a flat blade in a flat groove: 0.2 mm of the pin head in its counterbore plus 0.2 mm of
the blade in the groove open in tension before anything bears (10.8 mrad over the 37 mm top pin,
~95 % of a derived line's tip). The thesis's platforms were "set very tight"; a bolt set tight has
no play. The wedge latch does what that bolt does with the parts the robot already has:

* the pin's groove ends on the tip side in a **cone** (half-angle ``cone_deg`` from the pin's axis)
  instead of a flat shoulder;
* the blade's arc slots **taper** (``slot half-width`` from :attr:`WedgeLatch.entry_half_width_mm`
  at the open end to :attr:`WedgeLatch.lock_half_width_mm` at the locking end) over the blade's
  turn: as the latch servo turns the blade, each slot's two edges close on the cone and draw
  the pin deeper into the latch robot until its head bears on the front of its counterbore
  (the head clearance taken up) and the pins are stretched by the preload;
* a print looser than :attr:`WedgeLatch.lock_below_mm` past the head clearance first meets a steep,
  unloaded lead-in (the pin is free until its head bears), so the locking taper covers only the draw
  that can be loaded and stays self-locking across the print clearances 0.1-0.5 mm;
* the locking taper's angle ``gamma`` is below the friction angle of printed plastic on itself, so
  the wedge is **self-locking**: the pull cannot turn the blade back, the servo may rest.

What is computed here from the geometry and the servo (nothing is a constant):

* ``take_up_mm``: how far the wedge can draw a pin in, ``(entry - lock half-width) / tan(cone)``
  less the free turn before contact; the design asks for the head clearance plus
  ``take_up_margin_mm`` (print tolerance + the preload's own stretch);
* ``preload_n``: the servo's stall torque on the blade (3 pins at ``pin_circle_mm``) through the
  slot wedge and the cone, with friction ``mu`` on both: per pin ``F_t = T / (3 r)``, radial
  squeeze per edge ``N = F_t / (2 tan(gamma + phi))``, axial pull ``2 N tan(cone - phi)``;
* ``residual_play_mm(actual head clearance)``: what the preload cannot take up,
  ``max(0, clearance + stretch - take_up)`` (zero for the design's prints; a print whose head
  clearance exceeds the wedge's reach keeps the excess as free play and no preload);
* ``slip_hold_n``: the shear the pressed faces hold by friction, ``mu x preload`` (the model keeps
  the pins' vertical slip: it does not count on friction, see :mod:`structure_fem.model.hinge`).

Friction of printed ABS / PLA on itself: static, dry, about 0.2-0.45 depending on the layer
direction and the finish (the range published FDM friction tests report; none was measured for
this project): :data:`FRICTION_NOMINAL` 0.3 and the band's range :data:`FRICTION_RANGE` are that
assumption, and docs/measure-coupling.md says how to measure it on a print.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from cubot_cad.part import need

#: Static friction coefficient, printed plastic on itself (see the module docstring: an assumption).
FRICTION_NOMINAL = 0.3
#: Its range (the uncertainty band's distribution bounds, ``structure_fem.analysis.band``).
FRICTION_RANGE = (0.2, 0.45)
FRICTION_SOURCE = ("assumption: static friction of printed ABS/PLA on itself 0.2-0.45 (FDM tribology tests, "
                   "layer direction and finish); nominal 0.3")
#: Preload points per blade: one per pin of a block (``PIN_ANGLES_DEG``).
PINS_PER_BLADE = 3


@dataclass(frozen=True)
class WedgeLatch:
    """The wedge latch's own dimensions (mm, deg); the rest is the :class:`FrontRearSpec`'s."""

    #: Half-angle of the groove's tip-side cone, from the pin's axis.
    cone_deg: float = 30.0
    #: The locking end of the slot stays this far outside the groove's core (the edge bears on the cone).
    lock_margin_mm: float = 0.15
    #: Take-up beyond the nominal head clearance: print tolerance and the preload's stretch.
    take_up_margin_mm: float = 0.3
    #: Free turn at the open end before an edge can touch the cone of a pin in its loosest place (mm of
    #: slot half-width): the blade starts turning unloaded.
    entry_gap_mm: float = 0.05
    #: The self-locking taper starts this far below the nominal head clearance's draw (a tighter print's
    #: pin still meets the locking part of the slot); any draw before it is an unloaded lead-in.
    lock_below_mm: float = 0.2
    #: Taper of that lead-in (deg): it only moves a free pin (no preload yet), so it may be steep, but below
    #: 90 deg less the highest friction angle (:data:`FRICTION_RANGE`) or the edge jams the cone instead of
    #: drawing it.
    lead_in_deg: float = 60.0
    #: Static friction used for the preload and the locking check (:data:`FRICTION_NOMINAL`).
    friction: float = FRICTION_NOMINAL
    #: Lowest friction the wedge must still lock at (the low end of :data:`FRICTION_RANGE`).
    friction_min: float = FRICTION_RANGE[0]

    def __post_init__(self) -> None:
        need(20.0 <= self.cone_deg <= 60.0, f"wedge cone_deg {self.cone_deg:g} must be in 20..60 deg")
        need(0.05 <= self.lock_margin_mm <= 0.5, f"wedge lock_margin_mm {self.lock_margin_mm:g} must be in 0.05..0.5 mm")
        need(0.0 <= self.take_up_margin_mm <= 0.6,
             f"wedge take_up_margin_mm {self.take_up_margin_mm:g} must be in 0..0.6 mm")
        need(0.0 <= self.entry_gap_mm <= 0.3, f"wedge entry_gap_mm {self.entry_gap_mm:g} must be in 0..0.3 mm")
        need(0.0 <= self.lock_below_mm <= 0.5, f"wedge lock_below_mm {self.lock_below_mm:g} must be in 0..0.5 mm")
        jam = 90.0 - math.degrees(math.atan(FRICTION_RANGE[1]))
        need(10.0 <= self.lead_in_deg < jam,
             f"wedge lead_in_deg {self.lead_in_deg:g} must be in 10..{jam:.1f} deg (steeper jams at friction "
             f"{FRICTION_RANGE[1]:g})")
        need(0.05 <= self.friction_min <= self.friction <= 1.0,
             f"wedge friction {self.friction:g} / friction_min {self.friction_min:g}: need 0.05 <= min <= nominal <= 1")

    @property
    def tan_lead(self) -> float:
        return math.tan(math.radians(self.lead_in_deg))

    @property
    def tan_cone(self) -> float:
        return math.tan(math.radians(self.cone_deg))

    def take_up_mm(self, spec) -> float:
        """The draw the design asks for: the head's axial clearance (``spec.clearance_mm``) + margin."""
        return spec.clearance_mm + self.take_up_margin_mm

    def lock_half_width_mm(self, spec) -> float:
        return spec.groove_diameter_mm / 2 + self.lock_margin_mm

    def entry_half_width_mm(self, spec) -> float:
        return self.lock_half_width_mm(spec) + self.take_up_mm(spec) * self.tan_cone + self.entry_gap_mm

    def slot_arc_mm(self, spec) -> float:
        """Arc the slot runs over: the blade's turn at the pin circle."""
        return spec.pin_circle_mm * math.radians(spec.blade_turn_deg)

    # -- the slot's profile: an unloaded lead-in, then the self-locking taper ---------------------
    def lead_draw_mm(self, spec) -> float:
        """Draw taken by the lead-in (mm): the head clearance beyond :attr:`lock_below_mm` (0 for tight
        prints: then the whole slot is the locking taper)."""
        return max(0.0, spec.clearance_mm - self.lock_below_mm)

    def lock_start_half_width_mm(self, spec) -> float:
        """Slot half-width where the self-locking taper begins (the lead-in's end)."""
        draw = self.take_up_mm(spec) - self.lead_draw_mm(spec)
        return self.lock_half_width_mm(spec) + draw * self.tan_cone + self.entry_gap_mm

    def lead_arc_mm(self, spec) -> float:
        """Arc of the lead-in at the pin circle (mm)."""
        dh = self.entry_half_width_mm(spec) - self.lock_start_half_width_mm(spec)
        return dh / self.tan_lead

    def lead_fraction(self, spec) -> float:
        """The lead-in's share of the turn (0..1)."""
        return self.lead_arc_mm(spec) / self.slot_arc_mm(spec)

    def tan_taper(self, spec) -> float:
        """tan of the locking taper (each slot edge closes on the pin by this per mm of turn): the angle
        the self-locking check and the preload use."""
        run = self.slot_arc_mm(spec) - self.lead_arc_mm(spec)
        if run <= 0.0:
            return math.inf
        return (self.lock_start_half_width_mm(spec) - self.lock_half_width_mm(spec)) / run

    def half_width_mm(self, spec, f: float) -> float:
        """Slot half-width a fraction ``f`` of the turn from the open end (0) to the locking end (1)."""
        s = min(1.0, max(0.0, f)) * self.slot_arc_mm(spec)
        lead = self.lead_arc_mm(spec)
        if s < lead:
            return self.entry_half_width_mm(spec) - s * self.tan_lead
        return self.lock_start_half_width_mm(spec) - (s - lead) * self.tan_taper(spec)

    def turn_fraction(self, spec, half_width_mm: float) -> float:
        """The inverse of :meth:`half_width_mm`: where the slot is ``half_width_mm`` wide (clipped to 0..1)."""
        h0, hk = self.entry_half_width_mm(spec), self.lock_start_half_width_mm(spec)
        arc, lead = self.slot_arc_mm(spec), self.lead_arc_mm(spec)
        if half_width_mm >= hk:
            s = (h0 - half_width_mm) / self.tan_lead
        else:
            s = lead + (hk - half_width_mm) / self.tan_taper(spec)
        return min(1.0, max(0.0, s / arc))

    def profile_breaks(self, spec) -> tuple[float, ...]:
        """The turn fractions where the profile kinks (for drawing it exactly)."""
        f = self.lead_fraction(spec)
        return (0.0, f, 1.0) if f > 0.0 else (0.0, 1.0)

    # -- the groove (set-frame x of the pin; see GroovedPin.groove_mm) --------------------------
    def blade_deep_face_depth_mm(self, spec) -> float:
        """Depth behind the latch face of the blade's face towards the pin tips (where its edges bear)."""
        return spec.wall_mm + 2 * spec.plate_mm + spec.clearance_mm + spec.blade_mm

    def groove_x_mm(self, spec) -> tuple[float, float, float]:
        """(start of the groove, start of the cone, end of the cone) in the pin's set frame, the pin in
        its loosest place (head at the back of its counterbore, as drawn): the cone meets the locked slot's
        edge after the design's take-up, and the groove's root-side shoulder keeps a clearance to the
        blade when drawn in."""
        d_b = self.blade_deep_face_depth_mm(spec)
        g = spec.design_gap_mm
        rg, r = spec.groove_diameter_mm / 2, spec.pin_diameter_mm / 2
        x_s = g + d_b - self.lock_margin_mm / self.tan_cone - self.take_up_mm(spec)
        g0 = g + d_b - spec.blade_mm - spec.clearance_mm - self.take_up_mm(spec)
        return (g0, x_s, x_s + (r - rg) / self.tan_cone)

    def validate(self, spec) -> None:
        """The wedge fits the spec: it locks at the lowest friction, its slot edges bear on the cone
        (between the core and the full pin), and the pin keeps a full tip beyond the cone."""
        need(self.lead_fraction(spec) <= 0.5,
             f"wedge: the lead-in takes {100 * self.lead_fraction(spec):.0f} % of the blade's turn (> 50 %): "
             f"a longer blade_turn_deg ({spec.blade_turn_deg:g}), a steeper lead_in_deg ({self.lead_in_deg:g}) or "
             f"a larger lock_below_mm ({self.lock_below_mm:g})")
        tg = self.tan_taper(spec)
        need(tg < self.friction_min,
             f"wedge slot taper tan {tg:.3f} ({math.degrees(math.atan(tg)):.1f} deg) does not lock at friction "
             f"{self.friction_min:g}: a longer blade_turn_deg ({spec.blade_turn_deg:g}), a shallower cone_deg "
             f"({self.cone_deg:g}) or a smaller lock_below_mm ({self.lock_below_mm:g}) lowers it")
        need(math.radians(self.cone_deg) > math.atan(self.friction),
             f"wedge cone_deg {self.cone_deg:g} is below the friction angle ({math.degrees(math.atan(self.friction)):.1f} "
             "deg): the slot would squeeze the pin without drawing it in")
        r = spec.pin_diameter_mm / 2
        h0 = self.entry_half_width_mm(spec)
        need(h0 <= r - 0.1,
             f"wedge: the slot's open end ({2 * h0:.2f} mm) is wider than the {spec.pin_diameter_mm:g} mm pin less "
             "0.2 mm: the cone is too shallow for the take-up (cone_deg, take_up_margin_mm)")
        _g0, _x_s, x_e = self.groove_x_mm(spec)
        need(x_e + spec.pin_chamfer_mm + 0.5 <= spec.protrusion_mm,
             f"wedge: the cone ends at {x_e:.2f} mm, leaving the pin's tip (to {spec.protrusion_mm:.2f} mm) less "
             f"than its {spec.pin_chamfer_mm:g} mm chamfer + 0.5 mm (cone_deg {self.cone_deg:g})")

    # -- mechanics --------------------------------------------------------------------------------
    def preload_per_pin_n(self, spec, torque_nm: float, friction: float | None = None) -> float:
        """Axial preload (N) of one pin from ``torque_nm`` on its blade (see the module docstring)."""
        mu = self.friction if friction is None else friction
        phi = math.atan(mu)
        f_t = torque_nm / (PINS_PER_BLADE * spec.pin_circle_mm * 1e-3)
        gamma = math.atan(self.tan_taper(spec))
        squeeze = f_t / (2 * math.tan(gamma + phi))
        beta = math.radians(self.cone_deg)
        return max(0.0, 2 * squeeze * math.tan(beta - phi))

    def residual_play_mm(self, spec, head_clearance_mm: float, stretch_mm: float = 0.0) -> float:
        """Tension play the wedge leaves (mm) for a print whose head has ``head_clearance_mm`` of axial
        clearance and whose pins stretch ``stretch_mm`` under the preload."""
        return max(0.0, head_clearance_mm + stretch_mm - self.take_up_mm(spec))


def wedge_summary(spec, wedge: WedgeLatch, torque_nm: float, n_pins: int, axial_n_per_m: float) -> dict:
    """The wedge latch's numbers for one coupling (``n_pins`` pins, joint axial stiffness ``axial_n_per_m``):
    preload per pin and in all, the pins' stretch under it, the take-up, the residual tension play of the
    nominal print, the friction hold, the taper and whether it locks."""
    p_pin = wedge.preload_per_pin_n(spec, torque_nm)
    total = p_pin * n_pins
    stretch = total / axial_n_per_m * 1e3
    tg = wedge.tan_taper(spec)
    return {"preload_per_pin_n": p_pin, "preload_n": total, "stretch_mm": stretch,
            "take_up_mm": wedge.take_up_mm(spec), "head_clearance_mm": spec.clearance_mm,
            "residual_play_mm": wedge.residual_play_mm(spec, spec.clearance_mm, stretch),
            "taper_deg": math.degrees(math.atan(tg)), "locks_at_friction": wedge.friction_min,
            "friction": wedge.friction, "slip_hold_n": wedge.friction * total, "servo_torque_nm": torque_nm}
