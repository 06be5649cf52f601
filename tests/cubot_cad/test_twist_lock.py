"""The CuBot's twist-lock turns (issue 15, item 1): the cross key turns on a shaft in a fixed bearing
ring, driven by a named servo (cubot_cad.hardware.servos) through its horn, and locks.

Motion test in the docked top-down pair (robot B on robot A's cover, the measured docked offset):
the turning set (key, horn, horn screws, servo spline) is swept through the drive's 90 deg of travel
and must touch nothing (its own bearing ring, B's floor and servo bosses, the servo, every stand-in,
A's collar); turned to the lock it must hold when B is lifted, open it must lift out. Volumes are
manifold3d intersections (mm^3), as cubot_cad.checks.docking measures pairs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cubot_cad.checks.docking import (
    CONTACT_MM3,
    intersection_volume,
    manifold_of,
    to_manifold,
    union,
)
from cubot_cad.errors import InputError
from cubot_cad.piers.deck import HOLD_MM3, LIFT_MM

#: The mass lumps of the component table (no shape: a mass spread over the body), not stand-ins.
LUMPS = ("fasteners", "wiring")
STEPS = 12


@pytest.fixture(scope="module")
def cubot():
    from cubot_cad.robots.registry import make_robot

    return make_robot("cubot")


@pytest.fixture(scope="module")
def pair():
    from cubot_cad.checks.docking import dock

    return dock("cubot-top-down")


def _shift(ms, offset):
    t = tuple(float(v) for v in offset)
    return [m.translate(t) for m in ms]


def _vol(a, b) -> float:
    a, b = [x for x in a], [x for x in b]
    return 0.0 if not a or not b else intersection_volume(union(a), union(b))


def _stand_ins(robot, skip=()):
    return {f"{c.key}_{i + 1}": to_manifold(s) for c in robot.components() if c.key not in LUMPS + tuple(skip)
            for i, s in enumerate(c.solids())}


def _turning(robot, turn):
    """The turning set at ``turn`` deg clockwise: the key (printed) and the bought parts that turn."""
    placed = robot.build_placed(key_turn_deg=turn)
    key = next(p for p in placed if p.role == "cross_key")
    hw = [h for h in robot.hardware(placed) if h.moves]
    return manifold_of(key), [to_manifold(h.shape) for h in hw], placed


def _angles(robot):
    return [robot.drive_spec.travel_deg * i / STEPS for i in range(STEPS + 1)]


def _rotated(m, robot, turn):
    """Manifold ``m`` (robot frame) turned ``turn`` deg clockwise about the key's vertical axis."""
    x, y = (float(v) for v in robot.key_axis_mm)
    return m.translate((-x, -y, 0.0)).rotate((0.0, 0.0, -float(turn))).translate((x, y, 0.0))


def _moved_apart(a, b) -> float:
    """Volume (mm^3) in one of ``a``, ``b`` and not in the other."""
    return (a - b).volume() + (b - a).volume()


def test_the_key_turns_freely_through_its_travel_in_a_docked_pair(cubot, pair):
    """0..90 deg in 7.5 deg steps: the key touches neither its bearing ring nor B's floor nor A's collar,
    and nothing that turns (key, horn, horn screws, spline) touches anything of B that does not (servo
    bosses, ring screws and nuts, the servo, the motors, battery and boards) or anything of A."""
    assert cubot.drive_spec.travel_deg == 90.0 and cubot.top_spec.twist_deg == 45.0
    off = pair.offset_mm
    b_fixed_placed = [p for p in cubot.build_placed() if p.role != "cross_key"]
    ring = manifold_of(next(p for p in b_fixed_placed if p.role == "key_bearing"))
    body = manifold_of(next(p for p in b_fixed_placed if p.role == "body"))
    b_fixed = [manifold_of(p) for p in b_fixed_placed] + [to_manifold(h.shape) for h in cubot.hardware()
                                                         if not h.moves] + list(_stand_ins(cubot).values())
    a_placed = cubot.build_placed(with_locking_key=False)  # the locking key goes in after the turn
    a_cover = manifold_of(next(p for p in a_placed if p.role == "cover"))
    a_all = [manifold_of(p) for p in a_placed] + [to_manifold(h.shape) for h in cubot.hardware(a_placed)] \
        + list(_stand_ins(cubot).values())
    rows = []
    key0, hw0, _ = _turning(cubot, 0.0)
    for turn in _angles(cubot):
        # the open set turned about the key's axis (one build, not one per angle) ...
        key, hw = _rotated(key0, cubot, turn), [_rotated(h, cubot, turn) for h in hw0]
        if turn in (cubot.top_spec.twist_deg, cubot.drive_spec.travel_deg):
            # ... which is the set the robot itself places at that turn
            key_b, hw_b, _ = _turning(cubot, turn)
            # (to the tessellation: a part's outline is re-cut at each placement, 1e-4 of its volume)
            pairs = list(zip([key] + hw, [key_b] + hw_b, strict=True))
            assert all(_moved_apart(a, b) <= 1e-3 * b.volume() for a, b in pairs), turn
        moving = [key] + hw
        row = {"turn_deg": turn, "key_into_ring": _vol([key], [ring]), "key_into_floor": _vol([key], [body]),
               "key_into_lower_collar": _vol(_shift([key], off), [a_cover]),
               "turning_into_own_fixed": _vol(moving, b_fixed),
               "turning_into_lower_robot": _vol(_shift(moving, off), a_all)}
        rows.append(row)
        for k, v in row.items():
            if k != "turn_deg":
                assert v <= CONTACT_MM3, row
    assert [r["turn_deg"] for r in rows] == pytest.approx([7.5 * i for i in range(13)])
    # the measurement sees a real overlap: the key 0.3 mm off its axis rubs its ring and the floor
    key, _, _ = _turning(cubot, 0.0)
    bad = key.translate((cubot.clearance_mm + 0.3, 0.0, 0.0))
    assert _vol([bad], [body]) > 1.0 and _vol([bad], [ring]) > 1.0


