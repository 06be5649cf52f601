"""The side rail in pitch over the overlap the rails really engage (issue 12): not about the
rail's own axis (roll). Hand formula from the record's lips; the overlap from the CAD's rail."""

from __future__ import annotations

from dataclasses import replace

import pytest

from structure_fem.couplings import connector_sources as cs
from structure_fem.errors import InputError


def test_pitch_stiffness_and_play_follow_the_overlap(cubot):
    rec = cubot.connector("side_rail")
    d = rec.play_of("rail_vertical").play_m
    a = cs.rail_in_pitch(rec, 0.08, 0.03)
    b = cs.rail_in_pitch(rec, 0.08, 0.06)
    q = rec.axial_stiffness_n_per_m / 0.08
    assert a.rotational_stiffness_nm_per_rad == pytest.approx(q * 0.03 ** 3 / 12, rel=1e-12)
    assert a.shear_stiffness_n_per_m == pytest.approx(q * 0.03, rel=1e-12)
    assert a.backlash_rad == pytest.approx(2 * d / 0.03, rel=1e-12)
    # twice the overlap: 8x the pitch stiffness, half the pitch play, twice the vertical stiffness
    assert b.rotational_stiffness_nm_per_rad == pytest.approx(8 * a.rotational_stiffness_nm_per_rad, rel=1e-12)
    assert b.backlash_rad == pytest.approx(a.backlash_rad / 2, rel=1e-12)
    assert b.shear_stiffness_n_per_m == pytest.approx(2 * a.shear_stiffness_n_per_m, rel=1e-12)
    assert a.axial_stiffness_n_per_m == rec.axial_stiffness_n_per_m and a.play == rec.play  # along the rail: kept
    for bad in (0.0, 0.09):
        with pytest.raises(InputError, match="overlap"):
            cs.rail_in_pitch(rec, 0.08, bad)


@pytest.fixture
def no_fe(monkeypatch, tmp_path):
    """No FE result of the rail or the key anywhere (an empty cache, nothing packaged): the hand formulas."""
    monkeypatch.setattr(cs, "packaged_fe", lambda: [])
    return tmp_path


def test_with_the_packaged_fe_the_rail_in_pitch_uses_the_fe_q(cubot, tmp_path):
    """Since the side rail's FE is packaged (issue 12; tests/structure_fem/test_coupling_fe_rail_key.py):
    the same pitch formulas with the FE's q, ``provenance "fe: ..."``."""
    rec = cubot.connector("side_rail")
    robot, notes = cs.resolve(cubot, "fe", cache_dir=tmp_path)
    rail = robot.connector("side_rail")
    fe, _ = cs.fe_side_rail_for(cubot, cache_dir=tmp_path)
    assert rail == cs.rail_in_pitch(rec, 0.08, 0.03, aligned_overlap_m=0.08, fe=fe)
    assert rail.provenance.startswith("fe: ") and "pitch over the 30 mm staggered overlap" in rail.provenance
    assert "pitch over the staggered overlap" in notes["side_rail"]


def test_the_fe_source_puts_the_packaged_cubot_rail_in_pitch_over_30_mm(cubot, no_fe):
    """Without an FE result: the record's hand formula (the expectation before the rail's FE was packaged)."""
    rec = cubot.connector("side_rail")
    robot, notes = cs.resolve(cubot, "fe", cache_dir=no_fe)
    rail = robot.connector("side_rail")
    # CAD: 80 mm rails, staggered by half a 100 mm pitch: 30 mm engaged (aligned: 80 mm, merged bodies)
    want = cs.rail_in_pitch(rec, 0.08, 0.03)
    assert rail == replace(want, provenance=rail.provenance)
    assert rail.provenance.startswith("hand formula: rail in pitch over the 30 mm staggered overlap")
    assert "pitch over the staggered overlap" in notes["side_rail"]
    assert rail.rotational_stiffness_nm_per_rad != rec.rotational_stiffness_nm_per_rad
    # the record's own values stay available
    assert cs.resolve(cubot, "properties")[0].connector("side_rail") == rec
    # a rail that is not the parametric CuBot's hand formula is left as it is, and the note says why
    edited = cubot.with_connector(replace(rec, axial_stiffness_n_per_m=2 * rec.axial_stiffness_n_per_m))
    robot2, notes2 = cs.resolve(edited, "fe", cache_dir=no_fe)
    assert robot2.connector("side_rail") == edited.connector("side_rail")
    assert "not the parametric CuBot" in notes2["side_rail"]


def test_the_twist_key_gets_its_own_horizontal_stiffness(cubot, no_fe):
    """Horizontal (x) from the key stem, not the arms' vertical bending value; vertical (z) and
    pitch stay the arms'. A thicker stem is stiffer; shear is in series with bending. (Without an
    FE result of the key: with the packaged one, see test_coupling_fe_rail_key.py.)"""
    rec = cubot.connector("top_twist")
    key = cs.resolve(cubot, "fe", cache_dir=no_fe)[0].connector("top_twist")
    assert key.shear_stiffness_n_per_m == rec.axial_stiffness_n_per_m  # the arms' vertical value, now along z
    assert key.rotational_stiffness_nm_per_rad == rec.rotational_stiffness_nm_per_rad
    assert key.axial_stiffness_n_per_m != rec.axial_stiffness_n_per_m
    assert key.provenance.startswith("hand formula: horizontal (x) = the key stem")
    # the packaged geometry: 8 mm stem, 3.2 mm bore, 5.85 mm from the thrust disc to the roof's centre
    E = cubot.youngs_modulus_pa
    assert key.axial_stiffness_n_per_m == pytest.approx(cs.key_horizontal_stiffness(E, 0.008, 0.0032, 0.00585),
                                                        rel=1e-9)
    import math

    i_area = math.pi * (0.008 ** 4 - 0.0032 ** 4) / 64
    bend = 3 * E * i_area / 0.00585 ** 3
    area = math.pi * (0.008 ** 2 - 0.0032 ** 2) / 4
    shear = cs.KEY_SHEAR_COEFFICIENT * E / (2 * (1 + cs.KEY_POISSON)) * area / 0.00585
    assert cs.key_horizontal_stiffness(E, 0.008, 0.0032, 0.00585) == pytest.approx(1 / (1 / bend + 1 / shear))
    assert cs.key_horizontal_stiffness(E, 0.010, 0.0032, 0.00585) > key.axial_stiffness_n_per_m
    assert cs.key_horizontal_stiffness(E, 0.008, 0.0032, 0.008) < key.axial_stiffness_n_per_m
    with pytest.raises(InputError, match="bore"):
        cs.key_horizontal_stiffness(E, 0.008, 0.009, 0.005)
    # the pier's key (vertical, in compression) is unchanged by it
    from structure_fem.analysis.piers import pier_stiffness
    from structure_fem.model.connectors import ConnectorSet

    robot = cs.resolve(cubot, "fe", cache_dir=no_fe)[0]
    assert pier_stiffness(robot, ConnectorSet.from_robot(robot), 2).key_n_per_m == rec.axial_stiffness_n_per_m
