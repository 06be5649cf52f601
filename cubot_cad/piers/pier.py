"""Piers of failed CuBots (issue 16): a column of robots stacked with the top-down coupling.

A pier is ``k`` CuBots (1..:data:`MAX_ROBOTS`) stacked on the void floor through the
``cubot-top-down`` coupling of :mod:`cubot_cad.checks.docking`: robot *i + 1* stands on robot *i*'s
cover on its wheels and casters, its cross key down through the collar and turned, the locking
key in *i*'s cross hole. The lowest robot stands on its wheels and casters on the floor. The
bridge line rests on, and rolls over, the top of the pier, meant to be level with the ledge. A bare
cover plate cannot be rolled over (the collar and the cover screws' heads stand in the line robot's
track: ``PierColumn(..., deck=False)`` shows it), so the top robot wears a printed
:class:`~cubot_cad.piers.deck.PierDeck` (default ``deck=True``), docked on its cover through the same
coupling: the deck's top is the running surface.

Placement is the coupling's own: robot *i* sits at *i* times the measured docked offset of the
``cubot-top-down`` pair (:func:`~cubot_cad.checks.docking.dock_robot`), so the stack pitch is whatever
the wheels, the cover and the key make it; nothing is re-derived here.

Frame: the lowest robot's frame (mm; x forward, y left, z up, origin at the centre of its
footprint on its underside); the floor is at ``z = -floor_depth_mm``.

Numbers (all measured on the CAD):

* ``floor_depth_mm``: how far the robot stands below its underside: the lower of the wheels'
  exposed height (:attr:`~cubot_cad.robots.base.Robot.wheel_exposed_mm`, on the wheel solids) and the
  caster balls' (the seats' underside less :attr:`~cubot_cad.robots.base.Robot.caster_exposed_mm`);
  ``level_mm`` is how far apart the two are (0: the robot stands level on all four);
* ``cover_top_mm``: the cover plate's top face above the underside (the largest upward planar
  face of the placed cover, outside the collar);
* ``standing_height_mm`` = floor depth + cover top: floor to the running surface of one robot;
* ``stack_pitch_mm``: z of the coupling's docked offset, running surface to running surface;
* ``top_height_mm(k)`` = standing + (k - 1) x pitch: floor to the top robot's cover;
* ``deck_height_mm``: the top cover to the running deck, measured on the deck docked on the top
  robot (:func:`~cubot_cad.piers.deck.dock_deck`); ``running_surface_mm(k)`` = ``top_height_mm(k)`` +
  ``deck_height_mm`` (the cover itself without a deck).

Checks (:meth:`PierColumn.checks`):

* ``interference``: every pair of robots in the column, printed parts and the bought parts'
  stand-ins (wheels, casters, boards, the twist drive's servo, horn, screws and nuts), in their column states, by manifold3d as
  :mod:`cubot_cad.checks.docking` measures pairs: <= :data:`~cubot_cad.checks.docking.INTERFERENCE_LIMIT_MM3`;
* ``docking``: the ``cubot-top-down`` pair passes the docking check (interference and designed
  gap) and, at every interface, the key engages: the upper robot's turned key, lifted
  :data:`LIFT_MM` beyond its pull-out play, runs into the lower collar's roof (> :data:`HOLD_MM3`),
  while the same key aligned lifts out free (<= :data:`HOLD_MM3`: that is how it went in), and the
  aligned key at the docked pose runs into the lower robot's locking key (it cannot turn back);
* ``deck`` (with a deck, under ``docking``): the deck docks on the top robot's collar
  (:class:`~cubot_cad.piers.deck.DeckDock`: it stands on its ring at the coupling's stance, turns from
  open to square touching nothing, does not interfere with the locking key in, its key holds
  and is locked);
* ``running_surface``: a robot of the line rolling along x on its wheels over the pier top: the
  deck's top or, without a deck, the top cover. The protrusions are the top robot's parts
  (the locking key only with a deck: otherwise nothing docks on it), the cover screws' socket
  heads (stand-ins from :mod:`cubot_cad.hardware.fasteners`) and the deck with its key and screw heads,
  whatever reaches above the running surface. The line robot (key aligned, wheels on the
  running surface) sweeps, over a full pass along x, exactly the extrusion along x of its
  projection on the (y, z) plane, so a protrusion is in its way iff the (y, z) projections
  overlap (area > :data:`TOUCH_AREA_MM2`). Its ground clearance is the height above the running
  surface of its lowest part that is not a wheel or a caster ball. The check passes when no
  protrusion in its way is higher than that (``clearance_margin_mm``: the clearance less the
  highest protrusion in its way, 0 when none), its wheels run on the surface, and, with a deck,
  the deck's end chamfers (measured on the solid) are no steeper than the robot climbs
  (:func:`~cubot_cad.piers.deck.climb_limit_deg`) and no deeper than its ground clearance
  (``arrival_margin_mm``: a robot arriving that low meets the deck's end with its wheels and
  caster balls only);
* ``stability``: the column's CoM over its support polygon (convex hull of the lowest robot's
  floor contacts: the wheels' tread lines and the caster balls' points). Leaning the column (or
  the floor) by ``lean_deg`` in the worst direction moves the CoM's projection by
  ``h tan(lean)`` (h: CoM height above the floor), so the margin is the CoM's distance to the
  nearest polygon edge less ``h tan(lean)``; it tips at ``atan(distance / h)``. The interfaces are
  locked by the turned keys and stand on the same polygon with less above them, so the floor
  contact governs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from cubot_cad.errors import InputError
from cubot_cad.piers.deck import HOLD_MM3, LIFT_MM, cover_top_mm, screw_head_solids
from cubot_cad.shapes import convex_hull

PIER_PAIR = "cubot-top-down"
MIN_ROBOTS = 1
MAX_ROBOTS = 8
#: Lean of the column (or slope of the void floor) the stability margin is given for by default.
DEFAULT_LEAN_DEG = 5.0
MAX_LEAN_DEG = 45.0
#: A ground-contact solid within this of the lowest one stands on the floor (mm).
CONTACT_TOL_MM = 0.05
#: (y, z) projections that overlap by less than this only touch (mm^2): a wheel on the cover
#: plate, the meshes' float32 rounding.
TOUCH_AREA_MM2 = 0.05
#: Parts reaching less than this above the running surface are not protrusions (mm).
PROTRUSION_TOL_MM = 0.01
FLOOR_THICKNESS_MM = 5.0
FLOOR_COLOUR = (0.42, 0.36, 0.28)
#: Roles of the bought parts that stand on the ground.
CONTACT_ROLES = ("wheel", "caster")


def check_robots(k, what: str = "PierColumn.robots") -> int:
    """A pier's robot count: an integer in MIN_ROBOTS..MAX_ROBOTS; InputError (one line) otherwise."""
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not MIN_ROBOTS <= int(k) <= MAX_ROBOTS:
        raise InputError(f"{what} {k!r} is not a number of robots in {MIN_ROBOTS}..{MAX_ROBOTS} "
                         f"(a pier is 1 to {MAX_ROBOTS} CuBots stacked top-down)")
    return int(k)


