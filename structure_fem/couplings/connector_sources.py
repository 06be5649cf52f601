"""Where each connector value the model uses comes from: the record's hand formula, the FE, a measurement.

``robot_properties.json`` (written by `cubot_cad`, which must not import this package) holds
the hand-formula stiffness of every coupling with ``provenance = "hand formula: ..."`` and the
play per feature from the CAD's clearances. This module puts the finite-element result of
:mod:`structure_fem.couplings.connector_fe` in its place where one exists for the record's geometry:

* :func:`fe_front_rear_for` recognises the CuBot's or Cube Robot's front-rear coupling of a record
  (:data:`FE_ROBOTS`): it rebuilds the parametric robot at the record's print clearance (tension
  play / 2) and accepts it only
  if its hand formula gives exactly the record's values (same geometry, same modulus); then it
  looks the FE result up by the sha256 of geometry + material + mesh (``connector_fe.input_hash``)
  in the user cache (``~/.cache/voidcross/connector_fe/``) and in the packaged results
  (``structure_fem/data/connector_fe.json``, written by :func:`write_packaged_fe`). It never
  solves (a cold FE is 2-4 minutes): ``voidcross fem connectors`` computes a missing one.
* :func:`fe_side_rail_for` and :func:`fe_top_twist_for` do the same for the CuBot's side rail and
  twist key (:mod:`structure_fem.couplings.rail_key_fe`; ``python -m structure_fem.couplings.connector_sources``
  computes missing ones and packages all three); :func:`planar_side_rail_for` and
  :func:`planar_top_twist_for` use them where they exist, else the hand formulas (with a note).
* :func:`fe_platform_bolt_for` does the same for the test platform's bolt (:mod:`structure_fem.couplings.platform_bolt_fe`):
  it rebuilds the parametric :class:`cubot_cad.robots.platform.TestPlatform` whose hand formula gives the
  record's ``bolt`` values and looks its FE up by hash; :func:`resolve` then puts the FE's stiffness
  and the play of the CAD's ISO 273 clearance hole (:func:`with_fe_bolt`) in the record's place.
* :func:`fe_octbot_ring_for` does the same for the OctBot's ring coupling (:mod:`structure_fem.couplings.octbot_ring_fe`):
  it rebuilds the parametric :class:`cubot_cad.robots.octbot.OctBot` whose hand formula gives the record's
  ``ring_capture`` values and looks its FE up by hash; :func:`resolve` then puts the FE's axial and
  pitch stiffness and the play of the CAD's two clearances in series (hooks to the lip, the fingers'
  shoulders to the retainer: :func:`with_fe_ring`) in the record's place.
* :func:`resolve` returns the robot record the model then uses: the FE values (axial, pitch
  and shear stiffness) with ``provenance = "fe: <mesh, element, solver, cache key>"``, the play
  unchanged (the FE is of the bonded, play-free load path; the play is the CAD's), and a note
  per connector saying what was used and why.
* :func:`load_measured` reads a user's measured coupling (JSON) with
  ``provenance = "measured: <file>"``.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

from cubot_cad.properties import ConnectorProperties, RobotProperties
from structure_fem.errors import InputError

#: The FE results shipped with the package (a list of ``ConnectorFE.to_dict()``).
PACKAGED_FE = Path(__file__).parents[1] / "data" / "connector_fe.json"
SOURCES = ("fe", "properties")


def _clearance_of(rec: ConnectorProperties) -> float:
    """The print clearance (mm) a front-rear record was made with: its vertical slip is two radial
    clearances (own + mating bores), as a clearance latch's tension play is (a wedge latch has none)."""
    for feature in ("vertical_slip", "tension"):
        t = rec.play_of(feature)
        if t is not None and t.play_m > 0:
            return round(t.play_m * 1e3 / 2, 9)
    return 0.2


def _same(a: float, b: float) -> bool:
    return math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-15)


#: The parametric CAD robots whose front-rear coupling :mod:`structure_fem.couplings.connector_fe` models
#: (record name -> module, class); the side rail and twist key FE are the CuBot's only.
FE_ROBOTS = {"cubot": ("cubot_cad.robots.cubot", "CuBot"), "cube-robot": ("cubot_cad.robots.cube_robot", "CubeRobot")}


def cad_robot_for_record(robot: RobotProperties):
    """The parametric CAD robot (:data:`FE_ROBOTS`) whose hand formula reproduces the record's
    front-rear coupling exactly, or ``(None, why not)``."""
    if robot.name not in FE_ROBOTS:
        return None, "no FE model of this robot's couplings yet (only of the CuBot's and the Cube Robot's)"
    try:
        rec = robot.connector("front_rear")
    except Exception:  # noqa: BLE001 - a record without one
        return None, "the record has no front_rear coupling"
    import importlib

    mod, cls = FE_ROBOTS[robot.name]
    try:
        kw = {"clearance_mm": _clearance_of(rec)}
        if robot.name == "cubot":  # which latch: the wedge preloads, the clearance latch does not
            kw["front_rear_coupling"] = "wedge" if rec.preload_n > 0 else "clearance"
        cad = getattr(importlib.import_module(mod), cls)(**kw)
    except Exception as exc:  # noqa: BLE001 - a clearance outside what the CAD can build
        return None, f"the CAD cannot rebuild the record's front-rear coupling ({exc})"
    hand = cad.connector_properties(robot.youngs_modulus_pa, {"front_rear": rec.gap_m * 1e3})[0]
    if not all(_same(getattr(hand, f), getattr(rec, f)) for f in
               ("rotational_stiffness_nm_per_rad", "axial_stiffness_n_per_m", "backlash_rad", "height_m",
                "preload_n")):
        return None, (f"the record's front-rear values are not the parametric {cls}'s hand formula at its "
                      "clearance and modulus (edited or another geometry): no FE result applies")
    return cad, ""


def cubot_for_record(robot: RobotProperties):
    """:func:`cad_robot_for_record` for a CuBot record (its side rail and twist key have FE models)."""
    if robot.name != "cubot":
        return None, "no FE model of this robot's side rail or twist key (only of the CuBot's)"
    return cad_robot_for_record(robot)


