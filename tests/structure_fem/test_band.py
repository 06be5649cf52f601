"""The thresholds' uncertainty band (issue 38, deliverable 3): stated distributions sampled by a
seeded Latin hypercube, each sample's threshold by the table's own search, quantiles that say
what share of prints span a width, and a pick that the table and limits.json use."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

pytest.importorskip("exudyn")

from structure_fem.analysis import band as bandmod  # noqa: E402
from structure_fem.analysis.band import (  # noqa: E402
    FACTORS,
    Factor,
    apply_pick,
    band,
    perturbed,
    quantile_reached,
    samples,
)
from structure_fem.errors import InputError  # noqa: E402


def test_quantiles_say_what_share_of_the_samples_reach_a_width():
    v = [3] + [5] * 18 + [6]  # 20 samples: one print spans 3, one 6
    assert quantile_reached(v, 5) == 5  # 19 of 20 (95 %) reach 5
    assert quantile_reached(v, 50) == 5 and quantile_reached(v, 95) == 6
    assert quantile_reached([3, 3] + [5] * 18, 5) == 3  # two at 3: only 90 % reach 5
    with pytest.raises(InputError):
        quantile_reached([], 5)


def test_every_factor_states_its_source_and_the_samples_follow_its_distribution():
    assert {f.name for f in FACTORS} == {"play", "stiffness", "modulus", "mass"}
    assert all(f.source and f.applies_to for f in FACTORS)
    x = samples(400, seed=1)
    assert x.shape == (400, 4) and np.array_equal(x, samples(400, seed=1))  # seeded
    col = {f.name: x[:, k] for k, f in enumerate(FACTORS)}
    assert col["play"].min() >= 0 and col["play"].mean() == pytest.approx(1.0, abs=0.03)
    assert col["play"].std() == pytest.approx(0.25, rel=0.1)
    assert np.median(col["stiffness"]) == pytest.approx(1.0, abs=0.03)
    assert 0.65 <= col["modulus"].min() and col["modulus"].max() <= 1.0
    assert col["modulus"].mean() == pytest.approx((0.65 + 0.85 + 1.0) / 3, abs=0.01)
    # a Latin hypercube: each of the 400 equal-probability strata of a factor holds one sample
    from scipy import stats

    m = next(f for f in FACTORS if f.name == "modulus")
    u = stats.triang.cdf(col["modulus"], (m.mode - m.low) / (m.high - m.low), loc=m.low, scale=m.high - m.low)
    assert len(set(np.floor(u * 400).astype(int))) == 400
    with pytest.raises(InputError, match="samples"):
        samples(2)


def test_a_sample_scales_the_inputs_it_names(make_robot):
    from structure_fem.analysis.study import StudyInputs

    inp = StudyInputs.for_robot(make_robot(backlash=0.01), 15.0)
    p = perturbed(inp, [2.0, 1.5, 0.8, 1.1])
    fr, fr0 = p.connectors.front_rear, inp.connectors.front_rear
    assert fr.backlash_rad == pytest.approx(2.0 * fr0.backlash_rad)
    assert fr.rotational_nm_per_rad == pytest.approx(1.5 * 0.8 * fr0.rotational_nm_per_rad)  # stiffness x modulus
    assert p.robot.youngs_modulus_pa == pytest.approx(0.8 * inp.robot.youngs_modulus_pa)  # the bodies' bending
    assert p.robot.mass_kg == pytest.approx(1.1 * inp.robot.mass_kg)


@pytest.fixture(scope="module")
def derivation():
    """A cheap static derivation of the packaged CuBot (line and the 4 x 2 arch, 3 mm clearance)."""
    from structure_fem.analysis.study import Derivation, levels_of, structure_curve
    from structure_fem.model.structures import Structure
    from structure_fem.outputs.runs import RunOptions, make_inputs

    inp, _ = make_inputs(RunOptions(dynamic=False, clearance_mm=3.0, max_width=8))
    curves = [structure_curve(s, inp, 0, dynamic=False)
              for s in (Structure("line"), Structure("arch", 4, 2, "staggered"))]
    return Derivation(inp, curves, levels_of(curves))


def test_the_band_moves_with_its_inputs_and_the_pick_retiles_the_table(derivation, monkeypatch):
    nominal = {c.structure.name: c.threshold for c in derivation.curves}
    assert nominal["line"] >= 1
    b = band(derivation, n=6, workers=2)
    for s in b.structures:
        q = b.quantiles[s]
        assert q[5] <= q[50] <= q[95] and len(b.thresholds[s]) == 6
    # the samples run side by side in processes; in one process the band is the same, sample by sample
    assert band(derivation, n=6, workers=1).thresholds == b.thresholds
    # no spread: every sample is the drawn robot, the band is the nominal threshold
    exact = tuple(replace(f, kind="normal", mean=1.0, sd=1e-9, low=0.0) for f in FACTORS)
    monkeypatch.setattr(bandmod, "FACTORS", exact)
    monkeypatch.setattr(bandmod, "samples", lambda n, seed, factors=exact: np.ones((n, 4)))
    flat = band(derivation, n=4)
    assert all(flat.quantiles[s] == {5: nominal[s], 50: nominal[s], 95: nominal[s]} for s in flat.structures)
    # every print with twice the play: the band drops below the drawn robot's threshold
    monkeypatch.setattr(bandmod, "samples", lambda n, seed, factors=exact: np.tile([2.0, 1.0, 1.0, 1.0], (n, 1)))
    loose = band(derivation, n=4)
    assert loose.quantiles["line"][50] < nominal["line"]
    d = replace(derivation, curves=[replace(c) for c in derivation.curves])
    before = apply_pick(d, loose, "p5")
    assert before == nominal and d.curve("line").threshold == loose.quantiles["line"][5]
    assert d.levels[0][2] == d.curve("line").threshold or d.levels[0][0].name != "line"
    with pytest.raises(InputError, match="--pick"):
        apply_pick(d, loose, "p99")


def test_fem_table_band_on_request(cli, tmp_path, monkeypatch):
    """`fem table --band N`: the band per structure in --json, the table's section, the note in
    limits.json; the thresholds at the pick. Bad --band / --pick: exit 2, nothing written."""
    import structure_fem.analysis.study as study
    import structure_fem.outputs.runs as runs

    every = study.candidate_structures
    monkeypatch.setattr(study, "candidate_structures",
                        lambda conn, narrow=False: [s for s in every(conn, narrow) if s.name in ("line", "arch-4x2-staggered")])
    monkeypatch.setattr(runs, "tapered_arches", lambda d, thesis=None, progress=None: [])
    res = cli("fem", "table", "--static", "--clearance-mm", "3", "--max-width", "6", "--band", "4",
              "--out", str(tmp_path / "t"), "--json")
    assert res.code == 0, res.err
    out = res.json()
    b = out["band"]
    assert b["pick"] == "p5" and len(b["samples"]) == 4 and {f["name"] for f in b["factors"]} == {
        "play", "stiffness", "modulus", "mass"}
    line = b["per_structure"]["line"]
    assert out["thresholds"]["line"] == min(line["p5"], line["nominal"]) and line["nominal"] == b["nominal_thresholds"]["line"]
    assert "## Uncertainty band" in (tmp_path / "t" / "selection_table.md").read_text()
    assert "picked at p5" in json.loads((tmp_path / "t" / "limits.json").read_text())["notes"]
    for argv in (("--band", "2"), ("--band", "1", "--pick", "p5")):
        bad = cli("fem", "table", "--static", *argv, "--out", str(tmp_path / "bad"))
        assert bad.code == 2 and len(bad.error_lines) == 1 and "--band" in bad.error_lines[0]
        assert not (tmp_path / "bad").exists()
    bad = cli("fem", "table", "--static", "--band", "--pick", "p95", "--out", str(tmp_path / "bad"))
    assert bad.code == 2 and not (tmp_path / "bad").exists()


def test_an_unknown_distribution_is_refused():
    with pytest.raises(InputError, match="distribution"):
        Factor("x", "weibull").ppf(np.array([0.5]))


def test_the_band_plot_is_drawn_and_linked_from_the_table(cli, tmp_path, monkeypatch):
    import structure_fem.analysis.study as study
    import structure_fem.outputs.runs as runs

    every = study.candidate_structures
    monkeypatch.setattr(study, "candidate_structures",
                        lambda conn, narrow=False: [s for s in every(conn, narrow) if s.name == "line"])
    monkeypatch.setattr(runs, "tapered_arches", lambda d, thesis=None, progress=None: [])
    res = cli("fem", "table", "--static", "--clearance-mm", "3", "--max-width", "5", "--band", "4", "--pick",
              "nominal", "--out", str(tmp_path / "t"), "--json")
    assert res.code == 0, res.err
    out = res.json()
    png = tmp_path / "t" / "threshold_band.png"
    assert out["files"]["band_plot"] == str(png) and png.stat().st_size > 5000
    assert "](threshold_band.png)" in (tmp_path / "t" / "selection_table.md").read_text()
    assert out["thresholds"]["line"] == out["band"]["nominal_thresholds"]["line"]  # --pick nominal