def test_locked_it_holds_open_it_lifts_out(cubot, pair):
    """Turned to the lock (45 deg) and lifted 0.5 mm beyond its pull-out play, robot B runs into A's
    collar roof (it holds); open, B lifts out free all the way (the key passes the cross hole); with
    the locking key in, the key cannot turn back to open."""
    s = cubot.top_spec
    play = s.roof_under_mm - (s.head_z0_mm + s.head_mm)
    assert play == pytest.approx(cubot.clearance_mm)
    off = np.asarray(pair.offset_mm)
    a_closed = cubot.build_placed(with_locking_key=True)
    a_open = cubot.build_placed(with_locking_key=False)
    a_cover = manifold_of(next(p for p in a_closed if p.role == "cover"))
    lock = manifold_of(next(p for p in a_closed if p.role == "locking_key"))

    def robot_b(turn):
        placed = cubot.build_placed(key_turn_deg=turn)
        return [manifold_of(p) for p in placed] + [to_manifold(h.shape) for h in cubot.hardware(placed)] + \
            list(_stand_ins(cubot).values())

    def robot_a(placed):
        return [manifold_of(p) for p in placed] + [to_manifold(h.shape) for h in cubot.hardware(placed)]

    # each robot's manifolds built (and fused) once, then moved: the same solids at every height
    b_locked = [union(robot_b(s.twist_deg))]
    a_locked_all, a_open_all = [union(robot_a(a_closed))], [union(robot_a(a_open))]
    up = np.array([0.0, 0.0, play + LIFT_MM])
    locked = _vol(_shift(b_locked, off + up), a_locked_all)
    key_locked, _, _ = _turning(cubot, s.twist_deg)
    held = _vol(_shift([key_locked], off + up), [a_cover])
    assert held > 10 * HOLD_MM3 and locked >= held - 1e-6, (held, locked)
    # open: free at every height from docked to the key head above the collar
    b_open = [union(robot_b(0.0))]
    top = s.collar_mm - s.head_z0_mm + 1.0
    for dz in np.linspace(0.0, top, 9)[1:]:
        assert _vol(_shift(b_open, off + (0.0, 0.0, dz)), a_open_all) <= CONTACT_MM3, dz
    # docked and locked with the locking key in: nothing interferes; turned back open it hits the locking key
    assert _vol(_shift(b_locked, off), a_locked_all) <= CONTACT_MM3
    key_open, _, _ = _turning(cubot, 0.0)
    assert _vol(_shift([key_open], off), [lock]) > 10 * HOLD_MM3