def fe_key(robot: RobotProperties, settings=None):
    """``(cubot, material, key)`` of the FE that applies to the record, or ``(None, why, None)``."""
    from structure_fem.couplings import connector_fe as cfe

    cub, why = cad_robot_for_record(robot)
    if cub is None:
        return None, why, None
    try:
        mat = cfe.Material.from_cubot_cad(robot.material.lower())
    except Exception as exc:  # noqa: BLE001
        return None, f"material {robot.material!r} has no FE material ({exc})", None
    if not _same(mat.E_pa, robot.youngs_modulus_pa):
        return None, (f"the record's modulus {robot.youngs_modulus_pa:.4g} Pa is not the FE material's "
                      f"{mat.E_pa:.4g} Pa"), None
    settings = cfe.MeshSettings() if settings is None else settings
    return (cub, mat, settings), "", cfe.input_hash(cfe.FrontRearGeometry.of(cub), mat, settings)


def packaged_fe() -> list[dict]:
    if not PACKAGED_FE.is_file():
        return []
    try:
        data = json.loads(PACKAGED_FE.read_text())
    except ValueError as exc:
        raise InputError(f"{PACKAGED_FE} is not valid JSON: {exc}") from None
    return data if isinstance(data, list) else []


def lookup_fe(key: str, cache_dir=None, cls=None, packaged: bool = True):
    """The FE result of ``key`` from the cache or the packaged results (None if neither has it).
    ``cls``: the result class (default :class:`~structure_fem.couplings.connector_fe.ConnectorFE`; the side rail's
    and the twist key's are in :mod:`structure_fem.couplings.rail_key_fe`)."""
    from structure_fem.couplings import connector_fe as cfe

    cls = cfe.ConnectorFE if cls is None else cls
    base = Path(cache_dir) if cache_dir is not None else cfe.default_cache_dir()
    f = base / f"{key}.json"
    if f.is_file():
        try:
            d = json.loads(f.read_text())
            if d.get("input_hash") == key:
                return cls.from_dict(d, cache_hit=True), "user cache"
        except (OSError, ValueError, TypeError):
            pass
    for d in packaged_fe() if packaged else ():
        if d.get("input_hash") == key:
            try:
                return cls.from_dict(d, cache_hit=True), f"packaged structure_fem/data/{PACKAGED_FE.name}"
            except TypeError:
                continue  # an entry of another kind under the same key (cannot happen: the model is hashed)
    return None, ""


def _fe_rail_key(robot: RobotProperties, which: str, cache_dir=None, compute: bool = False,
                 packaged: bool = True):
    """``(SideRailFE / TwistKeyFE or None, where it came from or why not)`` for the record's side rail
    (``which="side_rail"``) or twist key (``"top_twist"``): the parametric CuBot that reproduces the
    record (:func:`cubot_for_record`), the FE material of the record's modulus, the default mesh."""
    from structure_fem.couplings import rail_key_fe as rk

    cub, why = cubot_for_record(robot)
    if cub is None:
        return None, why
    what, why, _key = fe_key(robot)
    if what is None:
        return None, why
    cub, mat, _settings = what
    if which == "side_rail":
        mesh = rk.FEMesh(rk.RAIL_SIZE_MM)
        overlap = rail_overlap_m(robot, cub) * 1e3
        if overlap <= 0:
            return None, f"staggered rails do not overlap ({overlap:g} mm)"
        key = rk.rail_input_hash(rk.SideRailGeometry.from_cubot(cub, overlap_mm=overlap), mat, mesh)
        cls, run = rk.SideRailFE, (lambda: rk.side_rail_fe(cub, mat, mesh, cache_dir=cache_dir, overlap_mm=overlap))
    else:
        mesh = rk.FEMesh(rk.KEY_SIZE_MM)
        key = rk.key_input_hash(rk.TwistKeyGeometry.from_cubot(cub), mat, mesh)
        cls, run = rk.TwistKeyFE, (lambda: rk.twist_key_fe(cub, mat, mesh, cache_dir=cache_dir))
    fe, where = lookup_fe(key, cache_dir, cls, packaged)
    if fe is not None:
        return fe, where
    if not compute:
        return None, (f"no FE result for this {which.replace('_', ' ')} (key {key[:12]}) in the cache or the "
                      "package: `python -m structure_fem.couplings.connector_sources` computes it (under a minute cold)")
    return run(), "computed now (cached)"


def fe_side_rail_for(robot: RobotProperties, cache_dir=None, compute: bool = False, packaged: bool = True):
    """``(SideRailFE or None, where it came from or why not)`` for the record's side rail."""
    return _fe_rail_key(robot, "side_rail", cache_dir, compute, packaged)


def fe_top_twist_for(robot: RobotProperties, cache_dir=None, compute: bool = False, packaged: bool = True):
    """``(TwistKeyFE or None, where it came from or why not)`` for the record's top twist key."""
    return _fe_rail_key(robot, "top_twist", cache_dir, compute, packaged)


def fe_front_rear_for(robot: RobotProperties, cache_dir=None, compute: bool = False, packaged: bool = True):
    """``(ConnectorFE or None, where it came from or why not)`` for the record's front-rear coupling."""
    from structure_fem.couplings import connector_fe as cfe

    what, why, key = fe_key(robot)
    if key is None:
        return None, why
    fe, where = lookup_fe(key, cache_dir, packaged=packaged)
    if fe is not None:
        return fe, where
    if not compute:
        return None, (f"no FE result for this geometry (key {key[:12]}) in the cache or the package: "
                      "`voidcross fem connectors` computes it (2-4 min cold)")
    cub, mat, settings = what
    return cfe.front_rear_fe(cub, mat, settings, cache_dir=cache_dir), "computed now (cached)"


