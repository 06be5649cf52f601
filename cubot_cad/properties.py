"""`RobotProperties`: the record `cubot_cad` hands to `structure_fem`.

SI units throughout (metres, kilograms, newtons, radians, pascals), because
the consumer is the mechanics model; `cubot_cad` converts from its
millimetre CAD when it writes the record.

Axes of a robot: x forward (front connector side), y left, z up; the origin is
the centre of the robot's footprint on its underside.

A file (``robot_properties.json``) holds a :class:`RobotPropertiesFile`, one
:class:`RobotProperties` per robot model. :func:`default_properties` returns
the packaged defaults so `structure_fem` runs when `cubot_cad` has not.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path

from .errors import InputError, require
from .jsonrecord import check_schema, from_dict, read_json, to_jsonable, write_json_atomic

SCHEMA_VERSION = 1

#: Connector kinds. ``front_rear``: grooved pins (front) into engagement
#: latches (rear); ``side_rail``: left/right sliding rail; ``top_twist``:
#: cross key / cross hole twist-and-lock; ``ring_capture``: OctBot ring and
#: three-finger capturer; ``bolt``: the test platform's nut and bolt.
CONNECTOR_KINDS = ("front_rear", "side_rail", "top_twist", "ring_capture", "bolt")


def _finite(x: float) -> bool:
    return isinstance(x, (int, float)) and math.isfinite(x)


#: Axes of a feature's play in the joint's planar frame: ``x`` along the structure (for a
#: front-rear coupling: along the pins), ``z`` vertical.
PLAY_AXES = ("x", "z")
#: ``both``: free by ``play_m`` either way from the docked position (a pin centred in its
#: hole); ``tension``: free by ``play_m`` only when the coupling opens (+x: the robots pull
#: apart; +z: the upper robot lifts off), in the other sense the faces already touch
#: (compression-only contact without a gap).
PLAY_SENSES = ("both", "tension")
#: Provenance of a record written before connectors carried one.
LEGACY_PROVENANCE = "hand formula (legacy record)"
#: Allowed provenance prefixes: a documented hand formula, a finite-element result, a user's
#: measurement (followed by ``: <what>``), or the legacy marker above.
PROVENANCE_PREFIXES = ("hand formula", "fe:", "measured:")


@dataclass(frozen=True)
class FeaturePlay:
    """Kinematic play of one feature of a coupling, from the CAD's clearances (SI).

    ``feature``: short name (``tension``, ``vertical_slip``, ``key_slip``, ...); ``axis`` and
    ``sense`` (:data:`PLAY_AXES`, :data:`PLAY_SENSES`) say where it acts; ``play_m``: the free
    travel before the feature bears (per side for ``both``); ``cad_feature``: which clearances
    of the CAD it is the sum of.
    """

    feature: str
    axis: str
    sense: str
    play_m: float
    cad_feature: str

    def __post_init__(self) -> None:
        require(bool(self.feature), "feature play needs a feature name")
        require(self.axis in PLAY_AXES, f"play {self.feature!r}: axis {self.axis!r} is not one of {PLAY_AXES}")
        require(self.sense in PLAY_SENSES,
                f"play {self.feature!r}: sense {self.sense!r} is not one of {PLAY_SENSES}")
        require(_finite(self.play_m) and 0 <= self.play_m < 0.01,
                f"play {self.feature!r}: play_m must be in [0, 0.01) m, got {self.play_m!r}")
        require(bool(self.cad_feature), f"play {self.feature!r}: name the CAD feature it comes from")


#: What touches the ground under a robot: a drive wheel's tyre or a caster's ball.
GROUND_CONTACT_FEATURES = ("wheel", "caster")
#: Contacts whose lowest point is within this of the robot's lowest one touch a flat ledge (m);
#: a higher one (a caster set up off the ground) does not carry load on the flat.
GROUND_TOUCH_TOLERANCE_M = 1e-4


@dataclass(frozen=True)
class GroundContact:
    """Where a robot touches a flat ground, in the planar (x-z) view (SI, robot frame).

    ``x_m``: along the robot, from the centre of its footprint (+x forward: the front face is at
    ``length_m / 2``, the rear face at ``-length_m / 2``); ``z_m``: the contact's lowest point
    below the underside (``-wheel_exposed_height_m`` for a wheel on a level robot); ``count``:
    how many wheels / casters stand side by side at that ``x`` (the planar model merges them).
    """

    feature: str
    x_m: float
    z_m: float
    count: int = 1

    def __post_init__(self) -> None:
        require(self.feature in GROUND_CONTACT_FEATURES,
                f"ground contact feature {self.feature!r} is not one of {', '.join(GROUND_CONTACT_FEATURES)}")
        require(_finite(self.x_m) and abs(self.x_m) < 1, f"ground contact x_m must be a finite length, got {self.x_m!r}")
        require(_finite(self.z_m) and -0.2 < self.z_m <= 1e-9,
                f"ground contact z_m must be at or below the underside (<= 0, > -0.2 m), got {self.z_m!r}")
        require(isinstance(self.count, int) and not isinstance(self.count, bool) and self.count >= 1,
                f"ground contact count must be an integer >= 1, got {self.count!r}")


def ground_contacts_from_components(components, length_mm: float) -> tuple[GroundContact, ...]:
    """The ground contacts of a robot from its component table (:class:`cubot_cad.hardware.components.Component`,
    robot frame, mm): every ``wheel`` (``cyl_y``: its lowest point is the axle height minus the
    radius, at the axle's x) and ``caster`` (``sphere``: the ball's centre minus its radius; a
    ``cyl_z`` or ``box`` stand-in: its centre minus half its height), those
    reaching the lowest plane (within :data:`GROUND_TOUCH_TOLERANCE_M`), merged per (feature, x)
    across the robot's width. Needs no CAD kernel (the table is plain numbers)."""
    pts: dict[tuple[str, float], list[float]] = {}
    for c in components:
        if c.role not in GROUND_CONTACT_FEATURES:
            continue
        # half its height below its centre: cyl_y / sphere: the diameter; cyl_z: the length; box: z size
        half = {"cyl_z": float(c.size_mm[1]) if len(c.size_mm) > 1 else float(c.size_mm[0]),
                "box": float(c.size_mm[2]) if len(c.size_mm) > 2 else float(c.size_mm[0])}.get(
                    c.kind, float(c.size_mm[0])) / 2
        for x, _y, z in c.positions_mm:
            key = (c.role, round(float(x), 6))
            pts.setdefault(key, []).append(float(z) - half)
    if not pts:
        return ()
    low = min(z for zs in pts.values() for z in zs)
    out = []
    for (feature, x), zs in sorted(pts.items(), key=lambda kv: kv[0][1]):
        touching = [z for z in zs if z - low <= GROUND_TOUCH_TOLERANCE_M * 1e3]
        if touching:
            require(abs(x) <= length_mm / 2 + 1e-9, f"{feature} at x = {x:g} mm is outside the robot's "
                    f"{length_mm:g} mm length")
            out.append(GroundContact(feature, x / 1e3, min(touching) / 1e3, len(touching)))
    return tuple(out)


