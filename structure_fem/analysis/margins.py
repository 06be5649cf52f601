"""Thresholds with their margin, what sets them, and their range over plausible inputs (SI in, mm out).

For each structure of a :class:`~structure_fem.analysis.study.Derivation` at its threshold ``w``
(its longest cantilever, minimal rows):

* **margin** = climb clearance - tip deflection at ``w`` (>= 0 by the definition of the
  threshold) and the same one width beyond (< 0 unless the search stopped at the widest
  width studied);
* **decomposition of the tip** along the bottom line of bodies, from the rear body (the
  *root*) to the front body. To first order the front corner's drop is the root's rigid
  motion (``support``: sinking into the ledge springs, and turning as the rear lifts, the
  tipping mode) plus, for every front-rear joint ahead of it (on the ground too: the joints
  behind the edge open their play as the structure turns about the edge), its relative
  rotation times its distance to the tip plus its relative vertical slide. Each joint's rotation and slide is split into the part inside its own
  play (``play``: the pitch dead band and the pins' vertical slip) and the rest
  (``elastic``). The three parts sum to the solved (nonlinear) tip to within the
  small-angle error (a test holds them to 1 %).
* **play, counterfactually**: the tip with every play of every coupling set to zero (same
  rows), and ``play_total`` = tip - that. In an arch the pins' tension gaps of the upper layer
  and the key and rail play turn the bottom joints beyond their own pitch band, so they show
  as ``elastic`` in the chain; ``play_total`` counts them. In an arch the rear body's motion
  (``support``) is large: the part on the ground turns about the edge as a block, each robot on
  its front corner, the pins' vertical slip letting each tilt (play-enabled, and counted in
  ``play_total``). With flexible bodies (the default) ``bodies`` = the tip less the tip of the
  same structure with rigid bodies (the robots' own bending, :mod:`structure_fem.model.bodies`), and
  ``elastic`` is the couplings' share without it. ``set_by`` names the largest of
  ``play_total``, ``support``, ``bodies`` and ``elastic``, by share of the tip.
* **range** over plausible inputs, one factor at a time and the combined extremes: print
  clearance 0.1 and 0.4 mm (every play scaled by clearance / the record's clearance), printed
  instead of bulk modulus (every stiffness and the bodies' modulus x ``PRINTED_MODULUS_FACTOR``), and
  the infill: the printed parts solid (100 % infill, the record's ``solid_print_mass_kg``: mass and
  inertia scaled by solid / as-sliced mass, centre of mass kept: an assumption), the heavy end of
  what a maker may print (the record is at its parts' recorded infill). The combined worst case
  takes the loose clearance, the printed modulus and (when the record has it) the solid parts.
  Each variant's threshold is found by stepping from the base threshold (the tip grows with the
  width).
"""

from __future__ import annotations

import math
from dataclasses import replace

from structure_fem.analysis.study import Curve, Derivation, StudyInputs
from structure_fem.errors import SolverFailure
from structure_fem.model.statics import Config, StaticResult, solve

#: Printed (FDM) ABS/PLA is less stiff than the datasheet's bulk value the record and the FE use:
#: 0.7 is the low end quoted for 100 % infill FDM parts (assumption; the print settings'
#: infill would lower it further).
PRINTED_MODULUS_FACTOR = 0.7
#: Print clearances (mm) the range covers: a tight and a loose printer.
PRINT_CLEARANCE_RANGE_MM = (0.1, 0.4)
#: The infill variant's name (the record's ``solid_print_mass_kg``).
SOLID_VARIANT = "printed parts solid (100 % infill)"
#: A threshold is flagged marginal when its margin is below this fraction of the climb clearance.
MARGINAL_FRACTION = 0.05