def platform_for_record(robot: RobotProperties):
    """The parametric :class:`cubot_cad.robots.platform.TestPlatform` whose hand formula reproduces the
    record's ``bolt`` coupling exactly (its print clearance is the record's backlash times the tab
    length), or ``(None, why not)``."""
    kinds = {c.kind: c for c in robot.connectors}
    if "bolt" not in kinds:
        return None, "the record has no bolt coupling (only the test platform's is modelled by FE)"
    rec = kinds["bolt"]
    from cubot_cad.robots.platform import TestPlatform

    tab = TestPlatform().tab_length_mm
    try:
        plat = TestPlatform(clearance_mm=round(rec.backlash_rad * tab, 9))
        hand = plat.connector_properties(robot.youngs_modulus_pa)[0]
    except Exception as exc:  # noqa: BLE001 - a clearance outside what the CAD can build
        return None, f"the CAD cannot rebuild the record's bolt coupling ({exc})"
    if not all(_same(getattr(hand, f), getattr(rec, f)) for f in
               ("rotational_stiffness_nm_per_rad", "axial_stiffness_n_per_m", "backlash_rad", "height_m")):
        return None, ("the record's bolt values are not the parametric TestPlatform's hand formula at its "
                      "clearance and modulus (edited or another geometry): no FE result applies")
    return plat, ""


def _fe_material(robot: RobotProperties):
    """``(Material or None, why not)``: the FE material of the record's material, if its modulus is
    the record's (an FE result at another modulus does not apply)."""
    from structure_fem.couplings import connector_fe as cfe

    try:
        mat = cfe.Material.from_cubot_cad(robot.material.lower())
    except Exception as exc:  # noqa: BLE001
        return None, f"material {robot.material!r} has no FE material ({exc})"
    if not _same(mat.E_pa, robot.youngs_modulus_pa):
        return None, (f"the record's modulus {robot.youngs_modulus_pa:.4g} Pa is not the FE material's "
                      f"{mat.E_pa:.4g} Pa")
    return mat, ""


def fe_platform_bolt_for(robot: RobotProperties, cache_dir=None, compute: bool = False, packaged: bool = True):
    """``(PlatformBoltFE or None, where it came from or why not)`` for the record's bolt (the test
    platform's lap joint, :mod:`structure_fem.couplings.platform_bolt_fe`): the parametric platform that
    reproduces the record (:func:`platform_for_record`), the FE material of the record's modulus,
    the default mesh; looked up by the hash of geometry + material + mesh."""
    from structure_fem.couplings import platform_bolt_fe as pb

    plat, why = platform_for_record(robot)
    if plat is None:
        return None, why
    mat, why = _fe_material(robot)
    if mat is None:
        return None, why
    mesh = pb.PlatformMesh()
    key = pb.input_hash(pb.PlatformBoltGeometry.from_platform(plat), mat, mesh)
    fe, where = lookup_fe(key, cache_dir, pb.PlatformBoltFE, packaged)
    if fe is not None:
        return fe, where
    if not compute:
        return None, (f"no FE result for this platform bolt (key {key[:12]}) in the cache or the package: "
                      "`python -m structure_fem.couplings.connector_sources` computes it (under a minute cold)")
    return pb.platform_bolt_fe(plat, mat, mesh, cache_dir=cache_dir), "computed now (cached)"


def octbot_for_record(robot: RobotProperties):
    """The parametric :class:`cubot_cad.robots.octbot.OctBot` whose hand formula reproduces the record's
    ``ring_capture`` coupling exactly (its print clearance is the record's tension play), or
    ``(None, why not)``."""
    kinds = {c.kind: c for c in robot.connectors}
    if "ring_capture" not in kinds:
        return None, "the record has no ring_capture coupling (only the OctBot's ring is modelled by FE)"
    rec = kinds["ring_capture"]
    t = rec.play_of("tension")
    if t is None:
        return None, "the record's ring_capture has no tension play: not the CAD's hand formula"
    from cubot_cad.robots.octbot import OctBot

    try:
        bot = OctBot(clearance_mm=round(t.play_m * 1e3, 9))
        hand = bot.connector_properties(robot.youngs_modulus_pa, {"ring_capture": rec.gap_m * 1e3})[0]
    except Exception as exc:  # noqa: BLE001 - a clearance outside what the CAD can build
        return None, f"the CAD cannot rebuild the record's ring coupling ({exc})"
    if not all(_same(getattr(hand, f), getattr(rec, f)) for f in
               ("rotational_stiffness_nm_per_rad", "axial_stiffness_n_per_m", "backlash_rad", "height_m")):
        return None, ("the record's ring_capture values are not the parametric OctBot's hand formula at its "
                      "clearance and modulus (edited or another geometry): no FE result applies")
    return bot, ""


def fe_octbot_ring_for(robot: RobotProperties, cache_dir=None, compute: bool = False, packaged: bool = True):
    """``(OctRingFE or None, where it came from or why not)`` for the record's ring coupling (the
    OctBot's fingers + retainer and ring, :mod:`structure_fem.couplings.octbot_ring_fe`): the parametric OctBot
    that reproduces the record (:func:`octbot_for_record`), the FE material of the record's modulus,
    the default mesh; looked up by the hash of geometry + material + mesh."""
    from structure_fem.couplings import octbot_ring_fe as orf

    bot, why = octbot_for_record(robot)
    if bot is None:
        return None, why
    mat, why = _fe_material(robot)
    if mat is None:
        return None, why
    mesh = orf.RingMesh()
    key = orf.input_hash(orf.OctRingGeometry.from_octbot(bot), mat, mesh)
    fe, where = lookup_fe(key, cache_dir, orf.OctRingFE, packaged)
    if fe is not None:
        return fe, where
    if not compute:
        return None, (f"no FE result for this OctBot ring (key {key[:12]}) in the cache or the package: "
                      "`python -m structure_fem.couplings.connector_sources` computes it (under a minute cold)")
    return orf.octbot_ring_fe(bot, mat, mesh, cache_dir=cache_dir), "computed now (cached)"


def _play_text(play) -> str:
    return ", ".join(f"{p.feature} {p.play_m * 1e3:.3g} mm ({p.axis}, {p.sense}; {p.cad_feature})" for p in play)