def ground_contact_fields(robot) -> dict:
    """``{"ground_contacts": ..., "ground_contacts_source": ...}`` for a parametric
    :class:`cubot_cad.robots.base.Robot` (empty when it has no wheels or casters: it lies on its
    underside, e.g. the test platform), to ``dataclasses.replace`` into its
    :class:`RobotProperties` when the record is written."""
    L = robot.envelope_mm[0]
    contacts = ground_contacts_from_components(robot.components(), L)
    if not contacts:
        return {}
    what = ", ".join(f"{c.count} {c.feature}{'s' if c.count > 1 else ''} at x = {c.x_m * 1e3:g} mm "
                     f"({(L / 2e3 - c.x_m) * 1e3:g} mm behind the front face)" for c in contacts)
    src = (f"cubot_cad {type(robot).__name__} component table (wheel: axle x, axle z - radius; caster: ball "
           f"centre x, centre z - radius; robot frame, {L:g} mm long): {what}")
    return {"ground_contacts": contacts, "ground_contacts_source": src}


@dataclass(frozen=True)
class ConnectorProperties:
    """Compliance of one docked coupling, lumped at the coupling point.

    ``rotational_stiffness_nm_per_rad`` is the bending (pitch) stiffness of the
    joint about the horizontal axis across the coupling; ``backlash_rad`` the
    free pitch play before it carries load (for a front-rear coupling: its
    ``tension`` play over the lever arm of the highest pin about the hinge);
    ``gap_m`` the face-to-face gap when docked; ``height_m`` the height
    of the coupling's load point above the robot's underside.

    ``play``: the translational play per feature (:class:`FeaturePlay`), each
    from the CAD's clearances; empty in records written before it existed (then
    the couplings have no translational play). ``provenance``: where the
    stiffness values come from, ``"hand formula: <which>"``, ``"fe: <mesh,
    element, solver, cache key>"`` or ``"measured: <file>"``.
    """

    kind: str
    rotational_stiffness_nm_per_rad: float
    axial_stiffness_n_per_m: float
    backlash_rad: float = 0.0
    gap_m: float = 0.0
    height_m: float = 0.0
    play: tuple[FeaturePlay, ...] = ()
    provenance: str = LEGACY_PROVENANCE
    #: Vertical (shear) stiffness after the play, N/m, when known apart from the axial one
    #: (an FE result); None: the model uses the axial stiffness in both directions.
    shear_stiffness_n_per_m: float | None = None
    #: Lever arm (m) of every tension member (pin) about the joint's hinge, from the CAD (one per
    #: pin; the underside edge of the touching faces for a zero docked gap): where the model's
    #: emergent hinge (:mod:`structure_fem.model.hinge`) puts its tension rows. Empty: not known (records
    #: written before it existed, couplings that are not pinned).
    pin_levers_m: tuple[float, ...] = ()
    #: Axial preload (N) that presses the faces together when locked (the wedge latch,
    #: :mod:`cubot_cad.couplings.preload`: from the latch servo's torque, the wedge and the friction);
    #: 0: none (a clearance coupling). The model pre-stretches the tension rows by it.
    preload_n: float = 0.0
    #: Static friction coefficient between the pressed faces (0: not stated); with ``preload_n`` it
    #: says what shear the faces hold (``friction x preload``), reported, not counted on.
    friction_coefficient: float = 0.0
    #: Where ``preload_n`` and ``friction_coefficient`` come from (empty when both are 0).
    preload_source: str = ""

    def play_of(self, feature: str) -> FeaturePlay | None:
        """The play of ``feature`` (None if the record has none)."""
        return next((p for p in self.play if p.feature == feature), None)

    def __post_init__(self) -> None:
        require(isinstance(self.provenance, str) and self.provenance.startswith(PROVENANCE_PREFIXES),
                f"{self.kind}.provenance must start with one of {', '.join(PROVENANCE_PREFIXES)}, "
                f"got {self.provenance!r}")
        names = [p.feature for p in self.play]
        require(len(set(names)) == len(names), f"{self.kind}: duplicate play features {names}")
        axes = [(p.axis, p.sense) for p in self.play]
        require(len(set(axes)) == len(axes), f"{self.kind}: two play features on the same axis and sense {axes}")
        require(self.kind in CONNECTOR_KINDS,
                f"connector kind {self.kind!r} is not one of {', '.join(CONNECTOR_KINDS)}")
        for name in ("rotational_stiffness_nm_per_rad", "axial_stiffness_n_per_m"):
            v = getattr(self, name)
            require(_finite(v) and v > 0, f"{self.kind}.{name} must be > 0, got {v!r}")
        for name in ("backlash_rad", "gap_m", "height_m"):
            v = getattr(self, name)
            require(_finite(v) and v >= 0, f"{self.kind}.{name} must be >= 0, got {v!r}")
        v = self.shear_stiffness_n_per_m
        require(v is None or (_finite(v) and v > 0), f"{self.kind}.shear_stiffness_n_per_m must be > 0, got {v!r}")
        for v in self.pin_levers_m:
            require(_finite(v) and 0 <= v < 1, f"{self.kind}.pin_levers_m must be lengths in [0, 1) m, got {v!r}")
        require(self.backlash_rad < 0.5, f"{self.kind}.backlash_rad {self.backlash_rad} is not a small angle (< 0.5 rad)")
        require(_finite(self.preload_n) and 0 <= self.preload_n < 1e4,
                f"{self.kind}.preload_n must be in [0, 1e4) N, got {self.preload_n!r}")
        require(_finite(self.friction_coefficient) and 0 <= self.friction_coefficient <= 1.5,
                f"{self.kind}.friction_coefficient must be in [0, 1.5], got {self.friction_coefficient!r}")
        require(not (self.preload_n > 0 or self.friction_coefficient > 0) or bool(self.preload_source),
                f"{self.kind}: a preload or friction needs its preload_source")