def test_the_fixed_screws_never_turn_and_stay_in_their_holes(cubot):
    """Only the horn, its screws and the spline turn with the key; the ring's screws and nuts and the
    servo's tab screws are where the floor's and the ring's holes are at every angle (the one-piece key
    of before took its flange screws round with it, off the floor holes)."""
    from cubot_cad.shapes import Z, cyl, tight_bbox

    d = cubot.drive_spec
    turning = {h.label for h in cubot.hardware() if h.moves}
    assert turning == {"servo_horn", "horn_screw_1", "horn_screw_2", "servo_spline"}
    fixed0 = {h.label: tight_bbox(h.shape) for h in cubot.hardware() if not h.moves}
    assert len([k for k in fixed0 if k.startswith("key_bearing_screw")]) == 4
    body = manifold_of(next(p for p in cubot.placed if p.role == "body"))
    ring = manifold_of(next(p for p in cubot.placed if p.role == "key_bearing"))
    x0, y0 = cubot.key_axis_mm
    probes = [to_manifold(cyl(1.0, d.ring_mm + cubot.floor_mm + 2.0, (x0 + x, y0 + y, -d.ring_mm - 1.0), Z))
              for x, y in d.ring_screw_points()]
    assert _vol(probes, [body]) == 0.0 and _vol(probes, [ring]) == 0.0  # the holes line up
    for turn in _angles(cubot):
        _, _, placed = _turning(cubot, turn)
        now = {h.label: tight_bbox(h.shape) for h in cubot.hardware(placed) if not h.moves}
        assert now.keys() == fixed0.keys()
        for k, b in now.items():
            assert b == pytest.approx(fixed0[k], abs=1e-9), (turn, k)
        key, _, _ = _turning(cubot, turn)
        assert _vol([key], probes) == 0.0
    # and the holes are the parts' own: the printed key has no screw hole but its horn's two tap holes
    from cubot_cad.hardware.fasteners import tap_hole_mm

    r_tap = tap_hole_mm(d.horn.screw_size) / 2
    circles = [e for e in cubot.twist_key.solid.Edges() if e.geomType() == "CIRCLE"
               and abs(e.radius() - r_tap) < 1e-6]
    centres = {(round(e.Center().x, 3), round(e.Center().y, 3)) for e in circles}
    assert centres == {(round(x, 3), round(y, 3)) for x, y in d.horn_screw_points()}


def test_the_old_flange_screw_collision_is_gone(cubot, pair):
    """What the deck's engineer found: the one-piece key's flange screws (M3 x 10 + nuts, turned with
    the key) reached into the lower robot's collar roof and through the locking key's lip. Modelled as
    solids, the old screws collide (the check sees it); the new drive's screws, nuts and ring do not."""
    from cubot_cad.hardware.fasteners import thread
    from cubot_cad.shapes import Z, cyl, rotated

    s, off = cubot.top_spec, np.asarray(pair.offset_mm)
    a_closed = cubot.build_placed(with_locking_key=True)
    a_cover = manifold_of(next(p for p in a_closed if p.role == "cover"))
    lock = manifold_of(next(p for p in a_closed if p.role == "locking_key"))
    t3 = thread("M3")
    x0, y0 = cubot.key_axis_mm
    old = []
    for x, y in s.flange_screw_points():  # head on the floor inside, 10 mm down through floor + flange
        tip = cubot.floor_mm - 10.0
        shank = rotated(cyl(t3.nominal_mm / 2, 10.0, (x, y, tip), Z), Z, -s.twist_deg)
        old.append(to_manifold(shank.translate((x0, y0, 0.0))))
    roof = [_vol(_shift([m], off), [a_cover]) for m in old]
    lip = [_vol(_shift([m], off), [lock]) for m in old]
    assert sum(v > 1.0 for v in roof) == 4 and max(lip) > 1.0, (roof, lip)  # as found: 4.3 and 10.6 mm^3
    placed = cubot.build_placed(key_turned=True)
    new = [to_manifold(h.shape) for h in cubot.hardware(placed)] + \
        [manifold_of(p) for p in placed if p.role in ("key_bearing", "cross_key")]
    a_all = [manifold_of(p) for p in a_closed] + list(_stand_ins(cubot).values())
    assert _vol(_shift(new, off), a_all) <= CONTACT_MM3
    # the ring's underside stays clear of the lower robot's locking-key lip by design
    assert cubot.drive_spec.ring_mm < s.stand_mm - s.collar_mm - s.lip_mm


