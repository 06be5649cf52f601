"""The pier deck (issue 16): a printed plate on the top robot of a pier that the line rolls over.

Why: a line robot cannot roll across a bare top cover (:mod:`cubot_cad.piers.pier`, running-surface
check): the top-down coupling's collar stands 8.7 mm (10.2 mm with the locking key) above the
cover, in the track of the rolling robot's cross key, caster seats and caster balls (its ground
clearance is 2.78 mm, the caster seats), and its right wheel runs over two cover-screw heads.

What it is (deck frame, mm: origin on the key axis in the plane the deck stands on, which is the
top robot's cover plate; x, y as the robot's; z up):

* a **ring foot** (outer radius ``ring_radius_mm``, wall ``ring_wall_mm``) from z = 0 up to the
  key-mount face at z = ``spec.stand_mm``: the stance of the top-down coupling, the height a
  robot's underside stands above the cover it docks on. Inside it are the collar, the locking key
  and the key flange; outside it, 17 mm further out, the cover screws' heads. It is round, so the
  deck can be turned on it;
* the **cross key**: a :class:`~cubot_cad.couplings.connectors.CrossKey` (``cross_key.stl``, one per pier),
  the robots' cross head (same spec as their :class:`~cubot_cad.couplings.twist.TwistKey`'s) on a square
  flange, screwed under the key-mount face with four ISO 7380 button-head screws into tap holes in
  the plate. The deck turns as a whole, so its key is fixed to it; a robot's key turns on its shaft
  (:mod:`cubot_cad.couplings.twist`). It is mounted turned clockwise by ``spec.twist_deg``
  (``CrossKey(turned=True)``), so it is locked when the deck is square with the robot;
* the **plate** from ``stand_mm`` to ``stand_mm + plate_mm``. Its top is the running deck: flat
  over ``length_mm`` (the robot's length) by ``width_mm`` (the robot's width, well over the wheel
  track), centred on the key axis;
* the **ends**: beyond ``length_mm`` each x end has a chamfer of ``ramp_deg``, ``ramp_drop_mm``
  deep, across the full width. This is the lead-in from the level the deck is meant to match (the
  ledge): a wheel or caster ball arriving up to ``ramp_drop_mm`` low rolls up a slope and does not
  meet a square edge.

Mounting, like a robot onto a robot: hold the deck turned counter-clockwise by ``twist_deg``
(its key is then aligned with the cross hole) and lower it until the ring stands on the cover.
The key head is then through the collar roof. Turn the deck clockwise by ``twist_deg`` until it is
square with the robot, and put the locking key into the hole arm, as at every interface of the
pier.

The slope, 45 deg, is the shallowest that prints without support. The deck prints top down (the
running deck on the bed, the mount face up, so its tap holes open upwards), and there the
chamfers face the bed. Forty-five degrees is the limit the repository prints to: the 45 deg
undersides of the body's corner bosses. It is also well within what the robot climbs: the 21 mm
wheel meets the edge of its design step (the 15 mm it stands on its wheels, which a deflected
front can climb) on a contact acos((21 - 15) / 21) = 73.4 deg steep, and the 10 mm caster ball
would meet the edge of a bare 2 mm step on one acos((5 - 2) / 5) = 53.1 deg steep (slopes from
horizontal, as ``ramp_deg``). The chamfer is only 2 mm deep, less than the line robot's ground
clearance (2.775 mm, its caster seats). So a robot arriving that low touches the deck's end with
its wheels and caster balls only, and clears it by the difference (0.77 mm). :meth:`cubot_cad.piers.pier.PierColumn.running_surface` measures both on the CAD.

The checks (:func:`dock_deck`) follow :mod:`cubot_cad.checks.docking` and :mod:`cubot_cad.piers.pier`:

* the deck, turned open, is lowered onto the top robot until first contact. It must stand on its
  ring with the key-mount face at the coupling's stance (``stand_mm``, within
  :data:`~cubot_cad.checks.docking.GAP_TOLERANCE_MM`);
* turned from open to square on its ring, it touches nothing (interference
  <= :data:`~cubot_cad.checks.docking.INTERFERENCE_LIMIT_MM3` at every step, with the cover screws'
  heads);
* square and with the locking key in, it does not interfere;
* the key engages. Lifted :data:`~cubot_cad.piers.pier.LIFT_MM` beyond its pull-out play, the square
  deck's key runs into the collar roof (> :data:`~cubot_cad.piers.pier.HOLD_MM3`), while the open deck
  lifts out free. Turned back open at the docked pose, its key runs into the locking key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from typing import ClassVar

import numpy as np

from cubot_cad.couplings.connectors import CrossKey, TopTwistSpec
from cubot_cad.errors import InputError
from cubot_cad.part import DEFAULT_CLEARANCE_MM, MIN_WALL_MM, Part, at_least, at_most, need

#: The shallowest chamfer that prints without support top down (deg from horizontal): the
#: repository's 45 deg rule (the undersides of the body's corner bosses, :mod:`cubot_cad.robots.cubot`).
PRINT_SLOPE_DEG = 45.0
#: The deck's cross key is screwed on with button heads (low enough to clear the locking key's lip).
SCREW_KIND = "ISO 7380"
#: Steps of the turn from open to square at which the deck is checked for interference.
TWIST_STEPS = 6
#: Colour of the deck in the pier's STEP and GLB (rgb 0-1).
DECK_COLOUR = (0.25, 0.62, 0.62)


def climb_limit_deg(robot) -> float:
    """How steep (deg from horizontal, as ``ramp_deg``) the contact is on which the robot's drive
    wheel meets the edge of the step it is designed to climb, its exposed wheel height:
    ``acos((R - h) / R)``."""
    R, h = float(robot.wheel_radius_mm), float(robot.wheel_exposed_mm)
    return math.degrees(math.acos((R - h) / R))


@dataclass(frozen=True)
class PierDeck(Part):
    """Running deck on the top robot of a pier (see the module docstring). Lengths mm, angles deg."""

    spec: TopTwistSpec = TopTwistSpec()
    #: Flat running deck along x (the robot's length) and across (the robot's width).
    length_mm: float = 100.0
    width_mm: float = 100.0
    #: The plate over the key-mount face: the running deck stands ``spec.stand_mm + plate_mm`` above
    #: the cover.
    plate_mm: float = 5.0
    ring_radius_mm: float = 40.0
    ring_wall_mm: float = 3.0
    #: The chamfer at each x end, beyond ``length_mm``: how deep, and its slope from horizontal.
    ramp_drop_mm: float = 2.0
    ramp_deg: float = 45.0
    #: The key flange's screws cut their thread this deep into the plate (tap hole + 0.5 mm).
    screw_thread_mm: float = 3.0
    clearance_mm: float = DEFAULT_CLEARANCE_MM
    name: ClassVar[str] = "pier_deck"
    description: ClassVar[str] = ("pier deck: flat running plate on the top robot of a pier, ring foot, 45 deg "
                                  "lead-in chamfers, carries a cross_key (4 M3 button heads into tap holes)")
    print_rotation: ClassVar = (((1.0, 0.0, 0.0), 180.0),)  # running deck on the bed

    def validate(self) -> None:
        s = self.spec
        need(abs(s.clearance_mm - self.clearance_mm) < 1e-12,
             f"PierDeck.spec.clearance_mm {s.clearance_mm:g} differs from clearance_mm {self.clearance_mm:g}")
        d = self.ramp_deg
        need(isinstance(d, (int, float)) and not isinstance(d, bool) and math.isfinite(d)
             and PRINT_SLOPE_DEG - 1e-9 <= d < 90.0,
             f"PierDeck.ramp_deg {d!r} is not a slope in [{PRINT_SLOPE_DEG:g}, 90) deg (shallower than "
             f"{PRINT_SLOPE_DEG:g} deg the chamfer overhangs the bed when the deck prints top down)")
        self.wall_check("plate_mm", self.plate_mm)
        self.wall_check("ring_wall_mm", self.ring_wall_mm)
        need(at_least(self.plate_mm - self.tap_depth_mm, MIN_WALL_MM),
             f"PierDeck.plate_mm {self.plate_mm:g} leaves under {MIN_WALL_MM:g} mm over the "
             f"{self.tap_depth_mm:g} mm tap holes of the key flange's screws")
        need(at_least(self.plate_mm - self.ramp_drop_mm, MIN_WALL_MM),
             f"PierDeck.ramp_drop_mm {self.ramp_drop_mm:g} leaves under {MIN_WALL_MM:g} mm of the "
             f"{self.plate_mm:g} mm plate at its ends")
        inner = self.ring_radius_mm - self.ring_wall_mm
        need(at_least(inner, self.reach_mm + self.clearance_mm),
             f"PierDeck.ring_radius_mm {self.ring_radius_mm:g} (wall {self.ring_wall_mm:g}) leaves the ring "
             f"inside the collar, locking key or key flange (they reach {self.reach_mm:.2f} mm from the key axis)")
        need(at_most(self.ring_radius_mm, min(self.length_mm, self.width_mm) / 2),
             f"PierDeck.ring_radius_mm {self.ring_radius_mm:g} puts the ring outside the "
             f"{self.length_mm:g} x {self.width_mm:g} mm plate")
        need(at_least(self.length_mm, 2 * self.ring_radius_mm) and at_least(self.width_mm, 2 * self.ring_radius_mm),
             f"PierDeck.length_mm {self.length_mm:g} / width_mm {self.width_mm:g} is smaller than the ring")
        from cubot_cad.hardware.fasteners import thread

        t = thread(s.screw_size)
        need(t.button_head_height_mm is not None,
             f"PierDeck.spec.screw_size {s.screw_size}: the table has no {SCREW_KIND} button head for it")
        under = s.stand_mm - s.flange_mm - t.button_head_height_mm  # the screw heads' underside
        need(at_least(under, s.collar_mm + s.lip_mm + self.clearance_mm),
             f"PierDeck.spec: the key flange's button heads ({under:.2f} mm above the cover) would touch the "
             f"locking key's lip ({s.collar_mm + s.lip_mm:.2f} mm)")

    # -- derived dimensions -------------------------------------------------------------------
    @property
    def stand_mm(self) -> float:
        """Key-mount face above the plane the ring stands on (the coupling's stance)."""
        return self.spec.stand_mm

    @property
    def height_mm(self) -> float:
        """The running deck above the plane the ring stands on (designed)."""
        return self.spec.stand_mm + self.plate_mm

    @property
    def ramp_run_mm(self) -> float:
        """How far each chamfer runs along x beyond ``length_mm``."""
        return self.ramp_drop_mm / math.tan(math.radians(self.ramp_deg))

    @property
    def total_length_mm(self) -> float:
        return self.length_mm + 2 * self.ramp_run_mm

    @property
    def tap_depth_mm(self) -> float:
        return self.screw_thread_mm + 0.5

    @property
    def reach_mm(self) -> float:
        """How far from the key axis the collar, the locking key's lip and the key flange reach."""
        s = self.spec
        lip = math.hypot(s.arm_length_mm / 2 + 3.0, s.arm_width_mm / 2 + 2.0)  # LockingKey.build's lip corner
        return max(s.cavity_radius_mm + s.collar_wall_mm, lip, s.flange_size_mm / math.sqrt(2))

    def key_screw_points(self) -> list[tuple[float, float]]:
        """(x, y) of the key flange's four screws, deck frame: the flange's points turned with the key."""
        a = math.radians(-self.spec.twist_deg)
        c, s_ = math.cos(a), math.sin(a)
        return [(c * x - s_ * y, s_ * x + c * y) for x, y in self.spec.flange_screw_points()]

    def screws(self):
        """The four key-flange screws (:class:`~cubot_cad.hardware.fasteners.FastenerUse`), through the flange
        into the plate's tap holes."""
        from cubot_cad.hardware.fasteners import bolted

        return bolted("pier_deck", self.spec.screw_size, self.spec.flange_mm, 4,
                      "pier deck: its cross key's flange into the deck's tap holes", thread_mm=self.screw_thread_mm,
                      kind=SCREW_KIND)

    @cached_property
    def key(self) -> CrossKey:
        """The mating half: the deck's flanged cross key (the robots' cross head, same spec), mounted turned."""
        return CrossKey(spec=self.spec, turned=True)

    @property
    def key_part(self) -> CrossKey:
        """The key as a printed part: ``cross_key`` (one per pier; it is only mounted turned)."""
        return CrossKey(spec=self.spec)

    # -- geometry --------------------------------------------------------------------------------
    def build(self):
        from cubot_cad.hardware.fasteners import tap_hole_mm
        from cubot_cad.shapes import Z, box, cut_all, cyl, prism

        s = self.spec
        h0, h1 = s.stand_mm, s.stand_mm + self.plate_mm
        L2, W2, xe = self.length_mm / 2, self.width_mm / 2, self.length_mm / 2 + self.ramp_run_mm
        R, w = self.ring_radius_mm, self.ring_wall_mm
        plate = box(-xe, xe, -W2, W2, h0, h1)
        ring = cyl(R, h0 + 0.01, (0, 0, 0), Z).cut(cyl(R - w, h0 + 0.2, (0, 0, -0.1), Z))
        body = plate.fuse(ring).clean()
        t, drop = math.tan(math.radians(self.ramp_deg)), self.ramp_drop_mm
        cut = []
        for sgn in (1, -1):  # the chamfer: a plane through (L2, h1) falling at ramp_deg outwards
            pts = [(L2 - 1, h1 + t), (xe + 1, h1 - drop - t), (xe + 1, h1 + 5), (L2 - 1, h1 + 5)]
            cut.append(prism([(sgn * x, z) for x, z in pts], "XZ", -W2 - 1, 2 * W2 + 2))
        r_tap = tap_hole_mm(s.screw_size) / 2
        cut += [cyl(r_tap, self.tap_depth_mm + 0.01, (x, y, h0 - 0.01), Z) for x, y in self.key_screw_points()]
        return cut_all(body, cut)

    def placed(self, turn_deg: float = 0.0) -> list:
        """The deck and its cross key (:class:`~cubot_cad.robots.base.Placed`, deck frame), the whole deck
        turned ``turn_deg`` counter-clockwise about the key axis (0: square, key turned (locked);
        ``spec.twist_deg``: open, key aligned with the cross hole)."""
        from cubot_cad.robots.base import Placed
        from cubot_cad.shapes import location

        return [Placed(self, location((0, 0, 0), turn_deg), "deck"),
                Placed(self.key, location((0, 0, self.stand_mm), turn_deg), "cross_key")]

    def screw_head_solids(self, turn_deg: float = 0.0) -> list:
        """Stand-ins of the four button heads under the key flange (ISO 7380, deck frame)."""
        from cubot_cad.hardware.fasteners import thread
        from cubot_cad.shapes import Z, cyl, rotated

        t = thread(self.spec.screw_size)
        z = self.stand_mm - self.spec.flange_mm - t.button_head_height_mm
        heads = [cyl(t.button_head_diameter_mm / 2, t.button_head_height_mm, (x, y, z), Z)
                 for x, y in self.key_screw_points()]
        return [rotated(h, Z, turn_deg) for h in heads] if turn_deg else heads

    def mass_kg(self, density_kg_m3: float) -> float:
        """Printed deck + its cross key (solid, as the manifest) at ``density_kg_m3``."""
        return (self.volume_mm3 + self.key.volume_mm3) * 1e-9 * density_kg_m3

    def assembly_com_mm(self) -> tuple[float, float, float]:
        """Centre of mass of the deck and its key (solid, deck frame, square)."""
        key = self.placed()[1]
        items = [(self.volume_mm3, np.asarray(self.com_mm)),
                 (self.key.volume_mm3, np.asarray(_com(self.key.solid.moved(key.loc))))]
        m = sum(v for v, _ in items)
        return tuple(float(c) for c in sum(v * c for v, c in items) / m)

    def check_fits(self, robot) -> PierDeck:
        """Raise :class:`InputError` (one line, naming the deck's parameter) unless this deck fits
        ``robot``'s top: same coupling spec; the ring on the cover plate and clear of the cover
        screws' heads at every angle of the turn; the running deck at least the robot's length and
        over both wheel tracks; the chamfer no steeper than the robot climbs. Returns the deck."""
        from cubot_cad.hardware.fasteners import thread

        name = getattr(robot, "name", type(robot).__name__)
        need(getattr(robot, "top_spec", None) == self.spec,
             f"PierDeck.spec is not the {name}'s top-down coupling spec (the deck's key must be the robot's)")
        body = robot.body
        R = self.ring_radius_mm
        need(at_most(R, min(body.length_mm, body.width_mm) / 2),
             f"PierDeck.ring_radius_mm {R:g} puts the ring beyond the {body.length_mm:g} x {body.width_mm:g} mm "
             "cover plate it stands on")
        head_r = thread(self.spec.screw_size).shcs_head_diameter_mm / 2
        yc = robot.y_centre_mm
        near = min(math.hypot(x, y - yc) for x, y in body.cover_screw_points()) - head_r
        need(at_most(R + self.clearance_mm, near),
             f"PierDeck.ring_radius_mm {R:g} runs into the cover screws' heads ({near:.2f} mm from the key axis) "
             "as the deck is turned on")
        need(at_least(self.length_mm, robot.length_mm),
             f"PierDeck.length_mm {self.length_mm:g} is shorter than the {name}'s {robot.length_mm:g} mm "
             "(the line rolls over the full robot length)")
        track = robot.wheel_base_mm / 2 + robot.wheel_width_mm / 2  # the wheels are centred on the body
        need(at_least(self.width_mm / 2, track),
             f"PierDeck.width_mm {self.width_mm:g} does not reach over the wheel tracks (+-{track:g} mm about "
             f"the body's centre, y = {yc:g})")
        lim = climb_limit_deg(robot)
        need(at_most(self.ramp_deg, lim),
             f"PierDeck.ramp_deg {self.ramp_deg:g} is steeper than the {name} climbs ({lim:.1f} deg: its "
             f"{robot.wheel_radius_mm:g} mm wheel at the edge of its {robot.wheel_exposed_mm:g} mm step)")
        return self

    @classmethod
    def for_robot(cls, robot, **dims) -> PierDeck:
        """The deck for ``robot`` (its coupling spec, length, width and clearance), ``dims``
        overriding; :class:`InputError` (one line) when they do not fit it."""
        args = {"spec": robot.top_spec, "length_mm": robot.length_mm, "width_mm": robot.width_mm,
                "clearance_mm": robot.clearance_mm, **dims}
        return cls(**args).check_fits(robot)


def _com(shape) -> tuple[float, float, float]:
    import cadquery as cq

    c = cq.Shape.centerOfMass(shape)
    return (c.x, c.y, c.z)


def default_deck(robot) -> PierDeck | None:
    """The default deck of ``robot`` (None for a robot without the top-down coupling)."""
    from cubot_cad.checks.docking import ROBOT_OF_PAIR

    if getattr(robot, "name", None) != ROBOT_OF_PAIR["cubot-top-down"]:
        return None
    return _default_deck(robot)


@lru_cache(maxsize=16)
def _default_deck(robot) -> PierDeck:
    return PierDeck.for_robot(robot)


def pier_parts(robot) -> list[tuple[Part, int]]:
    """Printed parts a pier of ``robot`` needs once (not per robot): the deck and its cross key."""
    deck = default_deck(robot)
    return [] if deck is None else [(deck, 1), (deck.key_part, 1)]


def top_face_z_mm(shape) -> float:
    """z of the largest upward planar face of ``shape`` (the running deck)."""
    best = max((f for f in shape.Faces() if f.geomType() == "PLANE" and f.normalAt().z > 1 - 1e-9),
               key=lambda f: f.Area())
    return float(best.Center().z)


def chamfer_faces(shape) -> list[dict]:
    """The deck's end chamfers measured on a solid: every planar face looking up and along x,
    with its slope (deg from horizontal), depth (z extent) and run (x extent)."""
    from cubot_cad.shapes import tight_bbox

    out = []
    for f in shape.Faces():
        if f.geomType() != "PLANE":
            continue
        n = f.normalAt()
        if n.z <= 1e-6 or n.z >= 1 - 1e-9 or abs(n.x) < 1e-6:
            continue
        b = tight_bbox(f)
        out.append({"x_mm": [round(b[0], 3), round(b[3], 3)], "slope_deg": round(math.degrees(math.acos(n.z)), 4),
                    "drop_mm": round(b[5] - b[2], 4), "run_mm": round(b[3] - b[0], 4), "top_z_mm": b[5]})
    return sorted(out, key=lambda r: r["x_mm"][0])


# -- docking the deck on the top robot -----------------------------------------------------------

@dataclass
class DeckDock:
    """The deck docked on a robot's cover (measured). Lengths mm (robot frame), volumes mm^3."""

    deck: PierDeck = field(repr=False)
    #: Where the deck frame sits in the robot's frame (the key axis on the cover plate).
    offset_mm: tuple[float, float, float]
    cover_top_mm: float
    #: The key-mount face above the cover in the docked pose (measured) and as designed.
    stand_mm: float
    design_stand_mm: float
    open_interference_mm3: float
    interference_mm3: float
    twist: list[dict]
    keys: dict
    deck_height_mm: float
    top_z_mm: float

    @property
    def stand_ok(self) -> bool:
        from cubot_cad.checks.docking import GAP_TOLERANCE_MM

        return abs(self.stand_mm - self.design_stand_mm) <= GAP_TOLERANCE_MM

    @property
    def twist_ok(self) -> bool:
        from cubot_cad.checks.docking import INTERFERENCE_LIMIT_MM3

        return all(r["interference_mm3"] <= INTERFERENCE_LIMIT_MM3 for r in self.twist)

    @property
    def interference_ok(self) -> bool:
        from cubot_cad.checks.docking import INTERFERENCE_LIMIT_MM3

        return self.interference_mm3 <= INTERFERENCE_LIMIT_MM3

    @property
    def ok(self) -> bool:
        k = self.keys
        return self.stand_ok and self.twist_ok and self.interference_ok and k["key_holds"] and k["key_locked"]

    def problems(self) -> list[str]:
        from cubot_cad.checks.docking import GAP_TOLERANCE_MM, INTERFERENCE_LIMIT_MM3

        out = []
        if not self.stand_ok:
            out.append(f"stands {self.stand_mm:.3f} mm, designed {self.design_stand_mm:g} +- {GAP_TOLERANCE_MM:g} mm")
        if not self.twist_ok:
            worst = max(self.twist, key=lambda r: r["interference_mm3"])
            out.append(f"turning on it runs {worst['interference_mm3']:.1f} mm^3 into the robot at "
                       f"{worst['turn_deg']:g} deg")
        if not self.interference_ok:
            out.append(f"interference {self.interference_mm3:.1f} mm^3 > {INTERFERENCE_LIMIT_MM3:g} mm^3")
        if not self.keys["key_holds"]:
            out.append("the key does not hold")
        if not self.keys["key_locked"]:
            out.append("the locking key does not stop the key")
        return out

    def summary(self) -> dict:
        from cubot_cad.checks.docking import INTERFERENCE_LIMIT_MM3

        return {"part": self.deck.name, "offset_mm": [round(v, 4) for v in self.offset_mm],
                "stand_mm": round(self.stand_mm, 4), "design_stand_mm": round(self.design_stand_mm, 4),
                "deck_height_mm": round(self.deck_height_mm, 4),
                "open_interference_mm3": round(self.open_interference_mm3, 4),
                "interference_mm3": round(self.interference_mm3, 4), "limit_mm3": INTERFERENCE_LIMIT_MM3,
                "twist": self.twist, **self.keys, "ok": self.ok, "problems": self.problems()}


def _deck_manifolds(deck: PierDeck, turn_deg: float, offset) -> list:
    from cubot_cad.checks.docking import manifold_of, to_manifold

    t = tuple(float(v) for v in offset)
    ms = [manifold_of(p) for p in deck.placed(turn_deg)] + [to_manifold(s) for s in deck.screw_head_solids(turn_deg)]
    return [m.translate(t) for m in ms]


@lru_cache(maxsize=16)
def dock_deck(robot, deck: PierDeck | None = None) -> DeckDock:
    """Dock ``deck`` (default: the robot's) on ``robot``'s cover and check it (module docstring)."""
    from cubot_cad.checks.docking import (
        GAP_RESOLUTION_MM,
        _contact_boundary,
        _near_union,
        intersection_volume,
        manifold_of,
        to_manifold,
        union,
    )
    from cubot_cad.piers.deck import HOLD_MM3, LIFT_MM, cover_top_mm, screw_head_solids

    deck = default_deck(robot) if deck is None else deck.check_fits(robot)
    if deck is None:
        raise InputError(f"the {getattr(robot, 'name', robot)!r} has no top-down coupling: no deck docks on it")
    s = deck.spec
    top = cover_top_mm(robot)
    heads = [to_manifold(h) for h in screw_head_solids(robot)]
    open_robot = [manifold_of(p) for p in robot.build_placed(with_locking_key=False)] + heads
    closed_placed = robot.build_placed(with_locking_key=True)
    closed_robot = [manifold_of(p) for p in closed_placed] + heads
    # approach: the open deck (turned by twist_deg: key aligned) lowered along -z onto the cover
    nominal = np.array([0.0, robot.y_centre_mm, top])
    up = np.array([0.0, 0.0, 1.0])
    moving = _deck_manifolds(deck, s.twist_deg, nominal)
    fa, mb = _near_union(open_robot, moving, [up * 40.0, up * -2.0])
    t = _contact_boundary(fa, mb, up, 40.0, -2.0)
    open_int = intersection_volume(fa, mb.translate(tuple(up * t)))
    t = 0.0 if abs(t) < GAP_RESOLUTION_MM else float(t)
    offset = tuple(float(v) for v in nominal + up * t)

    def against(fixed, turn, at):
        a, b = _near_union(fixed, _deck_manifolds(deck, turn, at), [np.zeros(3)])
        return 0.0 if a is None else intersection_volume(a, b)

    steps = [s.twist_deg * (1 - i / TWIST_STEPS) for i in range(TWIST_STEPS + 1)]
    twist = [{"turn_deg": round(a, 3), "interference_mm3": round(against(open_robot, a, offset), 4)} for a in steps]
    closed = against(closed_robot, 0.0, offset)
    # the key: held by the roof when lifted square, free when open; the locking key stops it turning back
    cover = union(manifold_of(p) for p in closed_placed if p.role == "cover")
    lock = union(manifold_of(p) for p in closed_placed if p.role == "locking_key")
    play = s.roof_under_mm - (s.head_z0_mm + s.head_mm)
    lift = play + LIFT_MM
    lifted = tuple(np.asarray(offset) + up * lift)

    def key_at(turn, at):
        key = deck.placed(turn)[1]
        return manifold_of(key).translate(tuple(float(v) for v in at))

    held = intersection_volume(cover, key_at(0.0, lifted))
    free = intersection_volume(cover, key_at(s.twist_deg, lifted))
    back = intersection_volume(lock, key_at(s.twist_deg, offset))
    keys = {"pull_out_play_mm": round(play, 3), "lift_mm": round(lift, 3),
            "turned_key_lifted_into_roof_mm3": round(held, 3), "aligned_key_lifted_into_roof_mm3": round(free, 4),
            "aligned_key_into_locking_key_mm3": round(back, 3),
            "key_holds": held > HOLD_MM3 and free <= HOLD_MM3, "key_locked": back > HOLD_MM3}
    # the running deck, measured on the placed solid
    from cubot_cad.shapes import location

    z_top = top_face_z_mm(deck.solid.moved(location(offset)))
    return DeckDock(deck, offset, top, t + deck.stand_mm, deck.stand_mm, open_int, closed, twist, keys,
                    z_top - top, z_top)


def deck_height_numbers(robot, docked: DeckDock | None = None) -> dict:
    """``deck_height`` (top cover to the running deck, mm) with where it comes from: measured on
    the docked deck (``docked``), or as designed (key stance + plate) for an export without docking."""
    deck = default_deck(robot) if docked is None else docked.deck
    if docked is not None:
        return {"value_mm": float(docked.deck_height_mm),
                "source": (f"cubot_cad docking: the {deck.name} docked on the cover (lowered open until its ring "
                           f"stands on the cover, key through the collar, turned square; key-mount face "
                           f"{docked.stand_mm:.3f} mm above the cover, clearance {deck.clearance_mm:g} mm): cover "
                           f"top to the running deck (the placed deck's largest upward face)")}
    return {"value_mm": float(deck.height_mm),
            "source": (f"cubot_cad design (export without docking): the {deck.name}'s key stance "
                       f"{deck.stand_mm:g} mm (the coupling's) + its {deck.plate_mm:g} mm plate")}


#: How far beyond its pull-out play the upper robot is lifted to see whether the key holds (mm).
LIFT_MM = 0.5


#: A lifted turned key must overlap the collar roof by more than this to hold (mm^3).
HOLD_MM3 = 1.0


def cover_top_mm(robot) -> float:
    """Top face of the cover plate above the robot's underside (mm): the largest upward-facing
    planar face of the placed cover."""
    cover = next(p for p in robot.placed if p.role == "cover")
    best = None
    for f in cover.shape.Faces():
        if f.geomType() != "PLANE" or f.normalAt().z < 1 - 1e-9:
            continue
        if best is None or f.Area() > best.Area():
            best = f
    if best is None:
        raise RuntimeError("the cover has no upward planar face")
    return float(best.Center().z)


def screw_head_solids(robot) -> list:
    """Stand-ins of the cover screws' socket heads (ISO 4762, from the fastener table) on the
    cover plate, robot frame: the bought parts above the running surface."""
    from cubot_cad.hardware.fasteners import thread
    from cubot_cad.shapes import Z, cyl

    t = thread(robot.top_spec.screw_size)
    z = cover_top_mm(robot)
    return [cyl(t.shcs_head_diameter_mm / 2, t.shcs_head_height_mm, (x, y, z), Z)
            for x, y in robot.body.cover_screw_points()]