def check_lean(lean_deg, what: str = "lean_deg") -> float:
    if isinstance(lean_deg, bool) or not isinstance(lean_deg, (int, float)) or not math.isfinite(lean_deg) \
            or not 0 <= lean_deg < MAX_LEAN_DEG:
        raise InputError(f"{what} {lean_deg!r} is not a lean angle in [0, {MAX_LEAN_DEG:g}) degrees")
    return float(lean_deg)


def _check_robot(robot) -> None:
    from cubot_cad.checks.docking import ROBOT_OF_PAIR

    name = getattr(robot, "name", type(robot).__name__)
    if name != ROBOT_OF_PAIR[PIER_PAIR]:
        raise InputError(f"a pier stacks robots through the {PIER_PAIR} coupling; the {name} has none "
                         "(only the cubot)")


def top_down_pair(robot):
    """The measured ``cubot-top-down`` pair of ``robot`` (docking's own cache: docked once per
    distinct robot, shared with every other caller of :func:`~cubot_cad.checks.docking.dock`)."""
    from cubot_cad.checks.docking import dock_of

    _check_robot(robot)
    return dock_of(robot, PIER_PAIR)


# -- measurements on one robot ------------------------------------------------------------------


def _contact_solids(robot):
    """(component, position, solid) of every wheel and caster ball."""
    out = []
    for comp in robot.components():
        if comp.role in CONTACT_ROLES:
            for pos, s in zip(comp.positions_mm, comp.solids(), strict=True):
                out.append((comp, pos, s))
    return out


def floor_depths_mm(robot) -> dict[str, float]:
    """How far below the underside the wheels and the caster balls reach (mm), from the CAD's
    exposed heights: wheels = ``wheel_exposed_mm``; casters = the seats' underside less
    ``caster_exposed_mm``."""
    seats = [p.shape for p in robot.placed if p.role == "caster_seat"]
    out = {"wheels": float(robot.wheel_exposed_mm)}
    if seats:
        from cubot_cad.shapes import tight_bbox

        seat_bottom = min(tight_bbox(s)[2] for s in seats)
        out["casters"] = float(robot.caster_exposed_mm - seat_bottom)
    return out


def support_polygon_mm(robot, floor_z_mm: float) -> list[tuple[float, float]]:
    """Convex hull (counter-clockwise, mm, robot frame) of the robot's floor contacts: the tread
    line of each wheel (across its width) and the point under each caster ball, for every
    contact solid whose lowest point is within CONTACT_TOL_MM of the floor."""
    from cubot_cad.shapes import tight_bbox

    pts = []
    for comp, (x, y, _z), s in _contact_solids(robot):
        if tight_bbox(s)[2] > floor_z_mm + CONTACT_TOL_MM:
            continue  # does not reach the floor
        if comp.kind == "cyl_y":
            w = comp.size_mm[1]
            pts += [(x, y - w / 2), (x, y + w / 2)]
        else:
            pts.append((x, y))
    return convex_hull(pts)


