"""OctBot capturer finger retainer, checked in the CAD by moving the parts: a plate screwed over the
housing's front whose slots pass the fingers' bars and hooks but not the shoulders on their tails.
It goes on over the hooks at any disc angle, touches nothing while the cam drives the fingers, stops
a finger pulled out along +x (without it the finger would come out freely), and so, the pegs staying
in the cam disc's slots, keeps the disc from lifting out of its open slot. Volumes from manifold3d
(mm^3), as the other mechanism tests."""

from __future__ import annotations

import pytest

FREE_MM3 = 1e-3  # float32 meshing noise of faces in contact (as test_octbot_drive.FREE_MM3)
HOLD_MM3 = 0.05


def _m(item):
    from cubot_cad.checks.docking import manifold_of

    return manifold_of(item)


def _iv(a, b) -> float:
    from cubot_cad.checks.docking import intersection_volume

    return intersection_volume(a, b)


def _robot(c=0.2):
    from cubot_cad.robots.octbot import OctBot

    return OctBot(clearance_mm=c)


def _moved(p, dx=0.0, dz=0.0):
    """``p`` translated in the robot's frame (the placement's own frame is rotated for the fingers)."""
    from cubot_cad.shapes import location

    return type(p)(p.part, location((dx, 0.0, dz)) * p.loc, p.role)


def _role(placed, role):
    return [p for p in placed if p.role == role]


@pytest.mark.parametrize("c", (0.1, 0.2, 0.5))
def test_the_retainer_touches_nothing_while_the_cam_drives_the_fingers(c):
    r = _robot(c)
    T = r.ring_spec.cam_turn_deg
    for deg in (0.0, T / 2, T):
        placed = r.build_placed(disc_deg=deg)
        ret = _m(_role(placed, "retainer")[0])
        others = {f"{p.role}{i}": _m(p) for i, p in enumerate(placed) if p.role in ("finger", "cam_disc", "housing")}
        hits = {k: v for k, m in others.items() if (v := _iv(ret, m)) > FREE_MM3}
        assert not hits, (deg, hits)


@pytest.mark.parametrize("c", (0.1, 0.2, 0.5))
def test_a_finger_pulled_out_bears_on_the_retainer_and_without_it_would_come_out(c):
    r = _robot(c)
    for deg in (0.0, r.ring_spec.cam_turn_deg):
        placed = r.build_placed(disc_deg=deg)
        ret = _m(_role(placed, "retainer")[0])
        housing = _m(_role(placed, "housing")[0])
        disc = _m(_role(placed, "cam_disc")[0])
        for f in _role(placed, "finger"):
            pulled = _m(_moved(f, dx=c + 0.15))
            assert _iv(ret, pulled) > HOLD_MM3, (deg, c)
            # the control: nothing else stops it (the peg slides out of the disc, the bar out of its slot)
            far = _m(_moved(f, dx=15.0))
            assert _iv(housing, far) <= FREE_MM3 and _iv(disc, far) <= FREE_MM3


def test_the_retained_fingers_keep_the_cam_disc_in_its_open_slot():
    r = _robot(0.2)
    placed = r.build_placed(disc_deg=r.ring_spec.cam_turn_deg / 2)
    disc = _moved(_role(placed, "cam_disc")[0], dz=1.0)
    fingers = [_m(p) for p in _role(placed, "finger")]
    assert sum(_iv(_m(disc), f) for f in fingers) > 0.1


@pytest.mark.parametrize("fingers_open", (False, True))
def test_the_retainer_goes_on_over_the_hooks(fingers_open):
    """Slid on along -x from clear of the hooks' tips to its seat, it touches no finger."""
    r = _robot(0.2)
    placed = r.build_placed(fingers_open=fingers_open)
    rs = r.ring_spec
    reach = rs.lip_mm + rs.clearance_mm + rs.hook_mm + rs.retainer_mm + 1.0
    ret = _role(placed, "retainer")[0]
    fingers = [_m(p) for p in _role(placed, "finger")]
    for k in range(9):
        m = _m(_moved(ret, dx=reach * (1 - k / 8)))
        assert all(_iv(m, f) <= FREE_MM3 for f in fingers), k


def test_the_retainer_screws_line_up_with_the_housing_inserts_and_are_in_the_bom():
    from cubot_cad.hardware.fasteners import countersunk_head_mm, thread

    r = _robot(0.2)
    rs, hs = r.ring_spec, r.housing
    placed = r.build_placed()
    ret = _role(placed, "retainer")[0].part.build()
    housing = hs.build()
    ins = thread(rs.retainer_screw_size)
    from cubot_cad.shapes import X, cyl

    for y, z in rs.retainer_screw_points_mm:
        # the insert hole is empty in the housing, the screw's clearance hole empty in the plate
        probe_h = cyl(ins.insert_hole_mm / 2 - 0.05, ins.insert_length_mm, (hs.front_mm - ins.insert_length_mm, y,
                                                                             rs.centre_z_mm + z), X)
        assert housing.intersect(probe_h).Volume() == pytest.approx(0.0, abs=1e-6)
        probe_p = cyl(ins.nominal_mm / 2, rs.retainer_mm, (hs.front_mm, y, rs.centre_z_mm + z), X)
        assert ret.intersect(probe_p).Volume() == pytest.approx(0.0, abs=1e-6)
    uses = [u for u in r.fasteners() if "retainer" in u.where]
    kind = countersunk_head_mm(rs.retainer_screw_size)[2]
    assert {(u.kind, u.size, u.count) for u in uses} == {(kind, "M2", 2), ("insert", "M2", 2)}
    screw = next(u for u in uses if u.kind == kind)
    assert rs.retainer_mm + ins.insert_length_mm / 2 <= screw.length_mm <= rs.retainer_mm + ins.insert_length_mm
    parts = dict((p.name, n) for p, n in r.printable_parts())
    assert parts["octbot_finger_retainer"] == 1


def test_retainer_dimensions_that_cannot_hold_are_refused():
    from cubot_cad.errors import InputError
    from cubot_cad.robots.octbot import RingSpec

    with pytest.raises(InputError, match="shoulder_mm"):
        RingSpec(shoulder_mm=0.5, clearance_mm=0.2)
    with pytest.raises(InputError, match="retainer_mm"):
        RingSpec(retainer_mm=1.5)
    with pytest.raises(InputError, match="retainer_screw_radius_mm"):  # heads into the finger slots
        RingSpec(retainer_screw_radius_mm=4.0)
    from cubot_cad.robots.octbot import OctBot

    with pytest.raises(InputError, match="retainer_screw_radius_mm"):  # inserts into the centre pocket
        OctBot(ring=RingSpec(retainer_screw_radius_mm=6.0))
    with pytest.raises(InputError, match="retainer_screw_radius_mm"):  # inserts out of the housing's top
        OctBot(ring=RingSpec(retainer_screw_radius_mm=19.0))
    with pytest.raises(InputError, match="countersunk"):
        RingSpec(retainer_screw_size="M2.5")
