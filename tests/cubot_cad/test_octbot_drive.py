"""OctBot capturer finger drive, checked in the CAD by moving it: a worm on an N20 gearmotor (in the
housing's pocket) turns a cam disc whose three spiral slots drive one peg on each finger, so the disc
angle sets the fingers' radial position (:meth:`RingSpec.finger_offset_mm`). Stepped from retracted
(0 deg, the fingers pass the ring's lip) to spread (``cam_turn_deg``, the hooks behind the lip), the
moving parts touch nothing, the fingers end where the docking model puts them, and spread they hold
the docked neighbour's ring. Volumes from manifold3d (mm^3), as the docking and component checks."""

from __future__ import annotations

import itertools

import pytest

#: Interference below this is float32 meshing noise (mm^3: the housing and the docked ring touch face
#: to face, 7e-6 mm^3); the moving parts are >= 0.1 mm apart. As test_components.LIMIT_MM3.
FREE_MM3 = 1e-3
STEPS = 9


def _m(item):
    from cubot_cad.checks.docking import manifold_of

    return manifold_of(item)


def _iv(a, b) -> float:
    from cubot_cad.checks.docking import intersection_volume

    return intersection_volume(a, b)


def _robot(c):
    from cubot_cad.robots.octbot import OctBot

    return OctBot(clearance_mm=c)


def _partner_ring(r):
    """The docked neighbour's ring in this robot's frame: its rear face the docked gap as the docking
    model measures it (40.005 mm: the ring's tube stands 0.005 mm proud of its lip) ahead of the front
    face."""
    from cubot_cad.checks.docking import dock_robot

    gap = dock_robot(r, "octbot-ring").gap_mm
    assert gap == pytest.approx(r.docked_gap_mm, abs=0.05)
    ring = next(p for p in r.placed if p.role == "ring")
    return _m(ring).translate((r.across_flats_mm + gap, 0.0, 0.0))


def _stand_ins(r):
    from cubot_cad.checks.docking import to_manifold

    return {c.key: to_manifold(s) for c in r.components() if c.key in ("worm_motor", "worm") for s in c.solids()}


def test_the_disc_angle_sets_the_finger_offset_linearly_between_the_two_ends():
    r = _robot(0.2)
    rs = r.ring_spec
    T = rs.cam_turn_deg
    assert r.finger_offset_mm(0.0) == pytest.approx(-rs.finger_travel_mm)
    assert r.finger_offset_mm(T) == pytest.approx(0.0)
    assert r.finger_offset_mm(T / 2) == pytest.approx(-rs.finger_travel_mm / 2)
    assert r.disc_deg_for(False) == 0.0 and r.disc_deg_for(True) == T
    from cubot_cad.errors import InputError
    from cubot_cad.shapes import loc_matrix

    with pytest.raises(InputError, match="disc_deg"):
        r.finger_offset_mm(T + 5)
    # the default placement (fingers retracted) and fingers_open=True are the drive's two ends
    for fo, deg in ((False, 0.0), (True, T)):
        a = [p for p in r.build_placed(fingers_open=fo) if p.role in ("finger", "cam_disc")]
        b = [p for p in r.build_placed(disc_deg=deg) if p.role in ("finger", "cam_disc")]
        for pa, pb in zip(a, b, strict=True):
            assert pa.part == pb.part
            assert loc_matrix(pa.loc).ravel().tolist() == pytest.approx(loc_matrix(pb.loc).ravel().tolist(), abs=1e-9)
    assert [p.role for p in r.placed].count("cam_disc") == 1
    parts = dict((p.name, n) for p, n in r.printable_parts())
    assert parts["octbot_finger_cam_disc"] == 1 and parts["octbot_finger"] == 3