def inner_distance_mm(polygon, point) -> float:
    """Signed distance of ``point`` to the nearest edge of a CCW convex ``polygon`` (> 0 inside)."""
    if len(polygon) < 3:
        return -math.inf
    px, py = point
    d = math.inf
    for (x0, y0), (x1, y1) in zip(polygon, polygon[1:] + polygon[:1], strict=True):
        ex, ey = x1 - x0, y1 - y0
        n = math.hypot(ex, ey)
        d = min(d, (ex * (py - y0) - ey * (px - x0)) / n)  # left of the edge = inside
    return d


def stack_numbers(robot, pair=None, deck_dock=None) -> dict:
    """Standing height, stack pitch and deck height of ``robot`` (mm) with where each comes from.

    ``pair``: the measured ``cubot-top-down`` pair (its docked offset gives the pitch, and the
    deck is docked too: ``deck_dock``, or docked here); None: the pitch and the deck height are
    the designed ones (cover top + the coupling's designed gap; the deck's stance + plate), for an
    export run without docking."""
    from cubot_cad.checks.docking import design_gap_mm
    from cubot_cad.piers.deck import deck_height_numbers, dock_deck

    _check_robot(robot)
    depths = floor_depths_mm(robot)
    depth = max(depths.values())
    top = cover_top_mm(robot)
    parts = " and ".join(f"{k} {v:.3f} mm" for k, v in depths.items())
    standing = {"value_mm": depth + top,
                "source": (f"cubot_cad CAD (clearance {robot.clearance_mm:g} mm): floor to the cover plate's top "
                           f"face of one robot on its wheels and casters = lowest ground contact below the "
                           f"underside ({parts}, measured on the wheel, caster-ball and seat solids) + cover "
                           f"top {top:.3f} mm above the underside (the cover's largest upward face)")}
    if pair is not None:
        if pair.name != PIER_PAIR:
            raise InputError(f"stack pitch needs the {PIER_PAIR} pair, got {pair.name}")
        pitch = {"value_mm": float(pair.offset_mm[2]),
                 "source": (f"cubot_cad docking: z of the measured {PIER_PAIR} docked offset (the upper robot "
                            f"lowered onto the cover until its wheels touch, key through the collar; gap "
                            f"{pair.gap_mm:.3f} mm, clearance {pair.clearance_mm:g} mm): cover top to cover top")}
    else:
        gap = float(design_gap_mm(robot, PIER_PAIR))
        pitch = {"value_mm": top + gap,
                 "source": (f"cubot_cad design (export without docking): cover top {top:.3f} mm + the "
                            f"{PIER_PAIR} coupling's designed gap {gap:.3f} mm (the wheels' exposed height)")}
    docked = deck_dock if deck_dock is not None else (dock_deck(robot) if pair is not None else None)
    if docked is not None and not docked.ok:  # as a failing docked pair: no measured number from it
        raise InputError(f"--clearance-mm {robot.clearance_mm:g}: the {docked.deck.name} fails to dock on the "
                         f"{robot.name} ({'; '.join(docked.problems())}); nothing written")
    return {"standing_height": standing, "stack_pitch": pitch, "deck_height": deck_height_numbers(robot, docked)}


def record_fields(robot, pair=None, deck_dock=None) -> dict:
    """The :class:`~cubot_cad.properties.RobotProperties` fields of a stackable robot (SI)."""
    n = stack_numbers(robot, pair, deck_dock)
    return {f"{k}_{u}": (v["value_mm"] / 1000 if u == "m" else v["source"])
            for k, v in n.items() for u in ("m", "source")}


def stack_fields(robot, pairs=None) -> dict:
    """:func:`record_fields` of ``robot`` when it stacks (has the top-down coupling), measured with
    its ``cubot-top-down`` pair when ``pairs`` holds it (designed otherwise); {} for the others."""
    from cubot_cad.checks.docking import ROBOT_OF_PAIR

    if getattr(robot, "name", None) != ROBOT_OF_PAIR[PIER_PAIR]:
        return {}
    return record_fields(robot, next((p for p in pairs or [] if p.name == PIER_PAIR), None))


def add_record_fields(path, fields_by_robot: dict[str, dict]):
    """Rewrite the properties file at ``path`` (atomically) with ``fields_by_robot`` (robot name
    -> :func:`record_fields`) set on those robots' records; returns the new file."""
    from dataclasses import replace

    from cubot_cad.properties import RobotPropertiesFile

    pf = RobotPropertiesFile.load(path)
    robots = tuple(replace(r, **fields_by_robot[r.name]) if r.name in fields_by_robot else r for r in pf.robots)
    new = replace(pf, robots=robots)
    new.save(path)
    return new


# -- manifold helpers ---------------------------------------------------------------------------

#: (x, y, z) -> (y, z, x): a proper rotation, so that project() (onto xy) gives the (y, z) projection.
_YZ = np.array([[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 0.0, 0.0]])


def _yz_projection(m):
    return m.transform(_YZ).project()


@dataclass(frozen=True)
class _Item:
    """One solid of a robot in the column: a label, its role and its manifold (robot frame)."""

    label: str
    role: str
    manifold: object = field(repr=False)
    contact: bool = False