def with_fe_ring(rec: ConnectorProperties, fe) -> ConnectorProperties:
    """The record's ring coupling with the FE's stiffness (pitch about the ring's bottom edge, axial;
    no shear: the record's none stays) and the play from the CAD's two clearances in series
    (``fe.play``: hook to lip and finger shoulders to retainer, one tension play) with its pitch dead band."""
    from cubot_cad.properties import FeaturePlay

    play = tuple(FeaturePlay(**p) for p in fe.play)
    return replace(rec, rotational_stiffness_nm_per_rad=fe.rotational_stiffness_nm_per_rad,
                   axial_stiffness_n_per_m=fe.axial_stiffness_n_per_m,
                   shear_stiffness_n_per_m=fe.shear_stiffness_n_per_m
                   if math.isfinite(fe.shear_stiffness_n_per_m) else rec.shear_stiffness_n_per_m,
                   backlash_rad=fe.backlash_rad, play=play,
                   provenance=(f"{fe_provenance(fe)}; hand formula {rec.rotational_stiffness_nm_per_rad:.4g} N m/rad, "
                               f"{rec.axial_stiffness_n_per_m:.4g} N/m; play: {_play_text(play)}, rotational "
                               f"{fe.backlash_rad * 1e3:.3g} mrad (the play over the top finger's "
                               f"{fe.lever_arms_m[0] * 1e3:.3g} mm arm)"))


def with_fe_bolt(rec: ConnectorProperties, fe) -> ConnectorProperties:
    """The record's bolt with the FE's stiffness (joint alone: pitch, axial, vertical shear) and the
    play from the CAD's clearance hole (``fe.play``; no rotational dead band: head and nut clamp)."""
    from cubot_cad.properties import FeaturePlay

    play = tuple(FeaturePlay(**p) for p in fe.play)
    return replace(rec, rotational_stiffness_nm_per_rad=fe.rotational_stiffness_nm_per_rad,
                   axial_stiffness_n_per_m=fe.axial_stiffness_n_per_m,
                   shear_stiffness_n_per_m=fe.shear_stiffness_n_per_m
                   if math.isfinite(fe.shear_stiffness_n_per_m) else None,
                   backlash_rad=fe.backlash_rad, play=play,
                   provenance=(f"{fe_provenance(fe)}; play: {_play_text(play)}, rotational {fe.backlash_rad:g} rad "
                               "(head and nut clamp)"))


def fe_provenance(fe) -> str:
    return f"{fe.provenance}; solver scipy SuperLU (splu, COLAMD); cache key {fe.input_hash[:16]}"


def with_fe(rec: ConnectorProperties, fe) -> ConnectorProperties:
    """The record's coupling with the FE's stiffness (play, heights and gap from the record)."""
    return replace(rec, rotational_stiffness_nm_per_rad=fe.rotational_stiffness_nm_per_rad,
                   axial_stiffness_n_per_m=fe.axial_stiffness_n_per_m,
                   shear_stiffness_n_per_m=fe.shear_stiffness_n_per_m
                   if math.isfinite(fe.shear_stiffness_n_per_m) else None,
                   provenance=fe_provenance(fe))


def resolve(robot: RobotProperties, source: str = "fe", cache_dir=None,
            measured: str | None = None) -> tuple[RobotProperties, dict[str, str]]:
    """The record the model uses and, per connector kind, what its values are and why.

    ``source="fe"``: FE results where one applies (:func:`fe_front_rear_for`), else the record;
    ``"properties"``: the record as it is. ``measured``: a JSON file of measured couplings
    (:func:`load_measured`) that replaces those connectors last."""
    if source not in SOURCES:
        raise InputError(f"connector source {source!r} is not one of {', '.join(SOURCES)}")
    notes: dict[str, str] = {}
    record = robot
    if source == "fe":
        fe, where = fe_front_rear_for(robot, cache_dir)
        if fe is not None:
            robot = _swap(robot, with_fe(robot.connector("front_rear"), fe))
            notes["front_rear"] = f"fe (result found in the {where})"
        elif any(c.kind == "front_rear" for c in robot.connectors):
            notes["front_rear"] = f"record (hand formula): {where}"
        key, why_key = planar_top_twist_for(record, cache_dir)
        if key is not None:
            robot = _swap(robot, key)
            if key.provenance.startswith("fe: "):
                notes["top_twist"] = (f"fe (result found in the {why_key}): horizontal = the key stem in the roof, "
                                      "vertical and pitch = the key arms under the roof (planar_top_twist_for)")
            else:
                notes["top_twist"] = ("record's key arms (vertical, pitch); horizontal: the key stem "
                                      f"(planar_top_twist_for; {why_key})")
        elif any(c.kind == "top_twist" for c in robot.connectors):
            notes["top_twist"] = f"record (horizontal = the arms' vertical value): {why_key}"
        rail, why = planar_side_rail_for(record, cache_dir)
        if rail is not None:
            robot = _swap(robot, rail)
            if rail.provenance.startswith("fe: "):
                notes["side_rail"] = (f"fe (result found in the {why}): rail lips + tongue per length, in pitch over "
                                      "the staggered overlap (planar_side_rail_for)")
            else:
                notes["side_rail"] = ("record's rail lips, in pitch over the staggered overlap "
                                      f"(planar_side_rail_for; {why})")
        elif any(c.kind == "side_rail" for c in robot.connectors):
            notes["side_rail"] = f"record (roll about the rail's axis): {why}"
        if any(c.kind == "bolt" for c in robot.connectors):
            bolt, why_bolt = fe_platform_bolt_for(record, cache_dir)
            if bolt is not None:
                robot = _swap(robot, with_fe_bolt(robot.connector("bolt"), bolt))
                notes["bolt"] = f"fe (result found in the {why_bolt}): lap joint + bolt, play from the ISO 273 hole"
            else:
                notes["bolt"] = f"record (hand formula): {why_bolt}"
        if any(c.kind == "ring_capture" for c in robot.connectors):
            ring, why_ring = fe_octbot_ring_for(record, cache_dir)
            if ring is not None:
                robot = _swap(robot, with_fe_ring(robot.connector("ring_capture"), ring))
                notes["ring_capture"] = (f"fe (result found in the {why_ring}): fingers + retainer and ring, hooks on "
                                         "the lip in series; play from the CAD's two clearances")
            else:
                notes["ring_capture"] = f"record (hand formula): {why_ring}"
    if measured is not None:
        for c in load_measured(measured, robot):
            robot = _swap(robot, c)
            notes[c.kind] = f"measured ({measured})"
    for c in robot.connectors:
        notes.setdefault(c.kind, "record")
    return robot, notes