@dataclass(frozen=True)
class RobotProperties:
    """Rigid-body and coupling facts of one robot model (SI units)."""

    name: str
    length_m: float
    width_m: float
    height_m: float
    mass_kg: float
    com_m: tuple[float, float, float]
    #: Inertia tensor about the centre of mass: Ixx, Iyy, Izz, Ixy, Ixz, Iyz.
    inertia_kg_m2: tuple[float, float, float, float, float, float]
    #: How far the main drive wheels protrude below the body: the step a
    #: deflected front can still climb (thesis: 15 mm).
    wheel_exposed_height_m: float
    #: How far the casters protrude (thesis: a third of 10 mm, 3.3 mm).
    caster_exposed_height_m: float
    material: str
    density_kg_m3: float
    youngs_modulus_pa: float
    connectors: tuple[ConnectorProperties, ...]
    source: str = "packaged-default"
    #: Floor to the top face of the cover of one robot standing on its wheels and casters (a pier
    #: of one), and what it was measured from. None: not known (a record written before it, or a
    #: robot that cannot be stacked: no top-down coupling).
    standing_height_m: float | None = None
    standing_height_source: str | None = None
    #: Cover top to cover top of two robots stacked with the top-down coupling (a pier of k robots
    #: is ``standing_height_m + (k - 1) * stack_pitch_m`` tall), and what it was measured from.
    #: None: not known, or the robot has no top-down coupling.
    stack_pitch_m: float | None = None
    stack_pitch_source: str | None = None
    #: The top cover of a pier to the running deck the line rolls over (the printed pier deck,
    #: ``cubot_cad.piers.deck``, on the top robot): a pier's running surface is ``pier_height_m(k) +
    #: deck_height_m``; and what it was measured from. None: not known, or no deck (no top-down coupling).
    deck_height_m: float | None = None
    deck_height_source: str | None = None
    #: Where the robot touches a flat ground (wheels, casters; :class:`GroundContact`, robot
    #: frame), and what they were derived from. None: not in the record (a record written before
    #: them, or a robot without wheels that lies on its underside): `structure_fem` then falls back
    #: (see ``structure_fem.model.contacts``).
    ground_contacts: tuple[GroundContact, ...] | None = None
    ground_contacts_source: str | None = None
    #: The printed body's effective second moment of area for bending in the structure's
    #: vertical plane (m^4; :func:`cubot_cad.checks.section.body_section`: the shell cut from the CAD,
    #: ``I_eff = L / integral dx / I(x)``), and how it was obtained. None: not in the record (a
    #: record written before it): `structure_fem.model.bodies` falls back to the envelope box.
    body_second_moment_m4: float | None = None
    body_second_moment_source: str | None = None
    #: The robot's mass if its printed parts were solid (100 % infill; kg), beside ``mass_kg`` at the
    #: recorded print settings, and how it was obtained: the heavy end of the infill a maker may choose
    #: (`structure_fem.analysis.margins`' threshold range). None: not in the record (or not sliced: then
    #: ``mass_kg`` is already the solid one).
    solid_print_mass_kg: float | None = None
    solid_print_mass_source: str | None = None

    def with_mass_scaled(self, k: float) -> RobotProperties:
        """The same robot ``k`` times as heavy: mass, inertia and the solid-print mass scaled, the centre
        of mass kept (a study's scaled input, not a measured record)."""
        solid = None if self.solid_print_mass_kg is None else self.solid_print_mass_kg * k
        return replace(self, mass_kg=self.mass_kg * k, inertia_kg_m2=tuple(i * k for i in self.inertia_kg_m2),
                       solid_print_mass_kg=solid)

    def __post_init__(self) -> None:
        require(bool(self.name), "robot name must not be empty")
        for name in ("standing_height", "stack_pitch", "deck_height"):
            v, src = getattr(self, f"{name}_m"), getattr(self, f"{name}_source")
            if v is None:
                require(src is None, f"{self.name}.{name}_source is given without {name}_m")
                continue
            require(_finite(v) and 0 < v < 1, f"{self.name}.{name}_m must be in (0, 1) m, got {v!r}")
            require(isinstance(src, str) and bool(src.strip()),
                    f"{self.name}.{name}_m needs a {name}_source saying where it comes from")
        i_b, i_src = self.body_second_moment_m4, self.body_second_moment_source
        if i_b is None:
            require(i_src is None, f"{self.name}.body_second_moment_source is given without body_second_moment_m4")
        else:
            require(_finite(i_b) and i_b > 0, f"{self.name}.body_second_moment_m4 must be > 0 m^4, got {i_b!r}")
            require(isinstance(i_src, str) and bool(i_src.strip()),
                    f"{self.name}.body_second_moment_m4 needs a body_second_moment_source saying where it comes from")
        for name in ("length_m", "width_m", "height_m", "mass_kg", "density_kg_m3", "youngs_modulus_pa"):
            v = getattr(self, name)
            require(_finite(v) and v > 0, f"{self.name}.{name} must be > 0, got {v!r}")
        m_s, m_src = self.solid_print_mass_kg, self.solid_print_mass_source
        if m_s is None:
            require(m_src is None, f"{self.name}.solid_print_mass_source is given without solid_print_mass_kg")
        else:
            require(_finite(m_s) and m_s >= self.mass_kg * (1 - 1e-9),
                    f"{self.name}.solid_print_mass_kg {m_s!r} must be >= mass_kg {self.mass_kg!r} (solid parts are "
                    "not lighter than printed ones): a changed mass_kg takes solid_print_mass_kg and inertia_kg_m2 "
                    "with it, by the same factor (`voidcross cad props --scale-mass F` writes such a variant; "
                    "docs/records.md lists the fields that change together)")
            require(isinstance(m_src, str) and bool(m_src.strip()),
                    f"{self.name}.solid_print_mass_kg needs a solid_print_mass_source saying where it comes from")
        for name in ("wheel_exposed_height_m", "caster_exposed_height_m"):
            v = getattr(self, name)
            require(_finite(v) and v >= 0, f"{self.name}.{name} must be >= 0, got {v!r}")
        gc, gsrc = self.ground_contacts, self.ground_contacts_source
        if gc is None:
            require(gsrc is None, f"{self.name}.ground_contacts_source is given without ground_contacts")
        else:
            require(len(gc) >= 1, f"{self.name}.ground_contacts is empty (omit it for a robot without contacts)")
            require(isinstance(gsrc, str) and bool(gsrc.strip()),
                    f"{self.name}.ground_contacts needs a ground_contacts_source saying where they come from")
            xs = [(c.feature, c.x_m) for c in gc]
            require(len(set(xs)) == len(xs), f"{self.name}: duplicate ground contacts {xs}")
            half = self.length_m / 2
            for c in gc:
                require(abs(c.x_m) <= half + 1e-9,
                        f"{self.name}: ground contact {c.feature} at x = {c.x_m:g} m is outside the body "
                        f"(+-{half:g} m)")
        require(len(self.com_m) == 3 and all(_finite(c) for c in self.com_m),
                f"{self.name}.com_m must be 3 finite numbers, got {self.com_m!r}")
        require(len(self.inertia_kg_m2) == 6 and all(_finite(c) for c in self.inertia_kg_m2),
                f"{self.name}.inertia_kg_m2 must be 6 finite numbers, got {self.inertia_kg_m2!r}")
        ixx, iyy, izz = self.inertia_kg_m2[:3]
        require(min(ixx, iyy, izz) > 0, f"{self.name}.inertia_kg_m2 principal terms must be > 0")
        # Triangle inequality of a physical inertia tensor (with a little slack for rounding).
        tol = 1e-9 + 1e-6 * (ixx + iyy + izz)
        require(ixx + iyy >= izz - tol and iyy + izz >= ixx - tol and ixx + izz >= iyy - tol,
                f"{self.name}.inertia_kg_m2 violates the triangle inequality: {self.inertia_kg_m2!r}")
        kinds = [c.kind for c in self.connectors]
        require(len(set(kinds)) == len(kinds), f"{self.name}: duplicate connector kinds {kinds}")

    @property
    def front_contact_setback_m(self) -> float | None:
        """How far the front-most ground contact sits behind the front face (m; None: no contacts)."""
        if not self.ground_contacts:
            return None
        return self.length_m / 2 - max(c.x_m for c in self.ground_contacts)

    @property
    def rear_contact_setback_m(self) -> float | None:
        """How far the rear-most ground contact sits ahead of the rear face (m; None: no contacts)."""
        if not self.ground_contacts:
            return None
        return self.length_m / 2 + min(c.x_m for c in self.ground_contacts)

    def connector(self, kind: str) -> ConnectorProperties:
        """The connector of ``kind``; :class:`InputError` if this robot has none."""
        for c in self.connectors:
            if c.kind == kind:
                return c
        have = ", ".join(c.kind for c in self.connectors) or "none"
        raise InputError(f"robot {self.name!r} has no {kind!r} connector (has: {have})")

    def pier_height_m(self, robots: int) -> float:
        """Floor to the top cover of a pier of ``robots`` (>= 1) of these robots stacked top-down
        (m): ``standing_height_m + (robots - 1) * stack_pitch_m``; :class:`InputError` when the
        record has neither (an old record, or a robot that does not stack)."""
        require(isinstance(robots, int) and not isinstance(robots, bool) and robots >= 1,
                f"a pier needs a whole number of robots >= 1, got {robots!r}")
        require(self.standing_height_m is not None and (robots == 1 or self.stack_pitch_m is not None),
                f"robot {self.name!r} has no standing height / stack pitch in its record (it does not stack, "
                "or the record predates them: re-export with `voidcross cad export`)")
        return self.standing_height_m + (robots - 1) * (self.stack_pitch_m or 0.0)

    def running_surface_height_m(self, robots: int) -> float:
        """Floor to the running deck of a pier of ``robots`` (m): :meth:`pier_height_m` +
        ``deck_height_m``; :class:`InputError` when the record has no deck height."""
        top = self.pier_height_m(robots)
        require(self.deck_height_m is not None,
                f"robot {self.name!r} has no deck height in its record (it does not stack, or the record "
                "predates it: re-export with `voidcross cad export`)")
        return top + self.deck_height_m

    def with_connector(self, connector: ConnectorProperties) -> RobotProperties:
        """A copy with ``connector`` replacing the one of the same kind (or added)."""
        rest = tuple(c for c in self.connectors if c.kind != connector.kind)
        return replace(self, connectors=rest + (connector,))


