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

With ``StudyInputs.dynamic`` (the default of ``fem table`` and ``fem design``) the criterion is the
table's: static tip + launch-transient allowance (:func:`structure_fem.model.dynamics.dynamic_allowance_m`
through :mod:`structure_fem.model.dynamics_cache`) <= clearance. The allowance is >= 0, so the dynamic
boundary lies on the passing side of the static one: the static bisection brackets it first (cheap
solves), then :data:`DYNAMIC_ITERATIONS` more halvings between the static boundary and the range's
good end each integrate the transients of one scaled input (0.3-1 s for a line, seconds for an
arch, cached by input hash). The answer gives both factors (``static_factor``, ``factor``) and the
allowance at the answer.
"""

from __future__ import annotations

import math
from dataclasses import replace

from structure_fem.analysis.study import StudyInputs, candidate_structures, min_rows
from structure_fem.errors import InputError, SolverFailure

#: Halvings of the dynamic refinement (each integrates one scaled input's launch transients).
DYNAMIC_ITERATIONS = 8

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
    return replace(inp, robot=inp.robot.with_mass_scaled(x))


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


def dynamic_tip_mm(s, w: int, inp: StudyInputs) -> tuple[float | None, float | None]:
    """(static tip, launch allowance) in mm at the longest cantilever with minimal standing rows, as
    the table's dynamic criterion takes them; (None, None) when a solve or a transient does not
    converge (counted as not spanning, as the table does)."""
    from structure_fem.model.dynamics_cache import allowance_m

    try:
        rows, res = min_rows(s, w, inp)
        a = allowance_m(s, w, inp.robot, inp.damping_ratio, rows=rows, connectors=inp.connectors,
                        flexible=inp.flexible, static=res)
    except SolverFailure:
        return None, None
    return res.tip_deflection_mm, 1e3 * a


def _passes_dynamic(s, w, inp, param, x) -> tuple[bool, float | None, float | None]:
    t, a = dynamic_tip_mm(s, w, scaled_inputs(inp, param, x))
    return (t is not None and t + a <= inp.clearance_m * 1e3), t, a


def dynamic_boundary(s, w: int, inp: StudyInputs, param: str, static: dict,
                     iterations: int = DYNAMIC_ITERATIONS) -> dict:
    """:func:`boundary` under the dynamic criterion, from the static answer ``static`` (module
    docstring): the static factor is kept as ``static_factor``."""
    side, (lo, hi), log = PARAMETERS[param]
    good = hi if side == "above" else lo
    out = dict(static, static_factor=static.get("factor"), static_bracket=static.get("bracket"))
    out.pop("bracket", None)
    ok1, tip1, a1 = _passes_dynamic(s, w, inp, param, 1.0)
    out.update(spans_now=ok1, allowance_now_mm=a1)
    start = static.get("factor")
    if start is None:  # not even the static criterion can be met by this parameter alone
        return out
    ok_s, _t, a_s = _passes_dynamic(s, w, inp, param, start)
    if ok_s:  # no overshoot to pay for at the static boundary (allowance 0 there)
        out.update(factor=start, allowance_mm=a_s, bracket=static.get("bracket"))
        return out
    ok_g, t_g, a_g = _passes_dynamic(s, w, inp, param, good)
    if not ok_g:
        out.update(factor=None, note=(f"does not span {w} by {param} alone with the launch transients: even at "
                                      f"x{good:g} the tip + allowance is "
                                      + ("not converged" if t_g is None else f"{t_g + a_g:.2f} mm")))
        return out
    a, b, a_at = good, start, a_g  # a passes, b fails
    for _ in range(iterations):
        m = math.sqrt(a * b) if log and a > 0 and b > 0 else 0.5 * (a + b)
        ok, _t, am = _passes_dynamic(s, w, inp, param, m)
        if ok:
            a, a_at = m, am
        else:
            b = m
    out.update(factor=a, allowance_mm=a_at, bracket=sorted((a, b)))
    out.pop("note", None)
    return out


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
    crit = ("static tip + launch-transient allowance <= clearance (the table's)" if inp.dynamic else
            "static tip <= clearance (--static: the table's default adds the launch allowance)")
    out = {"structure": s.name, "void_width": w, "clearance_mm": inp.clearance_m * 1e3, "criterion": crit,
           "dynamic": inp.dynamic, "results": []}
    for p in params:
        if p not in PARAMETERS:
            raise InputError(f"--vary {p!r} is not one of {', '.join(PARAMETERS)}")
        r = boundary(s, w, inp, p)
        if inp.dynamic:
            r = dynamic_boundary(s, w, inp, p, r)
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
        extra = ""
        if r.get("static_factor") is not None:
            extra = (f"; static criterion alone x{r['static_factor']:.3g}, launch allowance at the answer "
                     f"{r.get('allowance_mm') or 0.0:.2f} mm")
        lines.append(f"  {r['parameter']}: x{r['factor']:.3g} ({vals}); {now} (tip {tip}){extra}")
    return "\n".join(lines)