@pytest.mark.parametrize("c", (0.1, 0.2, 0.5))
def test_turning_the_disc_moves_the_fingers_from_retracted_to_spread_touching_nothing(c):
    """At every step: disc, fingers (with pegs), housing, worm and worm motor, and the docked
    neighbour's ring pairwise free; the fingers' radial position follows the disc angle."""
    from cubot_cad.shapes import tight_bbox

    r = _robot(c)
    rs = r.ring_spec
    h = r.across_flats_mm / 2
    ring = _partner_ring(r)
    stand = _stand_ins(r)
    assert set(stand) == {"worm_motor", "worm"}
    for k in range(STEPS):
        deg = rs.cam_turn_deg * k / (STEPS - 1)
        placed = r.build_placed(disc_deg=deg)
        moving = {f"{p.role}{i}": _m(p) for i, p in enumerate(placed) if p.role in ("finger", "cam_disc")}
        housing = _m(next(p for p in placed if p.role == "housing"))
        items = {**moving, "housing": housing, "partner_ring": ring, **stand}
        hits = [(a, b, v) for (a, ma), (b, mb) in itertools.combinations(items.items(), 2)
                if (v := _iv(ma, mb)) > FREE_MM3]
        assert not hits, (deg, hits)
        # every finger's bar is where the cam puts it: the finger at 0 deg points +z
        top = next(p for p in placed if p.role == "finger")
        bb = tight_bbox(top.shape)
        want = rs.centre_z_mm + rs.finger_radius_mm + rs.finger_offset_mm(deg) - rs.finger_mm / 2
        # the bar's inner face (the lowest point of the finger that points up)
        assert bb[2] == pytest.approx(want, abs=1e-6), deg
        assert bb[0] == pytest.approx(h + r.housing_mm - 8 - rs.cam_disc_mm - rs.clearance_mm + 0.5, abs=1e-6)


def test_the_cam_drives_the_pegs_a_finger_off_the_cam_law_hits_the_disc():
    """The kinematics are real: the disc turned while the fingers stay put, or a finger pushed 0.5 mm
    off the position the cam sets, puts its peg into the disc."""
    from cubot_cad.shapes import location

    r = _robot(0.2)
    rs = r.ring_spec
    T = rs.cam_turn_deg
    for deg in (T / 4, T / 2, T):
        disc = _m(next(p for p in r.build_placed(disc_deg=deg) if p.role == "cam_disc"))
        stuck = [_m(p) for p in r.build_placed(disc_deg=0.0) if p.role == "finger"]
        assert all(_iv(disc, f) > 0.1 for f in stuck), deg
    mid = r.build_placed(disc_deg=T / 2)
    disc = _m(next(p for p in mid if p.role == "cam_disc"))
    for p in (p for p in mid if p.role == "finger"):
        assert _iv(disc, _m(p)) <= FREE_MM3
        for dz in (0.5, -0.5):
            off = type(p)(p.part, p.loc * location((0, 0, dz)), p.role)
            assert _iv(disc, _m(off)) > 0.1, dz


def test_the_worm_reaches_the_disc_rim():
    """The worm's pitch cylinder is ``clearance_mm`` (the backlash) from the disc's rim, under it."""
    from cubot_cad.shapes import Y, cyl

    r = _robot(0.2)
    rs = r.ring_spec
    hs = r.housing
    h = r.across_flats_mm / 2
    disc = next(p for p in r.placed if p.role == "cam_disc").shape
    xw, zw = hs.worm_axis_mm
    y0, y1 = hs.worm_y_mm
    assert y0 < 0 < y1  # under the disc's centre
    assert zw + rs.worm_radius_mm + rs.clearance_mm == pytest.approx(rs.centre_z_mm - rs.cam_radius_mm)
    grown = cyl(rs.worm_radius_mm + rs.clearance_mm + 0.05, y1 - y0, (h + xw, y0, zw), Y)
    assert disc.intersect(grown).Volume() > 0.01
    exact = cyl(rs.worm_radius_mm, y1 - y0, (h + xw, y0, zw), Y)
    assert disc.intersect(exact).Volume() == pytest.approx(0.0, abs=1e-6)
    # and the worm sits in the plane of the disc: its axis through the disc's mid-thickness
    d0, d1 = hs.cam_disc_x_mm
    assert xw == pytest.approx((d0 + d1) / 2)


def test_spread_the_hooks_hold_the_ring_retracted_they_let_it_go():
    """Docked, the neighbour pulled away by the clearance + 0.3 mm: the spread hooks bear on its lip
    (> 0 each), the retracted ones pass (0)."""
    r = _robot(0.2)
    c = r.ring_spec.clearance_mm
    ring = _partner_ring(r).translate((c + 0.3, 0.0, 0.0))
    spread = [_m(p) for p in r.build_placed(fingers_open=True) if p.role == "finger"]
    retracted = [_m(p) for p in r.build_placed(fingers_open=False) if p.role == "finger"]
    held = [_iv(ring, f) for f in spread]
    assert all(v > 0.5 for v in held), held
    assert all(_iv(ring, f) <= FREE_MM3 for f in retracted)


def test_the_docked_pair_still_docks_at_its_gap():
    from cubot_cad.checks.docking import dock_robot

    r = _robot(0.2)
    p = dock_robot(r, "octbot-ring")
    assert p.ok, p.problems()
    assert p.gap_mm == pytest.approx(r.docked_gap_mm, abs=0.05)