@dataclass(frozen=True)
class RobotPropertiesFile:
    """What ``robot_properties.json`` holds: one record per robot model."""

    robots: tuple[RobotProperties, ...]
    schema_version: int = SCHEMA_VERSION

    def __post_init__(self) -> None:
        require(self.schema_version == SCHEMA_VERSION,
                f"robot properties schema_version {self.schema_version} is not {SCHEMA_VERSION}")
        require(len(self.robots) > 0, "robot properties file lists no robots")
        names = [r.name for r in self.robots]
        require(len(set(names)) == len(names), f"duplicate robot names {names}")

    def get(self, name: str) -> RobotProperties:
        for r in self.robots:
            if r.name == name:
                return r
        raise InputError(f"unknown robot {name!r} (known: {', '.join(r.name for r in self.robots)})")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(r.name for r in self.robots)

    def to_dict(self) -> dict:
        d = to_jsonable(self)
        return {"schema_version": d.pop("schema_version"), **d}

    @classmethod
    def from_dict(cls, data: object, what: str = "robot properties") -> RobotPropertiesFile:
        check_schema(data, SCHEMA_VERSION, what)
        return from_dict(cls, data, what)

    def save(self, path: str | os.PathLike) -> Path:
        return write_json_atomic(path, self.to_dict())

    @classmethod
    def load(cls, path: str | os.PathLike) -> RobotPropertiesFile:
        return cls.from_dict(read_json(path), str(path))


def default_properties_path() -> Path:
    """The packaged ``robot_properties.json`` (written by `voidcross cad export`)."""
    return Path(str(resources.files("cubot_cad") / "data" / "robot_properties.json"))


def default_properties() -> RobotPropertiesFile:
    """The packaged defaults, so downstream packages run without CAD installed."""
    return RobotPropertiesFile.load(default_properties_path())


def load_properties(path: str | os.PathLike | None = None) -> RobotPropertiesFile:
    """Load ``path``, or the packaged defaults when ``path`` is None."""
    return default_properties() if path is None else RobotPropertiesFile.load(path)