def record_clearance_mm(inp: StudyInputs) -> float:
    """The print clearance the record's play was made with: the front-rear vertical slip is two
    radial clearances (own + mating bores) and so is a clearance latch's tension play (pin head +
    blade, ``cubot_cad.couplings.compliance.front_rear_play_mm``); a wedge latch has no tension play."""
    fr = inp.connectors.front_rear
    t = fr.play_z[1] if fr.play_z[1] > 0 else fr.play_x[1]
    return t * 1e3 / 2 if t > 0 else 0.2


def _no_play(inp: StudyInputs) -> StudyInputs:
    return replace(inp, connectors=inp.connectors.scaled(1.0, 0.0))


def chain_decomposition(res: StaticResult) -> dict:
    """The tip split into ``support`` / ``play`` / ``elastic`` (mm) along the bottom line (see the
    module docstring), with ``sum_mm`` and the solved ``tip_mm`` beside it."""
    lay = res.layout
    bodies = lay.bodies
    ref = [b.com_m for b in bodies]
    dq = [(res.com_m[i][0] - ref[i][0], res.com_m[i][1] - ref[i][1], res.rotation_rad[i]) for i in range(len(bodies))]
    front = bodies[lay.front_body]
    x_tip = front.x_m + lay.length_m / 2
    chain = sorted((i for i, b in enumerate(bodies) if b.layer == 0 and b.parity == 0), key=lambda i: bodies[i].row)
    root = chain[-1]  # the rear body: every joint of the line, on the ground too, is in the chain
    ahead = chain[:-1]

    def drop_at(i: int, x: float) -> float:  # first-order downward motion of body i's point at x (z = its base)
        dx, dz, phi = dq[i]
        return -(dz + phi * (x - ref[i][0]))

    support = drop_at(root, x_tip)
    by_pair = {}
    for c in lay.couplings:
        if c.role == "front_rear":
            by_pair[(c.a, c.b)] = c
    play = elastic = 0.0
    joints = []
    for i in ahead:  # joint between i (front) and the body behind it
        rear = next(j for j in chain if bodies[j].row == bodies[i].row + 1)
        c = by_pair[(rear, i)]
        xj = c.point_m[0]
        theta = dq[i][2] - dq[rear][2]
        slide = (dq[i][1] + dq[i][2] * (xj - ref[i][0])) - (dq[rear][1] + dq[rear][2] * (xj - ref[rear][0]))
        b = c.joint.backlash_rad
        lo, hi = c.joint.play_z
        th_play = max(-b, min(b, theta))
        sl_play = max(-lo, min(hi, slide))
        lever = x_tip - xj
        p = -(th_play * lever + sl_play)
        e = -((theta - th_play) * lever + (slide - sl_play))
        play += p
        elastic += e
        joints.append({"row": bodies[i].row, "rotation_rad": theta, "slide_m": slide,
                       "play_mm": 1e3 * p, "elastic_mm": 1e3 * e})
    total = support + play + elastic
    return {"tip_mm": res.tip_deflection_mm, "support_mm": 1e3 * support, "play_mm": 1e3 * play,
            "elastic_mm": 1e3 * elastic, "sum_mm": 1e3 * total, "joints": joints}


def variant_curve(s, inp: StudyInputs, start: int, max_steps: int = 12) -> tuple[Curve, str]:
    """The static threshold of ``s`` under ``inp`` as a :class:`~structure_fem.analysis.study.Curve` (its
    tips and rows at the widths tried), stepping from ``start`` (the tip grows with the width; a
    width that does not converge counts as failing, as in the threshold search) and a note,
    non-empty when the search stopped after ``max_steps`` steps."""
    c = Curve(s)
    clear = inp.clearance_m * 1e3

    def passes(w: int) -> bool:
        try:
            return c.tip_mm[c.index(w, inp)] <= clear
        except SolverFailure:
            return False

    w, note = max(start, 1), ""
    if passes(w):
        for _ in range(max_steps):
            if w + 1 > inp.max_width or not passes(w + 1):
                break
            w += 1
        else:
            note = f"at least {w} (search stopped after {max_steps} steps)"
    else:
        for _ in range(max_steps):
            w -= 1
            if w < 1 or passes(w):
                break
        else:
            note = f"at most {w} (search stopped after {max_steps} steps)"
    c.threshold = max(w, 0)
    return c, note