def rail_overlap_m(robot: RobotProperties, cub) -> float:
    """How far two staggered robots' side rails engage (m): the CAD's rail length less half a pitch
    (the record's robot length + its front-rear docked gap)."""
    return cub.rail_spec.length_mm * 1e-3 - (robot.length_m + robot.connector("front_rear").gap_m) / 2


def rail_in_pitch(rec: ConnectorProperties, rail_length_m: float, overlap_m: float,
                  aligned_overlap_m: float | None = None, fe=None) -> ConnectorProperties:
    """The side rail as the planar model needs it: in **pitch** (the two lines' bodies turning
    relative to each other about the horizontal axis across the structure) over the length
    ``overlap_m`` the two rails actually engage, instead of about the rail's own axis (roll).

    The record's hand formula gives the lips' vertical stiffness for the whole rail,
    ``k = 2 k_lip`` (``axial_stiffness_n_per_m``, lips as cantilevers over ``rail_length_m``), so
    per metre of engagement ``q = k / rail_length``. Over an overlap ``l`` (uniform springs
    ``q`` about its centre): vertical ``k_z = q l``, pitch ``k_pitch = q l^3 / 12``. The
    tongue's vertical play ``d`` between the flanks (``rail_vertical``, the CAD's clearance)
    lets the coupling turn by ``2 d / l`` before both ends of the overlap bear. Along the rail
    (x) the record's value is kept. The model's rectangle ``|z| <= d``, ``|theta| <= 2 d / l``
    contains the true free region ``|z| + |theta| l / 2 <= d`` (its corners are looser).

    ``fe``: a :class:`structure_fem.couplings.rail_key_fe.SideRailFE`: its whole-wall values for this overlap
    (``fe.wall``: both rails on their side walls, loaded over the overlap; ``k_z`` and ``k_pitch``
    from the FE, not from ``q``), else its slice's ``q`` (lips + tongue, walls rigid) in place of the
    record's, with ``provenance = "fe: ..."``; the play as above."""
    if not (rail_length_m > 0 and 0 < overlap_m <= rail_length_m + 1e-12):
        raise InputError(f"side rail overlap {overlap_m:g} m outside (0, rail length {rail_length_m:g} m]")
    q = rec.axial_stiffness_n_per_m / rail_length_m if fe is None else fe.q_n_per_m_per_m
    if not (math.isfinite(q) and q > 0):
        raise InputError(f"side rail stiffness per length {q!r} N/m per m must be > 0")
    pl = rec.play_of("rail_vertical")
    d = 0.0 if pl is None else pl.play_m
    k_pitch = q * overlap_m ** 3 / 12
    extra = ""
    if aligned_overlap_m is not None:
        extra = (f"; aligned lines overlap {aligned_overlap_m * 1e3:.4g} mm (k_pitch {q * aligned_overlap_m ** 3 / 12:.4g} "
                 "N m/rad) but merge into one planar body: no rail coupling in the model")
    hand_q = rec.axial_stiffness_n_per_m / rail_length_m
    wall = getattr(fe, "wall", None) if fe is not None else None
    if wall and abs(wall["overlap_mm"] - overlap_m * 1e3) < 1e-6:
        k_z, k_p = wall["k_z_n_per_m"], wall["k_pitch_nm_per_rad"]
        return replace(rec, rotational_stiffness_nm_per_rad=k_p, shear_stiffness_n_per_m=k_z,
                       backlash_rad=2 * d / overlap_m,
                       provenance=(f"{fe_provenance(fe)}; rail in pitch over the {overlap_m * 1e3:.4g} mm staggered "
                                   f"overlap, whole rails on their side walls: k_z = {k_z:.4g} N/m, k_pitch = "
                                   f"{k_p:.4g} N m/rad (the rail slice alone, walls rigid: q l = {q * overlap_m:.4g} N/m, "
                                   f"q l^3 / 12 = {k_pitch:.4g} N m/rad; the hand formula's q {hand_q:.4g} N/m per m), "
                                   f"pitch play = 2 x {d * 1e3:.3g} mm (rail_vertical, CAD) / l; along the rail the "
                                   f"record's {rec.axial_stiffness_n_per_m:.4g} N/m" + extra))
    if fe is not None:
        return replace(rec, rotational_stiffness_nm_per_rad=k_pitch, shear_stiffness_n_per_m=q * overlap_m,
                       backlash_rad=2 * d / overlap_m,
                       provenance=(f"{fe_provenance(fe)}; rail in pitch over the {overlap_m * 1e3:.4g} mm staggered "
                                   f"overlap (the rail slice alone, walls rigid): k_z = q l = {q * overlap_m:.4g} N/m, "
                                   f"k_pitch = q l^3 / 12 = {k_pitch:.4g} N m/rad (hand formula's q {hand_q:.4g}"
                                   f" N/m per m), pitch play = 2 x {d * 1e3:.3g} mm (rail_vertical, CAD) / l; along "
                                   f"the rail the record's {rec.axial_stiffness_n_per_m:.4g} N/m" + extra))
    return replace(rec, rotational_stiffness_nm_per_rad=k_pitch, shear_stiffness_n_per_m=q * overlap_m,
                   backlash_rad=2 * d / overlap_m,
                   provenance=(f"hand formula: rail in pitch over the {overlap_m * 1e3:.4g} mm staggered overlap "
                               f"(rail {rail_length_m * 1e3:.4g} mm less half a pitch): lips' vertical stiffness per "
                               f"length q = {rec.axial_stiffness_n_per_m:.4g} N/m / {rail_length_m * 1e3:.4g} mm "
                               f"(record: two groove lips as cantilevers E w t^3 / 4 L^3), k_z = q l, k_pitch = "
                               f"q l^3 / 12, pitch play = 2 x {d * 1e3:.3g} mm (rail_vertical) / l; along the rail "
                               f"the record's {rec.axial_stiffness_n_per_m:.4g} N/m" + extra))