def test_the_servo_stand_in_fits_beside_the_parts_it_sits_by(cubot):
    """The SG90 (case and tabs) has 0 interference with every printed part and every other stand-in
    (motors, battery, boards, IR boards, latch servos, wheels); its tabs rest on the bosses and its
    screws go into the bosses' tap holes."""
    from cubot_cad.shapes import tight_bbox

    servo = next(c for c in cubot.components() if c.key == "twist_servo")
    assert servo.servo_model == "SG90" and servo.unit_mass_g == 9.0 and "TowerPro SG90" in servo.description
    sm = to_manifold(servo.solids()[0])
    for p in cubot.placed:
        assert _vol([sm], [manifold_of(p)]) <= CONTACT_MM3, p.part.name
    others = _stand_ins(cubot, skip=("twist_servo",))
    for name, m in others.items():
        assert _vol([sm], [m]) <= CONTACT_MM3, name
    for h in cubot.hardware():
        assert _vol([sm], [to_manifold(h.shape)]) <= CONTACT_MM3, h.label
    # the stand-ins it sits beside do not overlap each other either (battery moved out of the servo's way)
    near = {k: m for k, m in others.items() if k.split("_")[0] in ("battery", "main", "zigbee")}
    for k, m in near.items():
        for k2, m2 in others.items():
            if k2 != k:
                assert _vol([m], [m2]) <= CONTACT_MM3, (k, k2)
    # the tabs rest on the bosses (touching), the tap holes are under the tab holes
    d = cubot.drive_spec
    body = next(p for p in cubot.placed if p.role == "body")
    assert tight_bbox(servo.solids()[0])[2] == pytest.approx(d.case_face_mm, abs=1e-6)
    from cubot_cad.shapes import Z, box, cyl

    x0, y0 = cubot.key_axis_mm
    for x in d.boss_xs_mm():
        top = box(x0 + x - 1.5, x0 + x + 1.5, y0 - 1.5, y0 + 1.5, d.tab_z_mm - 0.05, d.tab_z_mm)
        assert body.shape.intersect(top).Volume() > 0.0  # the boss reaches the tab
        hole = cyl(0.6, d.tab_tap_depth_mm() - 0.2, (x0 + x, y0, d.tab_z_mm - d.tab_tap_depth_mm() + 0.1), Z)
        assert body.shape.intersect(hole).Volume() == pytest.approx(0.0, abs=1e-9)


def test_the_servo_drives_the_key_through_its_horn(cubot):
    """The output spline is on the key's axis and engages the horn's socket by 1.7 mm with an axial gap
    beyond the key's play (the servo carries no axial load); the horn is screwed to the key's hub face
    with two M2 x 5 into tap holes 4.1 mm deep; the hub face is above the drive motors."""
    from cubot_cad.shapes import tight_bbox

    d = cubot.drive_spec
    spline = next(h for h in cubot.hardware() if h.label == "servo_spline")
    b = tight_bbox(spline.shape)
    x0, y0 = cubot.key_axis_mm
    assert ((b[0] + b[3]) / 2, (b[1] + b[4]) / 2) == pytest.approx((x0, y0), abs=1e-6)
    assert d.spline_engagement_mm == pytest.approx(d.horn.socket_depth_mm - cubot.clearance_mm - d.spline_gap_mm)
    assert d.spline_engagement_mm >= 1.5 and d.spline_end_gap_mm > cubot.clearance_mm
    hs = d.horn_screw()
    assert (hs.size, hs.length_mm, hs.kind) == ("M2", 5.0, "ISO 4762")
    assert hs.length_mm - d.horn.arm_mm >= 3.0 and d.horn_tap_depth_mm() > hs.length_mm - d.horn.arm_mm
    motor = next(c for c in cubot.components() if c.key == "drive_motor")
    assert d.hub_top_mm >= max(p[2] for p in motor.positions_mm) + motor.size_mm[2] / 2 + 0.3
    horn = next(h for h in cubot.hardware() if h.label == "servo_horn")
    hb = tight_bbox(horn.shape)
    assert hb[2] == pytest.approx(d.hub_top_mm, abs=1e-6)  # seated on the hub face
    assert d.horn_boss_margin_deg(cubot.body.servo_boss_inner_mm) > 3.0


def test_the_servo_turns_the_key_with_a_margin(cubot):
    """Friction of the key's head on the collar roof and of its disc on the ring (mu 0.5) with the upper
    robot hanging from the key (its own weight): the SG90's 1.8 kgf cm stall torque is 5 times that."""
    from cubot_cad.couplings.twist import turning_torque_nm

    d, s = cubot.drive_spec, cubot.top_spec
    sv = d.servo_row
    assert sv.stall_torque_nm == pytest.approx(1.8 * 0.0980665)
    w = cubot.mass_properties().mass_kg * 9.80665
    t = turning_torque_nm(s, d, w)
    assert 0.02 < t < 0.05, t
    assert sv.stall_torque_nm / t > 4.0
    # the tension it can still turn against, and no load at all
    assert turning_torque_nm(s, d, 0.0) == 0.0
    f_max = sv.stall_torque_nm / turning_torque_nm(s, d, 1.0)
    assert 15.0 < f_max < 30.0, f_max


