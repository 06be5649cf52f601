"""Shared fixtures for structure_fem tests: robot records built in the test (so the numbers the
tests derive from are visible here) and the packaged record (for expectations derived from it)."""

from __future__ import annotations

import pytest

from cubot_cad.properties import (
    ConnectorProperties,
    GroundContact,
    RobotProperties,
    default_properties,
)

#: The CuBot's contacts (cubot_cad.robots.cubot defaults: casters 38 mm fore and aft of the wheels' axle at
#: the centre, all 15 mm below the underside), for test robots that stand on wheels.
CUBOT_LIKE_CONTACTS = ((-0.038, "caster"), (0.0, "wheel"), (0.038, "caster"))


def make_robot(mass=0.3, k=200.0, k_ax=2e5, backlash=0.0, com_x=0.0, name="testbot",
               contacts=None, contact_z=-0.015) -> RobotProperties:
    """A test robot; ``contacts``: ``((x_m, feature), ...)`` of its ground contacts (None: none in
    the record, so it rests on its body corners)."""
    L, W, H = 0.1, 0.1, 0.085
    iyy = mass * (L ** 2 + H ** 2) / 12
    ixx = mass * (W ** 2 + H ** 2) / 12
    izz = mass * (L ** 2 + W ** 2) / 12
    conns = (
        ConnectorProperties("front_rear", k, k_ax, backlash, 0.0, 0.03),
        ConnectorProperties("side_rail", k, k_ax, backlash, 0.0, 0.01),
        ConnectorProperties("top_twist", k, k_ax, backlash, 0.0, H),
    )
    gc = None if contacts is None else tuple(GroundContact(f, x, contact_z) for x, f in contacts)
    return RobotProperties(name, L, W, H, mass, (com_x, 0.0, 0.04), (ixx, iyy, izz, 0, 0, 0),
                           0.015, 0.0033, "ABS", 1040.0, 2.2e9, conns, source="test",
                           ground_contacts=gc, ground_contacts_source=None if gc is None else "test: chosen here")


@pytest.fixture(name="make_robot", scope="session")
def make_robot_fixture():
    """The factory :func:`make_robot` (robot records with explicit, test-chosen numbers)."""
    return make_robot


@pytest.fixture
def robot() -> RobotProperties:
    return make_robot()


def clearance_latch(conn, clearance_m: float = 2e-4):
    """``conn`` with the thesis's clearance latch on the front-rear coupling: 2 x ``clearance_m`` of
    tension play (head in its counterbore + blade in its groove), the pitch backlash that play over
    the highest pin, no preload. The packaged CuBot has the wedge latch since issue 38; tests about
    how the model treats play (dead bands, stalls, piers lifted off) use this one."""
    from dataclasses import replace

    fr = conn.front_rear
    play = 2 * clearance_m
    return replace(conn, front_rear=replace(fr, play_x=(0.0, play), backlash_rad=play / max(fr.levers_m),
                                            preload_n=0.0))


@pytest.fixture(name="clearance_latch", scope="session")
def clearance_latch_fixture():
    """The function :func:`clearance_latch`."""
    return clearance_latch


@pytest.fixture(scope="session")
def cubot() -> RobotProperties:
    return default_properties().get("cubot")