def planar_side_rail_for(robot: RobotProperties, cache_dir=None):
    """``(ConnectorProperties or None, why not)``: the record's side rail in pitch over the
    staggered overlap (:func:`rail_in_pitch`), for a record whose couplings are the parametric
    CuBot's hand formulas (:func:`cubot_for_record`: its rail length is the CAD's); the overlap
    is the rail length less half a pitch (robot length + docked gap). Where the FE of the rail
    (:func:`fe_side_rail_for`) exists for the record's geometry, its ``q`` is used (``provenance
    "fe: ..."``) and the second element says where it was found; else the hand formula's, and the
    second element says why (an empty string when nothing is amiss)."""
    if not any(c.kind == "side_rail" for c in robot.connectors):
        return None, "the record has no side rail"
    cub, why = cubot_for_record(robot)
    if cub is None:
        return None, why
    rec = robot.connector("side_rail")
    hand = cub.connector_properties(robot.youngs_modulus_pa, {"front_rear": robot.connector("front_rear").gap_m * 1e3})[1]
    if not all(_same(getattr(hand, f), getattr(rec, f)) for f in
               ("rotational_stiffness_nm_per_rad", "axial_stiffness_n_per_m", "backlash_rad", "height_m")):
        return None, "the record's side rail is not the parametric CuBot's hand formula (edited or another geometry)"
    length = cub.rail_spec.length_mm * 1e-3
    overlap = rail_overlap_m(robot, cub)
    if overlap <= 0:
        pitch = robot.length_m + robot.connector("front_rear").gap_m
        return None, f"staggered rails ({length * 1e3:g} mm) do not overlap at half a {pitch * 1e3:g} mm pitch"
    fe, where = fe_side_rail_for(robot, cache_dir)
    return rail_in_pitch(rec, length, overlap, aligned_overlap_m=length, fe=fe), where


#: Poisson's ratio of printed ABS/PLA for the key stem's shear (assumption, as connector_fe's).
KEY_POISSON = 0.35
#: Shear coefficient of the key stem's thick-walled tube section (Timoshenko; ~0.5 thin tube, 0.9 solid).
KEY_SHEAR_COEFFICIENT = 0.8


def key_horizontal_stiffness(youngs_modulus_pa: float, stem_od_m: float, bore_m: float, lever_m: float) -> float:
    """Horizontal stiffness (N/m) of a twist key: its stem (a tube of outer diameter ``stem_od_m``
    and bore ``bore_m``) as a short cantilever from the thrust disc under the floor to the
    collar roof that bears on it ``lever_m`` below, bending ``3 E I / L^3`` in series with shear
    ``kappa G A / L`` (``G = E / (2 (1 + nu))``; the stem is stubby, L about 0.7 D, so shear
    matters). The shaft's bearing in the floor and the floor plate are taken rigid (upper bound)."""
    for name, v in (("stem diameter", stem_od_m), ("lever", lever_m)):
        if not (v > 0):
            raise InputError(f"key {name} must be > 0 m, got {v!r}")
    if not (0 <= bore_m < stem_od_m):
        raise InputError(f"key bore {bore_m!r} m must be in [0, stem diameter {stem_od_m!r} m)")
    i_area = math.pi * (stem_od_m ** 4 - bore_m ** 4) / 64
    area = math.pi * (stem_od_m ** 2 - bore_m ** 2) / 4
    g = youngs_modulus_pa / (2 * (1 + KEY_POISSON))
    k_bend = 3 * youngs_modulus_pa * i_area / lever_m ** 3
    k_shear = KEY_SHEAR_COEFFICIENT * g * area / lever_m
    return 1.0 / (1.0 / k_bend + 1.0 / k_shear)