def test_the_new_parts_print_and_say_so(cubot, tmp_path):
    """The repository's printability check (watertight, manifold, on the bed, walls >= 0.8 mm) on the
    twist key and the bearing ring as exported; the key needs a support under its disc (recorded)."""
    from cubot_cad.checks.check import check_file
    from cubot_cad.mesh import mesh_of

    for part in (cubot.twist_key, cubot.key_bearing, cubot.body):
        stl = tmp_path / f"{part.name}.stl"
        stl.write_bytes(mesh_of(part.printable).export(file_type="stl"))
        c = check_file(stl, do_slice=False)
        assert c.ok and c.watertight and c.manifold and c.thinnest_wall_mm >= 0.8, (part.name, c)
    assert cubot.twist_key.print_settings()["supports"] and not cubot.key_bearing.print_settings()["supports"]


def test_the_bill_of_materials_lists_the_drive(cubot):
    from cubot_cad.outputs.bom import bom_rows

    rows = {r["item"]: r for r in bom_rows(cubot, 1040.0)}
    assert rows["twist_key"]["category"] == "printed" and int(rows["twist_key"]["quantity"]) == 1
    assert rows["key_bearing"]["category"] == "printed" and int(rows["key_bearing"]["quantity"]) == 1
    assert rows["twist_servo"]["category"] == "bought" and "SG90" in rows["twist_servo"]["description"]
    assert "tabs 32.38 mm" in rows["twist_servo"]["size"] and float(rows["twist_servo"]["unit_mass_g"]) == 9.0
    assert rows["twist_horn"]["category"] == "bought" and int(rows["twist_horn"]["quantity"]) == 1
    assert int(rows["M2x5 ISO 4762"]["quantity"]) == 2 and "horn" in rows["M2x5 ISO 4762"]["where"]
    assert int(rows["M2x8 ISO 4762"]["quantity"]) == 2 and "SG90" in rows["M2x8 ISO 4762"]["where"]
    assert int(rows["M3x10 ISO 10642"]["quantity"]) == 4 and "bearing" in rows["M3x10 ISO 10642"]["where"]
    assert "key bearing" in rows["M3 ISO 4032"]["where"]
    assert "cross-key flange" not in " ".join(r["where"] for r in rows.values())
    assert rows["cross_key"]["category"] == "pier"  # the flanged key is the pier deck's only


@pytest.mark.parametrize("kw, word", [
    ({"servo": "SG91"}, "servo 'SG91'"),
    ({"hub_top_mm": 12.0}, "TwistDriveSpec.hub_top_mm 12"),  # the horn would turn into the drive motors
    ({"horn_open_deg": 90.0}, "TwistDriveSpec.horn_open_deg 90"),  # the horn would sweep over a servo boss
    ({"ring_lip_mm": 3.0}, "locking key"),  # the ring would reach the lower robot's locking key
    ({"shaft_diameter_mm": 11.0}, "TwistDriveSpec.shaft_diameter_mm 11"),  # no wall round the horn's taps
    ({"disc_diameter_mm": 15.0}, "TwistDriveSpec.disc_diameter_mm 15"),
    ({"wire_slot_deg": 135.0}, "TwistDriveSpec.wire_slot_deg 135"),  # into a horn screw
])
def test_bad_drive_dimensions_are_one_line_input_errors(kw, word):
    from cubot_cad.couplings.twist import TwistDriveSpec
    from cubot_cad.robots.cubot import CuBot

    with pytest.raises(InputError) as exc:
        CuBot(drive=TwistDriveSpec(**kw)).twist_key.volume_mm3  # noqa: B018 (parts validate on build)
    assert "\n" not in str(exc.value) and word in str(exc.value), str(exc.value)


def test_the_metal_gear_servo_fits_too():
    """The table's MG90S (taller, metal gears) builds: the boards move up over it, nothing overlaps it."""
    from cubot_cad.couplings.twist import TwistDriveSpec
    from cubot_cad.robots.cubot import CuBot

    r = CuBot(drive=TwistDriveSpec(servo="MG90S"))
    servo = next(c for c in r.components() if c.key == "twist_servo")
    sm = to_manifold(servo.solids()[0])
    board = next(c for c in r.components() if c.key == "main_board")
    assert board.positions_mm[0][2] - board.size_mm[2] / 2 >= r.drive_spec.servo_top_mm
    for name, m in _stand_ins(r, skip=("twist_servo",)).items():
        assert _vol([sm], [m]) <= CONTACT_MM3, name
    for p in r.placed:
        if p.role in ("body", "cross_key", "key_bearing"):
            assert _vol([sm], [manifold_of(p)]) <= CONTACT_MM3, p.part.name
    assert math.isclose(servo.unit_mass_g, 13.4)
