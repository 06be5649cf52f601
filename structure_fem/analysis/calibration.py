"""Calibration of the test-platform bolt coupling to the thesis's bench measurement (SI units).

Thesis Ch. 6.5.2: "five connected platforms" (100 x 100 x 5 mm ABS, one bolt each at a single
horizontal point) deflect 5 mm at the end of the structure; three and four deflect "slightly".
The thesis does not say how they were set up, and two readings are plausible
(:data:`READINGS`), so the bolt is fitted with both and both are reported:

* ``held``: one platform held flat on the bench (clamped), four overhanging: the free end of a
  four-joint cantilever;
* ``crossing``: the platforms as in the thesis's crossing demonstrations (Ch. 6.5.1, Fig.
  6.15-6.17: platforms resting on the ground, pushed over a void, held there by the ones behind
  them, not clamped; the 5 mm paragraph goes on "for two robot wide void ... the front caster
  wheel will help the structure to climb the cliff"): three resting on the near ground on
  one-sided supports (n_p = n_g + 1, the most a five-platform structure can put over the void)
  and two over a two-wide void, the front at the far edge. The ground platforms' joints open
  too as the structure turns about the edge. With ``n`` platforms this reading puts
  ``(n - 1) // 2`` over the void (3 and 4 platforms: one over a one-wide void, as in Fig. 6.15-6.16).

One number cannot fix two parameters (rotational stiffness k, backlash b), so per reading the
fit is a one-parameter family: for every backlash b the stiffness k(b) that reproduces 5 mm,
with the 3- and 4-platform deflections it then predicts. Pure backlash would predict 3 mm for
four held platforms (60 % of five), pure stiffness 1.8 mm (36 %): the thesis's "slightly"
favours the stiffness-dominated end, so the *chosen* point is b = 0 (fewest parameters,
smallest 3- and 4-platform deflections); pass ``backlash`` to choose another (the platform
record's own bolt estimate is reported beside it). k(b) rises steeply as b approaches the value
that alone gives 5 mm: the family shows it. The ``held`` reading is the primary one
(``Calibration.stiffness_nm_per_rad``; the ``calibrated`` what-if below uses it); the
``crossing`` fit is in ``Calibration.readings`` beside it.

**What it feeds.** The CuBot's connectors do *not* come from this fit: its front-rear coupling
comes from the 3D finite-element model of its own pins, latches and walls
(:mod:`structure_fem.couplings.connector_fe`, ``provenance = "fe: ..."``) where a result applies to the
record, every other value from the record's hand formulas (``"hand formula: ..."``) or a user's
measurement (``"measured: ..."``); :data:`ROBOT_CONNECTORS_STATEMENT` says so in every report.
The fit only says how far the *platform bolt's* hand estimate is off. ``calibrated_connectors``
is a what-if: it multiplies the CuBot's hand-formula rotational stiffness by the ratio fitted /
estimated of the platform bolt (the estimate was off by that factor for the platform, assume
the same for the robot), an override the studies report beside the default.

**The FE check.** The bolt itself has a 3D FE model of the platform's CAD
(:mod:`structure_fem.couplings.platform_bolt_fe`); :func:`fe_comparison` puts it beside each reading's fit
(``Calibration.fe``, ``to_dict()["fe"]`` and ``["fe_statement"]``): the FE's whole-pitch stiffness
(joint + the two half plates, centre to centre, since the fit's platforms are rigid), the ratio
FE / fitted, whether the FE is stiffer or softer and by what factor, and the five-platform tip
the model gives with the FE. It is the only comparison of the connector FE with a measurement;
nothing is tuned to it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

from cubot_cad.properties import ConnectorProperties, RobotProperties, RobotPropertiesFile
from structure_fem.errors import InputError, SolverFailure
from structure_fem.model.connectors import ConnectorSet, Joint
from structure_fem.model.statics import Config, solve
from structure_fem.model.structures import Structure

#: Thesis Ch. 6.5.2: free-end deflection of five docked platforms (m).
MEASURED_TIP_M = 0.005
MEASURED_PLATFORMS = 5
#: Platforms held on the bench in the ``held`` reading.
HELD = 1
#: Said by every calibration report: where the robot's couplings come from (not from the bolt).
ROBOT_CONNECTORS_STATEMENT = (
    "The CuBot's connectors do not come from this bolt fit. Its front-rear coupling (pins, latches and the "
    "2.4 mm walls they are screwed to) comes from the 3D finite-element model of its own geometry "
    "(structure_fem.connector_fe, provenance 'fe: ...', wherever an FE result applies to the record); its "
    "side rail and top twist key from their own FE too (structure_fem.rail_key_fe) where results apply, else the "
    "record's hand formulas ('hand formula: ...'), or any coupling from a measurement ('measured: ...'); `fem table --json` lists each under calibration.connector_sources. This fit "
    "calibrates the test platform's nut and bolt only; `--connectors calibrated` is a what-if that scales "
    "the CuBot's hand-formula rotational stiffness by the platform's fitted / estimated ratio.")


@dataclass(frozen=True)
class Reading:
    """One reading of "n connected platforms deflect ...": how the platforms were set up.

    ``held``: platforms clamped on the bench (the rest overhang); ``0``: none held, the
    structure rests on the near ground on one-sided supports and ``over(n)`` platforms are
    over a void that wide (the front at its far edge)."""

    name: str
    description: str
    held: int

    def over(self, n: int) -> int:
        """Platforms past the edge for ``n`` platforms."""
        return n - self.held if self.held else (n - 1) // 2

    def config(self, n: int) -> Config:
        o = self.over(n)
        if o < 1:
            raise InputError(f"reading {self.name!r}: {n} platforms put none over the edge")
        return Config(Structure("line"), rows=n, rows_over=o, void_widths=o, clamped=self.held > 0)

    def set_up(self, n: int = MEASURED_PLATFORMS) -> dict:
        o = self.over(n)
        return {"platforms": n, "held": self.held, "on_the_ground": n - o, "over": o,
                "supports": "clamped (held on the bench)" if self.held else "one-sided (resting on the ground)"}


HELD_READING = Reading("held", "1 platform held flat on the bench, 4 overhanging: the free end of a "
                       "four-joint cantilever", HELD)
CROSSING_READING = Reading("crossing", "the crossing set-up of Ch. 6.5.1: 3 platforms resting on the near "
                           "ground (not held), 2 over a two-wide void, the front at its far edge (n_p = n_g + 1)", 0)
READINGS = (HELD_READING, CROSSING_READING)


def thesis_platform() -> RobotProperties:
    """The thesis's test platform from its stated size and material (used when the
    properties file has no ``platform`` record): 100 x 100 x 5 mm ABS, one bolt."""
    L, W, H, rho = 0.1, 0.1, 0.005, 1040.0
    m = rho * L * W * H
    ixx = m * (W ** 2 + H ** 2) / 12
    iyy = m * (L ** 2 + H ** 2) / 12
    izz = m * (L ** 2 + W ** 2) / 12
    bolt = ConnectorProperties("bolt", 20.0, 1.0e5, 0.0, 0.0, H / 2)
    return RobotProperties("platform", L, W, H, m, (0.0, 0.0, H / 2), (ixx, iyy, izz, 0, 0, 0),
                           0.005, 0.0, "ABS", rho, 2.2e9, (bolt,), source="thesis Ch. 6.5.1 dimensions")


def platform_from(props: RobotPropertiesFile | None) -> RobotProperties:
    if props is not None and "platform" in props.names:
        return props.get("platform")
    return thesis_platform()


def platform_tip_m(platform: RobotProperties, n: int, k: float, backlash: float,
                   reading: Reading = HELD_READING, flexible: bool = False) -> float:
    """Free-end deflection (m) of ``n`` docked platforms set up as ``reading`` says, bolt (k, backlash);
    ``flexible``: each platform bends with the record's section (the CAD's plate,
    ``body_second_moment_m4``) in series with the bolt, as the robots do in the tables."""
    conn = ConnectorSet.from_robot(platform)
    fr = replace(conn.front_rear, rotational_nm_per_rad=k, backlash_rad=backlash)
    conn = replace(conn, front_rear=fr)
    return solve(reading.config(n), platform, conn, flexible=flexible).tip_deflection_m


def _tip_or_inf(platform: RobotProperties, n: int, k: float, backlash: float, reading: Reading,
                flexible: bool = False) -> float:
    """:func:`platform_tip_m`, or infinity when the solve does not converge (a bolt so soft that
    the platforms fold over the edge: more than any finite tip)."""
    try:
        return platform_tip_m(platform, n, k, backlash, reading, flexible)
    except SolverFailure:
        return math.inf


def fit_stiffness(platform: RobotProperties, backlash: float, target_m: float = MEASURED_TIP_M,
                  n: int = MEASURED_PLATFORMS, reading: Reading = HELD_READING) -> float:
    """The bolt stiffness (N m/rad) for which ``n`` platforms set up as ``reading`` deflect
    ``target_m`` with ``backlash`` (bisection in log k; a non-converged solve counts as too soft)."""
    lo, hi = 1e-2, 1e5
    if _tip_or_inf(platform, n, hi, backlash, reading) >= target_m:
        raise InputError(f"backlash {backlash} rad alone deflects {n} platforms ({reading.name} reading) more "
                         f"than {target_m * 1e3:g} mm: no stiffness fits")
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        if _tip_or_inf(platform, n, mid, backlash, reading) > target_m:
            lo = mid
        else:
            hi = mid
        if hi / lo < 1 + 1e-5:
            break
    return math.sqrt(lo * hi)


def backlash_alone_rad(platform: RobotProperties, reading: Reading, n: int = MEASURED_PLATFORMS,
                       target_m: float = MEASURED_TIP_M) -> float:
    """The backlash that alone would give ``target_m``, counting the joints over the edge (their
    distances to the free end: ``L o (o + 1) / 2`` for ``o`` platforms over)."""
    o = reading.over(n)
    return target_m / (platform.length_m * o * (o + 1) / 2)


@dataclass(frozen=True)
class ReadingFit:
    """The bolt fitted under one :class:`Reading`: ``stiffness_nm_per_rad`` at ``backlash_rad``,
    the tips it predicts for 3/4/5 platforms (``tips_m``), the 5-platform tip with the fitted
    value fed back into the model (``refit_tip_m``), the family (backlash, k, tip3, tip4, tip5) SI."""

    reading: Reading
    backlash_rad: float
    stiffness_nm_per_rad: float
    estimate_nm_per_rad: float
    tips_m: dict[int, float]
    refit_tip_m: float
    family: tuple[tuple[float, float, float, float, float], ...]

    @property
    def ratio(self) -> float:
        return self.stiffness_nm_per_rad / self.estimate_nm_per_rad

    def to_dict(self) -> dict:
        return {"reading": self.reading.name, "description": self.reading.description,
                "set_up": self.reading.set_up(), "bolt_backlash_rad": self.backlash_rad,
                "bolt_stiffness_nm_per_rad": round(self.stiffness_nm_per_rad, 4),
                "fitted_over_estimate": round(self.ratio, 4),
                "refit_tip5_mm": round(self.refit_tip_m * 1e3, 4),
                "predicted_tip_mm": {str(n): round(t * 1e3, 3) for n, t in self.tips_m.items()},
                "family": [{"backlash_rad": b, "stiffness_nm_per_rad": round(k, 4), "tip3_mm": round(t3 * 1e3, 3),
                            "tip4_mm": round(t4 * 1e3, 3), "tip5_mm": round(t5 * 1e3, 3)}
                           for b, k, t3, t4, t5 in self.family]}


def fit_reading(plat: RobotProperties, reading: Reading, backlash: float, family_points: int = 4) -> ReadingFit:
    """The fit of ``reading`` at ``backlash`` and its family (backlash 0 .. 0.9 x the one that alone
    gives 5 mm; points where no stiffness fits are left out)."""
    est = ConnectorSet.from_robot(plat).front_rear.rotational_nm_per_rad
    k = fit_stiffness(plat, backlash, reading=reading)
    tips = {n: _tip_or_inf(plat, n, k, backlash, reading) for n in (3, 4, 5)}
    refit = platform_tip_m(plat, MEASURED_PLATFORMS, round(k, 6), backlash, reading)
    b_max = backlash_alone_rad(plat, reading)
    fam = []
    for f in [i / family_points * 0.9 for i in range(family_points + 1)]:
        bb = f * b_max
        try:
            kk = fit_stiffness(plat, bb, reading=reading)
        except InputError:
            continue
        fam.append((bb, kk, *(_tip_or_inf(plat, n, kk, bb, reading) for n in (3, 4, 5))))
    return ReadingFit(reading, backlash, k, est, tips, refit, tuple(fam))


def fe_comparison(plat: RobotProperties, fits: tuple[ReadingFit, ...], cache_dir=None) -> dict:
    """The FE of the platform's bolted lap joint (:mod:`structure_fem.couplings.platform_bolt_fe`, looked up by
    :func:`structure_fem.couplings.connector_sources.fe_platform_bolt_for`, never computed here) beside each
    reading's fitted stiffness: our only check of the connector FE against a measurement.

    The fit's platforms are rigid bodies, so its stiffness lumps each platform's own bending into
    its joint; the like-for-like FE number is the whole pitch (joint + the two half plates, centre
    to centre: ``pitch_stiffness_nm_per_rad``). Per reading: the ratio FE / fitted, whether the FE is
    stiffer or softer and by what factor, and the 5-platform tip the model gives with the FE's
    pitch stiffness (no rotational play: the FE's, head and nut clamp) instead of the fit."""
    from structure_fem.couplings.connector_sources import fe_platform_bolt_for

    fe, where = fe_platform_bolt_for(plat, cache_dir)
    if fe is None:
        return {"available": False, "why": where}
    k, kc = fe.pitch_stiffness_nm_per_rad, fe.contact_pitch_stiffness_nm_per_rad
    rows = []
    for r in fits:
        lo, hi = k / r.stiffness_nm_per_rad, kc / r.stiffness_nm_per_rad
        if lo >= 1:
            word, factor = "stiffer", f"{lo:.3g}-{hi:.3g}"
        elif hi <= 1:
            word, factor = "softer", f"{1 / hi:.3g}-{1 / lo:.3g}"
        else:
            word, factor = "bracketing", f"{lo:.3g}-{hi:.3g}"
        def tip(kk, flexible=False, r=r):
            return round(_tip_or_inf(plat, MEASURED_PLATFORMS, kk, fe.backlash_rad, r.reading, flexible) * 1e3, 3)

        rows.append({"reading": r.reading.name, "fitted_nm_per_rad": round(r.stiffness_nm_per_rad, 4),
                     "fitted_backlash_rad": r.backlash_rad, "fe_over_fitted": round(lo, 4),
                     "fe_contact_over_fitted": round(hi, 4), "fe_is": word, "factor": factor,
                     "fe_tip5_mm": tip(k), "fe_contact_tip5_mm": tip(kc),
                     # the model as the tables run it: flexible platforms (the record's section of the
                     # CAD's plate) + the FE's joint alone, per platform count 3, 4, 5
                     "model_tips_mm": {str(n): round(_tip_or_inf(plat, n, fe.rotational_stiffness_nm_per_rad,
                                                                  fe.backlash_rad, r.reading, True) * 1e3, 3)
                                       for n in (3, 4, 5)},
                     "model_tip5_mm": tip(fe.rotational_stiffness_nm_per_rad, True),
                     "model_contact_tip5_mm": tip(fe.contact_rotational_stiffness_nm_per_rad, True),
                     "measured_tip5_mm": MEASURED_TIP_M * 1e3})
    geometry = one_geometry(plat, fe)
    return {"available": True, "where": where, "provenance": fe.provenance,
            "joint_stiffness_nm_per_rad": round(fe.rotational_stiffness_nm_per_rad, 4),
            "pitch_stiffness_nm_per_rad": round(k, 4),
            "plate_pitch_stiffness_nm_per_rad": round(fe.plate_pitch_stiffness_nm_per_rad, 4),
            "contact_joint_stiffness_nm_per_rad": round(fe.contact_rotational_stiffness_nm_per_rad, 4),
            "contact_pitch_stiffness_nm_per_rad": round(kc, 4),
            "fe_backlash_rad": fe.backlash_rad,
            "one_geometry": geometry,
            "compared": ("pitch (joint + the two half plates, centre to centre) against the rigid-body fit, "
                         "which lumps the plates' bending into the joint; the FE as a bracket: abutting faces free "
                         "(lower bound) and their lower edge bearing (contact-closed)"),
            "readings": rows}


def one_geometry(plat: RobotProperties, fe) -> dict:
    """The platform's one geometry, seen by both models: the record's body section (the CAD's
    plate, cut outside the lap joint: :mod:`cubot_cad.checks.section`) as a pitch ``E I / L``
    beside the FE's continuous plate over the same pitch (``plate_pitch_stiffness_nm_per_rad``,
    the reference the FE's joint is measured against). They differ by the 3D plate effects the
    beam leaves out (Poisson's ratio across a 100 mm wide plate: up to ``1 / (1 - nu^2)``, 14 %),
    not by a different plate; the record's source says how its section was cut."""
    from structure_fem.model.bodies import body_bending

    body = body_bending(plat)
    beam = 1.0 / body.compliance_rad_per_nm
    return {"record_body_second_moment_mm4": round(body.second_moment_m4 * 1e12, 3),
            "record_section_source": body.source,
            "record_plate_pitch_nm_per_rad": round(beam, 4),
            "fe_plate_pitch_nm_per_rad": round(fe.plate_pitch_stiffness_nm_per_rad, 4),
            "fe_over_record": round(fe.plate_pitch_stiffness_nm_per_rad / beam, 4)}


@dataclass(frozen=True)
class Calibration:
    """Fitted bolt coupling and what it predicts, for the primary (``held``) reading, and
    ``readings``: the fit under every reading of :data:`READINGS`; ``family`` rows are
    (backlash, k, tip3, tip4, tip5) SI of the primary reading."""

    platform_source: str
    backlash_rad: float
    stiffness_nm_per_rad: float
    estimate_nm_per_rad: float
    estimate_backlash_rad: float
    tips_m: dict[int, float]
    family: tuple[tuple[float, float, float, float, float], ...]
    readings: tuple[ReadingFit, ...] = ()
    #: The FE of the bolt beside the fits (:func:`fe_comparison`); empty when not computed.
    fe: dict = field(default_factory=dict)

    @property
    def ratio(self) -> float:
        """Fitted / estimated platform bolt stiffness (primary reading)."""
        return self.stiffness_nm_per_rad / self.estimate_nm_per_rad

    def reading(self, name: str) -> ReadingFit:
        for r in self.readings:
            if r.reading.name == name:
                return r
        raise InputError(f"no calibration reading {name!r} (have: {', '.join(r.reading.name for r in self.readings)})")

    def to_dict(self) -> dict:
        ks = {r.reading.name: r.stiffness_nm_per_rad for r in self.readings}
        spread = (max(ks.values()) / min(ks.values())) if ks else 1.0
        return {
            "measurement": f"{MEASURED_PLATFORMS} docked 100x100x5 mm ABS platforms, {MEASURED_TIP_M * 1e3:g} mm "
                           "at the end of the structure (thesis Ch. 6.5.2); the set-up is not stated: fitted under "
                           f"{len(self.readings)} readings ({', '.join(ks)}), the primary one ({HELD_READING.name}: "
                           f"{HELD} held) in the top-level fields",
            "robot_connectors": ROBOT_CONNECTORS_STATEMENT,
            "platform_source": self.platform_source,
            "primary_reading": HELD_READING.name,
            "bolt_backlash_rad": self.backlash_rad,
            "bolt_stiffness_nm_per_rad": round(self.stiffness_nm_per_rad, 4),
            "bolt_stiffness_estimate_nm_per_rad": self.estimate_nm_per_rad,
            "bolt_backlash_estimate_rad": self.estimate_backlash_rad,
            "fitted_over_estimate": round(self.ratio, 4),
            "predicted_tip_mm": {str(n): round(t * 1e3, 3) for n, t in self.tips_m.items()},
            "family": [{"backlash_rad": b, "stiffness_nm_per_rad": round(k, 4), "tip3_mm": round(t3 * 1e3, 3),
                        "tip4_mm": round(t4 * 1e3, 3), "tip5_mm": round(t5 * 1e3, 3)}
                       for b, k, t3, t4, t5 in self.family],
            "readings": [r.to_dict() for r in self.readings],
            "readings_stiffness_ratio": round(spread, 4),
            "fe": self.fe,
            "fe_statement": fe_statement(self.fe),
            "platform_test": platform_test(self.fe),
        }


#: Thesis Ch. 6.5.2, the platform test as reported (mm; "slight" for three and four platforms).
THESIS_PLATFORM_TEST = {"3": "slight", "4": "slight", "5": MEASURED_TIP_M * 1e3}


def platform_test(fe: dict) -> dict:
    """The thesis's platform test beside the model run with one set of inputs and nothing fitted:
    the CAD's plate (the record's section, the FE's reference plate: :func:`one_geometry`) as
    flexible platforms, the bolt's FE joint (faces free; faces bearing as the other end of the
    bracket), no rotational play (head and nut clamp), per reading of the unstated set-up."""
    if not fe or not fe.get("available"):
        return {"available": False, "why": (fe or {}).get("why", "the FE of the platform bolt was not looked up")}
    g = fe["one_geometry"]
    rows = [{"reading": r["reading"], "model_tips_mm": r["model_tips_mm"],
             "model_faces_bearing_tip5_mm": r["model_contact_tip5_mm"]} for r in fe["readings"]]
    text = ("the thesis's platform test (Ch. 6.5.2: 3 and 4 platforms 'slight', 5 platforms 5 mm at the end) "
            f"beside the model with one set of inputs, nothing fitted (the CAD's plate: I {g['record_body_second_moment_mm4']:.4g} "
            f"mm^4, E I / L {g['record_plate_pitch_nm_per_rad']:.4g} N m/rad per platform, the FE's own plate "
            f"{g['fe_plate_pitch_nm_per_rad']:.4g}; the bolt's FE joint {fe['joint_stiffness_nm_per_rad']:.4g} N m/rad, "
            f"no rotational play): " + "; ".join(
                f"{r['reading']} reading {' / '.join(f'{v:.3g}' for v in r['model_tips_mm'].values())} mm for 3 / 4 / 5 "
                f"platforms ({r['model_faces_bearing_tip5_mm']:.3g} mm at 5 with the end faces bearing)" for r in rows)
            + " against the thesis's slight / slight / 5 mm")
    return {"available": True, "thesis": THESIS_PLATFORM_TEST, "inputs": g, "readings": rows, "statement": text}


def fe_statement(fe: dict) -> str:
    """One plain paragraph: the FE bolt against the fits (or why there is no FE)."""
    if not fe:
        return "The FE of the platform bolt was not looked up."
    if not fe.get("available"):
        return f"No FE of the platform bolt applies to this record: {fe.get('why', '?')}"
    def verdict(r):
        if r["fe_is"] == "bracketing":
            return f"the FE brackets it (FE / fitted {r['factor']})"
        return f"the FE is {r['fe_is']} by a factor {r['factor']}"

    parts = [f"{r['reading']} reading: fitted {r['fitted_nm_per_rad']:.4g} N m/rad, {verdict(r)}; with the FE the "
             f"model gives {r['fe_tip5_mm']:.3g} / {r['fe_contact_tip5_mm']:.3g} mm for five platforms against the "
             f"measured {r['measured_tip5_mm']:g}" for r in fe["readings"]]
    return (f"FE of the platform's bolted lap joint (3D, from the CAD), as the whole pitch centre to centre (joint + "
            f"the two half plates, the number comparable with the rigid-body fit): "
            f"{fe['pitch_stiffness_nm_per_rad']:.4g} N m/rad with the abutting end faces free (a lower bound), "
            f"{fe['contact_pitch_stiffness_nm_per_rad']:.4g} with their lower edge bearing (the joint alone "
            f"{fe['joint_stiffness_nm_per_rad']:.4g} / {fe['contact_joint_stiffness_nm_per_rad']:.4g}; a continuous "
            f"plate {fe['plate_pitch_stiffness_nm_per_rad']:.4g}). " + "; ".join(parts)
            + ". This is the only check of the connector FE against a measurement; no input was tuned to it.")


def calibrate(props: RobotPropertiesFile | None = None, backlash: float | None = None,
              family_points: int = 4, cache_dir=None) -> Calibration:
    """Fit the bolt stiffness for ``backlash`` (default 0: stiffness-only) under every reading,
    with their families; the primary (``held``) reading fills the top-level fields. ``fe``: the
    bolt's FE beside the fits (:func:`fe_comparison`; ``cache_dir`` for its lookup)."""
    plat = platform_from(props)
    bolt = ConnectorSet.from_robot(plat).front_rear
    b = 0.0 if backlash is None else backlash
    if not (isinstance(b, (int, float)) and math.isfinite(b) and b >= 0):
        raise InputError(f"calibration backlash must be >= 0 rad, got {b!r}")
    fits = tuple(fit_reading(plat, r, b, family_points) for r in READINGS)
    main = fits[0]
    return Calibration(plat.source, b, main.stiffness_nm_per_rad, bolt.rotational_nm_per_rad, bolt.backlash_rad,
                       main.tips_m, main.family, fits, fe_comparison(plat, fits, cache_dir))


def calibrated_connectors(conn: ConnectorSet, cal: Calibration) -> ConnectorSet:
    """The robot's connectors with every stiffness times the platform's fitted/estimated ratio."""
    def s(j: Joint | None) -> Joint | None:
        if j is None:
            return None
        return replace(j, rotational_nm_per_rad=j.rotational_nm_per_rad * cal.ratio,
                       provenance=f"{j.provenance}; rotational x{cal.ratio:.4g} (platform bolt calibration)")
    return replace(conn, front_rear=s(conn.front_rear), side_rail=s(conn.side_rail), top_twist=s(conn.top_twist))