def _robot_items(robot, key_turned: bool, with_locking_key: bool, extra=()) -> list[_Item]:
    from cubot_cad.checks.docking import manifold_of, to_manifold

    placed = robot.build_placed(key_turned=key_turned, with_locking_key=with_locking_key)
    items = [_Item(p.part.name, p.role, manifold_of(p)) for p in placed]
    items += [_Item(comp.key, comp.role, to_manifold(s), comp.role in CONTACT_ROLES)
              for comp in robot.components() for s in comp.solids()]
    items += [_Item(h.label, h.role, to_manifold(h.shape)) for h in robot.hardware(placed)]
    items += [_Item(label, role, to_manifold(s)) for label, role, s in extra]
    return items


def _shifted(items, offset):
    t = tuple(float(v) for v in offset)
    return [m.manifold.translate(t) for m in items]


# -- the column ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class PierColumn:
    """``robots`` CuBots stacked top-down (see the module docstring). Lengths mm, masses kg."""

    robot: object
    robots: int = 2
    #: A measured ``cubot-top-down`` pair of this robot to stack with (None: docked here, once
    #: per distinct robot); given, it must be that coupling's, at the robot's clearance.
    docked: object = field(default=None, compare=False, repr=False)
    #: The running deck on the top robot: True (the robot's default
    #: :class:`~cubot_cad.piers.deck.PierDeck`), a PierDeck, or False (the bare top cover).
    deck: object = True

    def __post_init__(self) -> None:
        _check_robot(self.robot)
        check_robots(self.robots)
        d = self.docked
        if d is not None and (getattr(d, "name", None) != PIER_PAIR
                              or getattr(d, "clearance_mm", None) != self.robot.clearance_mm):
            raise InputError(f"PierColumn.docked must be the {PIER_PAIR} pair at clearance "
                             f"{self.robot.clearance_mm:g} mm, got {getattr(d, 'name', d)!r}")
        from cubot_cad.piers.deck import PierDeck

        if isinstance(self.deck, PierDeck):
            self.deck.check_fits(self.robot)
        elif not isinstance(self.deck, bool):
            raise InputError(f"PierColumn.deck must be True, False or a PierDeck, got {self.deck!r}")

    # -- the deck ---------------------------------------------------------------------------
    @cached_property
    def deck_part(self):
        """The :class:`~cubot_cad.piers.deck.PierDeck` on the top robot (None: a bare top cover)."""
        from cubot_cad.piers.deck import default_deck

        if self.deck is False:
            return None
        return default_deck(self.robot) if self.deck is True else self.deck

    @cached_property
    def deck_dock(self):
        """The deck docked on the top robot's cover (:class:`~cubot_cad.piers.deck.DeckDock`), or None."""
        from cubot_cad.piers.deck import dock_deck

        return None if self.deck_part is None else dock_deck(self.robot, self.deck_part)

    @property
    def deck_offset_mm(self) -> tuple[float, float, float] | None:
        """Where the deck frame sits in the column frame (None without a deck)."""
        if self.deck_dock is None:
            return None
        return tuple(float(a + b) for a, b in zip(self.offsets_mm[-1], self.deck_dock.offset_mm, strict=True))

    @property
    def deck_height_mm(self) -> float | None:
        """Top cover to the running deck (measured on the docked deck); None without a deck."""
        return None if self.deck_dock is None else self.deck_dock.deck_height_mm

    def running_surface_mm(self, k: int | None = None) -> float:
        """Floor to the running surface of a ``k``-robot pier (default: this one's): the deck's top,
        ``top_height_mm(k) + deck_height_mm``, or the top cover without a deck."""
        return self.top_height_mm(k) + (self.deck_height_mm or 0.0)

    def measured_running_surface_mm(self) -> float:
        """The same, measured on the placed column: the placed deck's top face (or the top cover's)
        above the floor."""
        if self.deck_dock is None:
            return self.measured_top_height_mm()
        from cubot_cad.piers.deck import top_face_z_mm
        from cubot_cad.shapes import location

        return top_face_z_mm(self.deck_part.solid.moved(location(self.deck_offset_mm))) + self.floor_depth_mm

    def _deck_items(self, offset=(0.0, 0.0, 0.0)) -> list[_Item]:
        """The deck, its key and its screw heads (deck frame, shifted by ``offset``)."""
        from cubot_cad.checks.docking import manifold_of, to_manifold

        t = tuple(float(v) for v in offset)
        d = self.deck_part
        items = [_Item(p.part.name, p.role if p.role == "deck" else "deck_key", manifold_of(p).translate(t))
                 for p in d.placed()]
        items += [_Item(f"deck_screw_head_{n + 1}", "screw_head", to_manifold(h).translate(t))
                  for n, h in enumerate(d.screw_head_solids())]
        return items

    # -- geometry ---------------------------------------------------------------------------
    @cached_property
    def pair(self):
        """The measured ``cubot-top-down`` pair the column is stacked with."""
        return self.docked if self.docked is not None else top_down_pair(self.robot)

    @cached_property
    def offset_mm(self) -> tuple[float, float, float]:
        """The coupling's docked offset: where robot i + 1 sits relative to robot i."""
        return tuple(float(v) for v in self.pair.offset_mm)

    @cached_property
    def offsets_mm(self) -> tuple[tuple[float, float, float], ...]:
        off = np.asarray(self.offset_mm)
        return tuple(tuple(float(v) for v in off * i) for i in range(self.robots))

    def state(self, i: int) -> dict[str, bool]:
        """Connector state of robot ``i`` (0 = lowest): key turned when it stands on another robot,
        locking key in its cross hole when another robot or the deck stands on it."""
        return {"key_turned": i > 0, "with_locking_key": i < self.robots - 1 or self.deck_part is not None}

    def placed(self, i: int) -> list:
        """Robot ``i``'s printed parts (:class:`~cubot_cad.robots.base.Placed`, its own frame)."""
        return self.robot.build_placed(**self.state(i))

    @cached_property
    def floor_depths_mm(self) -> dict[str, float]:
        return floor_depths_mm(self.robot)

    @property
    def floor_depth_mm(self) -> float:
        return max(self.floor_depths_mm.values())

    @property
    def level_mm(self) -> float:
        """How far the wheels' and the casters' lowest points differ (0: stands level on all)."""
        d = list(self.floor_depths_mm.values())
        return max(d) - min(d)

    @cached_property
    def cover_top_mm(self) -> float:
        return cover_top_mm(self.robot)

    @property
    def standing_height_mm(self) -> float:
        """Floor to the cover plate's top face of one robot standing on its wheels and casters."""
        return self.floor_depth_mm + self.cover_top_mm

    @property
    def stack_pitch_mm(self) -> float:
        """Cover top to cover top of two stacked robots: the coupling's docked offset (z)."""
        return self.offset_mm[2]

    def top_height_mm(self, k: int | None = None) -> float:
        """Floor to the top robot's cover of a ``k``-robot pier (default: this one's)."""
        k = self.robots if k is None else check_robots(k, "k")
        return self.standing_height_mm + (k - 1) * self.stack_pitch_mm

    def measured_top_height_mm(self) -> float:
        """The same, measured on the placed column: the top robot's placed cover plate face above
        the floor (independent of the formula)."""
        from cubot_cad.shapes import location

        top = next(p for p in self.placed(self.robots - 1) if p.role == "cover")
        shape = top.part.solid.moved(location(self.offsets_mm[-1]) * top.loc)
        z = max((f for f in shape.Faces() if f.geomType() == "PLANE" and f.normalAt().z > 1 - 1e-9),
                key=lambda f: f.Area()).Center().z
        return float(z) + self.floor_depth_mm

    @cached_property
    def _unit_mass(self):
        return self.robot.mass_properties()

    @cached_property
    def deck_mass_kg(self) -> float:
        """The printed deck and its cross key (solid, ABS as the robots' mass); 0 without a deck."""
        from cubot_cad.part import material

        return 0.0 if self.deck_part is None else self.deck_part.mass_kg(material("abs")["density_kg_m3"])

    @property
    def mass_kg(self) -> float:
        return self.robots * self._unit_mass.mass_kg + self.deck_mass_kg

    @property
    def com_mm(self) -> tuple[float, float, float]:
        """Column CoM (column frame, mm): the robots' CoMs at their offsets (identical robots; the
        key turned or not moves no mass that matters) and the deck's."""
        m = self._unit_mass.mass_kg
        c = (np.asarray(self._unit_mass.com_m) * 1000 + np.mean(np.asarray(self.offsets_mm), axis=0))
        if self.deck_part is None:
            return tuple(float(v) for v in c)
        md = self.deck_mass_kg
        cd = np.asarray(self.deck_part.assembly_com_mm()) + np.asarray(self.deck_offset_mm)
        return tuple(float(v) for v in (self.robots * m * c + md * cd) / (self.robots * m + md))

    @property
    def com_height_mm(self) -> float:
        """CoM height above the floor."""
        return self.com_mm[2] + self.floor_depth_mm

    @cached_property
    def plan_footprint_mm(self) -> tuple[float, float, float, float]:
        """(x0, y0, x1, y1) of the column seen from above (printed parts and stand-ins)."""
        x0, y0, _, x1, y1, _ = self.robot.bbox_mm(include_components=True)
        xs = [o[0] for o in self.offsets_mm]
        ys = [o[1] for o in self.offsets_mm]
        out = [x0 + min(xs), y0 + min(ys), x1 + max(xs), y1 + max(ys)]
        if self.deck_part is not None:
            b, o = self.deck_part.bbox_mm, self.deck_offset_mm
            out = [min(out[0], b[0] + o[0]), min(out[1], b[1] + o[1]), max(out[2], b[3] + o[0]),
                   max(out[3], b[4] + o[1])]
        return tuple(out)

    @cached_property
    def support_polygon_mm(self) -> list[tuple[float, float]]:
        return support_polygon_mm(self.robot, -self.floor_depth_mm)

    # -- checks -----------------------------------------------------------------------------
    @cached_property
    def _items(self) -> list[list[_Item]]:
        cache: dict = {}
        out = []
        for i in range(self.robots):
            key = tuple(self.state(i).values())
            if key not in cache:
                cache[key] = _robot_items(self.robot, **self.state(i))
            out.append(cache[key])
        return out

    @cached_property
    def interference(self) -> dict:
        """Intersection volume (mm^3) of every pair of robots in the column (and the deck, named
        ``"deck"``) whose boxes meet."""
        from cubot_cad.checks.docking import (
            INTERFERENCE_LIMIT_MM3,
            _near_union,
            intersection_volume,
        )

        rows = []
        ms = [_shifted(items, o) for items, o in zip(self._items, self.offsets_mm, strict=True)]
        names: list = list(range(1, self.robots + 1))
        if self.deck_part is not None:
            ms.append([it.manifold for it in self._deck_items(self.deck_offset_mm)])
            names.append("deck")
        for i in range(len(ms)):
            for j in range(i + 1, len(ms)):
                a, b = _near_union(ms[i], ms[j], [np.zeros(3)])
                if a is None:
                    continue
                rows.append({"robots": [names[i], names[j]], "interference_mm3": round(intersection_volume(a, b), 4)})
        worst = max((r["interference_mm3"] for r in rows), default=0.0)
        return {"pairs": rows, "max_mm3": worst, "limit_mm3": INTERFERENCE_LIMIT_MM3,
                "ok": worst <= INTERFERENCE_LIMIT_MM3}

    @cached_property
    def docking(self) -> dict:
        """The coupling's docking check and, at every interface, whether the key engages: the
        turned key, lifted LIFT_MM beyond its pull-out play, runs into the collar roof (it holds);
        the aligned key lifted as far comes out free (it went in that way); and the aligned key at
        the docked pose runs into the locking key (the key cannot turn back)."""
        from cubot_cad.checks.docking import intersection_volume, manifold_of, union

        spec = self.robot.top_spec
        play = spec.roof_under_mm - (spec.head_z0_mm + spec.head_mm)
        lift = play + LIFT_MM
        aligned = next(p for p in self.robot.build_placed(key_turned=False) if p.role == "cross_key")
        rows = []
        for i in range(self.robots - 1):
            lower = self.placed(i)
            cover = union(manifold_of(p).translate(self.offsets_mm[i]) for p in lower if p.role == "cover")
            lock = union(manifold_of(p).translate(self.offsets_mm[i]) for p in lower if p.role == "locking_key")
            key = next(p for p in self.placed(i + 1) if p.role == "cross_key")
            at = np.asarray(self.offsets_mm[i + 1])
            up = tuple(at + (0.0, 0.0, lift))
            held = intersection_volume(cover, manifold_of(key).translate(up))
            free = intersection_volume(cover, manifold_of(aligned).translate(up))
            back = intersection_volume(lock, manifold_of(aligned).translate(tuple(at)))
            rows.append({"interface": [i + 1, i + 2], "lift_mm": round(lift, 3),
                         "turned_key_lifted_into_roof_mm3": round(held, 3),
                         "aligned_key_lifted_into_roof_mm3": round(free, 4),
                         "aligned_key_into_locking_key_mm3": round(back, 3),
                         "key_holds": held > HOLD_MM3 and free <= HOLD_MM3, "key_locked": back > HOLD_MM3})
        p = self.pair
        deck = None if self.deck_dock is None else self.deck_dock.summary()
        return {"pair": p.summary(), "pair_ok": p.ok, "pair_problems": p.problems(), "interfaces": rows,
                "pull_out_play_mm": round(play, 3), "deck": deck,
                "ok": p.ok and all(r["key_holds"] and r["key_locked"] for r in rows)
                and (deck is None or deck["ok"])}

    @cached_property
    def running_surface(self) -> dict:
        """A robot of the line rolling along x over the pier top: the deck's top, or the bare top
        cover without a deck (see the module docstring)."""
        from cubot_cad.shapes import location, tight_bbox

        r = self.robot
        heads = [(f"cover_screw_head_{n + 1}", "screw_head", s) for n, s in enumerate(screw_head_solids(r))]
        top_state = self.state(self.robots - 1)
        top = _robot_items(r, **top_state, extra=heads)  # the top robot's frame
        deck = self.deck_dock
        if deck is None:
            plane = self.cover_top_mm  # running surface, top robot's frame
            cover = next(p for p in self.placed(self.robots - 1) if p.role == "cover")
            sb = tight_bbox(cover.shape)
            surface = "top cover"
        else:
            top += self._deck_items(deck.offset_mm)
            plane = deck.top_z_mm
            sb = tight_bbox(self.deck_part.solid.moved(location(deck.offset_mm)))
            surface = self.deck_part.name
        line = _robot_items(r, key_turned=False, with_locking_key=True)
        # the line robot on its wheels on the running surface
        lift = (0.0, 0.0, self.stack_pitch_mm + plane - self.cover_top_mm)

        def bottom(m):
            return m.bounding_box()[2] + lift[2] - plane

        line_proj = [(it, _yz_projection(it.manifold.translate(lift)), bottom(it.manifold)) for it in line]
        lowest, clearance = min(((it, b) for it, _, b in line_proj if not it.contact), key=lambda t: t[1])
        protrusions, below = [], []
        for it in top:
            h_top = it.manifold.bounding_box()[5] - plane
            if h_top <= PROTRUSION_TOL_MM:
                below.append((it, h_top))
            above = it.manifold.trim_by_plane((0.0, 0.0, 1.0), plane + PROTRUSION_TOL_MM)
            if above.is_empty():
                continue
            h = above.bounding_box()[5] - plane
            proj = _yz_projection(above)
            meets = []
            for b, bproj, b_bottom in line_proj:
                area = (proj ^ bproj).area()
                if area > TOUCH_AREA_MM2:
                    meets.append({"line_part": b.label, "bottom_mm": round(b_bottom, 3), "overlap_mm2": round(area, 2)})
            y0, _, y1, _ = proj.bounds()
            x0, x1 = above.bounding_box()[0], above.bounding_box()[3]
            protrusions.append({"part": it.label, "role": it.role, "height_mm": round(h, 3),
                                "x_mm": [round(x0, 2), round(x1, 2)], "y_mm": [round(y0, 2), round(y1, 2)],
                                "in_track": bool(meets), "meets": _merge_meets(meets),
                                "blocks": bool(meets) and h > clearance + PROTRUSION_TOL_MM})
        treads = [tight_bbox(s) for comp, _pos, s in _contact_solids(r) if comp.role == "wheel"]
        on_surface = all(sb[1] <= t[1] and t[4] <= sb[4] for t in treads)
        blocking = [p for p in protrusions if p["blocks"]]
        in_track = [p["height_mm"] for p in protrusions if p["in_track"]]
        out = {"surface": surface, "running_surface_mm": round(self.running_surface_mm(), 3),
               "ground_clearance_mm": round(clearance, 3), "lowest_line_part": lowest.label,
               "clearance_margin_mm": round(clearance - max(in_track, default=0.0), 3),
               "wheel_tracks_y_mm": [[round(t[1], 2), round(t[4], 2)] for t in treads],
               "surface_y_mm": [round(sb[1], 2), round(sb[4], 2)], "wheels_on_surface": on_surface,
               "protrusions": protrusions, "blocking": [p["part"] for p in blocking]}
        ok = on_surface and not blocking
        if deck is not None:
            # what the deck covers: the highest of the top robot's parts (and the heads) under it
            under = [(it, h) for it, h in below if it.role not in ("deck", "deck_key")
                     and not it.label.startswith("deck_")]
            hi, h_hi = max(under, key=lambda t: t[1])
            out["under_deck"] = {"highest_part": hi.label, "below_running_surface_mm": round(-h_hi, 3),
                                 "above_cover_mm": round(h_hi + plane - self.cover_top_mm, 3)}
            out["ends"] = ends = self._deck_ends(clearance)
            ok = ok and ends["ok"]
        out["ok"] = ok
        out["measured_as"] = ("(y, z) projections of the top robot's parts, the cover-screw heads"
                              + (" and the deck" if deck is not None else "") + " above the running surface "
                              "against those of a line robot on its wheels on it (its sweep along x); ground "
                              "clearance = its lowest part other than wheels and caster balls")
        return out

    def _deck_ends(self, clearance_mm: float) -> dict:
        """The deck's end chamfers, measured on its solid, against what the line robot climbs and
        clears: no steeper than :func:`~cubot_cad.piers.deck.climb_limit_deg`, no deeper than its ground
        clearance (a robot arriving as low as the chamfer's foot touches the deck's end with its
        wheels and caster balls only)."""
        from cubot_cad.piers.deck import PRINT_SLOPE_DEG, chamfer_faces, climb_limit_deg

        faces = chamfer_faces(self.deck_part.solid)
        lim = climb_limit_deg(self.robot)
        steep = max(f["slope_deg"] for f in faces)
        drop = max(f["drop_mm"] for f in faces)
        flat = min(f["x_mm"][0] for f in faces if f["x_mm"][0] > 0) - max(f["x_mm"][1] for f in faces
                                                                           if f["x_mm"][1] < 0)
        return {"chamfers": [{k: v for k, v in f.items() if k != "top_z_mm"} for f in faces],
                "slope_deg": round(steep, 3), "drop_mm": round(drop, 3),
                "climb_limit_deg": round(lim, 3), "print_slope_deg": PRINT_SLOPE_DEG,
                "flat_length_mm": round(flat, 3), "robot_length_mm": self.robot.length_mm,
                "arrival_margin_mm": round(clearance_mm - drop, 3),
                "ok": len(faces) == 2 and steep <= lim + 1e-6 and drop < clearance_mm
                and flat >= self.robot.length_mm - 1e-6}

    def stability(self, lean_deg: float = DEFAULT_LEAN_DEG) -> dict:
        """CoM over the support polygon, and the margin left when leaning ``lean_deg`` (worst way)."""
        lean = check_lean(lean_deg)
        poly = self.support_polygon_mm
        c = self.com_mm
        d = inner_distance_mm(poly, (c[0], c[1]))
        h = self.com_height_mm
        margin = d - h * math.tan(math.radians(lean))
        return {"lean_deg": lean, "com_height_mm": round(h, 3), "com_xy_mm": [round(c[0], 3), round(c[1], 3)],
                "com_to_edge_mm": round(d, 3), "margin_mm": round(margin, 3),
                "tipping_deg": round(math.degrees(math.atan2(d, h)), 3), "ok": margin > 0}

    def checks(self, lean_deg: float = DEFAULT_LEAN_DEG) -> dict:
        return {"interference": self.interference, "docking": self.docking,
                "running_surface": self.running_surface, "stability": self.stability(lean_deg)}

    def summary(self, lean_deg: float = DEFAULT_LEAN_DEG, checks: bool = True) -> dict:
        """The column's numbers (mm, kg) and, with ``checks``, every check."""
        out = {
            "robot": self.robot.name, "robots": self.robots, "clearance_mm": self.robot.clearance_mm,
            "coupling": PIER_PAIR, "offset_mm": [round(v, 4) for v in self.offset_mm],
            "floor_depth_mm": {k: round(v, 4) for k, v in self.floor_depths_mm.items()},
            "level_mm": round(self.level_mm, 4), "cover_top_mm": round(self.cover_top_mm, 4),
            "standing_height_mm": round(self.standing_height_mm, 4),
            "stack_pitch_mm": round(self.stack_pitch_mm, 4),
            "top_height_mm": round(self.top_height_mm(), 4),
            "heights_mm": {str(k): round(self.top_height_mm(k), 4) for k in range(1, self.robots + 1)},
            "deck": None if self.deck_part is None else self.deck_part.name,
            "deck_height_mm": None if self.deck_height_mm is None else round(self.deck_height_mm, 4),
            "running_surface_mm": round(self.running_surface_mm(), 4),
            "running_surface_heights_mm": {str(k): round(self.running_surface_mm(k), 4)
                                           for k in range(1, self.robots + 1)},
            "mass_kg": round(self.mass_kg, 5), "com_mm": [round(v, 3) for v in self.com_mm],
            "com_height_mm": round(self.com_height_mm, 3),
            "footprint": {"plan_mm": [round(v, 3) for v in self.plan_footprint_mm],
                          "support_polygon_mm": [[round(x, 3), round(y, 3)] for x, y in self.support_polygon_mm]},
        }
        if checks:
            ch = self.checks(lean_deg)
            out["checks"] = ch
            out["ok"] = all(v["ok"] for v in ch.values())
        return out

    # -- models -----------------------------------------------------------------------------
    def assembly(self, fresh: bool = False, floor: bool = True):
        """cq.Assembly of the column (robots in their column states, bought parts as stand-ins)
        on a floor slab; ``fresh`` as in :meth:`~cubot_cad.robots.base.Robot.assembly` (for a GLB)."""
        import cadquery as cq

        from cubot_cad.shapes import box

        assy = cq.Assembly(name=f"pier-{self.robot.name}-{self.robots}")
        units: dict = {}
        for i, o in enumerate(self.offsets_mm):
            key = tuple(self.state(i).values())
            if key not in units:
                units[key] = self.robot.assembly(placed=self.placed(i), fresh=fresh, name=self.robot.name)
            assy.add(units[key], name=f"{self.robot.name}_{i + 1}", loc=cq.Location(cq.Vector(*o)))
        if self.deck_part is not None:
            from cubot_cad.piers.deck import DECK_COLOUR
            from cubot_cad.robots.base import role_colour

            deck = cq.Assembly(name=self.deck_part.name)
            for p in self.deck_part.placed():
                solid = p.part.solid.copy(False) if fresh else p.part.solid
                colour = DECK_COLOUR if p.role == "deck" else role_colour(p.role)
                deck.add(solid, name=f"{p.part.name}_1", loc=p.loc, color=cq.Color(*colour))
            for n, h in enumerate(self.deck_part.screw_head_solids()):
                deck.add(h, name=f"deck_screw_head_{n + 1}", color=cq.Color(0.6, 0.6, 0.6))
            assy.add(deck, name=self.deck_part.name, loc=cq.Location(cq.Vector(*self.deck_offset_mm)))
        if floor:
            x0, y0, x1, y1 = self.plan_footprint_mm
            z = -self.floor_depth_mm
            assy.add(box(x0 - 20, x1 + 20, y0 - 20, y1 + 20, z - FLOOR_THICKNESS_MM, z), name="void_floor",
                     color=cq.Color(*FLOOR_COLOUR))
        return assy


def _merge_meets(meets: list[dict]) -> list[dict]:
    """One row per line part (its instances merged, overlap areas summed)."""
    out: dict[str, dict] = {}
    for m in meets:
        row = out.setdefault(m["line_part"], {"line_part": m["line_part"], "bottom_mm": m["bottom_mm"],
                                               "overlap_mm2": 0.0})
        row["bottom_mm"] = min(row["bottom_mm"], m["bottom_mm"])
        row["overlap_mm2"] = round(row["overlap_mm2"] + m["overlap_mm2"], 2)
    return list(out.values())
