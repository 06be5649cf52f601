"""Couplings whose faces touch, built from their parts so the hinge emerges (issue 12, item 2; SI).

The lumped model (``hinge="lumped"``, ``--hinge lumped``; the default until 2026-12-04) lumps every
coupling at one point: a translational
spring with the record's play per axis plus a rotational spring with a *pitch dead band* of
``tension play / highest pin``. That dead band is a separate number standing for a mechanism:
the joint turns about the edge where the faces press together until the pins' tension play is
taken up. Here (``hinge="emergent"``, the default and the packaged record's) a coupling whose faces touch is modelled by
what carries the load, each with its own play from the CAD, and the hinge, its rotational play
and the composite action of stacked layers come out of the solve:

* **tension rows** along the face normal, bearing only in tension after the coupling's tension
  play (the record's ``play_x`` / ``play_z`` opening: pin head in its counterbore + latch blade in
  the groove for a front-rear coupling, the key's pull-out for a layer). A front-rear coupling has
  one row per distinct pin height (the record's ``pin_levers_m`` above the hinge), with
  stiffnesses that reproduce the record's axial and rotational stiffness exactly (:func:`rows`);
* **compression-only face contacts** where the faces can press: the bottom and top edges of the
  front / rear walls (the robot's underside and its top) for a front-rear coupling, and for a
  layer the upper robot's wheels and casters on the lower robot's top (its ``ground_contacts``;
  the body corners for a robot without). Frictionless: no force along the face;
* **shear** along the face with the record's play per feature (the pins' vertical slip, the key's
  slip) and stiffness, at the coupling point.

The side rail stays a lumped coupling (its pitch play is a real rotational clearance over the
overlap), but it slides along x (:func:`along_factor`).

Hogging then opens the pins and closes the bottom edge: the joint turns about that edge, each
row bearing once the rotation times its lever reaches the play (the CuBot: the two upper pins
at 0.4 mm / 37 mm = 10.8 mrad, the four lower ones at 0.4 / 26.5 = 15.1 mrad). Sagging turns it
about the top edge with the pins' levers measured from there. A layer turns about one of the
upper robot's wheels only by lifting its key. None of these rotations is an input.

Which couplings: a front-rear coupling with a zero docked gap (its faces touch: the CuBot) and
every top twist-lock. A coupling whose faces do not touch (the Cube Robot's 1.7 mm gap, the
OctBot's ring, the platform's lapped bolt) and the side rail (its faces slide past each other)
stay lumped: their pitch play is a real rotational clearance about the coupling itself.

Numerical choices (not physical inputs): the face contacts are stiff compared with the pins, a
penalty of :data:`FACE_CONTACT_FACTOR` x the coupling's axial stiffness (the walls bear in plane); a layer's contacts have the ledge contacts' stiffness
(:data:`structure_fem.model.statics.CONTACT_N_PER_M` per robot and point: a wheel on a surface). One-sided
springs are smoothed as the model's others (:func:`axis_force`); a separated contact or slack row
carries at most :data:`RESIDUAL_FORCE_N`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from structure_fem.model.connectors import HINGES, SMOOTHING, Joint  # noqa: F401  (HINGES: the joints' home)

#: Face contact penalty over the coupling's axial stiffness (numerical, a near-rigid contact): the
#: walls bear in plane, about E t b / depth = 2.2 GPa x 2.4 mm x 100 mm / 10 mm = 5e7 N/m per edge
#: for the CuBot, some 40x its coupling's 1.2e6 N/m; 30x puts 3 % of the joint's compliance in
#: the faces (100x moved the line's tips by 0.1-3 % and left Newton failing without play).
FACE_CONTACT_FACTOR = 30.0
#: Force (N) a separated one-sided spring keeps from its smoothing (``k e / 2``).
RESIDUAL_FORCE_N = 0.01
#: Along-the-rail stiffness a sliding side rail keeps (numerical, :func:`along_factor`).
RAIL_SLIDE_FACTOR = 1e-5
#: Without play, one-sided springs are smoothed over this fraction of the stretch one body's
#: weight makes (x the bands' 0.1): a row then bears about 5 % of that weight late (0.1 gave
#: sharper edges and Newton failed on every play-free chain from 2 links).
ZERO_PLAY_SCALE = 1.0
#: No one-sided spring is smoothed over less (m): the ledge contacts' smoothing
#: (``model.CONTACT_SMOOTHING_M``). Sharper kinks sit inside the finite-difference step of the
#: connectors' Jacobian, and Newton diverged on stiff play-free chains (30x 1e8 N/m faces: 1e-10 m).
MIN_SMOOTHING_M = 1e-8
#: A docked gap below this (m) counts as touching faces (the record writes 0 for them).
TOUCHING_GAP_M = 1e-9

KINDS = ("free", "lin", "band", "tension", "contact")


@dataclass(frozen=True)
class Axis:
    """One direction of a link: ``kind`` ``free`` (no force), ``lin`` (``k u``), ``band`` (free
    over ``[-closing, opening]``), ``tension`` (bears only for ``u > opening``) or ``contact``
    (bears only for ``u < 0``); ``e`` its smoothing (m), ``k_reg`` the weak spring (N/m) that
    gives a link inside its play a defined position. Forces in N, ``u`` in m (opening positive)."""

    kind: str
    k: float = 0.0
    closing: float = 0.0
    opening: float = 0.0
    e: float = 0.0
    k_reg: float = 0.0
    #: Length (m) the static solver's continuation widens the smoothing from (``start`` x this):
    #: the play of a band or a row; 0 for a contact (never widened, :func:`_contact`).
    scale: float = 0.0
    #: A preloaded row (``tension`` with ``opening < 0``): its force is not set to zero at ``u = 0``, it
    #: carries its share of the preload there (:func:`_preloaded_row`). A ``contact``'s ``opening`` > 0
    #: shifts it so that it presses with its share of the preload at ``u = 0`` (:func:`_preloaded_contact`).
    preloaded: bool = False


FREE = Axis("free")


@dataclass(frozen=True)
class Link:
    """One spring between bodies ``a`` and ``b`` at the global point ``point_m`` (both markers
    there in the reference state); ``u = position on b - position on a``."""

    a: int
    b: int
    point_m: tuple[float, float]
    x: Axis
    z: Axis
    feature: str


def emergent(coupling, hinge: str) -> bool:
    """Whether ``coupling`` (:class:`structure_fem.model.structures.Coupling`) is built from its parts."""
    if hinge != "emergent":
        return False
    if coupling.role == "top_twist":
        return True
    return coupling.role == "front_rear" and coupling.joint.kind == "front_rear" and \
        coupling.joint.gap_m <= TOUCHING_GAP_M


def along_factor(coupling, hinge: str) -> float:
    """What the lumped translational spring of ``coupling`` keeps along x: a side rail is a
    dovetail that slides (its lead-ins are there so a robot can slide in alongside), so with the
    emergent hinge it carries no force along the rail but :data:`RAIL_SLIDE_FACTOR` of its
    record's value, which only fixes a staggered line's position along the other (frictionless
    otherwise). The lumped model kept the record's value (the rail as a tie: harmless while every
    joint turned about its own load point, a stiff tie once the joints turn about their bottom
    edge). Every other coupling: 1."""
    return RAIL_SLIDE_FACTOR if (hinge == "emergent" and coupling.role == "side_rail") else 1.0


def rows(joint: Joint) -> tuple[tuple[float, float], ...]:
    """``(lever m, axial N/m)`` of each tension row of one front-rear coupling about its hinge.

    Two distinct pin heights (the CuBot: two pins at 37 mm, four at 26.5 mm): the two rows'
    stiffnesses solve ``k1 + k2 = k_axial`` and ``k1 a1^2 + k2 a2^2 = k_rot``, so the rows have the
    record's (FE) axial and rotational stiffness exactly. Otherwise (one height, more than two,
    no levers in the record, or a fit with a negative row): one equivalent row of ``k_axial`` at
    ``sqrt(k_rot / k_axial)``, which has both too."""
    ka, kr = joint.axial_n_per_m, joint.rotational_nm_per_rad
    levels = sorted({round(a, 9) for a in joint.levers_m if a > 0})
    if len(levels) == 2:
        a1, a2 = levels
        k2 = (kr - ka * a1 * a1) / (a2 * a2 - a1 * a1)
        k1 = ka - k2
        if k1 > 0 and k2 > 0:
            return ((a1, k1), (a2, k2))
    return ((math.sqrt(kr / ka), ka),)


def _smoothing(k: float, scale: float, force_scale_n: float) -> float:
    """The model's band smoothing (:func:`structure_fem.model.statics.translational_bands`): a link
    carrying ``force_scale_n`` sits within 1 % of ``scale`` of the sharp edge, at most a tenth of
    it; at least enough that a slack one-sided link carries :data:`RESIDUAL_FORCE_N`."""
    e_min = max(2 * RESIDUAL_FORCE_N / k, MIN_SMOOTHING_M)
    if scale <= 0:  # no play: smooth over the stretch one body's weight makes
        scale = ZERO_PLAY_SCALE * force_scale_n / k
    return max(min(SMOOTHING * scale, math.sqrt(0.04 * force_scale_n * scale / k)), e_min)


def _row(k: float, gap: float, force_scale_n: float) -> Axis:
    """A tension row with ``gap`` of play (and the weak in-play spring of the model's bands)."""
    k_reg = min(1e-3 * k, 0.01 * force_scale_n / gap) if gap > 0 else 1e-3 * k
    return Axis("tension", k, 0.0, gap, _smoothing(k, gap, force_scale_n), k_reg,
                gap or ZERO_PLAY_SCALE * force_scale_n / k)


def _contact(k: float, scale: float, force_scale_n: float) -> Axis:
    """A compression-only contact ``k/2 (u - sqrt(u^2 + e^2))`` (the ledge contacts' form),
    smoothed as a band of the coupling's play ``scale`` is. A separated contact keeps
    ``k e^2 / 4 u`` (the CuBot's faces: 0.14 N at 0.1 mm, 0.04 N at 0.4 mm) and a loaded one sits
    within 1 % of the play of the sharp contact. Its smoothing is not widened by the static
    solver's continuation: smoothed over millimetres it pushes the docked faces apart with
    ``k e / 2`` of kilonewtons (measured: every line from 4 widths then failed). A tenth of this
    ``e`` moves the line's tips by less than 0.02 mm (measured, w = 2..9)."""
    return Axis("contact", k, e=_smoothing(k, scale, force_scale_n))


def _contact_scale(play: float, k_row: float, force_scale_n: float) -> float:
    """The length a coupling's face contacts are smoothed as a band of (:func:`_contact`): its
    tension play; without play, the stretch one body's weight makes in the coupling's rows
    (``force / k_row``, as the rows' own smoothing, :func:`_smoothing`). Measured: smoothed over
    the stiff faces' own stretch instead (30x shorter), a play-free line resting on a pier, whose
    joints near the moment's change of sign sit on the kink between rows and faces, made Newton
    fail (21 rows over a 19-wide void, pier at 8, x0 play, x0.5 mass, every retry)."""
    return play if play > 0 else ZERO_PLAY_SCALE * force_scale_n / k_row


def _preloaded_row(k: float, force_n: float, force_scale_n: float) -> Axis:
    """A tension row pre-stretched to carry ``force_n`` at the docked position (the wedge latch's
    preload share): ``k/2 [(u + d) + sqrt((u + d)^2 + e^2)]`` with ``d`` solved so that it is exactly
    ``force_n`` at ``u = 0`` (``d = (4 d0^2 - e^2) / 4 d0``, ``d0 = force_n / k``); it goes slack only
    once the joint has opened by about ``d0``."""
    base = _row(k, 0.0, force_scale_n)
    d0 = force_n / k
    d = (4 * d0 * d0 - base.e * base.e) / (4 * d0)
    return Axis("tension", k, 0.0, -d, base.e, base.k_reg, base.scale, preloaded=True)


def _preloaded_contact(k: float, force_n: float, scale: float, force_scale_n: float) -> Axis:
    """A face contact pressing with ``force_n`` at the docked position: shifted by ``s`` so that
    ``k/2 [(u - s) - sqrt((u - s)^2 + e^2)] = -force_n`` at ``u = 0`` (``s = (q^2 - e^2) / 2 q``,
    ``q = 2 force_n / k``); it separates once the joint has opened by about ``force_n / k``."""
    base = _contact(k, scale, force_scale_n)
    if force_n <= 0:
        return base
    q = 2 * force_n / k
    return Axis("contact", k, 0.0, (q * q - base.e * base.e) / (2 * q), base.e, preloaded=True)


def _band(k: float, play: tuple[float, float], force_scale_n: float) -> Axis:
    c, o = play
    gap = max(c, o)
    if gap <= 0:
        return Axis("lin", k)
    e = min(SMOOTHING * gap, math.sqrt(0.04 * force_scale_n * gap / k))
    return Axis("band", k, c, o, e, min(1e-3 * k, 0.01 * force_scale_n / gap), gap)


def links(coupling, lay, force_scale_n: float, contact_n_per_m: float) -> tuple[Link, ...]:
    """The links of an emergent ``coupling`` of layout ``lay``
    (:class:`structure_fem.model.structures.Layout`); ``force_scale_n``: one body's weight (sets the
    smoothing, as :func:`structure_fem.model.statics.translational_bands`); ``contact_n_per_m``: the
    ledge contact stiffness per robot and point (a layer's wheels on the robot below)."""
    c, j, n = coupling, coupling.joint, coupling.count
    if c.role == "front_rear":
        x_j = c.point_m[0]
        base = lay.bodies[c.a].z_m
        rs = rows(j)
        kf = FACE_CONTACT_FACTOR * j.axial_n_per_m * n
        scale = _contact_scale(j.play_x[1], j.axial_n_per_m * n, force_scale_n)
        preload = j.preload_n * n if j.play_x[1] <= 0 else 0.0  # a row with play left carries no preload
        if preload > 0:
            # the preload stretches every pin alike: row i carries k_i / k_axial of it; the faces press
            # back with as much, shared between the edges so that the docked position is in equilibrium
            # (the rows' moment about the bottom edge = the top edge's share x the height)
            d0 = preload / (j.axial_n_per_m * n)
            top = sum(k * n * d0 * lever for lever, k in rs) / lay.height_m
            shares = {"bottom": preload - top, "top": top}
            out = [Link(c.a, c.b, (x_j, base + lever), _preloaded_row(k * n, k * n * d0, force_scale_n), FREE,
                        f"pin row {lever * 1e3:.3g} mm above the underside, preloaded {k * n * d0:.3g} N")
                   for lever, k in rs]
        else:
            shares = {"bottom": 0.0, "top": 0.0}
            out = [Link(c.a, c.b, (x_j, base + lever), _row(k * n, j.play_x[1], force_scale_n), FREE,
                        f"pin row {lever * 1e3:.3g} mm above the underside")
                   for lever, k in rs]
        out.append(Link(c.a, c.b, c.point_m, FREE, _band(j.k_z * n, j.play_z, force_scale_n), "pin shear"))
        for z, what in ((base, "bottom"), (base + lay.height_m, "top")):
            out.append(Link(c.a, c.b, (x_j, z), _preloaded_contact(kf, shares[what], scale, force_scale_n), FREE,
                            f"faces, {what} edge"))
        return tuple(out)
    if c.role == "top_twist":
        x_key, z_top = c.point_m
        out = [Link(c.a, c.b, c.point_m, _band(j.axial_n_per_m * n, j.play_x, force_scale_n),
                    _row(j.k_z * n, j.play_z[1], force_scale_n), "key")]
        upper = lay.bodies[c.b]
        points = lay.ground.points if lay.ground is not None else ((-lay.length_m / 2, 0.0), (lay.length_m / 2, 0.0))
        kc = contact_n_per_m * n
        scale = _contact_scale(j.play_z[1], j.k_z * n, force_scale_n)
        for gx, _gz in points:
            out.append(Link(c.a, c.b, (upper.x_m + gx, z_top), FREE, _contact(kc, scale, force_scale_n),
                            f"upper robot's contact at {gx * 1e3:+.3g} mm"))
        return tuple(out)
    raise ValueError(f"no emergent hinge for a {c.role} coupling")


# --------------------------------------------------------------------------- forces


def axis_force(ax: Axis, u: float, e: float | None = None) -> float:
    """Force (N) of ``ax`` at ``u`` (m), smoothed over ``e`` (default ``ax.e``); zero at ``u = 0``
    for ``band`` and ``tension`` (an undeformed coupling carries nothing; a contact: :func:`_contact`)."""
    e = ax.e if e is None else e
    k = ax.k
    if ax.kind == "free":
        return 0.0
    if ax.kind == "lin":
        return k * u
    if ax.kind == "contact":  # not zero at 0: see _contact (shifted by its opening when preloaded)
        w = u - ax.opening
        return 0.5 * k * (w - math.sqrt(w * w + e * e))
    o = ax.opening

    def t(x: float) -> float:
        a = x - o
        return 0.5 * k * (a + math.sqrt(a * a + e * e))

    if ax.kind == "tension":
        return t(u) - (0.0 if ax.preloaded else t(0.0)) + ax.k_reg * u
    c = ax.closing

    def f(x: float) -> float:
        b = x + c
        return t(x) + 0.5 * k * (b - math.sqrt(b * b + e * e))

    return f(u) - f(0.0) + ax.k_reg * u


def _sym_force(esym, ax: Axis, x, ee):
    """Symbolic force and tangent stiffness of ``ax`` (the formulas of :func:`axis_force`)."""
    k = ax.k
    if ax.kind == "free":
        return 0.0, 0.0
    if ax.kind == "lin":
        return k * x, k
    if ax.kind == "contact":
        w = x - ax.opening if ax.opening else x
        r = esym.sqrt(w * w + ee * ee)
        return 0.5 * k * (w - r), 0.5 * k * (1.0 - w / r)
    o = ax.opening
    a = x - o
    ra = esym.sqrt(a * a + ee * ee)
    f = 0.5 * k * (a + ra)
    if not ax.preloaded:
        f = f - 0.5 * k * (-o + esym.sqrt(o * o + ee * ee))
    kt = 0.5 * k * (1.0 + a / ra)
    if ax.kind == "band":
        c = ax.closing
        b = x + c
        rb = esym.sqrt(b * b + ee * ee)
        f = f + 0.5 * k * (b - rb) - 0.5 * k * (c - esym.sqrt(c * c + ee * ee))
        kt = kt + 0.5 * k * (1.0 - b / rb)
    return f + ax.k_reg * x, kt + ax.k_reg


def link_uf(mbs, keep: list, link: Link, beta: float = 0.0, start: float = 0.0, power: int = 20,
            symbolic: bool = True):
    """The ``ObjectConnectorCartesianSpringDamper`` force user function of ``link``: per axis
    :func:`axis_force`, plus ``beta k_t v`` (tangent-stiffness damping, :mod:`structure_fem.model.dynamics`).
    ``start > 0``: the static solver's smoothing continuation (:class:`structure_fem.model.statics.SolverOptions`):
    every smoothing starts at ``start`` x its ``scale`` and relaxes to ``e`` as the load factor
    ``t`` reaches 1 (``e + (start scale - e) (1 - t)^power``)."""
    axes = (link.x, link.z)

    def e0_of(ax: Axis) -> float:
        return start * ax.scale

    if not symbolic:
        def py(mbs_, t, item, u, v, k, d, off):
            out = [0.0, 0.0, 0.0]
            for i, ax in enumerate(axes):
                e0 = e0_of(ax)
                ee = ax.e + (e0 - ax.e) * max(0.0, 1.0 - t) ** power if e0 > ax.e else ax.e
                out[i] = axis_force(ax, u[i], ee)
            return out
        return py

    import exudyn as exu
    from exudyn.advancedUtilities import CreateSymbolicUserFunction

    esym = exu.symbolic

    def sym(mbs_, t, item, u, v, k, d, off):
        out = []
        for i, ax in enumerate(axes):
            e0 = e0_of(ax)
            ee = ax.e + (e0 - ax.e) * esym.pow(1.0 - t, power) if e0 > ax.e else ax.e
            f, kt = _sym_force(esym, ax, u[i], ee)
            out.append(f + beta * kt * v[i] if beta > 0 and ax.kind != "free" else f)
        return [out[0], out[1], 0.0]

    f = CreateSymbolicUserFunction(mbs, sym, "springForceUserFunction",
                                   itemTypeName="ObjectConnectorCartesianSpringDamper")
    keep.append(f)
    return f


def add_links(mbs, keep: list, objs: list, lay, coupling, contact_n_per_m: float, beta: float = 0.0,
              start: float = 0.0, power: int = 20, symbolic: bool = True) -> int:
    """Add the links of an emergent ``coupling`` to ``mbs`` (bodies ``objs`` of ``lay``); returns
    how many. Used by the static model and the transients alike."""
    from exudyn.itemInterface import MarkerBodyPosition, ObjectConnectorCartesianSpringDamper

    def local(i: int, p: tuple[float, float]) -> list[float]:
        cx, cz = lay.bodies[i].com_m
        return [p[0] - cx, p[1] - cz, 0.0]

    from structure_fem.model.structures import GRAVITY

    ls = links(coupling, lay, lay.bodies[coupling.a].mass_kg * GRAVITY, contact_n_per_m)
    for lk in ls:
        ma = mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[lk.a], localPosition=local(lk.a, lk.point_m)))
        mb = mbs.AddMarker(MarkerBodyPosition(bodyNumber=objs[lk.b], localPosition=local(lk.b, lk.point_m)))
        uf = link_uf(mbs, keep, lk, beta, start, power, symbolic)
        mbs.AddObject(ObjectConnectorCartesianSpringDamper(markerNumbers=[ma, mb], stiffness=[lk.x.k, lk.z.k, 0.0],
                                                           damping=[0.0, 0.0, 0.0], springForceUserFunction=uf))
    return len(ls)