def _variants(inp: StudyInputs) -> list[tuple[str, StudyInputs]]:
    c0 = record_clearance_mm(inp)
    lo, hi = PRINT_CLEARANCE_RANGE_MM
    soft = PRINTED_MODULUS_FACTOR

    r0 = inp.robot
    heavy = 1.0 if r0.solid_print_mass_kg is None else r0.solid_print_mass_kg / r0.mass_kg

    def v(play: float, stiff: float, mass: float = 1.0) -> StudyInputs:
        # the printed modulus softens the bodies too (flexible bodies bend with E I)
        robot = r0 if stiff == 1.0 else replace(r0, youngs_modulus_pa=r0.youngs_modulus_pa * stiff)
        if mass != 1.0:  # solid printed parts: the same distribution, heavier (assumption)
            robot = robot.with_mass_scaled(mass)
        return replace(inp, robot=robot, connectors=inp.connectors.scaled(stiff, play))

    out = [(f"print clearance {lo:g} mm", v(lo / c0, 1.0)), (f"print clearance {hi:g} mm", v(hi / c0, 1.0)),
           (f"printed modulus x{soft:g}", v(1.0, soft)),
           (f"print clearance {hi:g} mm and printed modulus x{soft:g}", v(hi / c0, soft))]
    if heavy != 1.0:
        out += [(SOLID_VARIANT, v(1.0, 1.0, heavy)),
                (f"print clearance {hi:g} mm, printed modulus x{soft:g} and {SOLID_VARIANT}", v(hi / c0, soft, heavy))]
    return out


def variant_ranges(d: Derivation, names: list[str] | None = None, progress=None) -> dict[str, list[dict]]:
    """Per structure (those named, with a threshold >= 1), its threshold under each plausible
    input variant (:func:`_variants`) by the derivation's own criterion: with ``inputs.dynamic``
    static tip + launch allowance <= clearance (the variants' transients at their static
    thresholds integrated side by side first, :func:`structure_fem.analysis.study.apply_dynamic`), else the
    static tip. Each entry: ``inputs``, ``threshold``, with the dynamic criterion
    ``static_threshold`` and ``dynamic_allowance_mm`` at the threshold, and a ``note`` when a
    search stopped early or a solve did not converge."""
    from structure_fem.analysis.study import apply_dynamic

    inp = d.inputs
    work = []  # (structure name, variant name, variant inputs, curve, note)
    for c in d.curves:
        if (names is not None and c.structure.name not in names) or c.threshold < 1:
            continue
        for vname, v in _variants(inp):
            vc, note = variant_curve(c.structure, v, c.threshold)
            work.append((c.structure.name, vname, v, vc, note))
    if inp.dynamic:  # one pool for every variant of every structure, each with its own inputs
        apply_dynamic([(vc, v) for _n, _vn, v, vc, _note in work], progress, label="launch transients (ranges)")
    out: dict[str, list[dict]] = {}
    for name, vname, _v, vc, note in work:
        e = {"inputs": vname, "threshold": vc.threshold}
        if inp.dynamic:
            e["static_threshold"] = vc.static_threshold
            a = vc.allowance_mm.get(vc.threshold)
            e["dynamic_allowance_mm"] = None if a is None else round(a, 4)
        fails = "; ".join(f"{f.what} at width {f.width} did not converge, {f.counted_as}" for f in vc.failures)
        note = "; ".join(x for x in (note, fails) if x)
        if note:
            e["note"] = note
        out.setdefault(name, []).append(e)
    return out


