"""Inverse design: what connector stiffness, play or robot mass makes a structure span a void.

:func:`design` answers a robot designer's question with the model the table uses: for one
structure and one void width ``w`` it bisects, one factor at a time, the scale on

* every coupling stiffness (rotational, axial, shear; ``stiffness``),
* every play (pitch dead band and translational play per feature; ``play``),
* the robot's mass and inertia (``mass``),

for the boundary where the tip at the longest cantilever (minimal standing rows) equals the
climb clearance. The tip falls as the stiffness grows and as the play or the mass shrink, which
the bisection relies on; a width whose solve does not converge counts as not spanning. Each
answer says whether the structure already spans ``w`` (then the factor says how much of that
quantity it could lose) and gives the scaled values.
"""

from __future__ import annotations

import math
from dataclasses import replace

from .errors import InputError, SolverFailure
from .study import StudyInputs, candidate_structures, min_rows

#: (name, passes when the factor is "above" or "below" the boundary, search range, log scale).
PARAMETERS = {
    "stiffness": ("above", (1e-2, 1e3), True),
    "play": ("below", (0.0, 8.0), False),
    "mass": ("below", (0.02, 8.0), True),
}


def structure_named(inp: StudyInputs, name: str):
    """The candidate structure called ``name`` (as in the table), or :class:`InputError` listing them."""
    structs = {s.name: s for s in candidate_structures(inp.connectors, narrow=True)}
    if name not in structs:
        raise InputError(f"--structure {name!r} is not one of {', '.join(structs)}")
    return structs[name]


def scaled_inputs(inp: StudyInputs, param: str, x: float) -> StudyInputs:
    if param == "stiffness":
        return replace(inp, connectors=inp.connectors.scaled(x, 1.0))
    if param == "play":
        return replace(inp, connectors=inp.connectors.scaled(1.0, x))
    r = inp.robot
    return replace(inp, robot=replace(r, mass_kg=r.mass_kg * x, inertia_kg_m2=tuple(i * x for i in r.inertia_kg_m2)))


def tip_mm(s, w: int, inp: StudyInputs) -> float | None:
    """Tip (mm) at the longest cantilever with minimal standing rows; None if no solve converges."""
    try:
        _rows, res = min_rows(s, w, inp)
    except SolverFailure:
        return None
    return res.tip_deflection_mm


def _passes(s, w, inp, param, x) -> tuple[bool, float | None]:
    t = tip_mm(s, w, scaled_inputs(inp, param, x))
    return (t is not None and t <= inp.clearance_m * 1e3), t


def boundary(s, w: int, inp: StudyInputs, param: str, iterations: int = 14) -> dict:
    """The factor on ``param`` at which ``s`` just spans ``w`` (see the module docstring)."""
    side, (lo, hi), log = PARAMETERS[param]
    ok1, tip1 = _passes(s, w, inp, param, 1.0)
    good, bad = (hi, lo) if side == "above" else (lo, hi)
    ok_good, tip_good = _passes(s, w, inp, param, good)
    out = {"parameter": param, "spans_now": ok1, "tip_now_mm": tip1}
    if not ok_good:
        out.update(factor=None, note=(f"does not span {w} by {param} alone: even at x{good:g} the tip is "
                                      + ("not converged" if tip_good is None else f"{tip_good:.2f} mm")))
        return out
    ok_bad, _ = _passes(s, w, inp, param, bad)
    if ok_bad:
        out.update(factor=bad, note=f"spans {w} over the whole range searched (x{lo:g}..x{hi:g})")
        return out
    a, b = good, bad  # a passes, b fails
    for _ in range(iterations):
        m = math.sqrt(a * b) if log and a > 0 and b > 0 else 0.5 * (a + b)
        if _passes(s, w, inp, param, m)[0]:
            a = m
        else:
            b = m
    out["factor"] = a  # the passing side of the boundary
    out["bracket"] = sorted((a, b))
    return out


def design(inp: StudyInputs, structure: str, w: int, params=tuple(PARAMETERS)) -> dict:
    """Per parameter the factor that makes ``structure`` span ``w`` and the values it means."""
    if not (isinstance(w, int) and 1 <= w <= inp.max_width):
        raise InputError(f"--void-width {w!r} outside 1..{inp.max_width} robot widths")
    s = structure_named(inp, structure)
    s.check_connectors(inp.connectors, inp.robot.name)
    fr = inp.connectors.front_rear
    # static criterion: a bisection of launch transients would be minutes per parameter; the
    # launch allowance at the answer is what `fem table` then adds (it can cost a width)
    out = {"structure": s.name, "void_width": w, "clearance_mm": inp.clearance_m * 1e3,
           "criterion": "static tip <= clearance (the table adds the launch allowance)", "results": []}
    for p in params:
        if p not in PARAMETERS:
            raise InputError(f"--vary {p!r} is not one of {', '.join(PARAMETERS)}")
        r = boundary(s, w, inp, p)
        x = r.get("factor")
        if x is not None:
            if p == "stiffness":
                r["values"] = {"front_rear_nm_per_rad": fr.rotational_nm_per_rad * x,
                               "front_rear_axial_n_per_m": fr.axial_n_per_m * x}
            elif p == "play":
                r["values"] = {"front_rear_tension_play_mm": fr.play_x[1] * x * 1e3,
                               "front_rear_backlash_mrad": fr.backlash_rad * x * 1e3}
            else:
                r["values"] = {"robot_mass_kg": inp.robot.mass_kg * x}
        out["results"].append(r)
    return out


def describe(res: dict) -> str:
    """One line per parameter for the terminal."""
    lines = [f"{res['structure']} over a {res['void_width']}-wide void (clearance {res['clearance_mm']:g} mm, "
             f"{res.get('criterion', 'static tip <= clearance')}):"]
    for r in res["results"]:
        now = "spans it now" if r["spans_now"] else "does not span it now"
        tip = "-" if r["tip_now_mm"] is None else f"{r['tip_now_mm']:.2f} mm"
        if r.get("factor") is None or "bracket" not in r:
            lines.append(f"  {r['parameter']}: {now} (tip {tip}); {r.get('note', '')}")
            continue
        vals = ", ".join(f"{k} {v:.4g}" for k, v in r["values"].items())
        lines.append(f"  {r['parameter']}: x{r['factor']:.3g} ({vals}); {now} (tip {tip})")
    return "\n".join(lines)