def planar_top_twist_for(robot: RobotProperties, cache_dir=None):
    """``(ConnectorProperties or None, why not)``: the record's top twist key with its own
    horizontal stiffness (:func:`key_horizontal_stiffness`) along x instead of the arms' vertical
    bending value, which stays the vertical (z, ``shear_stiffness_n_per_m``) one; for a record
    whose couplings are the parametric CuBot's hand formulas (its key geometry is the CAD's).

    Geometry (docked, :class:`cubot_cad.couplings.connectors.TopTwistSpec`, :class:`cubot_cad.couplings.twist.TwistKey`):
    the stem is ``arm_width_mm`` across with the IR bore ``ir_bore_mm``; it hangs from the thrust
    disc (its bottom ``disc_z_mm[0]`` below the upper robot's underside) to the collar roof, whose
    centre is ``stand_mm - roof_under_mm - roof_mm / 2`` below that underside.

    Where the FE of the key (:func:`fe_top_twist_for`) exists for the record's geometry, its
    horizontal, vertical and pitch stiffness are used (``provenance "fe: ..."``; the play stays the
    CAD's) and the second element says where it was found; else the hand formulas above, and the
    second element says why there is no FE."""
    if not any(c.kind == "top_twist" for c in robot.connectors):
        return None, "the record has no top twist key"
    cub, why = cubot_for_record(robot)
    if cub is None:
        return None, why
    rec = robot.connector("top_twist")
    gaps = {"front_rear": robot.connector("front_rear").gap_m * 1e3, "top_twist": rec.gap_m * 1e3}
    hand = cub.connector_properties(robot.youngs_modulus_pa, gaps)[2]
    if not all(_same(getattr(hand, f), getattr(rec, f)) for f in
               ("rotational_stiffness_nm_per_rad", "axial_stiffness_n_per_m", "backlash_rad", "height_m")):
        return None, "the record's top twist key is not the parametric CuBot's hand formula (edited or another geometry)"
    s, d = cub.top_spec, cub.drive_spec
    roof_mid = s.stand_mm - s.roof_under_mm - s.roof_mm / 2  # below the upper robot's underside
    disc = -d.disc_z_mm[0]  # the thrust disc's bottom, below the underside
    lever = (roof_mid - disc) * 1e-3
    if lever <= 0:
        return None, f"the collar roof ({roof_mid:g} mm) is not below the key's thrust disc ({disc:g} mm)"
    od, bore = s.arm_width_mm * 1e-3, s.ir_bore_mm * 1e-3
    k_h = key_horizontal_stiffness(robot.youngs_modulus_pa, od, bore, lever)
    k_v = rec.shear_stiffness_n_per_m or rec.axial_stiffness_n_per_m
    fe, where = fe_top_twist_for(robot, cache_dir)
    if fe is not None:
        return replace(rec, axial_stiffness_n_per_m=fe.horizontal_stiffness_n_per_m,
                       shear_stiffness_n_per_m=fe.vertical_stiffness_n_per_m,
                       rotational_stiffness_nm_per_rad=fe.rotational_stiffness_nm_per_rad,
                       provenance=(f"{fe_provenance(fe)}; horizontal (x) {fe.horizontal_stiffness_n_per_m:.4g} N/m "
                                   f"(hand formula {k_h:.4g}), vertical (z) {fe.vertical_stiffness_n_per_m:.4g} N/m "
                                   f"(hand {k_v:.4g}), pitch {fe.rotational_stiffness_nm_per_rad:.4g} N m/rad (hand "
                                   f"{rec.rotational_stiffness_nm_per_rad:.4g}); play: the CAD's")), where
    return replace(rec, axial_stiffness_n_per_m=k_h, shear_stiffness_n_per_m=k_v, provenance=(
        f"hand formula: horizontal (x) = the key stem ({od * 1e3:g} mm tube, {bore * 1e3:g} mm IR bore) as a "
        f"cantilever from the thrust disc to the collar roof's centre ({lever * 1e3:.3g} mm), bending 3 E I / L^3 in "
        f"series with shear kappa G A / L (kappa {KEY_SHEAR_COEFFICIENT:g}, nu {KEY_POISSON:g}: assumptions; floor "
        f"and shaft bearing rigid) = {k_h:.4g} N/m; vertical (z) and pitch = the record's four key arms as "
        f"cantilevers E w t^3 / 4 L^3 under the collar roof ({k_v:.4g} N/m)")), where


def _swap(robot: RobotProperties, c: ConnectorProperties) -> RobotProperties:
    """``robot`` with ``c`` in place of its connector of the same kind (order kept)."""
    return replace(robot, connectors=tuple(c if x.kind == c.kind else x for x in robot.connectors))


MEASURED_FIELDS = ("rotational_stiffness_nm_per_rad", "axial_stiffness_n_per_m", "shear_stiffness_n_per_m")