def structure_report(d: Derivation, c: Curve, ranges: bool | list[dict] = True) -> dict:
    """Threshold, margins, decomposition, bodies and range of one structure (``ranges``: compute
    the range, or the structure's entries of :func:`variant_ranges` already computed)."""
    inp = d.inputs
    s = c.structure
    clear = inp.clearance_m * 1e3
    w = c.threshold
    out: dict = {"structure": s.name, "threshold": w, "bodies": "flexible" if inp.flexible else "rigid",
                 "clearance_mm": clear}
    if inp.flexible:
        from structure_fem.model.bodies import body_bending

        out["bodies_source"] = body_bending(inp.robot).to_dict()
    if w < 1:
        out.update({"margin_mm": None, "note": "crosses no void within the clearance"})
        return out
    i = c.widths.index(w)
    allow = c.allowance_mm.get(w, 0.0)
    out["dynamic_allowance_mm"] = round(allow, 4) if w in c.allowance_mm else None
    out["static_threshold"] = c.static_threshold
    out["margin_mm"] = round(clear - c.tip_mm[i] - allow, 4)
    out["tip_mm"] = round(c.tip_mm[i], 4)
    out["rows"] = c.rows[i]
    out["robots"] = c.robots[i]
    out["tipping_factor"] = round(c.tipping[i], 4)
    # one width beyond, by the same criterion: its launch allowance too where it was integrated
    # (the dynamic threshold stepped down from there); beyond the static threshold the static tip
    # alone is over the clearance
    out["margin_beyond_mm"] = (round(clear - c.tip_mm[c.widths.index(w + 1)] - c.allowance_mm.get(w + 1, 0.0), 4)
                               if w + 1 in c.widths else None)
    out["marginal"] = out["margin_mm"] < MARGINAL_FRACTION * clear
    #: The search stopped at the widest width studied: the threshold (and its range) is a lower bound.
    out["capped_by_max_width"] = w >= inp.max_width
    try:
        res = solve(Config(s, c.rows[i], w, w), inp.robot, inp.connectors, inp.flexible)
        # the line the tipping factor is taken about: the front-most contact on the near ledge
        out["tipping_line_m"] = round(res.tipping_edge_m, 6)
        out["supports"] = res.layout.ground.kind if res.layout.ground is not None else "corners"
        dec = chain_decomposition(res)
        free = solve(Config(s, c.rows[i], w, w), inp.robot, _no_play(inp).connectors, inp.flexible)
        dec["without_play_tip_mm"] = free.tip_deflection_mm
        dec["play_total_mm"] = res.tip_deflection_mm - free.tip_deflection_mm
        shares = {"play": dec["play_total_mm"], "support (tipping about the edge)": dec["support_mm"]}
        if inp.flexible:  # the robots' own bending: the flexible tip less the rigid-body one
            rigid = solve(Config(s, c.rows[i], w, w), inp.robot, inp.connectors, False)
            dec["rigid_bodies_tip_mm"] = rigid.tip_deflection_mm
            shares["bodies"] = res.tip_deflection_mm - rigid.tip_deflection_mm
        shares["elastic"] = res.tip_deflection_mm - sum(shares.values())
        out["set_by"] = max(shares, key=lambda k: shares[k])
        if c.static_threshold is not None and c.static_threshold > w:
            out["set_by"] = "dynamic"  # the static criterion alone would allow a wider void
        if out["set_by"] in shares:
            out["set_by_share"] = round(shares[out["set_by"]] / res.tip_deflection_mm, 3)
        out["decomposition"] = {k: (round(v, 4) if isinstance(v, float) else v) for k, v in dec.items()
                                if k != "joints"}
    except SolverFailure as exc:
        out["decomposition"] = {"converged": False, "reason": str(exc)}
    if ranges:
        rng = ranges if isinstance(ranges, list) else variant_ranges(d, [s.name]).get(s.name, [])
        ts = [r["threshold"] for r in rng] + [w]
        out["range"] = {"min": min(ts), "max": max(ts), "variants": rng,
                        "criterion": ("variants: static tip + their own launch allowance <= clearance (the table's)"
                                      if inp.dynamic else "variants: static tip <= clearance (the table's)"),
                        "record_print_clearance_mm": round(record_clearance_mm(inp), 4)}
    return out


