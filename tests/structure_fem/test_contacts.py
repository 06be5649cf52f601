"""Supports where the robot touches the ground (issue 12, deliverable 5): wheel and caster contacts
from the CAD into the record, as the model's one-sided ledge / pier supports and tipping line."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from cubot_cad.errors import InputError as CadInputError
from cubot_cad.properties import GroundContact, RobotPropertiesFile, ground_contact_fields
from structure_fem.model.connectors import ConnectorSet
from structure_fem.model.contacts import ground_support
from structure_fem.model.structures import Structure, layout, rigid_tipping, tipping_edge

from .conftest import CUBOT_LIKE_CONTACTS


def test_cubot_contacts_come_from_its_wheels_and_casters():
    from cubot_cad.robots.cubot import CuBot

    f = ground_contact_fields(CuBot())
    got = {(c.feature, round(c.x_m, 9), round(c.z_m, 9), c.count) for c in f["ground_contacts"]}
    # casters 38 mm fore and aft, the two drive wheels side by side on the axle at x = 0, all 15 mm down
    assert got == {("caster", -0.038, -0.015, 1), ("wheel", 0.0, -0.015, 2), ("caster", 0.038, -0.015, 1)}
    assert "CuBot component table" in f["ground_contacts_source"]
    # the record's setbacks move with the CAD: casters further in sit further behind the front face
    moved = ground_contact_fields(CuBot(caster_x_mm=30.0))
    rec = default_cubot_with(f)
    assert rec.front_contact_setback_m == pytest.approx(0.012)
    assert default_cubot_with(moved).front_contact_setback_m == pytest.approx(0.020)


def test_platform_without_wheels_has_no_contacts():
    from cubot_cad.robots.platform import TestPlatform

    assert ground_contact_fields(TestPlatform()) == {}


def default_cubot_with(fields):
    from cubot_cad.properties import default_properties

    return replace(default_properties().get("cubot"), **fields)


def test_record_round_trips_and_validates_contacts(make_robot):
    r = make_robot(contacts=CUBOT_LIKE_CONTACTS)
    back = RobotPropertiesFile.from_dict(RobotPropertiesFile((r,)).to_dict()).robots[0]
    assert back == r and back.ground_contacts[1] == GroundContact("wheel", 0.0, -0.015)
    old = RobotPropertiesFile((make_robot(),)).to_dict()  # a record written before contacts existed
    for rob in old["robots"]:
        rob.pop("ground_contacts"), rob.pop("ground_contacts_source")
    assert RobotPropertiesFile.from_dict(old).robots[0].ground_contacts is None
    with pytest.raises(CadInputError, match="outside the body"):
        make_robot(contacts=((0.06, "caster"),))
    with pytest.raises(CadInputError, match="ground_contacts_source"):
        replace(r, ground_contacts_source=None)
    with pytest.raises(CadInputError, match="without ground_contacts"):
        replace(make_robot(), ground_contacts_source="x")
    with pytest.raises(CadInputError, match="feature"):
        GroundContact("skid", 0.0, -0.01)
    with pytest.raises(CadInputError, match="below the underside"):
        GroundContact("wheel", 0.0, 0.01)


def test_fallback_for_records_without_contacts(cubot, make_robot):
    g = ground_support(cubot)
    assert g.kind == "contacts" and g.setback_m(cubot.length_m) == pytest.approx(0.012)
    if cubot.ground_contacts is None:  # the packaged record predates them: the default CuBot's, said so
        assert "default parametric CuBot" in g.source
    # a record that is not the default CuBot (another length) is not given its contacts
    other = replace(cubot, length_m=0.09, ground_contacts=None, ground_contacts_source=None)
    assert ground_support(other).kind == "corners" and "not the default CuBot" in ground_support(other).source
    assert ground_support(make_robot()).kind == "corners"


def test_supports_sit_at_the_contacts_over_the_ledge(make_robot):
    from structure_fem.model.connectors import ConnectorSet

    r = make_robot(contacts=CUBOT_LIKE_CONTACTS)
    conn = ConnectorSet.from_robot(r)
    lay = layout(Structure("line"), r, conn, 7, 3, 3)
    xs = sorted(round(s.point_m[0], 9) for s in lay.supports)
    want = sorted(round(-0.1 * j - 0.05 + c, 9) for j in range(4) for c, _ in CUBOT_LIKE_CONTACTS)
    assert xs == want and all(s.point_m[1] == -0.015 for s in lay.supports)
    assert tipping_edge(lay) == pytest.approx(-0.012)  # the front caster of the front robot on the ledge
    # half a row further: the robot at the edge has its front caster over the void, its wheels on the ledge
    half = layout(Structure("line"), r, conn, 7, 3.3, 4)
    assert tipping_edge(half) == pytest.approx(-0.02)
    bridged = layout(Structure("line"), r, conn, 7, 5, 3, "bridged")
    assert sum(s.ledge == "far" for s in bridged.supports) == 3 * 2
    # a staggered line's robot at the edge has its wheels exactly on it: leaving, not a support
    stag = layout(Structure("two_line", 2, 1, "staggered"), r, conn, 7, 3, 3)
    assert all(s.point_m[0] < 0 for s in stag.supports)
    assert tipping_edge(stag) == pytest.approx(-0.012)


def _rigid_line_factor(n_p, n_g, a, s):
    """Rigid uniform line, ``n_p`` robots on the ledge, ``n_g`` over it, tipping about a line ``s``
    behind the edge: restoring sum (i - 1/2) a - s, overturning sum (j - 1/2) a + s."""
    back = sum((i - 0.5) * a - s for i in range(1, n_p + 1))
    over = sum((j - 0.5) * a + s for j in range(1, n_g + 1))
    return back / over


@pytest.mark.parametrize("n_p,n_g", [(4, 3), (6, 4), (11, 10)])
def test_contacts_tip_sooner_than_corners(n_p, n_g, make_robot):
    from structure_fem.model.statics import Config, solve

    s = Structure("line")
    on_corners = make_robot(k=2e4, k_ax=1e8)
    on_wheels = make_robot(k=2e4, k_ax=1e8, contacts=CUBOT_LIKE_CONTACTS)
    cfg = Config(s, n_p + n_g, n_g, n_g)
    a = on_corners.length_m

    def lumped(r):  # near-rigid couplings: one point spring each (the hinge model is not the subject)
        return replace(ConnectorSet.from_robot(r), hinge="lumped")

    tf_c = solve(cfg, on_corners, lumped(on_corners)).tipping_factor
    tf_w = solve(cfg, on_wheels, lumped(on_wheels)).tipping_factor
    assert tf_c == pytest.approx(_rigid_line_factor(n_p, n_g, a, 0.0), rel=0.01)
    assert tf_w == pytest.approx(_rigid_line_factor(n_p, n_g, a, 0.012), rel=0.01)
    assert tf_w < tf_c * (1 - 0.02)


def test_moving_the_contact_back_lowers_the_tipping_factor(make_robot):
    from structure_fem.analysis.study import StudyInputs, min_rows
    from structure_fem.model.connectors import ConnectorSet
    from structure_fem.model.statics import Config, solve

    factors, rows = [], []
    for front in (0.045, 0.038, 0.025, None):  # None: no front caster, it tips about its wheels
        contacts = ((-0.038, "caster"), (0.0, "wheel")) + (() if front is None else ((front, "caster"),))
        r = make_robot(contacts=contacts)
        lay = layout(Structure("line"), r, ConnectorSet.from_robot(r), 12, 5, 5)  # 7 on the ledge: all stand
        factors.append((rigid_tipping(lay), solve(Config(Structure("line"), 12, 5, 5), r).tipping_factor))
        rows.append(min_rows(Structure("line"), 5, StudyInputs.for_robot(r, 40.0))[0])
    assert factors[0][0] > factors[1][0] > factors[2][0] > factors[3][0]
    assert factors[0][1] > factors[1][1] > factors[2][1] > factors[3][1]
    assert rows == sorted(rows) and rows[0] < rows[-1]  # more rows needed on the ground to stand


def test_piers_rest_on_the_contacts_over_the_top(make_robot):
    from structure_fem.model.connectors import ConnectorSet
    from structure_fem.model.structures import Pier

    r = make_robot(contacts=CUBOT_LIKE_CONTACTS)
    pier = Pier(3.0, 1e6)
    lay = layout(Structure("line"), r, ConnectorSet.from_robot(r), 10, 5, 6, piers=(pier,))
    on = sorted(round(s.point_m[0], 9) for s in lay.supports if s.pier == 0)
    assert on == [0.312, 0.35, 0.388]  # the robot right over [0.3, 0.4]: its casters and wheels
    assert tipping_edge(lay) == pytest.approx(0.388)  # its front caster, 12 mm short of the far face


def test_the_tipping_factor_is_the_restoring_over_the_overturning_gravity_moment(make_robot):
    """One home for the moments: the anchored fallback's tipping factor takes them from
    ``gravity_moments``, the same sums the tipping factor divides."""
    from structure_fem.model.connectors import ConnectorSet
    from structure_fem.model.structures import GRAVITY, gravity_moments, tipping_factor

    r = make_robot(contacts=CUBOT_LIKE_CONTACTS)
    lay = layout(Structure("line"), r, ConnectorSet.from_robot(r), 9, 4, 4)
    com_x = np.array([b.com_m[0] for b in lay.bodies])
    back, over = gravity_moments(lay.bodies, com_x, 0.0)
    # every body is on one side or the other: the difference is the weight's first moment
    assert back - over == pytest.approx(-GRAVITY * float(np.sum([b.mass_kg * x for b, x in zip(lay.bodies, com_x, strict=True)])))
    assert back > 0 and over > 0
    assert tipping_factor(lay.bodies, com_x, 0.0) == pytest.approx(back / over, rel=1e-12)
    assert gravity_moments(lay.bodies, com_x, 1.0)[1] == 0.0  # nothing beyond a far edge