def load_measured(path: str, robot: RobotProperties) -> list[ConnectorProperties]:
    """A measured coupling file: ``{"<kind>": {"rotational_stiffness_nm_per_rad": .., "axial_stiffness_n_per_m":
    .., ["shear_stiffness_n_per_m": ..], ["note": ..]}}``; each replaces that connector's stiffness
    (play stays the CAD's) with ``provenance = "measured: <file>[; note]"``."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"--measured {path}: file not found")
    try:
        data = json.loads(p.read_text())
    except ValueError as exc:
        raise InputError(f"--measured {path} is not valid JSON: {exc}") from None
    if not isinstance(data, dict) or not data:
        raise InputError(f"--measured {path}: expected an object of connector kinds")
    out = []
    for kind, vals in data.items():
        if kind not in {c.kind for c in robot.connectors}:
            raise InputError(f"--measured {path}: robot {robot.name!r} has no {kind!r} connector "
                             f"(has: {', '.join(c.kind for c in robot.connectors)})")
        rec = robot.connector(kind)
        if not isinstance(vals, dict):
            raise InputError(f"--measured {path}: {kind} must be an object, got {vals!r}")
        unknown = set(vals) - set(MEASURED_FIELDS) - {"note", "moment_rotation"}
        if unknown:
            raise InputError(f"--measured {path}: {kind} has unknown field(s) {', '.join(sorted(unknown))}")
        kw = {}
        fit = ""
        if "moment_rotation" in vals:
            k, b, n = fit_moment_rotation(vals["moment_rotation"], f"--measured {path}: {kind}.moment_rotation")
            kw.update(rotational_stiffness_nm_per_rad=k, backlash_rad=b)
            fit = f"; fit of {n} moment-rotation points: k = {k:.4g} N m/rad, play {b * 1e3:.3g} mrad"
        for f in MEASURED_FIELDS:
            if f in vals:
                v = vals[f]
                if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
                    raise InputError(f"--measured {path}: {kind}.{f} must be a number > 0, got {v!r}")
                kw[f] = float(v)
        if not kw:
            raise InputError(f"--measured {path}: {kind} gives none of {', '.join(MEASURED_FIELDS)}, "
                             "moment_rotation")
        note = vals.get("note")
        out.append(replace(rec, **kw, provenance=f"measured: {p}" + fit + (f"; {note}" if note else "")))
    return out


def fit_moment_rotation(points, where: str) -> tuple[float, float, int]:
    """``(k, play, n)`` from measured ``[[moment_nm, rotation_rad], ...]`` of a coupling loaded one
    way (both > 0): the least-squares line ``rotation = play + moment / k`` (the dead band is taken
    up first, then the spring). Needs at least two distinct moments and a rising line."""
    if not isinstance(points, list) or len(points) < 2:
        raise InputError(f"{where}: give at least two [moment_nm, rotation_rad] points")
    ms, ts = [], []
    for i, pt in enumerate(points):
        ok = (isinstance(pt, list) and len(pt) == 2
              and all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in pt))
        if not ok or pt[0] <= 0 or pt[1] <= 0:
            raise InputError(f"{where}[{i}]: expected [moment_nm > 0, rotation_rad > 0], got {pt!r}")
        ms.append(float(pt[0]))
        ts.append(float(pt[1]))
    n = len(ms)
    mm, mt = sum(ms) / n, sum(ts) / n
    sxx = sum((m - mm) ** 2 for m in ms)
    if sxx <= 0:
        raise InputError(f"{where}: the moments are all equal ({ms[0]:g} N m): no stiffness can be fitted")
    slope = sum((m - mm) * (t - mt) for m, t in zip(ms, ts, strict=True)) / sxx
    if slope <= 0:
        raise InputError(f"{where}: the rotation does not grow with the moment (slope {slope:.3g} rad/N m)")
    return 1.0 / slope, max(0.0, mt - slope * mm), n


#: The FE results packaged per robot record (:func:`write_packaged_fe`).
PACKAGED_FINDERS = {"cubot": ("fe_front_rear_for", "fe_side_rail_for", "fe_top_twist_for"),
                    "cube-robot": ("fe_front_rear_for",), "platform": ("fe_platform_bolt_for",),
                    "octbot": ("fe_octbot_ring_for",)}
#: Each finder's cold time when last computed (s, this machine): only to start the longest first.
_EXPECTED_COLD_S = {"fe_front_rear_for": 120.0, "fe_top_twist_for": 66.0, "fe_side_rail_for": 70.0,
                    "fe_platform_bolt_for": 48.0, "fe_octbot_ring_for": 20.0}


def _packaged_task(name: str, finder: str, cache_dir, packaged: bool):
    """One (robot, coupling) FE in a worker process: ``(fe or None, where, seconds)``."""
    import time

    from cubot_cad.properties import default_properties

    t0 = time.perf_counter()
    fe, where = globals()[finder](default_properties().get(name), cache_dir, compute=True, packaged=packaged)
    return fe, where, time.perf_counter() - t0


def _packaged_lookup(name: str, finder: str, cache_dir, packaged: bool):
    """``(fe, where, 0.0)`` when the result is cached (or packaged), else None: no computing."""
    from cubot_cad.properties import default_properties

    fe, where = globals()[finder](default_properties().get(name), cache_dir, compute=False, packaged=packaged)
    return None if fe is None else (fe, where, 0.0)


def compute_packaged_fe(cache_dir=None, workers: int = 2, packaged: bool = True, progress=None):
    """The FE results of :data:`PACKAGED_FINDERS` for the packaged records, in that order, as
    ``(results, wall_s, per_task)``: each from the cache (or, with ``packaged``, the packaged file)
    when there, else computed and cached. Missing ones run in ``workers`` processes, longest first
    (each solve is one single-threaded sparse LU, so two cores give two solves at once).
    ``packaged=False`` ignores the packaged file (the cold measurement of ``fem bench --cold-fe``).
    ``progress(done, total, label)`` is called after each task."""
    import concurrent.futures as cf
    import multiprocessing as mp
    import time

    if not (isinstance(workers, int) and workers >= 1):
        raise InputError(f"workers must be an integer >= 1, got {workers!r}")
    tasks = [(name, finder) for name, finders in PACKAGED_FINDERS.items() for finder in finders]
    order = sorted(range(len(tasks)), key=lambda i: -_EXPECTED_COLD_S.get(tasks[i][1], 60.0))
    out: list = [None] * len(tasks)
    t0 = time.perf_counter()
    if workers > 1:  # what is already there is looked up here: spawn workers only for what is missing
        for i in order:
            out[i] = _packaged_lookup(*tasks[i], cache_dir, packaged)
        order = [i for i in order if out[i] is None]
    if workers == 1:
        for k, i in enumerate(order):
            out[i] = _packaged_task(*tasks[i], cache_dir, packaged)
            if progress:
                progress(k + 1, len(tasks), " ".join(tasks[i]))
    else:
        # spawn, not fork: gmsh/OCC keep threads and global state a forked child must not inherit
        with cf.ProcessPoolExecutor(max_workers=workers, mp_context=mp.get_context("spawn")) as ex:
            futs = {ex.submit(_packaged_task, *tasks[i], cache_dir, packaged): i for i in order}
            for k, i in enumerate(i for i in range(len(tasks)) if i not in futs.values()):
                if progress:
                    progress(k + 1, len(tasks), " ".join(tasks[i]))
            done0 = len(tasks) - len(futs)
            for k, f in enumerate(cf.as_completed(futs)):
                out[futs[f]] = f.result()
                if progress:
                    progress(done0 + k + 1, len(tasks), " ".join(tasks[futs[f]]))
    wall = time.perf_counter() - t0
    per_task = {f"{name}:{finder.removeprefix('fe_').removesuffix('_for')}": round(o[2], 3)
                for (name, finder), o in zip(tasks, out, strict=True)}
    for (name, _finder), (fe, where, _s) in zip(tasks, out, strict=True):
        if fe is None:
            raise InputError(f"no FE result applies to the packaged {name} record: {where}")
    return [o[0] for o in out], wall, per_task


def write_packaged_fe(cache_dir=None, workers: int = 2) -> Path:
    """Write ``structure_fem/data/connector_fe.json``: exactly the FE results that apply to the
    packaged records (:data:`PACKAGED_FINDERS`: the CuBot's front-rear, side rail and twist key,
    the Cube Robot's front-rear, the test platform's bolt, the OctBot's ring), from the cache, computing any that is missing
    (:func:`compute_packaged_fe`, ``workers`` processes). Entries of geometries no packaged record
    has any more are dropped. The file is replaced atomically, only once every result exists."""
    results, _wall, _per = compute_packaged_fe(cache_dir, workers)
    tmp = PACKAGED_FE.with_suffix(".tmp")
    tmp.write_text(json.dumps([fe.to_dict() for fe in results], indent=1, sort_keys=True) + "\n")
    tmp.replace(PACKAGED_FE)
    return PACKAGED_FE


if __name__ == "__main__":  # pragma: no cover
    import argparse

    ap = argparse.ArgumentParser(description="compute (or take from the cache) the packaged records' "
                                             "connector FE and write structure_fem/data/connector_fe.json")
    ap.add_argument("--workers", type=int, default=2, help="processes for the missing FE solves (default 2)")
    # through the package name, so the spawned workers import the same module
    from structure_fem.couplings.connector_sources import write_packaged_fe as _write

    print(_write(workers=ap.parse_args().workers))