def report(d: Derivation, ranges: bool = True, names: list[str] | None = None, progress=None) -> list[dict]:
    """:func:`structure_report` of every curve (or those named); the ranges of all of them at once
    (:func:`variant_ranges`: their launch transients side by side)."""
    curves = [c for c in d.curves if names is None or c.structure.name in names]
    rng = variant_ranges(d, [c.structure.name for c in curves], progress) if ranges else {}
    return [structure_report(d, c, rng.get(c.structure.name, []) if ranges else False) for c in curves]


def markdown(rep: list[dict]) -> str:
    """The section of the table's Markdown: thresholds, margins, what sets them, ranges."""
    if not rep:
        return ""
    clear = rep[0]["clearance_mm"]
    lines = ["## Thresholds, margins and what sets them", "",
             f"Margin = {clear:g} mm clearance - tip at the threshold; **marginal** when below "
             f"{100 * MARGINAL_FRACTION:g} % of the clearance ({MARGINAL_FRACTION * clear:.2f} mm). Decomposition "
             "of the tip along the bottom line (support = the rear body's motion: sinking, lifting; play = inside the joints' "
             "own pitch band and vertical slip; elastic = the rest); play (all) = tip - tip with every play set "
             f"to zero. Range: print clearance {PRINT_CLEARANCE_RANGE_MM[0]:g}-{PRINT_CLEARANCE_RANGE_MM[1]:g} mm, "
             f"printed modulus x{PRINTED_MODULUS_FACTOR:g} (couplings and bodies), and both. Bodies: flexible = "
             "each robot bends with its printed shell's section from the CAD (+ what that adds to the tip over "
             "rigid bodies), rigid = only the couplings bend.", "",
             "| structure | threshold | margin mm | beyond mm | tip mm | support / play / elastic mm | "
             "play (all) mm | set by | range | bodies |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rep:
        bodies = r["bodies"]
        if "rigid_bodies_tip_mm" in r.get("decomposition", {}):  # how much the robots' own bending adds
            bodies += f" (+{r['tip_mm'] - r['decomposition']['rigid_bodies_tip_mm']:.2f} mm)"
        if r["threshold"] < 1:
            lines.append(f"| {r['structure']} | 0 | - | - | - | - | - | - | - | {bodies} |")
            continue
        dec = r.get("decomposition", {})
        parts = ("-" if "support_mm" not in dec else
                 f"{dec['support_mm']:.2f} / {dec['play_mm']:.2f} / {dec['elastic_mm']:.2f}")
        flag = " **marginal**" if r["marginal"] else ""
        beyond = "-" if r["margin_beyond_mm"] is None else f"{r['margin_beyond_mm']:.2f}"
        rg = r.get("range")
        rng = "-" if rg is None else (f"{rg['min']}" if rg["min"] == rg["max"] else f"{rg['min']}-{rg['max']}")
        pa = "-" if "play_total_mm" not in dec else f"{dec['play_total_mm']:.2f}"
        setby = r.get("set_by", "-")
        if "set_by_share" in r:
            setby += f" ({100 * r['set_by_share']:.0f} %)"
        cap = " (>=, at the widest width studied)" if r.get("capped_by_max_width") else ""
        lines.append(f"| {r['structure']} | {r['threshold']}{cap} | {r['margin_mm']:.2f}{flag} | {beyond} | "
                     f"{r['tip_mm']:.2f} | {parts} | {pa} | {setby} | {rng} | {bodies} |")
    return "\n".join(lines) + "\n"


def _finite(v) -> bool:
    return isinstance(v, float) and math.isfinite(v)
